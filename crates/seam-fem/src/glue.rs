//! Mortar gluing of linear-elastic bodies across non-matching interfaces (the
//! paper's first application).
//!
//! Bodies b = 1…N with stiffness K_b and load f_b are numbered one after the
//! other (`dof = offset_b + 3·point + component`). Each interface pairs a master
//! and a slave surface; its mortar matrices D (slave × slave) and B (slave ×
//! master), applied to each component, give the constraint (paper (3)₁)
//!
//! ```text
//! (D u_s − B u_m)_{p,c} = 0      for each covered slave point p and component c,
//! ```
//!
//! one row of C per constrained slave dof. The glued problem is the saddle point
//!
//! ```text
//! [ K  Cᵀ ] [ u ]   [ f ]
//! [ C  0  ] [ λ ] = [ 0 ]
//! ```
//!
//! with the Dirichlet conditions eliminated. A slave dof is constrained once: not
//! when it is prescribed, and only by the first interface that claims it (cross
//! points and crosslines), which keeps C of full row rank. The multipliers of
//! those dofs are not dropped but moved to their neighbours (Wohlmuth's
//! modified basis, see `Constraints::new`), so that constant tractions stay in
//! the multiplier space and patch tests hold with supports on the slave side.
//!
//! # Solvers
//! - Elimination (paper (3)₂): with dual or lumped multipliers every row of C
//!   eliminates its own slave dof, C = [C_S C_R] with C_S diagonal, so
//!   u_S = T u_R with T = −C_S⁻¹C_R and u = P u_R, P = [I; T]. The reduced
//!   system PᵀKP u_R = Pᵀf is symmetric positive definite.
//! - [`Solver::Direct`]: the reduced system by sparse Cholesky
//!   ([`crate::solve::solve`]) for dual and lumped multipliers, unless T
//!   would fill PᵀKP in (a slave side much coarser than the master side, or
//!   many interface rows against K's size, as in small meshes); with
//!   standard multipliers (C_S is the slave mass matrix, T is dense), or on
//!   fill-in, the saddle point itself by sparse LDLᵀ with iterative refinement
//!   ([`crate::saddle`]). [`crate::Report::method`] says which ran.
//! - [`Solver::Pcg`]: the reduced system by preconditioned conjugate
//!   gradients, matrix-free for any multiplier: P x needs C_S⁻¹, one sparse LU
//!   solve on the interface.
//! - [`Solver::Petsc`]: a PETSc KSP ([`crate::petsc`]) on the reduced system
//!   assembled in the numbering of all dofs (eliminated ones as identity
//!   rows, so the point blocks stay whole) for dual and lumped multipliers;
//!   on the saddle point for standard multipliers (or crosspoints), FGMRES
//!   with a Schur-complement field-split preconditioner (GAMG on the
//!   augmented K + γCᵀC). Under `mpirun` the ranks assemble and reduce the
//!   cells they own, so that neither K nor the system is ever whole on one
//!   rank ([`crate::partition`]).
//!
//! # Multipliers and tractions
//! The slave rows of the saddle point read (K u)_S + C_Sᵀ λ = f_S, so
//! λ = C_S⁻ᵀ (f − K u)_S. −λ is the traction the master exerts on the slave
//! (force per area); the resultant on the slave is −Σ_p (D λ)_p.

use crate::backend::Solver;
use crate::constraints::{full_prolongation, prolongation, triple_product};
use crate::constraints::{Constraints, Elimination, Solved, NONE, TIE};
use crate::multibody::{free_dofs_of, Body, ProblemError, System, Timings};
use crate::petsc::{augmented, rigid_body_modes_in, solve_petsc_from, Augmented};
use crate::petsc::{PetscOptions, PetscSummary, Split};
use crate::solution::InterfaceSolution;
use crate::solve::{solve, Dirichlet};
use seam::CsrMatrix;
use std::borrow::Cow;
use std::time::Instant;

/// The glued system solved: u, λ (one per row of C), the method, its
/// iterations, and the residual ([`crate::Report::residual`]).
pub(crate) struct Glued {
    pub u: Vec<f64>,
    pub lambda: Vec<f64>,
    pub method: &'static str,
    pub iterations: usize,
    pub residual: f64,
    pub petsc: Option<PetscSummary>,
}

/// Solves the glued problem (module doc): `system` (of `bodies`) with the
/// constraints of its glued interfaces. The PETSc solver of the reduced
/// system takes K out of `system` (module doc of [`crate::petsc`]);
/// `over_ranks`: it runs over MPI ranks, `system` without K, which the
/// ranks assemble ([`crate::partition`]).
pub(crate) fn solve_glued(
    bodies: &[Body],
    system: &mut System,
    constraints: &Constraints,
    (solver, over_ranks): (Solver, bool),
    seconds: &mut Timings,
) -> Result<Glued, ProblemError> {
    let free = free_dofs_of(bodies, &system.dirichlet);
    let diagonal = constraints.eliminated_block_is_diagonal();
    let mut summary = PetscSummary::default();
    let with_lambda = |(u, lambda, method, iterations): Solved| (u, Some(lambda), method, iterations);
    let (u, lambda, method, iterations) = {
        let System { k, f, dirichlet, .. } = &*system;
        match solver {
            Solver::Direct if diagonal && !constraints.elimination_fills_in(k) => {
                eliminated(k, f, dirichlet, constraints, seconds)?
            }
            Solver::Petsc(options) if over_ranks && diagonal => {
                reduced_over_ranks(bodies, system, constraints, &free, &options, seconds, &mut summary)?
            }
            Solver::Petsc(options) if over_ranks => with_lambda(saddle_over_ranks(
                bodies,
                system,
                constraints,
                &free,
                &options,
                seconds,
                &mut summary,
            )?),
            Solver::Petsc(options) if diagonal => {
                reduced_petsc(system, constraints, &options, seconds, &mut summary)?
            }
            // Standard multipliers, crosspoints, fill-in: the saddle point.
            _ => {
                let clock = Instant::now();
                let modes = solver.near_nullspace(&system.points, None, None, None);
                seconds.setup += clock.elapsed().as_secs_f64();
                let (k, f, dirichlet) = (&system.k, &system.f[..], &system.dirichlet);
                with_lambda(solver.solve_saddle(
                    (k, f, dirichlet),
                    constraints,
                    (None, &modes),
                    seconds,
                    &mut summary,
                )?)
            }
        }
    };
    let petsc = matches!(solver, Solver::Petsc(_)).then_some(summary);
    let clock = Instant::now();
    let ku = stiffness_times(bodies, system, &u)?;
    let lambda = lambda.unwrap_or_else(|| eliminated_multipliers(&ku, &system.f, constraints));
    let residual = residual(&ku, &free, &system.f, constraints, &u, &lambda);
    seconds.solve += clock.elapsed().as_secs_f64();
    Ok(Glued { u, lambda, method, iterations, residual, petsc })
}

/// u and the method of an eliminated solve, whose multipliers follow from
/// K u ([`eliminated_multipliers`]), or of a solve that gives them.
type Eliminated = (Vec<f64>, Option<Vec<f64>>, &'static str, usize);

/// K u: by K, or cell by cell ([`crate::assembly::stiffness_times`]) once
/// K has gone to make room for PETSc ([`reduced_petsc`]).
fn stiffness_times(bodies: &[Body], system: &System, u: &[f64]) -> Result<Vec<f64>, ProblemError> {
    if system.k.nrows == u.len() {
        return Ok(system.k.mul_vec(u, 1));
    }
    let mut ku = Vec::with_capacity(u.len());
    for (b, body) in bodies.iter().enumerate() {
        let u = &u[system.offsets[b]..system.offsets[b + 1]];
        let part = crate::assembly::stiffness_times(body.mesh, &body.material, u)
            .map_err(|source| ProblemError::Assembly { body: b, source })?;
        ku.extend(part);
    }
    Ok(ku)
}

/// Diagonal C_S (dual, lumped): u = P_g y with P_gᵀKP_g y = P_gᵀf assembled
/// in the numbering of all dofs and solved by PETSc, the rigid-body modes of
/// the points (zero at eliminated dofs) as near-nullspace. K leaves `system`
/// once reduced: PETSc's matrix and multigrid hierarchy take its place
/// (at 433k unknowns K is a quarter of the peak).
fn reduced_petsc(
    system: &mut System,
    constraints: &Constraints,
    options: &PetscOptions,
    seconds: &mut Timings,
    summary: &mut PetscSummary,
) -> Result<Eliminated, ProblemError> {
    let k = std::mem::replace(&mut system.k, CsrMatrix::zeros(0, 0));
    let System { f, dirichlet, .. } = &*system;
    let clock = Instant::now();
    let elimination = match constraints.rows.is_empty() {
        true => None,
        false => Some(Elimination::new(constraints, &k, f)?),
    };
    let modes =
        rigid_body_modes_in(&system.points, None, elimination.as_ref().map(|e| &e.retained[..]), None);
    // The reduced matrix goes to PETSc, which keeps the only copy while it solves.
    let (a, g, p) = match elimination {
        Some(e) => {
            drop(k);
            (Cow::Owned(e.k), Cow::Owned(e.f), Some(e.p))
        }
        None => (Cow::Owned(k), Cow::Borrowed(&f[..]), None),
    };
    seconds.setup += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let y = solve_petsc_from(a, &g, dirichlet, &modes, options, None, summary)?;
    seconds.factorization += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let u = match p {
        Some(p) => p.mul_vec(&y, 1),
        None => y,
    };
    seconds.solve += clock.elapsed().as_secs_f64();
    let iterations = summary.solves.iter().map(|s| s.iterations).sum();
    Ok((u, None, "PETSc KSP on the reduced system (u_s = T u_m)", iterations))
}

/// Diagonal C_S over MPI ranks ([`crate::partition`]): A y = b with
/// A = QᵀKQ, assembled by the ranks from their cells (Σ_e Q_eᵀ K_e Q_e) and
/// summed where its rows are, and b = Qᵀ(f − K w), the ranks
/// giving their Q_eᵀ K_e w_e; Q = P_g without the columns of prescribed,
/// eliminated and unused dofs (identity rows of A, zero in b), w = P_g ȳ
/// the prescribed values; u = P_g y.
fn reduced_over_ranks(
    bodies: &[Body],
    system: &System,
    constraints: &Constraints,
    free: &[bool],
    options: &PetscOptions,
    seconds: &mut Timings,
    summary: &mut PetscSummary,
) -> Result<Eliminated, ProblemError> {
    let clock = Instant::now();
    let (p, retained) = full_prolongation(constraints);
    let inactive: Vec<bool> = free.iter().zip(&retained).map(|(&free, &r)| !free || r == NONE).collect();
    let mut q = CsrMatrix::zeros(0, p.ncols);
    for i in 0..p.nrows {
        let (cols, vals) = p.row(i);
        for (&j, &v) in cols.iter().zip(vals).filter(|(&j, _)| !inactive[j]) {
            q.indices.push(j);
            q.values.push(v);
        }
        q.indptr.push(q.indices.len());
        q.nrows += 1;
    }
    let mut prescribed = vec![0.0; p.nrows];
    for (dof, v) in system.dirichlet.iter() {
        prescribed[dof] = v;
    }
    let w = p.mul_vec(&prescribed, 1);
    let modes = rigid_body_modes_in(&system.points, None, Some(&retained), None);
    let ranges = crate::partition::row_ranges(bodies, &q, (&|_| 0, 0), crate::petsc::petsc_ranks());
    seconds.setup += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let identity: Vec<_> = (0..q.nrows).filter(|&i| inactive[i]).map(|i| (i, i, 1.0)).collect();
    let qtkw = crate::partition::assemble_over_ranks(bodies, &ranges, (&q, &w), &identity)?;
    let mut b = q.transpose_mul_vec(&system.f, 1);
    for ((b, &kw), &inactive) in b.iter_mut().zip(&qtkw).zip(&inactive) {
        *b = if inactive { 0.0 } else { *b - kw };
    }
    seconds.assembly += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let mut y = crate::petsc::solve_staged_over_ranks(&ranges, &b, (Split::None, &modes), options, summary)?;
    seconds.factorization += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    for (dof, v) in system.dirichlet.iter() {
        y[dof] = v;
    }
    let u = p.mul_vec(&y, 1);
    seconds.solve += clock.elapsed().as_secs_f64();
    let iterations = summary.solves.iter().map(|s| s.iterations).sum();
    Ok((u, None, "PETSc KSP on the reduced system (u_s = T u_m), K assembled over the MPI ranks", iterations))
}

/// Standard multipliers (or crosspoints) over MPI ranks
/// ([`crate::partition`]): the saddle point of [`crate::petsc::solve_petsc_saddle`],
/// [K_γ Cᵀ; C 0] on the free dofs, K's entries assembled by the ranks from
/// their cells (Q the identity on the free dofs, w the prescribed values:
/// QᵀKQ and f − K w), C, γCᵀC and the identity rows of the other dofs
/// staged here; K's diagonal for γ from the cells at the constrained dofs.
fn saddle_over_ranks(
    bodies: &[Body],
    system: &System,
    constraints: &Constraints,
    free: &[bool],
    options: &PetscOptions,
    seconds: &mut Timings,
    summary: &mut PetscSummary,
) -> Result<Solved, ProblemError> {
    let clock = Instant::now();
    let n = system.f.len();
    let mut q = CsrMatrix::zeros(0, n);
    for (i, _) in free.iter().enumerate().filter(|(_, &free)| free) {
        q.indptr.resize(i + 1, q.indices.len());
        q.indices.push(i);
        q.values.push(1.0);
    }
    q.indptr.resize(n + 1, q.indices.len());
    q.nrows = n;
    let mut w = vec![0.0; n];
    for (dof, v) in system.dirichlet.iter() {
        w[dof] = v;
    }
    let constrained: Vec<bool> = {
        let mut on = vec![false; n];
        constraints.c.indices.iter().for_each(|&j| on[j] = free[j]);
        on
    };
    let diagonal = crate::partition::stiffness_diagonal(bodies, &constrained)?;
    let Augmented { c, g, ct, ctc, gamma } =
        augmented((&constraints.c, &constraints.g), free, &w, |i| diagonal[i])?;
    let m = c.nrows;
    let mut extra = Vec::with_capacity(n - q.indices.len() + ctc.nnz() + 2 * c.nnz());
    for i in 0..n {
        if !free[i] {
            extra.push((i, i, 1.0));
            continue;
        }
        let (cols, vals) = ctc.row(i);
        extra.extend(cols.iter().zip(vals).filter(|(&j, _)| free[j]).map(|(&j, &v)| (i, j, gamma * v)));
        let (rows, vals) = ct.row(i);
        extra.extend(rows.iter().zip(vals).map(|(&r, &v)| (i, n + r, v)));
    }
    for r in 0..m {
        let (cols, vals) = c.row(r);
        extra.extend(cols.iter().zip(vals).map(|(&j, &v)| (n + r, j, v)));
    }
    let modes = rigid_body_modes_in(&system.points, None, None, None);
    // Rows balanced with the constraints' entries, in points of 3 × 3
    // entries: γCᵀC and Cᵀ in the points' rows, C in the multipliers' (the
    // last rank's).
    let constraint_entries =
        |p: usize| (3 * p..3 * p + 3).map(|d| ctc.row(d).0.len() + ct.row(d).0.len()).sum::<usize>() / 9;
    let mut ranges = crate::partition::row_ranges(
        bodies,
        &q,
        (&constraint_entries, c.nnz() / 9),
        crate::petsc::petsc_ranks(),
    );
    *ranges.last_mut().expect("at least one rank") = n + m; // the multipliers' rows: the last rank's
    seconds.setup += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let kw = crate::partition::assemble_over_ranks(bodies, &ranges, (&q, &w), &extra)?;
    drop(extra);
    let ctg = ct.mul_vec(&g, 1);
    let mut b: Vec<f64> =
        (0..n).map(|i| if free[i] { system.f[i] - kw[i] + gamma * ctg[i] } else { 0.0 }).collect();
    b.extend_from_slice(&g);
    seconds.assembly += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let mut x =
        crate::petsc::solve_staged_over_ranks(&ranges, &b, (Split::Saddle(n), &modes), options, summary)?;
    seconds.factorization += clock.elapsed().as_secs_f64();
    let lambda = x.split_off(n);
    for (dof, v) in system.dirichlet.iter() {
        x[dof] = v;
    }
    let iterations = summary.solves.iter().map(|s| s.iterations).sum();
    Ok((x, lambda, "PETSc KSP on the saddle point (fieldsplit), K assembled over the MPI ranks", iterations))
}

/// λ_r = (f − Ku)_{dof r} / C_{r, dof r}: the slave rows of the saddle point
/// when C_S is diagonal.
fn eliminated_multipliers(ku: &[f64], f: &[f64], constraints: &Constraints) -> Vec<f64> {
    constraints
        .rows
        .iter()
        .enumerate()
        .map(|(r, row)| (f[row.dof] - ku[row.dof]) / constraints.c.get(r, row.dof))
        .collect()
}

/// Diagonal C_S (dual, lumped): u = P u_R with PᵀKP u_R = Pᵀf, by sparse
/// Cholesky.
fn eliminated(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    constraints: &Constraints,
    seconds: &mut Timings,
) -> Result<Eliminated, ProblemError> {
    let clock = Instant::now();
    let (p, retained) = prolongation(constraints);
    let a = triple_product(&p, k);
    let g = p.transpose_mul_vec(f, 1);
    let mut reduced = Dirichlet::new();
    for (dof, v) in dirichlet.iter() {
        reduced.fix_dof(retained[dof], v);
    }
    seconds.setup += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let u_r = solve(&a, &g, &reduced)?;
    seconds.factorization += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let u = p.mul_vec(&u_r, 1);
    seconds.solve += clock.elapsed().as_secs_f64();
    Ok((u, None, "reduced Cholesky (u_s = T u_m)", 0))
}

/// max(‖(f − Ku − Cᵀλ)_F‖ / ‖f_F‖, ‖Cu‖ / (‖C‖ ‖u‖)) in the max norm, F the
/// `free` dofs.
fn residual(
    ku: &[f64],
    free: &[bool],
    f: &[f64],
    constraints: &Constraints,
    u: &[f64],
    lambda: &[f64],
) -> f64 {
    let ctl = constraints.c.transpose_mul_vec(lambda, 1);
    let (mut r, mut scale) = (0.0f64, 0.0f64);
    for i in (0..ku.len()).filter(|&i| free[i]) {
        r = r.max((f[i] - ku[i] - ctl[i]).abs());
        scale = scale.max(f[i].abs()).max(ku[i].abs());
    }
    let equilibrium = if scale > 0.0 { r / scale } else { r };
    let cu = constraints.c.mul_vec(u, 1);
    let c_max = constraints.c.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let u_max = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let gap = cu.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let compatibility = if c_max * u_max > 0.0 { gap / (c_max * u_max) } else { gap };
    equilibrium.max(compatibility)
}

/// Adds the glued interfaces' tractions −λ per slave point and resultants
/// −Σ_p (Dλ)_p to `out` (one per interface), λ expanded in the unmodified
/// basis (a removed point p gets Σ_q λ_q / |Q_p|).
pub(crate) fn add_tractions(out: &mut [InterfaceSolution], constraints: &Constraints, lambda: &[f64]) {
    let row_sums: Vec<Vec<f64>> = out.iter().map(|s| s.mortar.d.row_sums()).collect();
    let rows = constraints.rows.iter().zip(&constraints.parts).zip(lambda);
    for ((row, part), &l) in rows.filter(|((row, _), _)| row.interface != TIE) {
        let s = &mut out[row.interface];
        s.constrained[row.point] = true;
        for &(p, w) in part {
            s.traction[p][row.component] -= w * l;
            s.force[row.component] -= w * l * row_sums[row.interface][p];
        }
    }
}
