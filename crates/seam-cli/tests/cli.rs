//! The `seam` binary, run as a user would: in a temporary directory, checking
//! exit codes, stderr and the files it leaves.

use crate::common;

use common::{json, seam, stderr};
use seam_io::read_matrix_market_str;
use std::path::{Path, PathBuf};
use std::process::Output;

fn fixture(name: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../seam-io/tests/data").join(name);
    assert!(p.exists(), "missing fixture {}", p.display());
    p.to_string_lossy().into_owned()
}

fn summary(dir: &Path) -> serde_json::Value {
    json(&dir.join("summary.json"))
}

fn matrix(path: &Path) -> seam::CsrMatrix {
    read_matrix_market_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// A bad input: exit 2, exactly one line on stderr that names `file` and contains
/// `problem`, no panic, and no result left in the output directory.
fn assert_clean_failure(o: &Output, code: i32, file: &str, problem: &str, out: &Path) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "exit code; stderr: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line on stderr, got: {err}");
    assert!(err.contains(file), "stderr names {file}: {err}");
    assert!(err.to_lowercase().contains(&problem.to_lowercase()), "stderr says '{problem}': {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.join("summary.json").exists(), "no summary.json after a failure");
    assert!(!out.join("B.mtx").exists(), "no B.mtx after a failure");
}

#[test]
fn example_operator_writes_meshes_matrices_and_summary() {
    let tmp = tempfile::tempdir().unwrap();
    let o = seam(&["example", "operator", "-o", "out"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = tmp.path().join("out");
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(!report.contains("VIOLATED"), "{report}");
    assert_eq!(report.matches(" ok").count(), 4, "{report}");
    let s = summary(&out);
    for key in [
        "slave_nodes",
        "master_nodes",
        "slave_faces",
        "master_faces",
        "candidate_pairs",
        "intersecting_pairs",
        "segments",
        "slave_area",
        "covered_area",
        "uncovered_slave_nodes",
        "max_gap",
        "max_overlap",
        "multiplier",
        "threads",
    ] {
        assert!(s.get(key).is_some(), "summary.json lacks {key}");
    }
    for phase in ["read", "search", "assemble", "write", "total"] {
        assert!(s["seconds"][phase].as_f64().unwrap() >= 0.0);
    }
    let (b, d, t) = (matrix(&out.join("B.mtx")), matrix(&out.join("D.mtx")), matrix(&out.join("T.mtx")));
    let (ns, nm) =
        (s["slave_nodes"].as_u64().unwrap() as usize, s["master_nodes"].as_u64().unwrap() as usize);
    assert_eq!((b.nrows, b.ncols, d.nrows, d.ncols, t.nrows, t.ncols), (ns, nm, ns, ns, ns, nm));
    assert!(d.is_diagonal());
    // The meshes it wrote read back, and assembling them again gives the same B.
    let again = seam(
        &["assemble", "out/master.msh", "out/slave.msh", "-o", "again", "--multiplier", "dual"],
        tmp.path(),
    );
    assert!(again.status.success(), "{}", stderr(&again));
    assert_eq!(matrix(&tmp.path().join("again/B.mtx")), b);
}

#[test]
fn the_four_msh_flavours_give_the_same_matrices() {
    let tmp = tempfile::tempdir().unwrap();
    let mut reference: Option<(seam::CsrMatrix, seam::CsrMatrix)> = None;
    for flavour in ["v22.ascii", "v22.bin", "v41.ascii", "v41.bin"] {
        let (master, slave) =
            (fixture(&format!("square_tri.{flavour}.msh")), fixture(&format!("square_mixed.{flavour}.msh")));
        let o = seam(&["assemble", &master, &slave, "-o", flavour], tmp.path());
        assert!(o.status.success(), "{flavour}: {}", stderr(&o));
        let out = tmp.path().join(flavour);
        let s = summary(&out);
        assert!(
            (s["covered_area"].as_f64().unwrap() - 1.0).abs() < 1e-13,
            "{flavour}: unit squares cover each other"
        );
        assert_eq!(s["uncovered_slave_nodes"], 0);
        let m = (matrix(&out.join("B.mtx")), matrix(&out.join("D.mtx")));
        assert!(!out.join("T.mtx").exists(), "standard multipliers write no T.mtx");
        match &reference {
            None => reference = Some(m),
            // ASCII files hold printed coordinates, binary ones exact doubles:
            // the same pattern, values equal to round-off.
            Some(r) => {
                for (a, b) in [(&r.0, &m.0), (&r.1, &m.1)] {
                    assert_eq!((&a.indptr, &a.indices), (&b.indptr, &b.indices), "{flavour}: same pattern");
                    let diff = a.values.iter().zip(&b.values).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
                    assert!(diff < 1e-15, "{flavour} differs from v22.ascii by {diff:e}");
                }
            }
        }
    }
}

/// Gmsh second-order volumes (Hex27 master, Tet10 slave): their Quad9 and
/// Tri6 tops couple; dual multipliers write Q.mtx, and T.mtx = Qᵀ D⁻¹ B is
/// nodal (T·1 = 1); lumped multipliers on the Tri6 slave are refused.
#[test]
fn second_order_volume_files_couple_through_their_curved_faces() {
    let tmp = tempfile::tempdir().unwrap();
    let (master, slave) = (fixture("box_hex_o2.v41.bin.msh"), fixture("box_tet_o2.v22.ascii.msh"));
    let groups = ["--master-group", "top", "--slave-group", "top"];
    let o = seam(
        &[&["assemble", &master, &slave, "-o", "dual", "--multiplier", "dual"][..], &groups].concat(),
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = tmp.path().join("dual");
    let s = summary(&out);
    assert_eq!(s["slave_basis"], "transformed");
    assert_eq!(s["uncovered_slave_nodes"], 0);
    assert!((s["covered_fraction"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    let (t, q, d) = (matrix(&out.join("T.mtx")), matrix(&out.join("Q.mtx")), matrix(&out.join("D.mtx")));
    assert!(d.is_diagonal());
    assert_eq!(q.nrows, d.nrows);
    let used = t.row_sums().iter().filter(|v| v.abs() > 0.0).count();
    assert!(used > 0);
    for (p, v) in t.row_sums().iter().enumerate().filter(|(_, v)| v.abs() > 0.0) {
        assert!((v - 1.0).abs() < 1e-12, "T·1 = {v} in row {}", p + 1);
    }
    let o = seam(
        &[&["assemble", &master, &slave, "-o", "lumped", "--multiplier", "lumped"][..], &groups].concat(),
        tmp.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("box_tet_o2.v22.ascii.msh (slave)") && e.contains("use dual multipliers"), "{e}");
    assert!(!tmp.path().join("lumped").join("D.mtx").exists());
}

#[test]
fn volume_files_with_physical_surfaces_couple_across_the_interface() {
    // The top of the unit tet box (z = 1, [0,1]²) against the top of the 2×1×1 hex
    // box (z = 1, [0,2]×[0,1]): half of the slave is covered.
    let tmp = tempfile::tempdir().unwrap();
    let (tet, hex) = (fixture("box_tet.v41.ascii.msh"), fixture("box_hex.v41.bin.msh"));
    let o = seam(
        &["assemble", &tet, &hex, "-o", "out", "--master-group", "top", "--slave-group", "top"],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&tmp.path().join("out"));
    assert!((s["covered_area"].as_f64().unwrap() - 1.0).abs() < 1e-13, "{s}");
    assert!((s["slave_area"].as_f64().unwrap() - 2.0).abs() < 1e-13, "{s}");
    // 5 × 3 nodes at x = 0, ½, 1, 3/2, 2: the columns x = 3/2 and 2 have no master.
    assert_eq!(s["uncovered_slave_nodes"], 6, "{s}");
    // Both are outward normals on the same side: they do not face each other.
    let o = seam(
        &[
            "assemble",
            &tet,
            &hex,
            "-o",
            "opp",
            "--master-group",
            "top",
            "--slave-group",
            "top",
            "--facing",
            "opposite",
        ],
        tmp.path(),
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

/// A unit square of two triangles (MSH 2.2 ASCII), with a replaceable node line
/// and element line.
fn square_msh(node3: &str, element2: &str) -> String {
    format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n{node3}\n4 0 1 0\n$EndNodes\n\
         $Elements\n2\n1 2 2 1 1 1 2 3\n{element2}\n$EndElements\n"
    )
}

#[test]
fn bad_input_fails_cleanly_with_one_line_naming_the_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let good = write(dir, "good.msh", &square_msh("3 1 1 0", "2 2 2 1 1 1 3 4"));
    let out = dir.join("out");
    let o = seam(&["assemble", &good, "missing.msh", "-o", "out"], dir);
    assert_clean_failure(&o, 2, "missing.msh", "no such file", &out);

    let full = std::fs::read_to_string(fixture("square_tri.v41.ascii.msh")).unwrap();
    let truncated = write(dir, "truncated.msh", &full[..full.len() / 2]);
    let o = seam(&["assemble", &good, &truncated, "-o", "out"], dir);
    assert_clean_failure(&o, 2, "truncated.msh", "", &out);

    let nan = write(dir, "nan.msh", &square_msh("3 nan 1 0", "2 2 2 1 1 1 3 4"));
    let o = seam(&["assemble", &good, &nan, "-o", "out"], dir);
    assert_clean_failure(&o, 2, "nan.msh", "node 3", &out);

    let o = seam(&["assemble", &good, &good, "-o", "out", "--slave-group", "nowhere"], dir);
    assert_clean_failure(&o, 2, "good.msh", "nowhere", &out);

    let repeated = write(dir, "repeated.msh", &square_msh("3 1 1 0", "2 2 2 1 1 1 3 3"));
    let o = seam(&["assemble", &good, &repeated, "-o", "out"], dir);
    assert_clean_failure(&o, 2, "repeated.msh", "element 2", &out);

    let flat = write(dir, "flat.msh", &square_msh("3 2 0 0", "2 2 2 1 1 1 2 3"));
    let o = seam(&["assemble", &good, &flat, "-o", "out"], dir);
    assert_clean_failure(&o, 2, "flat.msh", "element", &out);

    let far = write(
        dir,
        "far.msh",
        &square_msh("3 1 1 0", "2 2 2 1 1 1 3 4")
            .replace("\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0", "\n1 5 0 0\n2 6 0 0\n3 6 1 0\n4 5 1 0"),
    );
    let o = seam(&["assemble", &good, &far, "-o", "out"], dir);
    assert_clean_failure(&o, 1, "far.msh", "do not overlap", &out);

    let o = seam(&["assemble", &good, &good, "-o", "good.msh/out"], dir);
    assert_clean_failure(
        &o,
        2,
        "good.msh/out",
        "cannot create output directory",
        &dir.join("good.msh-nonexistent"),
    );

    let o = seam(&["assemble", &good, &good, "-o", "out", "--threads", "0"], dir);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        !out.exists() || std::fs::read_dir(&out).unwrap().next().is_none(),
        "a failed run leaves no files"
    );
}

#[test]
fn existing_results_are_not_overwritten_without_force() {
    let tmp = tempfile::tempdir().unwrap();
    let (master, slave) = (fixture("square_tri.v41.ascii.msh"), fixture("square_mixed.v41.ascii.msh"));
    let first = seam(&["assemble", &master, &slave, "-o", "out", "--multiplier", "lumped"], tmp.path());
    assert!(first.status.success(), "{}", stderr(&first));
    let o = seam(&["assemble", &master, &slave, "-o", "out"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    assert!(tmp.path().join("out/T.mtx").exists(), "the earlier result is intact");
    let o = seam(&["assemble", &master, &slave, "-o", "out", "--force"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!tmp.path().join("out/T.mtx").exists(), "a stale T.mtx from the lumped run is removed");
    assert_eq!(summary(&tmp.path().join("out"))["multiplier"], "standard");
}

#[test]
fn every_command_has_help() {
    let tmp = tempfile::tempdir().unwrap();
    for args in [
        vec!["--help"],
        vec!["assemble", "--help"],
        vec!["transfer", "--help"],
        vec!["check", "--help"],
        vec!["solve", "--help"],
        vec!["example", "--help"],
        vec!["bench", "--help"],
        vec!["bench-transfer", "--help"],
    ] {
        let o = seam(&args, tmp.path());
        assert!(o.status.success());
        assert!(String::from_utf8_lossy(&o.stdout).contains("Usage"));
    }
    let o = seam(&["assemble", "--help"], tmp.path());
    let help = String::from_utf8_lossy(&o.stdout);
    for flag in [
        "--master-group",
        "--slave-group",
        "--multiplier",
        "--max-gap",
        "--facing",
        "--quad-order",
        "--threads",
    ] {
        assert!(help.contains(flag), "assemble --help lacks {flag}");
    }
}

#[test]
fn example_help_lists_every_example_and_solve_help_mentions_contact() {
    let tmp = tempfile::tempdir().unwrap();
    let o = seam(&["example", "--help"], tmp.path());
    let help = String::from_utf8_lossy(&o.stdout);
    for name in ["operator", "warped-glue", "bulging-contact", "hertz", "cattaneo-mindlin"] {
        assert!(help.contains(name), "example --help lacks {name}:\n{help}");
    }
    assert!(!help.contains("--slave-cells"), "the test-size flags stay hidden:\n{help}");
    let o = seam(&["example", "no-such-example", "-o", "x"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    for name in ["bulging-contact", "hertz"] {
        assert!(stderr(&o).contains(name), "the error lists {name}: {}", stderr(&o));
    }
    let o = seam(&["solve", "--help"], tmp.path());
    let help = String::from_utf8_lossy(&o.stdout).split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(help.contains("glued or in contact"), "{help}");
    assert!(help.contains("Coulomb friction"), "{help}");
    assert!(!tmp.path().join("x").exists());
}

fn vtu(path: &Path) -> seam_io::VtuMesh {
    seam_io::read_vtu_file(path).unwrap()
}

#[test]
fn transfer_reproduces_a_linear_field_and_reports_its_error() {
    let tmp = tempfile::tempdir().unwrap();
    let (source, target) = (fixture("square_tri.v41.bin.msh"), fixture("square_mixed.v22.ascii.msh"));
    let o = seam(
        &[
            "transfer",
            &source,
            &target,
            "-o",
            "out/t.vtu",
            "--expr",
            "2e0*x - 1E+3*y/1e3 + 5e-1",
            "--name",
            "u",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("out/t.json")).unwrap()).unwrap();
    assert!(s["l2_error"].as_f64().unwrap() < 1e-13, "{s}");
    assert!((s["covered_fraction"].as_f64().unwrap() - 1.0).abs() < 1e-13);
    let out = vtu(&tmp.path().join("out/t.vtu"));
    let u = out.point_field("u").unwrap();
    assert_eq!(u.components, 1);
    for (p, x) in out.mesh.points().iter().enumerate() {
        if out.mesh.used_points()[p] {
            assert!((u.values[p] - (2.0 * x[0] - x[1] + 0.5)).abs() < 1e-12);
        }
    }
    let gap = out.point_field("normal_gap").unwrap();
    let coverage = out.point_field("coverage").unwrap();
    assert!(out
        .mesh
        .used_points()
        .iter()
        .enumerate()
        .all(|(p, &u)| !u || (gap.values[p].abs() < 1e-14 && (coverage.values[p] - 1.0).abs() < 1e-12)));
}

#[test]
fn conservative_transfer_keeps_the_total_load() {
    let tmp = tempfile::tempdir().unwrap();
    let (source, target) = (fixture("square_mixed.v41.ascii.msh"), fixture("square_tri.v22.bin.msh"));
    let o = seam(
        &["transfer", &source, &target, "-o", "c.vtu", "--expr", "1 + x*y", "--mode", "conservative"],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("c.json")).unwrap()).unwrap();
    let (a, b) = (s["total_source"][0].as_f64().unwrap(), s["total_target"][0].as_f64().unwrap());
    assert!((a - b).abs() < 1e-12 * a.abs(), "{a} vs {b}");
    // One assembly: the target's coverage and gaps come from the columns of B
    // and agree with consistent mode's (the target as slave) on these
    // coplanar squares to round-off.
    let o = seam(&["transfer", &source, &target, "-o", "v.vtu", "--expr", "1 + x*y"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("v.json")).unwrap()).unwrap();
    for key in ["target_area", "covered_area", "covered_fraction", "uncovered_target_nodes", "target_nodes"] {
        let (c, k) = (s[key].as_f64().unwrap(), v[key].as_f64().unwrap());
        assert!((c - k).abs() <= 1e-13 * k.abs(), "{key}: conservative {c}, consistent {k}");
    }
    let (c, k) = (vtu(&tmp.path().join("c.vtu")), vtu(&tmp.path().join("v.vtu")));
    for field in ["coverage", "normal_gap"] {
        let (fc, fk) = (&c.point_field(field).unwrap().values, &k.point_field(field).unwrap().values);
        for (p, (a, b)) in fc.iter().zip(fk).enumerate() {
            assert!(
                (a - b).abs() <= 1e-13 || (a.is_nan() && b.is_nan()),
                "{field} at point {p}: {a} against {b}"
            );
        }
    }
    // The phases add up to the run's seconds (but for checking the paths).
    let phases: f64 = s["phases"].as_object().unwrap().values().map(|t| t.as_f64().unwrap()).sum();
    let seconds = s["seconds"].as_f64().unwrap();
    assert!(phases > 0.0 && phases <= seconds, "phases {phases} s of {seconds} s");
}

#[test]
fn transfer_of_a_gmsh_node_data_vector_field() {
    // The hex box's "temperature" ($NodeData) from its top to the top of the tet box.
    let tmp = tempfile::tempdir().unwrap();
    let (source, target) = (fixture("box_hex.v41.ascii.msh"), fixture("box_tet.v41.ascii.msh"));
    let args =
        ["transfer", &source, &target, "-o", "h.vtu", "--source-group", "top", "--target-group", "top"];
    let o = seam(&[&args[..], &["--field", "temperature"]].concat(), tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = vtu(&tmp.path().join("h.vtu"));
    let t = out.point_field("temperature").unwrap();
    assert!(out.mesh.used_points().iter().enumerate().all(|(p, &u)| !u || t.values[p].is_finite()));
    // "displacement" is given at 5 nodes only in its last time step: a clear error.
    let o = seam(&[&args[..], &["--field", "displacement", "--force"]].concat(), tmp.path());
    assert_clean_failure(&o, 2, "box_hex", "no finite value at node", &tmp.path().join("nothing"));
    let o = seam(&[&args[..], &["--field", "pressure", "--force"]].concat(), tmp.path());
    assert_clean_failure(
        &o,
        2,
        "box_hex",
        "no field named 'pressure' (fields: temperature, displacement)",
        &tmp.path().join("nothing"),
    );
    let o = seam(&[&args[..], &["--expr", "sin(x", "--force"]].concat(), tmp.path());
    assert_clean_failure(&o, 2, "sin(x", "does not parse", &tmp.path().join("nothing"));
}

#[test]
fn check_reports_coverage_gaps_orientation_and_invariants() {
    let tmp = tempfile::tempdir().unwrap();
    let (master, slave) = (fixture("square_tri.v41.ascii.msh"), fixture("square_mixed.v41.bin.msh"));
    let o = seam(&["check", &master, &slave, "--json", "r.json", "--vtu", "r.vtu", "--strict"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    for word in ["covered", "normal gap", "orientation  slave consistent", "quality", "verdict      ok"] {
        assert!(text.contains(word), "report lacks '{word}':\n{text}");
    }
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("r.json")).unwrap()).unwrap();
    assert_eq!(r["ok"], true);
    assert!(r["invariants"].as_array().unwrap().iter().all(|i| i["ok"] == true));
    assert!(vtu(&tmp.path().join("r.vtu")).point_field("coverage").is_some());
    // The 2×1 hex top is only half covered by the unit tet top: --strict fails with 3.
    let (tet, hex) = (fixture("box_tet.v41.ascii.msh"), fixture("box_hex.v41.bin.msh"));
    let o =
        seam(&["check", &tet, &hex, "--master-group", "top", "--slave-group", "top", "--strict"], tmp.path());
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("6 slave nodes"));
}

/// An n × n grid of quads on the unit square (MSH 2.2 ASCII), element i
/// tagged `first_tag + i`, in physical surface 1, then a copy of element
/// `duplicate` if any, in physical surface 2 (two physical surfaces that
/// overlap).
fn quads_msh(n: usize, first_tag: usize, duplicate: Option<usize>) -> String {
    let node = |i: usize, j: usize| j * (n + 1) + i + 1;
    let mut nodes = String::new();
    for j in 0..=n {
        for i in 0..=n {
            nodes += &format!("{} {} {} 0\n", node(i, j), i as f64 / n as f64, j as f64 / n as f64);
        }
    }
    let mut quads: Vec<[usize; 4]> = Vec::new();
    for j in 0..n {
        for i in 0..n {
            quads.push([node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)]);
        }
    }
    quads.extend(duplicate.map(|d| quads[d]));
    let elements: String = quads
        .iter()
        .enumerate()
        .map(|(e, q)| {
            let group = if e < n * n { 1 } else { 2 };
            format!("{} 3 2 {group} {group} {} {} {} {}\n", first_tag + e, q[0], q[1], q[2], q[3])
        })
        .collect();
    format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{}\n{nodes}$EndNodes\n$Elements\n{}\n{elements}$EndElements\n",
        (n + 1) * (n + 1),
        quads.len()
    )
}

/// A master surface with an element listed twice (a mesh merge's duplicate)
/// covers part of the slave twice: D and B are wrong together, I1 and I2
/// hold, and the bounds on the covered area and D's row sums catch it,
/// naming the slave elements behind the duplicate by their Gmsh tags.
#[test]
fn check_names_the_slave_elements_a_duplicated_master_element_covers_twice() {
    let tmp = tempfile::tempdir().unwrap();
    let master = write(tmp.path(), "master.msh", &quads_msh(2, 1, Some(3)));
    let slave = write(tmp.path(), "slave.msh", &quads_msh(4, 101, None));
    let o = seam(&["check", &master, &slave, "--json", "r.json", "--strict"], tmp.path());
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(err.contains("slave.msh") && err.contains("covered area ≤ slave area"), "{err}");
    assert!(err.contains("gmsh element tags) 111, 112, 115, 116"), "{err}");
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("covered 1.250000 (125.0000 % of the slave)"), "{text}");
    assert_eq!(text.matches("VIOLATED").count(), 2, "{text}");
    assert!(text.contains("at slave faces (gmsh element tags) 111, 112, 115, 116\n"), "{text}");
    assert!(text.contains("verdict      violated invariants\n"), "{text}");
    let r = json(&tmp.path().join("r.json"));
    assert_eq!(r["ok"], false);
    assert_eq!(r["face_ids"], "gmsh element tags");
    let violated: Vec<&serde_json::Value> =
        r["invariants"].as_array().unwrap().iter().filter(|i| i["ok"] == false).collect();
    assert_eq!(violated.len(), 2, "{r}");
    assert_eq!(violated[0]["offending_faces"], serde_json::json!([111, 112, 115, 116]), "{r}");
    let mut faces: Vec<u64> =
        violated[1]["offending_faces"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).collect();
    faces.sort_unstable();
    assert_eq!(faces, [111, 112, 115, 116], "{r}");
    assert_eq!(violated[1]["offending_nodes"].as_array().unwrap().len(), 5, "{r}");
    // Without --strict the report is the same and the run succeeds.
    let o = seam(&["check", &master, &slave], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout).matches("VIOLATED").count(), 2);
}

/// The slave of the test above as the top faces (S2) of a layer of C3D8
/// elements of an Abaqus `.inp` file, numbered as the quads: the report
/// names the faces as "element E face S2".
#[test]
fn check_names_element_faces_of_an_inp_slave_by_element_and_face() {
    let n = 4;
    let node = |i: usize, j: usize, layer: usize| layer * (n + 1) * (n + 1) + j * (n + 1) + i + 1;
    let mut inp = String::from("*NODE\n");
    for (layer, z) in [(0, -0.25), (1, 0.0)] {
        for j in 0..=n {
            for i in 0..=n {
                inp += &format!(
                    "{}, {}, {}, {z}\n",
                    node(i, j, layer),
                    i as f64 / n as f64,
                    j as f64 / n as f64
                );
            }
        }
    }
    inp += "*ELEMENT, TYPE=C3D8, ELSET=SLAB\n";
    for j in 0..n {
        for i in 0..n {
            let c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let nodes: Vec<String> =
                [0, 1].iter().flat_map(|&l| c.map(|(a, b)| node(a, b, l).to_string())).collect();
            inp += &format!("{}, {}\n", j * n + i + 1, nodes.join(", "));
        }
    }
    inp += "*SURFACE, NAME=TOP, TYPE=ELEMENT\nSLAB, S2\n";
    let tmp = tempfile::tempdir().unwrap();
    let master = write(tmp.path(), "master.msh", &quads_msh(2, 1, Some(3)));
    let slave = write(tmp.path(), "slave.inp", &inp);
    let args = ["check", &master, &slave, "--slave-group", "top", "--json", "r.json", "--strict"];
    let o = seam(&args, tmp.path());
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{err}");
    let faces = "slave faces element 11 face S2, element 12 face S2, element 15 face S2, element 16 face S2";
    assert!(err.contains(faces), "{err}");
    assert!(String::from_utf8_lossy(&o.stdout).contains(&format!("at {faces}\n")));
    let r = json(&tmp.path().join("r.json"));
    assert_eq!(r["face_ids"], seam_case::check::ELEMENT_FACE_TAGS);
    let face = |e: u64| seam_io::abaqus::face_tag(e, 2);
    let violated: Vec<&serde_json::Value> =
        r["invariants"].as_array().unwrap().iter().filter(|i| i["ok"] == false).collect();
    assert_eq!(
        violated[0]["offending_faces"],
        serde_json::json!([face(11), face(12), face(15), face(16)]),
        "{r}"
    );
}

#[test]
fn assemble_writes_the_mortar_segments() {
    let tmp = tempfile::tempdir().unwrap();
    let (master, slave) = (fixture("square_tri.v41.ascii.msh"), fixture("square_mixed.v41.ascii.msh"));
    let o = seam(&["assemble", &master, &slave, "-o", "out", "--segments", "seg/segments.vtu"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let seg = vtu(&tmp.path().join("seg/segments.vtu"));
    let s = summary(&tmp.path().join("out"));
    assert_eq!(seg.mesh.n_faces() as u64, s["segments"].as_u64().unwrap());
    let slave_ids = seg.cell_data.iter().find(|f| f.name == "slave_face").unwrap();
    assert!(slave_ids.values.iter().all(|&v| v >= 0.0 && v < s["slave_faces"].as_f64().unwrap()));
}

#[test]
fn transfer_bad_input_is_reported_cleanly() {
    let tmp = tempfile::tempdir().unwrap();
    // A VTU whose point field has 3 values for 4 points.
    let bad = write(
        tmp.path(),
        "short.vtu",
        r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
<UnstructuredGrid><Piece NumberOfPoints="4" NumberOfCells="2">
<PointData><DataArray type="Float64" Name="T" format="ascii">1 2 3</DataArray></PointData>
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 1 1 0 0 1 0</DataArray></Points>
<Cells><DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 0 2 3</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">3 6</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">5 5</DataArray></Cells>
</Piece></UnstructuredGrid></VTKFile>
"#,
    );
    let target = fixture("square_mixed.v41.ascii.msh");
    let o = seam(&["transfer", &bad, &target, "-o", "o.vtu", "--field", "T"], tmp.path());
    assert_clean_failure(&o, 2, "short.vtu", "T", &tmp.path().join("nothing"));
    assert!(!tmp.path().join("o.vtu").exists());
    // Surfaces five units apart: no coupling, exit 1.
    let far = write(
        tmp.path(),
        "far.msh",
        &square_msh("3 1 1 0", "2 2 2 1 1 1 3 4")
            .replace("\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0", "\n1 5 0 0\n2 6 0 0\n3 6 1 0\n4 5 1 0"),
    );
    let o = seam(&["transfer", &far, &target, "-o", "o.vtu", "--expr", "x"], tmp.path());
    assert_clean_failure(&o, 1, "far.msh", "do not overlap", &tmp.path().join("nothing"));
    assert!(!tmp.path().join("o.vtu").exists() && !tmp.path().join("o.json").exists());
}

#[test]
fn bench_transfer_prints_a_row_per_run_and_leaves_nothing_behind() {
    let tmp = tempfile::tempdir().unwrap();
    let o = seam(
        &[
            "bench-transfer",
            "--sizes",
            "400",
            "--threads",
            "1",
            "--multipliers",
            "dual,standard",
            "--modes",
            "conservative",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    let rows: Vec<&str> = table.lines().skip(2).collect();
    assert_eq!(rows.len(), 2, "{table}");
    for (row, multiplier) in rows.iter().zip(["dual", "standard"]) {
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        assert_eq!(&cells[1..6], ["400", cells[2], "conservative", multiplier, "1"], "{row}");
        let seconds: Vec<f64> = cells[6..14].iter().map(|c| c.parse().unwrap()).collect();
        assert!(seconds.iter().all(|&t| t >= 0.0) && seconds[7] > 0.0, "{row}");
    }
    let pid_dirs = std::fs::read_dir(std::env::temp_dir())
        .unwrap()
        .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with("seam-bench-transfer-"))
        .count();
    assert_eq!(pid_dirs, 0, "the benchmark removes its files");
}

/// `seam transfer` and `seam check` on second-order files: the top of the
/// Hex27 box (Quad9 faces, MSH 4.1 binary) and of the Tet10 box (Tri6 faces,
/// MSH 2.2 ASCII). Both tops are flat with straight edges, where
/// second-order spaces reproduce every quadratic field: the transferred field
/// equals the expression at every target node, mid-side nodes included, in
/// both directions and both modes keep the total.
#[test]
fn second_order_files_go_through_transfer_and_check() {
    let tmp = tempfile::tempdir().unwrap();
    let (hex, tet) = (fixture("box_hex_o2.v41.bin.msh"), fixture("box_tet_o2.v22.ascii.msh"));
    let groups = ["--source-group", "top", "--target-group", "top"];
    let expr = "1 + x - 2*y + 0.5*x*x - x*y + 2*y*y";
    let exact = |x: [f64; 3]| 1.0 + x[0] - 2.0 * x[1] + 0.5 * x[0] * x[0] - x[0] * x[1] + 2.0 * x[1] * x[1];
    for (source, target, name) in [(&hex, &tet, "to_tet"), (&tet, &hex, "to_hex")] {
        for multiplier in ["standard", "dual"] {
            let out = format!("{name}_{multiplier}.vtu");
            let o = seam(
                &[
                    &["transfer", source, target, "-o", &out, "--expr", expr, "--multiplier", multiplier][..],
                    &groups,
                ]
                .concat(),
                tmp.path(),
            );
            assert!(o.status.success(), "{name} {multiplier}: {}", stderr(&o));
            let result = vtu(&tmp.path().join(&out));
            let f = result.point_field("f").unwrap();
            let used = result.mesh.used_points();
            let (mut checked, mut corner_only) = (0, 0);
            for (p, &x) in result.mesh.points().iter().enumerate().filter(|&(p, _)| used[p]) {
                // The hex top is [0,2]×[0,1], the tet top [0,1]²: only covered nodes.
                if x[0] > 1.0 + 1e-12 {
                    continue;
                }
                assert!(
                    (f.values[p] - exact(x)).abs() < 1e-11,
                    "{name} {multiplier} at {x:?}: {}",
                    f.values[p]
                );
                checked += 1;
                corner_only +=
                    result.mesh.faces().iter().any(|face| face.corner_nodes().contains(&p)) as usize;
            }
            assert!(checked > 0 && corner_only < checked, "{name}: mid-side nodes checked");
        }
        if name == "to_tet" {
            continue; // conservative: the hex top's right half has no target to receive its loads
        }
        let out = format!("{name}_conservative.vtu");
        let o = seam(
            &[
                &["transfer", source, target, "-o", &out, "--expr", expr, "--mode", "conservative"][..],
                &groups,
            ]
            .concat(),
            tmp.path(),
        );
        assert!(o.status.success(), "{name} conservative: {}", stderr(&o));
        let s = json(&tmp.path().join(format!("{name}_conservative.json")));
        let (a, b) = (s["total_source"][0].as_f64().unwrap(), s["total_target"][0].as_f64().unwrap());
        assert!((a - b).abs() < 1e-12 * a.abs(), "{name}: total {a} vs {b}");
    }
    // check: the Tet10 top as slave is fully covered by the Hex27 top.
    let o = seam(
        &[
            "check",
            &hex,
            &tet,
            "--master-group",
            "top",
            "--slave-group",
            "top",
            "--json",
            "c.json",
            "--strict",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let r = json(&tmp.path().join("c.json"));
    assert_eq!(r["ok"], true, "{r}");
    assert!(r["invariants"].as_array().unwrap().iter().all(|i| i["ok"] == true), "{r}");
}
