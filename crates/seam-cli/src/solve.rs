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
    if args.petsc_options.is_some() && args.solver != LinearSolver::Petsc {
        return Err(anyhow!("--petsc-options needs --solver petsc").into());
    }
    let petsc_options = args.petsc_options.clone();
    let options = SolveOptions { solver: args.solver, petsc_options, rtol: args.rtol, pieces, operators };
    let pool = crate::assemble::thread_pool(args.threads)?;
    pool.install(|| seam_case::solve::solve_case_to_output(&args.case, &options, args.force))
}
