//! Isoparametric faces, in particular the second-order (curved) ones: Tri6,
//! Quad8 and Quad9 shape functions and their gradients (and, as the flat
//! special cases, Tri3 and Quad4), the face map x(ξ) = Σ N_i(ξ) x_i with its
//! tangents and surface Jacobian, its Bernstein control net (whose convex hull
//! encloses the face), and the inverse projection of a point along a direction
//! onto the true curved face (paper step D2 for isoparametric faces). The
//! operator uses it for every pair with a second-order face.
//!
//! Reference cells, node order and shape functions are those of the element
//! catalogue ([`crate::catalogue`], [`FaceKind`]): Gmsh's node order, quads
//! on \[0,1\]².

use crate::catalogue::faces::MONOMIALS;
pub use crate::catalogue::{shape_and_gradients, shape_values};
use crate::catalogue::{FaceKind, Xi};
use crate::clip::Frame;
use crate::element::{cross, dot, norm, sub};
use crate::mesh::{Point3, SurfaceMesh};

/// How many of the monomials of [`MonomialMap`] the map of a face with
/// `n_nodes` nodes uses ([`crate::FaceType::n_monomials`]; they come in the
/// order 1, s, t, s², st, t², s²t, st², s²t²): Tri3 the first 3, Quad4 5 (no
/// s², but st), Tri6 6, Quad8 8, Quad9 9. The coefficients of the others are
/// zero.
pub const fn monomials_of(n_nodes: usize) -> usize {
    match FaceKind::with_nodes(n_nodes) {
        Some(kind) => kind.info().n_monomials,
        None => MONOMIALS,
    }
}

/// A face map x(ξ) = Σ_i N_i(ξ) x_i in `D` dimensions written in the
/// monomials, x(ξ) = Σ_k c_k m_k(ξ): one branch-free evaluation for every
/// kind (for the Newton iterations and the quadrature points).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MonomialMap<const D: usize> {
    c: [[f64; D]; MONOMIALS],
}

impl<const D: usize> MonomialMap<D> {
    /// The map of a face of `kind` with nodes `x` (entries past
    /// `kind.n_nodes()` ignored).
    pub fn new(kind: FaceKind, x: &[[f64; D]; 9]) -> MonomialMap<D> {
        let table = &kind.info().monomials;
        let mut c = [[0.0; D]; MONOMIALS];
        for (row, xi) in table.iter().zip(x).take(kind.n_nodes()) {
            for (ck, &r) in c.iter_mut().zip(row) {
                for d in 0..D {
                    ck[d] += r * xi[d];
                }
            }
        }
        MonomialMap { c }
    }

    /// x(ξ).
    #[inline(always)]
    pub fn map(&self, [s, t]: Xi) -> [f64; D] {
        let m = [1.0, s, t, s * s, s * t, t * t, s * s * t, s * t * t, s * s * t * t];
        let mut x = [0.0; D];
        for k in 0..MONOMIALS {
            for d in 0..D {
                x[d] += m[k] * self.c[k][d];
            }
        }
        x
    }

    /// x(ξ), ∂x/∂ξ and ∂x/∂η.
    #[inline(always)]
    pub fn map_and_tangents(&self, xi: Xi) -> ([f64; D], [f64; D], [f64; D]) {
        self.map_and_tangents_first(xi, MONOMIALS)
    }

    /// [`MonomialMap::map_and_tangents`] over the first `m` monomials only,
    /// for a face that uses no others ([`monomials_of`]); meant for a
    /// constant `m`, so that the unused terms are never computed. In Horner
    /// form along s: x = A(t) + s B(t) + s² C(t) with A = c₀ + t c₂ + t² c₅,
    /// B = c₁ + t c₄ + t² c₇, C = c₃ + t c₆ + t² c₈, so ∂x/∂s = B + 2s C and
    /// ∂x/∂t = A′ + s B′ + s² C′.
    #[inline(always)]
    pub fn map_and_tangents_first(&self, [s, t]: Xi, m: usize) -> ([f64; D], [f64; D], [f64; D]) {
        let c = &self.c;
        let (mut x, mut a, mut b) = ([0.0; D], [0.0; D], [0.0; D]);
        for d in 0..D {
            // A, B, C and their t-derivatives, with the terms the kind has.
            let (mut pa, mut pb, mut pc) = (c[0][d] + t * c[2][d], c[1][d], 0.0);
            let (mut da, mut db, mut dc) = (c[2][d], 0.0, 0.0);
            if m > 3 {
                pb += t * c[4][d];
                db += c[4][d];
                pc += c[3][d];
            }
            if m > 5 {
                pa += t * t * c[5][d];
                da += 2.0 * t * c[5][d];
            }
            if m > 6 {
                pc += t * c[6][d];
                dc += c[6][d];
            }
            if m > 7 {
                pb += t * t * c[7][d];
                db += 2.0 * t * c[7][d];
            }
            if m > 8 {
                pc += t * t * c[8][d];
                dc += 2.0 * t * c[8][d];
            }
            x[d] = pa + s * (pb + s * pc);
            a[d] = pb + 2.0 * s * pc;
            b[d] = da + s * (db + s * dc);
        }
        (x, a, b)
    }
}

/// Newton iterations of [`ProjectedFace::inverse`].
const MAX_NEWTON: usize = 30;

/// Residual of [`CurvedFace::plane_inverse`] relative to the face size.
const NEWTON_RTOL: f64 = 1e-13;

/// A Newton step of [`ProjectedFace::inverse`] this short (in reference
/// coordinates) is the last.
const NEWTON_FINAL_STEP: f64 = 1e-8;

/// A curved face: its kind and node coordinates (entries past
/// `kind.n_nodes()` unused).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvedFace {
    /// Tri6, Quad8 or Quad9.
    pub kind: FaceKind,
    /// The nodes, in node order.
    pub x: [Point3; 9],
}

/// A face seen in a frame: its projection onto the plane, ξ ↦ P x(ξ) =
/// Σ_i N_i(ξ) P x_i, and its height above it, n·(x(ξ) − o) (both linear in
/// the nodes, so mapping the nodes once makes every evaluation two- or
/// one-dimensional).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectedFace {
    /// P x(ξ) in the monomials.
    pub map: MonomialMap<2>,
    /// The height in the monomials.
    pub height: MonomialMap<1>,
}

impl ProjectedFace {
    /// `face` seen in `frame`.
    pub fn new(face: &CurvedFace, frame: &Frame) -> ProjectedFace {
        ProjectedFace {
            map: MonomialMap::new(face.kind, &face.x.map(|x| frame.project(x))),
            height: MonomialMap::new(face.kind, &face.x.map(|x| [frame.height(x)])),
        }
    }

    /// The point ξ with P x(ξ) = `target` (the inverse projection along the
    /// frame normal, D1–D2), by Newton from `guess`, steps bounded to the
    /// size of the cell. Returns ξ and whether the iteration converged: to
    /// 1e-13 of the face size, or by a step below 1e-8 (Newton converges
    /// quadratically, so the next residual is of the order of its square);
    /// on failure the best iterate.
    pub fn inverse(&self, target: [f64; 2], guess: Xi) -> (Xi, bool) {
        self.inverse_first(target, guess, MONOMIALS)
    }

    /// [`ProjectedFace::inverse`] for a face whose map uses only the first
    /// `m` monomials ([`monomials_of`]), meant for a constant `m`.
    #[inline(always)]
    pub fn inverse_first(&self, target: [f64; 2], guess: Xi, m: usize) -> (Xi, bool) {
        let mut xi = guess;
        let mut best = (f64::INFINITY, xi);
        for _ in 0..MAX_NEWTON {
            let (q, pa, pb) = self.map.map_and_tangents_first(xi, m);
            let r = [q[0] - target[0], q[1] - target[1]];
            let det = pa[0] * pb[1] - pa[1] * pb[0];
            let size = (pa[0].abs() + pa[1].abs()).max(pb[0].abs() + pb[1].abs());
            let err = r[0].abs() + r[1].abs();
            if err < best.0 {
                best = (err, xi);
            }
            if err <= NEWTON_RTOL * size {
                return (xi, true);
            }
            if det.abs() <= 1e-14 * size * size {
                break;
            }
            let step = [(pb[1] * r[0] - pb[0] * r[1]) / det, (pa[0] * r[1] - pa[1] * r[0]) / det];
            let reach = step[0].abs().max(step[1].abs());
            if reach <= NEWTON_FINAL_STEP {
                return ([xi[0] - step[0], xi[1] - step[1]], true);
            }
            let lambda = if reach > 0.5 { 0.5 / reach } else { 1.0 };
            xi = [xi[0] - lambda * step[0], xi[1] - lambda * step[1]];
        }
        (best.1, false)
    }
}

/// Where a line meets a curved face ([`CurvedFace::inverse_project`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Reference coordinates on the face.
    pub xi: Xi,
    /// The line parameter: x(ξ) = p + t d.
    pub t: f64,
    /// Inside the reference cell (within 1e-10).
    pub inside: bool,
}

impl CurvedFace {
    /// The face of `kind` with `nodes` (at least `kind.n_nodes()`).
    ///
    /// # Panics
    /// If fewer nodes are given.
    pub fn new(kind: FaceKind, nodes: &[Point3]) -> CurvedFace {
        let mut x = [[0.0; 3]; 9];
        x[..kind.n_nodes()].copy_from_slice(&nodes[..kind.n_nodes()]);
        CurvedFace { kind, x }
    }

    /// Face `f` of `mesh`.
    pub fn of(mesh: &SurfaceMesh, f: usize) -> CurvedFace {
        let face = &mesh.faces()[f];
        let mut x = [[0.0; 3]; 9];
        for (i, &n) in face.nodes().iter().enumerate() {
            x[i] = mesh.points()[n];
        }
        CurvedFace { kind: FaceKind::of(face), x }
    }

    /// The nodes in use.
    pub fn nodes(&self) -> &[Point3] {
        &self.x[..self.kind.n_nodes()]
    }

    /// The Bernstein control net of the map (its first `n` entries): the face
    /// lies in the convex hull of these points, so their box encloses it. For a
    /// quadratic edge with end values a, b and mid value m the inner control
    /// point is 2m − (a + b)/2; Quad8 is first written as the Quad9 with the
    /// same map (serendipity ⊂ biquadratic), Quad9 is the tensor product; a
    /// Tri7's points are the corners of an enclosing box (below).
    pub fn control_net(&self) -> ([Point3; 9], usize) {
        let x = &self.x;
        let inner = |a: Point3, m: Point3, b: Point3| -> Point3 {
            std::array::from_fn(|k| 2.0 * m[k] - 0.5 * (a[k] + b[k]))
        };
        let mut c = *x;
        if self.kind.order() == 1 {
            return (c, self.kind.n_nodes());
        }
        if self.kind.is_triangle() {
            for i in 0..3 {
                c[3 + i] = inner(x[i], x[3 + i], x[(i + 1) % 3]);
            }
            if self.kind.n_nodes() == 6 {
                return (c, 6);
            }
            // Tri7: x(ξ) = x₆(ξ) + b(ξ) d, the Tri6 map through the same six
            // nodes plus the bubble b ∈ [0, 1] times the centre node's offset
            // d from x₆(⅓, ⅓); it lies in the box of the Tri6 net and that net
            // moved by d, given by its eight corners.
            let p6 = shape_values::<6>(self.kind.centre());
            let d: Point3 = std::array::from_fn(|k| x[6][k] - (0..6).map(|i| p6[i] * x[i][k]).sum::<f64>());
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for p in &c[..6] {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]).min(p[k] + d[k]);
                    hi[k] = hi[k].max(p[k]).max(p[k] + d[k]);
                }
            }
            for (i, corner) in c.iter_mut().take(8).enumerate() {
                *corner = std::array::from_fn(|k| if i >> k & 1 == 0 { lo[k] } else { hi[k] });
            }
            return (c, 8);
        }
        let centre = self.map([0.5, 0.5]);
        for i in 0..4 {
            c[4 + i] = inner(x[i], x[4 + i], x[(i + 1) % 4]);
        }
        // Along ξ through the middle row (nodes 7, 8, 5), then along η.
        let middle = inner(x[7], centre, x[5]);
        c[8] = inner(c[4], middle, c[6]);
        (c, 9)
    }

    /// The point ξ whose image projects to `target` in `frame`'s plane: the
    /// inverse projection along the frame normal (D1–D2),
    /// [`ProjectedFace::inverse`].
    pub fn plane_inverse(&self, frame: &Frame, target: [f64; 2], guess: Xi) -> (Xi, bool) {
        ProjectedFace::new(self, frame).inverse(target, guess)
    }

    /// x(ξ) and the tangents ∂x/∂ξ, ∂x/∂η.
    pub fn map_and_tangents(&self, xi: Xi) -> (Point3, Point3, Point3) {
        let (n, g) = shape_and_gradients(self.kind, xi);
        let (mut x, mut a, mut b) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for i in 0..self.kind.n_nodes() {
            for k in 0..3 {
                x[k] += n[i] * self.x[i][k];
                a[k] += g[i][0] * self.x[i][k];
                b[k] += g[i][1] * self.x[i][k];
            }
        }
        (x, a, b)
    }

    /// x(ξ).
    pub fn map(&self, xi: Xi) -> Point3 {
        self.map_and_tangents(xi).0
    }

    /// The surface Jacobian |∂x/∂ξ × ∂x/∂η|.
    pub fn jacobian(&self, xi: Xi) -> f64 {
        let (_, a, b) = self.map_and_tangents(xi);
        norm(cross(a, b))
    }

    /// The unit normal ∂x/∂ξ × ∂x/∂η / |…| at ξ (outward for a face
    /// numbered counter-clockwise seen from outside).
    pub fn normal(&self, xi: Xi) -> Point3 {
        let (_, a, b) = self.map_and_tangents(xi);
        let n = cross(a, b);
        let l = norm(n);
        n.map(|v| v / l)
    }

    /// Where the line p + t d meets the face: x(ξ) = p + t d, solved by Newton
    /// on (ξ, η, t) from the centroid with backtracking on |x(ξ) − p − t d|
    /// and steps held to a bounded neighbourhood of the cell (the safeguard:
    /// on a strongly curved face the undamped iteration can jump to a root
    /// far outside, where the quadratic map folds back). `None` when the
    /// iteration stalls (d tangent to the face) or the root lies far
    /// outside the cell; otherwise the root, [`Hit::inside`] telling whether
    /// it is on the face. Converges quadratically near a transversal root.
    pub fn inverse_project(&self, p: Point3, d: Point3) -> Option<Hit> {
        let scale = self.x[..self.kind.n_nodes()]
            .iter()
            .map(|&x| norm(sub(x, self.x[0])))
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let residual = |xi: Xi, t: f64| {
            let x = self.map(xi);
            [x[0] - p[0] - t * d[0], x[1] - p[1] - t * d[1], x[2] - p[2] - t * d[2]]
        };
        let dd = dot(d, d);
        let mut xi = self.kind.centre();
        let mut t = dot(sub(self.map(xi), p), d) / dd;
        let mut r = residual(xi, t);
        for _ in 0..50 {
            if norm(r) <= 1e-14 * scale {
                break;
            }
            let (_, a, b) = self.map_and_tangents(xi);
            // [a b −d] (δξ, δη, δt) = −r by Cramer's rule.
            let minus_d = d.map(|v| -v);
            let det = dot(a, cross(b, minus_d));
            if det.abs() <= 1e-14 * norm(a) * norm(b) * dd.sqrt() {
                return None;
            }
            let rhs = r.map(|v| -v);
            let step = [
                dot(rhs, cross(b, minus_d)) / det,
                dot(a, cross(rhs, minus_d)) / det,
                dot(a, cross(b, rhs)) / det,
            ];
            // Hold ξ within a bounded neighbourhood of the cell, then halve
            // the step until the residual decreases.
            let mut lambda: f64 = 1.0;
            let reach = step[0].abs().max(step[1].abs());
            if reach > 0.5 {
                lambda = 0.5 / reach;
            }
            let mut accepted = false;
            for _ in 0..30 {
                let trial = [xi[0] + lambda * step[0], xi[1] + lambda * step[1]];
                let tt = t + lambda * step[2];
                let rt = residual(trial, tt);
                if norm(rt) < norm(r) {
                    (xi, t, r, accepted) = (trial, tt, rt, true);
                    break;
                }
                lambda *= 0.5;
            }
            if !accepted {
                break;
            }
            if !self.kind.contains(xi, 1.0) {
                return None;
            }
        }
        if norm(r) > 1e-10 * scale {
            return None;
        }
        Some(Hit { xi, t, inside: self.kind.contains(xi, 1e-10) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalogue::tests::samples;

    const KINDS: [FaceKind; 3] = [FaceKind::Tri6, FaceKind::Quad8, FaceKind::Quad9];

    /// A face of `kind` on the sphere of radius `r` around the origin over
    /// the angular patch θ ∈ [0, a], φ ∈ [−a/2, a/2] (nodes on the sphere).
    fn sphere_face(kind: FaceKind, r: f64, a: f64) -> CurvedFace {
        let nodes: Vec<Point3> = kind
            .nodes()
            .iter()
            .map(|&[s, t]| {
                let (theta, phi) = (a * s, a * (t - 0.5));
                [r * phi.cos() * theta.cos(), r * phi.cos() * theta.sin(), r * phi.sin()]
            })
            .collect();
        CurvedFace::new(kind, &nodes)
    }

    #[test]
    fn points_come_back_from_strongly_curved_faces() {
        // A quarter of a great circle across each face: strongly curved.
        for kind in KINDS {
            let face = sphere_face(kind, 1.0, std::f64::consts::FRAC_PI_2);
            for xi in samples(kind).into_iter().filter(|&xi| kind.contains(xi, 0.0)) {
                let (x, _, _) = face.map_and_tangents(xi);
                // From a point off the face along the face normal, and along
                // a tilted direction.
                let n = face.normal(xi);
                for d in [n, [n[0] + 0.3, n[1] - 0.2, n[2] + 0.1]] {
                    let p = [x[0] - 0.2 * d[0], x[1] - 0.2 * d[1], x[2] - 0.2 * d[2]];
                    let hit = face.inverse_project(p, d).unwrap_or_else(|| panic!("{kind:?} {xi:?}: no hit"));
                    assert!(hit.inside, "{kind:?} {xi:?}: {hit:?}");
                    let e = (hit.xi[0] - xi[0]).abs().max((hit.xi[1] - xi[1]).abs());
                    assert!(e < 1e-12 && (hit.t - 0.2).abs() < 1e-12, "{kind:?} {xi:?}: {hit:?}");
                }
            }
        }
    }

    #[test]
    fn monomial_maps_are_the_shape_function_maps() {
        let all = [FaceKind::Tri3, FaceKind::Quad4, FaceKind::Tri6, FaceKind::Quad8, FaceKind::Quad9];
        for kind in all {
            // Nodes on a sphere, moved off it so that no shape function hides.
            let mut face = sphere_face(kind, 1.0, 1.0);
            for (i, x) in face.x.iter_mut().enumerate().take(kind.n_nodes()) {
                x[(i + 1) % 3] += 0.05 * (i as f64).sin();
            }
            let map = MonomialMap::new(kind, &face.x);
            let frame = Frame::householder([0.3, 0.2, 0.9], [0.1, 0.0, 0.0]);
            let projected = ProjectedFace::new(&face, &frame);
            for xi in samples(kind) {
                let (x, a, b) = face.map_and_tangents(xi);
                let (y, c, d) = map.map_and_tangents(xi);
                for k in 0..3 {
                    let e = (x[k] - y[k]).abs().max((a[k] - c[k]).abs()).max((b[k] - d[k]).abs());
                    assert!(e < 1e-14, "{kind:?} {xi:?}: {e:e}");
                }
                let q = projected.map.map_and_tangents(xi).0;
                let p = frame.project(x);
                assert!((q[0] - p[0]).abs().max((q[1] - p[1]).abs()) < 1e-14, "{kind:?} {xi:?}");
            }
        }
    }

    #[test]
    fn plane_inverse_finds_points_of_strongly_curved_faces() {
        // A quarter of a great circle across each face, seen in the plane of
        // its centre; Newton from the centre.
        for kind in KINDS {
            let face = sphere_face(kind, 1.0, std::f64::consts::FRAC_PI_2);
            let centre = kind.centre();
            let frame = Frame::householder(face.normal(centre), face.map(centre));
            for xi in samples(kind).into_iter().filter(|&xi| kind.contains(xi, 0.0)) {
                let (found, converged) = face.plane_inverse(&frame, frame.project(face.map(xi)), centre);
                let e = (found[0] - xi[0]).abs().max((found[1] - xi[1]).abs());
                assert!(converged && e < 1e-12, "{kind:?} {xi:?}: {found:?}, {e:e}");
            }
        }
    }

    /// Uniform numbers in [−½, ½) from `seed` (a 64-bit LCG).
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        }
    }

    /// The control net is the face's Bernstein–Bézier net: the map equals
    /// Σ_i B_i(ξ) c_i with Bernstein polynomials B_i ≥ 0, Σ B_i = 1, so the face
    /// lies in the convex hull of the c_i and their box encloses it (the
    /// search boxes of (A1)). Checked on strongly curved faces (mid-side and
    /// centre nodes moved by up to half the face size), with every sampled
    /// point of the face inside the net's box.
    #[test]
    fn the_control_net_is_the_bezier_net_and_its_box_encloses_the_face() {
        let mut random = uniform(3);
        // Quadratic Bernstein polynomials on [0, 1] in the order of `lagrange`.
        let bernstein = |s: f64| [(1.0 - s) * (1.0 - s), s * s, 2.0 * s * (1.0 - s)];
        for kind in KINDS {
            for _ in 0..50 {
                let mut face = sphere_face(kind, 1.0, 0.8);
                for (i, x) in face.x.iter_mut().enumerate().take(kind.n_nodes()) {
                    let amplitude = if i < 3 || (i == 3 && !kind.is_triangle()) { 0.1 } else { 0.5 };
                    for c in x.iter_mut() {
                        *c += amplitude * random();
                    }
                }
                let (net, n) = face.control_net();
                let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
                for c in &net[..n] {
                    for k in 0..3 {
                        lo[k] = lo[k].min(c[k]);
                        hi[k] = hi[k].max(c[k]);
                    }
                }
                let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
                for xi in samples(kind).into_iter().filter(|&xi| kind.contains(xi, 0.0)) {
                    let weights: Vec<f64> = if kind.is_triangle() {
                        let l = [1.0 - xi[0] - xi[1], xi[0], xi[1]];
                        let mut w = vec![l[0] * l[0], l[1] * l[1], l[2] * l[2]];
                        w.extend((0..3).map(|i| 2.0 * l[i] * l[(i + 1) % 3]));
                        w
                    } else {
                        let (a, b) = (bernstein(xi[0]), bernstein(xi[1]));
                        crate::catalogue::faces::QUAD9_GRID.iter().map(|&(p, q)| a[p] * b[q]).collect()
                    };
                    assert_eq!(weights.len(), n, "{kind:?}");
                    assert!(weights.iter().all(|&w| w >= 0.0));
                    let x = face.map(xi);
                    for k in 0..3 {
                        let bezier: f64 = weights.iter().zip(&net).map(|(w, c)| w * c[k]).sum();
                        assert!(
                            (bezier - x[k]).abs() < 1e-14 * size,
                            "{kind:?} {xi:?}: {bezier} vs {}",
                            x[k]
                        );
                        assert!(lo[k] <= x[k] && x[k] <= hi[k], "{kind:?} {xi:?}: outside the box");
                    }
                }
            }
        }
    }

    /// A Tri7 whose centre node is off the Tri6 map's centre (a bubble in
    /// its geometry) lies in the box of its eight points.
    #[test]
    fn a_tri7_lies_in_its_box() {
        let mut random = uniform(11);
        for _ in 0..50 {
            let mut face = sphere_face(FaceKind::Tri7, 1.0, 0.8);
            for x in face.x.iter_mut().take(7) {
                for c in x.iter_mut() {
                    *c += 0.3 * random();
                }
            }
            let (net, n) = face.control_net();
            assert_eq!(n, 8);
            let lo: Point3 =
                std::array::from_fn(|k| net[..n].iter().map(|c| c[k]).fold(f64::INFINITY, f64::min));
            let hi: Point3 =
                std::array::from_fn(|k| net[..n].iter().map(|c| c[k]).fold(f64::NEG_INFINITY, f64::max));
            for i in 0..=20 {
                for j in 0..=20 - i {
                    let x = face.map([i as f64 / 20.0, j as f64 / 20.0]);
                    for k in 0..3 {
                        assert!(lo[k] - 1e-15 <= x[k] && x[k] <= hi[k] + 1e-15, "outside the box");
                    }
                }
            }
        }
    }

    #[test]
    fn a_line_that_misses_or_grazes_gives_no_inside_hit() {
        let face = sphere_face(FaceKind::Quad9, 1.0, 0.5);
        // Parallel to the face's tangent plane at its centre, far above it.
        let (x, a, _) = face.map_and_tangents([0.5, 0.5]);
        let n = face.normal([0.5, 0.5]);
        let p = [x[0] + 5.0 * n[0], x[1] + 5.0 * n[1], x[2] + 5.0 * n[2]];
        assert!(face.inverse_project(p, a).is_none_or(|h| !h.inside));
        // Along the normal, but beside the patch.
        let beside = face.map([1.8, 0.5]);
        let hit = face.inverse_project(beside, n);
        assert!(hit.is_none_or(|h| !h.inside), "{hit:?}");
    }

    #[test]
    fn the_jacobian_integrates_the_sphere_patch_area() {
        // Area of θ ∈ [0, a], φ ∈ [−a/2, a/2] on the unit sphere: 2a sin(a/2);
        // the quadratic face approximates it closely, and a flat face is exact.
        let a = 0.2f64;
        let exact = 2.0 * a * (0.5 * a).sin();
        for kind in [FaceKind::Quad8, FaceKind::Quad9] {
            let face = sphere_face(kind, 1.0, a);
            // 8-point Gauss–Legendre product rule on [0,1]².
            let (x, w) = crate::gauss_legendre(8);
            let (x, w): (Vec<f64>, Vec<f64>) =
                x.iter().zip(&w).map(|(x, w)| (0.5 * (1.0 + x), 0.5 * w)).unzip();
            let mut area = 0.0;
            for i in 0..8 {
                for j in 0..8 {
                    area += w[i] * w[j] * face.jacobian([x[i], x[j]]);
                }
            }
            assert!((area - exact).abs() < 1e-4 * exact, "{kind:?}: {area} vs {exact}");
        }
        let flat = CurvedFace::new(
            FaceKind::Quad9,
            &FaceKind::Quad9.nodes().iter().map(|&[s, t]| [2.0 * s, 3.0 * t, 0.0]).collect::<Vec<_>>(),
        );
        assert!((flat.jacobian([0.3, 0.7]) - 6.0).abs() < 1e-14);
    }
}
