//! Isoparametric faces, in particular the second-order (curved) ones: Tri6,
//! Quad8 and Quad9 shape functions and their gradients (and, as the flat
//! special cases, Tri3 and Quad4), the face map x(ξ) = Σ N_i(ξ) x_i with its
//! tangents and surface Jacobian, its Bernstein control net (whose convex hull
//! encloses the face), and the inverse projection of a point along a direction
//! onto the true curved face (paper step D2 for isoparametric faces). The
//! operator uses it for every pair with a second-order face.
//!
//! Reference cells and node order are those of the first-order faces
//! ([`crate::FaceKind`]) and Gmsh:
//! vertices first, then the mid-edge nodes of edges (0,1), (1,2), (2,0) or
//! (0,1), (1,2), (2,3), (3,0), then (Quad9) the centre.
//!
//! | face | reference cell | shape functions |
//! |---|---|---|
//! | Tri6 | {(0,0), (1,0), (0,1)} | L_i(2L_i − 1) at vertices, 4 L_i L_j at mid-edges (L = 1−ξ−η, ξ, η) |
//! | Quad9 | \[0,1\]² | tensor products of ℓ₀ = (1−s)(1−2s), ℓ₁ = s(2s−1), ℓ_m = 4s(1−s) |
//! | Quad8 | \[0,1\]² | serendipity: Quad9 without the centre bubble, its share given to the others |
//!
//! Tri6 and Quad9 reproduce every quadratic polynomial in (ξ, η), Quad8 every
//! one of degree 2 (and ξ²η, ξη²).

use crate::clip::Frame;
use crate::element::{cross, dot, norm, sub, Xi};
use crate::mesh::{Face, Point3, SurfaceMesh};

/// A face type as an isoparametric map: the second-order ones and, as their
/// flat special cases, Tri3 and Quad4.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurvedKind {
    /// 3-node triangle (Gmsh type 2).
    Tri3,
    /// 4-node bilinear quadrangle (Gmsh type 3).
    Quad4,
    /// 6-node triangle (Gmsh type 9).
    Tri6,
    /// 8-node serendipity quadrangle (Gmsh type 16).
    Quad8,
    /// 9-node Lagrange quadrangle (Gmsh type 10).
    Quad9,
}

impl CurvedKind {
    /// The number of nodes.
    pub fn n_nodes(self) -> usize {
        match self {
            CurvedKind::Tri3 => 3,
            CurvedKind::Quad4 => 4,
            CurvedKind::Tri6 => 6,
            CurvedKind::Quad8 => 8,
            CurvedKind::Quad9 => 9,
        }
    }

    /// The reference coordinates of the nodes, in node order.
    pub fn nodes(self) -> &'static [Xi] {
        const TRI6: [Xi; 6] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]];
        const QUAD9: [Xi; 9] = [
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [0.5, 0.0],
            [1.0, 0.5],
            [0.5, 1.0],
            [0.0, 0.5],
            [0.5, 0.5],
        ];
        match self {
            CurvedKind::Tri3 => &TRI6[..3],
            CurvedKind::Quad4 => &QUAD9[..4],
            CurvedKind::Tri6 => &TRI6,
            CurvedKind::Quad8 => &QUAD9[..8],
            CurvedKind::Quad9 => &QUAD9,
        }
    }

    /// True for a point of the reference cell, enlarged by `tol`.
    pub fn contains(self, xi: Xi, tol: f64) -> bool {
        let [s, t] = xi;
        match self {
            CurvedKind::Tri3 | CurvedKind::Tri6 => s >= -tol && t >= -tol && s + t <= 1.0 + tol,
            CurvedKind::Quad4 | CurvedKind::Quad8 | CurvedKind::Quad9 => {
                (-tol..=1.0 + tol).contains(&s) && (-tol..=1.0 + tol).contains(&t)
            }
        }
    }

    /// The reference centroid.
    pub fn centre(self) -> Xi {
        if self.is_triangle() {
            [1.0 / 3.0, 1.0 / 3.0]
        } else {
            [0.5, 0.5]
        }
    }

    /// True for Tri3 and Tri6.
    pub fn is_triangle(self) -> bool {
        matches!(self, CurvedKind::Tri3 | CurvedKind::Tri6)
    }

    /// The kind of a mesh face.
    pub fn of(face: &Face) -> CurvedKind {
        match face {
            Face::Tri3(_) => CurvedKind::Tri3,
            Face::Quad4(_) => CurvedKind::Quad4,
            Face::Tri6(_) => CurvedKind::Tri6,
            Face::Quad8(_) => CurvedKind::Quad8,
            Face::Quad9(_) => CurvedKind::Quad9,
        }
    }
}

/// (index along ξ, index along η) of each Quad9 node in the 3 × 3 tensor grid
/// of 1D Lagrange functions.
const QUAD9_GRID: [(usize, usize); 9] =
    [(0, 0), (1, 0), (1, 1), (0, 1), (2, 0), (1, 2), (2, 1), (0, 2), (2, 2)];

/// Quadratic Lagrange polynomials on [0, 1] with nodes 0, 1, 1/2 and their
/// derivatives: ([ℓ₀, ℓ₁, ℓ_m], [ℓ₀', ℓ₁', ℓ_m']).
#[inline]
fn lagrange(s: f64) -> ([f64; 3], [f64; 3]) {
    (
        [(1.0 - s) * (1.0 - 2.0 * s), s * (2.0 * s - 1.0), 4.0 * s * (1.0 - s)],
        [4.0 * s - 3.0, 4.0 * s - 1.0, 4.0 - 8.0 * s],
    )
}

/// Shape functions N_i(ξ) and gradients ∂N_i/∂(ξ, η) of `kind`; entries past
/// `kind.n_nodes()` are 0.
#[inline(always)]
pub fn shape_and_gradients(kind: CurvedKind, xi: Xi) -> ([f64; 9], [[f64; 2]; 9]) {
    let (mut n, mut g) = ([0.0; 9], [[0.0; 2]; 9]);
    match kind {
        CurvedKind::Tri3 => {
            let [s, t] = xi;
            n[..3].copy_from_slice(&[1.0 - s - t, s, t]);
            g[..3].copy_from_slice(&[[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]);
        }
        CurvedKind::Quad4 => {
            let [s, t] = xi;
            n[..4].copy_from_slice(&shape_values::<4>(xi));
            g[..4].copy_from_slice(&[[t - 1.0, s - 1.0], [1.0 - t, -s], [t, s], [-t, 1.0 - s]]);
        }
        CurvedKind::Tri6 => {
            // Barycentric l = (1 − s − t, s, t): vertices l_i (2 l_i − 1),
            // mid-edge nodes 4 l_i l_(i+1).
            let [s, t] = xi;
            let l0 = 1.0 - s - t;
            n[..6].copy_from_slice(&shape_values::<6>(xi));
            let (c0, c1, c2) = (4.0 * l0 - 1.0, 4.0 * s - 1.0, 4.0 * t - 1.0);
            g[..6].copy_from_slice(&[
                [-c0, -c0],
                [c1, 0.0],
                [0.0, c2],
                [4.0 * (l0 - s), -4.0 * s],
                [4.0 * t, 4.0 * s],
                [-4.0 * t, 4.0 * (l0 - t)],
            ]);
        }
        CurvedKind::Quad8 | CurvedKind::Quad9 => {
            let ((a, da), (b, db)) = (lagrange(xi[0]), lagrange(xi[1]));
            for (i, &(p, q)) in QUAD9_GRID.iter().enumerate() {
                n[i] = a[p] * b[q];
                g[i] = [da[p] * b[q], a[p] * db[q]];
            }
            if kind == CurvedKind::Quad8 {
                // Serendipity: the bubble N₈ = ℓ_m ℓ_m goes back to the other
                // nodes by its values there (−1/4 at vertices, +1/2 at mid-edges).
                let (bubble, grad) = (n[8], g[8]);
                for i in 0..8 {
                    let w = if i < 4 { -0.25 } else { 0.5 };
                    n[i] += w * bubble;
                    g[i] = [g[i][0] + w * grad[0], g[i][1] + w * grad[1]];
                }
                n[8] = 0.0;
                g[8] = [0.0; 2];
            }
        }
    }
    (n, g)
}

/// Shape function values N_i(ξ) of the kind with `N` nodes (3 Tri3, 4 Quad4,
/// 6 Tri6, 8 Quad8, 9 Quad9): [`shape_and_gradients`] without the gradients,
/// sized for the quadrature loops.
#[inline(always)]
pub fn shape_values<const N: usize>(xi: Xi) -> [f64; N] {
    let [s, t] = xi;
    let mut n = [0.0; N];
    match N {
        3 => n.copy_from_slice(&[1.0 - s - t, s, t]),
        4 => n.copy_from_slice(&[(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t]),
        6 => {
            let l0 = 1.0 - s - t;
            n.copy_from_slice(&[
                l0 * (2.0 * l0 - 1.0),
                s * (2.0 * s - 1.0),
                t * (2.0 * t - 1.0),
                4.0 * l0 * s,
                4.0 * s * t,
                4.0 * t * l0,
            ]);
        }
        8 | 9 => {
            let (a, b) = (lagrange(s).0, lagrange(t).0);
            let mut all = [0.0; 9];
            for (i, &(p, q)) in QUAD9_GRID.iter().enumerate() {
                all[i] = a[p] * b[q];
            }
            if N == 8 {
                // Serendipity: the bubble goes back to the other nodes.
                let bubble = all[8];
                for (i, v) in all.iter_mut().enumerate().take(8) {
                    *v += if i < 4 { -0.25 } else { 0.5 } * bubble;
                }
            }
            n.copy_from_slice(&all[..N]);
        }
        _ => unreachable!("faces have 3, 4, 6, 8 or 9 nodes"),
    }
    n
}

/// How many of the monomials of [`MonomialMap`] the map of a face with
/// `n_nodes` nodes uses (they come in the order 1, s, t, s², st, t², s²t, st²,
/// s²t²): Tri3 the first 3, Quad4 5 (no s², but st), Tri6 6, Quad8 8, Quad9
/// 9. The coefficients of the others are zero.
pub const fn monomials_of(n_nodes: usize) -> usize {
    match n_nodes {
        3 => 3,
        4 => 5,
        6 => 6,
        8 => 8,
        _ => MONOMIALS,
    }
}

/// The biquadratic monomials m(ξ) = (1, s, t, s², st, t², s²t, st², s²t²) in
/// which every face map of this module is a polynomial (Tri6 uses the first
/// six, Quad8 the first eight).
const MONOMIALS: usize = 9;

/// Row i: the coefficients of shape function N_i of `kind` in the monomials.
const fn shape_monomials(kind: CurvedKind) -> [[f64; MONOMIALS]; 9] {
    let mut c = [[0.0; MONOMIALS]; 9];
    match kind {
        CurvedKind::Tri3 => {
            c[0] = [1.0, -1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
            c[1][1] = 1.0;
            c[2][2] = 1.0;
        }
        CurvedKind::Quad4 => {
            c[0] = [1.0, -1.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0];
            c[1] = [0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0];
            c[2][4] = 1.0;
            c[3] = [0.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0];
        }
        CurvedKind::Tri6 => {
            c[0] = [1.0, -3.0, -3.0, 2.0, 4.0, 2.0, 0.0, 0.0, 0.0];
            c[1] = [0.0, -1.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0];
            c[2] = [0.0, 0.0, -1.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0];
            c[3] = [0.0, 4.0, 0.0, -4.0, -4.0, 0.0, 0.0, 0.0, 0.0];
            c[4][4] = 4.0;
            c[5] = [0.0, 0.0, 4.0, 0.0, -4.0, -4.0, 0.0, 0.0, 0.0];
        }
        CurvedKind::Quad8 | CurvedKind::Quad9 => {
            // N_i = L_p(s) L_q(t) ([`QUAD9_GRID`]), L (`lagrange`) in powers
            // of its variable; INDEX[a][b] is the monomial s^a t^b.
            const L: [[f64; 3]; 3] = [[1.0, -3.0, 2.0], [0.0, -1.0, 2.0], [0.0, 4.0, -4.0]];
            const INDEX: [[usize; 3]; 3] = [[0, 2, 5], [1, 4, 7], [3, 6, 8]];
            let mut i = 0;
            while i < 9 {
                let (p, q) = QUAD9_GRID[i];
                let mut a = 0;
                while a < 3 {
                    let mut b = 0;
                    while b < 3 {
                        c[i][INDEX[a][b]] = L[p][a] * L[q][b];
                        b += 1;
                    }
                    a += 1;
                }
                i += 1;
            }
            if matches!(kind, CurvedKind::Quad8) {
                // Serendipity: the bubble goes back to the other nodes.
                let mut i = 0;
                while i < 8 {
                    let w = if i < 4 { -0.25 } else { 0.5 };
                    let mut k = 0;
                    while k < MONOMIALS {
                        c[i][k] += w * c[8][k];
                        k += 1;
                    }
                    i += 1;
                }
                c[8] = [0.0; MONOMIALS];
            }
        }
    }
    c
}

/// [`shape_monomials`] of every kind, by `CurvedKind as usize`.
const SHAPE_MONOMIALS: [[[f64; MONOMIALS]; 9]; 5] = [
    shape_monomials(CurvedKind::Tri3),
    shape_monomials(CurvedKind::Quad4),
    shape_monomials(CurvedKind::Tri6),
    shape_monomials(CurvedKind::Quad8),
    shape_monomials(CurvedKind::Quad9),
];

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
    pub fn new(kind: CurvedKind, x: &[[f64; D]; 9]) -> MonomialMap<D> {
        let table = &SHAPE_MONOMIALS[kind as usize];
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
    pub kind: CurvedKind,
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
    pub fn new(kind: CurvedKind, nodes: &[Point3]) -> CurvedFace {
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
        CurvedFace { kind: CurvedKind::of(face), x }
    }

    /// The nodes in use.
    pub fn nodes(&self) -> &[Point3] {
        &self.x[..self.kind.n_nodes()]
    }

    /// The Bernstein control net of the map (its first `n` entries): the face
    /// lies in the convex hull of these points, so their box encloses it. For a
    /// quadratic edge with end values a, b and mid value m the inner control
    /// point is 2m − (a + b)/2; Quad8 is first written as the Quad9 with the
    /// same map (serendipity ⊂ biquadratic), Quad9 is the tensor product.
    pub fn control_net(&self) -> ([Point3; 9], usize) {
        let x = &self.x;
        let inner = |a: Point3, m: Point3, b: Point3| -> Point3 {
            std::array::from_fn(|k| 2.0 * m[k] - 0.5 * (a[k] + b[k]))
        };
        let mut c = *x;
        match self.kind {
            CurvedKind::Tri3 | CurvedKind::Quad4 => {}
            CurvedKind::Tri6 => {
                for i in 0..3 {
                    c[3 + i] = inner(x[i], x[3 + i], x[(i + 1) % 3]);
                }
            }
            CurvedKind::Quad8 | CurvedKind::Quad9 => {
                let centre = self.map([0.5, 0.5]);
                for i in 0..4 {
                    c[4 + i] = inner(x[i], x[4 + i], x[(i + 1) % 4]);
                }
                // Along ξ through the middle row (nodes 7, 8, 5), then along η.
                let middle = inner(x[7], centre, x[5]);
                c[8] = inner(c[4], middle, c[6]);
            }
        }
        (c, if self.kind == CurvedKind::Quad8 { 9 } else { self.kind.n_nodes() })
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

    const KINDS: [CurvedKind; 3] = [CurvedKind::Tri6, CurvedKind::Quad8, CurvedKind::Quad9];

    /// Points of the reference cell (and a little outside) to test at.
    fn samples(kind: CurvedKind) -> Vec<Xi> {
        let mut out = Vec::new();
        for i in 0..=6 {
            for j in 0..=6 {
                let xi = [-0.1 + 1.2 * i as f64 / 6.0, -0.1 + 1.2 * j as f64 / 6.0];
                if kind.contains(xi, 0.1) {
                    out.push(xi);
                }
            }
        }
        out
    }

    #[test]
    fn shape_functions_are_a_partition_of_unity_and_nodal() {
        for kind in KINDS {
            for xi in samples(kind) {
                let (n, g) = shape_and_gradients(kind, xi);
                assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14, "{kind:?} {xi:?}");
                for k in 0..2 {
                    assert!(g.iter().map(|g| g[k]).sum::<f64>().abs() < 1e-13, "{kind:?} {xi:?}");
                }
            }
            for (i, &node) in kind.nodes().iter().enumerate() {
                let (n, _) = shape_and_gradients(kind, node);
                for (j, &v) in n.iter().enumerate().take(kind.n_nodes()) {
                    let expected = if i == j { 1.0 } else { 0.0 };
                    assert!((v - expected).abs() < 1e-15, "{kind:?}: N_{j}(node {i}) = {v}");
                }
            }
        }
    }

    /// The node order is Gmsh's: the reference nodes Gmsh reports for types
    /// 9 (Tri6), 16 (Quad8) and 10 (Quad9), recorded by seam-io's fixture
    /// script (Gmsh's quads live on [−1,1]², ours on [0,1]²).
    #[test]
    fn nodes_are_in_gmsh_order() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../seam-io/tests/data/second_order.txt");
        let text = std::fs::read_to_string(path).unwrap();
        for (gmsh_type, kind) in [(9, CurvedKind::Tri6), (16, CurvedKind::Quad8), (10, CurvedKind::Quad9)] {
            let line = text.lines().find(|l| l.starts_with(&format!("ref {gmsh_type} "))).unwrap();
            let gmsh: Vec<Xi> = line
                .split_whitespace()
                .nth(3)
                .unwrap()
                .split(';')
                .map(|node| {
                    let c: Vec<f64> = node.split(',').map(|v| v.parse().unwrap()).collect();
                    match kind {
                        CurvedKind::Tri6 => [c[0], c[1]],
                        _ => [(c[0] + 1.0) / 2.0, (c[1] + 1.0) / 2.0],
                    }
                })
                .collect();
            assert_eq!(gmsh, kind.nodes(), "{kind:?}");
        }
    }

    #[test]
    fn gradients_match_finite_differences() {
        let h = 1e-6;
        for kind in KINDS {
            for xi in samples(kind) {
                let (_, g) = shape_and_gradients(kind, xi);
                for k in 0..2 {
                    let (mut a, mut b) = (xi, xi);
                    a[k] += h;
                    b[k] -= h;
                    let (na, nb) = (shape_and_gradients(kind, a).0, shape_and_gradients(kind, b).0);
                    for i in 0..9 {
                        let fd = (na[i] - nb[i]) / (2.0 * h);
                        assert!(
                            (g[i][k] - fd).abs() < 1e-8,
                            "{kind:?} {xi:?} ∂N_{i}/∂ξ_{k}: {} vs {fd}",
                            g[i][k]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn quadratic_fields_are_reproduced() {
        // Every quadratic monomial (and, for the quads, ξ²η and ξη²; Quad9 also ξ²η²).
        type Field = fn(f64, f64) -> f64;
        let fields: [(Field, [bool; 3]); 9] = [
            (|_, _| 1.0, [true; 3]),
            (|s, _| s, [true; 3]),
            (|_, t| t, [true; 3]),
            (|s, _| s * s, [true; 3]),
            (|s, t| s * t, [true; 3]),
            (|_, t| t * t, [true; 3]),
            (|s, t| s * s * t, [false, true, true]),
            (|s, t| s * t * t, [false, true, true]),
            (|s, t| s * s * t * t, [false, false, true]),
        ];
        for (f, exact_for) in fields {
            for (k, kind) in KINDS.into_iter().enumerate().filter(|&(k, _)| exact_for[k]) {
                let values: Vec<f64> = kind.nodes().iter().map(|x| f(x[0], x[1])).collect();
                for xi in samples(kind) {
                    let (n, _) = shape_and_gradients(kind, xi);
                    let interpolated: f64 = values.iter().zip(&n).map(|(v, n)| v * n).sum();
                    assert!((interpolated - f(xi[0], xi[1])).abs() < 1e-14, "{kind:?} field {k} at {xi:?}");
                }
            }
        }
    }

    /// A face of `kind` on the sphere of radius `r` around the origin over
    /// the angular patch θ ∈ [0, a], φ ∈ [−a/2, a/2] (nodes on the sphere).
    fn sphere_face(kind: CurvedKind, r: f64, a: f64) -> CurvedFace {
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
        let all =
            [CurvedKind::Tri3, CurvedKind::Quad4, CurvedKind::Tri6, CurvedKind::Quad8, CurvedKind::Quad9];
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

    /// The control net is the face's Bernstein–Bézier net: the map equals
    /// Σ_i B_i(ξ) c_i with Bernstein polynomials B_i ≥ 0, Σ B_i = 1, so the face
    /// lies in the convex hull of the c_i and their box encloses it (the
    /// search boxes of (A1)). Checked on strongly curved faces (mid-side and
    /// centre nodes moved by up to half the face size), with every sampled
    /// point of the face inside the net's box.
    #[test]
    fn the_control_net_is_the_bezier_net_and_its_box_encloses_the_face() {
        let mut seed = 3u64;
        let mut random = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
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
                        QUAD9_GRID.iter().map(|&(p, q)| a[p] * b[q]).collect()
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

    #[test]
    fn a_line_that_misses_or_grazes_gives_no_inside_hit() {
        let face = sphere_face(CurvedKind::Quad9, 1.0, 0.5);
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
        for kind in [CurvedKind::Quad8, CurvedKind::Quad9] {
            let face = sphere_face(kind, 1.0, a);
            // 8-point Gauss–Legendre product rule on [0,1]².
            let (x, w) = gauss(8);
            let mut area = 0.0;
            for i in 0..8 {
                for j in 0..8 {
                    area += w[i] * w[j] * face.jacobian([x[i], x[j]]);
                }
            }
            assert!((area - exact).abs() < 1e-4 * exact, "{kind:?}: {area} vs {exact}");
        }
        let flat = CurvedFace::new(
            CurvedKind::Quad9,
            &CurvedKind::Quad9.nodes().iter().map(|&[s, t]| [2.0 * s, 3.0 * t, 0.0]).collect::<Vec<_>>(),
        );
        assert!((flat.jacobian([0.3, 0.7]) - 6.0).abs() < 1e-14);
    }

    /// Gauss–Legendre points and weights on [0, 1], by Newton on P_n.
    fn gauss(n: usize) -> (Vec<f64>, Vec<f64>) {
        let (mut x, mut w) = (vec![0.0; n], vec![0.0; n]);
        for i in 0..n {
            let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, z);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                    (p0, p1) = (p1, p2);
                }
                dp = n as f64 * (z * p1 - p0) / (z * z - 1.0);
                let dz = p1 / dp;
                z -= dz;
                if dz.abs() < 1e-16 {
                    break;
                }
            }
            x[i] = 0.5 * (1.0 - z);
            w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
        }
        (x, w)
    }
}
