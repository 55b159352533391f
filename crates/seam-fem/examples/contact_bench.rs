//! Contact benchmark: the Hertz and bulging-contact scenes
//! (`seam_fem::scene`) at growing sizes, each row in a fresh process so the
//! peak memory (VmHWM) is its own.
//!
//! ```text
//! cargo run --release -p seam-fem --example contact_bench                       # default table
//! cargo run --release -p seam-fem --example contact_bench -- --hertz 6,8 --bulging 12 --solvers direct
//! ```
//!
//! Sizes: Hertz `n` = slave cells across 1.5a (the fine zone; the meshes grade
//! out to 12.5a), bulging `n` = slave cells across (master 1.5× finer).
//! Solvers: `direct` (one Cholesky analysis, a numeric factorisation per
//! active-set step), `pcg` (point-block Jacobi PCG, rtol 1e-10, warm-started
//! from the previous step), `petsc` (CG + GAMG per step, rtol 1e-10,
//! warm-started; `--features petsc`).

mod common;

use common::{flag_sizes, flag_value, fresh_row, peak_mb, petsc, petsc_columns};
use seam_fem::pcg::PcgOptions;
use seam_fem::scene::{bulging_contact, hertz, BulgingContact, Hertz};
use seam_fem::Problem;
use seam_fem::SolveOptions;
use seam_fem::Solver;
use std::time::Instant;

fn row(scene: &str, n: usize, solver: &str) {
    let solver = match solver {
        "direct" => Solver::Direct,
        "pcg" => Solver::Pcg(PcgOptions { rtol: 1e-10, ..PcgOptions::default() }),
        "petsc" => petsc(1e-10),
        other => panic!("unknown solver {other}"),
    };
    let clock = Instant::now();
    let problem: Problem = match scene {
        "hertz" => hertz(&Hertz { fine_cells: n, ..Hertz::default() }).expect("valid scene"),
        "bulging" => {
            bulging_contact(&BulgingContact { cells: n, layers: n / 2, ..BulgingContact::default() })
                .expect("valid scene")
        }
        other => panic!("unknown scene {other}"),
    };
    let meshing = clock.elapsed().as_secs_f64();
    let solution = problem.solve(&SolveOptions { solver, ..SolveOptions::default() }).expect("solvable");
    let total = clock.elapsed().as_secs_f64();
    let r = &solution.report;
    let t = &r.seconds;
    let c = r.contact.as_ref().expect("a contact scene");
    let linear: usize = c.steps.iter().map(|s| s.linear_iterations).sum();
    let changes: usize = c.steps.iter().map(|s| s.added + s.removed).sum();
    println!(
        "| {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.1} | {:.0e} | {:.0} | {} |",
        r.dofs,
        c.contact_points,
        c.active,
        c.steps.len(),
        if linear > 0 { format!("{changes} / {linear}") } else { changes.to_string() },
        meshing,
        t.assembly,
        t.mortar,
        t.setup,
        t.factorization + t.solve,
        total,
        c.kkt.max(),
        peak_mb(),
        petsc_columns(r),
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() == 5 && args[1] == "--row" {
        row(&args[2], args[3].parse().expect("size"), &args[4]);
        return;
    }
    let scenes = [
        ("hertz", flag_sizes(&args, "--hertz", "4,6,8,10,12")),
        ("bulging", flag_sizes(&args, "--bulging", "12,20,28,36")),
    ];
    let solvers = flag_value(&args, "--solvers", "direct,pcg");
    println!(
        "| scene n | solver | dofs | contact points | active | steps | changes (/ linear its) | meshing s | K s | mortar s | setup s | solves s | total s | KKT | peak MB | KSP | KSP its | PETSc setup s | PETSc solve s |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (scene, list) in &scenes {
        for &n in list {
            for solver in solvers.split(',') {
                match fresh_row(&[scene, &n.to_string(), solver]) {
                    Ok(line) => println!("| {scene} {n} | {solver} {line}"),
                    Err(why) => println!("| {scene} {n} | {solver} | failed: {why} |"),
                }
            }
        }
    }
}
