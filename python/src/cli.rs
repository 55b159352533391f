//! The wheel's `seam` command: the command-line tool's code ([`seam_cli::run`])
//! in the Python process, so that `pip install` gives the same `seam` as
//! `cargo install`.

use pyo3::prelude::*;
use std::ffi::OsString;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// `_seam.cli(argv)`: runs `seam` with the command line `argv` (the program
/// name first), GIL released, and returns its exit code; the notices of
/// output directories go to stderr as the binary prints them, and a panic (a
/// bug) is exit code 101, as the binary's.
#[pyfunction]
pub fn cli(py: Python<'_>, argv: Vec<OsString>) -> u8 {
    seam_case::output::set_notice_handler(|line| eprintln!("seam: {line}"));
    let code = py.detach(|| catch_unwind(AssertUnwindSafe(|| seam_cli::run(argv))).unwrap_or(101));
    seam_case::output::set_notice_handler(crate::error::warn_notice);
    code
}
