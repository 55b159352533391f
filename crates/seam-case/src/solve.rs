//! The pipeline of `seam solve CASE.toml` and `seam.solve`: linear-elastic
//! bodies glued by mortar across non-matching interfaces and in frictionless
//! contact through them, in any mix (the case schema is in [`crate::case`]).
//!
//! [`solve_case`] reads, checks and solves a case without writing;
//! [`Solved::write`] writes its results; [`solve_case_to_output`] does both
//! as `seam solve` does, the outputs checked before the meshes are read.
//!
//! Order of work: the case is read and checked ([`Case::read`]); the output
//! files are checked (none exists unless `force`, the directory is
//! writable; [`solve_case_to_output`] only); the meshes are read and every named surface is looked up; only
//! then is anything assembled. Results are written all-or-nothing
//! ([`Staged`]):
//!
//! - `<dir>/<body>.vtu` per body: point data `displacement` (3), nodal
//!   `stress` (6, Voigt xx yy zz yz xz xy; volume-weighted average of the
//!   cells around the point) and `von_mises`; cell data `stress` (6, at the
//!   cell centre) and `von_mises`. Solved over N > 1 MPI ranks
//!   ([`SolveOptions::pieces`]): `<dir>/<body>.pvtu` instead, VTK's parallel
//!   file, and its N pieces `<dir>/<body>_<r>.vtu` (r = 0…N−1) with the same
//!   fields, the cells cut into N pieces of nearly equal counts by recursive
//!   coordinate bisection of their centres (a point on the boundary of
//!   pieces is in each of them).
//! - `<dir>/<slave body>_<surface>_interface.vtu` per interface: the slave
//!   surface (its own points only) with point data `traction` (3, force per
//!   area exerted by the master on the slave, −λ), `normal_traction` (t·n with
//!   n the slave's outward nodal normal: negative is compression),
//!   `tangential_traction` (3, t − (t·n)n), `normal` (3), `displacement` (3),
//!   `constrained` (1 where the interface constrains the point, else 0) and
//!   `body_point` (the point's 0-based index in the body's mesh). For a
//!   contact interface `traction` is −λ n, `normal` the normal of the contact
//!   constraint, `constrained` 1 at the contact points, and there are also
//!   `contact_pressure` (λ ≥ 0), `gap` (after deformation, ≥ 0), `initial_gap`
//!   (both NaN where the point is no contact point) and `active` (1 where the
//!   point is in contact at the solution, else 0).
//! - With several load steps (`[load]`, [`crate::case::LoadTable`]) the
//!   files above hold the final state (t = 1), and each step k is also
//!   written as `<dir>/steps/<name>_<kkkk>.vtu` (or `.pvtu` and its pieces),
//!   `<name>` a body or `<slave body>_<surface>_interface`, listed with its
//!   time by the ParaView collection `<dir>/<name>.pvd`.
//! - `<dir>/summary.json` (written last): `load` and one object per load
//!   step in `steps`; for a case with contact, with a `contact` object:
//!   active-set steps, active points, forces, KKT residuals.
//!
//! Names in file names keep letters, digits, `-`, `_` and `.`; any other
//! character becomes `_`.

use crate::output::Staged;
use crate::Failure;
use crate::{Case, InterfaceKind, SurfaceRef};
use anyhow::{anyhow, Context};
use rayon::prelude::*;
use seam::{Face, Facing, MaxGap, MortarOptions, MortarSummary, Multiplier, Named, Point3, SurfaceMesh};
use seam_fem::pcg::PcgOptions;
use seam_fem::petsc::PetscOptions;
use seam_fem::{
    Coupling, Load, Material, Problem, ProblemBody, ProblemError, ProblemInterface, Solution, Stresses,
    Support, SurfaceId,
};
use seam_io::Field;
use serde::Serialize;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A solved case: its problem, solution and results, and what `summary.json` holds.
pub struct Solved {
    /// The output directory.
    pub out_dir: PathBuf,
    /// The bodies, interfaces, supports and loads, as read.
    pub problem: Problem,
    /// The final state: displacements, stresses, interface results and the
    /// solver's report.
    pub solution: Solution,
    /// The results of every load step, oldest first; the last one is the
    /// final state (at t = 1). One step without `[load]`.
    pub steps: Vec<StepState>,
    /// What `summary.json` holds.
    pub summary: Summary,
    case: Case,
    case_path: PathBuf,
    /// Pieces of each body's output ([`SolveOptions::pieces`]).
    pieces: usize,
}

impl Solved {
    /// The final state's results (the last load step's).
    pub fn last(&self) -> &StepState {
        self.steps.last().expect("a solved case has at least one load step")
    }

    /// Per interface: the final state's results on the slave surface's own points.
    pub fn interfaces(&self) -> &[InterfaceResult] {
        &self.last().interfaces
    }
}

/// One interface's result on its slave surface, on the surface's own points:
/// the point fields of its VTU file (docs/cli.md names them).
pub struct InterfaceResult {
    /// The slave surface, compacted to the points its faces use.
    pub mesh: SurfaceMesh,
    /// Index of each compacted point in the slave body's mesh.
    pub body_point: Vec<usize>,
    /// The point fields, in the file's order: `traction`, for contact
    /// `contact_pressure`, `gap`, `initial_gap` (NaN off the contact points)
    /// and `active`, then `normal_traction`, `tangential_traction`, `normal`,
    /// `displacement`, `constrained` and `body_point`.
    pub fields: Vec<Field>,
}

impl InterfaceResult {
    /// The values of the point field `name` (`components` per point), if the
    /// interface has it.
    pub fn field(&self, name: &str) -> Option<&[f64]> {
        self.fields.iter().find(|f| f.name == name).map(|f| &f.values[..])
    }
}

/// `summary.json`. For a case with contact `constraints` counts the glued
/// constraint rows plus the contact points, `iterations` the active-set steps
/// and `residual` is the largest KKT residual; `contact` has the details.
#[derive(Serialize, Clone)]
pub struct Summary {
    /// The case file, as given.
    pub case: String,
    /// The directory the results are written to.
    pub output_dir: String,
    /// "direct", "pcg" or "petsc".
    pub solver: &'static str,
    /// The method the solver used, e.g. "saddle-point LU".
    pub method: &'static str,
    /// The interfaces' multiplier when they share one, "mixed" otherwise,
    /// "none" without interfaces.
    pub multiplier: String,
    /// Degrees of freedom (3 per mesh point that some cell uses).
    pub dofs: usize,
    /// Constraint rows.
    pub constraints: usize,
    /// Solver iterations (refinement steps of a direct solve).
    pub iterations: usize,
    /// The relative residual of the solution.
    pub residual: f64,
    /// Sum of all applied loads (tractions and body forces).
    pub applied_load: [f64; 3],
    /// Per body, in case order.
    pub bodies: Vec<BodySummary>,
    /// Per interface, in case order.
    pub interfaces: Vec<InterfaceSummary>,
    /// Contact cases only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactSummary>,
    /// The PETSc solver only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub petsc: Option<PetscSummary>,
    /// The MPI ranks PETSc's systems were distributed over (`mpirun -np N
    /// seam solve`); absent for one process.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ranks: Option<usize>,
    /// The load steps in pseudo-time (`[load]`).
    pub load: LoadSummary,
    /// Per load step, in order (the last one is the final state above).
    pub steps: Vec<LoadStepSummary>,
    /// Seconds per phase.
    pub seconds: Seconds,
    /// Worker threads.
    pub threads: usize,
    /// The version of seam.
    pub seam_version: &'static str,
}

/// The `load` object of `summary.json`.
#[derive(Serialize, Clone)]
pub struct LoadSummary {
    /// The number of load steps.
    pub steps: usize,
    /// Their pseudo-times, the last one 1.
    pub times: Vec<f64>,
}

/// One load step in the `steps` array of `summary.json`.
#[derive(Serialize, Clone)]
pub struct LoadStepSummary {
    /// The pseudo-time.
    pub time: f64,
    /// Solver iterations of the step: active-set steps with contact, else
    /// as the summary's `iterations`.
    pub iterations: usize,
    /// The relative residual after each iteration: with contact the
    /// complementarity residual of each active-set step, else the one
    /// residual of the glued solve.
    pub residuals: Vec<f64>,
    /// Finite deformation: the line search's step factor of each Newton
    /// iteration.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub line_search: Option<Vec<f64>>,
    /// Finite deformation: the parts the step was solved in (1, or more
    /// where Newton failed and the step was cut in halves).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub substeps: Option<usize>,
    /// Contact points active at the end of the step (0 without contact).
    pub active: usize,
    /// With friction: the active points that stick.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stick: Option<usize>,
    /// With friction: the active points that slip.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slip: Option<usize>,
    /// Linear solver iterations of the whole step (PCG or KSP; 0 for direct
    /// solves).
    pub linear_iterations: usize,
    /// With friction: how well the step's solution meets Coulomb's law.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<FrictionResiduals>,
    /// Per interface, in case order: the resultant force the master exerts
    /// on the slave at the end of the step (as the interface's `force`).
    pub forces: Vec<[f64; 3]>,
}

/// The residuals of Coulomb's law at the active points of the frictional
/// interfaces, each relative.
#[derive(Serialize, Clone, Copy, Default)]
pub struct FrictionResiduals {
    /// The cone: max (‖t_τ‖ − μ p)⁺ / max μ p.
    pub cone: f64,
    /// Sticking points do not slip: max ‖slip increment‖ over them / the
    /// largest slip increment or displacement of the step.
    pub stick: f64,
    /// Slipping points: the frictional traction opposes the slip,
    /// max (1 + cos ∠(t_τ, slip increment)).
    pub slip_direction: f64,
}

impl FrictionResiduals {
    /// Of the frictional interfaces of `solution` (None without friction).
    fn of(solution: &Solution) -> Option<FrictionResiduals> {
        let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let relative = |v: f64, s: f64| if s > 0.0 { v / s } else { v };
        let frictional: Vec<_> = solution
            .interfaces
            .iter()
            .filter_map(|f| Some((f, f.contact.as_ref().filter(|c| c.friction > 0.0)?)))
            .collect();
        if frictional.is_empty() {
            return None;
        }
        let u_max = solution.displacement.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let (mut cone, mut bound, mut stick, mut slip_max, mut direction) =
            (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for (f, c) in frictional {
            for p in (0..c.active.len()).filter(|&p| c.active[p]) {
                let (t, s) = (norm(f.tangential_traction[p]), norm(c.slip_increment[p]));
                cone = cone.max(t - c.friction_bound[p]);
                bound = bound.max(c.friction_bound[p]);
                slip_max = slip_max.max(s);
                if c.stick[p] {
                    stick = stick.max(s);
                } else if t > 0.0 && s > 0.0 {
                    let dot: f64 = (0..3).map(|k| f.tangential_traction[p][k] * c.slip_increment[p][k]).sum();
                    direction = direction.max(1.0 + dot / (t * s));
                }
            }
        }
        Some(FrictionResiduals {
            cone: relative(cone.max(0.0), bound),
            stick: relative(stick, slip_max.max(u_max)),
            slip_direction: direction,
        })
    }
}

impl LoadStepSummary {
    /// The step at `time`, solved by `solver`.
    fn new(time: f64, solution: &Solution, solver: LinearSolver) -> LoadStepSummary {
        let r = &solution.report;
        let petsc = r.petsc.as_ref().map_or(0, |p| p.solves.iter().map(|s| s.iterations).sum());
        let (residuals, active, linear_iterations) = match &r.contact {
            // Finite deformation: Newton's iterations, with or without contact.
            c if let Some(n) = &r.newton => (n.residuals.clone(), c.as_ref().map_or(0, |c| c.active), 0),
            Some(c) => (
                c.steps.iter().map(|s| s.residual).collect(),
                c.active,
                c.steps.iter().map(|s| s.linear_iterations).sum::<usize>(),
            ),
            None => {
                let linear = match solver {
                    LinearSolver::Direct => 0,
                    LinearSolver::Pcg => r.iterations,
                    LinearSolver::Petsc => petsc,
                };
                (vec![r.residual], 0, linear)
            }
        };
        let frictional =
            solution.interfaces.iter().filter_map(|f| f.contact.as_ref()).filter(|c| c.friction > 0.0);
        let (mut stick, mut slip, mut any) = (0, 0, false);
        for c in frictional {
            any = true;
            stick += c.stick.iter().filter(|&&s| s).count();
            slip += c.active.iter().zip(&c.stick).filter(|(&a, &s)| a && !s).count();
        }
        let (stick, slip) = if any { (Some(stick), Some(slip)) } else { (None, None) };
        LoadStepSummary {
            time,
            iterations: r.iterations,
            residuals,
            line_search: r.newton.as_ref().map(|n| n.line_search.clone()),
            substeps: r.newton.as_ref().map(|n| n.substeps),
            active,
            stick,
            slip,
            linear_iterations,
            friction: FrictionResiduals::of(solution),
            forces: solution.interfaces.iter().map(|f| f.force).collect(),
        }
    }
}

/// The `petsc` object of `summary.json`: what PETSc did.
#[derive(Serialize, Clone)]
pub struct PetscSummary {
    /// The KSP type, e.g. "cg" (after PETSc's options).
    pub ksp_type: String,
    /// The PC type, e.g. "gamg".
    pub pc_type: String,
    /// KSP iterations of each solve (one for glue, one per active-set step).
    pub iterations: Vec<usize>,
    /// The last solve's ‖b − A x‖₂ / ‖b‖₂.
    pub residual: f64,
    /// PETSc's converged reason of each solve, e.g. "CONVERGED_RTOL".
    pub reasons: Vec<String>,
    /// The preconditioner of each solve: "new", "refreshed" (GAMG's
    /// interpolation kept) or "kept".
    pub setups: Vec<&'static str>,
    /// PETSc's own seconds: building its matrices (`assembly`), the
    /// preconditioner's setup (`setup`) and the KSP solves (`solve`).
    pub seconds: PetscSeconds,
}

/// Seconds inside PETSc.
#[derive(Serialize, Clone)]
pub struct PetscSeconds {
    /// Building PETSc's matrices.
    pub assembly: f64,
    /// KSPSetUp: the preconditioner (GAMG's hierarchy).
    pub setup: f64,
    /// KSPSolve.
    pub solve: f64,
}

impl From<&seam_fem::petsc::PetscSummary> for PetscSummary {
    fn from(p: &seam_fem::petsc::PetscSummary) -> Self {
        PetscSummary {
            ksp_type: p.ksp_type.clone(),
            pc_type: p.pc_type.clone(),
            iterations: p.solves.iter().map(|s| s.iterations).collect(),
            residual: p.solves.last().map_or(0.0, |s| s.residual),
            reasons: p.solves.iter().map(|s| s.reason.clone()).collect(),
            setups: p.solves.iter().map(|s| s.setup.name()).collect(),
            seconds: PetscSeconds {
                assembly: p.assembly_seconds,
                setup: p.setup_seconds,
                solve: p.solve_seconds,
            },
        }
    }
}

/// The `contact` object of `summary.json`.
#[derive(Serialize, Clone)]
pub struct ContactSummary {
    /// The linear solver of the steps.
    pub method: &'static str,
    /// Active-set steps, the last one confirming the active set.
    pub iterations: usize,
    /// The cap (`[contact] max_iterations`).
    pub max_iterations: usize,
    /// The active-set steps.
    pub steps: Vec<StepSummary>,
    /// Slave points with a contact constraint, all interfaces.
    pub contact_points: usize,
    /// Of those, the points in contact at the solution.
    pub active_points: usize,
    /// The KKT residuals.
    pub kkt: KktSummary,
    /// Per interface, in case order.
    pub interfaces: Vec<ContactInterfaceSummary>,
}

/// One active-set step.
#[derive(Serialize, Clone)]
pub struct StepSummary {
    /// Active points during the step's solve.
    pub active: usize,
    /// Points that become active after it.
    pub added: usize,
    /// Points that become inactive after it.
    pub removed: usize,
    /// PCG iterations (0 for a direct solve).
    pub linear_iterations: usize,
    /// Solved to the requested tolerance (`--rtol`): every direct step; an
    /// iterative solver's steps solve to 10⁻³ until a solution leaves the
    /// active set unchanged, and that step and the later ones to rtol.
    pub full_tolerance: bool,
    /// How far the step's iterate is from the contact conditions, relative
    /// ([`seam_fem::ActiveSetStep::residual`]).
    pub residual: f64,
}

/// The relative KKT residuals of the contact solution.
#[derive(Serialize, Clone)]
pub struct KktSummary {
    /// Equilibrium residual.
    pub equilibrium: f64,
    /// Negative pressure residual.
    pub pressure: f64,
    /// Penetration residual.
    pub penetration: f64,
    /// Complementarity residual.
    pub complementarity: f64,
    /// The largest of the four.
    pub max: f64,
}

/// One contact interface.
#[derive(Serialize, Clone)]
pub struct ContactInterfaceSummary {
    /// The master surface, "body:surface".
    pub master: String,
    /// The slave surface, "body:surface".
    pub slave: String,
    /// Slave points with a contact constraint.
    pub contact_points: usize,
    /// Of those, the points in contact at the solution.
    pub active_points: usize,
    /// Resultant contact force of the master on the slave, −Σ_p d_p λ_p n_p.
    pub force: [f64; 3],
    /// Its magnitude.
    pub force_magnitude: f64,
    /// The largest contact pressure.
    pub max_pressure: f64,
}

/// One body in `summary.json`.
#[derive(Serialize, Clone)]
pub struct BodySummary {
    /// The body's name.
    pub name: String,
    /// Its mesh file, resolved.
    pub mesh: String,
    /// The name of its VTU file in the output directory.
    pub file: String,
    /// Mesh points.
    pub points: usize,
    /// Mesh cells.
    pub cells: usize,
    /// Degrees of freedom (3 per mesh point that some cell uses).
    pub dofs: usize,
    /// Young's modulus.
    pub young: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Has a Dirichlet condition of its own.
    pub supported: bool,
    /// Tractions and body force on the body.
    pub applied_load: [f64; 3],
    /// Sum of the interface forces on the body (as slave +force, as master −force);
    /// for a body without supports, −applied_load.
    pub interface_force: [f64; 3],
    /// The largest displacement magnitude.
    pub max_displacement: f64,
    /// The largest cell von Mises stress.
    pub max_von_mises: f64,
}

/// One interface in `summary.json`.
#[derive(Serialize, Clone)]
pub struct InterfaceSummary {
    /// The master surface, "body:surface".
    pub master: String,
    /// The slave surface, "body:surface".
    pub slave: String,
    /// "glue" or "contact".
    pub kind: &'static str,
    /// The name of its VTU file in the output directory.
    pub file: String,
    /// The multiplier basis: "standard", "dual" or "lumped".
    pub multiplier: String,
    /// The slave space the multipliers are built on: "nodal" (the faces'
    /// own functions), "transformed" (Popp's basis on second-order faces:
    /// dual multipliers for contact, or on Prism15 and Pyramid13 slaves) or
    /// "enriched" (dual multipliers on Tri6 and Quad8 faces with their face
    /// bubbles).
    pub slave_space: &'static str,
    /// Slave points with at least one constrained component.
    pub constrained_nodes: usize,
    /// Resultant force exerted by the master on the slave, −Σ_p (Dλ)_p.
    pub force: [f64; 3],
    /// Covered slave area / slave area.
    pub covered_fraction: f64,
    /// The mortar operator's summary (as `seam assemble` reports it).
    pub mortar: MortarSummary,
}

/// The `seconds` object of `summary.json`: wall-clock seconds per phase,
/// the solver's ([`seam_fem::Timings`]) between reading and output.
#[derive(Serialize, Default, Clone, Copy)]
pub struct Seconds {
    /// Reading the meshes.
    pub read: f64,
    /// Assembly, mortar operators, setup, factorization, solve; `stresses`
    /// includes the interface results and the output fields (all load
    /// steps together).
    #[serde(flatten)]
    pub solver: seam_fem::Timings,
    /// Preparing and writing the output files.
    pub output: f64,
    /// The whole run.
    pub total: f64,
}

/// The linear solver of the glued system, or of each active-set step of contact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum LinearSolver {
    /// Sparse direct: Cholesky of the reduced system (dual, lumped
    /// multipliers) or LDLᵀ of the saddle-point system (standard, or when the
    /// elimination would fill in).
    #[default]
    Direct,
    /// Preconditioned conjugate gradients on the reduced system (any
    /// multiplier, matrix-free, to the relative residual rtol): for large
    /// problems.
    Pcg,
    /// A PETSc KSP: by default CG with algebraic multigrid (GAMG, the
    /// rigid-body modes as near-nullspace) on the reduced system (dual and
    /// lumped multipliers) and each active-set step of contact, FGMRES with a
    /// Schur-complement field split on saddle points (standard multipliers);
    /// any PETSc option via PETSC_OPTIONS or --petsc-options (Python:
    /// petsc_options). Needs a build with the cargo feature `petsc`.
    Petsc,
}

seam::named!(LinearSolver, "solver", { Direct => "direct", Pcg => "pcg", Petsc => "petsc" });

/// How a case is solved.
#[derive(Clone, Debug)]
pub struct SolveOptions {
    /// The linear solver.
    pub solver: LinearSolver,
    /// PETSc's options for [`LinearSolver::Petsc`] (`-pc_type hypre`,
    /// `-ksp_monitor`, …), after those of `PETSC_OPTIONS`: PETSc starts with
    /// them, or, started already in this process, adds them to its options
    /// database, where they stay for later solves. Refused with another
    /// solver ([`options_problem`]).
    pub petsc_options: Option<String>,
    /// PCG: stop when ‖r‖₂ ≤ rtol ‖b‖₂; in [[`MIN_RTOL`], 1).
    pub rtol: f64,
    /// Pieces of each body's output: 1 writes `<body>.vtu`; N > 1 (a solve
    /// over N MPI ranks) writes `<body>.pvtu` and its N pieces
    /// `<body>_<r>.vtu` (module doc).
    pub pieces: usize,
    /// How the interfaces' operators are assembled: here, or by an assembler
    /// such as the binary's over MPI ranks.
    pub operators: seam_fem::Operators,
}

impl Default for SolveOptions {
    /// Direct, rtol 1e-10, one piece, operators assembled here.
    fn default() -> Self {
        SolveOptions {
            solver: LinearSolver::Direct,
            petsc_options: None,
            rtol: 1e-10,
            pieces: 1,
            operators: seam_fem::Operators::Here,
        }
    }
}

/// Reads the case file `case_path`, checks it, reads its meshes and solves
/// it, on the current rayon pool, without writing anything
/// ([`Solved::write`] writes the results).
///
/// # Errors
/// A [`Failure`] naming the case file and the item at fault.
pub fn solve_case(case_path: &Path, options: &SolveOptions) -> Result<Solved, Failure> {
    let start = Instant::now();
    check_rtol(options)?;
    let case = Case::read(case_path).map_err(|e| Failure::Case(e.to_string()))?;
    run(case, case_path, options, start)
}

/// Solves a case already read and checked (for example by
/// [`Case::from_toml`] and [`Case::check_mesh_files`]), `case_path` naming it
/// in messages and in summary.json, without writing anything.
///
/// # Errors
/// As [`solve_case`].
pub fn solve_checked_case(case: Case, case_path: &Path, options: &SolveOptions) -> Result<Solved, Failure> {
    let start = Instant::now();
    check_rtol(options)?;
    run(case, case_path, options, start)
}

/// `seam solve CASE.toml`: reads and checks the case, checks its output files
/// (none may exist unless `force`), reads the meshes, solves, and writes the
/// results into the case's output directory all-or-nothing (module doc).
///
/// # Errors
/// As [`solve_case`], and as [`Solved::write`].
pub fn solve_case_to_output(
    case_path: &Path,
    options: &SolveOptions,
    force: bool,
) -> Result<Solved, Failure> {
    let start = Instant::now();
    check_rtol(options)?;
    let case = Case::read(case_path).map_err(|e| Failure::Case(e.to_string()))?;
    check_solver(&case, case_path, options)?;
    let out_dir = case.resolve(&case.output.dir);
    let staged = prepare(&case, case_path, &out_dir, options.pieces, force)?;
    let mut solved = run(case, case_path, options, start)?;
    solved.summary = solved.write_staged(staged, &out_dir, (0.0, start))?;
    Ok(solved)
}

/// Friction needs a solver of nonsymmetric systems: `pcg` is refused.
fn check_solver(case: &Case, case_path: &Path, options: &SolveOptions) -> Result<(), Failure> {
    match case.interfaces.iter().enumerate().find(|(_, f)| f.friction.is_some_and(|mu| mu > 0.0)) {
        Some((i, f)) if options.solver == LinearSolver::Pcg => Err(Failure::Case(format!(
            "{}: {} has friction: its semismooth Newton systems are not symmetric, which pcg cannot \
             solve; use --solver direct or petsc",
            case_path.display(),
            f.describe(i)
        ))),
        _ => Ok(()),
    }
}

fn check_rtol(options: &SolveOptions) -> Result<(), Failure> {
    match options_problem(options) {
        None => Ok(()),
        Some(problem) => Err(Failure::Case(problem)),
    }
}

/// What is wrong with `options`, as text that starts with the option's
/// name (`rtol …`, `petsc_options …`): [`rtol_problem`], or PETSc options
/// without the PETSc solver; `None` when they are usable.
pub fn options_problem(options: &SolveOptions) -> Option<String> {
    if let Some(problem) = rtol_problem(options.rtol) {
        return Some(format!("rtol {problem}"));
    }
    (options.petsc_options.is_some() && options.solver != LinearSolver::Petsc)
        .then(|| "petsc_options needs the solver petsc".to_string())
}

/// The smallest relative tolerance accepted, 10 machine epsilons (≈ 2.2e-15):
/// a residual below it, relative to ‖b‖, is round-off in double precision.
pub const MIN_RTOL: f64 = 10.0 * f64::EPSILON;

/// What is wrong with the relative tolerance `rtol`, as text that follows
/// its name and starts with its value: outside (0, 1), or below [`MIN_RTOL`];
/// `None` when it is usable.
pub fn rtol_problem(rtol: f64) -> Option<String> {
    if !(rtol > 0.0 && rtol < 1.0) {
        return Some(format!("{rtol} must lie in (0, 1)"));
    }
    (rtol < MIN_RTOL).then(|| {
        format!(
            "{rtol:e} is below what double precision can reach: relative residuals under {MIN_RTOL:.1e} \
             (10 machine epsilons) are round-off; use 1e-14 or more"
        )
    })
}

/// The output files of `case` in `dir`, checked and staged (module doc of
/// [`crate::output`]).
fn prepare(
    case: &Case,
    case_path: &Path,
    dir: &Path,
    pieces: usize,
    force: bool,
) -> Result<(OutputNames, Staged), Failure> {
    let names = OutputNames::new(case, dir, pieces).map_err(|e| anyhow!("{}: {e}", case_path.display()))?;
    let mut inputs = case.mesh_paths();
    inputs.push(case_path.to_path_buf());
    let out = Staged::prepare(&names.all(), &inputs, force)?;
    Ok((names, out))
}

/// Reads the meshes of a checked case and looks up every surface it names:
/// the case's [`Problem`]. The other direction, a [`Problem`] written as a
/// case, is [`crate::write`].
///
/// # Errors
/// A [`Failure`] naming the case file, the body and the mesh file.
pub fn read_problem(case: &Case, case_path: &Path) -> Result<Problem, Failure> {
    build_problem(case)
        .map(|(problem, _)| problem)
        .map_err(|e| Failure::Case(format!("{}: {e:#}", case_path.display())))
}

/// Solves `problem`, already in memory, which `case` (read from `case_path`)
/// describes — a built-in example that wrote its meshes and case file, say —
/// exactly as [`solve_case`] solves that case, without reading the meshes
/// again; nothing is written ([`Solved::write`]).
///
/// # Errors
/// As [`solve_case`].
pub fn solve_problem(
    problem: Problem,
    case: Case,
    case_path: &Path,
    options: &SolveOptions,
) -> Result<Solved, Failure> {
    let start = Instant::now();
    check_rtol(options)?;
    let ids = problem.bodies.iter().map(crate::write::written_ids).collect();
    run_problem((problem, ids), case, case_path, options, (Seconds::default(), start))
}

/// The pipeline after the case check (module doc); `start` is when the run began.
fn run(case: Case, case_path: &Path, options: &SolveOptions, start: Instant) -> Result<Solved, Failure> {
    let mut seconds = Seconds::default();
    let clock = Instant::now();
    let problem =
        build_problem(&case).map_err(|e| Failure::Case(format!("{}: {e:#}", case_path.display())))?;
    seconds.read = clock.elapsed().as_secs_f64();
    run_problem(problem, case, case_path, options, (seconds, start))
}

/// The pipeline once the problem (with its bodies' ids) is in memory;
/// `clock`: the seconds so far and when the run began.
fn run_problem(
    (problem, ids): (Problem, Vec<BodyIds>),
    case: Case,
    case_path: &Path,
    options: &SolveOptions,
    (mut seconds, start): (Seconds, Instant),
) -> Result<Solved, Failure> {
    check_solver(&case, case_path, options)?;
    let solver = match options.solver {
        LinearSolver::Direct => seam_fem::Solver::Direct,
        LinearSolver::Pcg => {
            seam_fem::Solver::Pcg(PcgOptions { rtol: options.rtol, ..PcgOptions::default() })
        }
        LinearSolver::Petsc => {
            // PETSc starts here with the options, or adds them (module doc of seam_fem::petsc).
            seam_fem::petsc::initialize_petsc(options.petsc_options.as_deref().unwrap_or(""))
                .map_err(|e| Failure::Error(format!("{}: {e}", case_path.display())))?;
            seam_fem::Solver::Petsc(PetscOptions { rtol: options.rtol, ..PetscOptions::default() })
        }
    };
    let fem_options = seam_fem::SolveOptions {
        solver,
        max_active_set_steps: case.contact.max_iterations,
        operators: options.operators,
        newton: seam_fem::hyperelastic::NewtonOptions {
            rtol: case.newton.rtol,
            max_iterations: case.newton.max_iterations,
            ..Default::default()
        },
    };
    // Each load step in turn; the last one is the final state.
    let mut states: Vec<StepState> = Vec::with_capacity(problem.steps.len());
    let mut load_steps = Vec::with_capacity(problem.steps.len());
    let mut last = None;
    let times = problem.steps.times().to_vec();
    for (k, step) in seam_fem::solve_steps(&problem, &fem_options).enumerate() {
        let at =
            (times.len() > 1).then(|| format!("load step {} of {} (t = {}): ", k + 1, times.len(), times[k]));
        let (time, solution) = step.map_err(|e| problem_failure(e, &case, case_path, at.as_deref()))?;
        seconds.solver += solution.report.seconds;
        load_steps.push(LoadStepSummary::new(time, &solution, options.solver));
        let clock = Instant::now();
        let state = step_state(&case, case_path, (&problem, &ids), (time, &solution))?;
        seconds.solver.stresses += clock.elapsed().as_secs_f64();
        states.push(state);
        last = Some(solution);
    }
    let solution = last.ok_or_else(|| Failure::Error(format!("{}: no load step", case_path.display())))?;
    let out_dir = case.resolve(&case.output.dir);
    seconds.total = start.elapsed().as_secs_f64();
    let names = OutputNames::new(&case, &out_dir, options.pieces)
        .map_err(|e| anyhow!("{}: {e}", case_path.display()))?;
    let mut summary =
        summary(&case, case_path, options.solver, &names, &out_dir, &problem, &solution, seconds)?;
    summary.steps = load_steps;
    Ok(Solved {
        out_dir,
        problem,
        solution,
        steps: states,
        summary,
        case,
        case_path: case_path.to_path_buf(),
        pieces: options.pieces,
    })
}

/// The results of one load step: per body the point and cell fields of its
/// VTU file, per interface its results, each checked finite.
pub struct StepState {
    /// The pseudo-time.
    pub time: f64,
    /// Per interface: its results on the slave surface's own points.
    pub interfaces: Vec<InterfaceResult>,
    /// Per body: the point and cell fields of its VTU file.
    pub body_files: Vec<(Vec<Field>, Vec<Field>)>,
}

/// The results of the step at `time` with `solution` (every value checked
/// finite), the points and cells named by the bodies' `ids`.
fn step_state(
    case: &Case,
    case_path: &Path,
    (problem, ids): (&Problem, &[BodyIds]),
    (time, solution): (f64, &Solution),
) -> Result<StepState, Failure> {
    let interfaces: Vec<InterfaceResult> =
        (0..case.interfaces.len()).map(|i| interface_result(problem, solution, i, ids)).collect();
    let mut body_files = Vec::with_capacity(problem.bodies.len());
    for (b, body) in problem.bodies.iter().enumerate() {
        let (point, cell) = body_fields(&solution.displacement[b], &solution.stresses[b], &ids[b]);
        let what = format!("{}: body \"{}\"", case_path.display(), body.name);
        check_results(&point, &what, "point")?;
        check_results(&cell, &what, "cell")?;
        body_files.push((point, cell));
    }
    for (i, r) in interfaces.iter().enumerate() {
        check_results(
            &r.fields,
            &format!("{}: {}", case_path.display(), case.interfaces[i].describe(i)),
            "point",
        )?;
    }
    Ok(StepState { time, interfaces, body_files })
}

impl Solved {
    /// Writes exactly the files `seam solve` writes, into `dir` instead of the
    /// case's output directory: `<body>.vtu` per body,
    /// `<slave body>_<surface>_interface.vtu` per interface, and
    /// `summary.json` last (module doc), all-or-nothing; existing files are
    /// only replaced with `force`, an input of the case never. Returns the
    /// summary written (its `output_dir` is `dir`, its `seconds` include the
    /// writing).
    ///
    /// # Errors
    /// An output that exists without `force`, is an input or a directory, or
    /// cannot be written.
    pub fn write(&self, dir: &Path, force: bool) -> Result<Summary, Failure> {
        let start = Instant::now();
        let staged = prepare(&self.case, &self.case_path, dir, self.pieces, force)?;
        self.write_staged(staged, dir, (self.summary.seconds.total, start))
    }

    /// Writes the staged outputs; the total time is `total.0` seconds plus
    /// the time since `total.1`.
    fn write_staged(
        &self,
        (names, mut out): (OutputNames, Staged),
        dir: &Path,
        total: (f64, Instant),
    ) -> Result<Summary, Failure> {
        let clock = Instant::now();
        let last = self.last();
        for (b, body) in self.problem.bodies.iter().enumerate() {
            // The cells of each piece (one piece: none).
            let mut cells_of = vec![Vec::new(); names.pieces[b].len()];
            if !cells_of.is_empty() {
                let centres: Vec<Point3> =
                    body.mesh.cells().iter().map(|c| centre(body.mesh.points(), c)).collect();
                for (c, r) in seam::parts::bisect(&centres, cells_of.len()).into_iter().enumerate() {
                    cells_of[r].push(c);
                }
            }
            let (point, cell) = &last.body_files[b];
            write_body(
                &mut out,
                (&names.bodies[b], &names.pieces[b]),
                (&body.mesh, &cells_of),
                (point, cell),
            )?;
            if let Some(series) = names.series.get(b) {
                for (k, state) in self.steps.iter().enumerate() {
                    let (point, cell) = &state.body_files[b];
                    let paths = (series.steps[k].as_path(), &series.pieces[k][..]);
                    write_body(&mut out, paths, (&body.mesh, &cells_of), (point, cell))?;
                }
            }
        }
        for (i, (r, path)) in last.interfaces.iter().zip(&names.interfaces).enumerate() {
            let write = |p: &Path, r: &InterfaceResult| {
                seam_io::write_vtu_file(p, &r.mesh, &r.fields, &[]).map_err(std::io::Error::other)
            };
            out.write(path, |p| write(p, r))?;
            if let Some(series) = names.series.get(self.problem.bodies.len() + i) {
                for (k, state) in self.steps.iter().enumerate() {
                    out.write(&series.steps[k], |p| write(p, &state.interfaces[i]))?;
                }
            }
        }
        for series in &names.series {
            let entries: Vec<(f64, String)> = self
                .steps
                .iter()
                .zip(&series.steps)
                .map(|(state, file)| (state.time, format!("{STEPS_DIR}/{}", file_name(file))))
                .collect();
            out.write(&series.pvd, |p| seam_io::write_pvd_file(p, &entries).map_err(std::io::Error::other))?;
        }
        let mut summary = self.summary.clone();
        summary.output_dir = dir.display().to_string();
        summary.seconds.output += clock.elapsed().as_secs_f64();
        summary.seconds.total = total.0 + total.1.elapsed().as_secs_f64();
        let json = serde_json::to_string_pretty(&summary).context("summary")?;
        out.write(&names.summary, |p| std::fs::write(p, json + "\n"))?;
        out.commit(&[])?;
        Ok(summary)
    }
}

/// Writes a body's fields at `paths.0`: a `.vtu`, or with pieces
/// (`paths.1`, the cells of each in `cells_of`) a `.pvtu` and its pieces.
fn write_body(
    out: &mut Staged,
    (path, pieces): (&Path, &[PathBuf]),
    (mesh, cells_of): (&seam::VolumeMesh, &[Vec<usize>]),
    (point, cell): (&[Field], &[Field]),
) -> Result<(), Failure> {
    let write = |p: &Path, mesh: &seam::VolumeMesh, point: &[Field], cell: &[Field]| {
        seam_io::write_volume_vtu_file(p, mesh, point, cell).map_err(std::io::Error::other)
    };
    if pieces.is_empty() {
        return Ok(out.write(path, |p| write(p, mesh, point, cell))?);
    }
    for (piece_path, cells) in pieces.iter().zip(cells_of) {
        let (mesh, point, cell) = piece(mesh, cells, point, cell)?;
        out.write(piece_path, |p| write(p, &mesh, &point, &cell))?;
    }
    let sources: Vec<String> = pieces.iter().map(|p| file_name(p)).collect();
    out.write(path, |p| seam_io::write_pvtu_file(p, &sources, point, cell).map_err(std::io::Error::other))?;
    Ok(())
}

/// The mean of a cell's corners: where the partition into pieces places it.
fn centre(points: &[Point3], cell: &seam::Cell) -> Point3 {
    let corners = cell.corner_nodes();
    let sum = corners
        .iter()
        .fold([0.0; 3], |s, &n| [s[0] + points[n][0], s[1] + points[n][1], s[2] + points[n][2]]);
    sum.map(|v| v / corners.len() as f64)
}

/// The cells `cells` of `mesh` as a mesh of the points they use (in the
/// order of `mesh`), with the fields' entries of those points and cells.
fn piece(
    mesh: &seam::VolumeMesh,
    cells: &[usize],
    point: &[Field],
    cell: &[Field],
) -> anyhow::Result<(seam::VolumeMesh, Vec<Field>, Vec<Field>)> {
    let mut index = vec![usize::MAX; mesh.points().len()];
    cells.iter().flat_map(|&c| mesh.cells()[c].nodes()).for_each(|&n| index[n] = 0);
    let used: Vec<usize> = (0..index.len()).filter(|&p| index[p] == 0).collect();
    used.iter().enumerate().for_each(|(new, &old)| index[old] = new);
    let points = used.iter().map(|&p| mesh.points()[p]).collect();
    let piece_cells = cells.iter().map(|&c| mesh.cells()[c].map_nodes(|n| index[n])).collect();
    let select = |fields: &[Field], entries: &[usize]| -> Vec<Field> {
        fields
            .iter()
            .map(|f| {
                let values = entries.iter().flat_map(|&e| f.entry(e).iter().copied()).collect();
                Field::new(f.name.clone(), f.components, values)
            })
            .collect()
    };
    let piece = seam::VolumeMesh::new(points, piece_cells).context("a piece of a body's mesh")?;
    Ok((piece, select(point, &used), select(cell, cells)))
}

/// The subdirectory of the output directory that holds the load steps' files.
pub const STEPS_DIR: &str = "steps";

/// The output files of a case.
struct OutputNames {
    /// Per body: `<body>.vtu`, or `<body>.pvtu` when written in pieces.
    bodies: Vec<PathBuf>,
    /// Per body: its pieces `<body>_<r>.vtu` (none for a `.vtu`).
    pieces: Vec<Vec<PathBuf>>,
    interfaces: Vec<PathBuf>,
    /// With several load steps: per body, then per interface, its
    /// collection and its files of each step (none for one step).
    series: Vec<Series>,
    summary: PathBuf,
}

/// The files of a body or an interface over the load steps.
struct Series {
    /// `<name>.pvd`.
    pvd: PathBuf,
    /// Per step k = 1…N: `steps/<name>_<kkkk>.vtu` (or `.pvtu`).
    steps: Vec<PathBuf>,
    /// Per step: the pieces `steps/<name>_<kkkk>_<r>.vtu` of a `.pvtu`.
    pieces: Vec<Vec<PathBuf>>,
}

impl Series {
    /// The files of `stem` in `dir` over `steps` steps, written in `pieces`.
    fn new(dir: &Path, stem: &str, steps: usize, pieces: usize) -> Series {
        let extension = if pieces > 1 { "pvtu" } else { "vtu" };
        let step = |k: usize| format!("{stem}_{k:04}");
        let at = |name: String| dir.join(STEPS_DIR).join(name);
        Series {
            pvd: dir.join(format!("{stem}.pvd")),
            steps: (1..=steps).map(|k| at(format!("{}.{extension}", step(k)))).collect(),
            pieces: (1..=steps)
                .map(|k| match pieces {
                    0 | 1 => Vec::new(),
                    n => (0..n).map(|r| at(format!("{}_{r}.vtu", step(k)))).collect(),
                })
                .collect(),
        }
    }
}

impl OutputNames {
    fn new(case: &Case, dir: &Path, pieces: usize) -> anyhow::Result<OutputNames> {
        let extension = if pieces > 1 { "pvtu" } else { "vtu" };
        let bodies =
            case.bodies.iter().map(|b| dir.join(format!("{}.{extension}", file_part(&b.name)))).collect();
        let piece_names = case
            .bodies
            .iter()
            .map(|b| match pieces {
                0 | 1 => Vec::new(),
                n => (0..n).map(|r| dir.join(format!("{}_{r}.vtu", file_part(&b.name)))).collect(),
            })
            .collect();
        let interface_stems = case
            .interfaces
            .iter()
            .map(|f| {
                let s = SurfaceRef::parse(&f.slave, "")?;
                Ok(format!("{}_{}_interface", file_part(&s.body), file_part(&s.surface)))
            })
            .collect::<anyhow::Result<Vec<String>>>()?;
        let interfaces = interface_stems.iter().map(|stem| dir.join(format!("{stem}.vtu"))).collect();
        let steps = case.load.steps()?.len();
        let series = match steps {
            1 => Vec::new(),
            n => case
                .bodies
                .iter()
                .map(|b| Series::new(dir, &file_part(&b.name), n, pieces))
                .chain(interface_stems.iter().map(|stem| Series::new(dir, stem, n, 1)))
                .collect(),
        };
        let names = OutputNames {
            bodies,
            pieces: piece_names,
            interfaces,
            series,
            summary: dir.join("summary.json"),
        };
        let mut seen = BTreeSet::new();
        for path in names.all() {
            if !seen.insert(path.clone()) {
                anyhow::bail!(
                    "two outputs would be written to {}: rename a body or a surface",
                    path.display()
                );
            }
        }
        Ok(names)
    }

    fn all(&self) -> Vec<PathBuf> {
        let mut all: Vec<PathBuf> = self.pieces.iter().flatten().cloned().collect();
        all.extend(self.bodies.iter().cloned());
        all.extend(self.interfaces.iter().cloned());
        for s in &self.series {
            all.extend(s.pieces.iter().flatten().cloned());
            all.extend(s.steps.iter().cloned());
            all.push(s.pvd.clone());
        }
        all.push(self.summary.clone());
        all
    }
}

/// The last component of `path`, as text.
fn file_name(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}

/// `name` with every character other than a letter, digit, `-`, `_` or `.`
/// replaced by `_`.
fn file_part(name: &str) -> String {
    name.chars().map(|c| if c.is_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect()
}

/// The surfaces of body `name` the case refers to, in order of first mention.
fn referenced_surfaces(case: &Case, name: &str) -> Vec<String> {
    let refs = case
        .interfaces
        .iter()
        .flat_map(|f| [&f.master, &f.slave])
        .chain(case.dirichlet.iter().map(|d| &d.boundary))
        .chain(case.traction.iter().map(|t| &t.boundary));
    let mut surfaces: Vec<String> = Vec::new();
    for r in refs.filter_map(|r| SurfaceRef::parse(r, "").ok()) {
        if r.body == name && !surfaces.contains(&r.surface) {
            surfaces.push(r.surface);
        }
    }
    surfaces
}

/// How a body's mesh file numbers its nodes and cells, for the outputs
/// (`node_id`, `element_id`; module doc).
pub(crate) struct BodyIds {
    /// Per point of the body's mesh: its node's id (Gmsh tag or Abaqus id).
    pub nodes: Vec<u64>,
    /// Per cell: its element's id (Gmsh tag or Abaqus id).
    pub elements: Vec<u64>,
}

/// Reads one body's mesh (as [`crate::Body::model_format`]) and the surfaces
/// the case names on it, with the file's ids of its nodes and cells.
fn read_body(case: &Case, b: &crate::Body) -> anyhow::Result<(ProblemBody, BodyIds)> {
    let what = || format!("body \"{}\"", b.name);
    let path = case.resolve(&b.mesh);
    let msh = seam_io::read_model_file(&path, Some(b.model_format())).with_context(what)?;
    let mesh = msh.volume(b.volume.as_deref()).map_err(|e| e.with_path(&path)).with_context(what)?;
    let elements = msh.volume_elements(b.volume.as_deref()).map_err(|e| e.with_path(&path))?;
    // Degenerate or tangled cells, named by their ids, before any work.
    if let Err(seam_fem::AssemblyError::DegenerateCell { cell }) = seam_fem::cell_volumes(&mesh) {
        let element = &elements[cell];
        anyhow::bail!(
            "{}: {}: element {} ({}) is degenerate or tangled: its Jacobian determinant vanishes or changes sign",
            what(),
            path.display(),
            element.tag,
            element.type_name()
        );
    }
    let surfaces = referenced_surfaces(case, &b.name)
        .into_iter()
        .map(|s| {
            let surface = msh
                .surface_of_volume(&s, b.volume.as_deref())
                .map_err(|e| e.with_path(&path))
                .with_context(what)?;
            Ok((s, surface))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let material = Material::new(b.young, b.poisson).map_err(|e| anyhow!("{}: {e}", what()))?;
    let body_force_amplitude =
        crate::case::amplitude(b.body_force_amplitude.as_ref(), "body_force_amplitude")?;
    let ids = BodyIds { nodes: msh.node_tags.clone(), elements: elements.iter().map(|e| e.tag).collect() };
    let body = ProblemBody {
        name: b.name.clone(),
        mesh,
        material,
        law: b.material.law(),
        body_force: b.body_force,
        body_force_amplitude,
        surfaces,
    };
    Ok((body, ids))
}

/// The in-memory problem of a checked case (meshes read, surfaces looked
/// up), with the ids of each body's nodes and cells.
fn build_problem(case: &Case) -> anyhow::Result<(Problem, Vec<BodyIds>)> {
    let read: Vec<anyhow::Result<(ProblemBody, BodyIds)>> =
        case.bodies.par_iter().map(|b| read_body(case, b)).collect();
    let (bodies, ids): (Vec<ProblemBody>, Vec<BodyIds>) =
        read.into_iter().collect::<anyhow::Result<Vec<_>>>()?.into_iter().unzip();
    let mut problem = Problem { bodies, ..Problem::default() };
    let id = |problem: &Problem, text: &str| -> anyhow::Result<SurfaceId> {
        let r = SurfaceRef::parse(text, "")?;
        problem.find_surface(&format!("{}:{}", r.body, r.surface)).ok_or_else(|| anyhow!("no surface {text}"))
    };
    for f in &case.interfaces {
        let max_gap = f.max_gap.map_or(MaxGap::DEFAULT, MaxGap::Absolute);
        let (master, slave) = (id(&problem, &f.master)?, id(&problem, &f.slave)?);
        let options = MortarOptions {
            multiplier: effective_multiplier(f, problem.surface(slave)),
            facing: Facing::Opposite,
            max_gap,
            ..MortarOptions::default()
        };
        let kind = match f.kind {
            InterfaceKind::Glue => Coupling::Glue,
            InterfaceKind::Contact => Coupling::Contact,
        };
        problem.interfaces.push(ProblemInterface {
            master,
            slave,
            options,
            kind,
            friction: f.friction.unwrap_or(0.0),
        });
    }
    // Values and amplitudes were checked with the case (Case::check).
    let value = |v: &crate::case::Scalar| v.value().map_err(|e| anyhow!(e));
    for d in &case.dirichlet {
        let boundary = id(&problem, &d.boundary)?;
        let mut values = [None, None, None];
        for (k, v) in d.components() {
            values[k] = Some(value(v)?);
        }
        let amplitude = crate::case::amplitude(d.amplitude.as_ref(), "amplitude")?;
        problem.supports.push(Support { boundary, values, amplitude });
    }
    for t in &case.traction {
        let boundary = id(&problem, &t.boundary)?;
        let [x, y, z] = &t.t;
        let amplitude = crate::case::amplitude(t.amplitude.as_ref(), "amplitude")?;
        problem.loads.push(Load { boundary, t: [value(x)?, value(y)?, value(z)?], amplitude });
    }
    problem.steps = case.load.steps()?;
    Ok((problem, ids))
}

/// The interface's multiplier ([`crate::case::Interface::multiplier`]) on its slave surface.
fn effective_multiplier(f: &crate::case::Interface, slave: &SurfaceMesh) -> Multiplier {
    f.multiplier(slave.faces().iter().any(|face| face.is_curved()))
}

/// A solver error in the case's terms: bodies and interfaces by name. An
/// interface whose surfaces do not overlap is "nothing to couple" (exit 1).
/// Cell `cell` of body `body` as the user knows it: "element ID (TYPE) of
/// FILE", its id (Gmsh tag or Abaqus element id) read again from the body's
/// mesh (only on failure), or "cell N" if that fails.
fn element_name(case: &Case, body: usize, cell: usize) -> String {
    let b = &case.bodies[body];
    let path = case.resolve(&b.mesh);
    let element = seam_io::read_model_file(&path, Some(b.model_format())).ok().and_then(|msh| {
        let elements = msh.volume_elements(b.volume.as_deref()).ok()?;
        elements.get(cell).map(|e| format!("element {} ({})", e.tag, e.type_name()))
    });
    match element {
        Some(e) => format!("{e} of {}", path.display()),
        None => format!("cell {cell}"),
    }
}

/// The one line of `e` for `case` at `path`; a failure of finite deformation
/// names the load step (`at`, when there are several).
fn problem_failure(e: ProblemError, case: &Case, path: &Path, at: Option<&str>) -> Failure {
    let file = path.display();
    let at = at.unwrap_or("");
    match e {
        ProblemError::Mortar { interface, source } => {
            let what = case.interfaces[interface].describe(interface);
            match source {
                e @ seam::MortarError::NoOverlap { .. } => {
                    Failure::NoCoupling(format!("{file}: {what}: {e} (check the surfaces, or max_gap)"))
                }
                e => Failure::Error(format!("{file}: {what}: {e}")),
            }
        }
        ProblemError::BadInterface { interface, what } if interface < case.interfaces.len() => {
            Failure::Case(format!("{file}: {}: {what}", case.interfaces[interface].describe(interface)))
        }
        ProblemError::Assembly { body, source } => {
            let b = &case.bodies[body];
            Failure::Case(format!(
                "{file}: body \"{}\" ({}): {source}",
                b.name,
                case.resolve(&b.mesh).display()
            ))
        }
        ProblemError::NonFiniteSolution { body, dof } => {
            let b = &case.bodies[body];
            Failure::Error(format!(
                "{file}: body \"{}\": the solution is not finite at point {} of {} (component {}): an overflow; \
                 check the magnitudes of loads, prescribed values and moduli",
                b.name,
                dof / 3,
                case.resolve(&b.mesh).display(),
                ["x", "y", "z"][dof % 3]
            ))
        }
        ProblemError::SharedSlavePoint { glue, contact, at, .. } => {
            let (g, c) = (&case.interfaces[glue], &case.interfaces[contact]);
            let body = SurfaceRef::parse(&g.slave, "").map(|r| r.body).unwrap_or_default();
            Failure::Case(format!(
                "{file}: {} and {}: the node at ({}, {}, {}) of body \"{body}\" is a slave node of both, glued and \
                 in contact; a node cannot be both (split the surfaces so that they share no node)",
                g.describe(glue),
                c.describe(contact),
                at[0],
                at[1],
                at[2]
            ))
        }
        ProblemError::Solve(e @ seam_fem::SolveError::IllConditioned { .. }) => {
            // Name the likely cause: a nearly incompressible body.
            let soft: Vec<String> = case
                .bodies
                .iter()
                .filter(|b| b.poisson > 0.49)
                .map(|b| format!("body \"{}\" has ν = {}", b.name, b.poisson))
                .collect();
            let hint = match soft.is_empty() {
                true => String::new(),
                false => format!(
                    "; {} (close to 0.5: volumetric locking; use a smaller ν, or --solver pcg)",
                    soft.join(", ")
                ),
            };
            Failure::Error(format!("{file}: {e}{hint}"))
        }
        e @ (ProblemError::ActiveSetNotSettled { .. }
        | ProblemError::FrictionNotConverged { .. }
        | ProblemError::Solve(
            seam_fem::SolveError::NotConverged { .. }
            | seam_fem::SolveError::PetscNotConverged { .. }
            | seam_fem::SolveError::ToleranceUnreachable { .. },
        )) => Failure::Convergence(format!("{file}: {e}")),
        ProblemError::Newton { source } => {
            use seam_fem::hyperelastic::FiniteError;
            let text = match &source {
                FiniteError::Body { body, source } => match **source {
                    FiniteError::Inverted { cell } => format!(
                        "body \"{}\": {} is inverted by the displacements (J ≤ 0)",
                        case.bodies[*body].name,
                        element_name(case, *body, cell)
                    ),
                    _ => format!("body \"{}\": {source}", case.bodies[*body].name),
                },
                e => e.to_string(),
            };
            match source {
                FiniteError::NotConverged { .. } | FiniteError::LineSearch { .. } => {
                    Failure::Convergence(format!(
                        "{file}: finite deformation: {at}{text} (after cutting the step in halves {} times)",
                        seam_fem::MAX_CUTS
                    ))
                }
                _ => Failure::Error(format!("{file}: finite deformation: {at}{text}")),
            }
        }
        e @ (ProblemError::BadInterface { .. }
        | ProblemError::BadBody { .. }
        | ProblemError::MixedLaws { .. }
        | ProblemError::Finite { .. }
        | ProblemError::Value { .. }) => Failure::Case(format!("{file}: {e}")),
        e => Failure::Error(format!("{file}: {e}")),
    }
}

/// `surface` on its own points: the compacted mesh and, per point, its index
/// in the body's mesh.
fn own_points(surface: &SurfaceMesh) -> (SurfaceMesh, Vec<usize>) {
    let used = surface.used_points();
    let body_point: Vec<usize> = (0..used.len()).filter(|&p| used[p]).collect();
    let mut index = vec![usize::MAX; used.len()];
    for (k, &p) in body_point.iter().enumerate() {
        index[p] = k;
    }
    let points = body_point.iter().map(|&p| surface.points()[p]).collect();
    let faces = surface
        .faces()
        .iter()
        .map(|face| Face::from_nodes(&face.nodes().iter().map(|&p| index[p]).collect::<Vec<_>>()))
        .collect();
    let mesh = SurfaceMesh::new(points, faces).expect("a valid surface stays valid on its own points");
    (mesh, body_point)
}

/// Interface `i`'s results on its slave surface's own points (for contact,
/// the pressure is the first scalar field: the one ParaView shows first).
fn interface_result(problem: &Problem, solution: &Solution, i: usize, ids: &[BodyIds]) -> InterfaceResult {
    let f = &problem.interfaces[i];
    let node_ids = &ids[f.slave.body].nodes;
    let (mesh, body_point) = own_points(problem.surface(f.slave));
    let s = &solution.interfaces[i];
    let u = &solution.displacement[f.slave.body];
    let pick = |v: &[f64]| -> Vec<f64> { body_point.iter().map(|&p| v[p]).collect() };
    let pick3 = |v: &[[f64; 3]]| -> Vec<[f64; 3]> { body_point.iter().map(|&p| v[p]).collect() };
    let one = |v: &[bool]| -> Vec<f64> { body_point.iter().map(|&p| if v[p] { 1.0 } else { 0.0 }).collect() };
    let mut fields = vec![Field::vectors("traction", &pick3(&s.traction))];
    if let Some(c) = &s.contact {
        let at_contact = |v: &[f64]| -> Vec<f64> {
            body_point.iter().map(|&p| if c.contact[p] { v[p] } else { f64::NAN }).collect()
        };
        fields.extend([
            Field::scalars("contact_pressure", pick(&c.pressure)),
            Field::scalars("gap", at_contact(&c.gap)),
            Field::scalars("initial_gap", at_contact(&c.initial_gap)),
            Field::scalars("active", one(&c.active)),
        ]);
        if f.friction > 0.0 {
            fields.extend([
                Field::scalars("stick", one(&c.stick)),
                Field::vectors("slip", &pick3(&c.slip)),
                Field::vectors("slip_increment", &pick3(&c.slip_increment)),
                Field::scalars("friction_bound", pick(&c.friction_bound)),
            ]);
        }
    }
    let displacement: Vec<[f64; 3]> =
        body_point.iter().map(|&p| [u[3 * p], u[3 * p + 1], u[3 * p + 2]]).collect();
    fields.extend([
        Field::scalars("normal_traction", pick(&s.normal_traction)),
        Field::vectors("tangential_traction", &pick3(&s.tangential_traction)),
        Field::vectors("normal", &pick3(&s.normal)),
        Field::vectors("displacement", &displacement),
        Field::scalars("constrained", one(&s.constrained)),
        Field::scalars("body_point", body_point.iter().map(|&p| p as f64).collect()),
        Field::scalars("node_id", body_point.iter().map(|&p| node_ids[p] as f64).collect()),
    ]);
    InterfaceResult { mesh, body_point, fields }
}

/// Fields whose NaN marks "no value here" (off the contact points), as the
/// docs/cli.md documents; any other non-finite value is an error.
const NAN_MARKS_NO_VALUE: [&str; 2] = ["gap", "initial_gap"];

/// Nothing non-finite is written as a result (an overflow is reported with the
/// field and entry instead), apart from [`NAN_MARKS_NO_VALUE`].
fn check_results(fields: &[Field], what: &str, entity: &str) -> anyhow::Result<()> {
    for f in fields {
        let marks = NAN_MARKS_NO_VALUE.contains(&f.name.as_str());
        if let Some(i) = f.values.iter().position(|v| !(v.is_finite() || marks && v.is_nan())) {
            anyhow::bail!(
                "{what}: the {entity} field '{}' is {} at {entity} {} (0-based): an overflow; check the magnitudes \
                 of loads, prescribed values and moduli (nothing non-finite is written)",
                f.name,
                f.values[i],
                i / f.components.max(1)
            );
        }
    }
    Ok(())
}

/// Point and cell fields of a body's VTU file.
fn body_fields(u: &[f64], s: &Stresses, ids: &BodyIds) -> (Vec<Field>, Vec<Field>) {
    let six = |v: &[[f64; 6]]| v.iter().flatten().copied().collect::<Vec<f64>>();
    let id = |name: &str, ids: &[u64]| Field::scalars(name, ids.iter().map(|&i| i as f64).collect());
    let point = vec![
        Field::new("displacement", 3, u.to_vec()),
        Field::new("stress", 6, six(&s.nodal)),
        Field::scalars("von_mises", s.nodal_von_mises.clone()),
        id("node_id", &ids.nodes),
    ];
    let cell = vec![
        Field::new("stress", 6, six(&s.cell)),
        Field::scalars("von_mises", s.cell_von_mises.clone()),
        id("element_id", &ids.elements),
    ];
    (point, cell)
}

fn sum3(v: &[f64]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for (k, x) in v.iter().enumerate() {
        s[k % 3] += x;
    }
    s
}

fn norm3(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn max_norm(u: &[f64]) -> f64 {
    u.chunks_exact(3).map(|c| norm3([c[0], c[1], c[2]])).fold(0.0, f64::max)
}

#[allow(clippy::too_many_arguments)]
fn summary(
    case: &Case,
    path: &Path,
    solver: LinearSolver,
    names: &OutputNames,
    out_dir: &Path,
    problem: &Problem,
    solution: &Solution,
    seconds: Seconds,
) -> anyhow::Result<Summary> {
    let loads = problem.loads_and_supports(1.0).map_err(|e| anyhow!("{}: {e}", path.display()))?;
    let coupled = &problem.interfaces;
    let mut applied_load = [0.0; 3];
    let bodies = problem
        .bodies
        .iter()
        .enumerate()
        .map(|(b, body)| {
            let load = sum3(&loads[b].0);
            let mut interface_force = [0.0; 3];
            for (f, s) in coupled.iter().zip(&solution.interfaces) {
                let force = s.force;
                for k in 0..3 {
                    if f.slave.body == b {
                        interface_force[k] += force[k];
                    }
                    if f.master.body == b {
                        interface_force[k] -= force[k];
                    }
                }
            }
            for k in 0..3 {
                applied_load[k] += load[k];
            }
            BodySummary {
                name: body.name.clone(),
                mesh: case.resolve(&case.bodies[b].mesh).display().to_string(),
                file: file_name(&names.bodies[b]),
                points: body.mesh.points().len(),
                cells: body.mesh.cells().len(),
                dofs: 3 * body.mesh.used_points().into_iter().filter(|&u| u).count(),
                young: body.material.young(),
                poisson: body.material.poisson(),
                supported: problem.supports.iter().any(|s| s.boundary.body == b),
                applied_load: load,
                interface_force,
                max_displacement: max_norm(&solution.displacement[b]),
                max_von_mises: solution.stresses[b].cell_von_mises.iter().copied().fold(0.0, f64::max),
            }
        })
        .collect();
    let interfaces: Vec<InterfaceSummary> = coupled
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let s = &solution.interfaces[i];
            let mortar = &s.mortar;
            InterfaceSummary {
                master: problem.surface_name(f.master),
                slave: problem.surface_name(f.slave),
                kind: match f.kind {
                    Coupling::Glue => "glue",
                    Coupling::Contact => "contact",
                },
                file: file_name(&names.interfaces[i]),
                multiplier: f.options.multiplier.name().to_string(),
                slave_space: match (s.enriched, mortar.basis.is_some()) {
                    (true, _) => "enriched",
                    (false, true) => "transformed",
                    (false, false) => "nodal",
                },
                constrained_nodes: s.constrained_points(),
                force: s.force,
                covered_fraction: mortar.summary.covered_area / mortar.summary.slave_area,
                mortar: mortar.summary.clone(),
            }
        })
        .collect();
    let kinds: BTreeSet<&str> = interfaces.iter().map(|f| f.multiplier.as_str()).collect();
    let multiplier = match kinds.len() {
        0 => "none".to_string(),
        1 => kinds.first().map(|k| k.to_string()).unwrap_or_default(),
        _ => "mixed".to_string(),
    };
    let r = &solution.report;
    let contact = r
        .contact
        .as_ref()
        .map(|c| contact_summary(problem, solution, r.method, c, case.contact.max_iterations));
    let constraints = r.constraints + r.contact.as_ref().map_or(0, |c| c.contact_points);
    Ok(Summary {
        case: path.display().to_string(),
        output_dir: out_dir.display().to_string(),
        solver: solver.name(),
        method: r.method,
        multiplier,
        dofs: r.dofs,
        constraints,
        iterations: r.iterations,
        residual: r.residual,
        applied_load,
        bodies,
        interfaces,
        contact,
        petsc: r.petsc.as_ref().map(PetscSummary::from),
        ranks: r.petsc.as_ref().map(|p| p.ranks).filter(|&n| n > 1),
        load: LoadSummary { steps: problem.steps.len(), times: problem.steps.times().to_vec() },
        steps: Vec::new(),
        seconds,
        threads: rayon::current_num_threads(),
        seam_version: env!("CARGO_PKG_VERSION"),
    })
}

/// The `contact` object of `summary.json`.
fn contact_summary(
    problem: &Problem,
    solution: &Solution,
    method: &'static str,
    r: &seam_fem::ContactReport,
    max_iterations: usize,
) -> ContactSummary {
    let count = |v: &[bool]| v.iter().filter(|&&x| x).count();
    let interfaces = problem
        .interfaces
        .iter()
        .zip(&solution.interfaces)
        .filter_map(|(f, s)| Some((f, s.contact.as_ref()?, s.force)))
        .map(|(f, c, force)| ContactInterfaceSummary {
            master: problem.surface_name(f.master),
            slave: problem.surface_name(f.slave),
            contact_points: count(&c.contact),
            active_points: count(&c.active),
            force,
            force_magnitude: norm3(force),
            max_pressure: c.pressure.iter().copied().fold(0.0, f64::max),
        })
        .collect();
    let steps = r
        .steps
        .iter()
        .map(|s| StepSummary {
            active: s.active,
            added: s.added,
            removed: s.removed,
            linear_iterations: s.linear_iterations,
            full_tolerance: s.full_tolerance,
            residual: s.residual,
        })
        .collect();
    let k = &r.kkt;
    ContactSummary {
        method,
        iterations: r.steps.len(),
        max_iterations,
        steps,
        contact_points: r.contact_points,
        active_points: r.active,
        kkt: KktSummary {
            equilibrium: k.equilibrium,
            pressure: k.pressure,
            penetration: k.penetration,
            complementarity: k.complementarity,
            max: k.max(),
        },
        interfaces,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Contact defaults to lumped multipliers, except on a slave surface with
    /// second-order faces, which takes dual ones (lumped is refused on Tri6
    /// and Quad8 faces); a written multiplier, "lumped" included, and glue keep
    /// their own.
    #[test]
    fn contact_on_second_order_slave_faces_defaults_to_dual() {
        let points: Vec<Point3> = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.0, 0.0],
            [0.5, 0.5, 0.0],
            [0.0, 0.5, 0.0],
        ];
        let tri6 = SurfaceMesh::new(points.clone(), vec![Face::Tri6([0, 1, 2, 3, 4, 5])]).unwrap();
        let tri3 = SurfaceMesh::new(points, vec![Face::Tri3([0, 1, 2])]).unwrap();
        let interface = |kind, given| crate::case::Interface {
            master: "a:top".into(),
            slave: "b:bottom".into(),
            kind,
            multiplier_given: given,
            max_gap: None,
            friction: None,
        };
        use InterfaceKind::{Contact, Glue};
        for (kind, given, surface, expected) in [
            (Contact, None, &tri6, Multiplier::Dual),
            (Contact, None, &tri3, Multiplier::Lumped),
            (Contact, Some(Multiplier::Lumped), &tri6, Multiplier::Lumped),
            (Contact, Some(Multiplier::Dual), &tri3, Multiplier::Dual),
            (Glue, None, &tri6, Multiplier::Standard),
        ] {
            let f = interface(kind, given);
            assert_eq!(effective_multiplier(&f, surface), expected, "{kind:?} {given:?}");
        }
    }

    #[test]
    fn bad_options_and_cases_fail_in_one_line_before_any_work() {
        let rtol = SolveOptions { solver: LinearSolver::Pcg, rtol: 2.0, ..SolveOptions::default() };
        let e = solve_case(Path::new("nowhere.toml"), &rtol).err().unwrap();
        assert_eq!(e, Failure::Case("rtol 2 must lie in (0, 1)".into()));
        let tiny = SolveOptions { rtol: 1e-300, ..rtol.clone() };
        let e = solve_case(Path::new("nowhere.toml"), &tiny).err().unwrap();
        assert_eq!(
            e.to_string(),
            "rtol 1e-300 is below what double precision can reach: relative residuals under 2.2e-15 \
             (10 machine epsilons) are round-off; use 1e-14 or more"
        );
        assert_eq!(rtol_problem(1e-14), None);
        let petsc_options = SolveOptions { petsc_options: Some("-ksp_monitor".into()), ..rtol };
        let e = solve_case(Path::new("nowhere.toml"), &SolveOptions { rtol: 1e-10, ..petsc_options }).err();
        assert_eq!(e, Some(Failure::Case("petsc_options needs the solver petsc".into())));
        let e = solve_case(Path::new("nowhere.toml"), &SolveOptions::default()).err().unwrap();
        assert!(matches!(&e, Failure::Case(m) if m.contains("nowhere.toml") && !m.contains('\n')), "{e}");
        assert_eq!(e.exit_code(), 2);
    }

    #[test]
    fn a_json_case_is_its_toml_case() {
        let toml = "[[body]]\nname = \"a\"\nmesh = \"a.msh\"\nyoung = 1.0\npoisson = 0.3\n\n\
                    [[dirichlet]]\nboundary = \"a:bottom\"\nux = 0.0\nuy = 0.0\nuz = 0.0\n";
        let json = r#"{"body": [{"name": "a", "mesh": "a.msh", "young": 1.0, "poisson": 0.3}],
                       "dirichlet": [{"boundary": "a:bottom", "ux": 0.0, "uy": 0.0, "uz": 0.0}]}"#;
        let (a, b) =
            (Case::from_toml(toml, Path::new("d")).unwrap(), Case::from_json(json, Path::new("d")).unwrap());
        assert_eq!(a.mesh_paths(), b.mesh_paths());
        assert_eq!(a.bodies.len(), b.bodies.len());
        let e = Case::from_json(r#"{"body": [], "bogus": 1}"#, Path::new("d")).unwrap_err().to_string();
        assert!(e.contains("bogus"), "{e}");
    }
}
