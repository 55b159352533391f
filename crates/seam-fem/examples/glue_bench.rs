//! Glued-elasticity benchmark: the warped-glue problem (paper Fig. 2 geometry,
//! `seam_fem::scene`) at growing sizes, h_s/h_m = 4, slave s × s × s hexes,
//! master 4s × 4s × 2s (graded towards the interface).
//!
//! ```text
//! cargo run --release -p seam-fem --example glue_bench                          # default table
//! cargo run --release -p seam-fem --example glue_bench -- --sizes 6,8 --solvers standard-direct
//! ```
//!
//! Solvers: `standard-direct` (saddle-point LDLᵀ), `dual-direct` (reduced
//! Cholesky, or LDLᵀ when the elimination fills in), `standard-pcg`,
//! `dual-pcg` (matrix-free PCG, rtol 1e-8), `dual-petsc` (CG + GAMG on the
//! reduced system) and `standard-petsc` (FGMRES + field split on the saddle
//! point), rtol 1e-8, which need `--features petsc`:
//!
//! ```text
//! cargo run --release -p seam-fem --features petsc --example glue_bench -- --sizes 10,16,22,31 --solvers dual-petsc
//! ```
//!
//! Every row runs in a fresh process (`--row s solver`), so the peak memory
//! (VmHWM) is its own.

mod common;

use common::{flag_sizes, flag_value, fresh_row, peak_mb, petsc, petsc_columns};
use seam::{Multiplier, Named};
use seam_fem::pcg::PcgOptions;
use seam_fem::scene::{warped_glue, WarpedGlue};
use seam_fem::{SolveOptions, Solver};
use std::time::Instant;

fn row(s: usize, solver: &str) {
    let (multiplier, method) = solver.split_once('-').expect("solver is multiplier-method");
    let multiplier = Multiplier::from_name(multiplier).unwrap_or_else(|e| panic!("{e}"));
    let solver = match method {
        "direct" => Solver::Direct,
        "pcg" => Solver::Pcg(PcgOptions { rtol: 1e-8, ..PcgOptions::default() }),
        "petsc" => petsc(1e-8),
        other => panic!("unknown method {other}"),
    };
    let clock = Instant::now();
    let params = WarpedGlue {
        slave_cells: s,
        ratio: 4,
        slave_layers: s,
        master_layers: 2 * s,
        multiplier,
        ..WarpedGlue::default()
    };
    let problem = warped_glue(&params).expect("valid scene");
    let meshing = clock.elapsed().as_secs_f64();
    let solution = problem.solve(&SolveOptions { solver, ..SolveOptions::default() }).expect("solvable");
    let total = clock.elapsed().as_secs_f64();
    let r = &solution.report;
    let t = &r.seconds;
    println!(
        "| {} | {} | {:.2} | {:.2} | {:.3} | {:.2} | {:.2} | {:.2} | {:.1} | {} | {:.0e} | {:.0} | {} | {} |",
        r.dofs,
        r.constraints,
        meshing,
        t.assembly,
        t.mortar,
        t.setup,
        t.factorization,
        t.solve,
        total,
        r.iterations,
        r.residual,
        peak_mb(),
        r.method,
        petsc_columns(r)
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() == 4 && args[1] == "--row" {
        row(args[2].parse().expect("size"), &args[3]);
        return;
    }
    let sizes = flag_sizes(&args, "--sizes", "6,8,10,12,15");
    let solvers = flag_value(&args, "--solvers", "standard-direct,dual-direct,standard-pcg,dual-pcg");
    println!(
        "| solver | dofs | constraints | meshing s | K s | mortar s | setup s | factor/PCG s | solve s | total s | iterations | residual | peak MB | method | KSP | KSP its | PETSc setup s | PETSc solve s |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &s in &sizes {
        for solver in solvers.split(',') {
            match fresh_row(&[&s.to_string(), solver]) {
                Ok(line) => println!("| {solver} {}", line.trim_start_matches('|').trim_start()),
                Err(why) => println!("| {solver} | s = {s} failed: {why} |"),
            }
        }
    }
}
