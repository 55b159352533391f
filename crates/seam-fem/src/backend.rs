//! How the linear systems of glue and contact are solved: the solver chosen
//! once for a whole solve, and the operations it offers them.
//!
//! - [`Solver::solve_spd`]: A x = b, A symmetric positive definite on the
//!   free dofs (the reduced glued system, an active-set step on the rotated
//!   system): sparse Cholesky, PCG or a PETSc KSP (CG + GAMG), the iterative
//!   ones from a warm start.
//! - [`Solver::solve_general`]: A x = b, A any square matrix regular on the
//!   free dofs (a semismooth Newton step of frictional contact is not
//!   symmetric): sparse LU with partial pivoting, or PETSc's FGMRES; PCG
//!   refuses it ([`SolveError::NotSymmetric`]). (Frictional contact's direct
//!   solve uses `saddle::solve_nearly_saddle` instead, which knows the
//!   structure of its matrix.)
//!
//! - `Solver::solve_saddle` (crate-internal): the saddle point of
//!   constraints C u = g, [K Cᵀ; C 0] [u; λ] = [f; g] — sparse LDLᵀ, PCG on
//!   the system reduced by C (matrix-free), or PETSc's FGMRES with a
//!   Schur-complement field split, from a warm start (u, λ).
//!
//! All take Dirichlet values: prescribed dofs (and empty rows of A) leave
//! the system, their columns go to the right-hand side, and x holds the
//! prescribed values there (0 at empty rows).

use crate::constraints::{matrix_free, saddle_point, transposed_view, Constraints};
use crate::multibody::{ProblemError, Timings};
use crate::pcg::{free_system, solve_pcg_from, PcgOptions};
use crate::petsc::solve_petsc_saddle;
use crate::petsc::{solve_petsc_from, PetscOptions, PetscSummary};
use crate::solve::{solve, Dirichlet, SolveError};
use faer::linalg::solvers::Solve;
use faer::Mat;
use seam::CsrMatrix;
use std::borrow::Cow;

/// The linear solver of a glued system, or of each active-set step of
/// contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Solver {
    /// Sparse Cholesky of the reduced system (dual, lumped) or sparse LU of the
    /// saddle point (standard).
    Direct,
    /// Preconditioned conjugate gradients on the reduced system PᵀKP,
    /// matrix-free.
    Pcg(PcgOptions),
    /// A PETSc KSP on the reduced system PᵀKP, assembled (dual and lumped
    /// multipliers: by default CG + GAMG with the rigid-body modes), on the
    /// saddle point (standard multipliers: FGMRES with a Schur-complement
    /// field split), and on each active-set step of contact
    /// ([`crate::petsc`]; cargo feature `petsc`).
    Petsc(PetscOptions),
}

/// A solution and the iterations it took (0 for a direct solve).
pub type Solved = (Vec<f64>, usize);

/// A warm start of a saddle point: u and λ.
type SaddleStart<'a> = Option<(&'a [f64], &'a [f64])>;

impl Solver {
    /// The solver with its relative tolerance raised to at least `rtol`
    /// (iterative solvers; a direct one is unchanged): the loose steps of an
    /// iteration whose outer loop decides what is solved next.
    pub fn loosened(self, rtol: f64) -> Solver {
        match self {
            Solver::Direct => Solver::Direct,
            Solver::Pcg(o) => Solver::Pcg(PcgOptions { rtol: o.rtol.max(rtol), ..o }),
            Solver::Petsc(o) => Solver::Petsc(PetscOptions { rtol: o.rtol.max(rtol), ..o }),
        }
    }

    /// x of A x = b, A symmetric positive definite on the free dofs, with the
    /// values of `fixed` (module doc): sparse Cholesky, PCG from `start`, or
    /// a PETSc KSP from `start` with `modes` (the rigid-body modes in A's
    /// unknowns) as GAMG's near-nullspace; PETSc's solve is appended to
    /// `summary`. An owned A goes to PETSc, which keeps the only copy.
    ///
    /// # Errors
    /// The solver's: [`SolveError::Singular`], non-convergence, inconsistent
    /// input, [`SolveError::PetscUnavailable`].
    pub fn solve_spd(
        &self,
        a: Cow<'_, CsrMatrix>,
        b: &[f64],
        fixed: &Dirichlet,
        (start, modes): (Option<&[f64]>, &[Vec<f64>]),
        summary: &mut PetscSummary,
    ) -> Result<Solved, SolveError> {
        match self {
            Solver::Direct => solve(&a, b, fixed).map(|x| (x, 0)),
            Solver::Pcg(o) => solve_pcg_from(&a, b, fixed, o, start).map(|(x, r)| (x, r.iterations)),
            Solver::Petsc(o) => {
                solve_petsc_from(a, b, fixed, modes, o, start, summary).map(|x| (x, last_iterations(summary)))
            }
        }
    }

    /// x of A x = b, A any square matrix regular on the free dofs, with the
    /// values of `fixed` (module doc): sparse LU with partial pivoting
    /// (faer), or PETSc's FGMRES from `start` (by default block Jacobi with
    /// ILU(0); `modes` the near-nullspace a multigrid chosen by PETSc's
    /// options gets), the solve appended to `summary`.
    ///
    /// # Errors
    /// [`SolveError::NotSymmetric`] for PCG; [`SolveError::Singular`] when
    /// the LU factorisation meets a zero pivot; PETSc's errors; inconsistent
    /// input.
    pub fn solve_general(
        &self,
        a: &CsrMatrix,
        b: &[f64],
        fixed: &Dirichlet,
        (start, modes): (Option<&[f64]>, &[Vec<f64>]),
        summary: &mut PetscSummary,
    ) -> Result<Solved, SolveError> {
        match self {
            Solver::Direct => sparse_lu(a, b, fixed).map(|x| (x, 0)),
            Solver::Pcg(_) => Err(SolveError::NotSymmetric),
            Solver::Petsc(o) => crate::petsc::solve_petsc_general(a, b, fixed, modes, o, start, summary)
                .map(|x| (x, last_iterations(summary))),
        }
    }
}

impl Solver {
    /// The near-nullspace the solver takes (`modes` of the solves): for
    /// PETSc the six rigid-body modes of `points` in the unknowns x of a
    /// reduced system u = P x (zero at the dofs `retained` marks eliminated,
    /// then into the nodal frames of `rotation`), with `bodies` (contact:
    /// the first dof of each body) the translations of each body but the
    /// first too ([`crate::petsc::rigid_body_modes_in`]); none for the
    /// others.
    pub(crate) fn near_nullspace(
        &self,
        points: &[seam::Point3],
        bodies: Option<&[usize]>,
        retained: Option<&[usize]>,
        rotation: Option<&CsrMatrix>,
    ) -> Vec<Vec<f64>> {
        match self {
            Solver::Petsc(_) => crate::petsc::rigid_body_modes_in(points, bodies, retained, rotation),
            Solver::Direct | Solver::Pcg(_) => Vec::new(),
        }
    }

    /// u and λ of [K Cᵀ; C 0] [u; λ] = [f; g] for the `constraints` (their
    /// C and g) with the values of `dirichlet`, the method and its
    /// iterations: sparse LDLᵀ with iterative refinement
    /// ([`crate::saddle`]); PCG on the system reduced by C, matrix-free
    /// (each row of C eliminating its dof); or PETSc's FGMRES with a
    /// Schur-complement field split from `start` = (u, λ), `modes` the
    /// near-nullspace of K, the solve appended to `summary`.
    ///
    /// # Errors
    /// The solver's, as [`ProblemError::Solve`].
    pub(crate) fn solve_saddle(
        &self,
        (k, f, dirichlet): (&CsrMatrix, &[f64], &Dirichlet),
        constraints: &Constraints,
        (start, modes): (SaddleStart<'_>, &[Vec<f64>]),
        seconds: &mut Timings,
        summary: &mut PetscSummary,
    ) -> Result<crate::constraints::Solved, ProblemError> {
        match self {
            Solver::Direct => saddle_point(k, f, dirichlet, constraints, seconds),
            Solver::Pcg(o) => matrix_free(k, f, dirichlet, constraints, o, seconds),
            Solver::Petsc(o) => {
                let clock = std::time::Instant::now();
                let c = (&constraints.c, &constraints.g[..]);
                let solved = solve_petsc_saddle(k, f, dirichlet, c, modes, o, start, summary);
                seconds.factorization += clock.elapsed().as_secs_f64();
                let (u, lambda) = solved?;
                Ok((u, lambda, "PETSc KSP on the saddle point (fieldsplit)", last_iterations(summary)))
            }
        }
    }
}

/// The iterations of the last PETSc solve in `summary`.
fn last_iterations(summary: &PetscSummary) -> usize {
    summary.solves.last().map_or(0, |s| s.iterations)
}

/// A x = b with the values of `fixed` by sparse LU of A on the free dofs
/// (faer's supernodal LU with partial pivoting; A_FFᵀ is what A's rows give
/// without a copy as a column matrix, so Aᵀ is factored and solved
/// transposed).
pub(crate) fn sparse_lu(a: &CsrMatrix, b: &[f64], fixed: &Dirichlet) -> Result<Vec<f64>, SolveError> {
    let n = a.nrows;
    let (active, rhs) = free_system(a, b, fixed, None)?;
    let (a_ff, free) = free_block(a, &active);
    let mut x = vec![0.0; n];
    if !free.is_empty() {
        let lu = transposed_view(&a_ff).sp_lu().map_err(|_| SolveError::Singular)?;
        let mut y = Mat::<f64>::from_fn(free.len(), 1, |k, _| rhs[free[k]]);
        lu.solve_transpose_in_place(y.as_mut());
        // A pivot that is zero to round-off leaves non-finite entries.
        if (0..free.len()).any(|k| !y[(k, 0)].is_finite()) {
            return Err(SolveError::Singular);
        }
        for (k, &i) in free.iter().enumerate() {
            x[i] = y[(k, 0)];
        }
    }
    for (dof, v) in fixed.iter() {
        x[dof] = v;
    }
    Ok(x)
}

/// The block A_FF of the unknowns F that `active` marks, and F in order.
pub(crate) fn free_block(a: &CsrMatrix, active: &[bool]) -> (CsrMatrix, Vec<usize>) {
    let mut local = vec![usize::MAX; a.nrows];
    let free: Vec<usize> = (0..a.nrows).filter(|&i| active[i]).collect();
    for (k, &i) in free.iter().enumerate() {
        local[i] = k;
    }
    let mut a_ff = CsrMatrix::zeros(0, free.len());
    for &i in &free {
        let (cols, vals) = a.row(i);
        for (&j, &v) in cols.iter().zip(vals).filter(|(&j, _)| active[j]) {
            a_ff.indices.push(local[j]);
            a_ff.values.push(v);
        }
        a_ff.indptr.push(a_ff.indices.len());
        a_ff.nrows += 1;
    }
    (a_ff, free)
}
