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
//! system is not symmetric, and is solved whole — u, the glued multipliers
//! and z — by sparse LU ([`Solver::solve_general`]). A point with μ = 0, or a
//! tangential axis that is prescribed at the slave point (a symmetry plane,
//! whose reaction takes the force), has λ_τ = 0 in that direction, so μ = 0
//! is frictionless contact. The iteration stops when the sets repeat and the
//! update of (u, z) is below [`NEWTON_TOLERANCE`] of their size; c = c_n in ξ is per point
//! the mean diagonal stiffness of its slave dofs over d_p, and c = c_t in v
//! a tenth of it ([`C_T`]).
//!
//! The first step starts with the points of the frictionless initial active
//! set ([`super::initial_active_set`]) in stick, so that a body held only by
//! contact and friction is held from the first iteration; every later step
//! starts from the last one's u and z.

use super::frames::{contact_points, normal_row, ContactPoint};
use super::{initial_active_set, kkt, length_scale, ContactSolve};
use crate::backend::{free_block, Solver};
use crate::constraints::Constraints;
use crate::multibody::{Body, Interface, ProblemError, System, Timings};
use crate::pcg::free_system;
use crate::petsc::PetscSummary;
use crate::saddle::solve_nearly_saddle;
use crate::solution::ActiveSetStep;
use crate::solve::Dirichlet;
use crate::solve::SolveError;
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

/// What a frictional solve carries from one load step to the next.
#[derive(Clone, Debug, Default)]
pub(crate) struct FrictionState {
    /// The displacements at the end of the last step (empty before the first).
    pub(crate) u: Vec<f64>,
    /// Per contact point, by (interface, slave point): z at the end of the
    /// last step (frame components) and the accumulated slip (Cartesian).
    pub(crate) points: BTreeMap<(usize, usize), ([f64; 3], Point3)>,
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
/// [`ProblemError::BadInterface`] for a slave surface with a basis
/// transformation (dual multipliers on second-order faces), a singular
/// Newton step, no convergence within `max_steps`, the LU's errors.
pub(crate) fn solve_frictional(
    bodies: &[Body],
    interfaces: &[Interface],
    (solver, max_steps): (Solver, usize),
    system: &System,
    constraints: &Constraints,
    state: &mut FrictionState,
    seconds: &mut Timings,
) -> Result<(ContactSolve, Friction), ProblemError> {
    let clock = Instant::now();
    if let Some(i) = (0..interfaces.len()).find(|&i| interfaces[i].friction > 0.0) {
        let what = match solver {
            Solver::Direct => None,
            Solver::Pcg(_) => {
                Some("friction needs a solver of nonsymmetric systems: not PCG; use the direct solver")
            }
            Solver::Petsc(_) => Some(
                "friction is solved by sparse LU (the direct solver) only: its PETSc solver (GMRES on the \
                 system with the contact multipliers condensed) is not implemented yet",
            ),
        };
        if let Some(what) = what {
            return Err(ProblemError::BadInterface { interface: i, what: what.to_string() });
        }
    }
    if let Some(i) =
        (0..interfaces.len()).find(|&i| system.mortars[i].basis.is_some() && interfaces[i].friction > 0.0)
    {
        let what =
            "friction on second-order slave faces with dual multipliers (Popp's transformed basis) is \
                    not implemented; use a first-order slave surface, or lumped multipliers on Quad9 faces"
                .to_string();
        return Err(ProblemError::BadInterface { interface: i, what });
    }
    let (k, f, dirichlet) = (&system.k, &system.f, &system.dirichlet);
    let n = k.nrows;
    let points = contact_points(bodies, interfaces, &system.mortars, &system.offsets, dirichlet, None)?;
    let np = points.len();
    let n_glue = constraints.rows.len();
    let (z0, size) = (n + n_glue, n + n_glue + 3 * np);
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
    let apply = |row: &SparseRow, u: &[f64]| row.iter().map(|&(j, a)| a * u[j]).sum::<f64>();
    let mu: Vec<f64> = points.iter().map(|c| interfaces[c.interface].friction).collect();
    // A tangential axis prescribed at the slave point carries no friction.
    let free_tangent: Vec<[bool; 2]> = points
        .iter()
        .map(|c| {
            std::array::from_fn(|t| {
                let e = c.frame[t + 1];
                !(0..3).any(|j| e[j].abs() == 1.0 && dirichlet.value(c.first_dof + j).is_some())
            })
        })
        .collect();
    let diagonal = |i: usize| {
        let (cols, vals) = k.row(i);
        cols.iter().zip(vals).find(|(&j, _)| j == i).map_or(0.0, |(_, &v)| v)
    };
    // c_n per point: the mean diagonal stiffness of its slave dofs over d_p;
    // c_t = C_T c_n (module doc).
    let cn: Vec<f64> =
        points.iter().map(|c| (0..3).map(|j| diagonal(c.first_dof + j)).sum::<f64>() / (3.0 * c.d)).collect();
    let ct: Vec<f64> = cn.iter().map(|c| C_T * c).collect();

    // The previous step: u, z, and the tangential relative displacement.
    let first = state.u.is_empty();
    let u_prev = if first { vec![0.0; n] } else { state.u.clone() };
    let tangential_prev: Vec<[f64; 2]> =
        rows.iter().map(|r| [apply(&r[1], &u_prev), apply(&r[2], &u_prev)]).collect();
    let mut x = vec![0.0; size];
    x[..n].copy_from_slice(&u_prev);
    for (p, c) in points.iter().enumerate() {
        if let Some((z, _)) = state.points.get(&(c.interface, c.point)) {
            x[z0 + 3 * p..z0 + 3 * p + 3].copy_from_slice(z);
        }
    }
    let initial = initial_active_set(&points, interfaces.len(), 1e-9 * length_scale(bodies));
    let status_of = |x: &[f64]| -> Vec<Status> {
        points
            .iter()
            .enumerate()
            .map(|(p, c)| {
                let z = &x[z0 + 3 * p..z0 + 3 * p + 3];
                let lambda = [z[0] / c.d, z[1] / c.d, z[2] / c.d];
                let xi = lambda[0] - cn[p] * (c.gap - apply(&rows[p][0], x));
                if xi <= 0.0 {
                    return Status::Inactive;
                }
                let v = slip_vector(
                    lambda,
                    ct[p],
                    [0, 1].map(|t| apply(&rows[p][t + 1], x) - tangential_prev[p][t]),
                );
                if mu[p] > 0.0 && norm2(v) < mu[p] * xi {
                    Status::Stick
                } else {
                    Status::Slip
                }
            })
            .collect()
    };
    let mut status: Vec<Status> = if first {
        initial.iter().map(|&on| if on { Status::Stick } else { Status::Inactive }).collect()
    } else {
        status_of(&x)
    };
    seconds.setup += clock.elapsed().as_secs_f64();

    // Ordering groups of the unknowns (u, λ_g, z): the point of a dof, the
    // slave point of a multiplier.
    let groups: Vec<usize> = (0..n)
        .map(|i| i / 3)
        .chain(constraints.rows.iter().map(|r| r.dof / 3))
        .chain(points.iter().flat_map(|c| [c.first_dof / 3; 3]))
        .collect();

    let mut summary = PetscSummary::default();
    let mut steps = Vec::new();
    loop {
        let clock = Instant::now();
        let (a, b, coupled) = newton_system(
            (k, f, constraints),
            (&points, &rows, &status),
            (&mu, &ct, &free_tangent),
            (&x, &tangential_prev),
        );
        seconds.setup += clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let n_active = status.iter().filter(|&&s| s != Status::Inactive).count();
        let solved = match solver {
            Solver::Direct => nearly_saddle((&a, &b, n), dirichlet, &coupled, &groups),
            _ => solver.solve_general(&a, &b, dirichlet, (Some(&x), &[]), &mut summary),
        };
        let (next, linear_iterations) = solved.map_err(|e| match e {
            SolveError::Singular => ProblemError::SingularStep { step: steps.len() + 1, active: n_active },
            e => ProblemError::Solve(e),
        })?;
        seconds.solve += clock.elapsed().as_secs_f64();
        let change = relative_change(&x[..n], &next[..n]).max(relative_change(&x[z0..], &next[z0..]));
        x = next;
        let new_status = status_of(&x);
        let added = new_status
            .iter()
            .zip(&status)
            .filter(|(n, o)| **n != Status::Inactive && **o == Status::Inactive)
            .count();
        let removed = new_status
            .iter()
            .zip(&status)
            .filter(|(n, o)| **n == Status::Inactive && **o != Status::Inactive)
            .count();
        let settled = new_status == status;
        steps.push(ActiveSetStep {
            active: n_active,
            added,
            removed,
            linear_iterations,
            full_tolerance: true,
            residual: change,
        });
        status = new_status;
        if settled && change <= NEWTON_TOLERANCE {
            break;
        }
        if steps.len() >= max_steps {
            return Err(ProblemError::ActiveSetNotSettled { steps: steps.len(), added, removed });
        }
    }

    let clock = Instant::now();
    let u = x[..n].to_vec();
    let lambda = x[n..z0].to_vec();
    let z: Vec<[f64; 3]> = (0..np).map(|p| std::array::from_fn(|k| x[z0 + 3 * p + k])).collect();
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
    let w: Vec<f64> = rows.iter().map(|r| apply(&r[0], &u)).collect();
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
            let s = [0, 1].map(|t| apply(&rows[p][t + 1], &u) - tangential_prev[p][t]);
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
        mu,
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
            Solver::Petsc(_) => "PETSc KSP (GMRES) per semismooth Newton step",
            _ => "sparse LU per semismooth Newton step",
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

/// The semismooth Newton system at the iterate `x` with the sets `status`
/// (module doc): [K C_gᵀ Gᵀ; C_g 0 0; N 0 Z] over (u, λ_g, z), and per
/// unknown whether its row is a linearised slip row (the rest of the
/// system is symmetric once the identity rows are eliminated).
#[allow(clippy::type_complexity)]
fn newton_system(
    (k, f, constraints): (&CsrMatrix, &[f64], &Constraints),
    (points, rows, status): (&[ContactPoint], &[[SparseRow; 3]], &[Status]),
    (mu, ct, free_tangent): (&[f64], &[f64], &[[bool; 2]]),
    (x, tangential_prev): (&[f64], &[[f64; 2]]),
) -> (CsrMatrix, Vec<f64>, Vec<bool>) {
    let n = k.nrows;
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
    let apply = |row: &SparseRow| row.iter().map(|&(j, a)| a * x[j]).sum::<f64>();
    for (p, c) in points.iter().enumerate() {
        let zp = z0 + 3 * p;
        for (t, row) in rows[p].iter().enumerate() {
            for &(j, a) in row {
                triplets[j].push((zp + t, a));
            }
        }
        let (normal, tangent) = (zp, [zp + 1, zp + 2]);
        let zero = |triplets: &mut Vec<Vec<(usize, f64)>>, r: usize| triplets[r].push((r, 1.0));
        match status[p] {
            Status::Inactive => (0..3).for_each(|t| zero(&mut triplets, zp + t)),
            _ => {
                triplets[normal].extend(rows[p][0].iter().copied());
                b[normal] = c.gap;
            }
        }
        let frictionless = mu[p] == 0.0;
        for t in 0..2 {
            if status[p] == Status::Inactive {
                continue;
            }
            if frictionless || !free_tangent[p][t] {
                zero(&mut triplets, tangent[t]);
            } else if status[p] == Status::Stick {
                triplets[tangent[t]].extend(rows[p][t + 1].iter().copied());
                b[tangent[t]] = tangential_prev[p][t];
            }
        }
        if status[p] != Status::Slip || frictionless {
            continue;
        }
        // The linearised slip rows, divided by ‖v‖ (module doc).
        let d = c.d;
        let lambda = [x[zp] / d, x[zp + 1] / d, x[zp + 2] / d];
        let s = [0, 1].map(|t| apply(&rows[p][t + 1]) - tangential_prev[p][t]);
        let v = slip_vector(lambda, ct[p], s);
        let nv = norm2(v);
        let vh = [v[0] / nv, v[1] / nv];
        let (m, ln, c_p) = (mu[p], lambda[0], ct[p]);
        let lt = [lambda[1], lambda[2]];
        for t in 0..2 {
            if !free_tangent[p][t] {
                continue;
            }
            let r = tangent[t];
            coupled[r] = true;
            // (‖v‖ δ + λ_τ,t v̂ᵀ − μ λ_n δ) λ_τ'
            for q in 0..2 {
                let l1 = (if q == t { nv - m * ln } else { 0.0 }) + lt[t] * vh[q];
                triplets[r].push((tangent[q], l1 / (d * nv)));
                // c (λ_τ,t v̂ᵀ − μ λ_n δ) G_τ,q u'
                let l2 = c_p * (lt[t] * vh[q] - if q == t { m * ln } else { 0.0 });
                triplets[r].extend(rows[p][q + 1].iter().map(|&(j, a)| (j, l2 * a / nv)));
                b[r] += l2 * tangential_prev[p][q] / nv;
            }
            // − μ v_t λ_n'
            triplets[r].push((normal, -m * v[t] / (d * nv)));
            b[r] += (nv * lt[t] - m * ln * v[t]) / nv;
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
