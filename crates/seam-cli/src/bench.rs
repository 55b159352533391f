//! `seam bench`: the assembly benchmark of BENCHMARKS.md ([`seam_examples::bench`]).
//! Every (shape, size, threads) runs in a fresh process (`seam bench-case`) so
//! that its peak memory is its own; the driver prints one Markdown table.
//! `seam bench-transfer`: `seam transfer` end to end
//! ([`seam_examples::transfer_bench`]), one process per run.

use crate::args::{BenchArgs, BenchCaseArgs, BenchTransferArgs};
use crate::assemble::thread_pool;
use crate::Failure;
use anyhow::Context;
use seam::Named;
use seam_examples::bench::{measure, Row, HEADER};
use seam_examples::transfer_bench;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

pub fn run(args: &BenchArgs) -> Result<(), Failure> {
    let exe = current_exe()?;
    for line in HEADER {
        println!("{line}");
    }
    for shape in &args.shapes {
        for &faces in &args.sizes {
            for &threads in &args.threads {
                let out = run_child(
                    Command::new(&exe)
                        .args(["bench-case", "--shape", shape.name(), "--faces", &faces.to_string()])
                        .args(["--threads", &threads.to_string()]),
                )?;
                let r: Row = serde_json::from_slice(&out).context("benchmark case output")?;
                println!("{}", r.table_line());
            }
        }
    }
    Ok(())
}

pub fn run_case(args: &BenchCaseArgs) -> Result<(), Failure> {
    let pool = thread_pool(Some(args.threads))?;
    let row = pool.install(|| measure(args.shape, args.faces, args.threads))?;
    println!("{}", serde_json::to_string(&row).context("row")?);
    Ok(())
}

/// The driver of `seam bench-transfer`: the files of each size in a fresh
/// directory of the system's temporary directory (removed afterwards), then
/// `seam transfer` once per (mode, multiplier, threads).
pub fn run_transfer(args: &BenchTransferArgs) -> Result<(), Failure> {
    let exe = current_exe()?;
    let dir = std::env::temp_dir().join(format!("seam-bench-transfer-{}", std::process::id()));
    std::fs::create_dir(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let result = transfer_table(&exe, &dir, args);
    let _ = std::fs::remove_dir_all(&dir);
    result
}

fn transfer_table(exe: &Path, dir: &Path, args: &BenchTransferArgs) -> Result<(), Failure> {
    for line in transfer_bench::HEADER {
        println!("{line}");
    }
    for &faces in &args.sizes {
        let files = transfer_bench::write_problem(faces, dir)?;
        let out = dir.join("out.vtu");
        for mode in args.modes.iter().map(|m| m.name()) {
            for multiplier in args.multipliers.iter().map(|m| m.name()) {
                for &threads in &args.threads {
                    let start = Instant::now();
                    run_child(
                        Command::new(exe)
                            .arg("transfer")
                            .args([&files.source, &files.target])
                            .args(["-o".as_ref(), out.as_os_str()])
                            .args(["--field", "f", "--mode", mode, "--multiplier", multiplier])
                            .args(["--threads", &threads.to_string(), "--force"]),
                    )?;
                    let all_in = start.elapsed().as_secs_f64();
                    let summary: serde_json::Value = serde_json::from_slice(
                        &std::fs::read(out.with_extension("json")).context("the transfer's summary")?,
                    )
                    .context("the transfer's summary")?;
                    let phases = serde_json::from_value(summary["phases"].clone()).context("its phases")?;
                    let row =
                        transfer_bench::Row { files: &files, mode, multiplier, threads, phases, all_in };
                    println!("{}", row.table_line());
                }
            }
        }
    }
    Ok(())
}

fn current_exe() -> Result<std::path::PathBuf, Failure> {
    Ok(std::env::current_exe().context("cannot find the seam executable")?)
}

/// Runs a child `seam` and returns its standard output; its standard error
/// in the error when it fails.
fn run_child(command: &mut Command) -> Result<Vec<u8>, Failure> {
    let out = command.output().context("cannot run a benchmark case")?;
    if !out.status.success() {
        return Err(anyhow::anyhow!("benchmark case failed: {}", String::from_utf8_lossy(&out.stderr)).into());
    }
    Ok(out.stdout)
}
