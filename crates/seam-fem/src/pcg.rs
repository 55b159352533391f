//! Preconditioned conjugate gradients for symmetric positive definite systems.
//!
//! [`pcg`] is generic over the operator x ↦ A x and the preconditioner
//! r ↦ M⁻¹ r (both SPD), so it also serves matrix-free operators such as
//! Pᵀ K P. Starting from x₀, with r₀ = b − A x₀, z₀ = p₀ = M⁻¹ r₀:
//!
//! ```text
//! α_k = (r_k·z_k) / (p_k·A p_k),   x_{k+1} = x_k + α_k p_k,   r_{k+1} = r_k − α_k A p_k,
//! z_{k+1} = M⁻¹ r_{k+1},   β_k = (r_{k+1}·z_{k+1}) / (r_k·z_k),   p_{k+1} = z_{k+1} + β_k p_k,
//! ```
//!
//! until ‖r‖₂ ≤ rtol ‖b‖₂. The recursively updated r drifts from b − A x in
//! floating point, so convergence is confirmed with the true residual (and the
//! iteration restarted from it if that check fails). When a restart no longer
//! lowers the true residual, or has failed too often, round-off holds it above
//! rtol: the iteration stops (`stagnated`) rather than spend its iterations there.
//!
//! [`solve_pcg`] applies it to K u = f with Dirichlet conditions: on the free
//! dofs F it solves K_FF u_F = f_F − K_FD ū_D, written in the full dof space as
//! the operator that is K_FF on F and the identity elsewhere (right-hand side 0
//! there), so K is used as it is, without copying it.
//!
//! # Determinism
//! The products and reductions here give the same bits on any number of
//! threads: [`par_mul`] sums every row in its stored order, and dot products
//! add fixed-size chunks in a fixed order.
//!
//! # Preconditioners
//! Point-block Jacobi (the inverse of each point's 3 × 3 diagonal block) and the
//! scalar diagonal; both are parallel and deterministic. Iteration counts are
//! in [`Preconditioner`] (from `examples/solve_bench.rs`).

use crate::solve::{Dirichlet, SolveError};
use rayon::prelude::*;
use seam::CsrMatrix;

/// The failed confirmations (recursive residual below rtol, true one above)
/// after which [`pcg`] stops as stagnated, as it does at the first that does
/// not lower the true residual.
const MAX_FAILED_CONFIRMATIONS: usize = 8;

/// Chunk length of the deterministic parallel reductions and updates.
const CHUNK: usize = 4096;

/// Outcome of [`pcg`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PcgReport {
    /// Iterations done (operator applications, not counting the initial and
    /// confirming residuals).
    pub iterations: usize,
    /// ‖b − A x‖₂ / ‖b‖₂ at the end (0 when b = 0).
    pub relative_residual: f64,
    /// True when ‖b − A x‖₂ ≤ rtol ‖b‖₂.
    pub converged: bool,
    /// True when the iteration stopped because pᵀAp ≤ 0 or rᵀM⁻¹r < 0 (or a
    /// NaN appeared): A or M is not positive definite (e.g. A is singular).
    pub breakdown: bool,
    /// True when round-off holds the true residual above rtol: rtol is below
    /// what double precision reaches on this system.
    pub stagnated: bool,
}

impl PcgReport {
    /// The error of an iteration that did not converge: [`SolveError::Singular`]
    /// on a breakdown, [`SolveError::ToleranceUnreachable`] when it stagnated,
    /// else [`SolveError::NotConverged`]; `None` when it converged.
    pub fn error(&self, rtol: f64) -> Option<SolveError> {
        let (iterations, relative_residual) = (self.iterations, self.relative_residual);
        match (self.converged, self.breakdown, self.stagnated) {
            (true, ..) => None,
            (_, true, _) => Some(SolveError::Singular),
            (_, _, true) => Some(SolveError::ToleranceUnreachable { rtol, reached: relative_residual }),
            _ => Some(SolveError::NotConverged { iterations, relative_residual }),
        }
    }
}

/// x·y, summed by fixed chunks in a fixed order (the same bits on any number of
/// threads).
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    assert_eq!(x.len(), y.len(), "dot of vectors of different lengths");
    let partial: Vec<f64> = x
        .par_chunks(CHUNK)
        .zip(y.par_chunks(CHUNK))
        .map(|(a, b)| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>())
        .collect();
    partial.iter().sum()
}

/// y = K x, parallel over rows; every row is summed in its stored order, so the
/// result does not depend on the number of threads.
///
/// # Panics
/// If `x.len() != k.ncols` or `y.len() != k.nrows`.
pub fn par_mul(k: &CsrMatrix, x: &[f64], y: &mut [f64]) {
    assert_eq!(x.len(), k.ncols, "x must have one entry per column");
    assert_eq!(y.len(), k.nrows, "y must have one entry per row");
    y.par_chunks_mut(512).enumerate().for_each(|(c, ys)| {
        for (l, yi) in ys.iter_mut().enumerate() {
            let (cols, vals) = k.row(c * 512 + l);
            *yi = cols.iter().zip(vals).map(|(&j, &a)| a * x[j]).sum();
        }
    });
}

/// Preconditioned conjugate gradients for A x = b (module doc), from the
/// initial guess in `x`, which receives the solution.
///
/// `apply_a(p, y)` must set y = A p and `apply_m_inv(r, z)` set z = M⁻¹ r, with
/// A and M symmetric positive definite (on the space the iteration visits).
/// Stops when ‖b − A x‖₂ ≤ rtol ‖b‖₂ (`converged`), after `max_iter`
/// iterations, or on a breakdown (see [`PcgReport`]); never loops forever.
///
/// # Panics
/// If `x.len() != b.len()`.
pub fn pcg(
    apply_a: impl Fn(&[f64], &mut [f64]),
    apply_m_inv: impl Fn(&[f64], &mut [f64]),
    b: &[f64],
    x: &mut [f64],
    rtol: f64,
    max_iter: usize,
) -> PcgReport {
    let n = b.len();
    assert_eq!(x.len(), n, "x and b must have the same length");
    let b_norm = dot(b, b).sqrt();
    if b_norm == 0.0 {
        x.fill(0.0);
        return PcgReport { converged: true, ..PcgReport::default() };
    }
    let mut r = vec![0.0; n];
    let mut z = vec![0.0; n];
    let mut p = vec![0.0; n];
    let mut ap = vec![0.0; n];
    // r = b − A x, z = M⁻¹ r, p = z; returns (r·z, ‖r‖/‖b‖).
    let restart = |x: &[f64], r: &mut [f64], z: &mut [f64], p: &mut [f64], ap: &mut [f64]| {
        apply_a(x, ap);
        r.par_iter_mut().zip(b.par_iter().zip(ap.par_iter())).for_each(|(ri, (bi, ai))| *ri = bi - ai);
        apply_m_inv(r, z);
        p.copy_from_slice(z);
        (dot(r, z), dot(r, r).sqrt() / b_norm)
    };
    let (mut rz, mut res) = restart(x, &mut r, &mut z, &mut p, &mut ap);
    let mut iterations = 0;
    let report = |iterations, relative_residual, converged, breakdown, stagnated| PcgReport {
        iterations,
        relative_residual,
        converged,
        breakdown,
        stagnated,
    };
    // The true residual of the last failed confirmation, and their number.
    let (mut confirmed, mut failed) = (f64::INFINITY, 0);
    loop {
        if res.is_nan() || rz < 0.0 || rz.is_nan() {
            return report(iterations, res, false, true, false);
        }
        if res <= rtol {
            // Confirm with the true residual.
            let (rz_true, res_true) = restart(x, &mut r, &mut z, &mut p, &mut ap);
            if res_true <= rtol {
                return report(iterations, res_true, true, false, false);
            }
            failed += 1;
            if res_true >= confirmed || failed > MAX_FAILED_CONFIRMATIONS {
                return report(iterations, res_true.min(confirmed), false, false, true);
            }
            confirmed = res_true;
            (rz, res) = (rz_true, res_true);
            continue;
        }
        if iterations >= max_iter {
            return report(iterations, res, false, false, false);
        }
        apply_a(&p, &mut ap);
        let pap = dot(&p, &ap);
        if (rz == 0.0 || pap == 0.0) && res < f64::EPSILON {
            // r or p underflowed at a residual below round-off: the true one decides.
            let (_, res_true) = restart(x, &mut r, &mut z, &mut p, &mut ap);
            let converged = res_true <= rtol;
            return report(iterations, res_true, converged, false, !converged);
        }
        if pap.is_nan() || pap <= 0.0 || pap.is_infinite() {
            return report(iterations, res, false, true, false);
        }
        let alpha = rz / pap;
        x.par_chunks_mut(CHUNK).zip(p.par_chunks(CHUNK)).for_each(|(xs, ps)| {
            for (xi, pi) in xs.iter_mut().zip(ps) {
                *xi += alpha * pi;
            }
        });
        r.par_chunks_mut(CHUNK).zip(ap.par_chunks(CHUNK)).for_each(|(rs, aps)| {
            for (ri, ai) in rs.iter_mut().zip(aps) {
                *ri -= alpha * ai;
            }
        });
        apply_m_inv(&r, &mut z);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        p.par_chunks_mut(CHUNK).zip(z.par_chunks(CHUNK)).for_each(|(ps, zs)| {
            for (pi, zi) in ps.iter_mut().zip(zs) {
                *pi = zi + beta * *pi;
            }
        });
        iterations += 1;
        res = dot(&r, &r).sqrt() / b_norm;
    }
}

/// The preconditioner M of [`solve_pcg`].
///
/// Iterations to rtol 10⁻⁸ on the clamped unit-cube Hex8 block of
/// `solve_bench` (E = 1000, ν = 0.3), by free dofs: 30k: Jacobi 224,
/// point-block 220; 86k: 319 / 314; 305k: 489 / 483 (growing like h⁻¹, as
/// κ ~ h⁻²). The 3 × 3 blocks gain little on such well-shaped hexahedra; they
/// matter more for stretched cells and ν → ½.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Preconditioner {
    /// M = I.
    Identity,
    /// M = diag(K).
    Jacobi,
    /// M = the 3 × 3 diagonal block of each point (`dof = 3·point +
    /// component`), free components only; Jacobi when the size is not a
    /// multiple of 3.
    #[default]
    BlockJacobi,
}

/// Options of [`solve_pcg`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PcgOptions {
    /// Relative tolerance: stop when ‖r‖₂ ≤ rtol ‖b‖₂.
    pub rtol: f64,
    /// Iteration cap.
    pub max_iter: usize,
    /// The preconditioner.
    pub preconditioner: Preconditioner,
}

impl Default for PcgOptions {
    /// rtol 10⁻⁸, at most 20 000 iterations, point-block Jacobi.
    fn default() -> Self {
        PcgOptions { rtol: 1e-8, max_iter: 20_000, preconditioner: Preconditioner::BlockJacobi }
    }
}

/// A block-diagonal preconditioner z = D⁻¹ r with blocks of 1 or 3 dofs (the
/// diagonal, or the 3 × 3 blocks of the points), restricted to active dofs:
/// an inactive dof's row and column of D are those of the identity.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockJacobi {
    block: usize,
    inv: Vec<f64>,
}

impl BlockJacobi {
    /// D⁻¹ from the diagonal blocks of `k`. A block that is not positive
    /// definite falls back to the inverse of its diagonal (entries ≤ 0: 1).
    ///
    /// # Panics
    /// If `block` is not 1 or 3, `k.nrows` is not a multiple of it, or
    /// `active.len() != k.nrows`.
    pub fn new(k: &CsrMatrix, active: &[bool], block: usize) -> BlockJacobi {
        assert!(block == 1 || block == 3, "blocks of 1 or 3 dofs");
        assert_eq!(k.nrows % block, 0, "the size must be a multiple of the block");
        assert_eq!(active.len(), k.nrows, "one flag per dof");
        let nb = k.nrows / block;
        let bb = block * block;
        let mut inv = vec![0.0; nb * bb];
        inv.par_chunks_mut(bb).enumerate().for_each(|(p, out)| {
            let mut d = [0.0f64; 9];
            for a in 0..block {
                let i = block * p + a;
                for c in 0..block {
                    let j = block * p + c;
                    d[a * block + c] = if active[i] && active[j] {
                        k.get(i, j)
                    } else if i == j {
                        1.0
                    } else {
                        0.0
                    };
                }
            }
            let diag_inv = |v: f64| if v > 0.0 && v.is_finite() { 1.0 / v } else { 1.0 };
            if block == 1 {
                out[0] = diag_inv(d[0]);
            } else if let Some(m) = spd_inverse3(&d) {
                out.copy_from_slice(&m);
            } else {
                out.fill(0.0);
                for a in 0..3 {
                    out[4 * a] = diag_inv(d[4 * a]);
                }
            }
        });
        BlockJacobi { block, inv }
    }

    /// z = D⁻¹ r.
    ///
    /// # Panics
    /// If the lengths differ from the matrix size.
    pub fn apply(&self, r: &[f64], z: &mut [f64]) {
        let b = self.block;
        assert_eq!(r.len() * b, self.inv.len(), "r has the wrong length");
        assert_eq!(z.len(), r.len(), "z has the wrong length");
        z.par_chunks_mut(b * 1024).zip(r.par_chunks(b * 1024)).enumerate().for_each(|(c, (zs, rs))| {
            for (l, (zb, rb)) in zs.chunks_exact_mut(b).zip(rs.chunks_exact(b)).enumerate() {
                let m = &self.inv[(c * 1024 + l) * b * b..][..b * b];
                for a in 0..b {
                    zb[a] = (0..b).map(|c| m[a * b + c] * rb[c]).sum();
                }
            }
        });
    }
}

/// The inverse of a symmetric positive definite 3 × 3 matrix (row-major), or
/// None when it is not (numerically) positive definite.
fn spd_inverse3(d: &[f64; 9]) -> Option<[f64; 9]> {
    let (a, b, c, e, f, i) = (d[0], d[1], d[2], d[4], d[5], d[8]);
    // Leading minors (Sylvester's criterion).
    let m2 = a * e - b * b;
    let c00 = e * i - f * f;
    let c01 = c * f - b * i;
    let c02 = b * f - c * e;
    let det = a * c00 + b * c01 + c * c02;
    let scale = a.abs().max(e.abs()).max(i.abs());
    let positive = a > 0.0 && m2 > 1e-14 * scale * scale && det > 1e-14 * scale * scale * scale;
    if !positive || !det.is_finite() {
        return None;
    }
    let c11 = a * i - c * c;
    let c12 = b * c - a * f;
    let c22 = m2;
    let s = 1.0 / det;
    Some([c00 * s, c01 * s, c02 * s, c01 * s, c11 * s, c12 * s, c02 * s, c12 * s, c22 * s])
}

/// Solves K u = f with the Dirichlet conditions by preconditioned conjugate
/// gradients (module doc); returns the full u (prescribed values included)
/// and the report. Dofs with an empty row of K get u = 0 (or their prescribed
/// value), as in [`crate::solve::solve`]. The initial guess is u_F = 0, and the
/// tolerance is relative to ‖f_F − K_FD ū_D‖₂.
///
/// # Errors
/// [`SolveError::NotConverged`] at the iteration cap; [`SolveError::Singular`]
/// on a breakdown (K_FF not positive definite);
/// [`SolveError::ToleranceUnreachable`] when round-off holds the residual
/// above rtol; [`SolveError::Dimension`],
/// [`SolveError::DofOutOfRange`], [`SolveError::NonFiniteValue`] for
/// inconsistent input.
pub fn solve_pcg(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    options: &PcgOptions,
) -> Result<(Vec<f64>, PcgReport), SolveError> {
    solve_pcg_from(k, f, dirichlet, options, None)
}

/// The free dofs of K u = f with the values of `dirichlet` (rows of K that are
/// not empty and not prescribed) and b = f − K ū on them (0 elsewhere),
/// after checking the input (and the length of a start vector).
pub(crate) fn free_system(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    start: Option<&[f64]>,
) -> Result<(Vec<bool>, Vec<f64>), SolveError> {
    let n = k.nrows;
    if k.ncols != n || f.len() != n || start.is_some_and(|s| s.len() != n) {
        return Err(SolveError::Dimension { nrows: k.nrows, ncols: k.ncols, f_len: f.len() });
    }
    let mut prescribed = vec![0.0; n];
    let mut active: Vec<bool> = (0..n).map(|i| k.indptr[i + 1] > k.indptr[i]).collect();
    for (dof, v) in dirichlet.iter() {
        if dof >= n {
            return Err(SolveError::DofOutOfRange { dof, n_dofs: n });
        }
        if !v.is_finite() {
            return Err(SolveError::NonFiniteValue { dof });
        }
        prescribed[dof] = v;
        active[dof] = false;
    }
    let mut b = vec![0.0; n];
    par_mul(k, &prescribed, &mut b);
    b.par_iter_mut().zip(f.par_iter().zip(active.par_iter())).for_each(|(bi, (fi, &a))| {
        *bi = if a { fi - *bi } else { 0.0 };
    });
    Ok((active, b))
}

/// [`solve_pcg`] from the initial guess `start` (a full u; its prescribed
/// entries are ignored), e.g. the previous solution of a sequence of nearby
/// problems. The tolerance stays relative to ‖f_F − K_FD ū_D‖₂.
///
/// # Errors
/// As [`solve_pcg`]; [`SolveError::Dimension`] when `start` has another length.
pub fn solve_pcg_from(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    options: &PcgOptions,
    start: Option<&[f64]>,
) -> Result<(Vec<f64>, PcgReport), SolveError> {
    let n = k.nrows;
    let (active, b) = free_system(k, f, dirichlet, start)?;
    // A x = K x on the free rows (x vanishes on the others), x elsewhere.
    let apply_a = |x: &[f64], y: &mut [f64]| {
        par_mul(k, x, y);
        y.par_iter_mut().zip(x.par_iter().zip(active.par_iter())).for_each(|(yi, (xi, &a))| {
            if !a {
                *yi = *xi;
            }
        });
    };
    let block = match options.preconditioner {
        Preconditioner::BlockJacobi if n % 3 == 0 => 3,
        _ => 1,
    };
    let m = match options.preconditioner {
        Preconditioner::Identity => None,
        _ => Some(BlockJacobi::new(k, &active, block)),
    };
    let apply_m = |r: &[f64], z: &mut [f64]| match &m {
        Some(m) => m.apply(r, z),
        None => z.copy_from_slice(r),
    };
    let mut u: Vec<f64> = match start {
        Some(s) => s.iter().zip(&active).map(|(&v, &a)| if a { v } else { 0.0 }).collect(),
        None => vec![0.0; n],
    };
    let report = pcg(apply_a, apply_m, &b, &mut u, options.rtol, options.max_iter);
    if let Some(e) = report.error(options.rtol) {
        return Err(e);
    }
    for (dof, v) in dirichlet.iter() {
        u[dof] = v;
    }
    Ok((u, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{block, BlockKind, Grid, Side};
    use crate::{stiffness, traction, Material};

    fn problem(n: usize) -> (CsrMatrix, Vec<f64>, Dirichlet) {
        let mesh = block(n, n, n, |u, v, w| [u, v, w], BlockKind::Hex);
        let grid = Grid::new(n, n, n);
        let k = stiffness(&mesh, &Material::new(1000.0, 0.3).unwrap()).unwrap();
        let f = traction(&grid.side_faces(&mesh, Side::XMax).unwrap(), |_, _| [1.0, 0.3, -0.2]);
        let mut bc = Dirichlet::new();
        bc.clamp(grid.side_points(Side::XMin));
        bc.fix(grid.point(n, 0, 0), [None, Some(0.01), None]);
        (k, f, bc)
    }

    #[test]
    fn pcg_matches_the_direct_solve() {
        let (k, f, bc) = problem(4);
        let direct = crate::solve::solve(&k, &f, &bc).unwrap();
        let scale = direct.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for preconditioner in [Preconditioner::Identity, Preconditioner::Jacobi, Preconditioner::BlockJacobi]
        {
            let options = PcgOptions { rtol: 1e-10, max_iter: 1000, preconditioner };
            let (u, rep) = solve_pcg(&k, &f, &bc, &options).unwrap();
            assert!(rep.converged && rep.relative_residual <= 1e-10, "{rep:?}");
            let err = u.iter().zip(&direct).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(err <= 1e-7 * scale, "{preconditioner:?}: {err:e} vs {scale:e}");
            for (dof, v) in bc.iter() {
                assert_eq!(u[dof], v);
            }
        }
    }

    #[test]
    fn iteration_cap_is_an_error() {
        let (k, f, bc) = problem(3);
        let options = PcgOptions { rtol: 1e-12, max_iter: 3, preconditioner: Preconditioner::Jacobi };
        match solve_pcg(&k, &f, &bc, &options) {
            Err(SolveError::NotConverged { iterations, relative_residual }) => {
                assert_eq!(iterations, 3);
                assert!(relative_residual > 1e-12);
            }
            other => panic!("{other:?}"),
        }
        // A floating body: K_FF is singular and f is not balanced.
        let r = solve_pcg(&k, &f, &Dirichlet::new(), &PcgOptions { max_iter: 500, ..PcgOptions::default() });
        assert!(matches!(r, Err(SolveError::Singular | SolveError::NotConverged { .. })), "{r:?}");
    }

    /// A tolerance below round-off on a well-posed problem stops early and
    /// says so; it is not called singular.
    #[test]
    fn an_unreachable_tolerance_is_named_not_singular() {
        let (k, f, bc) = problem(3);
        for rtol in [1e-300, 1e-17] {
            let options = PcgOptions { rtol, ..PcgOptions::default() };
            match solve_pcg(&k, &f, &bc, &options) {
                Err(e @ SolveError::ToleranceUnreachable { reached, .. }) => {
                    assert!(reached > rtol && reached < 1e-12, "{e}");
                    let text = e.to_string();
                    assert!(text.contains("is below what double precision reaches on this system"), "{text}");
                }
                other => panic!("rtol {rtol:e}: {other:?}"),
            }
        }
    }

    #[test]
    fn generic_pcg_on_a_diagonal_and_zero_rhs() {
        let d = [1.0, 2.0, 4.0, 8.0];
        let b = [1.0, 1.0, 1.0, 1.0];
        let mut x = [0.0; 4];
        let a = |p: &[f64], y: &mut [f64]| {
            for i in 0..4 {
                y[i] = d[i] * p[i];
            }
        };
        let rep = pcg(a, |r, z| z.copy_from_slice(r), &b, &mut x, 1e-12, 10);
        assert!(rep.converged && rep.iterations <= 4, "{rep:?}");
        for i in 0..4 {
            assert!((x[i] - 1.0 / d[i]).abs() < 1e-12);
        }
        let mut x = [5.0; 4];
        let rep = pcg(a, |r, z| z.copy_from_slice(r), &[0.0; 4], &mut x, 1e-12, 10);
        assert_eq!((rep.iterations, x), (0, [0.0; 4]));
    }

    #[test]
    fn pcg_is_identical_on_one_and_two_threads() {
        let (k, f, bc) = problem(12);
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| solve_pcg(&k, &f, &bc, &PcgOptions::default()).unwrap())
        };
        let (u1, r1) = run(1);
        let (u2, r2) = run(2);
        assert_eq!(r1, r2);
        assert!(u1.iter().zip(&u2).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}
