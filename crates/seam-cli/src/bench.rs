//! `seam bench`: the assembly benchmark of BENCHMARKS.md ([`seam_examples::bench`]).
//! Every (shape, size, threads) runs in a fresh process (`seam bench-case`) so
//! that its peak memory is its own; the driver prints one Markdown table.

use crate::args::{BenchArgs, BenchCaseArgs, BenchShape};
use crate::assemble::thread_pool;
use crate::Failure;
use anyhow::Context;
use seam_examples::bench::{measure, Row, Shape, HEADER};
use std::process::Command;

pub fn run(args: &BenchArgs) -> Result<(), Failure> {
    let exe = std::env::current_exe().context("cannot find the seam executable")?;
    for line in HEADER {
        println!("{line}");
    }
    for shape in &args.shapes {
        for &faces in &args.sizes {
            for &threads in &args.threads {
                let out = Command::new(&exe)
                    .args(["bench-case", "--shape", shape.name(), "--faces", &faces.to_string()])
                    .args(["--threads", &threads.to_string()])
                    .output()
                    .context("cannot run a benchmark case")?;
                if !out.status.success() {
                    return Err(anyhow::anyhow!(
                        "benchmark case failed: {}",
                        String::from_utf8_lossy(&out.stderr)
                    )
                    .into());
                }
                let r: Row = serde_json::from_slice(&out.stdout).context("benchmark case output")?;
                println!("{}", r.table_line());
            }
        }
    }
    Ok(())
}

pub fn run_case(args: &BenchCaseArgs) -> Result<(), Failure> {
    let pool = thread_pool(Some(args.threads))?;
    let shape = match args.shape {
        BenchShape::Flat => Shape::Flat,
        BenchShape::Cylinder => Shape::Cylinder,
        BenchShape::CylinderO2 => Shape::CylinderQuadratic,
    };
    let row = pool.install(|| measure(shape, args.faces, args.threads))?;
    println!("{}", serde_json::to_string(&row).context("row")?);
    Ok(())
}
