//! Finite-deformation contact benchmark: the ironing example
//! ([`seam_fem::scene::ironing`]: a neo-Hookean indenter pressed into a
//! slab and slid three widths, 20 load steps) at growing sizes, each row in
//! a fresh process so that the peak memory (VmHWM) is its own, with the
//! direct solver or with PETSc (`--solver petsc`, `--features petsc`: each
//! Newton step by FGMRES with the Schur-complement field split, GAMG on the
//! displacements, rtol 1e-10). Each row also times one linear solve of the
//! same mesh by the same solver, assembly included (as a Newton iteration
//! includes its tangent's): both bodies in small strain under the
//! example's supports, without the interface.
//!
//! ```text
//! cargo run --release -p seam-fem --example ironing_bench                    # n = 4, 6
//! cargo run --release -p seam-fem --features petsc --example ironing_bench -- \
//!     --solver petsc --sizes 12 --friction 0.3
//! ```
//!
//! `n`: slab cells per unit length (6n × 2n × n), the indenter 2n × 2n × n;
//! `--friction μ` (default 0); `--first K`: only the first K load steps (a
//! measure of the cost per iteration where the whole history is too long).

mod common;

use common::{flag_sizes, flag_value, fresh_row, named_solver, peak_mb};
use seam_fem::scene::{ironing, Ironing};
use seam_fem::{solve_steps, Law, SolveOptions};
use std::time::Instant;

fn row(n: usize, solver: &str, friction: f64, first: usize) {
    let options = SolveOptions { solver: named_solver(solver), ..SolveOptions::default() };
    let p = Ironing { cells: n, indenter_cells: 2 * n, friction, ..Ironing::default() };
    let problem = ironing(&p).expect("valid scene");
    // One linear solve of the same mesh: small strain, no interface.
    let mut linear = problem.clone();
    linear.interfaces.clear();
    linear.bodies.iter_mut().for_each(|b| b.law = Law::Linear);
    let clock = Instant::now();
    seam_fem::solve(&linear, &options).expect("solvable");
    let reference = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let (mut iterations, mut steps, mut ksp, mut unknowns, mut active, mut slave) = (0, 0, 0, 0, 0, 0);
    let mut in_petsc = 0.0;
    for step in solve_steps(&problem, &options).take(first) {
        let (_, s) = step.expect("solvable");
        steps += 1;
        iterations += s.report.newton.as_ref().expect("Newton").residuals.len();
        if let Some(p) = &s.report.petsc {
            ksp += p.solves.iter().map(|s| s.iterations).sum::<usize>();
            in_petsc += p.assembly_seconds + p.setup_seconds + p.solve_seconds;
        }
        unknowns = s.report.dofs;
        active = s.report.contact.as_ref().map_or(0, |c| c.active);
        slave = s.interfaces[0].contact.as_ref().map_or(0, |c| c.contact.iter().filter(|&&b| b).count());
    }
    let seconds = clock.elapsed().as_secs_f64();
    let per = seconds / iterations as f64;
    println!(
        "| {n} | {unknowns} | {slave} | {friction} | {steps} | {iterations} ({:.1}) | {active} | {ksp} | {seconds:.1} | \
         {in_petsc:.1} | {per:.2} | {reference:.2} | {:.1}× | {:.0} |",
        iterations as f64 / steps as f64,
        per / reference,
        peak_mb()
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let solver = flag_value(&args, "--solver", "direct");
    let friction: f64 = flag_value(&args, "--friction", "0").parse().expect("a number");
    let first: usize = flag_value(&args, "--first", &usize::MAX.to_string()).parse().expect("a count");
    if args.get(1).map(String::as_str) == Some("--row") {
        let n = flag_value(&args, "--n", "4").parse().expect("a size");
        row(n, &solver, friction, first);
        return;
    }
    println!("ironing, solver {solver}, μ = {friction}");
    println!(
        "| n | unknowns | slave points covered | μ | steps | Newton iterations (per step) | active at the end | KSP \
         iterations | s | in PETSc, s | s per iteration | one linear solve, s | ratio | peak MB |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for n in flag_sizes(&args, "--sizes", "4,6") {
        let (n, mu, first) = (n.to_string(), friction.to_string(), first.to_string());
        let args = ["--n", &n, "--solver", &solver, "--friction", &mu, "--first", &first];
        match fresh_row(&args) {
            Ok(line) => println!("{line}"),
            Err(e) => println!("| {n} | failed: {e} |"),
        }
    }
}
