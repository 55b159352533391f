//! `mpirun -np N seam assemble` (feature `mpi`): the files of N ranks are
//! the bytes of one process, for N = 1…4, on flat, cylinder, warped and
//! second-order surfaces with gaps, overlaps and partial coverage; a bad file
//! stops every rank with one line from rank 0; other commands are refused.

mod common;

use common::{json, stderr};
use seam::generate::{cylinder, flat, hyperbolic_paraboloid, patch, quadratic_patch, Pattern, Quadratic};
use seam::SurfaceMesh;
use std::path::Path;
use std::process::{Command, Output};
use std::time::Duration;

/// `mpirun -np n seam ARGS` in `cwd`, killed after two minutes (no hang).
fn mpirun(n: usize, args: &[&str], cwd: &Path) -> Output {
    let mut child = Command::new("mpirun")
        .args(["--allow-run-as-root", "--oversubscribe", "-np", &n.to_string()])
        .arg(env!("CARGO_BIN_EXE_seam"))
        .args(args)
        .current_dir(cwd)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("mpirun runs (apt-get install openmpi-bin)");
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        assert!(start.elapsed() < Duration::from_secs(120), "mpirun -np {n} {args:?} hangs");
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

fn write(dir: &Path, name: &str, mesh: &SurfaceMesh) -> String {
    seam_io::write_msh_file(dir.join(name), mesh, "surface").unwrap();
    name.into()
}

/// `seam assemble` alone and under 1–4 ranks: the same bytes in every file
/// but summary.json, whose interface totals agree and which names the ranks.
fn same_files_on_ranks(name: &str, master: &SurfaceMesh, slave: &SurfaceMesh, flags: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let (m, s) = (write(dir.path(), "master.msh", master), write(dir.path(), "slave.msh", slave));
    let run = |ranks: Option<usize>, out: &str| {
        let mut args = vec!["assemble", m.as_str(), s.as_str(), "-o", out, "--segments"];
        let segments = format!("{out}/segments.vtu");
        args.push(&segments);
        args.extend(flags);
        let o = match ranks {
            None => common::seam(&args, dir.path()),
            Some(n) => mpirun(n, &args, dir.path()),
        };
        assert!(o.status.success(), "{name}, {ranks:?} ranks: {}", stderr(&o));
    };
    run(None, "one");
    let reference = json(&dir.path().join("one/summary.json"));
    assert!(reference.get("ranks").is_none(), "one process writes no `ranks`");
    let files = ["B.mtx", "D.mtx", "T.mtx", "Q.mtx", "segments.vtu"];
    for n in 1..=4 {
        let out = format!("np{n}");
        run(Some(n), &out);
        for file in files {
            let (a, b) = (dir.path().join("one").join(file), dir.path().join(&out).join(file));
            assert_eq!(a.exists(), b.exists(), "{name}, {n} ranks: {file}");
            if a.exists() {
                assert!(
                    std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(),
                    "{name}, {n} ranks: {file} differs"
                );
            }
        }
        let summary = json(&dir.path().join(&out).join("summary.json"));
        for key in
            ["slave_area", "covered_area", "segments", "candidate_pairs", "max_gap", "max_overlap", "nnz"]
        {
            assert_eq!(summary[key], reference[key], "{name}, {n} ranks: {key}");
        }
        if n == 1 {
            assert!(summary.get("ranks").is_none());
            continue;
        }
        assert_eq!(summary["ranks"], n, "{name}");
        let per_rank = summary["per_rank"].as_array().unwrap();
        assert_eq!(per_rank.len(), n);
        let faces: u64 = per_rank.iter().map(|r| r["slave_faces"].as_u64().unwrap()).sum();
        assert_eq!(faces as usize, slave.n_faces(), "{name}: every face on one rank");
        for r in &per_rank[1..] {
            assert!(r["bytes_received"].as_u64().unwrap() > 0 && r["bytes_sent"].as_u64().unwrap() > 0);
            let ghosts = r["ghost_master_faces"].as_u64().unwrap() as usize;
            assert!(
                ghosts < master.n_faces() || n == 1,
                "{name}: a rank received the whole master ({ghosts})"
            );
        }
    }
}

#[test]
fn ranks_write_the_bytes_of_one_process() {
    let quarter = std::f64::consts::FRAC_PI_2;
    // Flat, jittered triangles against quads, dual multipliers (T written).
    let slave = patch(24, 20, Pattern::Quads, flat(1.0, 1.0));
    let master = patch(17, 19, Pattern::JitteredTriangles { amplitude: 0.25, seed: 3 }, flat(1.0, 1.0));
    same_files_on_ranks("flat", &master, &slave, &["--multiplier", "dual"]);
    // A quarter cylinder, the master 1 % out (gaps), standard multipliers.
    let slave = patch(30, 12, Pattern::Quads, cylinder(1.0, quarter, 1.0));
    let master = patch(22, 10, Pattern::Triangles, cylinder(1.01, quarter, 1.0));
    same_files_on_ranks("cylinder", &master, &slave, &[]);
    // Warped quads; the master overlapping part of the slave only, so that
    // partition boundaries cross the end of the coverage.
    let slave = patch(20, 20, Pattern::Quads, hyperbolic_paraboloid(0.4));
    let master = patch(15, 9, Pattern::Quads, |u, v| {
        let (x, y) = (0.2 + 0.7 * u, 0.1 + 0.5 * v);
        [x, y, 0.4 * (x - 0.5) * (y - 0.5) - 0.002]
    });
    same_files_on_ranks("warped", &master, &slave, &["--multiplier", "dual"]);
    // Second order: Tri6 slave (the basis transformation, Q.mtx) against Quad9.
    let slave = quadratic_patch(9, 8, Quadratic::Tri6, None, cylinder(1.0, 1.2, 1.0));
    let master = quadratic_patch(7, 7, Quadratic::Quad9, Some((0.2, 5)), cylinder(1.0, 1.2, 1.0));
    same_files_on_ranks("second order", &master, &slave, &["--multiplier", "dual"]);
}

#[test]
fn a_bad_file_stops_every_rank_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let slave = write(dir.path(), "slave.msh", &patch(4, 4, Pattern::Quads, flat(1.0, 1.0)));
    std::fs::write(dir.path().join("bad.msh"), "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2\n")
        .unwrap();
    for n in [2, 3] {
        let o = mpirun(n, &["assemble", "bad.msh", &slave, "-o", "out"], dir.path());
        assert!(!o.status.success(), "{n} ranks");
        let lines: Vec<String> =
            stderr(&o).lines().filter(|l| l.starts_with("seam")).map(String::from).collect();
        assert_eq!(lines.len(), 1, "{n} ranks: one line from rank 0, got {lines:?}");
        assert!(lines[0].starts_with("seam: error:") && lines[0].contains("bad.msh"), "{lines:?}");
        assert!(!dir.path().join("out/B.mtx").exists(), "nothing written");
    }
    // Outputs that exist are not overwritten without --force, on any rank count.
    let master = write(dir.path(), "master.msh", &patch(3, 3, Pattern::Triangles, flat(1.0, 1.0)));
    assert!(mpirun(2, &["assemble", &master, &slave, "-o", "out"], dir.path()).status.success());
    let o = mpirun(2, &["assemble", &master, &slave, "-o", "out"], dir.path());
    assert!(!o.status.success() && stderr(&o).contains("--force"), "{}", stderr(&o));
}

#[test]
fn other_commands_are_refused_over_ranks() {
    let dir = tempfile::tempdir().unwrap();
    let o = mpirun(2, &["example", "warped-glue", "-o", "out"], dir.path());
    assert!(!o.status.success());
    let lines: Vec<String> = stderr(&o).lines().filter(|l| l.starts_with("seam")).map(String::from).collect();
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert!(lines[0].contains("only `seam assemble` runs over MPI ranks"), "{lines:?}");
    assert!(!dir.path().join("out").exists());
}
