//! Shared by the benchmark examples.

/// Peak resident memory (VmHWM) of this process in MB, NaN when unknown.
pub fn peak_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|kb| kb.parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

/// Runs this executable again with `--row` and `args`, in a fresh process
/// so that the row's peak memory is its own: its standard output trimmed,
/// or the last line of its standard error if it failed.
#[allow(dead_code)]
pub fn fresh_row(args: &[&str]) -> Result<String, String> {
    let exe = std::env::current_exe().expect("own path");
    let out = std::process::Command::new(exe).arg("--row").args(args).output().expect("run a row");
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
    } else {
        Err(String::from_utf8_lossy(&out.stderr).lines().last().unwrap_or("").to_string())
    }
}

/// The value after `flag` on the command line, or `default`.
#[allow(dead_code)]
pub fn flag_value(args: &[String], flag: &str, default: &str) -> String {
    args.iter()
        .position(|a| a == flag)
        .and_then(|i| args.get(i + 1))
        .map_or(default.to_string(), |v| v.clone())
}

/// The comma-separated sizes after `flag`, or `default`.
#[allow(dead_code)]
pub fn flag_sizes(args: &[String], flag: &str, default: &str) -> Vec<usize> {
    flag_value(args, flag, default)
        .split(',')
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().expect("sizes are integers"))
        .collect()
}

/// `Solver::Petsc` with relative tolerance `rtol`, PETSc started (its options
/// from PETSC_OPTIONS).
#[allow(dead_code)]
pub fn petsc(rtol: f64) -> seam_fem::Solver {
    seam_fem::petsc::initialize_petsc("").expect("PETSc (build with --features petsc)");
    seam_fem::Solver::Petsc(seam_fem::petsc::PetscOptions { rtol, ..Default::default() })
}

/// The solver called `name`: "direct", or "petsc" ([`petsc`] at rtol 1e-10).
#[allow(dead_code)]
pub fn named_solver(name: &str) -> seam_fem::Solver {
    match name {
        "direct" => seam_fem::Solver::Direct,
        "petsc" => petsc(1e-10),
        other => panic!("unknown solver {other}"),
    }
}

/// The PETSc columns of a row: KSP + PC, iterations (summed over the
/// solves), PETSc's setup and solve seconds; dashes without PETSc.
#[allow(dead_code)]
pub fn petsc_columns(report: &seam_fem::Report) -> String {
    match &report.petsc {
        Some(p) => format!(
            "{} + {} | {} | {:.2} | {:.2}",
            p.ksp_type,
            p.pc_type,
            p.solves.iter().map(|s| s.iterations).sum::<usize>(),
            p.setup_seconds,
            p.solve_seconds
        ),
        None => "– | – | – | –".into(),
    }
}
