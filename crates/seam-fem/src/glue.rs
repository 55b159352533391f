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
//!   would fill PᵀKP in (a slave side much coarser than the master side); with
//!   standard multipliers (C_S is the slave mass matrix, T is dense), or on
//!   fill-in, the saddle point itself by sparse LDLᵀ with iterative refinement
//!   ([`crate::saddle`]). [`crate::Report::method`] says which ran.
//! - [`Solver::Pcg`]: the reduced system by preconditioned conjugate
//!   gradients, matrix-free for any multiplier: P x needs C_S⁻¹, one sparse LU
//!   solve on the interface.
//!
//! # Multipliers and tractions
//! The slave rows of the saddle point read (K u)_S + C_Sᵀ λ = f_S, so
//! λ = C_S⁻ᵀ (f − K u)_S. −λ is the traction the master exerts on the slave
//! (force per area); the resultant on the slave is −Σ_p (D λ)_p.

use crate::multibody::{free_dofs, prolongation, retained_numbering, saddle_point, transposed_view};
use crate::multibody::{triple_product, Constraints, ProblemError, Solved, Solver, System, Timings, NONE};
use crate::pcg::{par_mul, pcg, BlockJacobi, PcgOptions};
use crate::solution::InterfaceSolution;
use crate::solve::{solve, Dirichlet, SolveError};
use faer::linalg::solvers::Solve;
use faer::Mat;
use seam::CsrMatrix;
use std::time::Instant;

/// The glued system solved: u, λ (one per row of C), the method, its
/// iterations, and the residual ([`crate::Report::residual`]).
pub(crate) struct Glued {
    pub u: Vec<f64>,
    pub lambda: Vec<f64>,
    pub method: &'static str,
    pub iterations: usize,
    pub residual: f64,
}

/// Solves the glued problem (module doc): `system` with the constraints of
/// its glued interfaces.
pub(crate) fn solve_glued(
    system: &System,
    constraints: &Constraints,
    solver: Solver,
    seconds: &mut Timings,
) -> Result<Glued, ProblemError> {
    let System { k, f, dirichlet, .. } = system;
    let diagonal = constraints.eliminated_block_is_diagonal();
    let (u, lambda, method, iterations) = match solver {
        Solver::Direct if diagonal && !constraints.elimination_fills_in(k) => {
            eliminated(k, f, dirichlet, constraints, seconds)?
        }
        Solver::Direct => saddle_point(k, f, dirichlet, constraints, seconds)?,
        Solver::Pcg(options) => matrix_free(k, f, dirichlet, constraints, &options, seconds)?,
    };
    let residual = residual(k, f, dirichlet, constraints, &u, &lambda);
    Ok(Glued { u, lambda, method, iterations, residual })
}

/// Diagonal C_S (dual, lumped): u = P u_R with PᵀKP u_R = Pᵀf, by sparse
/// Cholesky.
fn eliminated(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    constraints: &Constraints,
    seconds: &mut Timings,
) -> Result<Solved, ProblemError> {
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
    let ku = k.mul_vec(&u, 1);
    let lambda = constraints
        .rows
        .iter()
        .enumerate()
        .map(|(r, row)| (f[row.dof] - ku[row.dof]) / constraints.c.get(r, row.dof))
        .collect();
    seconds.solve += clock.elapsed().as_secs_f64();
    Ok((u, lambda, "reduced Cholesky (u_s = T u_m)", 0))
}

/// max(‖(f − Ku − Cᵀλ)_F‖ / ‖f_F‖, ‖Cu‖ / (‖C‖ ‖u‖)) in the max norm, F the free dofs.
fn residual(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    constraints: &Constraints,
    u: &[f64],
    lambda: &[f64],
) -> f64 {
    let ku = k.mul_vec(u, 1);
    let ctl = constraints.c.transpose_mul_vec(lambda, 1);
    let free = free_dofs(k, dirichlet);
    let (mut r, mut scale) = (0.0f64, 0.0f64);
    for i in (0..k.nrows).filter(|&i| free[i]) {
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
    for ((row, part), &l) in constraints.rows.iter().zip(&constraints.parts).zip(lambda) {
        let s = &mut out[row.interface];
        s.constrained[row.point] = true;
        for &(p, w) in part {
            s.traction[p][row.component] -= w * l;
            s.force[row.component] -= w * l * row_sums[row.interface][p];
        }
    }
}

/// PCG on PᵀKP, matrix-free (any multiplier): P x = [x; −C_S⁻¹C_R x] and
/// Pᵀy = y_R − C_Rᵀ C_S⁻ᵀ y_S with one sparse LU of C_S (interface-sized);
/// for C u = g (contact rows) u = P x + u_g with (u_g)_S = C_S⁻¹ g. The
/// Dirichlet dofs are eliminated as in [`solve_pcg`] (identity rows, zero
/// right-hand side), the preconditioner is K's point-block Jacobi.
pub(crate) fn matrix_free(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    constraints: &Constraints,
    options: &PcgOptions,
    seconds: &mut Timings,
) -> Result<Solved, ProblemError> {
    let clock = Instant::now();
    let n = k.nrows;
    let (retained, n_r) = retained_numbering(constraints);
    let reduction = Reduction::new(constraints, &retained, n_r)?;
    let mut active_r = vec![true; n_r];
    let mut lift = vec![0.0; n_r];
    for (dof, v) in dirichlet.iter() {
        active_r[retained[dof]] = false;
        lift[retained[dof]] = v;
    }
    let active = free_dofs(k, dirichlet);
    let mut u_g = vec![0.0; n];
    if constraints.g.iter().any(|&g| g != 0.0) {
        for (row, v) in constraints.rows.iter().zip(reduction.solve_cs(&constraints.g, false)) {
            u_g[row.dof] = v;
        }
    }
    // b = Pᵀ(f − K (P ū + u_g)) on the free retained dofs.
    let mut ku = vec![0.0; n];
    let lifted: Vec<f64> = reduction.apply_p(&lift).iter().zip(&u_g).map(|(a, b)| a + b).collect();
    par_mul(k, &lifted, &mut ku);
    let residual: Vec<f64> = f.iter().zip(&ku).map(|(a, b)| a - b).collect();
    let mut b = reduction.apply_pt(&residual);
    for (bi, &a) in b.iter_mut().zip(&active_r) {
        if !a {
            *bi = 0.0;
        }
    }
    let jacobi = BlockJacobi::new(k, &active, if n % 3 == 0 { 3 } else { 1 });
    seconds.setup += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let apply_a = |x: &[f64], y: &mut [f64]| {
        let mut kx = vec![0.0; n];
        par_mul(k, &reduction.apply_p(x), &mut kx);
        y.copy_from_slice(&reduction.apply_pt(&kx));
        for ((yi, xi), &a) in y.iter_mut().zip(x).zip(&active_r) {
            if !a {
                *yi = *xi;
            }
        }
    };
    let apply_m = |r: &[f64], z: &mut [f64]| {
        let mut full = vec![0.0; n];
        for (dof, &i) in retained.iter().enumerate() {
            if i != NONE {
                full[dof] = r[i];
            }
        }
        let mut out = vec![0.0; n];
        jacobi.apply(&full, &mut out);
        for (dof, &i) in retained.iter().enumerate() {
            if i != NONE {
                z[i] = out[dof];
            }
        }
    };
    let mut x = vec![0.0; n_r];
    let report = pcg(apply_a, apply_m, &b, &mut x, options.rtol, options.max_iter);
    if report.breakdown {
        return Err(SolveError::Singular.into());
    }
    if !report.converged {
        let (iterations, relative_residual) = (report.iterations, report.relative_residual);
        return Err(SolveError::NotConverged { iterations, relative_residual }.into());
    }
    seconds.factorization += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    for ((xi, l), &a) in x.iter_mut().zip(&lift).zip(&active_r) {
        if !a {
            *xi = *l;
        }
    }
    let u: Vec<f64> = reduction.apply_p(&x).iter().zip(&u_g).map(|(a, b)| a + b).collect();
    let mut ku = vec![0.0; n];
    par_mul(k, &u, &mut ku);
    let rest: Vec<f64> = constraints.rows.iter().map(|row| f[row.dof] - ku[row.dof]).collect();
    let lambda = reduction.solve_cs(&rest, true);
    seconds.solve += clock.elapsed().as_secs_f64();
    Ok((u, lambda, "reduced PCG, matrix-free (u_s = T u_m)", report.iterations))
}

/// C = [C_S C_R] split by eliminated (S) and retained (R) dofs, C_S factored.
struct Reduction<'a> {
    constraints: &'a Constraints,
    retained: &'a [usize],
    c_r: CsrMatrix,
    c_r_t: CsrMatrix,
    lu: faer::sparse::linalg::solvers::Lu<usize, f64>,
}

impl<'a> Reduction<'a> {
    fn new(constraints: &'a Constraints, retained: &'a [usize], n_r: usize) -> Result<Self, ProblemError> {
        let nc = constraints.rows.len();
        let mut c_s = CsrMatrix::zeros(0, nc);
        let mut c_r = CsrMatrix::zeros(0, n_r);
        for r in 0..nc {
            let (cols, vals) = constraints.c.row(r);
            for (&j, &v) in cols.iter().zip(vals) {
                match constraints.row_of[j] {
                    NONE => {
                        c_r.indices.push(retained[j]);
                        c_r.values.push(v);
                    }
                    l => {
                        c_s.indices.push(l);
                        c_s.values.push(v);
                    }
                }
            }
            for m in [&mut c_s, &mut c_r] {
                m.indptr.push(m.indices.len());
                m.nrows += 1;
            }
        }
        // Columns of C_S follow the row order of their eliminated dofs, which
        // increases with the dof within an interface; sort to be safe.
        for i in 0..c_s.nrows {
            let range = c_s.indptr[i]..c_s.indptr[i + 1];
            let mut pairs: Vec<(usize, f64)> = c_s.indices[range.clone()]
                .iter()
                .copied()
                .zip(c_s.values[range.clone()].iter().copied())
                .collect();
            pairs.sort_unstable_by_key(|p| p.0);
            for (k, (j, v)) in range.zip(pairs) {
                c_s.indices[k] = j;
                c_s.values[k] = v;
            }
        }
        let c_s_t = c_s.transpose();
        let lu = transposed_view(&c_s_t).sp_lu().map_err(|_| SolveError::Singular)?;
        let c_r_t = c_r.transpose();
        Ok(Reduction { constraints, retained, c_r, c_r_t, lu })
    }

    /// C_S⁻¹ w, or C_S⁻ᵀ w.
    fn solve_cs(&self, w: &[f64], transpose: bool) -> Vec<f64> {
        let mut x = Mat::<f64>::from_fn(w.len(), 1, |i, _| w[i]);
        if transpose {
            self.lu.solve_transpose_in_place(x.as_mut());
        } else {
            self.lu.solve_in_place(x.as_mut());
        }
        (0..w.len()).map(|i| x[(i, 0)]).collect()
    }

    /// u = P x.
    fn apply_p(&self, x: &[f64]) -> Vec<f64> {
        let mut u = vec![0.0; self.retained.len()];
        for (ui, &i) in u.iter_mut().zip(self.retained) {
            if i != NONE {
                *ui = x[i];
            }
        }
        let s = self.solve_cs(&self.c_r.mul_vec(x, 1), false);
        for (row, si) in self.constraints.rows.iter().zip(s) {
            u[row.dof] = -si;
        }
        u
    }

    /// z = Pᵀ y.
    fn apply_pt(&self, y: &[f64]) -> Vec<f64> {
        let y_s: Vec<f64> = self.constraints.rows.iter().map(|row| y[row.dof]).collect();
        let t = self.solve_cs(&y_s, true);
        let correction = self.c_r_t.mul_vec(&t, 1);
        let mut z = vec![0.0; self.c_r.ncols];
        for (&i, &yi) in self.retained.iter().zip(y) {
            if i != NONE {
                z[i] = yi;
            }
        }
        for (zi, c) in z.iter_mut().zip(correction) {
            *zi -= c;
        }
        z
    }
}
