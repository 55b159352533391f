//! `mpirun -np N seam assemble` (feature `mpi`): the files of N ranks are
//! the bytes of one process, for N = 1…4, on flat, cylinder, warped and
//! second-order surfaces with gaps, overlaps and partial coverage; a bad file
//! stops every rank with one line from rank 0; other commands are refused.
//!
//! `mpirun -np N seam solve --solver petsc`: for N = 1…3 the glued (dual and
//! standard multipliers) and contact patch tests are exact with MUMPS, and
//! the warped-glue example gives the single-process solution to the solver's
//! tolerance with the default GAMG solvers (glued, for N > 1, with the
//! stiffness assembled by the ranks that own the cells); a bad mesh,
//! another solver or a solve that does not converge stops every rank with
//! one line. Hyperelastic bodies in contact (rank 0 assembling each
//! Newton step, PETSc solving it over the ranks) give one process's answer.

use crate::common;

use common::{json, stacked_case, stderr, vtu_field, write_block};
use seam::generate::{cylinder, flat, hyperbolic_paraboloid, patch, quadratic_patch, Pattern};
use seam::FaceKind;
use seam::SurfaceMesh;
use seam_fem::generate::Side;
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
        for r in per_rank {
            let mb = r["peak_memory_mb"].as_f64().unwrap();
            assert!(mb > 1.0 && mb < 4000.0, "{name}: peak memory {mb} MB");
        }
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
    let slave = quadratic_patch(9, 8, FaceKind::Tri6, None, cylinder(1.0, 1.2, 1.0));
    let master = quadratic_patch(7, 7, FaceKind::Quad9, Some((0.2, 5)), cylinder(1.0, 1.2, 1.0));
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

/// `seam solve case.toml --force ARGS` in `dir`, alone or under `ranks`
/// ranks, the results moved to `dir/<to>`; returns summary.json.
fn solve_on(dir: &Path, ranks: Option<usize>, args: &[&str], to: &str) -> serde_json::Value {
    let args = [&["solve", "case.toml", "--force", "--solver", "petsc"][..], args].concat();
    let o = match ranks {
        None => common::seam(&args, dir),
        Some(n) => mpirun(n, &args, dir),
    };
    assert!(o.status.success(), "{to}: {}", stderr(&o));
    std::fs::rename(dir.join("out"), dir.join(to)).unwrap();
    json(&dir.join(to).join("summary.json"))
}

/// A body's output in `dir`: `<body>.vtu` from one process, `<body>.pvtu`
/// with its `ranks` pieces `<body>_<r>.vtu` from several (and no `.vtu`).
fn body_file(dir: &Path, body: &str, ranks: usize) -> std::path::PathBuf {
    let pieces: Vec<bool> = (0..ranks.max(2)).map(|r| dir.join(format!("{body}_{r}.vtu")).exists()).collect();
    let (vtu, pvtu) = (dir.join(format!("{body}.vtu")), dir.join(format!("{body}.pvtu")));
    match ranks {
        1 => {
            assert!(vtu.exists() && !pvtu.exists() && !pieces.contains(&true), "{}", dir.display());
            vtu
        }
        _ => {
            assert!(pvtu.exists() && !vtu.exists() && !pieces.contains(&false), "{}", dir.display());
            assert!(!dir.join(format!("{body}_{ranks}.vtu")).exists(), "{ranks} pieces");
            pvtu
        }
    }
}

/// The largest difference of the bodies' displacements in `dir/a` (one
/// process) and `dir/b` (`ranks` ranks), point by point (a point on the
/// boundary of pieces is in each of them), relative to the largest
/// displacement; the pieces hold every cell once.
fn difference(dir: &Path, a: &str, (b, ranks): (&str, usize)) -> f64 {
    ["lower", "upper"]
        .iter()
        .map(|body| {
            let ((x, u), (y, v)) = (
                vtu_field(&body_file(&dir.join(a), body, 1), "displacement", false),
                vtu_field(&body_file(&dir.join(b), body, ranks), "displacement", false),
            );
            let cells = |d: &str, n| vtu_field(&body_file(&dir.join(d), body, n), "von_mises", true).1.len();
            assert_eq!(cells(a, 1), cells(b, ranks), "{body}: the pieces hold every cell once");
            let index: std::collections::HashMap<[u64; 3], usize> =
                x.iter().enumerate().map(|(i, p)| (p.map(f64::to_bits), i)).collect();
            let scale = u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let mut seen = vec![false; x.len()];
            let e = y.iter().enumerate().fold(0.0f64, |m, (j, p)| {
                let i = index[&p.map(f64::to_bits)];
                seen[i] = true;
                (0..3).fold(m, |m, k| m.max((u[3 * i + k] - v[3 * j + k]).abs()))
            });
            assert!(seen.iter().all(|&s| s), "{body}: every point in a piece");
            e / scale
        })
        .fold(0.0, f64::max)
}

/// Young's modulus, Poisson's ratio and the pressure of the patch tests.
const E: f64 = 1000.0;
const NU: f64 = 0.25;
const P: f64 = 2.0;

/// Two blocks of one material stacked at z = 1/2, meshed 4×3×2 (lower,
/// master) and 3×2×2 graded along x (upper, slave), both on rollers at x = 0
/// and y = 0, the lower one at z = 0, pressed by P on top, coupled by an
/// interface with the keys `interface`: uniaxial stress σ_zz = −P, whose
/// displacement u = (νPx, νPy, −Pz)/E is linear, so exact for Hex8 and mortar
/// (glued or in contact).
fn patch_stack(dir: &Path, interface: &str) {
    let sides = [("bottom", Side::ZMin), ("top", Side::ZMax), ("xmin", Side::XMin), ("ymin", Side::YMin)];
    write_block(&dir.join("lower.msh"), [4, 3, 2], |u, v, w| [u, v, 0.5 * w], &sides);
    write_block(
        &dir.join("upper.msh"),
        [3, 2, 2],
        |u, v, w| [0.7 * u + 0.3 * u * u, v, 0.5 + 0.5 * w],
        &sides,
    );
    let rest = format!(
        "[[dirichlet]]\nboundary = \"upper:xmin\"\nux = 0.0\n\n[[dirichlet]]\nboundary = \"upper:ymin\"\nuy = 0.0\n\n\
         [[traction]]\nboundary = \"upper:top\"\nt = [0.0, 0.0, -{P:?}]\n\n[output]\ndir = \"out\"\n"
    );
    std::fs::write(dir.join("case.toml"), stacked_case((E, NU), (E, NU), interface, &rest)).unwrap();
}

#[test]
fn ranks_solve_the_glued_and_contact_patch_tests_exactly() {
    let mumps = ["--petsc-options", "-pc_type lu -pc_factor_mat_solver_type mumps"];
    for interface in [
        "kind = \"glue\"\nmultiplier = \"dual\"",
        "kind = \"glue\"\nmultiplier = \"standard\"",
        "kind = \"contact\"",
        // Friction sticks with zero traction: exact with dual multipliers, whose T
        // reproduces the linear tangential motion (lumped ones do not, I4).
        "kind = \"contact\"\nmultiplier = \"dual\"\nfriction = 0.3",
    ] {
        let what = interface.replace('\n', " ");
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        patch_stack(dir, interface);
        let one = solve_on(dir, None, &mumps, "one");
        assert!(one.get("ranks").is_none(), "{what}: one process writes no `ranks`");
        for n in 1..=3 {
            let to = format!("np{n}");
            let s = solve_on(dir, Some(n), &mumps, &to);
            assert_eq!(s.get("ranks").and_then(|r| r.as_u64()), (n > 1).then_some(n as u64), "{what}");
            assert_eq!(s["dofs"], one["dofs"], "{what}");
            // Glued: K assembled by the ranks that own the cells.
            let partitioned = s["method"].as_str().unwrap().contains("assembled over the MPI ranks");
            assert_eq!(partitioned, n > 1 && what.contains("glue"), "{what}, {n} ranks: {}", s["method"]);
            // The interface's operator, assembled over the ranks: one
            // process's statistics, bit for bit.
            assert_eq!(s["interfaces"][0]["mortar"], one["interfaces"][0]["mortar"], "{what}, {n} ranks");
            for reason in s["petsc"]["reasons"].as_array().unwrap() {
                assert!(reason.as_str().unwrap().starts_with("CONVERGED"), "{what}, {n} ranks: {s}");
            }
            for body in ["lower", "upper"] {
                let (points, u) = vtu_field(&body_file(&dir.join(&to), body, n), "displacement", false);
                for (x, u) in points.iter().zip(u.chunks(3)) {
                    let exact = [NU * P * x[0] / E, NU * P * x[1] / E, -P * x[2] / E];
                    let e = (0..3).fold(0.0f64, |m, k| m.max((u[k] - exact[k]).abs()));
                    assert!(e < 1e-12 * P / E, "{what}, {n} ranks, {body} at {x:?}: {u:?} vs {exact:?}");
                }
            }
            let e = difference(dir, "one", (&to, n));
            assert!(e <= 1e-10, "{what}, {n} ranks: {e:.1e} from one process");
            if let Some(c) = s.get("contact") {
                assert_eq!(c["active_points"], one["contact"]["active_points"], "{what}");
                assert!(c["kkt"]["max"].as_f64().unwrap() <= 1e-8, "{what}, {n} ranks: {c}");
            }
        }
    }
}

/// The glued patch test with a Tet10 slave and dual multipliers, which
/// `seam solve` puts into the enriched slave space (raised slave cells, ties
/// as eliminated rows; the Tet14 cells go to the ranks by their kind):
/// exact to round-off (1e-11 of P/E) alone and over two ranks. (MUMPS's estimate of its workspace falls
/// short on this saddle point, INFOG(1) = −9: ICNTL(14) gives it room.)
#[test]
fn ranks_glue_the_enriched_slave_space_exactly() {
    use seam_fem::generate::BlockKind;
    let mumps = ["--petsc-options", "-pc_type lu -pc_factor_mat_solver_type mumps -mat_mumps_icntl_14 100"];
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    patch_stack(dir, "kind = \"glue\"\nmultiplier = \"dual\"");
    let sides = [("bottom", Side::ZMin), ("top", Side::ZMax), ("xmin", Side::XMin), ("ymin", Side::YMin)];
    common::write_block_of(
        &dir.join("upper.msh"),
        ([2, 2, 2], BlockKind::Tet, true),
        |u, v, w| [u, v, 0.5 + 0.5 * w],
        &sides,
    );
    for (n, to) in [(None, "one"), (Some(2), "np2")] {
        let s = solve_on(dir, n, &mumps, to);
        assert_eq!(s["interfaces"][0]["slave_space"], "enriched", "{to}");
        for body in ["lower", "upper"] {
            let (points, u) =
                vtu_field(&body_file(&dir.join(to), body, n.unwrap_or(1)), "displacement", false);
            for (x, u) in points.iter().zip(u.chunks(3)) {
                let exact = [NU * P * x[0] / E, NU * P * x[1] / E, -P * x[2] / E];
                let e = (0..3).fold(0.0f64, |m, k| m.max((u[k] - exact[k]).abs()));
                assert!(e < 1e-11 * P / E, "{to}, {body} at {x:?}: {u:?} vs {exact:?}");
            }
        }
    }
}

#[test]
fn ranks_solve_warped_glue_as_one_process_does() {
    for multiplier in ["dual", "standard"] {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let o = common::seam(&["example", "warped-glue", "-o", ".", "--ratio", "2"], dir);
        assert!(o.status.success(), "{}", stderr(&o));
        let case = std::fs::read_to_string(dir.join("case.toml")).unwrap();
        let case = case.replace("multiplier = \"standard\"", &format!("multiplier = \"{multiplier}\""));
        std::fs::write(dir.join("case.toml"), case).unwrap();
        // GAMG's aggregates depend on the rows' distribution: the solutions
        // agree to the solver's tolerance, not to round-off.
        let rtol = ["--rtol", "1e-12"];
        let one = solve_on(dir, None, &rtol, "one");
        for n in 1..=3 {
            let to = format!("np{n}");
            let s = solve_on(dir, Some(n), &rtol, &to);
            assert_eq!(s["petsc"]["pc_type"], one["petsc"]["pc_type"], "{multiplier}");
            let mortar = |s: &serde_json::Value| s["interfaces"][0]["mortar"].clone();
            assert_eq!(mortar(&s), mortar(&one), "{multiplier}, {n} ranks: the operator over the ranks");
            assert_eq!(s["petsc"]["reasons"][0], "CONVERGED_RTOL", "{multiplier}, {n} ranks: {s}");
            let partitioned = s["method"].as_str().unwrap().contains("assembled over the MPI ranks");
            assert_eq!(partitioned, n > 1, "{multiplier}, {n} ranks: {}", s["method"]);
            let e = difference(dir, "one", (&to, n));
            assert!(e <= 1e-8, "{multiplier}, {n} ranks: {e:.1e} from one process");
        }
    }
}

/// Contact with active-set steps over the ranks: PETSc's system is refreshed
/// on every rank for each new active set (GAMG's interpolation kept), and
/// the answer is one process's, to the solver's tolerance.
#[test]
fn ranks_solve_bulging_contact_as_one_process_does() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let o = common::seam(&["example", "bulging-contact", "-o", ".", "--slave-cells", "4"], dir);
    assert!(o.status.success(), "{}", stderr(&o));
    let rtol = ["--rtol", "1e-12"];
    let one = solve_on(dir, None, &rtol, "one");
    for n in 2..=3 {
        let to = format!("np{n}");
        let s = solve_on(dir, Some(n), &rtol, &to);
        assert_eq!(s["contact"]["active_points"], one["contact"]["active_points"], "{n} ranks");
        let setups = s["petsc"]["setups"].as_array().unwrap();
        assert!(setups[0] == "new" && setups[1..].contains(&"refreshed".into()), "{n} ranks: {setups:?}");
        let e = difference(dir, "one", (&to, n));
        assert!(e <= 1e-8, "{n} ranks: {e:.1e} from one process");
    }
}

/// Neo-Hookean blocks (the patch stack) in contact with μ = 0.3, the upper
/// top pressed down by a tenth of its height and pushed along x over three
/// load steps: finite deformation with `--solver petsc` (each Newton step
/// by FGMRES with the field split, rank 0 assembling) over two ranks gives
/// one process's answer to 1e-8, with the same Newton iterations, active and
/// sticking points at every step.
#[test]
fn ranks_solve_finite_deformation_contact_as_one_process_does() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    patch_stack(dir, "kind = \"contact\"\nmultiplier = \"dual\"\nfriction = 0.3");
    let case = std::fs::read_to_string(dir.join("case.toml")).unwrap();
    let top = format!("[[traction]]\nboundary = \"upper:top\"\nt = [0.0, 0.0, -{P:?}]\n");
    assert!(case.contains(&top), "{case}");
    let pressed = "[[dirichlet]]\nboundary = \"upper:top\"\nux = 0.01\nuz = -0.05\n\n[load]\nsteps = 3\n";
    let case = case
        .replace(&top, pressed)
        .replace("poisson = 0.25\n", "poisson = 0.25\nmaterial = \"neo-hookean\"\n");
    assert_eq!(case.matches("neo-hookean").count(), 2, "{case}");
    std::fs::write(dir.join("case.toml"), case).unwrap();
    let rtol = ["--rtol", "1e-12"];
    let one = solve_on(dir, None, &rtol, "one");
    assert!(one["method"].as_str().unwrap().contains("PETSc"), "{}", one["method"]);
    let s = solve_on(dir, Some(2), &rtol, "np2");
    assert_eq!(s["ranks"], 2);
    let counts = |s: &serde_json::Value| -> Vec<[serde_json::Value; 3]> {
        s["steps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| [0, 1, 2].map(|k| t[["iterations", "active", "stick"][k]].clone()))
            .collect()
    };
    assert_eq!(counts(&s), counts(&one));
    assert!(counts(&one).iter().all(|c| c[1].as_u64().unwrap() > 0), "{:?}", counts(&one));
    let e = difference(dir, "one", ("np2", 2));
    assert!(e <= 1e-8, "2 ranks: {e:.1e} from one process");
}

#[test]
fn a_bad_mesh_another_solver_or_a_failed_solve_stops_every_rank() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    patch_stack(dir, "kind = \"glue\"");
    let good = std::fs::read(dir.join("lower.msh")).unwrap();
    std::fs::write(dir.join("lower.msh"), &good[..good.len() / 2]).unwrap();
    let cases: [(&[&str], &str); 2] = [
        (&["solve", "case.toml", "--solver", "petsc"], "lower.msh"),
        (&["solve", "case.toml", "--solver", "direct"], "needs --solver petsc"),
    ];
    for (args, expected) in cases {
        for n in [2, 3] {
            let o = mpirun(n, args, dir);
            assert_eq!(o.status.code(), Some(2), "{args:?}, {n} ranks: {}", stderr(&o));
            let lines: Vec<String> =
                stderr(&o).lines().filter(|l| l.starts_with("seam")).map(String::from).collect();
            assert_eq!(lines.len(), 1, "{args:?}, {n} ranks: one line from rank 0, got {lines:?}");
            assert!(lines[0].starts_with("seam: error:") && lines[0].contains(expected), "{lines:?}");
            assert!(!dir.join("out").exists(), "nothing written");
        }
    }
    // A solve that stops without converging, on every rank.
    std::fs::write(dir.join("lower.msh"), &good).unwrap();
    let capped =
        ["solve", "case.toml", "--solver", "petsc", "--petsc-options", "-pc_type none -ksp_max_it 1"];
    let o = mpirun(2, &capped, dir);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let lines: Vec<String> = stderr(&o).lines().filter(|l| l.starts_with("seam")).map(String::from).collect();
    assert!(lines.len() == 1 && lines[0].contains("DIVERGED_ITS"), "{lines:?}");
    assert!(!dir.join("out").exists(), "nothing written");
}

#[test]
fn other_commands_are_refused_over_ranks() {
    let dir = tempfile::tempdir().unwrap();
    let o = mpirun(2, &["example", "warped-glue", "-o", "out"], dir.path());
    assert!(!o.status.success());
    let lines: Vec<String> = stderr(&o).lines().filter(|l| l.starts_with("seam")).map(String::from).collect();
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert!(
        lines[0].contains("only `seam assemble` and `seam solve --solver petsc` run over MPI ranks"),
        "{lines:?}"
    );
    assert!(!dir.path().join("out").exists());
}
