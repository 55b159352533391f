//! The multi-body problem in finite deformation: hyperelastic bodies
//! ([`crate::hyperelastic`]), total Lagrangian, glued in the reference
//! configuration and in contact (with or without friction) on the current
//! one (the private `contact` module).
//!
//! Glue ties the meshes as 4C and MOOSE do in finite deformation: D and B
//! are assembled once on the undeformed interfaces and the constraint
//! C u = 0 stays linear, so it is eliminated as in small strain,
//! u = P y with P = [I; −C_S⁻¹C_R] (dual or lumped multipliers: C_S
//! diagonal). Each load step is then Newton's method on y
//! ([`crate::hyperelastic`]'s predictor and line search) for
//! Pᵀ (f − f_int(P y)) = 0 with the tangent Pᵀ K(u) P, from the last step's
//! displacements. The multipliers are read off the slave rows,
//! λ = C_S⁻ᵀ (f − f_int(u))_S: the interface traction per reference area.
//! With contact interfaces each Newton step is that module's semi-smooth
//! step on y and the contact multipliers instead.

mod contact;

use crate::constraints::{Constraints, NONE};
use crate::hyperelastic::{
    cauchy_stresses, internal_force, newton, tangent, Constrained, FiniteError, Hyperelastic, Linear,
    Nonlinear,
};
use crate::multibody::{assemble_system, check_input, Body, Coupling, Interface, ProblemError, Timings};
use crate::petsc::PetscSummary;
use crate::solution::{ContactReport, Report, Solution, SolveOptions};
use crate::Solver;
use seam::{CsrMatrix, VolumeMesh};
use std::time::Instant;

/// What finite deformation carries from one load step to the next.
#[derive(Clone, Debug, Default)]
pub(crate) struct FiniteState {
    /// The displacements (all bodies' dofs in turn; empty before the first
    /// step).
    pub(crate) u: Vec<f64>,
    /// The contact multipliers, slips and last evaluations.
    contact: contact::History,
    /// The pseudo-time of `u` (0 at rest) and the rate Δu/Δt of the last
    /// load step (empty before it): contact's Newton iteration starts from
    /// the extrapolation u + (t − time) rate.
    time: f64,
    rate: Vec<f64>,
}

/// The bodies side by side, each of its law, dofs at `offsets`.
struct Bodies<'a> {
    meshes: Vec<&'a VolumeMesh>,
    laws: &'a [Hyperelastic],
    offsets: &'a [usize],
}

impl Bodies<'_> {
    /// Runs `each(body, mesh, law, u of that body)` and names the body in a
    /// failure.
    fn each<T>(
        &self,
        u: &[f64],
        each: impl Fn(&VolumeMesh, &Hyperelastic, &[f64]) -> Result<T, FiniteError>,
    ) -> Result<Vec<T>, FiniteError> {
        (0..self.meshes.len())
            .map(|b| {
                each(self.meshes[b], &self.laws[b], &u[self.offsets[b]..self.offsets[b + 1]])
                    .map_err(|e| FiniteError::Body { body: b, source: Box::new(e) })
            })
            .collect()
    }
}

impl Nonlinear for Bodies<'_> {
    fn len(&self) -> usize {
        *self.offsets.last().expect("the leading zero")
    }

    fn force(&self, u: &[f64]) -> Result<Vec<f64>, FiniteError> {
        Ok(self.each(u, internal_force)?.concat())
    }

    fn tangent(&self, u: &[f64]) -> Result<CsrMatrix, FiniteError> {
        let blocks = self.each(u, tangent)?;
        let n = self.len();
        let mut k = CsrMatrix::zeros(0, n);
        for (block, &offset) in blocks.iter().zip(self.offsets) {
            for i in 0..block.nrows {
                let (cols, vals) = block.row(i);
                k.indices.extend(cols.iter().map(|&j| offset + j));
                k.values.extend_from_slice(vals);
                k.indptr.push(k.indices.len());
                k.nrows += 1;
            }
        }
        Ok(k)
    }
}

/// P of u = P y (n × n in the numbering of all dofs; eliminated dofs'
/// columns empty): each eliminated dof d of row r, u_d = −Σ_{j≠d} c_rj u_j /
/// c_rd, with the eliminated u_j substituted in turn; `None` when a row
/// couples two eliminated dofs both ways (standard multipliers: C_S not
/// triangular).
fn prolongation(constraints: &Constraints) -> Option<CsrMatrix> {
    let n = constraints.row_of.len();
    let mut rows: Vec<Option<Vec<(usize, f64)>>> = vec![None; n];
    let mut visiting = vec![false; n];
    fn expand(
        d: usize,
        c: &Constraints,
        rows: &mut Vec<Option<Vec<(usize, f64)>>>,
        visiting: &mut Vec<bool>,
    ) -> Option<()> {
        if rows[d].is_some() {
            return Some(());
        }
        let r = c.row_of[d];
        if r == NONE {
            rows[d] = Some(vec![(d, 1.0)]);
            return Some(());
        }
        if std::mem::replace(&mut visiting[d], true) {
            return None; // a cycle
        }
        let (cols, vals) = c.c.row(r);
        let pivot = c.c.get(r, d);
        let mut entries = Vec::new();
        for (&j, &v) in cols.iter().zip(vals).filter(|(&j, _)| j != d) {
            expand(j, c, rows, visiting)?;
            let row = rows[j].as_ref().expect("expanded");
            entries.extend(row.iter().map(|&(k, w)| (k, -v / pivot * w)));
        }
        rows[d] = Some(crate::contact::merged(&mut entries));
        visiting[d] = false;
        Some(())
    }
    for d in 0..n {
        expand(d, constraints, &mut rows, &mut visiting)?;
    }
    let mut p = CsrMatrix::zeros(0, n);
    for row in rows.into_iter().flatten() {
        p.indices.extend(row.iter().map(|e| e.0));
        p.values.extend(row.iter().map(|e| e.1));
        p.indptr.push(p.indices.len());
        p.nrows += 1;
    }
    Some(p)
}

/// The multipliers λ of C_Sᵀ λ = r_S, r = f − f_int(u) (the rows'
/// eliminated dofs form a triangular C_S, [`prolongation`]): each row's λ
/// once the other rows that hold its dof are known.
fn multipliers(constraints: &Constraints, f: &[f64], f_int: &[f64]) -> Vec<f64> {
    let c = &constraints.c;
    let ct = c.transpose();
    let m = constraints.rows.len();
    let mut lambda = vec![f64::NAN; m];
    // Row r's equation is column d_r of Cᵀ: Σ_q c_q,d λ_q = r_d; solve the
    // rows whose other terms are known, repeatedly (a triangular system).
    let mut left = m;
    while left > 0 {
        let before = left;
        for (r, row) in constraints.rows.iter().enumerate() {
            if !lambda[r].is_nan() {
                continue;
            }
            let (qs, vs) = ct.row(row.dof);
            let known = qs.iter().all(|&q| q == r || !lambda[q].is_nan());
            if known {
                let rest: f64 =
                    qs.iter().zip(vs).filter(|(&q, _)| q != r).map(|(&q, &v)| v * lambda[q]).sum();
                lambda[r] = (f[row.dof] - f_int[row.dof] - rest) / c.get(r, row.dof);
                left -= 1;
            }
        }
        assert!(left < before, "C_S is triangular (prolongation)");
    }
    lambda
}

/// Solves hyperelastic `bodies` (`laws[b]` the law of body b), glued and in
/// contact by `interfaces`, in one load step from rest: the solver's view,
/// as [`crate::solve_coupled`] is for linear bodies (a [`crate::Problem`]
/// with load steps: [`crate::solve_steps`]).
///
/// # Errors
/// As [`crate::solve_steps`] for hyperelastic bodies.
pub fn solve_finite(
    bodies: &[Body],
    laws: &[Hyperelastic],
    interfaces: &[Interface],
    options: &SolveOptions,
) -> Result<Solution, ProblemError> {
    solve_finite_from(bodies, laws, interfaces, options, (1.0, &mut FiniteState::default()))
}

/// Solves the hyperelastic `bodies` (`laws[b]` the law of body b), glued
/// and in contact, at pseudo-time `t` from the last step's `state`
/// (displacements, contact history; empty: at rest), which it replaces by
/// the solution's (module doc).
///
/// # Errors
/// [`ProblemError::Finite`] for what this path does not solve (friction,
/// standard multipliers on a glued interface, other solvers than the
/// direct one) and for Newton's failures; the assembly's errors.
pub(crate) fn solve_finite_from(
    bodies: &[Body],
    laws: &[Hyperelastic],
    interfaces: &[Interface],
    options: &SolveOptions,
    (t, state): (f64, &mut FiniteState),
) -> Result<Solution, ProblemError> {
    check_input(bodies, interfaces)?;
    crate::contact::check_couplings(interfaces)?;
    if matches!(options.solver, Solver::Pcg(_)) {
        let what = "hyperelastic bodies are solved with the direct solver or PETSc, not PCG (the contact \
                    steps are not symmetric, the tangent may be indefinite)"
            .into();
        return Err(ProblemError::Finite { what });
    }
    let mut seconds = Timings::default();
    let system = assemble_system(bodies, interfaces, (false, options.operators), &mut seconds)?;
    let clock = Instant::now();
    let constraints =
        Constraints::new((interfaces, bodies), &system.mortars, &system.offsets, &system.dirichlet);
    let elimination = match constraints.rows.is_empty() {
        true => None,
        false => match prolongation(&constraints) {
            Some(p) => Some(p),
            None => {
                let interface = constraints.rows[0].interface;
                let what = format!(
                    "interface {interface}: glue in finite deformation needs dual or lumped multipliers (standard \
                     ones couple the slave points; set multiplier = \"dual\")"
                );
                return Err(ProblemError::Finite { what });
            }
        },
    };
    let n = *system.offsets.last().expect("the leading zero");
    if state.u.len() != n {
        state.u = vec![0.0; n];
    }
    let before = state.u.clone();
    let guess = (options.newton.extrapolate && state.rate.len() == n && t > state.time)
        .then(|| before.iter().zip(&state.rate).map(|(u, r)| u + (t - state.time) * r).collect::<Vec<f64>>());
    let u = &mut state.u;
    let mut summary = PetscSummary::default();
    let mut linear = Linear {
        solver: options.solver,
        modes: match options.solver {
            Solver::Petsc(_) => crate::rigid_body_modes(&system.points).to_vec(),
            _ => Vec::new(),
        },
        summary: &mut summary,
    };
    let nonlinear =
        Bodies { meshes: bodies.iter().map(|b| b.mesh).collect(), laws, offsets: &system.offsets };
    let contact_interfaces: Vec<(usize, &Interface)> =
        interfaces.iter().enumerate().filter(|(_, f)| f.kind == Coupling::Contact).collect();
    let points: Vec<&[seam::Point3]> = bodies.iter().map(|b| b.mesh.points()).collect();
    let young = bodies.iter().map(|b| b.material.young()).fold(0.0, f64::max);
    let contact = contact::Contact::new(&contact_interfaces, &system.offsets, &points, young);
    state.contact = contact.history(std::mem::take(&mut state.contact))?;
    seconds.setup += clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let (method, newton_report, f_int, solved) = match contact.is_empty() {
        true => {
            // The saddle point where the elimination would fill in (as for small strain).
            let how = match &elimination {
                None => Constrained::Free,
                Some(p) => {
                    let k = nonlinear.tangent(u).map_err(|source| ProblemError::Newton { source })?;
                    match constraints.elimination_fills_in(&k) {
                        true => Constrained::Saddle(p, &constraints),
                        false => Constrained::Eliminated(p),
                    }
                }
            };
            let method = match how {
                _ if matches!(options.solver, Solver::Petsc(_)) => "Newton with line search, PETSc",
                Constrained::Saddle(..) => "Newton with line search, saddle-point LDLᵀ",
                _ => "Newton with line search, sparse Cholesky (sparse LU where the tangent is indefinite)",
            };
            let solved =
                newton(&nonlinear, how, (&system.f, &system.dirichlet), u, (&options.newton, &mut linear));
            let (next, report) = solved.map_err(|source| ProblemError::Newton { source })?;
            *u = next;
            let f_int = nonlinear.force(u).map_err(|source| ProblemError::Newton { source })?;
            (method, report, f_int, None)
        }
        false => {
            let held = {
                let mut held = vec![false; n];
                system.dirichlet.iter().for_each(|(d, _)| held[d] = true);
                held
            };
            let newton =
                contact::Newton { bodies: &nonlinear, load: &system.f, p: elimination.as_ref(), held };
            let solved = contact.solve(
                &newton,
                &system.dirichlet,
                (u, &mut state.contact),
                (&options.newton, guess),
                &mut linear,
            )?;
            let method = match options.solver {
                Solver::Petsc(_) => "semi-smooth Newton on the current configuration, PETSc",
                _ => "semi-smooth Newton on the current configuration, sparse LU",
            };
            (method, solved.report.clone(), solved.internal.clone(), Some(solved))
        }
    };
    seconds.solve = clock.elapsed().as_secs_f64();
    if t > state.time {
        state.rate = state.u.iter().zip(&before).map(|(a, b)| (a - b) / (t - state.time)).collect();
        state.time = t;
    }
    let u = &state.u;

    // λ from the slave rows: C_Sᵀ λ = (f − f_int(u))_S, by back
    // substitution (the rows' order: a row's other eliminated dofs are
    // eliminated by later rows, or it is a tie).
    let lambda = multipliers(&constraints, &system.f, &f_int);
    let offsets = &system.offsets;
    let displacement: Vec<Vec<f64>> =
        (0..bodies.len()).map(|b| u[offsets[b]..offsets[b + 1]].to_vec()).collect();
    let clock = Instant::now();
    let mut fields = Ok(());
    let out =
        crate::coupled::interface_solutions(system.mortars, interfaces, (&constraints, &lambda), |out| {
            if let Some(solved) = &solved {
                fields = contact.fields(solved, &state.contact, out);
            }
        });
    fields?;
    let stresses = (0..bodies.len())
        .map(|b| {
            cauchy_stresses(bodies[b].mesh, &laws[b], &displacement[b]).map_err(|e| ProblemError::Newton {
                source: FiniteError::Body { body: b, source: Box::new(e) },
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    seconds.stresses = clock.elapsed().as_secs_f64();
    let used = |b: &Body| b.mesh.used_points().into_iter().filter(|&u| u).count();
    let contact_report = solved.as_ref().map(|s| {
        let points = out.iter().filter_map(|o| o.contact.as_ref());
        ContactReport {
            contact_points: points.clone().map(|c| c.contact.iter().filter(|&&c| c).count()).sum(),
            active: points.map(|c| c.active.iter().filter(|&&a| a).count()).sum(),
            steps: Vec::new(),
            kkt: s.kkt,
        }
    });
    let report = Report {
        dofs: bodies.iter().map(|b| 3 * used(b)).sum(),
        constraints: constraints.rows.len(),
        method,
        iterations: newton_report.residuals.len(),
        residual: newton_report.residuals.last().copied().unwrap_or(0.0),
        contact: contact_report,
        petsc: matches!(options.solver, Solver::Petsc(_)).then_some(summary),
        newton: Some(newton_report),
        seconds,
    };
    Ok(Solution { displacement, stresses, interfaces: out, report })
}
