//! The benchmark of the solve over MPI ranks in BENCHMARKS.md:
//! `seam solve --solver petsc` on the warped-glue case (h_s/h_m = 4, rtol
//! 10⁻⁸, one thread per rank) by one process and under `mpirun -np N`:
//! seconds per phase (rank 0's own work, PETSc's matrix, setup and solve,
//! stresses and output) and the peak memory of each rank, largest first.
//!
//! ```text
//! cargo build --release -p seam-cli --features mpi
//! cargo run --release -p seam-examples --example solve_ranks_bench -- 16,24,32 1,2 dual,standard
//! ```
//!
//! Arguments: slave cells across (the size), rank counts (1 runs without
//! mpirun), multipliers. SEAM names the binary (default
//! target/release/seam); SEAM_BENCH_DIR keeps the cases.

use seam::{Multiplier, Named};
use seam_fem::scene::{warped_glue, WarpedGlue};
use std::process::Command;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let arg = |i: usize, default: &str| args.get(i).map_or(default, String::as_str).to_string();
    let numbers =
        |text: String| -> Vec<usize> { text.split(',').map(|s| s.parse().expect("a number")).collect() };
    let (sizes, ranks) = (numbers(arg(1, "16,24")), numbers(arg(2, "1,2")));
    let multipliers = arg(3, "dual,standard");
    let seam = std::env::var("SEAM").unwrap_or_else(|_| "target/release/seam".into());
    let tmp = tempfile::tempdir()?;
    let dir = std::env::var("SEAM_BENCH_DIR").map_or(tmp.path().to_path_buf(), std::path::PathBuf::from);
    println!("| slave cells | multiplier | dofs | ranks | rank 0 before PETSc s | PETSc matrix s | PETSc setup s | PETSc solve s | stresses + output s | total s | iterations | KSP | peak MB per rank |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &cells in &sizes {
        for multiplier in multipliers.split(',') {
            let multiplier = Multiplier::from_name(multiplier)?;
            let params = WarpedGlue { slave_cells: cells, ratio: 4, multiplier, ..WarpedGlue::default() };
            let case_dir = dir.join(format!("wg{cells}-{multiplier:?}"));
            std::fs::create_dir_all(&case_dir)?;
            let case = seam_case::write::write_problem_case(&warped_glue(&params)?, &case_dir, &[], true)?;
            for &n in &ranks {
                let mut command = match n {
                    1 => Command::new("/usr/bin/time"),
                    _ => {
                        let mut c = Command::new("mpirun");
                        c.args([
                            "--allow-run-as-root",
                            "--oversubscribe",
                            "-np",
                            &n.to_string(),
                            "/usr/bin/time",
                        ]);
                        c
                    }
                };
                let o = command
                    .args(["-f", "rank-peak-kb %M", &seam, "solve"])
                    .arg(&case)
                    .args(["--solver", "petsc", "--rtol", "1e-8", "--threads", "1", "--force"])
                    .output()?;
                let stderr = String::from_utf8_lossy(&o.stderr);
                anyhow::ensure!(o.status.success(), "{n} ranks: {stderr}");
                // The ranks' lines come in any order: largest first.
                let mut peaks: Vec<f64> = stderr
                    .lines()
                    .filter_map(|l| l.strip_prefix("rank-peak-kb "))
                    .map(|kb| kb.trim().parse::<f64>().unwrap_or(0.0) / 1024.0)
                    .collect();
                peaks.sort_by(|a, b| b.total_cmp(a));
                let peaks: Vec<String> = peaks.iter().map(|p| format!("{p:.0}")).collect();
                let s: serde_json::Value =
                    serde_json::from_str(&std::fs::read_to_string(case_dir.join("out/summary.json"))?)?;
                let sec = |k: &str| s["seconds"][k].as_f64().unwrap_or(0.0);
                let petsc = |k: &str| s["petsc"]["seconds"][k].as_f64().unwrap_or(0.0);
                println!(
                    "| {cells} | {multiplier:?} | {} | {n} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {} | {} + {} | {} |",
                    s["dofs"],
                    sec("read") + sec("assembly") + sec("mortar") + sec("setup"),
                    petsc("assembly"),
                    petsc("setup"),
                    petsc("solve"),
                    sec("stresses") + sec("output"),
                    sec("total"),
                    s["petsc"]["iterations"][0],
                    s["petsc"]["ksp_type"].as_str().unwrap_or(""),
                    s["petsc"]["pc_type"].as_str().unwrap_or(""),
                    peaks.join(" / "),
                );
            }
        }
    }
    Ok(())
}
