//! Multiplier spaces, applied per slave face to its standard blocks.
//!
//! With M_e the standard block of face e on its covered part,
//! (M_e)_pq = ∫_{e,cov} λ_p λ_q, and D_e = diag(M_e 1) = diag(∫_{e,cov} λ_p):
//!
//! - dual: ψ_p = Σ_r a_pr λ_r with A = D_e M_e⁻¹, so that ∫_{e,cov} ψ_p λ_q =
//!   (A M_e)_pq = δ_pq ∫_{e,cov} λ_p. The face's D block becomes D_e and its B
//!   block A·B_e. Since B_e 1 = M_e 1 (the master shape functions sum to one),
//!   A B_e 1 = D_e 1: rows of D and B still agree (I1).
//! - lumped: D block replaced by D_e, B unchanged.
//!
//! Because both are linear in the per-face blocks, nothing is integrated twice.

use super::isoparametric::MAX_NODES;
use super::Multiplier;
use crate::catalogue::FaceKind;
use nalgebra::{SMatrix, SVector};

/// Smallest ratio of a Cholesky pivot to the largest diagonal entry of M_e
/// accepted for the dual basis; below it the covered part is a sliver and the
/// face falls back to lumping (counted in `FaceStats::dual_fallbacks`).
const DUAL_PIVOT_RTOL: f64 = 1e-12;

/// The weight α of the basis transformation of second-order slave faces
/// (Popp, Wohlmuth, Gee and Wall, SIAM J. Sci. Comput. 34 (2012)):
/// λ̃_v = λ_v + α Σ_{edges e at v} λ_e at corners, λ̃_e = (1 − 2α) λ_e at
/// mid-edge nodes, a Quad9 centre unchanged. The λ̃ still sum to one, are
/// continuous across faces, and have positive integrals (on a flat face Tri6
/// corners 2αA/3 instead of 0, Quad8 corners A/20 instead of −A/12).
///
/// α = 1/5 is Popp et al.'s weight, used on surfaces with second-order quads;
/// on a Quad8 it puts each corner function's centroid on its corner
/// (∫λ̃_c (x − x_c) = (5α − 1)/18 of the unit square). Surfaces whose
/// transformed faces are all Tri6 take [`TRI6_ALPHA`].
///
/// By default ([`super::BasisTransformation::Needed`]) only slave surfaces
/// with Tri6 or Quad8 faces are transformed (their Quad9 faces too, so that
/// the λ̃ stay continuous across shared edges). A surface of Quad9 (and
/// first-order) faces keeps the plain dual basis: its ∫ λ_p are positive
/// already (corners A/36 on a flat face), and the transformation there costs
/// accuracy in gluing: Hex27 bodies across a curved interface converge with
/// H1 rate 1.4–1.7 with it and 2.0 without (`seam-fem` test
/// `glue_convergence_second_order`). Contact transforms Quad9 too
/// ([`super::BasisTransformation::All`]).
pub const BASIS_ALPHA: f64 = 0.2;

/// The weight α of the basis transformation ([`BASIS_ALPHA`]) on slave
/// surfaces whose transformed faces are all Tri6: 1/8, the weight at which
/// the second moments of a corner function about its vertex vanish on every
/// flat triangle, ∫λ̃_c (x − x_c)(x − x_c)ᵀ = (8α − 1)/180 (v₁v₁ᵀ + v₂v₂ᵀ +
/// (v₁v₂ᵀ + v₂v₁ᵀ)/2)·2A (v₁, v₂ the edges from x_c). A corner coefficient of
/// the dual multiplier, a λ̃_c-weighted mean, then reads a smooth field at
/// its vertex with no h² term where the field is stationary (the peak of a
/// contact pressure). Measured against α = 1/5 (`seam-fem` tests
/// `contact_hertz_second_order`, `glue_convergence_second_order`): Hertz's
/// p₀ on Tet10 from −6.9 % to +0.6 % (n = 2) and −3.1 % to −2.2 % (n = 4);
/// dual-glued Tet10 bodies within 3.4 % of standard multipliers' H1 errors
/// instead of 22 %. Not everywhere better: with the curved indenter as a
/// Tri6 slave finer than its Tet10 master, Hertz's p₀ reads −7.3 % instead
/// of −4.5 % at n = 4 (the master's resolution, amplified most at the
/// corners; its pressure profile along the axes is better, 0.086 instead of
/// 0.114 of p₀).
pub const TRI6_ALPHA: f64 = 0.125;

/// The weight α of the basis transformation of the slave surface's
/// second-order faces, or `None` when they keep the plain Lagrange basis:
/// transformed when it has a Tri6 or a Quad8 face, or with
/// [`BasisTransformation::All`](super::BasisTransformation::All) any
/// second-order face; [`TRI6_ALPHA`] when those are all Tri6, else
/// [`BASIS_ALPHA`] (one α per surface keeps the λ̃ continuous across the
/// edges that triangles and quads share).
pub(super) fn transformation_weight(
    slave: &crate::mesh::SurfaceMesh,
    which: super::BasisTransformation,
) -> Option<f64> {
    use crate::mesh::Face;
    let transformed = |f: &Face| match which {
        super::BasisTransformation::Needed => !f.kind().info().positive_integrals,
        super::BasisTransformation::All => f.is_curved(),
    };
    if !slave.faces().iter().any(transformed) {
        return None;
    }
    let quads = slave.faces().iter().any(|f| f.is_curved() && !f.kind().is_triangle());
    Some(if quads { BASIS_ALPHA } else { TRI6_ALPHA })
}

/// Row `p` of the transformation λ̃ = Q_e λ of a face of `kind` with weight
/// `alpha` ([`transformation_weight`]), as (column, value) pairs; identity
/// for first-order faces and without a weight.
pub(super) fn transformation_row(
    kind: FaceKind,
    alpha: Option<f64>,
    p: usize,
) -> impl Iterator<Item = (usize, f64)> {
    let k = kind.n_corners();
    let second = kind.order() == 2;
    let entries: [(usize, f64); 3] = match (alpha.filter(|_| second), p) {
        (None, _) => [(p, 1.0), (0, 0.0), (0, 0.0)],
        // Corner p: its two edges are k + p (to p + 1) and k + (p + k − 1) % k.
        (Some(a), p) if p < k => [(p, 1.0), (k + p, a), (k + (p + k - 1) % k, a)],
        (Some(a), p) if p < 2 * k => [(p, 1.0 - 2.0 * a), (0, 0.0), (0, 0.0)],
        (Some(_), p) => [(p, 1.0), (0, 0.0), (0, 0.0)],
    };
    entries.into_iter().filter(|&(_, v)| v != 0.0)
}

/// Q_e as a matrix.
fn transformation<const N: usize>(kind: FaceKind, alpha: f64) -> SMatrix<f64, N, N> {
    let mut q = SMatrix::zeros();
    for p in 0..N {
        for (c, v) in transformation_row(kind, Some(alpha), p) {
            q[(p, c)] = v;
        }
    }
    q
}

/// What decides whether a slave node is covered: per local node, the
/// covered and the full integral of its (for second-order faces transformed,
/// positive) basis function over the face.
pub(super) struct FaceMeasures {
    /// (Q_e M_e 1)_p = ∫_{e,cov} λ̃_p.
    pub(super) covered: [f64; MAX_NODES],
    /// (Q_e ∫_e λ)_p = ∫_e λ̃_p.
    pub(super) full: [f64; MAX_NODES],
}

impl FaceMeasures {
    /// From a face's standard D block (stride [`MAX_NODES`]) and full integrals.
    pub(super) fn new(
        kind: FaceKind,
        alpha: Option<f64>,
        d: &[f64; MAX_NODES * MAX_NODES],
        full: &[f64; MAX_NODES],
    ) -> Self {
        let n = kind.n_nodes();
        let row_sums: [f64; MAX_NODES] = std::array::from_fn(|p| (0..n).map(|q| d[p * MAX_NODES + q]).sum());
        let apply = |v: &[f64; MAX_NODES]| -> [f64; MAX_NODES] {
            std::array::from_fn(|p| {
                if p < n {
                    transformation_row(kind, alpha, p).map(|(c, a)| a * v[c]).sum()
                } else {
                    0.0
                }
            })
        };
        FaceMeasures { covered: apply(&row_sums), full: apply(full) }
    }
}

/// Applies `multiplier` to a face's blocks in place: `d` is n_s × n_s row-major
/// with stride [`MAX_NODES`] (`d[p * MAX_NODES + q]`), `b` column-major with
/// n_s rows (`b[j * n_s + p]`). For dual multipliers on a second-order face
/// of a surface with a transformation weight `alpha`
/// ([`transformation_weight`]) the blocks are first written in the
/// transformed basis λ̃ = Q_e λ. Returns true when the dual basis had to fall
/// back to lumping.
pub(super) fn apply_multiplier(
    multiplier: Multiplier,
    kind: FaceKind,
    alpha: Option<f64>,
    d: &mut [f64; MAX_NODES * MAX_NODES],
    b: &mut [f64],
) -> bool {
    let n_s = kind.n_nodes();
    match multiplier {
        Multiplier::Standard => false,
        Multiplier::Lumped => {
            let row_sums: [f64; MAX_NODES] =
                std::array::from_fn(|p| (0..n_s).map(|q| d[p * MAX_NODES + q]).sum());
            *d = diagonal(&row_sums[..n_s]);
            false
        }
        Multiplier::Dual => match n_s {
            3 => dual::<3>(kind, None, d, b),
            4 => dual::<4>(kind, None, d, b),
            6 => dual::<6>(kind, alpha, d, b),
            7 => dual::<7>(kind, alpha, d, b),
            8 => dual::<8>(kind, alpha, d, b),
            _ => dual::<9>(kind, alpha, d, b),
        },
    }
}

/// The dual basis of a face with `N` nodes: with M the standard block on the
/// covered part (in the transformed basis of weight `alpha` if any),
/// A = diag(M 1) M⁻¹,
/// D_e = diag(M 1), B_e ← A B_e.
fn dual<const N: usize>(
    kind: FaceKind,
    alpha: Option<f64>,
    d: &mut [f64; MAX_NODES * MAX_NODES],
    b: &mut [f64],
) -> bool {
    let mut m = SMatrix::<f64, N, N>::from_fn(|p, q| d[p * MAX_NODES + q]);
    if let Some(alpha) = alpha {
        let q = transformation::<N>(kind, alpha);
        m = q * m * q.transpose();
        for column in b.chunks_exact_mut(N) {
            let v = q * SVector::<f64, N>::from_column_slice(column);
            column.copy_from_slice(v.as_slice());
        }
    }
    let row_sums: [f64; N] = std::array::from_fn(|p| m.row(p).sum());
    if row_sums.iter().all(|&s| s == 0.0) {
        return false; // an uncovered face contributes nothing
    }
    let fallback = match dual_coefficients(&m, &row_sums) {
        Some(a) => {
            for column in b.chunks_exact_mut(N) {
                let v = a * SVector::<f64, N>::from_column_slice(column);
                column.copy_from_slice(v.as_slice());
            }
            false
        }
        None => true,
    };
    *d = diagonal(&row_sums);
    fallback
}

/// A = diag(M 1) M⁻¹, or `None` when M is numerically singular.
fn dual_coefficients<const N: usize>(
    m: &SMatrix<f64, N, N>,
    row_sums: &[f64; N],
) -> Option<SMatrix<f64, N, N>> {
    let chol = m.cholesky()?;
    let max_diag = (0..N).map(|p| m[(p, p)]).fold(0.0, f64::max);
    let min_pivot = (0..N).map(|p| chol.l_dirty()[(p, p)].powi(2)).fold(f64::INFINITY, f64::min);
    if min_pivot.is_nan() || min_pivot <= DUAL_PIVOT_RTOL * max_diag {
        return None;
    }
    let inv = chol.inverse();
    Some(SMatrix::from_fn(|p, q| row_sums[p] * inv[(p, q)]))
}

fn diagonal(v: &[f64]) -> [f64; MAX_NODES * MAX_NODES] {
    let mut d = [0.0; MAX_NODES * MAX_NODES];
    for (p, &x) in v.iter().enumerate() {
        d[p * MAX_NODES + p] = x;
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: usize = MAX_NODES;

    /// The mass matrix of the unit right triangle (area ½): (1 + δ_pq)/24.
    fn tri_mass() -> [f64; N * N] {
        let mut d = [0.0; N * N];
        for p in 0..3 {
            for q in 0..3 {
                d[p * N + q] = if p == q { 2.0 } else { 1.0 } / 24.0;
            }
        }
        d
    }

    #[test]
    fn dual_basis_on_a_full_triangle_is_the_classical_one() {
        // Classical linear dual basis: ψ_p = 3λ_p − Σ_{q≠p} λ_q, i.e. A = 4I − 𝟙.
        let mut d = tri_mass();
        // One master column equal to M·e_0 (B block of an identical master face).
        let mut b = vec![2.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0];
        assert!(!apply_multiplier(Multiplier::Dual, FaceKind::Tri3, Some(BASIS_ALPHA), &mut d, &mut b));
        for p in 0..3 {
            assert!((d[p * N + p] - 1.0 / 6.0).abs() < 1e-16);
            let expected = if p == 0 { 1.0 / 6.0 } else { 0.0 };
            assert!((b[p] - expected).abs() < 1e-16, "b[{p}] = {}", b[p]);
        }
    }

    #[test]
    fn lumped_is_the_row_sum() {
        let mut d = tri_mass();
        let mut b = vec![1.0, 2.0, 3.0];
        apply_multiplier(Multiplier::Lumped, FaceKind::Tri3, Some(BASIS_ALPHA), &mut d, &mut b);
        assert_eq!(d[0], 4.0 / 24.0);
        assert_eq!(d[1], 0.0);
        assert_eq!(b, vec![1.0, 2.0, 3.0]);
    }

    #[test]
    fn singular_mass_falls_back_to_lumping() {
        let mut d = [0.0; N * N];
        for p in 0..3 {
            for q in 0..3 {
                d[p * N + q] = 1.0; // rank one
            }
        }
        let mut b = vec![1.0, 1.0, 1.0];
        assert!(apply_multiplier(Multiplier::Dual, FaceKind::Tri3, Some(BASIS_ALPHA), &mut d, &mut b));
        assert_eq!(d[0], 3.0);
        assert_eq!(d[1], 0.0);
    }

    #[test]
    fn transformed_basis_sums_to_one_and_has_positive_integrals() {
        // Integrals of the Lagrange functions on a unit-area flat face.
        let cases: [(FaceKind, f64, Vec<f64>); 4] = [
            (FaceKind::Tri6, BASIS_ALPHA, [[0.0; 3], [1.0 / 3.0; 3]].concat()),
            (FaceKind::Tri6, TRI6_ALPHA, [[0.0; 3], [1.0 / 3.0; 3]].concat()),
            (FaceKind::Quad8, BASIS_ALPHA, [[-1.0 / 12.0; 4], [1.0 / 3.0; 4]].concat()),
            (FaceKind::Quad9, BASIS_ALPHA, [&[1.0 / 36.0; 4][..], &[1.0 / 9.0; 4], &[4.0 / 9.0]].concat()),
        ];
        for (kind, alpha, integrals) in cases {
            let n = kind.n_nodes();
            for c in 0..n {
                let column: f64 = (0..n)
                    .flat_map(|p| transformation_row(kind, Some(alpha), p))
                    .filter(|e| e.0 == c)
                    .map(|e| e.1)
                    .sum();
                assert!((column - 1.0).abs() < 1e-15, "{kind:?}: λ_{c} appears with total weight {column}");
            }
            let mut full = [0.0; N];
            full[..n].copy_from_slice(&integrals);
            let measures = FaceMeasures::new(kind, Some(alpha), &[0.0; N * N], &full);
            assert!(measures.full[..n].iter().all(|&v| v > 0.04), "{kind:?}: {:?}", &measures.full[..n]);
            assert!((measures.full.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        }
    }

    /// [`TRI6_ALPHA`]: on a scalene flat triangle the second moments of the
    /// transformed corner functions about their vertices vanish (and do not
    /// at [`BASIS_ALPHA`]).
    #[test]
    fn tri6_corner_functions_have_no_second_moments() {
        let x = [[0.3, -0.2], [2.1, 0.4], [0.9, 1.7]];
        let rule = crate::quadrature::triangle_rule(6).unwrap();
        let area2 = (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[2][0] - x[0][0]) * (x[1][1] - x[0][1]);
        let moments = |alpha: f64, c: usize| {
            let mut m = [0.0; 4]; // ∫λ̃_c, and the moments xx, xy, yy about x_c
            for (pt, &w) in rule.points.iter().zip(rule.weights) {
                let phi: [f64; 6] = crate::curved::shape_values(*pt);
                let l = [1.0 - pt[0] - pt[1], pt[0], pt[1]];
                let p = [0, 1].map(|i| (0..3).map(|v| l[v] * x[v][i]).sum::<f64>() - x[c][i]);
                let value: f64 =
                    transformation_row(FaceKind::Tri6, Some(alpha), c).map(|(q, a)| a * phi[q]).sum();
                let wv = 0.5 * w * area2 * value;
                for (k, f) in [1.0, p[0] * p[0], p[0] * p[1], p[1] * p[1]].into_iter().enumerate() {
                    m[k] += wv * f;
                }
            }
            m
        };
        for c in 0..3 {
            let [m0, xx, xy, yy] = moments(TRI6_ALPHA, c);
            assert!((m0 - area2 / 24.0).abs() < 1e-14, "∫λ̃_{c} = {m0}");
            for v in [xx, xy, yy] {
                assert!(v.abs() < 1e-14, "corner {c}: second moment {v}");
            }
            let [_, xx, _, yy] = moments(BASIS_ALPHA, c);
            assert!(xx + yy > 1e-3, "corner {c} at α = 1/5: {}", xx + yy);
        }
    }

    /// One weight per surface: 1/8 on Tri6 surfaces, 1/5 as soon as a
    /// second-order quad shares the surface (continuity across their edges).
    #[test]
    fn one_transformation_weight_per_surface() {
        use super::super::BasisTransformation::{All, Needed};
        use crate::mesh::{Face, SurfaceMesh};
        // A unit square as a Quad9 (x ≥ 0) and two Tri6 beside it (x ≤ 0).
        let grid = |i: usize, j: usize| [0.5 * i as f64 - 1.0, 0.5 * j as f64, 0.0];
        let points: Vec<_> = (0..25).map(|k| grid(k % 5, k / 5)).collect();
        let at = |i: usize, j: usize| 5 * j + i;
        let quad = Face::Quad9([
            at(2, 0),
            at(4, 0),
            at(4, 2),
            at(2, 2),
            at(3, 0),
            at(4, 1),
            at(3, 2),
            at(2, 1),
            at(3, 1),
        ]);
        let tris = [
            Face::Tri6([at(0, 0), at(2, 0), at(2, 2), at(1, 0), at(2, 1), at(1, 1)]),
            Face::Tri6([at(0, 0), at(2, 2), at(0, 2), at(1, 1), at(1, 2), at(0, 1)]),
        ];
        let surface = |faces: Vec<Face>| SurfaceMesh::new(points.clone(), faces).unwrap();
        assert_eq!(transformation_weight(&surface(tris.to_vec()), Needed), Some(TRI6_ALPHA));
        assert_eq!(transformation_weight(&surface([&tris[..], &[quad]].concat()), Needed), Some(BASIS_ALPHA));
        assert_eq!(transformation_weight(&surface(vec![quad]), Needed), None);
        assert_eq!(transformation_weight(&surface(vec![quad]), All), Some(BASIS_ALPHA));
        let linear = Face::Tri3([at(0, 0), at(2, 0), at(2, 2)]);
        assert_eq!(transformation_weight(&surface(vec![linear]), All), None);
    }
}
