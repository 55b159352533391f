//! Dirichlet conditions by elimination and the sparse Cholesky solve.
//!
//! With the dofs split into free F and prescribed D (values ū_D),
//!
//! ```text
//! K_FF u_F = f_F − K_FD ū_D,      u_D = ū_D,
//! ```
//!
//! K_FF is symmetric positive definite when the prescribed dofs remove every
//! rigid-body motion of every connected body; it is factored as LLᵀ by faer's
//! sparse Cholesky (with its fill-reducing ordering).
//!
//! # Singularity
//! K_FF is singular (or numerically so) when a body can move without deforming.
//! In floating point the factorisation may then still succeed with a tiny pivot,
//! so the solve also checks itself: with the same factors it solves K_FF x = K_FF z
//! for a fixed vector z and requires ‖x − z‖_∞ ≤ [`SINGULAR_PROBE_RTOL`] ‖z‖_∞.
//! Along a null direction the error is O(‖z‖), elsewhere O(κ ε), so this
//! detects singular systems and rejects only those with a condition number
//! beyond ~10¹⁰.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Mat, Side};
use seam::CsrMatrix;
use std::collections::BTreeMap;

/// Largest relative error of the self-check solve (module doc) before the system
/// counts as singular.
pub const SINGULAR_PROBE_RTOL: f64 = 1e-6;

/// Why a solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// K is singular on the free dofs.
    #[error("the problem is singular: the body can move without deforming; add Dirichlet conditions")]
    Singular,
    /// K is not square, or f does not have one entry per row of K.
    #[error("dimension mismatch: K is {nrows}×{ncols} and f has {f_len} entries")]
    Dimension {
        /// Rows of K.
        nrows: usize,
        /// Columns of K.
        ncols: usize,
        /// Entries of f.
        f_len: usize,
    },
    /// A Dirichlet condition refers to a dof that does not exist.
    #[error("Dirichlet condition on dof {dof} (point {}, component {}), but there are only {n_dofs} dofs", dof / 3, dof % 3)]
    DofOutOfRange {
        /// The dof.
        dof: usize,
        /// The number of dofs.
        n_dofs: usize,
    },
    /// A prescribed value is NaN or infinite.
    #[error("Dirichlet value of dof {dof} (point {}, component {}) is not finite", dof / 3, dof % 3)]
    NonFiniteValue {
        /// The dof.
        dof: usize,
    },
}

/// Prescribed displacements: a value per fixed dof (`dof = 3·point + component`).
/// Fixing a dof again replaces its value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Dirichlet {
    values: BTreeMap<usize, f64>,
}

impl Dirichlet {
    /// No conditions.
    pub fn new() -> Dirichlet {
        Dirichlet::default()
    }

    /// Prescribes the components of `point` given as `Some(value)`:
    /// `fix(p, [Some(0.0), None, None])` fixes u_x only.
    pub fn fix(&mut self, point: usize, values: [Option<f64>; 3]) -> &mut Self {
        for (c, v) in values.iter().enumerate() {
            if let Some(v) = *v {
                self.values.insert(3 * point + c, v);
            }
        }
        self
    }

    /// Prescribes the same components and values on every point of `points`.
    pub fn fix_all(
        &mut self,
        points: impl IntoIterator<Item = usize>,
        values: [Option<f64>; 3],
    ) -> &mut Self {
        for p in points {
            self.fix(p, values);
        }
        self
    }

    /// Clamps the points: u = 0 in all three components.
    pub fn clamp(&mut self, points: impl IntoIterator<Item = usize>) -> &mut Self {
        self.fix_all(points, [Some(0.0); 3])
    }

    /// Prescribes one dof.
    pub fn fix_dof(&mut self, dof: usize, value: f64) -> &mut Self {
        self.values.insert(dof, value);
        self
    }

    /// The prescribed value of `dof`, if any.
    pub fn value(&self, dof: usize) -> Option<f64> {
        self.values.get(&dof).copied()
    }

    /// (dof, value) in increasing dof order.
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.values.iter().map(|(&d, &v)| (d, v))
    }

    /// Number of prescribed dofs.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// True when nothing is prescribed.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}

/// Solves K u = f with the Dirichlet conditions by elimination (module doc);
/// returns the full vector u (prescribed values included).
///
/// K must be symmetric (not checked; the factorisation reads the entries K_ij,
/// j ≥ i, of the free rows). Dofs whose
/// row of K has no stored entry (points that no cell uses) are not unknowns:
/// they get u = 0, or their prescribed value.
///
/// # Errors
/// [`SolveError::Singular`] when K is (numerically) singular on the free dofs;
/// [`SolveError::Dimension`], [`SolveError::DofOutOfRange`],
/// [`SolveError::NonFiniteValue`] for inconsistent input.
pub fn solve(k: &CsrMatrix, f: &[f64], dirichlet: &Dirichlet) -> Result<Vec<f64>, SolveError> {
    let n = k.nrows;
    if k.ncols != n || f.len() != n {
        return Err(SolveError::Dimension { nrows: k.nrows, ncols: k.ncols, f_len: f.len() });
    }
    let mut u = vec![0.0; n];
    let mut fixed = vec![false; n];
    for (dof, v) in dirichlet.iter() {
        if dof >= n {
            return Err(SolveError::DofOutOfRange { dof, n_dofs: n });
        }
        if !v.is_finite() {
            return Err(SolveError::NonFiniteValue { dof });
        }
        u[dof] = v;
        fixed[dof] = true;
    }
    // Reduced numbering of the free dofs.
    let mut local = vec![usize::MAX; n];
    let mut free = Vec::new();
    for i in 0..n {
        if !fixed[i] && k.indptr[i + 1] > k.indptr[i] {
            local[i] = free.len();
            free.push(i);
        }
    }
    let m = free.len();
    if m == 0 {
        return Ok(u);
    }
    // Lower triangle of K_FF in CSC (column r = row free[r] of the symmetric K,
    // entries at or below the diagonal), and r_F = f_F − K_FD ū_D.
    let mut col_ptr = Vec::with_capacity(m + 1);
    let mut row_idx = Vec::new();
    let mut vals = Vec::new();
    let mut rhs = Mat::<f64>::zeros(m, 2);
    col_ptr.push(0usize);
    for (r, &i) in free.iter().enumerate() {
        let (cols, values) = k.row(i);
        let mut b = f[i];
        for (&j, &v) in cols.iter().zip(values) {
            if fixed[j] {
                b -= v * u[j];
            } else if local[j] != usize::MAX && local[j] >= r {
                row_idx.push(local[j]);
                vals.push(v);
            }
        }
        rhs[(r, 0)] = b;
        col_ptr.push(row_idx.len());
    }
    // The probe z and K_FF z (second column), from the full rows of K.
    let z: Vec<f64> = (0..m).map(probe).collect();
    for (r, &i) in free.iter().enumerate() {
        let (cols, values) = k.row(i);
        rhs[(r, 1)] = cols
            .iter()
            .zip(values)
            .filter(|(&j, _)| local[j] != usize::MAX)
            .map(|(&j, &v)| v * z[local[j]])
            .sum();
    }
    let symbolic = SymbolicSparseColMatRef::new_checked(m, m, &col_ptr, None, &row_idx);
    let kff = SparseColMatRef::new(symbolic, &vals);
    let llt = kff.sp_cholesky(Side::Lower).map_err(|_| SolveError::Singular)?;
    llt.solve_in_place(rhs.as_mut());
    let (mut err, mut size) = (0.0f64, 0.0f64);
    for r in 0..m {
        err = err.max((rhs[(r, 1)] - z[r]).abs());
        size = size.max(z[r].abs());
    }
    // NaN (a failed factorisation) counts as singular too.
    if err.is_nan() || err > SINGULAR_PROBE_RTOL * size {
        return Err(SolveError::Singular);
    }
    for (r, &i) in free.iter().enumerate() {
        u[i] = rhs[(r, 0)];
    }
    if u.iter().any(|v| !v.is_finite()) {
        return Err(SolveError::Singular);
    }
    Ok(u)
}

/// A fixed pseudo-random entry in \[1, 2) (SplitMix64 of the index).
fn probe(r: usize) -> f64 {
    let mut x = (r as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^= x >> 31;
    1.0 + (x >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 1D Laplacian chain of `n` nodes, springs of stiffness 1.
    fn chain(n: usize) -> CsrMatrix {
        let rows: Vec<(Vec<usize>, Vec<f64>)> = (0..n)
            .map(|i| {
                let mut c = Vec::new();
                let mut v = Vec::new();
                if i > 0 {
                    c.push(i - 1);
                    v.push(-1.0);
                }
                c.push(i);
                v.push(if i == 0 || i == n - 1 { 1.0 } else { 2.0 });
                if i + 1 < n {
                    c.push(i + 1);
                    v.push(-1.0);
                }
                (c, v)
            })
            .collect();
        CsrMatrix::from_rows(n, rows.iter().map(|(c, v)| (c.as_slice(), v.as_slice())))
    }

    #[test]
    fn chain_with_both_ends_prescribed_is_linear() {
        let k = chain(6);
        let mut d = Dirichlet::new();
        d.fix_dof(0, 1.0).fix_dof(5, 6.0);
        let u = solve(&k, &[0.0; 6], &d).unwrap();
        for (i, v) in u.iter().enumerate() {
            assert!((v - (1.0 + i as f64)).abs() < 1e-13, "{u:?}");
        }
    }

    #[test]
    fn floating_chain_is_singular() {
        let k = chain(6);
        assert_eq!(solve(&k, &[0.0; 6], &Dirichlet::new()), Err(SolveError::Singular));
        let mut d = Dirichlet::new();
        d.fix_dof(6, 0.0);
        assert_eq!(solve(&k, &[0.0; 6], &d), Err(SolveError::DofOutOfRange { dof: 6, n_dofs: 6 }));
        assert!(matches!(solve(&k, &[0.0; 5], &d), Err(SolveError::Dimension { .. })));
    }

    #[test]
    fn dirichlet_builder() {
        let mut d = Dirichlet::new();
        d.fix(2, [Some(1.0), None, Some(3.0)]).clamp([0]);
        d.fix(2, [Some(5.0), None, None]);
        let all: Vec<_> = d.iter().collect();
        assert_eq!(all, vec![(0, 0.0), (1, 0.0), (2, 0.0), (6, 5.0), (8, 3.0)]);
        assert_eq!(d.value(7), None);
        assert_eq!(d.len(), 5);
    }
}
