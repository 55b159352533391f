//! The `seam` binary: [`seam_cli::run`] on the process's arguments, its
//! notices of output directories on stderr.
#![forbid(unsafe_code)]

use std::process::ExitCode;

fn main() -> ExitCode {
    // Waiting for another run, or recovering an interrupted one: one line each.
    seam_case::output::set_notice_handler(|line| eprintln!("seam: {line}"));
    ExitCode::from(seam_cli::run(std::env::args_os()))
}
