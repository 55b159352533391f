//! Friction benchmark and accuracy study: Cattaneo–Mindlin
//! ([`seam_fem::scene::cattaneo_mindlin`]: pressed in one load step, sheared to
//! Q = 0.5 μP in `--shear-steps`, default 4) at growing sizes, each row in a
//! fresh process so the peak memory (VmHWM) is its own, with the direct
//! solver (condensed on the contact jumps) or with PETSc (`--solver petsc`,
//! `--features petsc`: FGMRES + GAMG per Newton step on the reduced
//! displacements, rtol 1e-10). Each row also solves the pressing step
//! frictionless (μ = 0: Hertz on the same mesh, the same solver, the
//! indenter's symmetry plane also held along x) and gives the ratio of the
//! whole frictional history to it.
//!
//! ```text
//! cargo run --release -p seam-fem --example friction_bench                 # n = 4, 6, 8
//! cargo run --release -p seam-fem --example friction_bench -- --sizes 12,16
//! cargo run --release -p seam-fem --features petsc --example friction_bench -- \
//!     --solver petsc --shear-steps 10 --sizes 8,14,18
//! ```
//!
//! `n`: slave cells radially across the band [0.55a, 1.1a] of the rings on
//! the block's top (the scene's [`seam_fem::scene::Layout::Rings`]);
//! `--master-ratio R`: the indenter's cells R× finer (default 1.3).

mod common;

use common::{flag_sizes, flag_value, fresh_row, named_solver, peak_mb};
use seam_fem::scene::{cattaneo_mindlin, CattaneoMindlin, Hertz};
use seam_fem::{solve_steps, SolveOptions, Support};
use std::time::Instant;

fn row(n: usize, solver: &str, shear_steps: usize, master_ratio: f64) {
    let options = SolveOptions { solver: named_solver(solver), ..SolveOptions::default() };
    let defaults = CattaneoMindlin::default();
    let hertz = Hertz { fine_cells: n, master_ratio, ..defaults.hertz };
    let p = CattaneoMindlin { hertz, shear_steps, ..defaults };
    let problem = cattaneo_mindlin(&p).expect("valid scene");
    // Hertz on the same mesh: the pressing step, frictionless, the
    // indenter's symmetry plane also held along x (friction alone holds the
    // indenter along x, and against turning about y, otherwise).
    let mut frictionless = problem.clone();
    frictionless.interfaces[0].friction = 0.0;
    let indenter = problem.supports.iter().find(|s| s.boundary.body == 0).expect("the indenter's y = 0");
    frictionless.supports.push(Support::new(indenter.boundary, [Some(0.0), None, None]));
    let clock = Instant::now();
    let hertz = solve_steps(&frictionless, &options).next().expect("a load step");
    hertz.expect("solvable");
    let hertz = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let (mut iterations, mut condense, mut newton, mut last) = (Vec::new(), 0.0, 0.0, None);
    let (mut ksp, mut pc_setup, mut ksp_solve) = (0, 0.0, 0.0);
    for step in solve_steps(&problem, &options) {
        let (_, s) = step.expect("solvable");
        iterations.push(s.report.contact.as_ref().expect("contact").steps.len().to_string());
        condense += s.report.seconds.factorization;
        newton += s.report.seconds.solve;
        if let Some(p) = &s.report.petsc {
            ksp += p.solves.iter().map(|s| s.iterations).sum::<usize>();
            (pc_setup, ksp_solve) = (pc_setup + p.setup_seconds, ksp_solve + p.solve_seconds);
        }
        last = Some(s);
    }
    let total = clock.elapsed().as_secs_f64();
    let s = last.expect("load steps");
    let m = p.measure(&problem, &s);
    let c = s.report.contact.as_ref().expect("contact");
    println!(
        "| {} | {} | {} / {} | {} | {} ({:.1} s + {:.1} s) | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.0} | {:+.2} % | {:+.2} % | {:.1} % |",
        s.report.dofs,
        c.contact_points,
        m.stick,
        m.slip,
        iterations.join(", "),
        ksp,
        pc_setup,
        ksp_solve,
        condense,
        newton,
        total,
        hertz,
        total / hertz,
        peak_mb(),
        100.0 * (m.stick_radius / p.stick_radius() - 1.0),
        100.0 * (m.contact_radius / p.hertz.contact_radius - 1.0),
        100.0 * m.traction_error,
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() == 6 && args[1] == "--row" {
        let (steps, ratio) = (args[4].parse().expect("shear steps"), args[5].parse().expect("master ratio"));
        row(args[2].parse().expect("size"), &args[3], steps, ratio);
        return;
    }
    let solver = flag_value(&args, "--solver", "direct");
    let shear_steps = flag_value(&args, "--shear-steps", "4");
    let ratio =
        flag_value(&args, "--master-ratio", &CattaneoMindlin::default().hertz.master_ratio.to_string());
    println!("solver {solver}, {shear_steps} shear steps, master {ratio}× finer");
    println!(
        "| n | dofs | contact points | stick / slip | Newton iterations per load step | KSP iterations (PC setup + KSP solve) | setup (condensation) s | Newton s | total s | frictionless Hertz s | ratio | peak MB | c error | a error | q L2 error |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for n in flag_sizes(&args, "--sizes", "4,6,8") {
        match fresh_row(&[&n.to_string(), &solver, &shear_steps, &ratio]) {
            Ok(line) => println!("| {n} {line}"),
            Err(why) => println!("| {n} | failed: {why} |"),
        }
    }
}
