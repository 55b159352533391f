//! The transfer operator T = D⁻¹B on the covered slave nodes, and its
//! transpose for conservative (load) transfer.
//!
//! - Diagonal D (dual, lumped): T is built explicitly, row p = B_p / D_pp.
//! - Standard D (SPD on the covered nodes C): T v = D_CC⁻¹ (B v)_C, applied by a
//!   sparse Cholesky factorisation of D_CC (faer); T is dense in general and is
//!   never formed.
//!
//! - Dual multipliers on second-order slave faces: D is diagonal in the
//!   transformed basis λ̃ = Q λ, and the nodal transfer is T = Qᵀ D⁻¹ B.
//!
//! Uncovered slave nodes get zero rows: T v is 0 there, never a division by zero.
//! Conservative transfer f_m = Tᵀ f_s keeps the total, 1ᵀ f_m = 1ᵀ f_s (I6),
//! because T 1 = 1 on the covered nodes (I1) — for loads carried by covered
//! nodes.

use super::{Mortar, MortarError};
use crate::sparse::CsrMatrix;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::Llt;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};

/// The transfer operator of a [`Mortar`], ready to apply.
pub struct Transfer {
    kind: Kind,
    nrows: usize,
    ncols: usize,
}

enum Kind {
    Explicit(CsrMatrix),
    Factored {
        b: CsrMatrix,
        /// Covered slave nodes, in increasing order (the rows of D_CC).
        covered: Vec<usize>,
        llt: Llt<usize, f64>,
    },
}

impl Mortar {
    /// The transfer operator T = D⁻¹B restricted to covered slave nodes.
    ///
    /// # Errors
    /// [`MortarError::Factorization`] if D_CC is not numerically positive definite.
    pub fn transfer(&self) -> Result<Transfer, MortarError> {
        let (nrows, ncols) = (self.b.nrows, self.b.ncols);
        if self.d.is_diagonal() {
            let diag = self.d.diagonal();
            // With a basis transformation every row of D⁻¹B with D_pp > 0 is
            // needed; T = Qᵀ (D⁻¹B) is then cut to the covered rows.
            let keep = |p: usize| diag[p] > 0.0 && (self.covered[p] || self.basis.is_some());
            let rows: Vec<(&[usize], Vec<f64>)> = (0..nrows)
                .map(|p| match self.b.row(p) {
                    (cols, vals) if keep(p) => (cols, vals.iter().map(|v| v / diag[p]).collect()),
                    _ => (&[][..], Vec::new()),
                })
                .collect();
            let mut t = CsrMatrix::from_rows(ncols, rows.iter().map(|(c, v)| (*c, v.as_slice())));
            if let Some(q) = &self.basis {
                t = transpose_times(q, &t, &self.covered);
            }
            return Ok(Transfer { kind: Kind::Explicit(t), nrows, ncols });
        }
        let covered: Vec<usize> = (0..nrows).filter(|&p| self.covered[p]).collect();
        let mut local = vec![usize::MAX; nrows];
        for (k, &p) in covered.iter().enumerate() {
            local[p] = k;
        }
        let mut triplets = Vec::with_capacity(self.d.nnz());
        for &p in &covered {
            let (cols, vals) = self.d.row(p);
            for (&q, &v) in cols.iter().zip(vals) {
                if local[q] != usize::MAX && local[q] >= local[p] {
                    triplets.push(Triplet::new(local[q], local[p], v));
                }
            }
        }
        let n = covered.len();
        let dcc = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets)
            .map_err(|e| MortarError::Factorization(format!("{e:?}")))?;
        let llt = dcc.sp_cholesky(Side::Lower).map_err(|e| MortarError::Factorization(format!("{e:?}")))?;
        Ok(Transfer { kind: Kind::Factored { b: self.b.clone(), covered, llt }, nrows, ncols })
    }
}

impl Transfer {
    /// The explicit T when D is diagonal (dual and lumped multipliers).
    pub fn matrix(&self) -> Option<&CsrMatrix> {
        match &self.kind {
            Kind::Explicit(t) => Some(t),
            Kind::Factored { .. } => None,
        }
    }

    /// Consistent transfer u_s = T u_m of `k`-component nodal values (row-major,
    /// master points × k); uncovered slave nodes get 0.
    ///
    /// # Panics
    /// If `master_values.len() != n_master_points * k`.
    pub fn apply(&self, master_values: &[f64], k: usize) -> Vec<f64> {
        match &self.kind {
            Kind::Explicit(t) => t.mul_vec(master_values, k),
            Kind::Factored { b, covered, llt } => {
                solve_covered(llt, covered, &b.mul_vec(master_values, k), k)
            }
        }
    }

    /// Conservative transfer f_m = Tᵀ f_s of `k`-component nodal loads (slave
    /// points × k); loads on uncovered slave nodes are not transferred.
    ///
    /// # Panics
    /// If `slave_loads.len() != n_slave_points * k`.
    pub fn apply_transpose(&self, slave_loads: &[f64], k: usize) -> Vec<f64> {
        match &self.kind {
            Kind::Explicit(t) => t.transpose_mul_vec(slave_loads, k),
            Kind::Factored { b, covered, llt } => {
                assert_eq!(slave_loads.len(), self.nrows * k, "loads must have n_slave × k entries");
                // Tᵀ f = Bᵀ D_CC⁻¹ f_C (D symmetric).
                b.transpose_mul_vec(&solve_covered(llt, covered, slave_loads, k), k)
            }
        }
    }

    /// Number of slave points (rows of T).
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of master points (columns of T).
    pub fn ncols(&self) -> usize {
        self.ncols
    }
}

/// The rows `keep` of Qᵀ A (Q square sparse, A sparse), the others empty.
fn transpose_times(q: &CsrMatrix, a: &CsrMatrix, keep: &[bool]) -> CsrMatrix {
    let qt = q.transpose();
    let mut dense = vec![0.0; a.ncols];
    let mut touched: Vec<usize> = Vec::new();
    let rows: Vec<(Vec<usize>, Vec<f64>)> = (0..qt.nrows)
        .map(|r| {
            if !keep[r] {
                return (Vec::new(), Vec::new());
            }
            let (ps, ws) = qt.row(r);
            for (&p, &w) in ps.iter().zip(ws) {
                let (cols, vals) = a.row(p);
                for (&c, &v) in cols.iter().zip(vals) {
                    if dense[c] == 0.0 && !touched.contains(&c) {
                        touched.push(c);
                    }
                    dense[c] += w * v;
                }
            }
            touched.sort_unstable();
            let vals = touched.iter().map(|&c| std::mem::take(&mut dense[c])).collect();
            (std::mem::take(&mut touched), vals)
        })
        .collect();
    CsrMatrix::from_rows(a.ncols, rows.iter().map(|(c, v)| (c.as_slice(), v.as_slice())))
}

/// x with x_C = D_CC⁻¹ r_C on the covered rows C and 0 elsewhere (k components).
fn solve_covered(llt: &Llt<usize, f64>, covered: &[usize], r: &[f64], k: usize) -> Vec<f64> {
    let mut rhs = Mat::from_fn(covered.len(), k, |i, l| r[covered[i] * k + l]);
    llt.solve_in_place(rhs.as_mut());
    let mut x = vec![0.0; r.len()];
    for (i, &p) in covered.iter().enumerate() {
        for l in 0..k {
            x[p * k + l] = rhs[(i, l)];
        }
    }
    x
}
