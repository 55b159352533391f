//! `seam solve CASE.toml`: flags and the report; the pipeline (reading,
//! solving, writing; the files written) is [`seam_case::solve`].

use crate::args::SolveArgs;
use crate::Failure;
use anyhow::anyhow;
use seam_case::report::report;
use seam_case::solve::{LinearSolver, SolveOptions, Solved};
use seam_fem::Operators;

/// `pieces`: the pieces of each body's output (the MPI ranks; 1 writes
/// `<body>.vtu`, more `<body>.pvtu`); `operators`: how the interfaces'
/// operators are assembled (here, or over the ranks).
pub fn run(args: &SolveArgs, pieces: usize, operators: Operators) -> Result<(), Failure> {
    let solved = solve(args, pieces, operators)?;
    println!("seam solve {} → {}", args.case.display(), solved.out_dir.display());
    for line in report(&solved) {
        println!("  {line}");
    }
    Ok(())
}

/// Reads, checks, solves and writes the case ([`seam_case::solve::solve_case_to_output`])
/// on `--threads` worker threads.
pub fn solve(args: &SolveArgs, pieces: usize, operators: Operators) -> Result<Solved, Failure> {
    if let Some(problem) = seam_case::solve::rtol_problem(args.rtol) {
        return Err(anyhow!("--rtol {problem}").into());
    }
    let options = SolveOptions { solver: args.solver, rtol: args.rtol, pieces, operators };
    match (args.solver, &args.petsc_options) {
        (LinearSolver::Petsc, options) => seam_fem::petsc::initialize_petsc(options.as_deref().unwrap_or(""))
            .map_err(|e| anyhow!("--solver petsc: {e}"))?,
        (_, Some(_)) => return Err(anyhow!("--petsc-options needs --solver petsc").into()),
        (_, None) => {}
    }
    let pool = crate::assemble::thread_pool(args.threads)?;
    pool.install(|| seam_case::solve::solve_case_to_output(&args.case, &options, args.force))
}
