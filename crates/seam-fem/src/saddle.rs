//! Symmetric saddle-point systems by sparse LDLᵀ with a paired ordering.
//!
//! ```text
//! [ A  Cᵀ ] [ x ]   [ f ]
//! [ C  0  ] [ λ ] = [ g ]       A symmetric positive definite, C of full row rank.
//! ```
//!
//! Such a matrix has no Cholesky factor, but an LDLᵀ factor exists for orderings
//! that eliminate each multiplier after the primal unknown it is paired with:
//! that pivot is then the Schur complement −c²/a < 0. Unknowns are grouped
//! (the dofs of a point, together with the multipliers paired with them), the
//! groups ordered by nested dissection of their graph ([`crate::ordering`]),
//! primal unknowns first within a group. faer's supernodal LDLᵀ factors the
//! permuted matrix with the expected signs (+ primal, − multiplier); a pivot
//! that is tiny or of the wrong sign is replaced by ±δ (dynamic regularisation),
//! and iterative refinement on the original system removes the perturbation.

use crate::ordering::{inverse, nested_dissection, Graph};
use crate::solve::SolveError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, Side};
use seam::CsrMatrix;

/// Largest number of refinement steps.
pub const MAX_REFINEMENTS: usize = 10;

/// Refinement stops when ‖b − M x‖_∞ ≤ `REFINEMENT_RTOL` ‖b‖_∞, or when a step
/// no longer halves the residual (round-off reached).
pub const REFINEMENT_RTOL: f64 = 1e-14;

/// What [`solve_saddle`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SaddleReport {
    /// Refinement steps done.
    pub refinements: usize,
    /// ‖b − M x‖_∞ / ‖b‖_∞ at the end.
    pub relative_residual: f64,
    /// Stored entries of L.
    pub nnz_l: usize,
}

/// Solves M y = b for the symmetric matrix `m` (full pattern, CSR) with
/// `signs[i]` = +1 for primal and −1 for multiplier unknowns, and `group[i]`
/// the ordering group of unknown i (module doc); groups are numbered from 0.
///
/// # Errors
/// [`SolveError::Singular`] when the factorisation breaks down or the residual
/// is not finite; [`SolveError::IllConditioned`] when refinement stalls above
/// [`REFINEMENT_RTOL`]·10⁴; [`SolveError::OutOfMemory`].
pub fn solve_saddle(
    m: &CsrMatrix,
    b: &[f64],
    signs: &[i8],
    group: &[usize],
) -> Result<(Vec<f64>, SaddleReport), SolveError> {
    SaddleFactor::new(m, signs, group)?.solve_refined(m, b)
}

/// The LDLᵀ factor of a symmetric saddle-point matrix (module doc), to
/// solve with it many times.
pub struct SaddleFactor {
    symbolic: faer::sparse::linalg::cholesky::SymbolicCholesky<usize>,
    values: Vec<f64>,
    mem: MemBuffer,
    par: faer::Par,
}

impl SaddleFactor {
    /// Factors `m` (full pattern, CSR; symmetric, its lower triangle used)
    /// with `signs` and `group` as in [`solve_saddle`].
    ///
    /// # Errors
    /// [`SolveError::Singular`] when the factorisation breaks down;
    /// [`SolveError::OutOfMemory`].
    pub fn new(m: &CsrMatrix, signs: &[i8], group: &[usize]) -> Result<SaddleFactor, SolveError> {
        let n = m.nrows;
        let perm = paired_ordering(m, signs, group);
        let inv = inverse(&perm);
        // Lower triangle, CSC: column j holds the entries (i, j), i ≥ j, of row j
        // (M is symmetric).
        let mut col_ptr = vec![0usize];
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        for j in 0..n {
            let (cols, vals) = m.row(j);
            for (&i, &v) in cols.iter().zip(vals).filter(|(&i, _)| i >= j) {
                row_idx.push(i);
                values.push(v);
            }
            col_ptr.push(row_idx.len());
        }
        let symbolic = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let ord = SymmetricOrdering::Custom(PermRef::new_checked(&perm, &inv, n));
        let sym = factorize_symbolic_cholesky(symbolic, Side::Lower, ord, CholeskySymbolicParams::default())
            .map_err(|_| SolveError::OutOfMemory)?;
        let par = crate::solve::parallelism();
        let scale = m.values.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        let regularization = LdltRegularization {
            dynamic_regularization_signs: Some(signs),
            dynamic_regularization_delta: 1e-10 * scale,
            dynamic_regularization_epsilon: 1e-14 * scale,
        };
        let mut l_values = Vec::new();
        l_values.try_reserve_exact(sym.len_val()).map_err(|_| SolveError::OutOfMemory)?;
        l_values.resize(sym.len_val(), 0.0f64);
        let scratch = sym
            .factorize_numeric_ldlt_scratch::<f64>(par, Default::default())
            .or(sym.solve_in_place_scratch::<f64>(1, par));
        let mut mem = MemBuffer::try_new(scratch).map_err(|_| SolveError::OutOfMemory)?;
        let a = SparseColMatRef::new(symbolic, &values);
        sym.factorize_numeric_ldlt(
            &mut l_values,
            a,
            Side::Lower,
            regularization,
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(|_| SolveError::Singular)?;
        Ok(SaddleFactor { symbolic: sym, values: l_values, mem, par })
    }

    /// Stored entries of L.
    pub fn nnz_l(&self) -> usize {
        self.values.len()
    }

    /// y = M⁻¹ r by one forward and back substitution (without refinement:
    /// the factor of the regularised matrix).
    pub fn solve(&mut self, r: &[f64]) -> Vec<f64> {
        let n = r.len();
        let mut x = Mat::<f64>::from_fn(n, 1, |i, _| r[i]);
        let ldlt = faer::sparse::linalg::cholesky::LdltRef::new(&self.symbolic, &self.values);
        ldlt.solve_in_place_with_conj(Conj::No, x.as_mut(), self.par, MemStack::new(&mut self.mem));
        (0..n).map(|i| x[(i, 0)]).collect()
    }

    /// y of M y = b for the matrix `m` this factors, by iterative refinement
    /// on `m` (module doc).
    ///
    /// # Errors
    /// As [`solve_saddle`].
    pub fn solve_refined(
        &mut self,
        m: &CsrMatrix,
        b: &[f64],
    ) -> Result<(Vec<f64>, SaddleReport), SolveError> {
        let mut report = SaddleReport { nnz_l: self.nnz_l(), ..SaddleReport::default() };
        let b_max = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        let mut x = self.solve(b);
        let mut previous = f64::INFINITY;
        loop {
            let mx = m.mul_vec(&x, 1);
            let r: Vec<f64> = b.iter().zip(&mx).map(|(p, q)| p - q).collect();
            let r_max = r.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            report.relative_residual = if b_max > 0.0 { r_max / b_max } else { r_max };
            if !report.relative_residual.is_finite() {
                return Err(SolveError::Singular);
            }
            // Converged, at the cap, or stagnating at round-off.
            let stagnating = report.relative_residual > 0.5 * previous;
            if report.relative_residual <= REFINEMENT_RTOL
                || report.refinements == MAX_REFINEMENTS
                || stagnating
            {
                break;
            }
            previous = report.relative_residual;
            for (xi, d) in x.iter_mut().zip(self.solve(&r)) {
                *xi += d;
            }
            report.refinements += 1;
        }
        if report.relative_residual > 1e4 * REFINEMENT_RTOL {
            return Err(SolveError::IllConditioned { residual: report.relative_residual });
        }
        Ok((x, report))
    }
}

/// GMRES stops at ‖b − J x‖₂ ≤ `GMRES_RTOL` ‖b‖₂ ([`solve_nearly_saddle`]).
pub const GMRES_RTOL: f64 = 1e-13;

/// GMRES keeps at most this many Krylov vectors ([`solve_nearly_saddle`]).
pub const GMRES_MAX_ITERATIONS: usize = 400;

/// x of J x = b for a square J that is a symmetric saddle-point matrix
/// (module doc) except in the rows of the unknowns marked `coupled`, which
/// are multipliers (`signs` −1) whose columns are constraint columns; and the
/// GMRES iterations taken. GMRES on J, right-preconditioned by the LDLᵀ
/// factor of M: J with each coupled row replaced by the transpose of its
/// column (a constraint row, as sticking is for a slipping point). J M⁻¹ − I
/// then has rank at most the number of coupled unknowns, which bounds the
/// iterations (plus one); without coupled unknowns J = M is solved directly,
/// with iterative refinement. With coupled unknowns the system is first
/// equilibrated, S J S (S x) = S b, S diagonal (`scaling`).
///
/// # Errors
/// As [`solve_saddle`]; [`SolveError::NotConverged`] when the residual of
/// the equilibrated system stays above 10³ [`GMRES_RTOL`] of its right-hand
/// side (GMRES stops after [`GMRES_MAX_ITERATIONS`]).
pub fn solve_nearly_saddle(
    j: &CsrMatrix,
    b: &[f64],
    coupled: &[bool],
    signs: &[i8],
    group: &[usize],
) -> Result<(Vec<f64>, usize), SolveError> {
    let n = j.nrows;
    if !coupled.contains(&true) {
        return solve_saddle(j, b, signs, group).map(|(x, _)| (x, 0));
    }
    // Equilibrated: S J S y = S b, x = S y (S = `scaling`), so that the
    // multipliers' pivots are not lost below the factor's regularisation.
    let (mut j, mut jt) = (j.clone(), j.transpose());
    let s = scaling(&j, &jt, signs);
    for m in [&mut j, &mut jt] {
        for i in 0..n {
            for k in m.indptr[i]..m.indptr[i + 1] {
                m.values[k] *= s[i] * s[m.indices[k]];
            }
        }
    }
    let j = &j;
    let b: Vec<f64> = b.iter().zip(&s).map(|(b, s)| b * s).collect();
    let b = &b[..];
    let mut m = CsrMatrix::zeros(0, n);
    for i in 0..n {
        let (cols, vals) = if coupled[i] { jt.row(i) } else { j.row(i) };
        for (&c, &v) in cols.iter().zip(vals).filter(|(&c, _)| !(coupled[i] && coupled[c])) {
            m.indices.push(c);
            m.values.push(v);
        }
        m.indptr.push(m.indices.len());
        m.nrows += 1;
    }
    let mut factor = SaddleFactor::new(&m, signs, group)?;
    // Restarted from the true residual (iterative refinement of the
    // round-off of the regularised factor) while that halves it.
    let b_norm = norm(b);
    let mut x = factor.solve(b);
    let (mut iterations, mut previous) = (0, f64::INFINITY);
    for _ in 0..MAX_REFINEMENTS {
        let r: Vec<f64> = b.iter().zip(j.mul_vec(&x, 1)).map(|(p, q)| p - q).collect();
        let relative = norm(&r) / b_norm;
        if !relative.is_finite() {
            return Err(SolveError::Singular);
        }
        if relative <= GMRES_RTOL || relative > 0.5 * previous {
            break;
        }
        previous = relative;
        let (dx, k) = gmres(j, &r, |r| factor.solve(r))?;
        x.iter_mut().zip(dx).for_each(|(x, d)| *x += d);
        iterations += k;
    }
    let relative = norm(&b.iter().zip(j.mul_vec(&x, 1)).map(|(p, q)| p - q).collect::<Vec<f64>>()) / b_norm;
    if relative > 1e3 * GMRES_RTOL {
        return Err(SolveError::NotConverged { iterations, relative_residual: relative });
    }
    Ok((x.iter().zip(&s).map(|(x, s)| x * s).collect(), iterations))
}

/// The diagonal scaling S of [`solve_nearly_saddle`]: 1/√|J_ii| for a primal
/// unknown i, then for a multiplier the inverse of its column's largest entry
/// |J_ci| S_c over primal rows c (its constraint column, 1 where it vanishes).
fn scaling(j: &CsrMatrix, jt: &CsrMatrix, signs: &[i8]) -> Vec<f64> {
    let mut s: Vec<f64> = (0..j.nrows)
        .map(|i| {
            let (cols, vals) = j.row(i);
            let d = cols.iter().zip(vals).find(|(&c, _)| c == i).map_or(0.0, |(_, v)| v.abs());
            if signs[i] > 0 && d > 0.0 {
                1.0 / d.sqrt()
            } else {
                1.0
            }
        })
        .collect();
    for i in (0..j.nrows).filter(|&i| signs[i] < 0) {
        let (cols, vals) = jt.row(i);
        let big = cols
            .iter()
            .zip(vals)
            .filter(|(&c, _)| signs[c] > 0)
            .fold(0.0f64, |m, (&c, v)| m.max((v * s[c]).abs()));
        if big > 0.0 {
            s[i] = 1.0 / big;
        }
    }
    s
}

/// ‖x‖₂.
fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// Right-preconditioned GMRES (modified Gram–Schmidt, Givens rotations)
/// from x₀ = 0 to ‖b − J x‖₂ ≤ [`GMRES_RTOL`] ‖b‖₂ in exact arithmetic, without
/// restarts; x and the iterations taken.
fn gmres(
    j: &CsrMatrix,
    b: &[f64],
    mut precondition: impl FnMut(&[f64]) -> Vec<f64>,
) -> Result<(Vec<f64>, usize), SolveError> {
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
    let beta = norm(b);
    let mut basis = vec![b.iter().map(|v| v / beta).collect::<Vec<f64>>()];
    let mut h: Vec<Vec<f64>> = Vec::new();
    let mut rotations: Vec<(f64, f64)> = Vec::new();
    let mut g = vec![beta];
    let mut k = 0;
    loop {
        let mut w = j.mul_vec(&precondition(&basis[k]), 1);
        let mut column = vec![0.0; k + 2];
        for (i, v) in basis.iter().enumerate() {
            column[i] = dot(&w, v);
            w.iter_mut().zip(v).for_each(|(w, v)| *w -= column[i] * v);
        }
        column[k + 1] = norm(&w);
        for (i, &(c, s)) in rotations.iter().enumerate() {
            let (p, q) = (column[i], column[i + 1]);
            column[i] = c * p + s * q;
            column[i + 1] = -s * p + c * q;
        }
        let (p, q) = (column[k], column[k + 1]);
        let rho = p.hypot(q);
        if !rho.is_finite() || rho == 0.0 {
            return Err(SolveError::Singular);
        }
        let (c, s) = (p / rho, q / rho);
        column[k] = rho;
        column[k + 1] = 0.0;
        rotations.push((c, s));
        g.push(-s * g[k]);
        g[k] *= c;
        let wn = norm(&w);
        let breakdown = wn == 0.0;
        if !breakdown {
            basis.push(w.iter().map(|v| v / wn).collect());
        }
        h.push(column);
        k += 1;
        if g[k].abs() <= GMRES_RTOL * beta || breakdown || k == GMRES_MAX_ITERATIONS {
            break;
        }
    }
    // y from the triangular H y = g, x = P(V y).
    let mut y = vec![0.0; k];
    for i in (0..k).rev() {
        let sum: f64 = (i + 1..k).map(|l| h[l][i] * y[l]).sum();
        y[i] = (g[i] - sum) / h[i][i];
    }
    let mut v = vec![0.0; b.len()];
    for (yi, vi) in y.iter().zip(&basis) {
        v.iter_mut().zip(vi).for_each(|(v, b)| *v += yi * b);
    }
    Ok((precondition(&v), k))
}

/// Nested dissection of the group graph, primal unknowns before multipliers
/// within each group (`perm[new] = old`).
fn paired_ordering(m: &CsrMatrix, signs: &[i8], group: &[usize]) -> Vec<usize> {
    let n_groups = group.iter().max().map_or(0, |g| g + 1);
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); n_groups];
    for (i, &g) in group.iter().enumerate() {
        members[g].push(i);
    }
    let rows: Vec<Vec<usize>> = members
        .iter()
        .map(|unknowns| {
            let mut row: Vec<usize> =
                unknowns.iter().flat_map(|&i| m.row(i).0.iter().map(|&j| group[j])).collect();
            row.sort_unstable();
            row.dedup();
            row
        })
        .collect();
    let graph = Graph::from_rows(n_groups, |g| &rows[g]);
    nested_dissection(&graph)
        .into_iter()
        .flat_map(|g| {
            let unknowns = &members[g];
            let primal = unknowns.iter().copied().filter(|&i| signs[i] > 0);
            primal.chain(unknowns.iter().copied().filter(|&i| signs[i] <= 0)).collect::<Vec<_>>()
        })
        .collect()
}
