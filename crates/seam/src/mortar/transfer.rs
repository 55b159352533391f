//! The transfer operator T = D⁻¹B on the covered slave nodes, and its
//! transpose for conservative (load) transfer.
//!
//! - Diagonal D (dual, lumped): T is built explicitly, row p = B_p / D_pp.
//! - Standard D (SPD on the covered nodes C): T v = D_CC⁻¹ (B v)_C; T is dense
//!   in general and is never formed. D_CC is a mass matrix, whose Jacobi-scaled
//!   condition number is bounded independently of h (≤ 4 on first-order
//!   faces), so conjugate gradients with diag(D_CC) reach a relative residual
//!   of [`CG_RTOL`] in some 30 iterations at any size — several times faster
//!   than a sparse Cholesky factorisation (faer), which is kept for the
//!   surfaces where they are not: a solve that takes over [`CG_MAX`] steps
//!   (slivers of coverage can make D_CC ill-conditioned) factorises D_CC, and
//!   later solves use the factors; so does a transfer applied so often that
//!   factorising is cheaper ([`CG_SWEEPS_BEFORE_FACTORING`]). The two ways
//!   agree to ~1e-14; which one a solve takes depends on the solves before it,
//!   never on the number of threads.
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
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// Relative residual ‖D_CC x − r‖₂ / ‖r‖₂ at which conjugate gradients stop:
/// the solution is then as exact as a Cholesky solve's (within ~1e-14).
pub const CG_RTOL: f64 = 1e-15;

/// Iterations after which a solve gives up on conjugate gradients and
/// factorises D_CC (about 30 suffice on a mass matrix, whatever its size).
pub const CG_MAX: usize = 200;

/// Conjugate-gradient steps (sweeps over D_CC) after which a transfer
/// applied again and again factorises D_CC instead: about what a
/// factorisation costs (0.65 s against 4 ms per step at 200k points), so
/// that repeated transfers cost at most about twice the cheaper way.
pub const CG_SWEEPS_BEFORE_FACTORING: usize = 150;

/// The transfer operator of a [`Mortar`], ready to apply.
pub struct Transfer {
    kind: Kind,
    nrows: usize,
    ncols: usize,
}

enum Kind {
    Explicit(CsrMatrix),
    /// T v = D_CC⁻¹ (B v)_C.
    Solved {
        b: CsrMatrix,
        d: CoveredMass,
    },
}

/// D_CC with its solver: conjugate gradients, or a Cholesky factorisation
/// made when they are too slow (at once, or at the first slow solve).
struct CoveredMass {
    /// Covered slave nodes, in increasing order (the rows of D_CC).
    covered: Vec<usize>,
    /// D_CC in local numbering.
    dcc: CsrMatrix,
    /// 1 / its diagonal (positive).
    inv_diag: Vec<f64>,
    llt: OnceLock<Result<Llt<usize, f64>, MortarError>>,
    /// Conjugate-gradient steps taken so far (by all solves).
    sweeps: AtomicUsize,
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
        let d = CoveredMass::new(&self.d, covered)?;
        Ok(Transfer { kind: Kind::Solved { b: self.b.clone(), d }, nrows, ncols })
    }
}

impl CoveredMass {
    /// D_CC of `d` on the rows and columns `covered` (increasing).
    fn new(d: &CsrMatrix, covered: Vec<usize>) -> Result<CoveredMass, MortarError> {
        let mut local = vec![usize::MAX; d.nrows];
        for (k, &p) in covered.iter().enumerate() {
            local[p] = k;
        }
        let mut dcc = CsrMatrix {
            nrows: covered.len(),
            ncols: covered.len(),
            indptr: Vec::with_capacity(covered.len() + 1),
            indices: Vec::with_capacity(d.nnz()),
            values: Vec::with_capacity(d.nnz()),
        };
        dcc.indptr.push(0);
        let mut diag = Vec::with_capacity(covered.len());
        for (k, &p) in covered.iter().enumerate() {
            let (cols, vals) = d.row(p);
            let mut dkk = 0.0;
            for (&q, &v) in cols.iter().zip(vals) {
                if local[q] != usize::MAX {
                    dcc.indices.push(local[q]);
                    dcc.values.push(v);
                    if local[q] == k {
                        dkk = v;
                    }
                }
            }
            dcc.indptr.push(dcc.indices.len());
            diag.push(dkk);
        }
        if let Some(k) = diag.iter().position(|&v| !(v > 0.0 && v.is_finite())) {
            let e = format!("D has the diagonal entry {} at covered slave point {}", diag[k], covered[k]);
            return Err(MortarError::Factorization(e));
        }
        let inv_diag = diag.iter().map(|d| 1.0 / d).collect();
        Ok(CoveredMass { covered, dcc, inv_diag, llt: OnceLock::new(), sweeps: AtomicUsize::new(0) })
    }

    /// The Cholesky factorisation of D_CC, made once.
    fn factorised(&self) -> Result<&Llt<usize, f64>, MortarError> {
        let llt = self.llt.get_or_init(|| {
            let triplets: Vec<Triplet<usize, usize, f64>> = (0..self.dcc.nrows)
                .flat_map(|p| {
                    let (cols, vals) = self.dcc.row(p);
                    cols.iter()
                        .zip(vals)
                        .filter(move |(&q, _)| q >= p)
                        .map(move |(&q, &v)| Triplet::new(q, p, v))
                })
                .collect();
            let n = self.dcc.nrows;
            let dcc = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets)
                .map_err(|e| MortarError::Factorization(format!("{e:?}")))?;
            dcc.sp_cholesky(Side::Lower).map_err(|e| MortarError::Factorization(format!("{e:?}")))
        });
        llt.as_ref().map_err(Clone::clone)
    }

    /// x = D_CC⁻¹ r for `k` interleaved right-hand sides by conjugate
    /// gradients preconditioned with diag(D_CC), from the lumped guess, one
    /// sweep over D_CC per step for all of them; and whether every one reached
    /// ‖D_CC x − r‖ ≤ [`CG_RTOL`] ‖r‖ within `max_iterations` (else the last
    /// iterates). Deterministic: the products are row by row, the sums in a
    /// fixed order.
    fn cg(&self, r: &[f64], k: usize, max_iterations: usize) -> (Vec<f64>, bool) {
        if k <= 4 {
            return self.cg_group(r, k, max_iterations);
        }
        // In groups of at most four columns (a column's iterates do not
        // depend on the others of its group).
        let n = self.inv_diag.len();
        let (mut x, mut converged) = (vec![0.0; r.len()], true);
        for first in (0..k).step_by(4) {
            let g = (k - first).min(4);
            let rg: Vec<f64> = (0..n).flat_map(|i| &r[i * k + first..i * k + first + g]).copied().collect();
            let (xg, ok) = self.cg_group(&rg, g, max_iterations);
            converged &= ok;
            for i in 0..n {
                x[i * k + first..i * k + first + g].copy_from_slice(&xg[i * g..(i + 1) * g]);
            }
        }
        (x, converged)
    }

    fn cg_group(&self, r: &[f64], k: usize, max_iterations: usize) -> (Vec<f64>, bool) {
        match k {
            1 => self.cg_k::<1>(r, max_iterations),
            2 => self.cg_k::<2>(r, max_iterations),
            3 => self.cg_k::<3>(r, max_iterations),
            _ => self.cg_k::<4>(r, max_iterations),
        }
    }

    /// [`CoveredMass::cg`] for `K` columns.
    fn cg_k<const K: usize>(&self, r: &[f64], max_iterations: usize) -> (Vec<f64>, bool) {
        let (n, inv) = (self.inv_diag.len(), &self.inv_diag);
        // Σ_i v_il w_il per column l, in row order.
        let dots = |v: &[f64], w: &[f64]| {
            let mut s = [0.0; K];
            for (vi, wi) in v.chunks_exact(K).zip(w.chunks_exact(K)) {
                for l in 0..K {
                    s[l] += vi[l] * wi[l];
                }
            }
            s
        };
        let target = dots(r, r).map(|rr| CG_RTOL * rr.sqrt());
        let mut x: Vec<f64> = (0..n * K).map(|i| r[i] * inv[i / K]).collect();
        let mut ap = vec![0.0; n * K];
        self.multiply_k::<K>(&x, &mut ap);
        let mut res: Vec<f64> = r.iter().zip(&ap).map(|(r, a)| r - a).collect();
        let mut z: Vec<f64> = (0..n * K).map(|i| res[i] * inv[i / K]).collect();
        let mut p = z.clone();
        let mut rz = dots(&res, &z);
        let rr0 = dots(&res, &res);
        let mut active: [bool; K] = std::array::from_fn(|l| rr0[l].sqrt() > target[l]);
        let (mut alpha, mut beta) = ([0.0; K], [0.0; K]);
        for _ in 0..max_iterations {
            if !active.contains(&true) {
                return (x, true);
            }
            self.sweeps.fetch_add(1, Ordering::Relaxed);
            self.multiply_k::<K>(&p, &mut ap);
            let pap = dots(&p, &ap);
            for l in 0..K {
                if active[l] && pap[l].partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                    return (x, false);
                }
                alpha[l] = if active[l] { rz[l] / pap[l] } else { 0.0 };
            }
            let (mut rz_next, mut rr) = ([0.0; K], [0.0; K]);
            let rows = x.chunks_exact_mut(K).zip(res.chunks_exact_mut(K)).zip(z.chunks_exact_mut(K));
            for (((xi, ri), zi), (pi, (api, &inv_i))) in
                rows.zip(p.chunks_exact(K).zip(ap.chunks_exact(K).zip(inv)))
            {
                for l in 0..K {
                    xi[l] += alpha[l] * pi[l];
                    ri[l] -= alpha[l] * api[l];
                    zi[l] = ri[l] * inv_i;
                    rz_next[l] += ri[l] * zi[l];
                    rr[l] += ri[l] * ri[l];
                }
            }
            for l in 0..K {
                beta[l] = if active[l] { rz_next[l] / rz[l] } else { 0.0 };
                if active[l] {
                    rz[l] = rz_next[l];
                }
                active[l] = active[l] && rr[l].sqrt() > target[l];
            }
            for (pi, zi) in p.chunks_exact_mut(K).zip(z.chunks_exact(K)) {
                for l in 0..K {
                    pi[l] = zi[l] + beta[l] * pi[l];
                }
            }
        }
        let converged = !active.contains(&true);
        (x, converged)
    }

    /// y = D_CC x for `K` interleaved columns, rows in parallel (each row's
    /// sums in column order).
    fn multiply_k<const K: usize>(&self, x: &[f64], y: &mut [f64]) {
        const ROWS: usize = 4096;
        let (ptr, cols, vals) = (&self.dcc.indptr, &self.dcc.indices, &self.dcc.values);
        y.par_chunks_mut(ROWS * K).enumerate().for_each(|(chunk, ys)| {
            for (i, yi) in ys.chunks_exact_mut(K).enumerate() {
                let row = chunk * ROWS + i;
                let range = ptr[row]..ptr[row + 1];
                let mut sum = [0.0; K];
                for (&j, &v) in cols[range.clone()].iter().zip(&vals[range]) {
                    let xj = &x[j * K..j * K + K];
                    for l in 0..K {
                        sum[l] += v * xj[l];
                    }
                }
                yi.copy_from_slice(&sum);
            }
        });
    }

    /// x with x_C = D_CC⁻¹ r_C on the covered rows C and 0 elsewhere (k
    /// components): conjugate gradients, or the factorisation once they have
    /// been slow (over [`CG_MAX`] steps) or have taken
    /// [`CG_SWEEPS_BEFORE_FACTORING`] steps over all solves. If the
    /// factorisation fails (D_CC, the Gram matrix of the λ_p on the covered
    /// part, is positive definite but for round-off), the last iterates.
    fn solve(&self, r: &[f64], k: usize) -> Vec<f64> {
        let rc: Vec<f64> = self.covered.iter().flat_map(|&p| r[p * k..(p + 1) * k].iter().copied()).collect();
        if self.sweeps.load(Ordering::Relaxed) >= CG_SWEEPS_BEFORE_FACTORING {
            let _ = self.factorised();
        }
        let xc = match self.llt.get() {
            Some(Ok(llt)) => solve_with(llt, &rc, k),
            _ => match self.cg(&rc, k, CG_MAX) {
                (x, true) => x,
                (x, false) => self.factorised().map_or(x, |llt| solve_with(llt, &rc, k)),
            },
        };
        let mut x = vec![0.0; r.len()];
        for (i, &p) in self.covered.iter().enumerate() {
            x[p * k..(p + 1) * k].copy_from_slice(&xc[i * k..(i + 1) * k]);
        }
        x
    }
}

/// D_CC⁻¹ r for `k` interleaved columns by the factorisation.
fn solve_with(llt: &Llt<usize, f64>, r: &[f64], k: usize) -> Vec<f64> {
    let n = r.len() / k;
    let mut rhs = Mat::from_fn(n, k, |i, l| r[i * k + l]);
    llt.solve_in_place(rhs.as_mut());
    (0..n * k).map(|i| rhs[(i / k, i % k)]).collect()
}

impl Transfer {
    /// The explicit T when D is diagonal (dual and lumped multipliers).
    pub fn matrix(&self) -> Option<&CsrMatrix> {
        match &self.kind {
            Kind::Explicit(t) => Some(t),
            Kind::Solved { .. } => None,
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
            Kind::Solved { b, d } => d.solve(&b.mul_vec(master_values, k), k),
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
            Kind::Solved { b, d } => {
                assert_eq!(slave_loads.len(), self.nrows * k, "loads must have n_slave × k entries");
                // Tᵀ f = Bᵀ D_CC⁻¹ f_C (D symmetric).
                b.transpose_mul_vec(&d.solve(slave_loads, k), k)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The 1D Laplacian tridiag(−1, 2 + shift, −1) of order n.
    fn laplacian(n: usize, shift: f64) -> CsrMatrix {
        let rows: Vec<(Vec<usize>, Vec<f64>)> = (0..n)
            .map(|i| {
                let cols: Vec<usize> = (i.saturating_sub(1)..(i + 2).min(n)).collect();
                let vals = cols.iter().map(|&j| if j == i { 2.0 + shift } else { -1.0 }).collect();
                (cols, vals)
            })
            .collect();
        CsrMatrix::from_rows(n, rows.iter().map(|(c, v)| (c.as_slice(), v.as_slice())))
    }

    fn residual(d: &CsrMatrix, x: &[f64], r: &[f64]) -> f64 {
        let dx = d.mul_vec(x, 1);
        let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
        norm(&dx.iter().zip(r).map(|(a, b)| a - b).collect::<Vec<_>>()) / norm(r)
    }

    #[test]
    fn well_conditioned_systems_are_solved_by_conjugate_gradients() {
        // Shift 2: κ ≤ 3, like a Jacobi-scaled mass matrix.
        let d = laplacian(3000, 2.0);
        let mass = CoveredMass::new(&d, (0..3000).collect()).unwrap();
        let r: Vec<f64> = (0..3000).map(|i| (i as f64 * 0.01).sin()).collect();
        let (x, converged) = mass.cg(&r, 1, 40);
        assert!(converged && residual(&d, &x, &r) <= CG_RTOL);
        assert_eq!(mass.solve(&r, 1), x, "no factorisation is made");
        assert!(mass.llt.get().is_none());
        // Applied again and again, it is factorised once the steps add up.
        while mass.llt.get().is_none() {
            let y = mass.solve(&r, 1);
            let steps = mass.sweeps.load(Ordering::Relaxed);
            assert!(steps < CG_SWEEPS_BEFORE_FACTORING + 40 || mass.llt.get().is_some(), "{steps} steps");
            assert!(residual(&d, &y, &r) <= CG_RTOL);
        }
        assert!(residual(&d, &mass.solve(&r, 1), &r) < 1e-15);
        // Two columns at once, the second converging first: each as alone.
        let both: Vec<f64> = r.iter().flat_map(|&v| [v, 1.0]).collect();
        let (xx, converged) = mass.cg(&both, 2, 40);
        assert!(converged);
        assert_eq!(xx.iter().step_by(2).copied().collect::<Vec<_>>(), x);
        let ones: Vec<f64> = xx.iter().skip(1).step_by(2).copied().collect();
        assert!(residual(&d, &ones, &vec![1.0; 3000]) <= CG_RTOL);
        // Six columns go in groups of four and two, each column as alone.
        let six: Vec<f64> = r.iter().flat_map(|&v| [v, 1.0, v, 2.0, -v, 1.0]).collect();
        let (x6, converged) = mass.cg(&six, 6, 40);
        assert!(converged);
        assert_eq!(x6.iter().step_by(6).copied().collect::<Vec<_>>(), x);
        assert_eq!(x6.iter().skip(1).step_by(6).copied().collect::<Vec<_>>(), ones);
        // Bit for bit on any number of threads.
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| mass.cg(&both, 2, 40).0)
        };
        assert_eq!(on(1), xx);
        assert_eq!(on(3), xx);
    }

    #[test]
    fn ill_conditioned_systems_fall_back_to_the_factorisation() {
        // κ ≈ 4n²/π² = 1.6e6: conjugate gradients need more than CG_MAX steps.
        let n = 2000;
        let d = laplacian(n, 0.0);
        let mass = CoveredMass::new(&d, (0..n).collect()).unwrap();
        let r: Vec<f64> = (0..2 * n).map(|i| ((i / 2) as f64 * 0.37).cos() + (i % 2) as f64).collect();
        assert!(!mass.cg(&r, 2, CG_MAX).1, "conjugate gradients are slow");
        let x = mass.solve(&r, 2);
        assert!(matches!(mass.llt.get(), Some(Ok(_))));
        for l in 0..2 {
            let (xl, rl): (Vec<f64>, Vec<f64>) = (0..n).map(|i| (x[2 * i + l], r[2 * i + l])).unzip();
            // A backward-stable solve: residual ≲ ε κ = 3.6e-10.
            let res = residual(&d, &xl, &rl);
            assert!(res < 1e-9, "component {l}: {res}");
        }
    }

    #[test]
    fn a_non_positive_diagonal_is_a_factorization_error() {
        let mut d = laplacian(10, 0.0);
        d.values[d.indptr[4] + 1] = 0.0;
        let e = CoveredMass::new(&d, (0..10).collect()).err().unwrap();
        assert!(e.to_string().contains("diagonal entry 0 at covered slave point 4"), "{e}");
    }
}
