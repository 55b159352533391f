//! The MPI benchmark of BENCHMARKS.md: `mpirun -np N seam
//! assemble` on the cylinder problem of the transfer benchmark (the target's
//! quads as slave, the source's triangles as master, dual multipliers, one
//! thread per rank), seconds per phase, bytes exchanged, ghost master faces
//! and memory per rank; then the partition alone for many ranks (ghosts).
//!
//! ```text
//! cargo build --release -p seam-cli --features mpi
//! cargo run --release -p seam-examples --example ranks_bench -- 1000000,4000000 1,2,4
//! cargo run --release -p seam-examples --example ranks_bench -- 4000000 none   # the partition alone
//! ```
//!
//! Ghosts: the master faces a rank receives beyond its share, r − M·s/S for a
//! rank with s of the S slave faces receiving r of the M master faces.

use seam::parts::split;
use seam::{FaceTree, MortarOptions, Multiplier};
use seam_examples::transfer_bench::problem;
use std::process::Command;
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let list = |i: usize, default: &str| -> Vec<usize> {
        let text = args.get(i).map_or(default, String::as_str);
        text.split(',').filter(|s| *s != "none").map(|s| s.parse().expect("a number")).collect()
    };
    let (sizes, ranks) = (list(1, "1000000"), list(2, "1,2,4"));
    let seam = std::env::var("SEAM").unwrap_or_else(|_| "target/release/seam".into());
    let tmp = tempfile::tempdir()?;
    // SEAM_BENCH_DIR keeps the meshes (and the outputs) for other runs.
    let dir = std::env::var("SEAM_BENCH_DIR").map_or(tmp.path().to_path_buf(), std::path::PathBuf::from);
    println!("| slave faces | ranks | total s | read s | search s | assemble s | write s | rank seconds | ghost master faces (max share) | bytes exchanged | peak MB per rank |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for &faces in sizes.iter().filter(|_| !ranks.is_empty()) {
        let files = seam_examples::transfer_bench::write_problem(faces, &dir)?;
        for &n in &ranks {
            let out = dir.join(format!("out{n}"));
            let start = Instant::now();
            let o = Command::new("mpirun")
                .args(["--allow-run-as-root", "--oversubscribe", "-np", &n.to_string()])
                .args(["/usr/bin/time", "-f", "rank-peak-kb %M", &seam, "assemble"])
                .arg(&files.source)
                .arg(&files.target)
                .arg("-o")
                .arg(&out)
                .args(["--multiplier", "dual", "--threads", "1", "--force"])
                .output()?;
            let wall = start.elapsed().as_secs_f64();
            let stderr = String::from_utf8_lossy(&o.stderr);
            anyhow::ensure!(o.status.success(), "mpirun -np {n}: {stderr}");
            let peaks: Vec<f64> = stderr
                .lines()
                .filter_map(|l| l.strip_prefix("rank-peak-kb "))
                .map(|kb| kb.trim().parse::<f64>().unwrap_or(0.0) / 1024.0)
                .collect();
            let s: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(out.join("summary.json"))?)?;
            let sec = |k: &str| s["seconds"][k].as_f64().unwrap_or(0.0);
            let (mut rank_seconds, mut ghost, mut bytes) = (Vec::new(), 0.0f64, 0u64);
            if let Some(per_rank) = s["per_rank"].as_array() {
                let master = files.source_faces as f64;
                for r in per_rank {
                    let (sf, gm) =
                        (r["slave_faces"].as_f64().unwrap(), r["ghost_master_faces"].as_f64().unwrap());
                    rank_seconds.push(format!("{:.2}", r["seconds"].as_f64().unwrap()));
                    ghost = ghost.max((gm - master * sf / files.target_faces as f64) / gm);
                    bytes += r["bytes_received"].as_u64().unwrap() + r["bytes_sent"].as_u64().unwrap();
                }
            }
            println!(
                "| {} | {n} | {:.2} (wall {wall:.2}) | {:.2} | {:.2} | {:.2} | {:.2} | {} | {} | {} | {} |",
                files.target_faces,
                sec("total"),
                sec("read"),
                sec("search"),
                sec("assemble"),
                sec("write"),
                if rank_seconds.is_empty() { "–".into() } else { rank_seconds.join(" / ") },
                if n == 1 { "–".into() } else { format!("{:.2} %", 100.0 * ghost) },
                if n == 1 { "–".into() } else { format!("{:.1} MB", bytes as f64 / 1e6) },
                peaks.iter().map(|p| format!("{p:.0}")).collect::<Vec<_>>().join(" / "),
            );
        }
    }
    // The partition alone, for many ranks: ghosts per rank at given faces per rank.
    let faces = *sizes.last().unwrap();
    let (source, target) = problem(faces);
    let tree = FaceTree::new(&source);
    let options = MortarOptions { multiplier: Multiplier::Dual, ..Default::default() };
    println!("\n| slave faces | ranks | slave faces per rank | ghost share, max over ranks | mean |");
    println!("|---|---|---|---|---|");
    for n in [2usize, 4, 16, 40, 64, 256, 1024, 4096] {
        if target.n_faces() / n < 100 {
            break;
        }
        let parts = split(&tree, &target, &options, n);
        let (m, s) = (source.n_faces() as f64, target.n_faces() as f64);
        let shares: Vec<f64> = parts
            .iter()
            .map(|p| {
                let received = p.master_faces.len() as f64;
                (received - m * p.slave_faces.len() as f64 / s) / received
            })
            .collect();
        let max = shares.iter().cloned().fold(0.0, f64::max);
        let mean = shares.iter().sum::<f64>() / n as f64;
        println!(
            "| {} | {n} | {} | {:.2} % | {:.2} % |",
            target.n_faces(),
            target.n_faces() / n,
            100.0 * max,
            100.0 * mean
        );
    }
    Ok(())
}
