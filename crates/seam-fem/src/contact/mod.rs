//! Frictionless two-body contact with the mortar operator (the paper's second
//! application), solved by a primal-dual active set method: the iteration
//! and its linear solves here; the contact points, their nodal frames and the
//! changes of variables in `frames`.
//!
//! # The discrete problem
//! Each contact interface pairs a master and a slave surface of two bodies. Its
//! mortar matrices have a diagonal D (lumped or dual multipliers), so
//! T = D⁻¹B acts node by node (on second-order slave faces in the transformed
//! unknowns, below). With n_p the slave's outward unit nodal normal,
//! the non-penetration condition at a slave point p is (paper §2, a variational
//! inequality with "ordinary inequality constraints")
//!
//! ```text
//! w_p := n_p·(u_s − T u_m)_p  ≤  g_p := n_p·(T x_m − x_s)_p ,
//! ```
//!
//! the weighted initial gap g_p (negative for an initial overlap). The weighted
//! row d_p w_p ≤ d_p g_p has the multiplier d_p λ_p, λ_p ≥ 0 the contact
//! pressure; the master pushes the slave with −λ_p n_p per area. Only the normal
//! direction is coupled.
//!
//! # Constraints as boxes
//! Per contact point the Cartesian dofs of u_s,p are replaced by (w_p, v₁, v₂)
//! in the nodal frame (n_p, t₁, t₂) (the nodal rotation of Krause & Sander):
//!
//! ```text
//! u_s,p = n_p (w_p + n_p·(T u_m)_p) + t₁ v₁ + t₂ v₂ ,      u = P x ,
//! ```
//!
//! so the constraints become boxes w_p ≤ g_p and the energy
//! ½ xᵀ(PᵀKP)x − (Pᵀf)ᵀx keeps one fixed sparsity pattern. Components
//! prescribed at a contact point must be tangential (a symmetry plane): the
//! normal is projected onto their complement and t₁, t₂ include those axes.
//!
//! # Second-order slave faces (Popp, Wohlmuth, Gee & Wall 2012)
//! Dual multipliers on Tri6, Quad8 and Quad9 slave faces live in the
//! transformed basis λ̃ = Q λ ([`seam::Mortar::basis`]; corner: λ_c + α Σ λ_e over
//! its edge nodes, edge node: (1 − 2α) λ_e, Quad9 centre unchanged; α is
//! [`seam::BASIS_ALPHA`], or [`seam::TRI6_ALPHA`] on surfaces of Tri6 faces; contact
//! interfaces are assembled with [`seam::BasisTransformation::All`], so Quad9
//! slave surfaces are transformed too, unlike glued ones), in which
//! D is diagonal and positive and row p of B belongs to the dual function ψ_p,
//! biorthogonal to λ̃_p. Writing the slave displacement in that basis,
//! u_s = Σ_r λ_r u_r = Σ_p λ̃_p ũ_p with u_s = Qᵀ ũ per component (corner
//! u_c = ũ_c, edge node u_e = (1 − 2α) ũ_e + α (ũ_c₁ + ũ_c₂)), the weak
//! non-penetration row ∫ψ_p n·(u_s − u_m) is D_pp ũ_p − (B u_m)_p: diagonal in
//! ũ. So the problem is solved in u = P_b ũ (P_b = Qᵀ on the slave points of
//! such interfaces, the identity elsewhere): K̃ = P_bᵀ K P_b, f̃ = P_bᵀ f, glued
//! constraints C̃ = C P_b (Q mixes the nodes of one face, so the sparsity
//! pattern does not change), and everything above applies to ũ as to a
//! first-order u: one contact point per transformed node p, its frame at
//! p's nodal normal n_p ([`seam::nodal_normals`]: the area vectors of the corner
//! polygons of the faces around p, mid-edge and centre nodes included; exact
//! on flat surfaces, an approximation of the normal at p on curved ones),
//! t_row = row p of D⁻¹B and the gap
//! g_p = n_p·((D⁻¹B x_m)_p − x̃_s,p) with x̃_s = Q⁻ᵀ x_s. After the solve
//! u = P_b ũ. The reported pressure λ_p = μ_p / D_pp is then the coefficient
//! of ψ_p in the multiplier λ_h = Σ_p λ_p ψ_p (as in Popp et al.): for a
//! uniform pressure every λ_p equals it (Σ_p ψ_p = 1), otherwise it is a
//! λ̃_p-weighted mean of the pressure around p, not a nodal value. (The L2
//! projection of λ_h onto the slave's Lagrange space, the natural nodal
//! value, reads Hertz's p₀ worse on every tetrahedral mesh: measured in the
//! tests' `contact_hertz_second_order.rs`.)
//! Prescribed slave components carry over to ũ at corners (ũ_c = u_c) and at
//! an edge node whose two corners have the component prescribed too,
//! ũ_e = (u_e − α (u_c₁ + u_c₂)) / (1 − 2α); any other prescribed slave
//! component is refused. Lumped multipliers on Quad9 faces (positive row
//! sums) need no transformation.
//!
//! # Primal-dual active set (Hüeber & Wohlmuth)
//! Starting from A₀ = {p : g_p ≤ 0} and the closest points of each interface
//! (touching, overlapping, or nearest points: a force-controlled body is held
//! from the start), each
//! step solves the linear problem with w_p = g_p on A_k and no constraint
//! elsewhere, computes μ_p = (Pᵀf − PᵀKP x)_{w_p} (= d_p λ_p), and sets
//!
//! ```text
//! A_{k+1} = {p : μ_p + c (w_p − g_p) > 0} ,
//! ```
//!
//! a semismooth Newton step for the nonlinear complementarity function. When
//! A_{k+1} = A_k the iterate satisfies the KKT conditions exactly (up to the
//! linear solve): μ > 0 on A, w ≤ g off A. The iteration is capped
//! ([`SolveOptions::max_active_set_steps`]).
//!
//! # With glued interfaces
//! Glued interfaces ([`Coupling::Glue`]) in the same problem are eliminated
//! first, u = P_g y with P_g = [I; −C_S⁻¹C_R] as in [`crate::glue`] (dual or
//! lumped multipliers, so that C_S is diagonal), keeping the global numbering
//! (eliminated dofs become empty rows); the contact rotation then acts on y,
//! with n_p·(T u_m)_p expanded through P_g where a master dof is a glued
//! slave dof. The glued multipliers are recovered from the slave rows,
//! λ = C_S⁻ᵀ (f − K u − C_cᵀμ)_S. A point that is a slave point of both a
//! glued and a contact interface is refused before any work.
//!
//! # Linear solves
//! - [`Solver::Direct`]: the system is condensed on the contact normals W
//!   once (one sparse Cholesky factorisation of the other unknowns, |W|
//!   solves for the dense Schur complement S on W); each step is then a dense
//!   Cholesky solve on the inactive points, and one last sparse solve
//!   recovers u. Suits |W| up to a few thousand points.
//! - [`Solver::Pcg`]: every step solves the whole system by PCG, warm-started
//!   from the previous step.
//!
//! Iterative solvers (PCG, PETSc) solve the steps to a relative 10⁻³ while
//! the active set changes, and to rtol from the first step whose loose
//! solution leaves it unchanged (`active_set_method`;
//! [`ActiveSetStep::full_tolerance`]): about a third of the iterations of
//! exact steps (Hertz at 96k unknowns with GAMG: 1 349 → 476).

mod frames;
pub(crate) use frames::{frame, merged};
pub(crate) mod friction;

use crate::backend::Solver;
use crate::constraints::{free_dofs, triple_product};
use crate::constraints::{Constraints, Elimination, Row};
use crate::multibody::{bodies_stiffness, Body, Coupling, Interface, ProblemError, System, Timings};
use crate::petsc::{KeptKsp, PetscSummary, Split};
use crate::solution::{ActiveSetStep, ContactFields, InterfaceSolution, Kkt, SolveOptions};
use crate::solve::{CholeskyAnalysis, CholeskyFactor, DirectOptions, Dirichlet, SolveError};
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use seam::{CsrMatrix, Multiplier, Point3};
use std::borrow::Cow;
use std::time::Instant;

use frames::{contact_points, normal_row, rotated_dirichlet, rotation, ContactPoint, SlaveBasis};

/// Solves the frictionless contact problem (module doc): `system` with the
/// constraints of its glued interfaces and the contact interfaces, after
/// [`check_couplings`]; with second-order slave faces in the transformed
/// unknowns ũ (module doc; `system`'s mortars are borrowed for that solve and
/// put back).
///
/// # Errors
/// [`ProblemError`] for a failed assembly, a singular step (a body held by
/// nothing), no convergence within `max_steps` active-set steps, or a
/// prescribed slave component that does not carry over to ũ.
pub(crate) fn solve_contact(
    bodies: &[Body],
    interfaces: &[Interface],
    options: &SolveOptions,
    system: &mut System,
    constraints: &Constraints,
    seconds: &mut Timings,
) -> Result<ContactSolve, ProblemError> {
    let clock = Instant::now();
    let basis = SlaveBasis::new(bodies, interfaces, system)?;
    seconds.setup += clock.elapsed().as_secs_f64();
    let Some(basis) = basis else {
        return active_set_steps(
            bodies,
            interfaces,
            options,
            (system, &|| bodies_stiffness(bodies)),
            constraints,
            seconds,
        );
    };
    // The same solve in ũ (module doc): K̃ = P_bᵀ K P_b, f̃ = P_bᵀ f, C̃ = C P_b;
    // K itself is not needed any more (K̃ is formed again from the bodies).
    let clock = Instant::now();
    let reform = || Ok(triple_product(&basis.p, &bodies_stiffness(bodies)?));
    let (mut transformed, glued) = basis.transform(system, constraints);
    seconds.setup += clock.elapsed().as_secs_f64();
    let steps = active_set_steps(bodies, interfaces, options, (&mut transformed, &reform), &glued, seconds);
    (system.mortars, system.points) = (transformed.mortars, transformed.points);
    let mut steps = steps?;
    steps.u = basis.p.mul_vec(&steps.u, 1);
    Ok(steps)
}

/// The active set in the unknowns of `system`: on the rotated system when the
/// glued interfaces eliminate node by node, else on saddle points.
fn active_set_steps(
    bodies: &[Body],
    interfaces: &[Interface],
    options: &SolveOptions,
    (system, reform): (&mut System, &dyn Fn() -> Result<CsrMatrix, ProblemError>),
    constraints: &Constraints,
    seconds: &mut Timings,
) -> Result<ContactSolve, ProblemError> {
    let eliminated = constraints.rows.is_empty() || constraints.eliminated_block_is_diagonal();
    if eliminated {
        rotated_steps(bodies, interfaces, options, (system, reform), constraints, seconds)
    } else {
        saddle_steps(bodies, interfaces, options, system, constraints, seconds)
    }
}

/// What an active-set solve found.
pub(crate) struct ContactSolve {
    /// Displacements of all bodies.
    pub u: Vec<f64>,
    /// Per contact point: w_p = n_p·(u_s − T u_m)_p.
    pub w: Vec<f64>,
    /// Per contact point: μ_p = d_p λ_p (0 off the active set).
    pub mu: Vec<f64>,
    /// Per contact point: in the final active set.
    pub active: Vec<bool>,
    pub steps: Vec<ActiveSetStep>,
    /// The glued interfaces' multipliers, one per row of their constraints.
    pub lambda: Vec<f64>,
    pub kkt: Kkt,
    pub method: &'static str,
    pub points: Vec<ContactPoint>,
    /// The PETSc solves, with [`Solver::Petsc`].
    pub petsc: Option<PetscSummary>,
}

/// The singular-step error.
fn singular(step: usize, active: usize) -> ProblemError {
    ProblemError::SingularStep { step, active }
}

/// The active set on the system rotated into nodal frames, glued interfaces
/// (dual, lumped) eliminated first (module doc). The iterative solvers run
/// their steps without `system`'s K, which `reform` forms again for the KKT
/// check and the glued multipliers: K would otherwise sit beside the
/// rotated system and the solver's own matrix (PETSc's, and its multigrid
/// hierarchy) through every step.
fn rotated_steps(
    bodies: &[Body],
    interfaces: &[Interface],
    options: &SolveOptions,
    (system, reform): (&mut System, &dyn Fn() -> Result<CsrMatrix, ProblemError>),
    constraints: &Constraints,
    seconds: &mut Timings,
) -> Result<ContactSolve, ProblemError> {
    let (f, dirichlet, offsets) = (&system.f, &system.dirichlet, &system.offsets);
    let clock = Instant::now();
    let glued =
        if constraints.rows.is_empty() { None } else { Some(Elimination::new(constraints, &system.k, f)?) };
    let (k, f) = match &glued {
        Some(g) => (&g.k, &g.f[..]),
        None => (&system.k, &f[..]),
    };
    let n = k.nrows;
    let p_g = glued.as_ref().map(|g| &g.p);
    let points = contact_points(bodies, interfaces, &system.mortars, offsets, dirichlet, p_g)?;
    let p = rotation(n, &points, None, None);
    let a = triple_product(&p, k);
    let b = p.transpose_mul_vec(f, 1);
    let prescribed = rotated_dirichlet(n, dirichlet, &points);
    seconds.setup += clock.elapsed().as_secs_f64();

    let scale = length_scale(bodies);
    let active = initial_active_set(&points, interfaces.len(), 1e-9 * scale);
    let mut petsc = None;
    let (x, active, mu, steps) = match options.solver {
        Solver::Direct => {
            let clock = Instant::now();
            let mut tied = prescribed.clone();
            for c in &points {
                tied.fix_dof(c.first_dof, 0.0);
            }
            let analysis = CholeskyAnalysis::new(&a, &tied, &DirectOptions::default())?;
            let normals: Vec<usize> = points.iter().map(|c| c.first_dof).collect();
            let condensed =
                Condensed::new(&analysis, &a, &b, &tied, (&normals, None)).map_err(|e| match e {
                    SolveError::Singular => ProblemError::Unsupported { points: points.len() },
                    e => ProblemError::Solve(e),
                })?;
            seconds.factorization += clock.elapsed().as_secs_f64();
            let clock = Instant::now();
            let (active, w, mu, steps) = active_set_method(
                &points,
                active,
                scale,
                (options.max_active_set_steps, false),
                |active, step, _| {
                    let n_active = active.iter().filter(|&&on| on).count();
                    let (w, mu) = condensed.step(&points, active).ok_or_else(|| singular(step, n_active))?;
                    Ok((w, mu, 0))
                },
            )?;
            seconds.solve += clock.elapsed().as_secs_f64();
            let clock = Instant::now();
            let x = condensed.expand(&a, &w);
            seconds.solve += clock.elapsed().as_secs_f64();
            (x, active, mu, steps)
        }
        Solver::Pcg(_) | Solver::Petsc(_) => {
            let clock = Instant::now();
            // K goes for the steps (formed again after them). PETSc's
            // near-nullspace: the rigid-body modes in the unknowns x
            // (u = P_g P x), zero at eliminated dofs and rotated into the
            // nodal frames at contact points.
            system.k = CsrMatrix::zeros(0, 0);
            let retained = glued.as_ref().map(|g| &g.retained[..]);
            let bodies = Some(&system.offsets[..]);
            let modes = options.solver.near_nullspace(&system.points, bodies, retained, Some(&p));
            let mut summary = PetscSummary::default();
            let mut ksp = KeptKsp::default();
            let mut previous: Option<Vec<f64>> = None;
            let (active, _, mu, steps) = active_set_method(
                &points,
                active,
                scale,
                (options.max_active_set_steps, true),
                |active, step, tight| {
                    let mut fixed = prescribed.clone();
                    for c in points.iter().zip(active).filter(|(_, &on)| on).map(|(c, _)| c) {
                        fixed.fix_dof(c.first_dof, c.gap);
                    }
                    let n_active = active.iter().filter(|&&on| on).count();
                    // Each step from the previous one's solution; PETSc's
                    // system kept over the steps and refreshed for each
                    // active set (KeptKsp).
                    let start = previous.as_deref();
                    let solved = match step_solver(options.solver, tight) {
                        Solver::Petsc(o) => {
                            ksp.solve((&a, &b, &fixed), (Split::None, &modes, true), &o, start, &mut summary)
                        }
                        solver => {
                            solver.solve_spd(Cow::Borrowed(&a), &b, &fixed, (start, &modes), &mut summary)
                        }
                    };
                    let (x, iterations) = solved.map_err(|e| match e {
                        SolveError::Singular => singular(step, n_active),
                        e => ProblemError::Solve(e),
                    })?;
                    let r = residual_at_normals(&a, &b, &x, &points);
                    let mu = r.iter().zip(active).map(|(&r, &on)| if on { r } else { 0.0 }).collect();
                    let w = points.iter().map(|c| x[c.first_dof]).collect();
                    previous = Some(x);
                    Ok((w, mu, iterations))
                },
            )?;
            seconds.factorization += clock.elapsed().as_secs_f64();
            petsc = matches!(options.solver, Solver::Petsc(_)).then_some(summary);
            (previous.expect("at least one step"), active, mu, steps)
        }
    };

    if system.k.nrows != system.f.len() {
        let clock = Instant::now();
        system.k = reform()?;
        seconds.assembly += clock.elapsed().as_secs_f64();
    }
    let clock = Instant::now();
    let (k, f) = match &glued {
        Some(g) => (&g.k, &g.f[..]),
        None => (&system.k, &system.f[..]),
    };
    let y = p.mul_vec(&x, 1);
    let kkt = kkt(k, f, &system.dirichlet, &points, (&y, &x), &mu);
    let u = match &glued {
        Some(g) => g.p.mul_vec(&y, 1),
        None => y,
    };
    let lambda = glued.as_ref().map_or(Vec::new(), |g| g.multipliers(constraints, system, &u, &points, &mu));
    let method = match options.solver {
        Solver::Direct => "sparse Cholesky, active set on the condensed contact normals",
        Solver::Pcg(_) => "PCG per active-set step",
        Solver::Petsc(_) => "PETSc KSP per active-set step",
    };
    let w = points.iter().map(|c| x[c.first_dof]).collect();
    seconds.solve += clock.elapsed().as_secs_f64();
    Ok(ContactSolve { u, w, mu, active, steps, lambda, kkt, method, points, petsc })
}

/// The active set with glued interfaces that do not eliminate node by node
/// (standard multipliers, crosspoints): each step solves the saddle point of
/// the glued rows and the active contact rows n_p·(u_s − T u_m)_p = g_p, by
/// sparse LDLᵀ ([`saddle_point`]) or by PCG on the system reduced by these
/// rows, matrix-free ([`matrix_free`]: each contact row eliminates the
/// component of u_s,p along which n_p is largest); μ_p is the multiplier of
/// p's row (the same d_p λ_p as in the rotated system),
/// w_p = n_p·(u_s − T u_m)_p.
fn saddle_steps(
    bodies: &[Body],
    interfaces: &[Interface],
    options: &SolveOptions,
    system: &System,
    constraints: &Constraints,
    seconds: &mut Timings,
) -> Result<ContactSolve, ProblemError> {
    let (k, f, dirichlet) = (&system.k, &system.f, &system.dirichlet);
    let clock = Instant::now();
    let points = contact_points(bodies, interfaces, &system.mortars, &system.offsets, dirichlet, None)?;
    seconds.setup += clock.elapsed().as_secs_f64();
    let scale = length_scale(bodies);
    let active = initial_active_set(&points, interfaces.len(), 1e-9 * scale);
    let n_glue = constraints.rows.len();
    let normal_motion = |u: &[f64]| -> Vec<f64> {
        points
            .iter()
            .map(|c| {
                let slave: f64 = (0..3).map(|k| c.frame[0][k] * u[c.first_dof + k]).sum();
                slave - c.a_row.iter().map(|&(j, a)| a * u[j]).sum::<f64>()
            })
            .collect()
    };
    let mut last: Option<(Vec<f64>, Vec<f64>)> = None;
    let mut summary = PetscSummary::default();
    let iterative = !matches!(options.solver, Solver::Direct);
    let modes = options.solver.near_nullspace(&system.points, None, None, None);
    let (active, w, mu, steps) = active_set_method(
        &points,
        active,
        scale,
        (options.max_active_set_steps, iterative),
        |active, step, tight| {
            let mut c = constraints.clone();
            for point in points.iter().zip(active).filter(|(_, &on)| on).map(|(p, _)| p) {
                let n = point.frame[0];
                let mut entries: Vec<(usize, f64)> = (0..3)
                    .map(|k| (point.first_dof + k, n[k]))
                    .chain(point.a_row.iter().map(|&(j, a)| (j, -a)))
                    .collect();
                entries.sort_unstable_by_key(|e| e.0);
                c.c.indices.extend(entries.iter().map(|e| e.0));
                c.c.values.extend(entries.iter().map(|e| e.1));
                c.c.indptr.push(c.c.indices.len());
                c.c.nrows += 1;
                let axis = (0..3).max_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs())).expect("three axes");
                let row = Row {
                    dof: point.first_dof + axis,
                    interface: point.interface,
                    point: point.point,
                    component: axis,
                };
                c.row_of[row.dof] = c.rows.len();
                c.rows.push(row);
                c.g.push(point.gap);
            }
            let n_active = c.rows.len() - n_glue;
            // From the previous step (PETSc): u, and the glued rows' λ (the
            // contact rows change with the active set).
            let start =
                last.as_ref().filter(|_| matches!(options.solver, Solver::Petsc(_))).map(|(u, lambda)| {
                    let mut nu = lambda.clone();
                    nu.resize(c.rows.len(), 0.0);
                    (u.clone(), nu)
                });
            let start = start.as_ref().map(|(u, nu)| (&u[..], &nu[..]));
            let solved = step_solver(options.solver, tight).solve_saddle(
                (k, f, dirichlet),
                &c,
                (start, &modes),
                seconds,
                &mut summary,
            );
            let (u, nu, _, iterations) = solved.map_err(|e| match e {
                ProblemError::Solve(SolveError::Singular) => singular(step, n_active),
                e => e,
            })?;
            let w = normal_motion(&u);
            let mut mu = vec![0.0; points.len()];
            let mut rows = nu[n_glue..].iter();
            for (m, _) in mu.iter_mut().zip(active).filter(|(_, &on)| on) {
                *m = *rows.next().expect("one multiplier per active point");
            }
            last = Some((u, nu[..n_glue].to_vec()));
            let linear_iterations = if matches!(options.solver, Solver::Direct) { 0 } else { iterations };
            Ok((w, mu, linear_iterations))
        },
    )?;
    let clock = Instant::now();
    let (u, lambda) = last.expect("at least one step");
    // KKT with the glued reactions C_gᵀλ moved to the load side.
    let reaction = constraints.c.transpose_mul_vec(&lambda, 1);
    let f_net: Vec<f64> = f.iter().zip(&reaction).map(|(f, r)| f - r).collect();
    let mut x = vec![0.0; k.nrows];
    for (c, &wp) in points.iter().zip(&w) {
        x[c.first_dof] = wp;
    }
    let kkt = kkt(k, &f_net, dirichlet, &points, (&u, &x), &mu);
    seconds.solve += clock.elapsed().as_secs_f64();
    Ok(ContactSolve {
        u,
        w,
        mu,
        active,
        steps,
        lambda,
        kkt,
        method: match options.solver {
            Solver::Direct => "saddle-point LDLᵀ per active-set step",
            Solver::Pcg(_) => "matrix-free PCG per active-set step (u_s = T u_m)",
            Solver::Petsc(_) => "PETSc KSP on the saddle point per active-set step",
        },
        points,
        petsc: matches!(options.solver, Solver::Petsc(_)).then_some(summary),
    })
}

/// Refuses what the contact solve cannot do: contact with standard
/// multipliers (D must be diagonal), and a slave point of both a glued and a
/// contact interface. (Lumped multipliers on Tri6 and Quad8 slave faces are
/// refused by the mortar assembly.)
pub(crate) fn check_couplings(interfaces: &[Interface]) -> Result<(), ProblemError> {
    let bad = |interface: usize, what: String| Err(ProblemError::BadInterface { interface, what });
    for (i, f) in interfaces.iter().enumerate() {
        if f.kind == Coupling::Contact && f.options.multiplier == Multiplier::Standard {
            return bad(
                i,
                "contact needs a diagonal D: multiplier \"lumped\" (the default) or \"dual\"".into(),
            );
        }
    }
    for (i, f) in interfaces.iter().enumerate().filter(|(_, f)| f.kind == Coupling::Glue) {
        for (j, c) in
            interfaces.iter().enumerate().filter(|(_, c)| c.kind == Coupling::Contact && c.slave == f.slave)
        {
            let (used_f, used_c) = (f.slave_surface.used_points(), c.slave_surface.used_points());
            if let Some(point) = (0..used_f.len()).find(|&p| used_f[p] && used_c[p]) {
                let at = f.slave_surface.points()[point];
                return Err(ProblemError::SharedSlavePoint { glue: i, contact: j, point, at });
            }
        }
    }
    Ok(())
}

impl Elimination {
    /// The glued interfaces' multipliers at u: λ_r = (f − Ku − C_cᵀμ)_{dof r} /
    /// C_{r, dof r} (the slave rows of the saddle point, C_S diagonal), C_c the
    /// contact constraints.
    fn multipliers(
        &self,
        constraints: &Constraints,
        system: &System,
        u: &[f64],
        points: &[ContactPoint],
        mu: &[f64],
    ) -> Vec<f64> {
        // The rows in the dofs of all bodies (`a_row` is in y).
        let rows: Vec<Vec<(usize, f64)>> =
            points.iter().map(|c| normal_row(&c.t_row, c.frame[0], None)).collect();
        let r = contact_residual(&system.k, &system.f, points, (u, mu), |i| &rows[i]);
        constraints
            .rows
            .iter()
            .enumerate()
            .map(|(i, row)| r[row.dof] / constraints.c.get(i, row.dof))
            .collect()
    }
}

/// f − K u − C_cᵀμ, where `row(i)` is point i's n_p·(T u_m)_p as (dof, a) in
/// the unknowns of u: C_cᵀμ puts d_p λ_p n_p on the slave dofs and −d_p λ_p a
/// on each dof of the row.
fn contact_residual<'a>(
    k: &CsrMatrix,
    f: &[f64],
    points: &[ContactPoint],
    (u, mu): (&[f64], &[f64]),
    row: impl Fn(usize) -> &'a [(usize, f64)],
) -> Vec<f64> {
    let ku = k.mul_vec(u, 1);
    let mut r: Vec<f64> = f.iter().zip(&ku).map(|(f, ku)| f - ku).collect();
    for (i, (c, &m)) in points.iter().zip(mu).enumerate() {
        for comp in 0..3 {
            r[c.first_dof + comp] -= m * c.frame[0][comp];
        }
        for &(j, a) in row(i) {
            r[j] += m * a;
        }
    }
    r
}

/// A₀: the points with g_p ≤ 0, and on each interface the points closest to
/// the master (g_p within `tolerance` of the smallest gap), so that a body held
/// only by the contact (force control) is held from the first step. A
/// point activated wrongly gets μ_p < 0 and leaves in the next step.
fn initial_active_set(points: &[ContactPoint], interfaces: usize, tolerance: f64) -> Vec<bool> {
    let mut closest = vec![f64::INFINITY; interfaces];
    for c in points {
        closest[c.interface] = closest[c.interface].min(c.gap);
    }
    points.iter().map(|c| c.gap <= tolerance.max(closest[c.interface] + tolerance)).collect()
}

/// A length of the problem: the largest bounding-box diagonal of the bodies.
fn length_scale(bodies: &[Body]) -> f64 {
    let diagonal = |points: &[Point3]| {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for x in points {
            for c in 0..3 {
                lo[c] = lo[c].min(x[c]);
                hi[c] = hi[c].max(x[c]);
            }
        }
        (0..3).map(|c| (hi[c] - lo[c]).powi(2)).sum::<f64>().sqrt()
    };
    bodies.iter().map(|b| diagonal(b.mesh.points())).fold(0.0, f64::max)
}

/// The primal-dual active set iteration (module doc) around `step`, which
/// returns, for an active set, the step number and whether the linear solve
/// must meet its full tolerance, (w, μ, linear iterations) per contact
/// point. Returns the final active set, w, μ and the steps.
///
/// When `inexact` (iterative solvers), the steps solve to a looser tolerance
/// ([`step_solver`]) while the active set still changes: their solutions only
/// decide the next active set, which they decide as exact ones would up to
/// the points on the verge of changing. A step whose loose solution leaves
/// the active set as it was goes on to the full tolerance (`step` once more
/// on the same set, warm-started; its linear iterations add up), and so do
/// all later steps, so the result is that of exact steps (Hüeber and
/// Wohlmuth's iteration with inexact inner solves, an inexact semismooth
/// Newton method).
#[allow(clippy::type_complexity)]
fn active_set_method(
    points: &[ContactPoint],
    mut active: Vec<bool>,
    scale: f64,
    (max_iterations, inexact): (usize, bool),
    mut step: impl FnMut(&[bool], usize, bool) -> Result<(Vec<f64>, Vec<f64>, usize), ProblemError>,
) -> Result<(Vec<bool>, Vec<f64>, Vec<f64>, Vec<ActiveSetStep>), ProblemError> {
    let mut steps = Vec::new();
    let mut tight = !inexact;
    loop {
        let n_active = active.iter().filter(|&&on| on).count();
        let (mut w, mut mu, mut linear_iterations) = step(&active, steps.len() + 1, tight)?;
        let mut next = next_active_set(points, &active, &w, &mu, scale);
        if !tight && next == active {
            tight = true;
            let refined;
            (w, mu, refined) = step(&active, steps.len() + 1, true)?;
            linear_iterations += refined;
            next = next_active_set(points, &active, &w, &mu, scale);
        }
        let added = next.iter().zip(&active).filter(|(&n, &o)| n && !o).count();
        let removed = next.iter().zip(&active).filter(|(&n, &o)| !n && o).count();
        steps.push(ActiveSetStep {
            active: n_active,
            added,
            removed,
            linear_iterations,
            full_tolerance: tight,
            residual: complementarity_residual(points, &active, &w, &mu),
        });
        if added + removed == 0 {
            return Ok((active, w, mu, steps));
        }
        if steps.len() >= max_iterations {
            return Err(ProblemError::ActiveSetNotSettled { steps: steps.len(), added, removed });
        }
        active = next;
    }
}

/// How far an iterate is from the contact conditions, relative: the
/// largest of max_{p ∈ A} (−μ_p)⁺ / max |μ| (pulling on an active point)
/// and max_{p ∉ A} (w_p − g_p)⁺ / max(|w|, |g|) (penetration at an inactive
/// one); w = g on A and μ = 0 off A hold by construction, so it is 0 (up to
/// the linear solve) exactly when the active set is right.
fn complementarity_residual(points: &[ContactPoint], active: &[bool], w: &[f64], mu: &[f64]) -> f64 {
    let max_abs = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |m, v| m.max(v.abs()));
    let relative = |v: f64, s: f64| if s > 0.0 { v / s } else { v };
    let mu_max = max_abs(&mut mu.iter().copied());
    let length = max_abs(&mut w.iter().copied().chain(points.iter().map(|c| c.gap)));
    let (mut pull, mut penetration) = (0.0f64, 0.0f64);
    for (((c, &on), &w), &mu) in points.iter().zip(active).zip(w).zip(mu) {
        if on {
            pull = pull.max(-mu);
        } else {
            penetration = penetration.max(w - c.gap);
        }
    }
    relative(pull, mu_max).max(relative(penetration, length))
}

/// The solver of a step: `solver` when `tight`, else `solver` loosened to
/// [`LOOSE_RTOL`].
fn step_solver(solver: Solver, tight: bool) -> Solver {
    if tight {
        solver
    } else {
        solver.loosened(LOOSE_RTOL)
    }
}

/// The relative tolerance of the active-set steps before the active set
/// settles: solutions to 0.1 % decide the next active set as exact ones do
/// but for points on the verge of changing. Measured with GAMG (rtol 10⁻¹⁰;
/// steps, the settling one counted twice, and KSP iterations) on Hertz n =
/// 10 and bulging contact n = 24:
/// exact steps 11 and 1 349, 5 and 224; 10⁻⁵ 12 and 714, 6 and 106; 10⁻³ 12
/// and 476, 7 and 101; 10⁻² 13 and 440, 6 and 132; 5·10⁻² 14 and 1 018, 6
/// and 172 (the active set wanders).
const LOOSE_RTOL: f64 = 1e-3;

/// A condensation's factor values and S ([`Condensed::into_kept`]).
pub(super) type Kept = (Vec<f64>, Mat<f64>);

/// The problem condensed on a set W of its unknowns (the contact normals
/// w_p; for friction also the tangential jumps): with A_OO = (PᵀKP) on all
/// other unknowns O factored once (every W unknown held at 0),
///
/// ```text
/// x(w) = x₀ + Σ_j Z_j w_j,   Z_j = −A_OO⁻¹ A_O,j ,
/// μ(w) = c − S w,           S = A_WW + A_WO Z,   c = (b − A x₀)_W ,
/// ```
///
/// so an active-set step is a dense solve S_II w_I = c_I − S_IA g_A on the
/// inactive points I (w_A = g_A), and the sparse factorisation is done once
/// (S by a second one, with W last: [`CholeskyAnalysis::schur_complement`]).
pub(super) struct Condensed<'a> {
    factor: CholeskyFactor<'a>,
    /// The dofs of W.
    w: Vec<usize>,
    pub(super) s: Mat<f64>,
    x0: Vec<f64>,
    pub(super) c: Vec<f64>,
}

impl<'a> Condensed<'a> {
    /// Factors A_OO (`analysis` of A with every dof of `w` prescribed, in
    /// `tied`) and forms S, unless `known` (the factor's values and S of this
    /// A, W and analysis, from [`Condensed::into_kept`]); then x₀ and c.
    pub(super) fn new(
        analysis: &'a CholeskyAnalysis,
        a: &CsrMatrix,
        b: &[f64],
        tied: &Dirichlet,
        (w, known): (&[usize], Option<Kept>),
    ) -> Result<Condensed<'a>, SolveError> {
        let (factor, s) = match known {
            Some((values, s)) => (CholeskyFactor::again(analysis, values), s),
            // S first: its factor is gone before A_OO's is made.
            None => {
                let s = analysis.schur_complement(a, w)?;
                (analysis.factor(a)?, s)
            }
        };
        let mut condensed = Condensed { factor, w: w.to_vec(), s, x0: Vec::new(), c: Vec::new() };
        condensed.load(a, b, tied);
        Ok(condensed)
    }

    /// The factor's values and S, for [`Condensed::new`] on the next load
    /// step of the same A.
    pub(super) fn into_kept(self) -> Kept {
        (self.factor.into_values(), self.s)
    }

    /// x₀ and c for the load `b` and the values of `tied` (its dofs those
    /// analysed).
    pub(super) fn load(&mut self, a: &CsrMatrix, b: &[f64], tied: &Dirichlet) {
        let (free, m) = (self.factor.analysis().free(), self.factor.analysis().free().len());
        // x₀: the prescribed values, w = 0, A_OO x_O = (b − A ū)_O.
        let mut x0 = vec![0.0; a.nrows];
        for (dof, v) in tied.iter() {
            x0[dof] = v;
        }
        let r = residual(a, b, &x0);
        let mut rhs = Mat::<f64>::from_fn(m, 1, |i, _| r[free[i]]);
        self.factor.solve_in_place(rhs.as_mut());
        for (i, &dof) in free.iter().enumerate() {
            x0[dof] = rhs[(i, 0)];
        }
        let r = residual(a, b, &x0);
        self.c = self.w.iter().map(|&dof| r[dof]).collect();
        self.x0 = x0;
    }

    /// One active-set step (W the normals of `points`, in order): w_A = g_A,
    /// S_II w_I = c_I − S_IA g_A, and μ_A = (c − S w)_A, μ_I = 0. None when
    /// S_II is (numerically) singular.
    fn step(&self, points: &[ContactPoint], active: &[bool]) -> Option<(Vec<f64>, Vec<f64>)> {
        let nw = points.len();
        let mut w: Vec<f64> =
            points.iter().zip(active).map(|(p, &on)| if on { p.gap } else { 0.0 }).collect();
        let inactive: Vec<usize> = (0..nw).filter(|&i| !active[i]).collect();
        if !inactive.is_empty() {
            let s_ii = Mat::<f64>::from_fn(inactive.len(), inactive.len(), |i, j| {
                self.s[(inactive[i], inactive[j])]
            });
            let mut rhs = Mat::<f64>::from_fn(inactive.len(), 1, |i, _| {
                let r = inactive[i];
                self.c[r] - (0..nw).filter(|&j| active[j]).map(|j| self.s[(r, j)] * w[j]).sum::<f64>()
            });
            let llt = s_ii.as_ref().llt(Side::Lower).ok()?;
            let l = llt.L();
            let diagonal = (0..inactive.len()).map(|i| l[(i, i)]);
            let (lo, hi) = diagonal.fold((f64::INFINITY, 0.0f64), |(lo, hi), d| (lo.min(d), hi.max(d)));
            if lo.is_nan() || lo <= 1e-7 * hi {
                return None;
            }
            llt.solve_in_place(rhs.as_mut());
            for (i, &r) in inactive.iter().enumerate() {
                w[r] = rhs[(i, 0)];
            }
        }
        let mu = (0..nw)
            .map(|i| {
                if active[i] {
                    self.c[i] - (0..nw).map(|j| self.s[(i, j)] * w[j]).sum::<f64>()
                } else {
                    0.0
                }
            })
            .collect();
        Some((w, mu))
    }

    /// x(w) = x₀ + Z w for the values `w` of W: one more solve with A_OO.
    pub(super) fn expand(&self, a: &CsrMatrix, w: &[f64]) -> Vec<f64> {
        let analysis = self.factor.analysis();
        let (free, local) = (analysis.free(), analysis.local());
        let mut rhs = Mat::<f64>::zeros(free.len(), 1);
        for (&dof, &wp) in self.w.iter().zip(w) {
            let (idx, vals) = a.row(dof);
            for (&q, &v) in idx.iter().zip(vals) {
                if local[q] != usize::MAX {
                    rhs[(local[q], 0)] -= v * wp;
                }
            }
        }
        self.factor.solve_in_place(rhs.as_mut());
        let mut x = self.x0.clone();
        for (i, &dof) in free.iter().enumerate() {
            x[dof] += rhs[(i, 0)];
        }
        for (&dof, &wp) in self.w.iter().zip(w) {
            x[dof] = wp;
        }
        x
    }
}

/// b − A x.
fn residual(a: &CsrMatrix, b: &[f64], x: &[f64]) -> Vec<f64> {
    let ax = a.mul_vec(x, 1);
    b.iter().zip(ax).map(|(b, ax)| b - ax).collect()
}

/// (b − A x) at each contact point's w dof: μ_p where active.
fn residual_at_normals(a: &CsrMatrix, b: &[f64], x: &[f64], points: &[ContactPoint]) -> Vec<f64> {
    points
        .iter()
        .map(|c| {
            let (cols, vals) = a.row(c.first_dof);
            b[c.first_dof] - cols.iter().zip(vals).map(|(&j, &v)| v * x[j]).sum::<f64>()
        })
        .collect()
}

/// A_{k+1} = {μ + c(w − g) > 0}: an active point stays unless μ_p < 0, an
/// inactive one enters when w_p > g_p, each beyond a round-off margin
/// (10⁻¹² of the largest |μ|, resp. of the length scale) so that a point with
/// zero pressure and zero gap does not flip back and forth.
fn next_active_set(points: &[ContactPoint], active: &[bool], w: &[f64], mu: &[f64], scale: f64) -> Vec<bool> {
    let mu_margin = 1e-12 * mu.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let gap_margin = 1e-12 * scale;
    points
        .iter()
        .zip(active)
        .zip(mu)
        .zip(w)
        .map(|(((c, &on), &mu), &w)| if on { mu >= -mu_margin } else { w - c.gap > gap_margin })
        .collect()
}

/// The KKT residuals (see [`Kkt`]) in the unknowns y (Cartesian dofs, glued
/// slave dofs eliminated): Cᵀλ puts d_p λ_p n_p on y_s,p and −d_p λ_p a_j on
/// y_j (`a_row`).
fn kkt(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    points: &[ContactPoint],
    (u, x): (&[f64], &[f64]),
    mu: &[f64],
) -> Kkt {
    let r = contact_residual(k, f, points, (u, mu), |i| &points[i].a_row);
    let free = free_dofs(k, dirichlet);
    let max_free = |v: &[f64]| (0..v.len()).filter(|&i| free[i]).fold(0.0f64, |m, i| m.max(v[i].abs()));
    let max_abs = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |m, v| m.max(v.abs()));
    let relative = |v: f64, s: f64| if s > 0.0 { v / s } else { v };
    let pressure: Vec<f64> = points.iter().zip(mu).map(|(c, &m)| m / c.d).collect();
    let p_max = max_abs(&mut pressure.iter().copied());
    let u_max = max_abs(&mut u.iter().copied().chain(points.iter().map(|c| c.gap)));
    let slack: Vec<f64> = points.iter().map(|c| c.gap - x[c.first_dof]).collect();
    Kkt {
        equilibrium: relative(max_free(&r), max_free(f).max(max_free(&magnitudes(k, u)))),
        pressure: relative(pressure.iter().fold(0.0f64, |m, &l| m.max(-l)), p_max),
        penetration: relative(slack.iter().fold(0.0f64, |m, &s| m.max(-s)), u_max),
        complementarity: relative(
            max_abs(&mut pressure.iter().zip(&slack).map(|(l, s)| l * s)),
            p_max * u_max,
        ),
    }
}

/// Σ_j |K_ij u_j| per row.
fn magnitudes(k: &CsrMatrix, u: &[f64]) -> Vec<f64> {
    (0..k.nrows)
        .map(|i| {
            let (cols, vals) = k.row(i);
            cols.iter().zip(vals).map(|(&j, v)| (v * u[j]).abs()).sum()
        })
        .collect()
}

/// Adds the contact interfaces' fields to `out` (one per interface): per
/// contact point its normal, gaps, pressure λ_p = μ_p / d_p, activity and
/// traction −λ_p n_p, and the resultant −Σ_p μ_p n_p.
pub(crate) fn add_contact_fields(
    out: &mut [InterfaceSolution],
    steps: &ContactSolve,
    friction: Option<&friction::Friction>,
) {
    for (i, (((c, &m), &on), &wp)) in
        steps.points.iter().zip(&steps.mu).zip(&steps.active).zip(&steps.w).enumerate()
    {
        let s = &mut out[c.interface];
        let (p, n) = (c.point, c.frame[0]);
        let n_points = s.traction.len();
        let fields = s.contact.get_or_insert_with(|| ContactFields::new(n_points));
        let pressure = m / c.d;
        fields.contact[p] = true;
        fields.initial_gap[p] = c.gap;
        fields.gap[p] = c.gap - wp;
        fields.pressure[p] = pressure;
        fields.active[p] = on;
        s.constrained[p] = true;
        s.normal[p] = n;
        s.traction[p] = n.map(|v| -pressure * v);
        for comp in 0..3 {
            s.force[comp] -= m * n[comp];
        }
        if let Some(f) = friction {
            // The frictional part: −λ_τ,1 τ₁ − λ_τ,2 τ₂ per area, −d_p λ_τ in the resultant.
            let [l1, l2] = f.tangential[i];
            for comp in 0..3 {
                let t = l1 * c.frame[1][comp] + l2 * c.frame[2][comp];
                s.traction[p][comp] -= t;
                s.force[comp] -= c.d * t;
            }
            fields.friction = f.mu[i];
            fields.stick[p] = f.status[i] == friction::Status::Stick;
            (fields.slip_increment[p], fields.slip[p]) = f.slip[i];
            fields.friction_bound[p] = f.mu[i] * pressure;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::multibody::{assemble_system, bodies_stiffness, Operators};
    use crate::scene::{bulging_contact, BulgingContact};

    /// The saddle point per step (used with glued interfaces that do not
    /// eliminate), solved directly or by matrix-free PCG, and the rotated,
    /// condensed system take the same active-set steps to the same solution,
    /// on a contact that spreads over several steps (the bulging bodies).
    #[test]
    fn the_saddle_path_and_frictionless_newton_match_the_rotated_one_over_several_steps() {
        let problem =
            bulging_contact(&BulgingContact { cells: 8, layers: 4, ..BulgingContact::default() }).unwrap();
        let prepared = problem.loads_and_supports(1.0).unwrap();
        let (bodies, interfaces) = (problem.solver_bodies(&prepared), problem.coupled());
        let options = SolveOptions::default();
        let mut seconds = Timings::default();
        let mut system =
            assemble_system(&bodies, &interfaces, (true, Operators::Here), &mut seconds).unwrap();
        let constraints =
            Constraints::new((&interfaces, &bodies), &system.mortars, &system.offsets, &system.dirichlet);
        let reform = || bodies_stiffness(&bodies);
        let a =
            rotated_steps(&bodies, &interfaces, &options, (&mut system, &reform), &constraints, &mut seconds)
                .unwrap();
        let b = saddle_steps(&bodies, &interfaces, &options, &system, &constraints, &mut seconds).unwrap();
        // μ = 0 through the frictional Newton method is the same frictionless solution.
        let mut state = friction::FrictionState::default();
        let solver = (options.solver, options.max_active_set_steps);
        let (c, f) = friction::solve_frictional(
            &bodies,
            &interfaces,
            solver,
            &mut system,
            &constraints,
            &mut state,
            &mut seconds,
        )
        .unwrap();
        assert!(f.tangential.iter().all(|t| *t == [0.0, 0.0]));
        assert!(f.status.iter().all(|&s| s != friction::Status::Stick));
        assert_eq!(a.active, c.active);
        assert!(a.steps.len() >= 2, "{:?}", a.steps);
        // The same steps; their residuals to round-off of the two solves.
        let without_residual = |s: &[ActiveSetStep]| -> Vec<ActiveSetStep> {
            s.iter().map(|s| ActiveSetStep { residual: 0.0, ..*s }).collect()
        };
        assert_eq!(without_residual(&a.steps), without_residual(&b.steps));
        for (x, y) in a.steps.iter().zip(&b.steps) {
            assert!((x.residual - y.residual).abs() <= 1e-12, "{x:?} {y:?}");
        }
        assert!(a.steps.last().is_some_and(|s| s.residual <= 1e-12), "converged: {:?}", a.steps);
        assert_eq!(a.active, b.active);
        let max = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |m, x| m.max(x.abs()));
        let u_scale = max(&mut a.u.iter().copied());
        let mu_scale = max(&mut a.mu.iter().copied());
        let du = max(&mut a.u.iter().zip(&b.u).map(|(x, y)| x - y));
        let dmu = max(&mut a.mu.iter().zip(&b.mu).map(|(x, y)| x - y));
        let du_friction = max(&mut a.u.iter().zip(&c.u).map(|(x, y)| x - y));
        let dmu_friction = max(&mut a.mu.iter().zip(&c.mu).map(|(x, y)| x - y));
        assert!(
            du_friction <= 1e-12 * u_scale && dmu_friction <= 1e-12 * mu_scale,
            "μ = 0: u {du_friction:e} of {u_scale:e}, μ {dmu_friction:e} of {mu_scale:e}"
        );
        assert!(
            du <= 1e-9 * u_scale && dmu <= 1e-8 * mu_scale,
            "u {du:e} of {u_scale:e}, μ {dmu:e} of {mu_scale:e}"
        );
        assert!(b.kkt.max() <= 1e-10, "{:?}", b.kkt);

        // The same steps with each saddle point solved by matrix-free PCG.
        let pcg = Solver::Pcg(crate::pcg::PcgOptions { rtol: 1e-13, ..Default::default() });
        let options = SolveOptions { solver: pcg, ..options };
        let c = saddle_steps(&bodies, &interfaces, &options, &system, &constraints, &mut seconds).unwrap();
        let changes =
            |s: &ContactSolve| s.steps.iter().map(|s| (s.active, s.added, s.removed)).collect::<Vec<_>>();
        assert_eq!(changes(&a), changes(&c));
        assert!(c.steps.iter().all(|s| s.linear_iterations > 0), "{:?}", c.steps);
        let du = max(&mut a.u.iter().zip(&c.u).map(|(x, y)| x - y));
        let dmu = max(&mut a.mu.iter().zip(&c.mu).map(|(x, y)| x - y));
        assert!(
            du <= 1e-8 * u_scale && dmu <= 1e-7 * mu_scale,
            "PCG: u {du:e} of {u_scale:e}, μ {dmu:e} of {mu_scale:e}"
        );
        assert!(c.kkt.max() <= 1e-8, "{:?}", c.kkt);
    }
}
