//! Friction benchmark and accuracy study: Cattaneo–Mindlin
//! ([`seam_fem::scene::cattaneo_mindlin`]: pressed in one load step, sheared to
//! Q = 0.5 μP in four) at growing sizes, each row in a fresh process so the
//! peak memory (VmHWM) is its own, with the direct solver (condensed on the
//! contact jumps).
//!
//! ```text
//! cargo run --release -p seam-fem --example friction_bench                 # n = 4, 6, 8
//! cargo run --release -p seam-fem --example friction_bench -- --sizes 10,12
//! ```
//!
//! `n`: slave cells across the fine zone [0, 1.5a], as for Hertz.

mod common;

use common::{flag_sizes, fresh_row, peak_mb};
use seam_fem::scene::{cattaneo_mindlin, CattaneoMindlin, Hertz};
use seam_fem::{solve_steps, SolveOptions};
use std::time::Instant;

fn row(n: usize) {
    let defaults = CattaneoMindlin::default();
    let p = CattaneoMindlin { hertz: Hertz { fine_cells: n, ..defaults.hertz }, shear_steps: 4, ..defaults };
    let clock = Instant::now();
    let problem = cattaneo_mindlin(&p).expect("valid scene");
    let (mut iterations, mut condense, mut newton, mut last) = (Vec::new(), 0.0, 0.0, None);
    for step in solve_steps(&problem, &SolveOptions::default()) {
        let (_, s) = step.expect("solvable");
        iterations.push(s.report.contact.as_ref().expect("contact").steps.len().to_string());
        condense += s.report.seconds.factorization;
        newton += s.report.seconds.solve;
        last = Some(s);
    }
    let total = clock.elapsed().as_secs_f64();
    let s = last.expect("load steps");
    let m = p.measure(&problem, &s);
    let c = s.report.contact.as_ref().expect("contact");
    println!(
        "| {} | {} | {} / {} | {} | {:.1} | {:.1} | {:.1} | {:.0} | {:+.2} % | {:+.2} % | {:.1} % |",
        s.report.dofs,
        c.contact_points,
        m.stick,
        m.slip,
        iterations.join(", "),
        condense,
        newton,
        total,
        peak_mb(),
        100.0 * (m.stick_radius / p.stick_radius() - 1.0),
        100.0 * (m.contact_radius / p.hertz.contact_radius - 1.0),
        100.0 * m.traction_error,
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() == 3 && args[1] == "--row" {
        row(args[2].parse().expect("size"));
        return;
    }
    println!(
        "| n | dofs | contact points | stick / slip | Newton iterations per load step | condensation s | Newton s | total s | peak MB | c error | a error | q L2 error |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for n in flag_sizes(&args, "--sizes", "4,6,8") {
        match fresh_row(&[&n.to_string()]) {
            Ok(line) => println!("| {n} {line}"),
            Err(why) => println!("| {n} | failed: {why} |"),
        }
    }
}
