//! One solve for every multi-body problem — glued interfaces, contact
//! interfaces, or both — and one solution: per body its displacement and
//! stresses, per interface its traction (with normal and tangential parts),
//! resultant force and, for contact, pressure, gaps and active set.
//!
//! [`solve_coupled`] takes the solver's view (loads as vectors, [`Body`],
//! [`Interface`]); [`crate::problem::solve`] the named [`crate::Problem`] of a
//! case file or an example. Glue only: the glued system ([`crate::glue`]).
//! With contact: the active-set method ([`crate::contact`]) with the glued
//! interfaces eliminated or as saddle-point rows.

use crate::constraints::Constraints;
use crate::contact::{add_contact_fields, check_couplings, solve_contact, ActiveSetStep, Kkt};
use crate::glue::{add_tractions, solve_glued};
use crate::multibody::{assemble_system, check_input, Body, Coupling, Interface};
use crate::multibody::{ProblemError, Solver, Timings};
use crate::stress::{recover_stresses, Stresses};
use rayon::prelude::*;
use seam::{Mortar, Point3};
use std::time::Instant;

/// How a problem is solved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// The linear solver of the glued system, or of each active-set step.
    pub solver: Solver,
    /// Contact: the cap on active-set steps.
    pub max_active_set_steps: usize,
}

impl Default for SolveOptions {
    /// Direct solves, at most 50 active-set steps.
    fn default() -> Self {
        SolveOptions { solver: Solver::Direct, max_active_set_steps: 50 }
    }
}

/// The solution of a multi-body problem.
#[derive(Clone, Debug)]
pub struct Solution {
    /// Per body: displacements, 3 per mesh point.
    pub displacement: Vec<Vec<f64>>,
    /// Per body: cell and nodal stresses, von Mises.
    pub stresses: Vec<Stresses>,
    /// Per interface, in input order.
    pub interfaces: Vec<InterfaceSolution>,
    /// Sizes, method, residuals and timings.
    pub report: Report,
}

/// The solution on one interface, per point of the slave body (zero, or
/// false, off the slave surface).
#[derive(Clone, Debug)]
pub struct InterfaceSolution {
    /// Glue or contact.
    pub kind: Coupling,
    /// The mortar operator of the interface.
    pub mortar: Mortar,
    /// The traction (force per area) the master exerts on the slave: −λ for
    /// glue (at prescribed and crosspoint dofs the value of the modified
    /// multiplier there), −λ_p n_p for contact.
    pub traction: Vec<[f64; 3]>,
    /// The slave's outward unit normal: the contact constraint's at contact
    /// points, else the nodal normal.
    pub normal: Vec<Point3>,
    /// t·n: negative is compression.
    pub normal_traction: Vec<f64>,
    /// t − (t·n) n.
    pub tangential_traction: Vec<[f64; 3]>,
    /// The interface constrains the point (glue: some component; contact: a
    /// contact point).
    pub constrained: Vec<bool>,
    /// Resultant force of the master on the slave, −Σ_p (D λ)_p.
    pub force: [f64; 3],
    /// Contact interfaces: pressure, gaps and active set.
    pub contact: Option<ContactFields>,
}

impl InterfaceSolution {
    /// An interface with no traction yet, on a slave body of `n` points.
    fn new(kind: Coupling, mortar: Mortar, n: usize) -> InterfaceSolution {
        InterfaceSolution {
            kind,
            mortar,
            traction: vec![[0.0; 3]; n],
            normal: vec![[0.0; 3]; n],
            normal_traction: vec![0.0; n],
            tangential_traction: vec![[0.0; 3]; n],
            constrained: vec![false; n],
            force: [0.0; 3],
            contact: (kind == Coupling::Contact).then(|| ContactFields::new(n)),
        }
    }

    /// The number of points the interface constrains.
    pub fn constrained_points(&self) -> usize {
        self.constrained.iter().filter(|&&c| c).count()
    }
}

/// A contact interface's fields per slave body point (zero, or false, off the
/// contact points). With dual multipliers on second-order slave faces they
/// belong to the transformed unknowns of Popp et al. (2012) at each node
/// (module doc of [`crate::contact`]): the pressure is the coefficient λ_p of
/// the dual function ψ_p (a weighted mean of the pressure around p, not a
/// nodal value), the gaps are those of ũ_p.
#[derive(Clone, Debug)]
pub struct ContactFields {
    /// Has a contact constraint (a contact point).
    pub contact: Vec<bool>,
    /// The initial weighted gap g_p.
    pub initial_gap: Vec<f64>,
    /// The gap after deformation, g_p − w_p (≥ 0).
    pub gap: Vec<f64>,
    /// The contact pressure λ_p (≥ 0, force per area).
    pub pressure: Vec<f64>,
    /// In the final active set.
    pub active: Vec<bool>,
}

impl ContactFields {
    /// No contact point yet on a slave body of `n` points.
    pub(crate) fn new(n: usize) -> ContactFields {
        ContactFields {
            contact: vec![false; n],
            initial_gap: vec![0.0; n],
            gap: vec![0.0; n],
            pressure: vec![0.0; n],
            active: vec![false; n],
        }
    }
}

/// What the solve did.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Displacement unknowns, 3 per point of all bodies that some cell uses.
    pub dofs: usize,
    /// Rows of the glued interfaces' constraints.
    pub constraints: usize,
    /// The method used, e.g. "saddle-point LDLᵀ".
    pub method: &'static str,
    /// Glue only: PCG iterations, or refinement steps of a direct solve;
    /// with contact: active-set steps.
    pub iterations: usize,
    /// Glue only: ‖f − K u − Cᵀλ‖ / ‖f‖ over the free dofs and ‖C u‖
    /// relative to ‖C‖‖u‖, the larger; with contact: the largest KKT residual.
    pub residual: f64,
    /// With contact: active-set steps and KKT residuals.
    pub contact: Option<ContactReport>,
    /// With [`crate::Solver::Petsc`]: the KSP and PC, each solve's
    /// iterations and residual, PETSc's own seconds.
    pub petsc: Option<crate::petsc::PetscSummary>,
    /// Seconds per phase.
    pub seconds: Timings,
}

/// The contact part of a [`Report`].
#[derive(Clone, Debug, PartialEq)]
pub struct ContactReport {
    /// Contact points (slave points with a constraint), all interfaces.
    pub contact_points: usize,
    /// Active points at the solution, all interfaces.
    pub active: usize,
    /// The active-set steps.
    pub steps: Vec<ActiveSetStep>,
    /// KKT residuals of the solution.
    pub kkt: Kkt,
}

/// Solves bodies coupled by glued and contact `interfaces` (module doc).
///
/// # Errors
/// [`ProblemError`] for inconsistent input (an interface to a missing body,
/// loads or supports that do not fit a mesh, standard multipliers for
/// contact, a point that is slave of a glued and of a contact interface), a
/// failed assembly, an interface with no overlap, a singular system, an
/// active set that does not settle, or a non-finite solution.
pub fn solve_coupled(
    bodies: &[Body],
    interfaces: &[Interface],
    options: &SolveOptions,
) -> Result<Solution, ProblemError> {
    check_input(bodies, interfaces)?;
    check_couplings(interfaces)?;
    let mut seconds = Timings::default();
    // Under mpirun, glued bodies are assembled by the ranks (`partition`):
    // K is not formed here.
    let over_ranks = matches!(options.solver, Solver::Petsc(_))
        && crate::petsc::petsc_ranks() > 1
        && interfaces.iter().all(|f| f.kind == Coupling::Glue);
    let mut system = assemble_system(bodies, interfaces, !over_ranks, &mut seconds)?;
    let clock = Instant::now();
    let constraints = Constraints::new(interfaces, &system.mortars, &system.offsets, &system.dirichlet);
    seconds.setup += clock.elapsed().as_secs_f64();
    let used = |b: &Body| b.mesh.used_points().into_iter().filter(|&u| u).count();
    let (dofs, n_constraints) = (bodies.iter().map(|b| 3 * used(b)).sum(), constraints.rows.len());

    let mut steps = match interfaces.iter().any(|f| f.kind == Coupling::Contact) {
        true => Some(solve_contact(bodies, interfaces, options, &mut system, &constraints, &mut seconds)?),
        false => None,
    };
    let (u, lambda, method, iterations, residual, contact, petsc) = match &mut steps {
        Some(s) => {
            let report = ContactReport {
                contact_points: s.points.len(),
                active: s.active.iter().filter(|&&on| on).count(),
                steps: s.steps.clone(),
                kkt: s.kkt,
            };
            let (u, lambda) = (std::mem::take(&mut s.u), std::mem::take(&mut s.lambda));
            (u, lambda, s.method, s.steps.len(), s.kkt.max(), Some(report), s.petsc.take())
        }
        None => {
            let g =
                solve_glued(bodies, &mut system, &constraints, (options.solver, over_ranks), &mut seconds)?;
            (g.u, g.lambda, g.method, g.iterations, g.residual, None, g.petsc)
        }
    };
    let offsets = &system.offsets;
    let displacement: Vec<Vec<f64>> =
        (0..bodies.len()).map(|b| u[offsets[b]..offsets[b + 1]].to_vec()).collect();
    for (body, u) in displacement.iter().enumerate() {
        if let Some(dof) = u.iter().position(|v| !v.is_finite()) {
            return Err(ProblemError::NonFiniteSolution { body, dof });
        }
    }

    let clock = Instant::now();
    let mut out: Vec<InterfaceSolution> = system
        .mortars
        .into_iter()
        .zip(interfaces)
        .map(|(mortar, f)| InterfaceSolution::new(f.kind, mortar, f.slave_surface.n_points()))
        .collect();
    add_tractions(&mut out, &constraints, &lambda);
    if let Some(steps) = &steps {
        add_contact_fields(&mut out, steps);
    }
    for (s, f) in out.iter_mut().zip(interfaces) {
        normal_parts(s, &seam::nodal_normals(f.slave_surface));
    }
    let stresses = bodies
        .par_iter()
        .zip(&displacement)
        .enumerate()
        .map(|(b, (body, u))| {
            recover_stresses(body.mesh, &body.material, u)
                .map_err(|source| ProblemError::Assembly { body: b, source })
        })
        .collect::<Result<Vec<_>, _>>()?;
    seconds.stresses = clock.elapsed().as_secs_f64();
    let report =
        Report { dofs, constraints: n_constraints, method, iterations, residual, contact, petsc, seconds };
    Ok(Solution { displacement, stresses, interfaces: out, report })
}

/// The normal (the nodal normal where no contact constraint set one) and the
/// normal and tangential parts of the traction.
fn normal_parts(s: &mut InterfaceSolution, nodal: &[Point3]) {
    let contact = s.contact.as_ref().map(|c| &c.contact);
    for p in 0..s.traction.len() {
        if !contact.is_some_and(|c| c[p]) {
            s.normal[p] = nodal[p];
        }
        let (t, n) = (s.traction[p], s.normal[p]);
        let tn = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
        s.normal_traction[p] = tn;
        s.tangential_traction[p] = std::array::from_fn(|k| t[k] - tn * n[k]);
    }
}
