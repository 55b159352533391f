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

use super::Multiplier;
use nalgebra::Matrix4;

/// Smallest ratio of a Cholesky pivot to the largest diagonal entry of M_e
/// accepted for the dual basis; below it the covered part is a sliver and the
/// face falls back to lumping (counted in `FaceStats::dual_fallbacks`).
const DUAL_PIVOT_RTOL: f64 = 1e-12;

/// Applies `multiplier` to a face's blocks in place: `d` is n_s × n_s row-major
/// (`d[p * 4 + q]`), `b` column-major with 4 rows (`b[j * 4 + p]`). Returns true
/// when the dual basis had to fall back to lumping.
pub(super) fn apply_multiplier(multiplier: Multiplier, n_s: usize, d: &mut [f64; 16], b: &mut [f64]) -> bool {
    let row_sums: [f64; 4] = std::array::from_fn(|p| (0..n_s).map(|q| d[p * 4 + q]).sum());
    match multiplier {
        Multiplier::Standard => false,
        Multiplier::Lumped => {
            *d = diagonal(row_sums);
            false
        }
        Multiplier::Dual => {
            if row_sums.iter().all(|&s| s == 0.0) {
                return false; // an uncovered face contributes nothing
            }
            let fallback = match dual_coefficients(n_s, d, row_sums) {
                Some(a) => {
                    for column in b.chunks_exact_mut(4) {
                        let old = [column[0], column[1], column[2], column[3]];
                        for p in 0..n_s {
                            column[p] = (0..n_s).map(|r| a[(p, r)] * old[r]).sum();
                        }
                    }
                    false
                }
                None => true,
            };
            *d = diagonal(row_sums);
            fallback
        }
    }
}

/// A = D_e M_e⁻¹ (the n_s × n_s leading block of the result), or `None` when
/// M_e is numerically singular.
fn dual_coefficients(n_s: usize, d: &[f64; 16], row_sums: [f64; 4]) -> Option<Matrix4<f64>> {
    // Pad a triangle's 3×3 block with a unit (3,3) entry: block-diagonal, SPD.
    let m = Matrix4::from_fn(|p, q| {
        if p < n_s && q < n_s {
            d[p * 4 + q]
        } else if p == q {
            1.0
        } else {
            0.0
        }
    });
    let chol = m.cholesky()?;
    let max_diag = (0..n_s).map(|p| m[(p, p)]).fold(0.0, f64::max);
    let min_pivot = (0..n_s).map(|p| chol.l_dirty()[(p, p)].powi(2)).fold(f64::INFINITY, f64::min);
    if min_pivot.is_nan() || min_pivot <= DUAL_PIVOT_RTOL * max_diag {
        return None;
    }
    let inv = chol.inverse();
    Some(Matrix4::from_fn(|p, q| if p < n_s { row_sums[p] * inv[(p, q)] } else { 0.0 }))
}

fn diagonal(v: [f64; 4]) -> [f64; 16] {
    let mut d = [0.0; 16];
    for p in 0..4 {
        d[p * 4 + p] = v[p];
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mass matrix of the unit right triangle (area ½): (1 + δ_pq)/24.
    fn tri_mass() -> [f64; 16] {
        let mut d = [0.0; 16];
        for p in 0..3 {
            for q in 0..3 {
                d[p * 4 + q] = if p == q { 2.0 } else { 1.0 } / 24.0;
            }
        }
        d
    }

    #[test]
    fn dual_basis_on_a_full_triangle_is_the_classical_one() {
        // Classical linear dual basis: ψ_p = 3λ_p − Σ_{q≠p} λ_q, i.e. A = 4I − 𝟙.
        let mut d = tri_mass();
        // One master column equal to M·e_0 (B block of an identical master face).
        let mut b = vec![2.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0, 0.0];
        assert!(!apply_multiplier(Multiplier::Dual, 3, &mut d, &mut b));
        for p in 0..3 {
            assert!((d[p * 4 + p] - 1.0 / 6.0).abs() < 1e-16);
            let expected = if p == 0 { 1.0 / 6.0 } else { 0.0 };
            assert!((b[p] - expected).abs() < 1e-16, "b[{p}] = {}", b[p]);
        }
    }

    #[test]
    fn lumped_is_the_row_sum() {
        let mut d = tri_mass();
        let mut b = vec![1.0, 2.0, 3.0, 0.0];
        apply_multiplier(Multiplier::Lumped, 3, &mut d, &mut b);
        assert_eq!(d[0], 4.0 / 24.0);
        assert_eq!(d[1], 0.0);
        assert_eq!(b, vec![1.0, 2.0, 3.0, 0.0]);
    }

    #[test]
    fn singular_mass_falls_back_to_lumping() {
        let mut d = [0.0; 16];
        for p in 0..3 {
            for q in 0..3 {
                d[p * 4 + q] = 1.0; // rank one
            }
        }
        let mut b = vec![1.0, 1.0, 1.0, 0.0];
        assert!(apply_multiplier(Multiplier::Dual, 3, &mut d, &mut b));
        assert_eq!(d[0], 3.0);
        assert_eq!(d[1], 0.0);
    }
}
