//! `seam bench`: the assembly benchmark of BENCHMARKS.md.
//!
//! Slave bilinear quads against master triangles whose legs are ≈ 1.41× the quad
//! edge (about as many faces on both sides, as in the dune-grid-glue peer's
//! meshes), on a flat square and on a cylinder patch. Every (case, size, threads) runs in a fresh
//! process (`seam bench-case`) so that its peak memory is its own; the driver
//! prints one Markdown table.

use crate::args::{BenchArgs, BenchCaseArgs, BenchShape};
use crate::assemble::thread_pool;
use crate::Failure;
use anyhow::{bail, Context};
use seam::generate::{cylinder, flat, patch, Pattern};
use seam::{assemble_with_tree, FaceTree, MaxGap, MortarOptions, SurfaceMesh};
use serde::{Deserialize, Serialize};
use std::process::Command;
use std::time::Instant;

/// One measured run.
#[derive(Serialize, Deserialize)]
struct Row {
    shape: String,
    slave_faces: usize,
    master_faces: usize,
    threads: usize,
    candidate_pairs: usize,
    segments: usize,
    /// Covered fraction of the slave area: a benchmark of a wrong answer is worthless.
    covered: f64,
    generate: f64,
    search: f64,
    assemble: f64,
    peak_mb: f64,
    /// Peak memory beyond the input meshes and the output B, D, per slave face.
    extra_bytes_per_face: f64,
}

pub fn run(args: &BenchArgs) -> Result<(), Failure> {
    let exe = std::env::current_exe().context("cannot find the seam executable")?;
    println!("| shape | slave faces | master faces | threads | candidate pairs | segments | covered | search s | assemble s | search+assemble s | slave faces/s | peak MB | extra B/face |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
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
                let work = r.search + r.assemble;
                println!(
                    "| {} | {} | {} | {} | {} | {} | {:.6} | {:.3} | {:.3} | {:.3} | {:.0} | {:.0} | {:.0} |",
                    r.shape,
                    r.slave_faces,
                    r.master_faces,
                    r.threads,
                    r.candidate_pairs,
                    r.segments,
                    r.covered,
                    r.search,
                    r.assemble,
                    work,
                    r.slave_faces as f64 / work,
                    r.peak_mb,
                    r.extra_bytes_per_face
                );
            }
        }
    }
    Ok(())
}

/// The meshes of one case: n × n slave quads (n² ≈ `faces`) and m × m cells of
/// two jittered master triangles with m = n/√2, so h_m/h_s ≈ 1.41 and the face
/// counts match.
fn meshes(shape: BenchShape, faces: usize) -> (SurfaceMesh, SurfaceMesh) {
    let n = ((faces as f64).sqrt().round() as usize).max(1);
    let m = ((n as f64 / std::f64::consts::SQRT_2).round() as usize).max(1);
    let master = Pattern::JitteredTriangles { amplitude: 0.2, seed: 42 };
    match shape {
        BenchShape::Flat => {
            (patch(m, m, master, flat(1.0, 1.0)), patch(n, n, Pattern::Quads, flat(1.0, 1.0)))
        }
        BenchShape::Cylinder => {
            let quarter = std::f64::consts::FRAC_PI_2;
            (
                patch(m, m, master, cylinder(1.001, quarter, 1.0)),
                patch(n, n, Pattern::Quads, cylinder(1.0, quarter, 1.0)),
            )
        }
    }
}

pub fn run_case(args: &BenchCaseArgs) -> Result<(), Failure> {
    let pool = thread_pool(Some(args.threads))?;
    let t = Instant::now();
    let (master, slave) = meshes(args.shape, args.faces);
    let generate = t.elapsed().as_secs_f64();
    let input_rss = rss_bytes("VmRSS")?;
    let t = Instant::now();
    let tree = pool.install(|| FaceTree::new(&master));
    let search = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let options = match args.shape {
        BenchShape::Flat => MortarOptions::default(),
        // The gap of 0.001 is more than half a face at 1M faces: an absolute limit of
        // twice the gap.
        BenchShape::Cylinder => MortarOptions { max_gap: MaxGap::Absolute(0.002), ..Default::default() },
    };
    let mortar = pool
        .install(|| assemble_with_tree(&master, &tree, &slave, &options, &|_| {}))
        .map_err(anyhow::Error::from)?;
    let assemble = t.elapsed().as_secs_f64();
    let peak = rss_bytes("VmHWM")?;
    let csr_bytes = |m: &seam::CsrMatrix| (m.indptr.len() + m.indices.len() + m.values.len()) * 8;
    let output = csr_bytes(&mortar.b) + csr_bytes(&mortar.d);
    let row = Row {
        shape: args.shape.name().to_string(),
        slave_faces: slave.n_faces(),
        master_faces: master.n_faces(),
        threads: args.threads,
        candidate_pairs: mortar.summary.candidate_pairs,
        segments: mortar.summary.segments,
        covered: mortar.summary.covered_area / mortar.summary.slave_area,
        generate,
        search,
        assemble,
        peak_mb: peak as f64 / 1e6,
        extra_bytes_per_face: (peak as f64 - input_rss as f64 - output as f64) / slave.n_faces() as f64,
    };
    println!("{}", serde_json::to_string(&row).context("row")?);
    Ok(())
}

/// A memory figure of this process from /proc/self/status (Linux), in bytes.
fn rss_bytes(key: &str) -> anyhow::Result<u64> {
    let status = std::fs::read_to_string("/proc/self/status").context("cannot read /proc/self/status")?;
    for line in status.lines() {
        if let Some(rest) = line.strip_prefix(key).and_then(|r| r.strip_prefix(':')) {
            let kb: u64 =
                rest.trim().trim_end_matches("kB").trim().parse().context("bad /proc/self/status")?;
            return Ok(kb * 1024);
        }
    }
    bail!("no {key} in /proc/self/status")
}
