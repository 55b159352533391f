//! The PETSc solver ([`crate::Solver::Petsc`], cargo feature `petsc`): each
//! symmetric positive definite system that the PCG path would solve —
//! the glued system reduced by the dual or lumped constraints, each
//! active-set step of contact — goes to a PETSc KSP instead: by default CG
//! preconditioned by smoothed-aggregation multigrid (GAMG) with block size 3
//! and the six rigid-body modes of the bodies' points as near-nullspace, as
//! PETSc's elasticity example ex56. Everything PETSc offers is reachable by
//! its options (`PETSC_OPTIONS`, or the string given to
//! [`initialize_petsc`]: `-pc_type hypre`, `-pc_type lu
//! -pc_factor_mat_solver_type mumps`, `-ksp_monitor`, `-log_view`, …).
//!
//! The system keeps its numbering, 3 dofs per point: prescribed dofs, and
//! dofs that the reduction eliminated (empty rows), become identity rows
//! with zero right-hand side, so that the point blocks stay whole.
//! Successive solves of a contact problem start from the previous solution.
//!
//! Built without the feature, every PETSc solve fails with
//! [`SolveError::PetscUnavailable`].

use crate::constraints::NONE;
use crate::pcg::free_system;
use crate::solve::{Dirichlet, SolveError};
use seam::CsrMatrix;

/// Options of the PETSc solver (those of the KSP that PETSc's options do not
/// override).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PetscOptions {
    /// Relative tolerance of the KSP (`-ksp_rtol`): ‖r‖ ≤ rtol ‖b‖ in the
    /// KSP's norm (for CG the preconditioned one).
    pub rtol: f64,
    /// Iteration cap (`-ksp_max_it`).
    pub max_iter: usize,
}

impl Default for PetscOptions {
    /// rtol 10⁻¹⁰, at most 10 000 iterations.
    fn default() -> Self {
        PetscOptions { rtol: 1e-10, max_iter: 10_000 }
    }
}

/// One KSP solve.
#[derive(Clone, Debug, PartialEq)]
pub struct PetscSolve {
    /// KSP iterations.
    pub iterations: usize,
    /// ‖b − A x‖₂ / ‖b‖₂ at the end (the KSP's own test may use another
    /// norm: for CG the preconditioned residual's).
    pub residual: f64,
    /// PETSc's converged reason, e.g. "CONVERGED_RTOL".
    pub reason: String,
}

/// What the PETSc solves of a problem report.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PetscSummary {
    /// The KSP type (after PETSc's options), e.g. "cg".
    pub ksp_type: String,
    /// The PC type, e.g. "gamg".
    pub pc_type: String,
    /// Each solve, in order (one for a glued problem, one per active-set
    /// step of contact).
    pub solves: Vec<PetscSolve>,
    /// Seconds building PETSc's matrices.
    pub assembly_seconds: f64,
    /// Seconds of PETSc's setup (the preconditioner: GAMG's hierarchy).
    pub setup_seconds: f64,
    /// Seconds of PETSc's solves.
    pub solve_seconds: f64,
}

/// Initialises PETSc once per process with `options` (PETSc's command-line
/// options, after `PETSC_OPTIONS`); later calls add their options. PETSc is
/// finalised at process exit.
///
/// # Errors
/// [`SolveError::PetscUnavailable`] without the feature;
/// [`SolveError::Petsc`] when PETSc cannot start.
pub fn initialize_petsc(options: &str) -> Result<(), SolveError> {
    #[cfg(feature = "petsc")]
    return seam_petsc::initialize(options).map_err(|e| SolveError::Petsc(e.0));
    #[cfg(not(feature = "petsc"))]
    {
        let _ = options;
        Err(SolveError::PetscUnavailable)
    }
}

/// The six rigid-body modes of `points` (GAMG's near-nullspace) in the
/// unknowns x of a reduced system u = P x: zero at the dofs that `retained`
/// marks eliminated ([`NONE`]), then taken into nodal frames by `rotation`ᵀ.
pub(crate) fn rigid_body_modes_in(
    points: &[seam::Point3],
    retained: Option<&[usize]>,
    rotation: Option<&CsrMatrix>,
) -> [Vec<f64>; 6] {
    crate::rigid_body_modes(points).map(|mut mode| {
        if let Some(retained) = retained {
            mode.iter_mut().zip(retained).filter(|(_, &r)| r == NONE).for_each(|(v, _)| *v = 0.0);
        }
        match rotation {
            Some(p) => p.transpose_mul_vec(&mode, 1),
            None => mode,
        }
    })
}

/// K u = f with the values of `dirichlet` by a PETSc KSP, from `start` (its
/// entries at free dofs), with `modes` as near-nullspace (vectors in the
/// numbering of K); the solve is appended to `summary`. Prescribed dofs and
/// empty rows of K are identity rows (module doc).
///
/// # Errors
/// Inconsistent input (as [`crate::pcg::solve_pcg_from`]); a PETSc error
/// ([`SolveError::Petsc`]); a KSP that stops without converging
/// ([`SolveError::PetscNotConverged`]); no PETSc in this build.
pub(crate) fn solve_petsc_from(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    modes: &[Vec<f64>],
    options: &PetscOptions,
    start: Option<&[f64]>,
    summary: &mut PetscSummary,
) -> Result<Vec<f64>, SolveError> {
    let n = k.nrows;
    let (active, b) = free_system(k, f, dirichlet, start)?;
    // A = K on the free rows and columns, the identity elsewhere.
    let (mut indptr, mut indices, mut values) = (Vec::with_capacity(n + 1), Vec::new(), Vec::new());
    indptr.push(0);
    for i in 0..n {
        if active[i] {
            let (cols, vals) = k.row(i);
            for (&j, &v) in cols.iter().zip(vals).filter(|(&j, _)| active[j]) {
                indices.push(j);
                values.push(v);
            }
        } else {
            indices.push(i);
            values.push(1.0);
        }
        indptr.push(indices.len());
    }
    let mut u: Vec<f64> = match start {
        Some(s) => s.iter().zip(&active).map(|(&v, &a)| if a { v } else { 0.0 }).collect(),
        None => vec![0.0; n],
    };
    let a = (indptr, indices, values);
    ksp_solve(&a, &b, &mut u, modes, options, start.is_some(), summary)?;
    for (dof, v) in dirichlet.iter() {
        u[dof] = v;
    }
    Ok(u)
}

/// The CSR arrays of a matrix.
type Csr = (Vec<usize>, Vec<usize>, Vec<f64>);

#[cfg(feature = "petsc")]
fn ksp_solve(
    (indptr, indices, values): &Csr,
    b: &[f64],
    x: &mut [f64],
    modes: &[Vec<f64>],
    options: &PetscOptions,
    warm: bool,
    summary: &mut PetscSummary,
) -> Result<(), SolveError> {
    let n = b.len();
    let matrix = seam_petsc::Csr { rowptr: indptr, cols: indices, values };
    let config = seam_petsc::KspConfig {
        rtol: options.rtol,
        max_iterations: options.max_iter,
        ..seam_petsc::KspConfig::default()
    };
    let block = if n % 3 == 0 { 3 } else { 1 };
    let petsc = |e: seam_petsc::PetscError| SolveError::Petsc(e.0);
    let mut system = seam_petsc::System::new(matrix, block, modes, &config).map_err(petsc)?;
    let report = system.solve(b, x, warm).map_err(petsc)?;
    // The true residual ‖b − A x‖₂ / ‖b‖₂ (the KSP's own may be preconditioned).
    let (mut r2, mut b2) = (0.0, 0.0);
    for i in 0..n {
        let ax: f64 = (indptr[i]..indptr[i + 1]).map(|k| values[k] * x[indices[k]]).sum();
        r2 += (b[i] - ax) * (b[i] - ax);
        b2 += b[i] * b[i];
    }
    let residual = if b2 > 0.0 { (r2 / b2).sqrt() } else { r2.sqrt() };
    summary.ksp_type = report.ksp_type.clone();
    summary.pc_type = report.pc_type.clone();
    summary.assembly_seconds += report.assembly_seconds;
    summary.setup_seconds += report.setup_seconds;
    summary.solve_seconds += report.solve_seconds;
    summary.solves.push(PetscSolve {
        iterations: report.iterations,
        residual,
        reason: report.reason_name.clone(),
    });
    if !report.converged() {
        return Err(SolveError::PetscNotConverged {
            reason: report.reason_name,
            iterations: report.iterations,
            residual,
        });
    }
    Ok(())
}

#[cfg(not(feature = "petsc"))]
fn ksp_solve(
    _: &Csr,
    _: &[f64],
    _: &mut [f64],
    _: &[Vec<f64>],
    _: &PetscOptions,
    _: bool,
    _: &mut PetscSummary,
) -> Result<(), SolveError> {
    Err(SolveError::PetscUnavailable)
}
