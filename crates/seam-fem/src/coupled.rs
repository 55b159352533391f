//! One solve for every multi-body problem — glued interfaces, contact
//! interfaces, or both — and one [`Solution`].
//!
//! [`solve_coupled`] takes the solver's view (loads as vectors, [`Body`],
//! [`Interface`]); [`crate::problem::solve`] the named [`crate::Problem`] of a
//! case file or an example. Glue only: the glued system ([`crate::glue`]).
//! With contact: the active-set method ([`crate::contact`]) with the glued
//! interfaces eliminated or as saddle-point rows.

use crate::backend::Solver;
use crate::constraints::Constraints;
use crate::contact::friction::{solve_frictional, FrictionState};
use crate::contact::{add_contact_fields, check_couplings, solve_contact};
use crate::glue::{add_tractions, solve_glued};
use crate::multibody::{assemble_system, check_input, Body, Coupling, Interface, ProblemError, Timings};
use crate::solution::{ContactReport, InterfaceSolution, Report, Solution, SolveOptions};
use crate::stress::recover_stresses;
use rayon::prelude::*;
use seam::Point3;
use std::time::Instant;

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
    solve_coupled_from(bodies, interfaces, options, &mut FrictionState::default())
}

/// [`solve_coupled`] as one load step of a history: with friction, from the
/// state the step before left in `state`, which is updated
/// ([`crate::contact::friction`]).
pub(crate) fn solve_coupled_from(
    bodies: &[Body],
    interfaces: &[Interface],
    options: &SolveOptions,
    state: &mut FrictionState,
) -> Result<Solution, ProblemError> {
    check_input(bodies, interfaces)?;
    check_couplings(interfaces)?;
    let mut seconds = Timings::default();
    // Under mpirun, glued bodies are assembled by the ranks (`partition`):
    // K is not formed here.
    let over_ranks = matches!(options.solver, Solver::Petsc(_))
        && crate::petsc::petsc_ranks() > 1
        && interfaces.iter().all(|f| f.kind == Coupling::Glue);
    let mut system = assemble_system(bodies, interfaces, (!over_ranks, options.operators), &mut seconds)?;
    let clock = Instant::now();
    let constraints =
        Constraints::new((interfaces, bodies), &system.mortars, &system.offsets, &system.dirichlet);
    seconds.setup += clock.elapsed().as_secs_f64();
    let used = |b: &Body| b.mesh.used_points().into_iter().filter(|&u| u).count();
    let (dofs, n_constraints) = (bodies.iter().map(|b| 3 * used(b)).sum(), constraints.rows.len());

    let frictional = interfaces.iter().any(|f| f.kind == Coupling::Contact && f.friction > 0.0);
    let mut friction = None;
    let mut steps = match interfaces.iter().any(|f| f.kind == Coupling::Contact) {
        true if frictional => {
            let solver = (options.solver, options.max_active_set_steps);
            let (steps, f) =
                solve_frictional(bodies, interfaces, solver, &mut system, &constraints, state, &mut seconds)?;
            friction = Some(f);
            Some(steps)
        }
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
    let out = interface_solutions(system.mortars, interfaces, (&constraints, &lambda), |out| {
        if let Some(steps) = &steps {
            add_contact_fields(out, steps, friction.as_ref());
        }
    });
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
    let report = Report {
        dofs,
        constraints: n_constraints,
        method,
        iterations,
        residual,
        contact,
        petsc,
        newton: None,
        seconds,
    };
    Ok(Solution { displacement, stresses, interfaces: out, report })
}

/// The solutions of `interfaces` with their `mortars`: the glued tractions
/// of the multipliers λ of `constraints`, then what `contact` adds, then
/// the normal and tangential parts.
pub(crate) fn interface_solutions(
    mortars: Vec<seam::Mortar>,
    interfaces: &[Interface],
    (constraints, lambda): (&Constraints, &[f64]),
    contact: impl FnOnce(&mut [InterfaceSolution]),
) -> Vec<InterfaceSolution> {
    let mut out: Vec<InterfaceSolution> = mortars
        .into_iter()
        .zip(interfaces)
        .map(|(mortar, f)| InterfaceSolution::new(f.kind, mortar, f.slave_surface.n_points()))
        .collect();
    add_tractions(&mut out, constraints, lambda);
    contact(&mut out);
    for (s, f) in out.iter_mut().zip(interfaces) {
        normal_parts(s, &seam::nodal_normals(f.slave_surface));
    }
    out
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
