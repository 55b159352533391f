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
    let stack = MemStack::new(&mut mem);
    let a = SparseColMatRef::new(symbolic, &values);
    let ldlt = sym
        .factorize_numeric_ldlt(&mut l_values, a, Side::Lower, regularization, par, stack, Default::default())
        .map_err(|_| SolveError::Singular)?;
    let mut report = SaddleReport { nnz_l: sym.len_val(), ..SaddleReport::default() };

    let mut solve_in_place = |r: &[f64]| -> Vec<f64> {
        let mut x = Mat::<f64>::from_fn(n, 1, |i, _| r[i]);
        ldlt.solve_in_place_with_conj(Conj::No, x.as_mut(), par, MemStack::new(&mut mem));
        (0..n).map(|i| x[(i, 0)]).collect()
    };
    let b_max = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let mut x = solve_in_place(b);
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
        if report.relative_residual <= REFINEMENT_RTOL || report.refinements == MAX_REFINEMENTS || stagnating
        {
            break;
        }
        previous = report.relative_residual;
        for (xi, d) in x.iter_mut().zip(solve_in_place(&r)) {
            *xi += d;
        }
        report.refinements += 1;
    }
    if report.relative_residual > 1e4 * REFINEMENT_RTOL {
        return Err(SolveError::IllConditioned { residual: report.relative_residual });
    }
    Ok((x, report))
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
