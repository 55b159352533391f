//! Coulomb friction on contact interfaces: a semismooth Newton method on the
//! dual (or lumped) multipliers in the nodal frames (Hüeber, Stadler &
//! Wohlmuth 2008; the complementarity functions as in Gitterle, Popp, Gee &
//! Wall 2010), quasi-static and in small deformation, over the load steps of
//! [`crate::history`].
//!
//! # The discrete problem
//! At a contact point p with frame (n, τ₁, τ₂), weight d_p, gap g_p and
//! T = D⁻¹B, the relative displacement r_p = (u_s − T u_m)_p has the
//! normal part w_p = n·r_p and the tangential parts (τ₁·r_p, τ₂·r_p); the
//! slip of a load step is s_p = (τ·r_p) − (τ·r_p)ⁿ⁻¹, its increment since
//! the step before (the mortar-weighted slip divided by d_p). The unknowns
//! are u, the glued multipliers, and per contact point z_p = d_p λ_p with
//! λ_p = (λ_n, λ_τ): the master exerts −λ_n n − λ_τ,1 τ₁ − λ_τ,2 τ₂ per area
//! on the slave (λ_n the contact pressure, λ_τ along the slip). Equilibrium
//! is K u + C_gᵀ λ_g + Σ_p G_pᵀ z_p = f, G_p the rows n·r_p, τ₁·r_p, τ₂·r_p.
//! Coulomb's law is the pair of complementarity functions (c > 0)
//!
//! ```text
//! C_n = λ_n − max(0, ξ) = 0,                         ξ = λ_n − c (g_p − w_p),
//! C_τ = max(μ ξ, ‖v‖) λ_τ − μ max(0, ξ) v = 0,       v = λ_τ + c s_p,
//! ```
//!
//! which split the points into inactive (ξ ≤ 0: λ = 0), stick
//! (‖v‖ < μ ξ: w = g, s = 0) and slip (w = g, ‖v‖ λ_τ = μ λ_n v: λ_τ along
//! the slip with ‖λ_τ‖ = μ λ_n). The semismooth Newton step takes each set
//! from the current iterate and linearises C_τ on the slip set,
//!
//! ```text
//! (‖v‖ I + λ_τ v̂ᵀ − μ λ_n I) λ_τ' + c (λ_τ v̂ᵀ − μ λ_n I) s' − μ v λ_n' = C_τ(λ_τ, s, λ_n)
//! ```
//!
//! (C_τ is homogeneous of degree 2, so J x − C_τ = C_τ), divided by ‖v‖: the
//! system is not symmetric. In nodal frames whose tangents are relative too
//! the jumps (n, τ₁, τ₂)·(u_s − T u_m)_p are unknowns of their own
//! (`rotated_newton`; glued interfaces with dual or lumped multipliers
//! eliminated first, u = P_g y, as for frictionless contact). The direct
//! solver condenses the system on them (up to [`CONDENSED_MAX`] contact
//! points): the stiffness on all the others is factored once by sparse
//! Cholesky, its Schur complement S on the jumps formed once for all load
//! steps, and each Newton step is a dense LU on the jumps. PETSc substitutes
//! z = (b − A x) on the jumps' rows instead, so that each step is a system
//! in x alone, symmetric but for the slip rows (FGMRES + GAMG, inexact:
//! [`FORCING`]). Otherwise (the direct solver; PCG is refused) the system is solved whole — u, the glued
//! multipliers and z (`assembled_newton`): sparse LDLᵀ of the symmetric
//! saddle matrix that the Newton matrix becomes when the rows of the
//! slipping multipliers are replaced by their columns preconditions GMRES on
//! the Newton matrix ([`solve_nearly_saddle`]: the two differ in as many rows
//! as there are slip unknowns, so GMRES needs few iterations). A point with μ = 0, or a
//! tangential axis that is prescribed at the slave point (a symmetry plane,
//! whose reaction takes the force), has λ_τ = 0 in that direction, so μ = 0
//! is frictionless contact. The iteration stops when the sets repeat and the
//! update of (u, z) — of the jumps and z, condensed — is below
//! [`NEWTON_TOLERANCE`] of their size, or below [`ROUND_OFF_FLOOR`] and no
//! longer halving (round-off); c = c_n in ξ is per point
//! the mean diagonal stiffness of its slave dofs over d_p, and c = c_t in v
//! a tenth of it ([`C_T`]).
//!
//! The first step starts with the points of the frictionless initial active
//! set ([`super::initial_active_set`]) in stick, so that a body held only by
//! contact and friction is held from the first iteration; every later step
//! starts from the last one's u and z.

use super::frames::{contact_points, normal_row, rotated_dirichlet, rotation, ContactPoint, SlaveBasis};
use super::{initial_active_set, kkt, length_scale, Condensed, ContactSolve};
use crate::backend::{free_block, Solver};
use crate::constraints::{triple_product, Constraints, Elimination};
use crate::multibody::{Body, Coupling, Interface, ProblemError, System, Timings};
use crate::pcg::free_system;
use crate::petsc::{KeptKsp, PetscOptions, PetscSummary, Split};
use crate::saddle::solve_nearly_saddle;
use crate::solution::ActiveSetStep;
use crate::solve::Dirichlet;
use crate::solve::SolveError;
use crate::solve::{CholeskyAnalysis, DirectOptions};
use faer::linalg::solvers::Solve;
use faer::Mat;
use seam::{CsrMatrix, Point3};
use std::collections::BTreeMap;
use std::time::Instant;

/// c_t / c_n. Larger values weigh the slip more than the traction in the
/// slip direction v = λ_τ + c_t s and make the iteration cycle between
/// stick and slip; measured on the frictional patch test driven in slip
/// (Newton iterations over its 10 load steps, both patch tests together):
/// 1: no convergence (all points alternate between stick and slip), 0.3:
/// 79, 0.1: 67, 0.03: 79, 0.01: 88.
const C_T: f64 = 0.1;

/// The relative update of (u, z) below which the Newton iteration stops
/// once the sets repeat (its convergence is superlinear, so the iterate is
/// then far more accurate).
const NEWTON_TOLERANCE: f64 = 1e-10;

/// The most contact points (covered slave points) whose frictional steps
/// are condensed on their jumps (module doc): S has (3 × this)² entries
/// (290 MB) and each Newton step factors it densely (1.4·10¹¹ flops, some
/// 10 s on two cores; 0.3 s at 910 points); beyond, the whole system is
/// solved per step.
const CONDENSED_MAX: usize = 2000;

/// Below this relative update an iteration whose sets repeat also stops
/// when the update no longer halves: the round-off of the solves (the
/// condensed steps' floor is 1e-10 to 1e-9 at 10⁵ unknowns).
const ROUND_OFF_FLOOR: f64 = 1e-8;

/// The forcing term of the inexact Newton steps with PETSc once the sets
/// repeat: each KSP solve to η = this × (the last relative update)² (at
/// least the solver's rtol), which keeps the convergence quadratic
/// (Eisenstat & Walker's second choice) and spares the early steps the
/// full tolerance.
const FORCING: f64 = 0.1;

/// What a frictional solve carries from one load step to the next.
#[derive(Default)]
pub(crate) struct FrictionState {
    /// The displacements at the end of the last step (empty before the first).
    pub(crate) u: Vec<f64>,
    /// Per contact point, by (interface, slave point): z at the end of the
    /// last step (frame components) and the accumulated slip (Cartesian).
    pub(crate) points: BTreeMap<(usize, usize), ([f64; 3], Point3)>,
    /// The direct solver's condensation of the last step ([`Condensed`]):
    /// the load steps of one problem share it.
    condensed: Option<KeptCondensation>,
    /// PETSc's system of the last step's Newton iteration, kept for the next
    /// load step ([`KeptKsp`]).
    ksp: KeptKsp,
}

/// A condensation kept for the next load step: the analysis of A_OO, its
/// factor's values and S, and the fingerprint of A, W and the held dofs it
/// belongs to.
struct KeptCondensation {
    key: u64,
    analysis: CholeskyAnalysis,
    values: Vec<f64>,
    s: Mat<f64>,
}

/// A fingerprint of A, W and the held dofs (FNV-1a over their bits), to know
/// a condensation again.
fn fingerprint(a: &CsrMatrix, w: &[usize], held: &Dirichlet) -> u64 {
    let held: Vec<usize> = held.iter().map(|(dof, _)| dof).collect();
    let words = a.indptr.iter().chain(&a.indices).chain(w).chain(&held).map(|&i| i as u64);
    crate::Fnv::of(words.chain(a.values.iter().map(|v| v.to_bits())))
}

/// Where a contact point is in an iteration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Status {
    /// Not in contact: λ = 0.
    Inactive,
    /// In contact, not slipping.
    Stick,
    /// In contact, slipping (or frictionless).
    Slip,
}

/// The frictional fields per contact point, besides [`ContactSolve`].
pub(crate) struct Friction {
    /// Per contact point: λ_τ in the frame (τ₁, τ₂ components).
    pub(crate) tangential: Vec<[f64; 2]>,
    /// Per contact point: its status at the solution.
    pub(crate) status: Vec<Status>,
    /// Per contact point: the slip of this step and the accumulated slip.
    pub(crate) slip: Vec<(Point3, Point3)>,
    /// Per contact point: μ.
    pub(crate) mu: Vec<f64>,
}

/// A sparse row over the unknowns.
type SparseRow = Vec<(usize, f64)>;

/// Solves the frictional contact problem of one load step (module doc),
/// updating `state` for the next one.
///
/// # Errors
/// [`ProblemError::BadInterface`] for a solver other than the direct one or
/// a prescribed slave component the transformed basis cannot carry
/// ([`SlaveBasis::new`]), a singular Newton step, no convergence within
/// `max_steps`, the solves' errors.
pub(crate) fn solve_frictional(
    bodies: &[Body],
    interfaces: &[Interface],
    (solver, max_steps): (Solver, usize),
    system: &mut System,
    constraints: &Constraints,
    state: &mut FrictionState,
    seconds: &mut Timings,
) -> Result<(ContactSolve, Friction), ProblemError> {
    // Dense S and a dense LU per Newton step: for up to CONDENSED_MAX points.
    let points = interfaces.iter().zip(&system.mortars).filter(|(f, _)| f.kind == Coupling::Contact);
    let covered: usize = points.map(|(_, m)| m.covered.iter().filter(|&&c| c).count()).sum();
    // Glued interfaces, if any, eliminated node by node (dual, lumped).
    let eliminable = constraints.rows.is_empty() || constraints.eliminated_block_is_diagonal();
    let path = Path::of(solver, covered, eliminable).map_err(|what| {
        let interface = interfaces.iter().position(|f| f.friction > 0.0).unwrap_or(0);
        ProblemError::BadInterface { interface, what: what.into() }
    })?;
    let how = (solver, max_steps, path);
    let clock = Instant::now();
    let basis = SlaveBasis::new(bodies, interfaces, system)?;
    seconds.setup += clock.elapsed().as_secs_f64();
    let Some(basis) = basis else {
        return frictional_step(bodies, interfaces, how, system, constraints, state, seconds);
    };
    // In the transformed unknowns ũ, u = P_b ũ, as frictionless contact
    // (module doc of `contact`); `state` keeps ũ between the load steps.
    let clock = Instant::now();
    let (transformed, glued) = basis.transform(system, constraints);
    seconds.setup += clock.elapsed().as_secs_f64();
    let solved = frictional_step(bodies, interfaces, how, &transformed, &glued, state, seconds);
    (system.mortars, system.points) = (transformed.mortars, transformed.points);
    let (mut steps, friction) = solved?;
    steps.u = basis.p.mul_vec(&steps.u, 1);
    Ok((steps, friction))
}

/// How the Newton steps of a frictional solve are solved (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Path {
    /// Condensed on the contact jumps, a dense LU per step (the direct
    /// solver, glued interfaces eliminated node by node).
    Condensed,
    /// In the displacements alone, the contact multipliers substituted
    /// (PETSc, glued interfaces eliminated node by node).
    Reduced,
    /// The whole system (the direct solver otherwise).
    Assembled,
}

impl Path {
    /// The path of `solver` with `covered` contact points, the glued
    /// interfaces `eliminable` or not; a one-line reason when there is none.
    fn of(solver: Solver, covered: usize, eliminable: bool) -> Result<Path, &'static str> {
        match solver {
            Solver::Direct if eliminable && covered <= CONDENSED_MAX => Ok(Path::Condensed),
            Solver::Direct => Ok(Path::Assembled),
            Solver::Petsc(_) if eliminable => Ok(Path::Reduced),
            Solver::Petsc(_) => Err("friction with PETSc needs the glued interfaces next to it eliminated \
                 node by node: dual or lumped multipliers and no crosspoints (or the direct solver)"),
            Solver::Pcg(_) => {
                Err("friction needs a solver of nonsymmetric systems: not PCG; use the direct \
                 solver or PETSc")
            }
        }
    }
}

/// [`solve_frictional`] on the Newton `path`.
fn frictional_step(
    bodies: &[Body],
    interfaces: &[Interface],
    (solver, max_steps, path): (Solver, usize, Path),
    system: &System,
    constraints: &Constraints,
    state: &mut FrictionState,
    seconds: &mut Timings,
) -> Result<(ContactSolve, Friction), ProblemError> {
    let clock = Instant::now();
    let (k, f, dirichlet) = (&system.k, &system.f, &system.dirichlet);
    let n = k.nrows;
    let points = contact_points(bodies, interfaces, &system.mortars, &system.offsets, dirichlet, None)?;
    // G_p: the rows e_k·(u_s − T u_m)_p, e = n, τ₁, τ₂.
    let rows: Vec<[SparseRow; 3]> = points
        .iter()
        .map(|c| {
            std::array::from_fn(|k| {
                let e = c.frame[k];
                let mut row: SparseRow = (0..3).map(|j| (c.first_dof + j, e[j])).collect();
                row.extend(normal_row(&c.t_row, e, None).into_iter().map(|(j, a)| (j, -a)));
                row
            })
        })
        .collect();
    let jumps = |u: &[f64]| -> Vec<[f64; 3]> {
        rows.iter().map(|r| r.each_ref().map(|row| row.iter().map(|&(j, a)| a * u[j]).sum())).collect()
    };
    let diagonal = |i: usize| {
        let (cols, vals) = k.row(i);
        cols.iter().zip(vals).find(|(&j, _)| j == i).map_or(0.0, |(_, &v)| v)
    };
    // c_n per point: the mean diagonal stiffness of its slave dofs over d_p;
    // c_t = C_T c_n (module doc).
    let cn: Vec<f64> =
        points.iter().map(|c| (0..3).map(|j| diagonal(c.first_dof + j)).sum::<f64>() / (3.0 * c.d)).collect();
    // The previous step: u, z, and the tangential jumps.
    let first = state.u.is_empty();
    let u_prev = if first { vec![0.0; n] } else { state.u.clone() };
    let jumps_prev = jumps(&u_prev);
    let law = Law {
        mu: points.iter().map(|c| interfaces[c.interface].friction).collect(),
        ct: cn.iter().map(|c| C_T * c).collect(),
        cn,
        // A tangential axis prescribed at the slave point carries no friction.
        free_tangent: points
            .iter()
            .map(|c| {
                std::array::from_fn(|t| {
                    let e = c.frame[t + 1];
                    !(0..3).any(|j| e[j].abs() == 1.0 && dirichlet.value(c.first_dof + j).is_some())
                })
            })
            .collect(),
        before: jumps_prev.iter().map(|j| [j[1], j[2]]).collect(),
        points: &points,
    };
    let z_prev: Vec<[f64; 3]> =
        points.iter().map(|c| state.points.get(&(c.interface, c.point)).map_or([0.0; 3], |h| h.0)).collect();
    let status: Vec<Status> = if first {
        let initial = initial_active_set(&points, interfaces.len(), 1e-9 * length_scale(bodies));
        initial.iter().map(|&on| if on { Status::Stick } else { Status::Inactive }).collect()
    } else {
        jumps_prev.iter().zip(&z_prev).enumerate().map(|(p, (j, z))| law.status(p, *j, *z)).collect()
    };
    seconds.setup += clock.elapsed().as_secs_f64();

    let mut summary = PetscSummary::default();
    let newton = match path {
        Path::Condensed | Path::Reduced => {
            let glued =
                if constraints.rows.is_empty() { None } else { Some(Elimination::new(constraints, k, f)?) };
            // The contact points in the unknowns y left by the elimination, u = P_g y.
            let glued_points = match &glued {
                Some(g) => {
                    let offsets = &system.offsets;
                    Some(contact_points(bodies, interfaces, &system.mortars, offsets, dirichlet, Some(&g.p))?)
                }
                None => None,
            };
            let law = match &glued_points {
                Some(points) => Law { points, ..law.clone() },
                None => law.clone(),
            };
            let eliminated = Eliminated {
                k: glued.as_ref().map_or(k, |g| &g.k),
                f: glued.as_ref().map_or(f, |g| &g.f),
                dirichlet,
                p_g: glued.as_ref().map(|g| &g.p),
                retained: glued.as_ref().map(|g| &g.retained[..]),
                points: &system.points,
                offsets: &system.offsets,
            };
            let start = (&jumps_prev[..], &u_prev[..], status);
            let how = (solver, max_steps, (&mut state.condensed, &mut state.ksp));
            let solved = rotated_newton(&law, eliminated, start, how, &mut summary, seconds);
            solved.map(|(y, _, z, status, steps)| match &glued {
                None => (y, Vec::new(), z, status, steps),
                Some(g) => {
                    let u = g.p.mul_vec(&y, 1);
                    let lambda = glued_multipliers((k, f, constraints), &rows, &u, &z);
                    (u, lambda, z, status, steps)
                }
            })
        }
        Path::Assembled => {
            let start = (&u_prev[..], &z_prev[..], status);
            assembled_newton(
                &law,
                (k, f, dirichlet, constraints),
                &rows,
                start,
                (solver, max_steps),
                &mut summary,
                seconds,
            )
        }
    };
    let (u, lambda, z, status, steps) = newton?;

    let clock = Instant::now();
    // KKT of the normal problem, the glued and frictional forces moved to the load side.
    let mut f_net = f.clone();
    let reaction = constraints.c.transpose_mul_vec(&lambda, 1);
    f_net.iter_mut().zip(&reaction).for_each(|(f, r)| *f -= r);
    for (r, z) in rows.iter().zip(&z) {
        for t in 1..3 {
            for &(j, a) in &r[t] {
                f_net[j] -= a * z[t];
            }
        }
    }
    let jump = jumps(&u);
    let w: Vec<f64> = jump.iter().map(|j| j[0]).collect();
    let mut slack = vec![0.0; n];
    for (c, &wp) in points.iter().zip(&w) {
        slack[c.first_dof] = wp;
    }
    let normal: Vec<f64> = z.iter().map(|z| z[0]).collect();
    let kkt = kkt(k, &f_net, dirichlet, &points, (&u, &slack), &normal);
    let slip: Vec<(Point3, Point3)> = points
        .iter()
        .enumerate()
        .map(|(p, c)| {
            let s = law.slip(p, jump[p]);
            let increment: Point3 = std::array::from_fn(|j| s[0] * c.frame[1][j] + s[1] * c.frame[2][j]);
            let before = state.points.get(&(c.interface, c.point)).map_or([0.0; 3], |h| h.1);
            (increment, std::array::from_fn(|j| before[j] + increment[j]))
        })
        .collect();
    state.u.clone_from(&u);
    state.points =
        points.iter().zip(&z).zip(&slip).map(|((c, z), s)| ((c.interface, c.point), (*z, s.1))).collect();
    seconds.solve += clock.elapsed().as_secs_f64();
    let friction = Friction {
        tangential: z.iter().zip(&points).map(|(z, c)| [z[1] / c.d, z[2] / c.d]).collect(),
        status: status.clone(),
        slip,
        mu: law.mu,
    };
    let steps = ContactSolve {
        u,
        w,
        mu: normal,
        active: status.iter().map(|&s| s != Status::Inactive).collect(),
        steps,
        lambda,
        kkt,
        method: match solver {
            Solver::Petsc(_) => "PETSc KSP per semismooth Newton step on the reduced displacements",
            _ if path == Path::Condensed => {
                "sparse Cholesky, semismooth Newton on the condensed contact unknowns"
            }
            _ => "sparse LDLᵀ and GMRES per semismooth Newton step",
        },
        points,
        petsc: matches!(solver, Solver::Petsc(_)).then_some(summary),
    };
    Ok((steps, friction))
}

/// v = λ_τ + c s.
fn slip_vector(lambda: [f64; 3], c: f64, s: [f64; 2]) -> [f64; 2] {
    [lambda[1] + c * s[0], lambda[2] + c * s[1]]
}

fn norm2(v: [f64; 2]) -> f64 {
    v[0].hypot(v[1])
}

/// ‖b − a‖∞ / max(‖a‖∞, ‖b‖∞) (0 when both vanish).
fn relative_change(a: &[f64], b: &[f64]) -> f64 {
    let max = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = max(&mut a.iter().chain(b).copied());
    let diff = max(&mut a.iter().zip(b).map(|(x, y)| x - y));
    if scale > 0.0 {
        diff / scale
    } else {
        diff
    }
}

/// Coulomb's law at the contact points of one load step (module doc): the
/// sets and the linearised slip rows.
#[derive(Clone)]
struct Law<'a> {
    points: &'a [ContactPoint],
    /// μ per point.
    mu: Vec<f64>,
    /// c_n, c_t per point.
    cn: Vec<f64>,
    ct: Vec<f64>,
    /// Per point and tangent: not prescribed at the slave point.
    free_tangent: Vec<[bool; 2]>,
    /// The tangential jumps at the end of the last step.
    before: Vec<[f64; 2]>,
}

impl Law<'_> {
    /// Whether tangent t of point p carries friction (μ > 0, not prescribed).
    fn frictional(&self, p: usize, t: usize) -> bool {
        self.mu[p] > 0.0 && self.free_tangent[p][t]
    }

    /// s_p: the tangential jump of this step (zero along prescribed tangents),
    /// from p's jumps (n, τ₁, τ₂).
    fn slip(&self, p: usize, jump: [f64; 3]) -> [f64; 2] {
        [0, 1].map(|t| if self.free_tangent[p][t] { jump[t + 1] - self.before[p][t] } else { 0.0 })
    }

    /// The set of point p at its jumps and z.
    fn status(&self, p: usize, jump: [f64; 3], z: [f64; 3]) -> Status {
        let c = &self.points[p];
        let lambda = z.map(|z| z / c.d);
        let xi = lambda[0] - self.cn[p] * (c.gap - jump[0]);
        if xi <= 0.0 {
            return Status::Inactive;
        }
        let v = slip_vector(lambda, self.ct[p], self.slip(p, jump));
        if self.mu[p] > 0.0 && norm2(v) < self.mu[p] * xi {
            Status::Stick
        } else {
            Status::Slip
        }
    }

    /// The linearised slip row of tangent t at the slipping point p, divided
    /// by ‖v‖ (module doc): coefficients of (z_n, z_τ₁, z_τ₂) and of the
    /// tangential jumps (τ₁, τ₂), and the right-hand side.
    fn slip_row(&self, p: usize, t: usize, jump: [f64; 3], z: [f64; 3]) -> ([f64; 3], [f64; 2], f64) {
        let d = self.points[p].d;
        let lambda = z.map(|z| z / d);
        let v = slip_vector(lambda, self.ct[p], self.slip(p, jump));
        let nv = norm2(v);
        let vh = [v[0] / nv, v[1] / nv];
        let (m, ln, c) = (self.mu[p], lambda[0], self.ct[p]);
        let lt = [lambda[1], lambda[2]];
        let (mut on_z, mut on_jump) = ([0.0; 3], [0.0; 2]);
        // − μ v_t λ_n'
        on_z[0] = -m * v[t] / (d * nv);
        let mut rhs = (nv * lt[t] - m * ln * v[t]) / nv;
        for q in (0..2).filter(|&q| self.free_tangent[p][q]) {
            // (‖v‖ δ + λ_τ,t v̂ᵀ − μ λ_n δ) λ_τ'
            let l1 = (if q == t { nv - m * ln } else { 0.0 }) + lt[t] * vh[q];
            on_z[q + 1] = l1 / (d * nv);
            // c (λ_τ,t v̂ᵀ − μ λ_n δ) s'
            let l2 = c * (lt[t] * vh[q] - if q == t { m * ln } else { 0.0 });
            on_jump[q] = l2 / nv;
            rhs += l2 * self.before[p][q] / nv;
        }
        (on_z, on_jump, rhs)
    }
}

/// What a Newton iteration gives: u, the glued multipliers, z per contact
/// point, the sets and the iterations.
type Newton = (Vec<f64>, Vec<f64>, Vec<[f64; 3]>, Vec<Status>, Vec<ActiveSetStep>);

/// The bookkeeping of one Newton iteration: the step record, and whether
/// the iteration stops (the sets repeat, the step was solved to the
/// solver's tolerance, `tight`, and the update is below
/// [`NEWTON_TOLERANCE`], or below [`ROUND_OFF_FLOOR`] and no longer halving).
fn record(
    status: &mut Vec<Status>,
    new_status: Vec<Status>,
    (change, linear_iterations, tight): (f64, usize, bool),
    steps: &mut Vec<ActiveSetStep>,
    max_steps: usize,
) -> Result<bool, ProblemError> {
    let changed = |now: bool| {
        let inactive = |s: &Status| *s == Status::Inactive;
        new_status.iter().zip(status.iter()).filter(|(n, o)| inactive(n) == now && inactive(o) != now).count()
    };
    let (added, removed) = (changed(false), changed(true));
    let switched = new_status.iter().zip(status.iter()).filter(|(n, o)| n != o).count();
    let settled = switched == 0;
    // Stagnating at the round-off of the solves: the update no longer halves.
    let stagnating = steps.last().is_some_and(|s| change <= ROUND_OFF_FLOOR && change > 0.5 * s.residual);
    steps.push(ActiveSetStep {
        active: status.iter().filter(|&&s| s != Status::Inactive).count(),
        added,
        removed,
        linear_iterations,
        full_tolerance: tight,
        residual: change,
    });
    *status = new_status;
    if settled && tight && (change <= NEWTON_TOLERANCE || stagnating) {
        return Ok(true);
    }
    if steps.len() >= max_steps {
        return Err(ProblemError::FrictionNotConverged {
            steps: steps.len(),
            changed: switched,
            update: change,
        });
    }
    Ok(false)
}

/// The Newton iteration on the whole system over (u, λ_g, z)
/// ([`newton_system`]), from u and z at the end of the last step.
#[allow(clippy::type_complexity)]
fn assembled_newton(
    law: &Law,
    (k, f, dirichlet, constraints): (&CsrMatrix, &[f64], &Dirichlet, &Constraints),
    rows: &[[SparseRow; 3]],
    (u_prev, z_prev, mut status): (&[f64], &[[f64; 3]], Vec<Status>),
    (solver, max_steps): (Solver, usize),
    summary: &mut PetscSummary,
    seconds: &mut Timings,
) -> Result<Newton, ProblemError> {
    let (n, n_glue, points) = (k.nrows, constraints.rows.len(), law.points);
    let z0 = n + n_glue;
    let mut x = vec![0.0; z0 + 3 * points.len()];
    x[..n].copy_from_slice(u_prev);
    for (p, z) in z_prev.iter().enumerate() {
        x[z0 + 3 * p..z0 + 3 * p + 3].copy_from_slice(z);
    }
    // Ordering groups of the unknowns (u, λ_g, z): the point of a dof, the
    // slave point of a multiplier.
    let groups: Vec<usize> = (0..n)
        .map(|i| i / 3)
        .chain(constraints.rows.iter().map(|r| r.dof / 3))
        .chain(points.iter().flat_map(|c| [c.first_dof / 3; 3]))
        .collect();
    let at = |x: &[f64], p: usize| -> ([f64; 3], [f64; 3]) {
        let jump = rows[p].each_ref().map(|row| row.iter().map(|&(j, a)| a * x[j]).sum());
        (jump, std::array::from_fn(|k| x[z0 + 3 * p + k]))
    };
    let mut steps = Vec::new();
    loop {
        let clock = Instant::now();
        let jz: Vec<([f64; 3], [f64; 3])> = (0..points.len()).map(|p| at(&x, p)).collect();
        let (a, b, coupled) = newton_system((k, f, constraints), law, rows, &status, &jz);
        seconds.setup += clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let n_active = status.iter().filter(|&&s| s != Status::Inactive).count();
        let solved = match solver {
            Solver::Direct => nearly_saddle((&a, &b, n), dirichlet, &coupled, &groups),
            _ => solver.solve_general(&a, &b, dirichlet, (Some(&x), &[]), summary),
        };
        let (next, linear_iterations) = solved.map_err(|e| match e {
            SolveError::Singular => ProblemError::SingularStep { step: steps.len() + 1, active: n_active },
            e => ProblemError::Solve(e),
        })?;
        seconds.solve += clock.elapsed().as_secs_f64();
        let change = relative_change(&x[..n], &next[..n]).max(relative_change(&x[z0..], &next[z0..]));
        x = next;
        let new_status =
            (0..points.len()).map(|p| at(&x, p)).enumerate().map(|(p, (j, z))| law.status(p, j, z));
        if record(
            &mut status,
            new_status.collect(),
            (change, linear_iterations, true),
            &mut steps,
            max_steps,
        )? {
            break;
        }
    }
    let z = (0..points.len()).map(|p| at(&x, p).1).collect();
    Ok((x[..n].to_vec(), x[n..z0].to_vec(), z, status, steps))
}

/// The glued interfaces' multipliers at u and the contact multipliers z:
/// λ_r = (f − K u − Σ_p Gᵀ_p z_p)_{dof r} / C_{r, dof r} (the slave rows of
/// the saddle point; C_S diagonal when the glue is eliminated).
fn glued_multipliers(
    (k, f, constraints): (&CsrMatrix, &[f64], &Constraints),
    rows: &[[SparseRow; 3]],
    u: &[f64],
    z: &[[f64; 3]],
) -> Vec<f64> {
    let mut r: Vec<f64> = f.iter().zip(k.mul_vec(u, 1)).map(|(f, ku)| f - ku).collect();
    for (row, z) in rows.iter().zip(z) {
        for (g, &zk) in row.iter().zip(z) {
            g.iter().for_each(|&(j, a)| r[j] -= a * zk);
        }
    }
    constraints.rows.iter().enumerate().map(|(i, row)| r[row.dof] / constraints.c.get(i, row.dof)).collect()
}

/// A system in the unknowns y left by the elimination of the glued
/// interfaces (u = P_g y; y = u without glued interfaces).
#[derive(Clone, Copy)]
struct Eliminated<'a> {
    k: &'a CsrMatrix,
    f: &'a [f64],
    dirichlet: &'a Dirichlet,
    /// P_g, if glued interfaces were eliminated.
    p_g: Option<&'a CsrMatrix>,
    /// Per dof: [`crate::constraints::NONE`] if eliminated.
    retained: Option<&'a [usize]>,
    /// The mesh points of all bodies (the rigid-body modes).
    points: &'a [Point3],
    /// offsets[b] = first dof of body b.
    offsets: &'a [usize],
}

/// The equation of a contact unknown (a jump of W) in a Newton step
/// (module doc).
#[derive(Clone, Copy, Debug)]
enum JumpRow {
    /// Equilibrium with z = 0 there (an inactive point).
    Free,
    /// The jump prescribed: the gap (an active normal), the last step's
    /// (a sticking tangent).
    Held(f64),
    /// The linearised slip row ([`Law::slip_row`]).
    Slip([f64; 3], [f64; 2], f64),
}

impl JumpRow {
    /// The equation of jump k (0 normal, 1–2 tangents) of point p at its
    /// `jump` and `z` with the set `status`.
    fn of(law: &Law, p: usize, k: usize, status: Status, (jump, z): ([f64; 3], [f64; 3])) -> JumpRow {
        match (status, k) {
            (Status::Inactive, _) => JumpRow::Free,
            (_, 0) => JumpRow::Held(law.points[p].gap),
            (Status::Stick, k) => JumpRow::Held(law.before[p][k - 1]),
            (Status::Slip, k) => {
                let (on_z, on_jump, rhs) = law.slip_row(p, k - 1, jump, z);
                JumpRow::Slip(on_z, on_jump, rhs)
            }
        }
    }
}

/// The jumps W of the rotated Newton iteration: W's index of each point's
/// jumps (normal, tangents), the point and jump of each entry of W, and its
/// dof.
#[derive(Clone, Copy)]
struct Jumps<'a> {
    slot: &'a [[Option<usize>; 3]],
    owner: &'a [(usize, usize)],
    dofs: &'a [usize],
    /// Per dof: its index in W, or `usize::MAX`.
    index: &'a [usize],
}

/// How the rotated Newton iteration solves its steps.
enum Steps<'a> {
    /// z_W = c − S w; a dense LU on W per step (the direct solver); the
    /// fingerprint of S ([`fingerprint`]).
    Condensed(Condensed<'a>, u64),
    /// The step's system in x alone, z_W = (b − A x)_W substituted, by a
    /// PETSc KSP with `options` (`ksp`, kept over the steps: [`KeptKsp`])
    /// from the last iterate `x`; `modes` the rigid-body modes in x.
    Reduced { x: Vec<f64>, modes: Vec<Vec<f64>>, options: PetscOptions, ksp: KeptKsp },
}

/// What the Newton iteration keeps for the next load step: the direct
/// solver's condensation, PETSc's system.
type Carried<'s> = (&'s mut Option<KeptCondensation>, &'s mut KeptKsp);

/// The Newton iteration in nodal frames with relative tangents
/// ([`rotation`]: the jumps of every contact point are unknowns of their
/// own, W), glued interfaces eliminated first (`system`). With the direct
/// solver condensed on W: A_OO (all others, the jumps held) is factored
/// once and z_W = c − S w ([`Condensed`], S kept in `cache` for the next
/// load step), each Newton step a dense LU on W. With PETSc reduced to x:
/// z_W = (b − A x)_W is substituted in the rows of W, so each step is a
/// system in x alone — the rows of A off W and at inactive points, x_W held
/// at the gap (active normals) and at the last step's jump (sticking
/// tangents), the linearised slip rows combining the point's rows of A
/// (not symmetric: FGMRES with GAMG), solved to 10⁻³ while the sets change
/// and to the solver's tolerance once they repeat; PETSc's system is `kept`
/// for the next load step.
fn rotated_newton(
    law: &Law,
    system: Eliminated,
    (jumps_prev, y_prev, mut status): (&[[f64; 3]], &[f64], Vec<Status>),
    (solver, max_steps, (cache, kept)): (Solver, usize, Carried),
    summary: &mut PetscSummary,
    seconds: &mut Timings,
) -> Result<Newton, ProblemError> {
    let clock = Instant::now();
    let (n, points) = (system.k.nrows, law.points);
    let relative: Vec<[bool; 2]> = (0..points.len()).map(|p| [0, 1].map(|t| law.frictional(p, t))).collect();
    let rotate = rotation(n, points, Some(&relative), system.p_g);
    let a = triple_product(&rotate, system.k);
    let b = rotate.transpose_mul_vec(system.f, 1);
    // W: per point its normal jump and its frictional tangential jumps.
    let mut slot: Vec<[Option<usize>; 3]> = vec![[None; 3]; points.len()];
    let (mut w_dofs, mut owner) = (Vec::new(), Vec::new());
    for (p, c) in points.iter().enumerate() {
        for k in (0..3).filter(|&k| k == 0 || relative[p][k - 1]) {
            slot[p][k] = Some(w_dofs.len());
            w_dofs.push(c.first_dof + k);
            owner.push((p, k));
        }
    }
    let mut index = vec![usize::MAX; n];
    for (i, &dof) in w_dofs.iter().enumerate() {
        index[dof] = i;
    }
    let jumps = Jumps { slot: &slot, owner: &owner, dofs: &w_dofs, index: &index };
    let held = rotated_dirichlet(n, system.dirichlet, points);
    // x = P⁻¹ y: y off the contact points; there the normal jump, the
    // relative tangents' jumps and the others' slave displacements.
    let to_x = |y: &[f64]| -> Vec<f64> {
        let mut x = y.to_vec();
        for (p, c) in points.iter().enumerate() {
            for (k, e) in c.frame.iter().enumerate() {
                let slave: f64 = (0..3).map(|j| e[j] * y[c.first_dof + j]).sum();
                let master = if slot[p][k].is_some() {
                    normal_row(&c.t_row, *e, system.p_g).iter().map(|&(j, v)| v * y[j]).sum()
                } else {
                    0.0
                };
                x[c.first_dof + k] = slave - master;
            }
        }
        x
    };
    let mut analysis = None;
    let mut steps_by = match solver {
        Solver::Direct => {
            let mut tied = held.clone();
            for &dof in &w_dofs {
                tied.fix_dof(dof, 0.0);
            }
            let key = fingerprint(&a, &w_dofs, &tied);
            let (held_by, known) = match cache.take().filter(|k| k.key == key) {
                Some(k) => (k.analysis, Some((k.values, k.s))),
                None => (CholeskyAnalysis::new(&a, &tied, &DirectOptions::default())?, None),
            };
            let condensed = Condensed::new(analysis.insert(held_by), &a, &b, &tied, (&w_dofs, known))
                .map_err(|e| match e {
                    SolveError::Singular => ProblemError::Unsupported { points: points.len() },
                    e => ProblemError::Solve(e),
                })?;
            Steps::Condensed(condensed, key)
        }
        Solver::Petsc(options) => {
            let modes = solver.near_nullspace(system.points, Some(system.offsets), system.retained, None);
            let modes = modes.iter().map(|m| to_x(m)).collect();
            Steps::Reduced { x: to_x(y_prev), modes, options, ksp: std::mem::take(kept) }
        }
        Solver::Pcg(_) => unreachable!("refused by Path::of"),
    };
    seconds.factorization += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let nw = w_dofs.len();
    // z_W, exactly 0 at inactive points (their rows say so): c − S w, or b − A x.
    let z_of = |steps_by: &Steps, w: &[f64], status: &[Status]| -> Vec<f64> {
        let mut z: Vec<f64> = match steps_by {
            Steps::Condensed(c, _) => {
                (0..nw).map(|i| c.c[i] - (0..nw).map(|j| c.s[(i, j)] * w[j]).sum::<f64>()).collect()
            }
            Steps::Reduced { x, .. } => w_dofs
                .iter()
                .map(|&dof| {
                    let (cols, vals) = a.row(dof);
                    b[dof] - cols.iter().zip(vals).map(|(&j, &v)| v * x[j]).sum::<f64>()
                })
                .collect(),
        };
        for p in (0..status.len()).filter(|&p| status[p] == Status::Inactive) {
            slot[p].iter().flatten().for_each(|&i| z[i] = 0.0);
        }
        z
    };
    let mut w = vec![0.0; nw];
    for (p, jump) in jumps_prev.iter().enumerate() {
        (0..3).for_each(|k| slot[p][k].into_iter().for_each(|i| w[i] = jump[k]));
    }
    let mut z = z_of(&steps_by, &w, &[]);
    let at = |v: &[f64], p: usize, fill: [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|k| slot[p][k].map_or(fill[k], |i| v[i]))
    };
    // Tangents off W: their jump is the last step's (no slip), z = 0.
    let jump_at = |w: &[f64], p: usize| at(w, p, [0.0, law.before[p][0], law.before[p][1]]);
    let mut steps = Vec::new();
    // The KSP's forcing: loose while the sets change, then shrinking with
    // the updates (the direct steps are exact).
    let mut forcing = match solver {
        Solver::Direct => 0.0,
        _ => super::LOOSE_RTOL,
    };
    loop {
        let rows: Vec<JumpRow> = owner
            .iter()
            .map(|&(p, k)| JumpRow::of(law, p, k, status[p], (jump_at(&w, p), at(&z, p, [0.0; 3]))))
            .collect();
        let (next, (linear_iterations, tight)) = match &mut steps_by {
            Steps::Condensed(c, _) => (condensed_step(c, &rows, jumps), (0, true)),
            Steps::Reduced { x, modes, options, ksp } => {
                let system = (&a, &b[..], &held);
                let solved = reduced_step(
                    system,
                    (&rows, jumps),
                    points,
                    (*options, forcing),
                    (x, modes, ksp),
                    summary,
                );
                let solved = solved.map_err(ProblemError::Solve)?;
                (w_dofs.iter().map(|&dof| x[dof]).collect(), solved)
            }
        };
        if next.iter().any(|v| !v.is_finite()) {
            let active = status.iter().filter(|&&s| s != Status::Inactive).count();
            return Err(ProblemError::SingularStep { step: steps.len() + 1, active });
        }
        let z_next = z_of(&steps_by, &next, &status);
        let change = relative_change(&w, &next).max(relative_change(&z, &z_next));
        (w, z) = (next, z_next);
        let new_status: Vec<Status> =
            (0..points.len()).map(|p| law.status(p, jump_at(&w, p), at(&z, p, [0.0; 3]))).collect();
        let settled = new_status == status;
        if record(&mut status, new_status, (change, linear_iterations, tight), &mut steps, max_steps)? {
            break;
        }
        if settled && forcing > 0.0 {
            forcing = (FORCING * change * change).min(super::LOOSE_RTOL);
        }
    }
    let y = match steps_by {
        Steps::Condensed(c, key) => {
            let y = c.expand(&a, &w);
            let (values, s) = c.into_kept();
            let analysis = analysis.take().expect("the direct solver's analysis");
            *cache = Some(KeptCondensation { key, analysis, values, s });
            y
        }
        Steps::Reduced { x, ksp, .. } => {
            *kept = ksp;
            x
        }
    };
    let u = rotate.mul_vec(&y, 1);
    seconds.solve += clock.elapsed().as_secs_f64();
    let z = (0..points.len()).map(|p| at(&z, p, [0.0; 3])).collect();
    Ok((u, Vec::new(), z, status, steps))
}

/// The next w of a condensed Newton step (`rows` the equations of the
/// `jumps`): z_W = c − S w substituted, a dense LU.
fn condensed_step(c: &Condensed, rows: &[JumpRow], Jumps { slot, owner, .. }: Jumps) -> Vec<f64> {
    let (s, c) = (&c.s, &c.c);
    let nw = rows.len();
    let mut j = Mat::<f64>::zeros(nw, nw);
    let mut r = Mat::<f64>::zeros(nw, 1);
    for (i, row) in rows.iter().enumerate() {
        match *row {
            JumpRow::Free => {
                (0..nw).for_each(|l| j[(i, l)] = s[(i, l)]);
                r[(i, 0)] = c[i];
            }
            JumpRow::Held(v) => {
                j[(i, i)] = 1.0;
                r[(i, 0)] = v;
            }
            JumpRow::Slip(on_z, on_jump, rhs) => {
                let p = owner[i].0;
                let mut rhs = rhs;
                for (kk, &a) in on_z.iter().enumerate() {
                    if let Some(m) = slot[p][kk] {
                        (0..nw).for_each(|l| j[(i, l)] -= a * s[(m, l)]);
                        rhs -= a * c[m];
                    }
                }
                for (q, &a) in on_jump.iter().enumerate() {
                    if let Some(m) = slot[p][q + 1] {
                        j[(i, m)] += a;
                    }
                }
                r[(i, 0)] = rhs;
            }
        }
    }
    // Equilibrated (rows, then columns, by their largest entries): the held
    // rows' 1 and the stiffness rows of S differ by orders of magnitude.
    let largest = |v: &mut dyn Iterator<Item = f64>| match v.fold(0.0f64, |m, x| m.max(x.abs())) {
        m if m > 0.0 => 1.0 / m,
        _ => 1.0,
    };
    for i in 0..nw {
        let f = largest(&mut (0..nw).map(|l| j[(i, l)]));
        (0..nw).for_each(|l| j[(i, l)] *= f);
        r[(i, 0)] *= f;
    }
    let columns: Vec<f64> = (0..nw).map(|l| largest(&mut (0..nw).map(|i| j[(i, l)]))).collect();
    for (l, &f) in columns.iter().enumerate() {
        (0..nw).for_each(|i| j[(i, l)] *= f);
    }
    let next = j.partial_piv_lu().solve(&r);
    (0..nw).map(|i| next[(i, 0)] * columns[i]).collect()
}

/// A reduced Newton step (`rotated_newton`): A x = b with the rows of the
/// `jumps` replaced by their equations `rows` — held jumps as prescribed
/// values besides `held`, each slip row Σ_k a_k A_{W(p,k)} − Σ_q c_q e_{W(p,q+1)}
/// = Σ_k a_k b_{W(p,k)} − r (z = b − A x in a·z + c·s = r), times d_p so
/// that it weighs as a row of A — solved by PETSc from `x` into `x`, `modes`
/// the near-nullspace, to the relative residual `forcing` (or the solver's
/// tolerance if that is looser, or if x already meets the forcing; no solve
/// if x meets that tolerance); returns the KSP iterations and whether the
/// solve was to the solver's tolerance.
fn reduced_step(
    (a, b, held): (&CsrMatrix, &[f64], &Dirichlet),
    (rows, jumps): (&[JumpRow], Jumps),
    points: &[ContactPoint],
    (options, forcing): (PetscOptions, f64),
    (x, modes, ksp): (&mut Vec<f64>, &[Vec<f64>], &mut KeptKsp),
    summary: &mut PetscSummary,
) -> Result<(usize, bool), SolveError> {
    let (n, Jumps { slot, owner, dofs: w_dofs, index: w_of }) = (a.nrows, jumps);
    let mut fixed = held.clone();
    let mut m = CsrMatrix::zeros(0, n);
    let mut rhs = b.to_vec();
    let mut row: Vec<(usize, f64)> = Vec::new();
    for i in 0..n {
        row.clear();
        let (cols, vals) = a.row(i);
        match w_of.get(i).and_then(|&wi| rows.get(wi).map(|r| (wi, *r))) {
            Some((wi, JumpRow::Slip(on_z, on_jump, r))) => {
                let p = owner[wi].0;
                let d = points[p].d;
                rhs[i] = -r;
                for (k, &c) in on_z.iter().enumerate() {
                    if let Some(m) = slot[p][k] {
                        let (cols, vals) = a.row(w_dofs[m]);
                        row.extend(cols.iter().zip(vals).map(|(&j, &v)| (j, c * v)));
                        rhs[i] += c * b[w_dofs[m]];
                    }
                }
                for (q, &c) in on_jump.iter().enumerate() {
                    if let Some(m) = slot[p][q + 1] {
                        row.push((w_dofs[m], -c));
                    }
                }
                row = super::frames::merged(&mut row);
                row.iter_mut().for_each(|e| e.1 *= d);
                rhs[i] *= d;
            }
            found => {
                if let Some((_, JumpRow::Held(v))) = found {
                    fixed.fix_dof(i, v);
                }
                row.extend(cols.iter().zip(vals).map(|(&j, &v)| (j, v)));
            }
        }
        m.indices.extend(row.iter().map(|e| e.0));
        m.values.extend(row.iter().map(|e| e.1));
        m.indptr.push(m.indices.len());
        m.nrows += 1;
    }
    // Both the forcing and the solver's rtol are relative to the
    // right-hand side (on the free rows, the prescribed values moved to the
    // right); a forcing above the residual at the start would leave x as it
    // is, so the solve is then to rtol.
    let mut start = x.clone();
    let mut is_fixed = vec![false; n];
    for (dof, v) in fixed.iter() {
        (start[dof], is_fixed[dof]) = (v, true);
    }
    let (mut r0, mut b0) = (0.0, 0.0);
    for i in (0..n).filter(|&i| !is_fixed[i]) {
        let (cols, vals) = m.row(i);
        let (mut ax, mut moved) = (0.0, 0.0);
        for (&j, &v) in cols.iter().zip(vals) {
            ax += v * start[j];
            if is_fixed[j] {
                moved += v * start[j];
            }
        }
        (r0, b0) = (r0 + (rhs[i] - ax).powi(2), b0 + (rhs[i] - moved).powi(2));
    }
    let relative = if b0 > 0.0 { (r0 / b0).sqrt() } else { 1.0 };
    if relative <= options.rtol {
        // x solves this step already (PETSc would stop before iterating).
        *x = start;
        return Ok((0, true));
    }
    let tight = forcing >= relative || forcing <= options.rtol;
    let step = PetscOptions { rtol: if tight { options.rtol } else { forcing }, ..options };
    // Set up anew when the held jumps change (refreshing costs iterations).
    let (next, iterations) =
        ksp.solve((&m, &rhs, &fixed), (Split::NearlySymmetric, modes, false), &step, Some(&x[..]), summary)?;
    *x = next;
    Ok((iterations, tight))
}

/// The semismooth Newton system at the jumps and z of every contact point
/// (`at`) with the sets `status` (module doc): [K C_gᵀ Gᵀ; C_g 0 0; N 0 Z]
/// over (u, λ_g, z), and per unknown whether its row is a linearised slip
/// row (the rest of the system is symmetric once the identity rows are
/// eliminated).
fn newton_system(
    (k, f, constraints): (&CsrMatrix, &[f64], &Constraints),
    law: &Law,
    rows: &[[SparseRow; 3]],
    status: &[Status],
    at: &[([f64; 3], [f64; 3])],
) -> (CsrMatrix, Vec<f64>, Vec<bool>) {
    let (n, points) = (k.nrows, law.points);
    let n_glue = constraints.rows.len();
    let z0 = n + n_glue;
    let size = z0 + 3 * points.len();
    let mut coupled = vec![false; size];
    let mut triplets: Vec<Vec<(usize, f64)>> = vec![Vec::new(); size];
    let mut b = vec![0.0; size];
    b[..n].copy_from_slice(f);
    for (i, row) in triplets.iter_mut().enumerate().take(n) {
        let (cols, vals) = k.row(i);
        row.extend(cols.iter().zip(vals).map(|(&j, &v)| (j, v)));
    }
    for i in 0..n_glue {
        let (cols, vals) = constraints.c.row(i);
        for (&j, &v) in cols.iter().zip(vals) {
            triplets[n + i].push((j, v));
            triplets[j].push((n + i, v));
        }
        b[n + i] = constraints.g[i];
    }
    for p in 0..points.len() {
        let zp = z0 + 3 * p;
        for (t, row) in rows[p].iter().enumerate() {
            for &(j, a) in row {
                triplets[j].push((zp + t, a));
            }
        }
        for k in 0..3 {
            let r = zp + k;
            // A tangent without friction carries z = 0, as an inactive point.
            let row = match k > 0 && !law.frictional(p, k - 1) {
                true => JumpRow::Free,
                false => JumpRow::of(law, p, k, status[p], at[p]),
            };
            match row {
                JumpRow::Free => triplets[r].push((r, 1.0)),
                JumpRow::Held(v) => {
                    triplets[r].extend(rows[p][k].iter().copied());
                    b[r] = v;
                }
                JumpRow::Slip(on_z, on_jump, rhs) => {
                    coupled[r] = true;
                    triplets[r].extend(on_z.iter().enumerate().map(|(k, &a)| (zp + k, a)));
                    for (q, &a) in on_jump.iter().enumerate().filter(|(_, &a)| a != 0.0) {
                        triplets[r].extend(rows[p][q + 1].iter().map(|&(j, g)| (j, a * g)));
                    }
                    b[r] = rhs;
                }
            }
        }
    }
    let mut a = CsrMatrix::zeros(0, size);
    for mut row in triplets {
        row.sort_unstable_by_key(|e| e.0);
        for (j, v) in super::frames::merged(&mut row) {
            a.indices.push(j);
            a.values.push(v);
        }
        a.indptr.push(a.indices.len());
        a.nrows += 1;
    }
    (a, b, coupled)
}

/// The Newton step x of `a` x = `b` with the values of `fixed` by
/// [`solve_nearly_saddle`], and its GMRES iterations: the prescribed dofs and
/// the identity rows of the multipliers (z = b there) leave the system,
/// `coupled` marks the slip rows, `groups` orders the unknowns (a multiplier
/// with its slave point); the first `n` unknowns are the displacements.
fn nearly_saddle(
    (a, b, n): (&CsrMatrix, &[f64], usize),
    fixed: &Dirichlet,
    coupled: &[bool],
    groups: &[usize],
) -> Result<(Vec<f64>, usize), SolveError> {
    let mut known = fixed.clone();
    for i in n..a.nrows {
        if a.row(i).0 == [i] && a.row(i).1 == [1.0] {
            known.fix_dof(i, b[i]);
        }
    }
    let (active, rhs) = free_system(a, b, &known, None)?;
    let (a_ff, free) = free_block(a, &active);
    let b_f: Vec<f64> = free.iter().map(|&i| rhs[i]).collect();
    let coupled_f: Vec<bool> = free.iter().map(|&i| coupled[i]).collect();
    let signs: Vec<i8> = free.iter().map(|&i| if i < n { 1 } else { -1 }).collect();
    let groups_f: Vec<usize> = free.iter().map(|&i| groups[i]).collect();
    let (x_f, iterations) = solve_nearly_saddle(&a_ff, &b_f, &coupled_f, &signs, &groups_f)?;
    let mut x = vec![0.0; a.nrows];
    for (dof, v) in known.iter() {
        x[dof] = v;
    }
    for (&i, v) in free.iter().zip(x_f) {
        x[i] = v;
    }
    Ok((x, iterations))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::multibody::{assemble_system, Operators};
    use crate::scene::{cattaneo_mindlin, CattaneoMindlin, Hertz, Layout};
    use crate::solution::SolveOptions;
    use seam::Multiplier;

    /// The Newton iteration condensed on the contact unknowns and the one on
    /// the whole system reach the same solution, load step after load step,
    /// on a partial slip (Cattaneo–Mindlin, coarse). (Their iterations may
    /// differ: the condensed one starts from z in equilibrium with the new
    /// load, the other from the last step's.)
    #[test]
    fn the_condensed_newton_iteration_is_the_assembled_one() {
        let p = CattaneoMindlin::default();
        // On tensor grids with lumped multipliers: the whole system's LDLᵀ
        // refines only to 1e-10 on the rings' thin outer layers.
        let hertz =
            Hertz { fine_cells: 3, layout: Layout::Tensor, multiplier: Multiplier::Lumped, ..p.hertz };
        let p = CattaneoMindlin { hertz, shear_steps: 2, ..p };
        let problem = cattaneo_mindlin(&p).unwrap();
        let options = SolveOptions::default();
        let interfaces = problem.coupled();
        let (mut condensed, mut assembled) = (FrictionState::default(), FrictionState::default());
        let mut slipped = 0;
        for &t in problem.steps.times() {
            let prepared = problem.loads_and_supports(t).unwrap();
            let bodies = problem.solver_bodies(&prepared);
            let mut seconds = Timings::default();
            let system =
                assemble_system(&bodies, &interfaces, (true, Operators::Here), &mut seconds).unwrap();
            let constraints =
                Constraints::new((&interfaces, &bodies), &system.mortars, &system.offsets, &system.dirichlet);
            assert!(constraints.rows.is_empty());
            let mut solve = |condense: bool, state: &mut FrictionState| {
                let path = if condense { Path::Condensed } else { Path::Assembled };
                let how = (options.solver, options.max_active_set_steps, path);
                frictional_step(&bodies, &interfaces, how, &system, &constraints, state, &mut seconds)
                    .unwrap()
            };
            let (a, fa) = solve(true, &mut condensed);
            let (b, fb) = solve(false, &mut assembled);
            assert_eq!(fa.status, fb.status, "t = {t}");
            let max = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |m, x| m.max(x.abs()));
            let u_scale = max(&mut a.u.iter().copied());
            let du = max(&mut a.u.iter().zip(&b.u).map(|(x, y)| x - y));
            assert!(du <= 1e-9 * u_scale, "t = {t}: u {du:e} of {u_scale:e}");
            let z = |s: &ContactSolve, f: &Friction| -> Vec<f64> {
                s.mu.iter().chain(f.tangential.iter().flatten()).copied().collect()
            };
            let (za, zb) = (z(&a, &fa), z(&b, &fb));
            let z_scale = max(&mut za.iter().copied());
            let dz = max(&mut za.iter().zip(&zb).map(|(x, y)| x - y));
            assert!(dz <= 1e-8 * z_scale, "t = {t}: z {dz:e} of {z_scale:e}");
            slipped += fa.status.iter().filter(|&&s| s == Status::Slip).count();
        }
        assert!(slipped > 0);
    }
}
