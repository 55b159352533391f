//! Reference elements: shape functions, face map x(ξ), surface Jacobian, and the
//! inverse projection of a point along a direction onto a face (paper steps D1–D2).
//!
//! | element | reference cell | shape functions λ_i |
//! |---|---|---|
//! | Tri3 | {(0,0), (1,0), (0,1)} | 1−ξ−η, ξ, η |
//! | Quad4 | [0,1]² | (1−ξ)(1−η), ξ(1−η), ξη, (1−ξ)η |
//!
//! Symbols: `xi` = (ξ, η) reference coordinates; `x` = the face map
//! x(ξ) = Σ λ_i(ξ) x_i; `jac` = |∂x/∂ξ × ∂x/∂η|, the surface Jacobian.
//! Quads are bilinear patches and stay so when warped: nothing here splits or
//! flattens them.

use crate::catalogue::faces::first_order_values;
use crate::catalogue::{FaceKind, Xi};
use crate::mesh::{Point3, SurfaceMesh};

/// A face with its corner coordinates: the element-level view of one mesh face.
///
/// For a triangle, `x[3]` repeats `x[2]` and is never used.
#[derive(Clone, Copy, Debug)]
pub struct FaceElement {
    /// Element type: [`FaceKind::Tri3`] or [`FaceKind::Quad4`] (every other
    /// kind counts as a quad).
    pub kind: FaceKind,
    /// Corner coordinates in cyclic order.
    pub x: [Point3; 4],
}

/// Relative warp below which a quad counts as planar, `warp(q) < PLANAR_WARP`:
/// the surface Jacobian of such a quad differs from an affine function by
/// O(warp²) ≤ 1e-14 relative, so polynomial rules stay exact to round-off.
pub const PLANAR_WARP: f64 = 1e-7;

impl FaceElement {
    /// The element of face `f` of `mesh`; for a second-order face, the
    /// first-order element through its corners (its chordal approximation).
    pub fn of(mesh: &SurfaceMesh, f: usize) -> Self {
        FaceElement { kind: mesh.faces()[f].kind().linear(), x: mesh.corners(f) }
    }

    /// Number of corners (3 or 4).
    #[inline]
    pub fn n_nodes(&self) -> usize {
        if self.kind == FaceKind::Tri3 {
            3
        } else {
            4
        }
    }

    /// The corners actually used.
    pub fn corners(&self) -> &[Point3] {
        &self.x[..self.n_nodes()]
    }

    /// Shape functions λ_i(ξ); entry 3 is 0 for a triangle.
    #[inline]
    pub fn shape(&self, xi: Xi) -> [f64; 4] {
        first_order_values(self.kind == FaceKind::Tri3, xi)
    }

    /// The face map x(ξ) = Σ λ_i(ξ) x_i.
    #[inline]
    pub fn map(&self, xi: Xi) -> Point3 {
        let l = self.shape(xi);
        let mut p = [0.0; 3];
        for i in 0..self.n_nodes() {
            for k in 0..3 {
                p[k] += l[i] * self.x[i][k];
            }
        }
        p
    }

    /// Tangents (∂x/∂ξ, ∂x/∂η) at ξ.
    #[inline]
    pub fn tangents(&self, xi: Xi) -> (Point3, Point3) {
        let x = &self.x;
        if self.kind == FaceKind::Tri3 {
            return (sub(x[1], x[0]), sub(x[2], x[0]));
        }
        let [s, t] = xi;
        let mut a = [0.0; 3];
        let mut b = [0.0; 3];
        for k in 0..3 {
            a[k] = (1.0 - t) * (x[1][k] - x[0][k]) + t * (x[2][k] - x[3][k]);
            b[k] = (1.0 - s) * (x[3][k] - x[0][k]) + s * (x[2][k] - x[1][k]);
        }
        (a, b)
    }

    /// Surface Jacobian |∂x/∂ξ × ∂x/∂η| at ξ (constant for triangles).
    #[inline]
    pub fn jacobian(&self, xi: Xi) -> f64 {
        let (a, b) = self.tangents(xi);
        norm(cross(a, b))
    }

    /// The surface Jacobian as a field, precomputed once per face. For x(ξ) =
    /// a + bξ + cη + dξη the area vector is ∂x/∂ξ × ∂x/∂η = b×c + ξ b×d + η d×c,
    /// affine in ξ: on a triangle (d = 0) and a planar quad (all three terms
    /// along n) |J| is the affine n·(…); on a warped quad it is the norm of the
    /// affine vector.
    pub fn jacobian_field(&self) -> JacobianField {
        let x = &self.x;
        let b = sub(x[1], x[0]);
        let (c, d) = if self.kind == FaceKind::Tri3 {
            (sub(x[2], x[0]), [0.0; 3])
        } else {
            (
                sub(x[3], x[0]),
                [
                    x[0][0] - x[1][0] + x[2][0] - x[3][0],
                    x[0][1] - x[1][1] + x[2][1] - x[3][1],
                    x[0][2] - x[1][2] + x[2][2] - x[3][2],
                ],
            )
        };
        let v = [cross(b, c), cross(b, d), cross(d, c)];
        if self.is_planar() {
            let n = self.normal();
            let s = if dot(n, v[0]) + 0.5 * (dot(n, v[1]) + dot(n, v[2])) >= 0.0 { 1.0 } else { -1.0 };
            JacobianField::Affine([s * dot(n, v[0]), s * dot(n, v[1]), s * dot(n, v[2])])
        } else {
            JacobianField::Norm(v)
        }
    }

    /// The face normal of DESIGN.md §2: Tri3, the unit normal of its plane;
    /// Quad4, the unit normal at the centre, (x2−x0)×(x3−x1) normalised.
    pub fn normal(&self) -> Point3 {
        let x = &self.x;
        let n = if self.kind == FaceKind::Tri3 {
            cross(sub(x[1], x[0]), sub(x[2], x[0]))
        } else {
            cross(sub(x[2], x[0]), sub(x[3], x[1]))
        };
        scale(n, 1.0 / norm(n))
    }

    /// The centroid of the corners.
    pub fn centre(&self) -> Point3 {
        let n = self.n_nodes() as f64;
        let mut c = [0.0; 3];
        for p in self.corners() {
            for k in 0..3 {
                c[k] += p[k] / n;
            }
        }
        c
    }

    /// The longest distance between two corners.
    pub fn diameter(&self) -> f64 {
        let c = self.corners();
        let mut d: f64 = 0.0;
        for i in 0..c.len() {
            for j in i + 1..c.len() {
                d = d.max(norm(sub(c[i], c[j])));
            }
        }
        d
    }

    /// Relative warp of a quad: the distance of its corners from their mean plane
    /// divided by its diameter, |(x0 − x1 + x2 − x3)·n| / (4 diam); 0 for a triangle.
    pub fn warp(&self) -> f64 {
        if self.kind == FaceKind::Tri3 {
            return 0.0;
        }
        let x = &self.x;
        let d = [
            x[0][0] - x[1][0] + x[2][0] - x[3][0],
            x[0][1] - x[1][1] + x[2][1] - x[3][1],
            x[0][2] - x[1][2] + x[2][2] - x[3][2],
        ];
        dot(d, self.normal()).abs() / (4.0 * self.diameter())
    }

    /// True for triangles and quads whose warp is below [`PLANAR_WARP`].
    pub fn is_planar(&self) -> bool {
        self.warp() < PLANAR_WARP
    }

    /// The reference cell as triangles: one for Tri3, two for Quad4
    /// ([`FaceKind::reference_triangles`]).
    pub fn reference_triangles(&self) -> &'static [[Xi; 3]] {
        self.kind.reference_triangles()
    }

    /// The face projected onto a plane by the linear map `project` (for seam,
    /// the projection along the slave normal, `clip::Frame::project`).
    pub fn project(&self, project: impl Fn(Point3) -> [f64; 2]) -> PlaneFace {
        PlaneFace::new(
            self.kind,
            [project(self.x[0]), project(self.x[1]), project(self.x[2]), project(self.x[3])],
        )
    }

    /// Inverse projection (D1–D2): the reference coordinates ξ of the point of the
    /// face whose projection by `project` is `target`. See [`PlaneFace::inverse`].
    pub fn inverse_project(&self, project: impl Fn(Point3) -> [f64; 2], target: [f64; 2]) -> InverseMap {
        self.project(project).inverse(target)
    }
}

/// A face projected onto a plane: its corners q_i in plane coordinates, with the
/// face's reference map kept (a quad stays bilinear). The map is stored as
/// q(ξ, η) = a + bξ + cη + dξη (d = 0 for a triangle) with [b c]⁻¹, so that
/// inverting it costs a few flops.
#[derive(Clone, Copy, Debug)]
pub struct PlaneFace {
    /// Element type: [`FaceKind::Tri3`] or [`FaceKind::Quad4`] (every other
    /// kind counts as a quad).
    pub kind: FaceKind,
    /// Projected corners; for a triangle `q[3]` repeats `q[2]`.
    pub q: [[f64; 2]; 4],
    a: [f64; 2],
    b: [f64; 2],
    c: [f64; 2],
    d: [f64; 2],
    /// [b c]⁻¹, row-major.
    inv: [[f64; 2]; 2],
    /// max(|b|, |c|): the size of the face in the plane.
    scale: f64,
    /// |d| ≤ 1e-13 · scale: see [`PlaneFace::is_affine`].
    affine: bool,
}

impl PlaneFace {
    /// The projected face with corners `q` (for a triangle `q[3]` is ignored).
    pub fn new(kind: FaceKind, q: [[f64; 2]; 4]) -> PlaneFace {
        let a = q[0];
        let b = sub2(q[1], q[0]);
        let (c, d) = if kind == FaceKind::Tri3 {
            (sub2(q[2], q[0]), [0.0; 2])
        } else {
            (sub2(q[3], q[0]), [q[0][0] - q[1][0] + q[2][0] - q[3][0], q[0][1] - q[1][1] + q[2][1] - q[3][1]])
        };
        let r = 1.0 / (b[0] * c[1] - b[1] * c[0]);
        let inv = [[c[1] * r, -c[0] * r], [-b[1] * r, b[0] * r]];
        let scale = norm2(b).max(norm2(c)).max(f64::MIN_POSITIVE);
        let affine = norm2(d) <= 1e-13 * scale;
        PlaneFace { kind, q, a, b, c, d, inv, scale, affine }
    }

    /// The projected corners actually used.
    pub fn corners(&self) -> &[[f64; 2]] {
        if self.kind == FaceKind::Tri3 {
            &self.q[..3]
        } else {
            &self.q
        }
    }

    /// The ξ with Σ λ_i(ξ) q_i = `target`. Triangle: closed form, ξ = [b c]⁻¹(p − a).
    /// Quad: Newton on the 2×2 bilinear system from that parallelogram guess
    /// (exact for parallelograms); if it does not converge in a few steps, the
    /// exact root of the system's quadratic is used (the safeguard). A quad
    /// that is a parallelogram to round-off ([`PlaneFace::is_affine`]) takes
    /// one fixed-point step ξ ← [b c]⁻¹(e − dξη) instead, exact to O(|d|²).
    #[inline]
    pub fn inverse(&self, target: [f64; 2]) -> InverseMap {
        let e = sub2(target, self.a);
        let xi = self.apply_inv(e);
        if self.kind == FaceKind::Tri3 {
            InverseMap::classify(xi, FaceKind::Tri3)
        } else if self.affine {
            let st = xi[0] * xi[1];
            let xi = self.apply_inv([e[0] - self.d[0] * st, e[1] - self.d[1] * st]);
            InverseMap::classify(xi, FaceKind::Quad4)
        } else {
            self.newton(xi, e)
        }
    }

    /// [b c]⁻¹ v.
    #[inline]
    fn apply_inv(&self, v: [f64; 2]) -> Xi {
        [self.inv[0][0] * v[0] + self.inv[0][1] * v[1], self.inv[1][0] * v[0] + self.inv[1][1] * v[1]]
    }

    /// As [`PlaneFace::inverse`], with Newton started from `guess` (for a
    /// quad that is not a parallelogram; the other inverses are closed-form): a point of a small plane triangle
    /// whose vertices' reference coordinates are known starts next to its root.
    #[inline]
    pub fn inverse_near(&self, target: [f64; 2], guess: Xi) -> InverseMap {
        if self.kind != FaceKind::Tri3 && !self.affine {
            self.newton(guess, sub2(target, self.a))
        } else {
            self.inverse(target)
        }
    }

    /// q(ξ) − a − e: the residual of the bilinear system at ξ.
    #[inline]
    fn residual(&self, xi: Xi, e: [f64; 2]) -> [f64; 2] {
        let (b, c, d) = (self.b, self.c, self.d);
        [
            b[0] * xi[0] + c[0] * xi[1] + d[0] * xi[0] * xi[1] - e[0],
            b[1] * xi[0] + c[1] * xi[1] + d[1] * xi[0] * xi[1] - e[1],
        ]
    }

    /// Newton from the parallelogram guess clamped into [0,1]²: started inside
    /// the element it finds the element's own root, not the second root of the
    /// bilinear system (which lies outside and which a strongly distorted quad's
    /// unclamped guess can lead to). A result outside the element, or no
    /// convergence, is checked against the exact roots: the one nearest the
    /// element wins.
    fn newton(&self, guess: Xi, e: [f64; 2]) -> InverseMap {
        let start = [guess[0].clamp(0.0, 1.0), guess[1].clamp(0.0, 1.0)];
        let newton = self.newton_from(start, e);
        if let Some(xi) = newton {
            if distance_to_square(xi) <= INSIDE_TOL {
                return InverseMap::classify(xi, FaceKind::Quad4);
            }
        }
        let residual = |xi: Xi| norm2(self.residual(xi, e)) / self.scale;
        let exact = closed_form_bilinear(self.b, self.c, self.d, e).filter(|&r| residual(r) < 1e-10);
        match (newton, exact) {
            (Some(n), Some(x)) if distance_to_square(x) < distance_to_square(n) => {
                InverseMap::classify(x, FaceKind::Quad4)
            }
            (Some(n), _) => InverseMap::classify(n, FaceKind::Quad4),
            (None, Some(x)) => InverseMap::classify(x, FaceKind::Quad4),
            (None, None) => {
                InverseMap::NotConverged { xi: start, iters: NEWTON_MAX_ITER, residual: residual(start) }
            }
        }
    }

    /// Plain Newton on the bilinear system; `None` if it does not converge.
    fn newton_from(&self, mut xi: Xi, e: [f64; 2]) -> Option<Xi> {
        let (b, c, d) = (self.b, self.c, self.d);
        for _ in 0..NEWTON_MAX_ITER {
            let r = self.residual(xi, e);
            if r[0].abs().max(r[1].abs()) <= NEWTON_RTOL * self.scale {
                return Some(xi);
            }
            let ja = [b[0] + d[0] * xi[1], b[1] + d[1] * xi[1]];
            let jb = [c[0] + d[0] * xi[0], c[1] + d[1] * xi[0]];
            let step = solve2(ja, jb, r);
            if !(step[0].is_finite() && step[1].is_finite()) {
                return None;
            }
            xi = [xi[0] - step[0], xi[1] - step[1]];
            if step[0].abs().max(step[1].abs()) < 1e-15 {
                return Some(xi);
            }
        }
        None
    }

    /// The map q(ξ) = a + bξ + cη + dξη.
    #[inline]
    pub fn map(&self, xi: Xi) -> [f64; 2] {
        let (a, b, c, d) = (self.a, self.b, self.c, self.d);
        let st = xi[0] * xi[1];
        [a[0] + b[0] * xi[0] + c[0] * xi[1] + d[0] * st, a[1] + b[1] * xi[0] + c[1] * xi[1] + d[1] * st]
    }

    /// det ∂q/∂ξ at ξ (constant for a triangle).
    #[inline]
    pub fn det(&self, xi: Xi) -> f64 {
        let ja = [self.b[0] + self.d[0] * xi[1], self.b[1] + self.d[1] * xi[1]];
        let jb = [self.c[0] + self.d[0] * xi[0], self.c[1] + self.d[1] * xi[0]];
        cross2(ja, jb)
    }

    /// ±1: the sign of det ∂q/∂ξ at the centre of the reference cell.
    pub fn orientation(&self) -> f64 {
        let m = if self.kind == FaceKind::Tri3 { 1.0 / 3.0 } else { 0.5 };
        let ja = [self.b[0] + self.d[0] * m, self.b[1] + self.d[1] * m];
        let jb = [self.c[0] + self.d[0] * m, self.c[1] + self.d[1] * m];
        if cross2(ja, jb) >= 0.0 {
            1.0
        } else {
            -1.0
        }
    }

    /// True when the map is affine: a triangle, or a quad whose projection is a
    /// parallelogram (to round-off).
    pub fn is_affine(&self) -> bool {
        self.affine
    }

    /// How far the inverse map ξ(q) is from a polynomial over a plane triangle
    /// whose vertices have reference coordinates `xi`: with det ∂q/∂ξ affine in
    /// ξ, |∇det| · diam(xi) / min_i |det(xi_i)|, the triangle's size over (up
    /// to a factor) its distance to the fold det = 0 where ξ(q) is singular.
    /// 0 for an affine map, infinite when det vanishes at a vertex.
    pub fn fold_ratio(&self, xi: &[Xi; 3]) -> f64 {
        if self.kind == FaceKind::Tri3 || self.is_affine() {
            return 0.0;
        }
        let gradient = [cross2(self.b, self.d), cross2(self.d, self.c)];
        let min_det = xi.iter().fold(f64::INFINITY, |m, &x| m.min(self.det(x).abs()));
        let diameter = (0..3).fold(0.0f64, |m, i| m.max(norm2(sub2(xi[i], xi[(i + 1) % 3]))));
        norm2(gradient) * diameter / min_det
    }

    /// How far the map is from affine: with det_i = det ∂q/∂ξ at the corners
    /// (det is affine in ξ, so these bound it), (max − min) / (max + min) of
    /// |det_i|; 0 for triangles and parallelograms, 1 when a corner's det
    /// vanishes or changes sign. The inverse map ξ(q), and with it the
    /// integrand of a segment in the plane, is analytic on the face with its
    /// singularities where det = 0, at a distance that shrinks as this grows.
    pub fn distortion(&self) -> f64 {
        if self.kind == FaceKind::Tri3 {
            return 0.0;
        }
        let dets = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].map(|xi| self.det(xi));
        let (lo, hi) =
            dets.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &d| (l.min(d), h.max(d)));
        if lo.signum() != hi.signum() || lo == 0.0 {
            return 1.0;
        }
        let (lo, hi) = if lo > 0.0 { (lo, hi) } else { (-hi, -lo) };
        (hi - lo) / (hi + lo)
    }
}

/// How far outside [0,1]² a converged root may lie and still be the element's own.
const INSIDE_TOL: f64 = 1e-9;

/// Distance from ξ to the square [0,1]² (0 inside).
fn distance_to_square(xi: Xi) -> f64 {
    let d = |v: f64| (v - v.clamp(0.0, 1.0)).abs();
    d(xi[0]).max(d(xi[1]))
}

/// Newton stops when the residual is below this fraction of the face size.
const NEWTON_RTOL: f64 = 1e-15;

/// The surface Jacobian |J(ξ)| of one face, ready to evaluate (see
/// [`FaceElement::jacobian_field`]).
#[derive(Clone, Copy, Debug)]
pub enum JacobianField {
    /// j0 + j1 ξ + j2 η (triangles, planar quads).
    Affine([f64; 3]),
    /// |v0 + ξ v1 + η v2| (warped quads).
    Norm([Point3; 3]),
}

impl JacobianField {
    /// True when |J| is constant (triangles, parallelograms), to round-off.
    pub fn is_constant(&self) -> bool {
        match self {
            JacobianField::Affine(j) => j[1].abs() + j[2].abs() <= 1e-13 * j[0].abs(),
            JacobianField::Norm(_) => false,
        }
    }

    /// |J(ξ)|.
    #[inline]
    pub fn at(&self, xi: Xi) -> f64 {
        match self {
            JacobianField::Affine(j) => j[0] + j[1] * xi[0] + j[2] * xi[1],
            JacobianField::Norm(v) => {
                let w = [
                    v[0][0] + xi[0] * v[1][0] + xi[1] * v[2][0],
                    v[0][1] + xi[0] * v[1][1] + xi[1] * v[2][1],
                    v[0][2] + xi[0] * v[1][2] + xi[1] * v[2][2],
                ];
                norm(w)
            }
        }
    }
}

/// Result of an inverse projection, degenerate cases being values (not errors).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InverseMap {
    /// Converged, inside the reference cell (up to 1e-10).
    Inside(Xi),
    /// Converged, outside the reference cell.
    Outside(Xi),
    /// Neither Newton nor the closed-form safeguard gave a root; `xi` is the best
    /// iterate.
    NotConverged {
        /// Best iterate.
        xi: Xi,
        /// Newton iterations used.
        iters: usize,
        /// Residual |P(x(ξ)) − target| relative to the face size.
        residual: f64,
    },
}

impl InverseMap {
    /// The reference coordinates, whatever the status.
    pub fn xi(&self) -> Xi {
        match *self {
            InverseMap::Inside(xi) | InverseMap::Outside(xi) => xi,
            InverseMap::NotConverged { xi, .. } => xi,
        }
    }

    fn classify(xi: Xi, kind: FaceKind) -> InverseMap {
        const TOL: f64 = 1e-10;
        let inside = if kind == FaceKind::Tri3 {
            xi[0] >= -TOL && xi[1] >= -TOL && xi[0] + xi[1] <= 1.0 + TOL
        } else {
            xi.iter().all(|&v| (-TOL..=1.0 + TOL).contains(&v))
        };
        if inside {
            InverseMap::Inside(xi)
        } else {
            InverseMap::Outside(xi)
        }
    }
}

/// Newton iterations allowed before the closed-form safeguard.
const NEWTON_MAX_ITER: usize = 12;

/// Exact inverse of e = bξ + cη + dξη: crossing with (c + dξ) eliminates η and
/// leaves (b×d) ξ² + (b×c − e×d) ξ − e×c = 0; of its (up to two) roots, with η
/// from the least-squares solve of the remaining linear equation, the one
/// nearest [0,1]² is returned.
fn closed_form_bilinear(b: [f64; 2], c: [f64; 2], d: [f64; 2], e: [f64; 2]) -> Option<Xi> {
    let qa = cross2(b, d);
    let qb = cross2(b, c) - cross2(e, d);
    let qc = -cross2(e, c);
    let roots: [f64; 2] = if qa.abs() <= 1e-14 * qb.abs() {
        [-qc / qb, f64::NAN]
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            return None;
        }
        let t = -0.5 * (qb + qb.signum() * disc.sqrt());
        [t / qa, qc / t]
    };
    let with_eta = |s: f64| {
        let g = [c[0] + d[0] * s, c[1] + d[1] * s];
        let t = ((e[0] - b[0] * s) * g[0] + (e[1] - b[1] * s) * g[1]) / (g[0] * g[0] + g[1] * g[1]);
        (s.is_finite() && t.is_finite()).then_some([s, t])
    };
    match (with_eta(roots[0]), with_eta(roots[1])) {
        (Some(x), Some(y)) => Some(if distance_to_square(x) <= distance_to_square(y) { x } else { y }),
        (x, y) => x.or(y),
    }
}

/// Solves [a b] x = r for x (2×2, columns a and b) by Cramer's rule.
#[inline]
fn solve2(a: [f64; 2], b: [f64; 2], r: [f64; 2]) -> [f64; 2] {
    let det = a[0] * b[1] - a[1] * b[0];
    [(r[0] * b[1] - r[1] * b[0]) / det, (a[0] * r[1] - a[1] * r[0]) / det]
}

#[inline]
fn sub2(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline]
fn cross2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[inline]
fn norm2(a: [f64; 2]) -> f64 {
    (a[0] * a[0] + a[1] * a[1]).sqrt()
}

/// a − b.
#[inline]
pub fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a · b.
#[inline]
pub fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b.
#[inline]
pub fn cross(a: Point3, b: Point3) -> Point3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// |a|.
#[inline]
pub fn norm(a: Point3) -> f64 {
    dot(a, a).sqrt()
}

#[inline]
pub(crate) fn scale(a: Point3, s: f64) -> Point3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalogue::shape_values;
    use proptest::prelude::*;

    fn quad(x: [Point3; 4]) -> FaceElement {
        FaceElement { kind: FaceKind::Quad4, x }
    }

    /// Projection onto the xy-plane (along e3).
    fn xy(p: Point3) -> [f64; 2] {
        [p[0], p[1]]
    }

    fn warped_quad(h: [f64; 4], jitter: [f64; 8]) -> FaceElement {
        quad([
            [0.0 + jitter[0], 0.0 + jitter[1], h[0]],
            [1.0 + jitter[2], 0.0 + jitter[3], h[1]],
            [1.0 + jitter[4], 1.0 + jitter[5], h[2]],
            [0.0 + jitter[6], 1.0 + jitter[7], h[3]],
        ])
    }

    #[test]
    fn shape_functions_are_a_partition_of_unity_and_nodal() {
        for kind in [FaceKind::Tri3, FaceKind::Quad4] {
            let face = FaceElement { kind, x: [[0.0; 3]; 4] };
            let corners = kind.nodes();
            for (i, &c) in corners.iter().enumerate() {
                let l = face.shape(c);
                for (j, &v) in l.iter().enumerate().take(corners.len()) {
                    assert_eq!(v, if i == j { 1.0 } else { 0.0 });
                }
            }
            let l = face.shape([0.3, 0.2]);
            assert!((l.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn jacobian_of_hyperbolic_paraboloid_quad_matches_closed_form() {
        // x(ξ,η) = (ξ, η, cξη) on [0,1]²: |J| = sqrt(1 + c²(ξ² + η²)).
        let c = 0.7;
        let q = quad([[0., 0., 0.], [1., 0., 0.], [1., 1., c], [0., 1., 0.]]);
        for xi in [[0.2, 0.9], [0.5, 0.5], [1.0, 0.0]] {
            let exact = (1.0 + c * c * (xi[0] * xi[0] + xi[1] * xi[1])).sqrt();
            assert!((q.jacobian(xi) - exact).abs() < 1e-15);
            let x = q.map(xi);
            assert!((x[2] - c * xi[0] * xi[1]).abs() < 1e-15);
        }
        // d = x0 − x1 + x2 − x3 = (0, 0, c), n ∝ (−c, −c, 2), diam = √(2 + c²).
        assert!((q.warp() - c / (2.0 * 2f64.sqrt() * (2.0 + c * c))).abs() < 1e-15);
        assert!(!q.is_planar());
    }

    #[test]
    fn jacobian_field_matches_the_tangents() {
        let faces = [
            quad([[0., 0., 0.], [1., 0., 0.], [1., 1., 0.7], [0., 1., 0.]]),
            quad([[0., 0., 0.], [2., 0., 0.], [1.5, 1., 0.], [0.2, 0.8, 0.]]),
            quad([[0., 0., 0.], [0.2, 0.8, 0.], [1.5, 1., 0.], [2., 0., 0.]]),
            FaceElement {
                kind: FaceKind::Tri3,
                x: [[0., 0., 0.], [1., 0.2, 0.3], [0.1, 1., -0.2], [0.1, 1., -0.2]],
            },
        ];
        for f in faces {
            let field = f.jacobian_field();
            for xi in [[0.0, 0.0], [0.3, 0.6], [1.0, 1.0], [0.9, 0.05]] {
                let xi = if f.kind == FaceKind::Tri3 { [xi[0] * 0.5, xi[1] * 0.5] } else { xi };
                assert!((field.at(xi) - f.jacobian(xi)).abs() < 1e-15, "{f:?} at {xi:?}");
            }
        }
    }

    #[test]
    fn planar_quads_are_recognised() {
        let q = quad([[0., 0., 0.], [2., 0., 0.], [1.5, 1., 0.], [0.2, 0.8, 0.]]);
        assert!(q.is_planar());
        assert_eq!(q.warp(), 0.0);
    }

    #[test]
    fn newton_safeguard_recovers_from_a_bad_guess() {
        // A strongly non-parallelogram quad, point near a corner.
        let q = [[0., 0.], [1., 0.], [0.05, 0.06], [0., 1.]];
        let target = [0.04, 0.05];
        let xi = PlaneFace::new(FaceKind::Quad4, q).inverse(target).xi();
        let l = shape_values::<4>(xi);
        let p = [
            l[0] * q[0][0] + l[1] * q[1][0] + l[2] * q[2][0] + l[3] * q[3][0],
            l[0] * q[0][1] + l[1] * q[1][1] + l[2] * q[2][1] + l[3] * q[3][1],
        ];
        assert!((p[0] - target[0]).abs() < 1e-13 && (p[1] - target[1]).abs() < 1e-13, "{xi:?} -> {p:?}");
    }

    /// issue: a convex quad with a 148° angle (from a jittered 200k-face mesh)
    /// whose parallelogram guess for its third corner led Newton to the second
    /// root (−0.431, 2.343) of the bilinear system instead of (1, 1).
    #[test]
    fn newton_finds_the_elements_root_on_a_distorted_convex_quad() {
        let q = [
            [0.7870618857440987, 0.9534040592414329],
            [0.7901480800975261, 0.9525948663665575],
            [0.7893474648094624, 0.955697475223923],
            [0.7879061164954276, 0.9549118483176244],
        ];
        let face = PlaneFace::new(FaceKind::Quad4, q);
        for (k, corner) in [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].into_iter().enumerate() {
            let xi = face.inverse(q[k]).xi();
            assert!(
                (xi[0] - corner[0]).abs() < 1e-9 && (xi[1] - corner[1]).abs() < 1e-9,
                "corner {k}: {xi:?}"
            );
        }
    }

    /// A random convex quad, possibly strongly distorted: four points at random
    /// angles on an ellipse (angles in order), so the quad is convex with
    /// interior angles up to nearly 180°.
    fn distorted_convex_quad() -> impl Strategy<Value = [[f64; 2]; 4]> {
        (prop::array::uniform4(0.0f64..1.0), 0.2f64..1.0, 0.0f64..3.1).prop_map(|(u, aspect, tilt)| {
            let mut a: Vec<f64> = u
                .iter()
                .enumerate()
                .map(|(i, v)| (i as f64 + 0.05 + 0.9 * v) * std::f64::consts::FRAC_PI_2)
                .collect();
            a.sort_by(f64::total_cmp);
            let p = |t: f64| {
                let (x, y) = (t.cos(), aspect * t.sin());
                [x * tilt.cos() - y * tilt.sin(), x * tilt.sin() + y * tilt.cos()]
            };
            [p(a[0]), p(a[1]), p(a[2]), p(a[3])]
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// On any convex quad, however distorted, the inverse of a point of the
        /// element is its own reference coordinate.
        #[test]
        fn inverse_is_exact_on_distorted_convex_quads(q in distorted_convex_quad(), s in 0.0f64..1.0, t in 0.0f64..1.0) {
            let face = PlaneFace::new(FaceKind::Quad4, q);
            let r = face.inverse(face.map([s, t]));
            let xi = r.xi();
            prop_assert!(matches!(r, InverseMap::Inside(_)), "{r:?}");
            prop_assert!((xi[0] - s).abs() < 1e-7 && (xi[1] - t).abs() < 1e-7, "{xi:?} vs ({s}, {t})");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// inverse_project(project(map(ξ))) = ξ on randomly warped quads.
        #[test]
        fn inverse_projection_inverts_the_quad_map(
            h in prop::array::uniform4(-0.4f64..0.4),
            jitter in prop::array::uniform8(-0.2f64..0.2),
            s in 0.0f64..1.0, t in 0.0f64..1.0,
        ) {
            let q = warped_quad(h, jitter);
            let inv = q.inverse_project(xy, xy(q.map([s, t])));
            let xi = inv.xi();
            prop_assert!(matches!(inv, InverseMap::Inside(_)), "{inv:?}");
            prop_assert!((xi[0] - s).abs() < 1e-12 && (xi[1] - t).abs() < 1e-12, "{xi:?} vs {s},{t}");
        }

        #[test]
        fn inverse_projection_inverts_the_triangle_map(
            x in prop::array::uniform9(-1.0f64..1.0), s in 0.0f64..1.0, t in 0.0f64..1.0,
        ) {
            let tri = FaceElement {
                kind: FaceKind::Tri3,
                x: [[x[0], x[1], x[2]], [x[3] + 2.0, x[4], x[5]], [x[6], x[7] + 2.0, x[8]], [x[6], x[7] + 2.0, x[8]]],
            };
            let (s, t) = if s + t > 1.0 { (1.0 - s, 1.0 - t) } else { (s, t) };
            let xi = tri.inverse_project(xy, xy(tri.map([s, t]))).xi();
            prop_assert!((xi[0] - s).abs() < 1e-10 && (xi[1] - t).abs() < 1e-10);
        }
    }
}
