//! The `seam` command-line tool: argument parsing and glue, as in ripgrep:
//! parse the flags, call the library, print its report. The computation is in
//! `seam` (the maths), `seam-io` (the files), `seam-case` (case files and the
//! pipelines of `solve`, `assemble`, `transfer`, `check`) and `seam-examples`
//! (the built-in examples, the benchmark, the pictures).
//!
//! Exit codes: 0 = success; 1 = ran, but the meshes do not couple (no overlap;
//! for `solve`, an interface whose surfaces do not meet);
//! 2 = error (bad input, unwritable output, …); 3 = `check --strict` found
//! incomplete coverage or a violated invariant. Errors are one line on stderr,
//! and so are the notices of the output directories (waiting for another run
//! writing there, what was recovered from an interrupted one;
//! [`seam_case::output`]).
//!
//! The binary is [`run`] on the process's arguments; the Python wheel's `seam`
//! command calls the same function.
#![forbid(unsafe_code)]

mod args;
mod assemble;
mod bench;
mod check;
mod example;
mod solve;
mod transfer;

use args::{Cli, Command};
use clap::Parser;
#[cfg(feature = "mpi")]
use seam_case::ranks;
use std::ffi::OsString;

/// What went wrong, sorted by exit code (1, 2, 3).
pub use seam_case::Failure;

/// Runs `seam` with the command line `args` (the program name first, as
/// [`std::env::args_os`] gives it) and returns the exit code (module doc).
pub fn run<I, T>(args: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let args: Vec<OsString> = args.into_iter().map(Into::into).collect();
    // Under an MPI launcher: MPI for the whole run, and N > 1 ranks their own way.
    #[cfg(feature = "mpi")]
    let ranks = match ranks::launched().then(ranks::Ranks::initialize).transpose() {
        Ok(ranks) => ranks,
        Err(e) => return exit(Err(e)),
    };
    #[cfg(feature = "mpi")]
    if let Some(ranks) = ranks.as_ref().filter(|r| r.size() > 1) {
        return over_ranks(ranks, &args);
    }
    let cli = match Cli::try_parse_from(&args) {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    let code = exit(match cli.command {
        Command::Assemble(a) => assemble::run(&a),
        Command::Transfer(t) => transfer::run(&t),
        Command::Check(c) => check::run(&c),
        Command::Solve(s) => solve::run(&s, 1, seam_fem::Operators::Here),
        Command::Example(e) => example::run(&e),
        Command::Bench(b) => bench::run(&b),
        Command::BenchCase(c) => bench::run_case(&c),
        Command::BenchTransfer(t) => bench::run_transfer(&t),
    });
    // PETSc (if a solve started it) before MPI.
    #[cfg(feature = "mpi")]
    if let Some(ranks) = ranks {
        seam_fem::petsc::finalize_petsc();
        drop(ranks);
    }
    code
}

/// Under `mpirun -np N` with N > 1: `assemble` over the ranks ([`ranks`]),
/// and `solve --solver petsc` with PETSc's systems and the interfaces'
/// operators over them (rank 0 runs the pipeline and leads, the others follow
/// its PETSc calls and assemble their parts of each operator); every other
/// command is refused. Only rank 0 speaks.
#[cfg(feature = "mpi")]
fn over_ranks(ranks: &ranks::Ranks, args: &[OsString]) -> u8 {
    let quiet = 2;
    let command = match Cli::try_parse_from(args) {
        Ok(cli) => cli.command,
        Err(e) if ranks.rank() == 0 => return usage_error(e),
        Err(_) => return quiet,
    };
    match (command, ranks.rank()) {
        (Command::Assemble(a), 0) => exit(assemble::run_over_ranks(&a, ranks)),
        (Command::Assemble(a), _) => match assemble::global_pool(a.coupling.threads) {
            Ok(()) if ranks.work().is_ok() => 0,
            _ => quiet,
        },
        (Command::Solve(s), 0) => {
            seam_fem::petsc::lead_petsc();
            let result = match s.solver {
                seam_case::solve::LinearSolver::Petsc => {
                    solve::run(&s, ranks.size(), ranks::operators_over_ranks())
                }
                _ => Err(Failure::Error(format!(
                    "on {} MPI ranks `seam solve` needs --solver petsc (the other solvers run on one process)",
                    ranks.size()
                ))),
            };
            let code = exit(result);
            seam_fem::petsc::finalize_petsc(); // releases the other ranks
            code
        }
        (Command::Solve(s), _) => {
            // Rank 0 checks the thread count; a bad one is its error.
            let _ = assemble::global_pool(s.threads);
            let followed = ranks.follow();
            seam_fem::petsc::finalize_petsc();
            if followed.is_ok() {
                0
            } else {
                quiet
            }
        }
        (_, 0) => exit(Err(Failure::Error(format!(
            "only `seam assemble` and `seam solve --solver petsc` run over MPI ranks ({} here): run other commands without mpirun or with -np 1",
            ranks.size()
        )))),
        _ => quiet,
    }
}

/// The exit code of a command's result, its error as one line on stderr.
fn exit(result: Result<(), Failure>) -> u8 {
    match result {
        Ok(()) => 0,
        Err(e) => {
            let prefix = match e {
                Failure::NoCoupling(_) => "seam: ",
                Failure::CheckFailed(_) => "seam: check failed: ",
                Failure::Case(_) | Failure::Convergence(_) | Failure::Error(_) => "seam: error: ",
            };
            eprintln!("{prefix}{}", e.message());
            e.exit_code()
        }
    }
}

/// Help and version go to stdout as clap prints them (exit 0); a usage error
/// is one line on stderr, the first of clap's message, with exit code 2.
fn usage_error(e: clap::Error) -> u8 {
    use clap::error::ErrorKind;
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
        let _ = e.print();
        return 0;
    }
    // clap's message without the usage and the pointer to --help, on one line.
    let text = e.render().to_string();
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
        .filter(|l| !l.is_empty())
        .collect();
    let message = lines.join(" ");
    let message = message.strip_prefix("error: ").unwrap_or(&message);
    eprintln!("seam: error: {message} (see seam --help)");
    2
}
