//! The PETSc solver ([`crate::Solver::Petsc`], cargo feature `petsc`): the
//! linear systems of a solve go to a PETSc KSP.
//!
//! - The symmetric positive definite ones — the glued system reduced by dual
//!   or lumped constraints, each active-set step of contact on the rotated
//!   system — by default by CG preconditioned by smoothed-aggregation
//!   multigrid (GAMG) with block size 3 and the six rigid-body modes of the
//!   bodies' points as near-nullspace, as PETSc's elasticity example ex56
//!   (`solve_petsc_from`).
//! - The saddle points of standard multipliers (and crosspoints), glued or
//!   at each active-set step: augmented, by default by FGMRES with a
//!   Schur-complement field split whose displacement block is one GAMG
//!   cycle (`solve_petsc_saddle`).
//!
//! Everything PETSc offers is reachable by its options (`PETSC_OPTIONS`, or
//! the string given to [`initialize_petsc`]: `-pc_type hypre`, `-pc_type lu
//! -pc_factor_mat_solver_type mumps`, `-ksp_monitor`, `-log_view`, …).
//!
//! The system keeps its numbering, 3 dofs per point: prescribed dofs, and
//! dofs that the reduction eliminated (empty rows), become identity rows
//! with zero right-hand side, so that the point blocks stay whole.
//! Successive solves of a contact problem start from the previous solution
//! and keep one PETSc system (`KeptKsp`): a step whose held dofs differ
//! refreshes its values, and GAMG keeps its interpolation (only the coarse
//! operators and smoothers are formed again).
//! A glued system reduced for PETSc gives up K once PᵀKP is formed: PETSc's
//! matrix and multigrid hierarchy take its place, and the K u that the
//! multipliers and the residual need afterwards is formed cell by cell
//! ([`crate::assembly::stiffness_times`]).
//!
//! Built without the feature, every PETSc solve fails with
//! [`SolveError::PetscUnavailable`].

use crate::constraints::NONE;
use crate::pcg::free_system;
use crate::solve::{Dirichlet, SolveError};
use seam::CsrMatrix;
use std::borrow::Cow;

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
    /// What the solve's preconditioner was.
    pub setup: Setup,
}

/// The preconditioner of a solve, in a sequence of systems that keep one
/// KSP (the steps of contact and friction).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Setup {
    /// Set up for this system from scratch.
    #[default]
    New,
    /// Set up again for this system's values, GAMG keeping the
    /// interpolation of an earlier setup.
    Refreshed,
    /// An earlier system's, kept: no setup (this system has the same held
    /// dofs, or is the same).
    Kept,
}

impl Setup {
    /// "new", "refreshed" or "kept".
    pub fn name(self) -> &'static str {
        match self {
            Setup::New => "new",
            Setup::Refreshed => "refreshed",
            Setup::Kept => "kept",
        }
    }
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
    /// The MPI ranks PETSc's systems were distributed over (1: one process;
    /// see `lead_petsc`, feature `petsc`).
    pub ranks: usize,
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

/// The MPI ranks this process's PETSc systems are distributed over: those
/// it leads (`lead_petsc`), itself included; 1 on one process or without
/// the feature.
pub fn petsc_ranks() -> usize {
    #[cfg(feature = "petsc")]
    return seam_petsc::ranks();
    #[cfg(not(feature = "petsc"))]
    1
}

/// Why [`follow_petsc`] returned.
#[cfg(feature = "petsc")]
pub use seam_petsc::Followed;

/// Makes this process, rank 0 of an MPI run, lead the other ranks, which
/// call [`follow_petsc`]: every PETSc solve of this process then runs on all
/// ranks, each holding a block of the system's rows. Returns the number of
/// ranks. [`finalize_petsc`] releases the followers.
#[cfg(feature = "petsc")]
pub fn lead_petsc() -> usize {
    seam_petsc::lead()
}

/// A rank other than 0 of an MPI run whose rank 0 leads ([`lead_petsc`]):
/// takes its part in every PETSc call of the leader until the leader
/// finalises (then call [`finalize_petsc`]) or yields, for the program's own
/// work.
///
/// # Errors
/// [`SolveError::Petsc`]: a call failed on this rank (the leader failed too).
#[cfg(feature = "petsc")]
pub fn follow_petsc() -> Result<seam_petsc::Followed, SolveError> {
    seam_petsc::follow().map_err(|e| SolveError::Petsc(e.0))
}

/// The leader hands its followers back to their program between PETSc
/// calls ([`follow_petsc`] returns `Yielded` there).
#[cfg(feature = "petsc")]
pub fn yield_petsc() {
    seam_petsc::yield_followers()
}

/// Finalises PETSc if it was initialised (a program that finalises MPI
/// itself calls this first; a leader releases its followers); nothing
/// without the feature.
pub fn finalize_petsc() {
    #[cfg(feature = "petsc")]
    seam_petsc::finalize();
}

/// The six rigid-body modes of `points` (GAMG's near-nullspace) in the
/// unknowns x of a reduced system u = P x: zero at the dofs that `retained`
/// marks eliminated ([`NONE`]), then taken into nodal frames by `rotation`ᵀ.
/// With `bodies` (offsets[b] = first dof of body b), also the three
/// translations of each body but the first: in contact a body held through
/// its contact points is soft in them, which the modes of the bodies
/// together do not represent (GAMG then needs several times the
/// iterations: BENCHMARKS.md, Friction with PETSc).
pub(crate) fn rigid_body_modes_in(
    points: &[seam::Point3],
    bodies: Option<&[usize]>,
    retained: Option<&[usize]>,
    rotation: Option<&CsrMatrix>,
) -> Vec<Vec<f64>> {
    let whole = crate::rigid_body_modes(points);
    let mut modes = whole.to_vec();
    for body in bodies.unwrap_or(&[]).windows(2).skip(1) {
        for translation in &whole[..3] {
            let mut mode = vec![0.0; translation.len()];
            mode[body[0]..body[1]].copy_from_slice(&translation[body[0]..body[1]]);
            modes.push(mode);
        }
    }
    for mode in &mut modes {
        if let Some(retained) = retained {
            mode.iter_mut().zip(retained).filter(|(_, &r)| r == NONE).for_each(|(v, _)| *v = 0.0);
        }
        if let Some(p) = rotation {
            *mode = p.transpose_mul_vec(mode, 1);
        }
    }
    modes
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
    k: Cow<'_, CsrMatrix>,
    f: &[f64],
    dirichlet: &Dirichlet,
    modes: &[Vec<f64>],
    options: &PetscOptions,
    start: Option<&[f64]>,
    summary: &mut PetscSummary,
) -> Result<Vec<f64>, SolveError> {
    solve_free_rows(k, f, dirichlet, (Split::None, modes), options, start, summary)
}

/// A x = b, A any square matrix regular on the free dofs, with the values
/// of `fixed` by a PETSc KSP from `start`: by default FGMRES (right
/// preconditioning: the tolerance is on the true residual) with block
/// Jacobi, ILU(0) per rank (GAMG's default Chebyshev smoothing diverges on
/// systems that are not symmetric; `-pc_type gamg -mg_levels_pc_type sor`
/// is the multigrid choice), `modes` the near-nullspace a multigrid gets; the
/// solve is appended to `summary`.
///
/// # Errors
/// As [`solve_petsc_from`].
pub(crate) fn solve_petsc_general(
    a: &CsrMatrix,
    b: &[f64],
    fixed: &Dirichlet,
    modes: &[Vec<f64>],
    options: &PetscOptions,
    start: Option<&[f64]>,
    summary: &mut PetscSummary,
) -> Result<Vec<f64>, SolveError> {
    solve_free_rows(Cow::Borrowed(a), b, fixed, (Split::General, modes), options, start, summary)
}

/// The Newton step K Δu = r of hyperelastic bodies with the values of
/// `dirichlet` by a PETSc KSP: FGMRES with GAMG (the tangent may be
/// indefinite far from equilibrium), `modes` its near-nullspace; the solve
/// is appended to `summary`.
///
/// # Errors
/// As [`solve_petsc_from`].
pub(crate) fn solve_petsc_tangent(
    k: CsrMatrix,
    r: &[f64],
    dirichlet: &Dirichlet,
    modes: &[Vec<f64>],
    options: &PetscOptions,
    summary: &mut PetscSummary,
) -> Result<Vec<f64>, SolveError> {
    solve_free_rows(Cow::Owned(k), r, dirichlet, (Split::NearlySymmetric, modes), options, None, summary)
}

/// A x = b for a matrix bordered by multipliers, [K G; F H] with K on the
/// `first` unknowns (points of 3, `modes` their near-nullspace), by a
/// PETSc KSP: FGMRES with the Schur-complement field split of
/// [`seam_petsc::Structure::Saddle`] (GAMG on K); the solve is appended to
/// `summary`.
///
/// # Errors
/// As [`solve_petsc_from`].
pub(crate) fn solve_petsc_bordered(
    a: &CsrMatrix,
    b: &[f64],
    (first, modes): (usize, &[Vec<f64>]),
    options: &PetscOptions,
    summary: &mut PetscSummary,
) -> Result<Vec<f64>, SolveError> {
    let none = Dirichlet::new();
    solve_free_rows(Cow::Borrowed(a), b, &none, (Split::Saddle(first), modes), options, None, summary)
}

/// K u = f with the values of `dirichlet` by PETSc (`split`: symmetric
/// points or a general matrix): A = K on the free rows and columns and the
/// identity elsewhere, b = f − K ū on the free rows and 0 elsewhere, from
/// `start`'s free entries. An owned K is dropped once A is built.
fn solve_free_rows(
    k: Cow<'_, CsrMatrix>,
    f: &[f64],
    dirichlet: &Dirichlet,
    (split, modes): (Split, &[Vec<f64>]),
    options: &PetscOptions,
    start: Option<&[f64]>,
    summary: &mut PetscSummary,
) -> Result<Vec<f64>, SolveError> {
    let (a, b, mut u) = free_rows(&k, f, dirichlet, start, false)?;
    drop(k); // an owned K (a reduced system) is not needed any more: PETSc gets A
    ksp_solve(a, &b, &mut u, (split, modes), options, start.is_some(), summary)?;
    for (dof, v) in dirichlet.iter() {
        u[dof] = v;
    }
    Ok(u)
}

/// The system PETSc gets for K u = f with the values of `dirichlet` (module
/// doc): A = K on the free rows and columns and the identity elsewhere,
/// b = f − K ū on the free rows and 0 elsewhere, and the initial guess:
/// `start`'s free entries. With `keep_pattern` A keeps all of K's entries
/// (zeros off the free rows and columns), so that systems of one K with
/// other held dofs share a pattern. (The identity rows of held dofs
/// precondition better than K's diagonal there: fewer KSP iterations on
/// Cattaneo–Mindlin.)
fn free_rows(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    start: Option<&[f64]>,
    keep_pattern: bool,
) -> Result<(Rows, Vec<f64>, Vec<f64>), SolveError> {
    let (active, b, u) = free_start(k, f, dirichlet, start)?;
    let rows = rows_of(k, &active, keep_pattern)?;
    Ok((rows, b, u))
}

/// Per dof whether it is free, b, and the initial guess ([`free_rows`]).
type FreeStart = (Vec<bool>, Vec<f64>, Vec<f64>);

/// Which dofs are free, b, and the initial guess ([`free_rows`]).
fn free_start(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    start: Option<&[f64]>,
) -> Result<FreeStart, SolveError> {
    let (active, b) = free_system(k, f, dirichlet, start)?;
    let u: Vec<f64> = match start {
        Some(s) => s.iter().zip(&active).map(|(&v, &a)| if a { v } else { 0.0 }).collect(),
        None => vec![0.0; k.nrows],
    };
    Ok((active, b, u))
}

/// A of [`free_rows`] for the free dofs `active`.
fn rows_of(k: &CsrMatrix, active: &[bool], keep_pattern: bool) -> Result<Rows, SolveError> {
    let n = k.nrows;
    let mut a = Rows::new(n, n, k.nnz() + if keep_pattern { n } else { 0 })?;
    for i in 0..n {
        each_entry(k, active, keep_pattern, i, |j, v| a.push(j, v));
        a.end_row()?;
    }
    Ok(a)
}

/// `entry(column, value)` for each entry of row i of A ([`free_rows`]), in
/// order.
#[inline]
fn each_entry(
    k: &CsrMatrix,
    active: &[bool],
    keep_pattern: bool,
    i: usize,
    mut entry: impl FnMut(usize, f64),
) {
    let (cols, vals) = k.row(i);
    if active[i] {
        for (&j, &v) in cols.iter().zip(vals) {
            if active[j] {
                entry(j, v);
            } else if keep_pattern {
                entry(j, 0.0);
            }
        }
    } else if keep_pattern {
        let before = cols.partition_point(|&j| j < i);
        cols[..before].iter().for_each(|&j| entry(j, 0.0));
        entry(i, 1.0);
        cols[before..].iter().filter(|&&j| j != i).for_each(|&j| entry(j, 0.0));
    } else {
        entry(i, 1.0);
    }
}

/// The fingerprints of A's pattern (columns and row ends) and of its values
/// ([`free_rows`] with the pattern kept), and its entries, without forming A.
#[cfg(feature = "petsc")]
fn fingerprints(k: &CsrMatrix, active: &[bool]) -> (u64, u64, usize) {
    use crate::Fnv;
    let (mut pattern, mut values, mut count) = (Fnv::default(), Fnv::default(), 0);
    for i in 0..k.nrows {
        each_entry(k, active, true, i, |j, v| {
            pattern.add(j as u64);
            values.add(v.to_bits());
            count += 1;
        });
        pattern.add(u64::MAX);
    }
    (pattern.0, values.0, count)
}

/// A KSP kept over a sequence of systems with changing held dofs: the
/// active-set steps of contact, the semismooth Newton steps of friction.
/// - The first system is set up anew.
/// - One with other held dofs, when the solve says `refresh`, refreshes the matrix
///   (systems of one pattern: each keeps the pattern of its A, [`free_rows`]):
///   GAMG keeps the interpolation of its first setup and forms only the
///   coarse operators and the smoothers again. Otherwise, or when the
///   pattern differs, it is set up anew.
/// - One with the same held dofs and other values replaces the operator
///   and keeps the preconditioner (no setup).
/// - The same system again (a step solved once more to a tighter
///   tolerance) is solved from where the last solve stopped.
///
/// Each solve's [`PetscSolve::setup`] says which. Refreshing pays on the
/// symmetric active-set steps (a third of the setup time at the same
/// iterations), not on friction's Newton steps, whose preconditioner then
/// needs more FGMRES iterations than a new setup saves (BENCHMARKS.md, "One
/// PETSc system over the steps").
#[derive(Default)]
pub(crate) struct KeptKsp {
    #[cfg(feature = "petsc")]
    kept: Option<Kept>,
}

/// The kept system, the fingerprints of its pattern and of the values last
/// given, and its held dofs.
#[cfg(feature = "petsc")]
struct Kept {
    system: seam_petsc::System,
    pattern: u64,
    values: u64,
    held: Vec<usize>,
}

impl KeptKsp {
    /// A x = b with the values of `fixed`, from `start`, to `options`'
    /// relative tolerance, a matrix of `split` with `modes` as its
    /// near-nullspace, refreshed for other held dofs if `refresh` (else set
    /// up anew); the solve is appended to `summary`. Returns x and the KSP
    /// iterations.
    ///
    /// # Errors
    /// As [`solve_petsc_from`].
    #[cfg(feature = "petsc")]
    pub(crate) fn solve(
        &mut self,
        (a, b, fixed): (&CsrMatrix, &[f64], &Dirichlet),
        (split, modes, refresh): (Split, &[Vec<f64>], bool),
        options: &PetscOptions,
        start: Option<&[f64]>,
        summary: &mut PetscSummary,
    ) -> Result<crate::backend::Solved, SolveError> {
        let (active, b, mut x) = free_start(a, b, fixed, start)?;
        let held: Vec<usize> = fixed.iter().map(|(dof, _)| dof).collect();
        let (pattern, values, count) = if refresh { fingerprints(a, &active) } else { (0, 0, 0) };
        let (kept, setup) = match self.kept.take() {
            Some(kept) if kept.held == held && refresh && kept.values == values => (kept, Setup::Kept),
            Some(mut kept) if kept.held == held => {
                let rows = rows_of(a, &active, refresh)?;
                kept.system.set_operator(rows.csr()).map_err(petsc)?;
                (Kept { values, ..kept }, Setup::Kept)
            }
            Some(mut kept) if refresh && kept.pattern == pattern => {
                // The values straight into PETSc's matrix, or through a copy
                // of the rows (several ranks).
                let mut filled = false;
                let in_place = kept.system.refresh_in_place(|into| {
                    if into.len() != count {
                        return; // not the pattern of these rows: refreshed from them below
                    }
                    let mut next = 0;
                    for i in 0..a.nrows {
                        each_entry(a, &active, true, i, |_, v| {
                            into[next] = v;
                            next += 1;
                        });
                    }
                    filled = true;
                });
                if !(in_place.map_err(petsc)? && filled) {
                    kept.system.refresh(rows_of(a, &active, true)?.csr()).map_err(petsc)?;
                }
                (Kept { values, held, ..kept }, Setup::Refreshed)
            }
            _ => {
                let rows = rows_of(a, &active, refresh)?;
                let (structure, config) = structure_and_config(split, b.len(), options);
                let system = seam_petsc::System::new(rows.csr(), structure, modes, &config).map_err(petsc)?;
                (Kept { system, pattern, values, held }, Setup::New)
            }
        };
        let kept = self.kept.insert(kept);
        let before = summary.solves.len();
        let solved = (start.is_some(), Some(options.rtol));
        let report = solve_and_report(&mut kept.system, &b, &mut x, solved, summary);
        summary.solves.iter_mut().skip(before).for_each(|s| s.setup = setup);
        report?;
        let iterations = summary.solves.last().map_or(0, |s| s.iterations);
        for (dof, v) in fixed.iter() {
            x[dof] = v;
        }
        Ok((x, iterations))
    }

    #[cfg(not(feature = "petsc"))]
    pub(crate) fn solve(
        &mut self,
        _: (&CsrMatrix, &[f64], &Dirichlet),
        _: (Split, &[Vec<f64>], bool),
        _: &PetscOptions,
        _: Option<&[f64]>,
        _: &mut PetscSummary,
    ) -> Result<crate::backend::Solved, SolveError> {
        Err(SolveError::PetscUnavailable)
    }
}

/// A matrix in compressed rows with PETSc's indices (32 bits), built row by
/// row: 12 bytes an entry, the only copy of a system besides PETSc's own.
struct Rows {
    indptr: Vec<Index>,
    indices: Vec<Index>,
    values: Vec<f64>,
}

impl Rows {
    /// Room for `rows` rows and about `entries` entries, columns below `cols`.
    fn new(rows: usize, cols: usize, entries: usize) -> Result<Rows, SolveError> {
        if rows.max(cols) > Index::MAX as usize {
            return Err(too_large());
        }
        let mut indptr = Vec::with_capacity(rows + 1);
        indptr.push(0);
        Ok(Rows { indptr, indices: Vec::with_capacity(entries), values: Vec::with_capacity(entries) })
    }

    #[inline]
    fn push(&mut self, col: usize, value: f64) {
        self.indices.push(col as Index);
        self.values.push(value);
    }

    fn end_row(&mut self) -> Result<(), SolveError> {
        let end = Index::try_from(self.indices.len()).map_err(|_| too_large())?;
        self.indptr.push(end);
        Ok(())
    }

    /// The matrix as PETSc takes it.
    #[cfg(feature = "petsc")]
    fn csr(&self) -> seam_petsc::Csr<'_> {
        seam_petsc::Csr { rowptr: &self.indptr, cols: &self.indices, values: &self.values }
    }
}

fn too_large() -> SolveError {
    SolveError::Petsc("the system exceeds PETSc's 32-bit indices (2³¹ − 1 entries)".into())
}

/// PETSc's index type (`PetscInt`, 32 bits in Debian's build).
#[cfg(feature = "petsc")]
type Index = seam_petsc::Index;
#[cfg(not(feature = "petsc"))]
type Index = i32;

/// The saddle point [K Cᵀ; C 0] [u; λ] = [f; g] with the values of
/// `dirichlet` (prescribed dofs and empty rows of K as identity rows, C's
/// columns there moved to the right-hand side) by a PETSc KSP, from `start`
/// = (u, λ); the solve is appended to `summary`. Returns u (prescribed
/// values included) and λ.
///
/// K alone may be singular (a body held only by its interface), so the
/// system is augmented, K_γ = K + γ CᵀC and f_γ = f + γ Cᵀg, which changes
/// nothing at the solution (C u = g) and makes K_γ positive definite; γ
/// balances CᵀC's diagonal against K's where the constraints act. By default
/// FGMRES (right preconditioning: the tolerance is on the true residual)
/// preconditioned by PCFIELDSPLIT: Schur complement, upper triangular factorisation, one
/// GAMG cycle on K_γ (`modes` its near-nullspace), Jacobi on
/// C diag(K_γ)⁻¹ Cᵀ. Measured on warped-glue (standard multipliers, 10k
/// unknowns): 55 iterations, against 167 for MINRES with the block-diagonal
/// factorisation and 29 for the reduced system of dual multipliers.
///
/// # Errors
/// As [`solve_petsc_from`].
pub(crate) fn solve_petsc_saddle(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    (c, g): (&CsrMatrix, &[f64]),
    modes: &[Vec<f64>],
    options: &PetscOptions,
    start: Option<(&[f64], &[f64])>,
    summary: &mut PetscSummary,
) -> Result<(Vec<f64>, Vec<f64>), SolveError> {
    let (n, m) = (k.nrows, c.nrows);
    let (active, mut b) = free_system(k, f, dirichlet, start.map(|s| s.0))?;
    let mut prescribed = vec![0.0; n];
    for (dof, v) in dirichlet.iter() {
        prescribed[dof] = v;
    }
    let diagonal_k = k.diagonal();
    let Augmented { c: c_free, g: g_free, ct, ctc, gamma } =
        augmented((c, g), &active, &prescribed, |i| diagonal_k[i])?;
    let ctg = ct.mul_vec(&g_free, 1);
    let mut a = Rows::new(n + m, n + m, k.nnz() + ctc.nnz() + 2 * c_free.nnz())?;
    for i in 0..n {
        if active[i] {
            b[i] += gamma * ctg[i];
            // Row i of K + γ CᵀC over the free columns (two sorted rows merged), then Cᵀ.
            let ((kc, kv), (cc, cv)) = (k.row(i), ctc.row(i));
            let (mut p, mut q) = (0, 0);
            while p < kc.len() || q < cc.len() {
                let (j, v) = match (kc.get(p), cc.get(q)) {
                    (Some(&a), Some(&b)) if a == b => {
                        (p, q) = (p + 1, q + 1);
                        (a, kv[p - 1] + gamma * cv[q - 1])
                    }
                    (Some(&a), Some(&b)) if a < b => {
                        p += 1;
                        (a, kv[p - 1])
                    }
                    (Some(&a), None) => {
                        p += 1;
                        (a, kv[p - 1])
                    }
                    (_, Some(&b)) => {
                        q += 1;
                        (b, gamma * cv[q - 1])
                    }
                    (None, None) => unreachable!("one of the rows has entries left"),
                };
                if active[j] {
                    a.push(j, v);
                }
            }
            let (rows, vals) = ct.row(i);
            for (&r, &v) in rows.iter().zip(vals) {
                a.push(n + r, v);
            }
        } else {
            a.push(i, 1.0);
        }
        a.end_row()?;
    }
    for r in 0..m {
        let (cols, vals) = c_free.row(r);
        for (&j, &v) in cols.iter().zip(vals) {
            a.push(j, v);
        }
        a.end_row()?;
    }
    b.extend_from_slice(&g_free);
    let mut x: Vec<f64> = match start {
        Some((u, lambda)) => u
            .iter()
            .zip(&active)
            .map(|(&v, &a)| if a { v } else { 0.0 })
            .chain(lambda.iter().copied())
            .collect(),
        None => vec![0.0; n + m],
    };
    ksp_solve(a, &b, &mut x, (Split::Saddle(n), modes), options, start.is_some(), summary)?;
    let lambda = x.split_off(n);
    for (dof, v) in dirichlet.iter() {
        x[dof] = v;
    }
    Ok((x, lambda))
}

/// The constraints of a saddle point on the free dofs (`active`): C there,
/// g − C_D ū, Cᵀ, CᵀC, and the augmentation's γ, which balances CᵀC's
/// diagonal against K's (`k_diagonal(i)`) where the constraints act: a
/// larger γ makes K_γ harder for multigrid, a smaller one weakens the
/// augmentation (both cost iterations).
///
/// # Errors
/// [`SolveError::ProductOutOfMemory`] when CᵀC cannot be allocated.
pub(crate) fn augmented(
    (c, g): (&CsrMatrix, &[f64]),
    active: &[bool],
    prescribed: &[f64],
    k_diagonal: impl Fn(usize) -> f64,
) -> Result<Augmented, SolveError> {
    let n = active.len();
    let mut c_free = CsrMatrix::zeros(0, n);
    let mut g_free = g.to_vec();
    for r in 0..c.nrows {
        let (cols, vals) = c.row(r);
        for (&j, &v) in cols.iter().zip(vals) {
            if active[j] {
                c_free.indices.push(j);
                c_free.values.push(v);
            } else {
                g_free[r] -= v * prescribed[j];
            }
        }
        c_free.indptr.push(c_free.indices.len());
        c_free.nrows += 1;
    }
    let ct = c_free.transpose();
    let ctc = crate::constraints::gram(&c_free)?;
    let (sum_k, sum_c) = ctc
        .diagonal()
        .iter()
        .enumerate()
        .filter(|(_, &d)| d > 0.0)
        .fold((0.0, 0.0), |(sk, sc), (i, &d)| (sk + k_diagonal(i), sc + d));
    let gamma = if sum_c > 0.0 { sum_k / sum_c } else { 0.0 };
    Ok(Augmented { c: c_free, g: g_free, ct, ctc, gamma })
}

/// A saddle point's constraints on the free dofs ([`augmented`]).
pub(crate) struct Augmented {
    /// C on the free dofs.
    pub c: CsrMatrix,
    /// g − C_D ū.
    pub g: Vec<f64>,
    /// Cᵀ.
    pub ct: CsrMatrix,
    /// CᵀC.
    pub ctc: CsrMatrix,
    /// γ of K_γ = K + γ CᵀC.
    pub gamma: f64,
}

/// A system's matrix: points of 3 unknowns throughout, or a saddle point
/// whose first `n` unknowns are the points'.
#[derive(Clone, Copy)]
#[cfg_attr(not(feature = "petsc"), allow(dead_code))]
pub(crate) enum Split {
    /// Points of 3 unknowns throughout.
    None,
    /// A saddle point whose first unknowns are the points'.
    Saddle(usize),
    /// Points of 3 unknowns, a matrix that is not symmetric.
    General,
    /// Points of 3 unknowns, a matrix of elasticity symmetric but for a few
    /// rows.
    NearlySymmetric,
}

#[cfg(feature = "petsc")]
fn ksp_solve(
    a: Rows,
    b: &[f64],
    x: &mut [f64],
    (split, modes): (Split, &[Vec<f64>]),
    options: &PetscOptions,
    warm: bool,
    summary: &mut PetscSummary,
) -> Result<(), SolveError> {
    let (structure, config) = structure_and_config(split, b.len(), options);
    let mut system = seam_petsc::System::new(a.csr(), structure, modes, &config).map_err(petsc)?;
    drop(a); // PETSc has its copy: ours goes before the preconditioner's setup
    solve_and_report(&mut system, b, x, (warm, None), summary)
}

/// The structure of a system of n unknowns and its KSP: CG (+ GAMG) on
/// points, FGMRES with the field split on a saddle point.
#[cfg(feature = "petsc")]
fn structure_and_config(
    split: Split,
    n: usize,
    options: &PetscOptions,
) -> (seam_petsc::Structure, seam_petsc::KspConfig) {
    use seam_petsc::{KspConfig, Structure};
    let base = KspConfig { rtol: options.rtol, max_iterations: options.max_iter, ..KspConfig::default() };
    match split {
        Split::None => (Structure::Blocks(if n % 3 == 0 { 3 } else { 1 }), base),
        Split::General => (
            Structure::Blocks(if n % 3 == 0 { 3 } else { 1 }),
            KspConfig { ksp_type: "fgmres".into(), pc_type: "bjacobi".into(), symmetric: false, ..base },
        ),
        Split::NearlySymmetric => (
            Structure::Blocks(if n % 3 == 0 { 3 } else { 1 }),
            KspConfig { ksp_type: "fgmres".into(), pc_type: "gamg".into(), symmetric: false, ..base },
        ),
        Split::Saddle(first) => (
            Structure::Saddle { first, block_size: 3 },
            KspConfig { ksp_type: "fgmres".into(), pc_type: "fieldsplit".into(), symmetric: false, ..base },
        ),
    }
}

#[cfg(feature = "petsc")]
fn petsc(e: seam_petsc::PetscError) -> SolveError {
    SolveError::Petsc(e.0)
}

/// Solves `system` for b from x (when `warm`), to `rtol` if given, and
/// appends the solve to `summary`.
#[cfg(feature = "petsc")]
fn solve_and_report(
    system: &mut seam_petsc::System,
    b: &[f64],
    x: &mut [f64],
    (warm, rtol): (bool, Option<f64>),
    summary: &mut PetscSummary,
) -> Result<(), SolveError> {
    let report = system.solve_to(b, x, warm, rtol).map_err(petsc)?;
    let residual = report.residual;
    summary.ksp_type = report.ksp_type.clone();
    summary.pc_type = report.pc_type.clone();
    summary.assembly_seconds += report.assembly_seconds;
    summary.setup_seconds += report.setup_seconds;
    summary.solve_seconds += report.solve_seconds;
    summary.ranks = report.ranks;
    summary.solves.push(PetscSolve {
        iterations: report.iterations,
        residual,
        reason: report.reason_name.clone(),
        setup: Setup::New,
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

/// y of A y = b, A the matrix every rank staged ([`crate::partition`]),
/// summed where its rows are (rank r holds rows `ranges[r]..ranges[r + 1]`),
/// points or a saddle point (`split`), `modes` its near-nullspace; the
/// solve is appended to `summary`.
///
/// # Errors
/// As [`solve_petsc_from`].
#[cfg(feature = "petsc")]
pub(crate) fn solve_staged_over_ranks(
    ranges: &[usize],
    b: &[f64],
    (split, modes): (Split, &[Vec<f64>]),
    options: &PetscOptions,
    summary: &mut PetscSummary,
) -> Result<Vec<f64>, SolveError> {
    if b.len() > Index::MAX as usize {
        return Err(too_large());
    }
    let ranges: Vec<Index> = ranges.iter().map(|&r| r as Index).collect(); // ≤ n, checked above
    let (structure, config) = structure_and_config(split, b.len(), options);
    let mut system = seam_petsc::System::staged(&ranges, structure, modes, &config).map_err(petsc)?;
    let mut y = vec![0.0; b.len()];
    solve_and_report(&mut system, b, &mut y, (false, None), summary)?;
    Ok(y)
}

#[cfg(not(feature = "petsc"))]
pub(crate) fn solve_staged_over_ranks(
    _: &[usize],
    _: &[f64],
    _: (Split, &[Vec<f64>]),
    _: &PetscOptions,
    _: &mut PetscSummary,
) -> Result<Vec<f64>, SolveError> {
    Err(SolveError::PetscUnavailable)
}

#[cfg(not(feature = "petsc"))]
fn ksp_solve(
    _: Rows,
    _: &[f64],
    _: &mut [f64],
    _: (Split, &[Vec<f64>]),
    _: &PetscOptions,
    _: bool,
    _: &mut PetscSummary,
) -> Result<(), SolveError> {
    Err(SolveError::PetscUnavailable)
}
