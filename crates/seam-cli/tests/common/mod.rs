//! Helpers shared by the integration tests: running the binary and reading
//! what it leaves.

use std::path::Path;
use std::process::{Command, Output};

/// Runs `seam ARGS` in `cwd`.
pub fn seam(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_seam"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the seam binary runs")
}

/// Its standard error, as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A JSON file.
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}
