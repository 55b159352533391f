//! `seam solve CASE.toml` and `seam example warped-glue`, run as a user would:
//! meshes written with seam-io's MSH writer, a case file, the binary.

use crate::common;

use common::{assert_rejected, json, seam, stacked_case, stderr, vtu_field, write_stacked_blocks};
use std::path::Path;

const E: f64 = 1000.0;
const NU: f64 = 0.25;
const P: f64 = 2.0;

/// Two blocks stacked at the flat interface z = 1/2, meshed 3×3×2 (lower,
/// master) and 2×2×2 with graded x (upper, slave), on rollers at x = 0, y = 0
/// and z = 0, pressed by P on top: uniaxial stress σ_zz = −P, whose
/// displacement u = (νPx, νPy, −Pz)/E is linear, so exact for Hex8 and mortar.
fn patch_case(dir: &Path, multiplier: &str) {
    write_stacked_blocks(dir);
    let interface = format!("kind = \"glue\"\nmultiplier = \"{multiplier}\"");
    let rest = format!(
        "[[traction]]\nboundary = \"upper:top\"\nt = [0.0, 0.0, -{P:?}]\n\n[output]\ndir = \"out\"\n"
    );
    let case = stacked_case((E, NU), (E, NU), &interface, &rest);
    std::fs::write(dir.join("case.toml"), case).unwrap();
}

#[test]
fn a_glued_patch_test_is_exact_and_balanced() {
    for (multiplier, solver) in
        [("standard", "direct"), ("dual", "direct"), ("standard", "pcg"), ("dual", "pcg")]
    {
        let tmp = tempfile::tempdir().unwrap();
        patch_case(tmp.path(), multiplier);
        let o = seam(&["solve", "case.toml", "--solver", solver, "--rtol", "1e-14"], tmp.path());
        assert!(o.status.success(), "{multiplier}: {}", stderr(&o));
        let report = String::from_utf8_lossy(&o.stdout);
        assert!(report.contains("balance    upper"), "{report}");
        let out = tmp.path().join("out");
        for body in ["lower", "upper"] {
            let (points, u) = vtu_field(&out.join(format!("{body}.vtu")), "displacement", false);
            for (x, u) in points.iter().zip(u.chunks(3)) {
                let exact = [NU * P * x[0] / E, NU * P * x[1] / E, -P * x[2] / E];
                for k in 0..3 {
                    assert!(
                        (u[k] - exact[k]).abs() < 1e-12 * P / E,
                        "{multiplier} {body} at {x:?}: {u:?} vs {exact:?}"
                    );
                }
            }
            let (_, stress) = vtu_field(&out.join(format!("{body}.vtu")), "stress", true);
            for s in stress.chunks(6) {
                let exact = [0.0, 0.0, -P, 0.0, 0.0, 0.0];
                assert!(
                    s.iter().zip(exact).all(|(a, b)| (a - b).abs() < 1e-10),
                    "{multiplier} {body}: σ = {s:?}"
                );
            }
            let (_, vm) = vtu_field(&out.join(format!("{body}.vtu")), "von_mises", true);
            assert!(vm.iter().all(|v| (v - P).abs() < 1e-10));
        }
        // The interface: uniform compression P, no shear.
        let f = seam_io::read_vtu_file(out.join("upper_bottom_interface.vtu")).unwrap();
        assert_eq!(f.mesh.n_points(), 9, "the slave surface's own points");
        let tn = f.point_field("normal_traction").unwrap();
        assert!(tn.values.iter().all(|v| (v + P).abs() < 1e-10), "{multiplier}: {:?}", tn.values);
        let tt = f.point_field("tangential_traction").unwrap();
        assert!(tt.values.iter().all(|v| v.abs() < 1e-10));
        assert!(f.point_field("constrained").unwrap().values.iter().all(|&c| c == 1.0));
        for name in ["traction", "normal", "displacement", "body_point"] {
            assert!(f.point_field(name).is_some(), "{name}");
        }
        // summary.json: the force through the interface is the load on the upper body.
        let s = json(&out.join("summary.json"));
        for key in [
            "dofs",
            "constraints",
            "multiplier",
            "solver",
            "method",
            "iterations",
            "residual",
            "applied_load",
            "bodies",
            "interfaces",
            "seconds",
        ] {
            assert!(s.get(key).is_some(), "summary.json lacks {key}");
        }
        for phase in
            ["read", "assembly", "mortar", "setup", "factorization", "solve", "stresses", "output", "total"]
        {
            assert!(s["seconds"][phase].as_f64().unwrap() >= 0.0, "{phase}");
        }
        assert_eq!(s["multiplier"], multiplier);
        assert_eq!(s["solver"], solver);
        assert_eq!(s["dofs"], 3 * (4 * 4 * 3 + 3 * 3 * 3));
        assert!(s["residual"].as_f64().unwrap() < 1e-10);
        let force: Vec<f64> = (0..3).map(|k| s["interfaces"][0]["force"][k].as_f64().unwrap()).collect();
        let load: Vec<f64> = (0..3).map(|k| s["bodies"][1]["applied_load"][k].as_f64().unwrap()).collect();
        assert!((load[2] + P).abs() < 1e-12, "P over the unit square: {load:?}");
        for k in 0..3 {
            assert!((force[k] + load[k]).abs() <= 1e-10 * P, "{multiplier}: force {force:?}, load {load:?}");
        }
        assert_eq!(s["interfaces"][0]["mortar"]["slave_nodes"], 9);
        assert_eq!(s["interfaces"][0]["slave"], "upper:bottom");
    }
}

#[test]
fn input_errors_fail_with_one_line_before_any_work() {
    let tmp = tempfile::tempdir().unwrap();
    patch_case(tmp.path(), "standard");
    let good = std::fs::read_to_string(tmp.path().join("case.toml")).unwrap();
    let cases = [
        (good.replace("slave = \"upper:bottom\"", "slave = \"middle:bottom\""), "no body named \"middle\""),
        (good.replace("slave = \"upper:bottom\"", "slave = \"upper:bottm\""), "\"bottm\""),
        (good.replace("mesh = \"upper.msh\"", "mesh = \"nowhere.msh\""), "nowhere.msh does not exist"),
        (good.replacen(&format!("young = {E:?}"), "young = -5.0", 1), "Young's modulus E = -5.0 must be positive"),
        (
            good.replacen(&format!("poisson = {NU}"), "poisson = 0.5", 1),
            "Poisson's ratio ν = 0.5 must lie in (-1, 0.5)",
        ),
        (good.replace("uz = 0.0", "ux = 0.0"), "can move freely along z"),
        (
            good.replace("kind = \"glue\"", "kind = \"contact\""),
            "interface 1 (upper:bottom → lower:top): contact needs multiplier \"lumped\" (the default) or \"dual\"",
        ),
        (good.replace("young", "youngs"), "unknown field `youngs`"),
        (good.replace("mesh = \"upper.msh\"", "mesh = \"case.toml\""), "not a Gmsh MSH file"),
    ];
    assert_rejected(tmp.path(), &cases);
    // An unknown surface names the body and the mesh, and lists the surfaces there are.
    std::fs::write(tmp.path().join("bad.toml"), good.replace("upper:top", "upper:lid")).unwrap();
    let err = stderr(&seam(&["solve", "bad.toml"], tmp.path()));
    for part in ["body \"upper\"", "upper.msh", "\"lid\"", "bottom", "top"] {
        assert!(err.contains(part), "'{part}' in: {err}");
    }
    let o = seam(&["solve", "missing.toml"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("missing.toml"));
}

#[test]
fn results_are_not_overwritten_without_force() {
    let tmp = tempfile::tempdir().unwrap();
    patch_case(tmp.path(), "dual");
    assert!(seam(&["solve", "case.toml"], tmp.path()).status.success());
    let summary = tmp.path().join("out/summary.json");
    let before = std::fs::read(&summary).unwrap();
    let o = seam(&["solve", "case.toml"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("already exists; pass --force"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&summary).unwrap(), before);
    let o = seam(&["solve", "case.toml", "--force", "--solver", "direct", "--threads", "1"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(json(&summary)["threads"], 1);
}

#[test]
fn the_warped_glue_example_writes_a_case_that_solve_reruns() {
    let tmp = tempfile::tempdir().unwrap();
    let o = seam(&["example", "warped-glue", "-o", "ex", "--ratio", "2"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let report = String::from_utf8_lossy(&o.stdout);
    for part in ["h_s/h_m = 2", "81 nodes", "balance    upper", "max |u|", "seconds", "warped-glue.png"] {
        assert!(report.contains(part), "'{part}' in:\n{report}");
    }
    let ex = tmp.path().join("ex");
    for file in [
        "lower.msh",
        "upper.msh",
        "case.toml",
        "out/lower.vtu",
        "out/upper.vtu",
        "out/upper_bottom_interface.vtu",
    ] {
        assert!(ex.join(file).is_file(), "{file}");
    }
    let png = std::fs::read(ex.join("warped-glue.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let first = json(&ex.join("out/summary.json"));
    assert_eq!(first["interfaces"][0]["mortar"]["slave_nodes"], 81);
    let force = &first["interfaces"][0]["force"];
    let load = &first["bodies"][1]["applied_load"];
    for k in 0..3 {
        let (f, l) = (force[k].as_f64().unwrap(), load[k].as_f64().unwrap());
        assert!((f + l).abs() <= 1e-10 * 1.02, "component {k}: force {f}, load {l}");
    }
    // Not again without --force; `seam solve` on its case gives the same result.
    let o = seam(&["example", "warped-glue", "-o", "ex", "--ratio", "2"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("already exists"));
    let o = seam(&["solve", "ex/case.toml", "--force"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let again = json(&ex.join("out/summary.json"));
    assert_eq!(again["dofs"], first["dofs"]);
    assert_eq!(again["interfaces"][0]["force"], first["interfaces"][0]["force"]);
}

/// `seam example warped-glue --order 2` through the binary: Hex27 bodies
/// written as second-order MSH files, the interface's 81 slave nodes of
/// Quad9 faces; the case it writes solves again to the same result.
#[test]
fn the_second_order_warped_glue_example_runs_and_reruns() {
    let tmp = tempfile::tempdir().unwrap();
    let o = seam(&["example", "warped-glue", "-o", "ex", "--order", "2", "--ratio", "2"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let report = String::from_utf8_lossy(&o.stdout);
    for part in ["Hex27 cells", "h_s/h_m = 2", "81 nodes", "balance    upper"] {
        assert!(report.contains(part), "'{part}' in:\n{report}");
    }
    let ex = tmp.path().join("ex");
    let mesh = seam_io::read_volume_file(ex.join("upper.msh"), None).unwrap();
    assert!(mesh.cells().iter().all(|c| matches!(c, seam::Cell::Hex27(_))), "Hex27 cells in upper.msh");
    let first = json(&ex.join("out/summary.json"));
    let force = &first["interfaces"][0]["force"];
    let load = &first["bodies"][1]["applied_load"];
    for k in 0..3 {
        let (f, l) = (force[k].as_f64().unwrap(), load[k].as_f64().unwrap());
        assert!((f + l).abs() <= 1e-10, "component {k}: force {f}, load {l}");
    }
    let o = seam(&["solve", "ex/case.toml", "--force"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let again = json(&ex.join("out/summary.json"));
    assert_eq!(again["dofs"], first["dofs"]);
    assert_eq!(again["interfaces"][0]["force"], first["interfaces"][0]["force"]);
}

/// Built without the `petsc` feature, `--solver petsc` says how to get it
/// (one line, exit code 2, nothing written).
#[cfg(not(feature = "petsc"))]
#[test]
fn petsc_without_the_feature_says_how_to_build_it() {
    let tmp = tempfile::tempdir().unwrap();
    let o = seam(&["example", "warped-glue", "-o", "ex", "--ratio", "2"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::remove_dir_all(tmp.path().join("ex/out")).unwrap();
    let o = seam(&["solve", "ex/case.toml", "--solver", "petsc"], tmp.path());
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    assert!(e.contains("built without PETSc") && e.contains("--features petsc"), "{e}");
    assert!(!tmp.path().join("ex/out").exists());
}

/// One MSH 2.2 file holding two physical volumes, "lower" (z < 1) and "upper"
/// (z > 1), of n × n × n Hex8 cells each over [0, 1]² × [0, 2] (x graded),
/// nodes numbered with z fastest so that each volume's nodes are scattered
/// through the file; physical surfaces "bottom" (z = 0), "xmin" and "ymin"
/// (of the lower volume), "mid" (z = 1, between the volumes) and "top" (z = 2).
fn two_volume_msh(n: usize) -> String {
    let nz = 2 * n;
    let node = |i: usize, j: usize, k: usize| 1 + k + (nz + 1) * (i + (n + 1) * j);
    let mut nodes = vec![String::new(); (n + 1) * (n + 1) * (nz + 1)];
    for (i, j, k) in (0..=n).flat_map(|i| (0..=n).flat_map(move |j| (0..=nz).map(move |k| (i, j, k)))) {
        let (u, v, w) = (i as f64 / n as f64, j as f64 / n as f64, k as f64 / n as f64);
        nodes[node(i, j, k) - 1] = format!("{} {:?} {:?} {:?}", node(i, j, k), 0.7 * u + 0.3 * u * u, v, w);
    }
    let mut elements: Vec<String> = Vec::new();
    let mut push = |kind: u32, physical: u32, nodes: &[usize]| {
        let list: Vec<String> = nodes.iter().map(usize::to_string).collect();
        elements.push(format!("{} {kind} 2 {physical} {physical} {}", elements.len() + 1, list.join(" ")));
    };
    for (i, j, k) in (0..n).flat_map(|i| (0..n).flat_map(move |j| (0..nz).map(move |k| (i, j, k)))) {
        let hex = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
            .map(|(a, b, c)| node(i + a, j + b, k + c));
        push(5, if k < n { 1 } else { 2 }, &hex);
    }
    for (a, b) in (0..n).flat_map(|a| (0..n).map(move |b| (a, b))) {
        let z = |k| [node(a, b, k), node(a + 1, b, k), node(a + 1, b + 1, k), node(a, b + 1, k)];
        push(3, 3, &z(0));
        push(3, 6, &z(n));
        push(3, 7, &z(nz));
        push(3, 4, &[node(0, a, b), node(0, a + 1, b), node(0, a + 1, b + 1), node(0, a, b + 1)]);
        push(3, 5, &[node(a, 0, b), node(a + 1, 0, b), node(a + 1, 0, b + 1), node(a, 0, b + 1)]);
    }
    let names = ["3 1 \"lower\"", "3 2 \"upper\"", "2 3 \"bottom\"", "2 4 \"xmin\"", "2 5 \"ymin\""];
    let names = [&names[..], &["2 6 \"mid\"", "2 7 \"top\""]].concat();
    format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n{}\n{}\n$EndPhysicalNames\n\
         $Nodes\n{}\n{}\n$EndNodes\n$Elements\n{}\n{}\n$EndElements\n",
        names.len(),
        names.join("\n"),
        nodes.len(),
        nodes.join("\n"),
        elements.len(),
        elements.join("\n")
    )
}

/// Two bodies, each one physical volume of the same file (`volume = ...`),
/// glued at the surface between them: the other volume's nodes are not
/// unknowns (the dofs count only the body's own), the shared surface faces
/// out of each body, and the uniaxial patch test u = (νPx, νPy, −Pz)/E holds
/// on every node of each body, written in the file's node numbering (the
/// nodes of the other volume: zero).
#[test]
fn bodies_from_the_volumes_of_one_file_are_glued_and_exact() {
    let tmp = tempfile::tempdir().unwrap();
    let n = 2;
    std::fs::write(tmp.path().join("two.msh"), two_volume_msh(n)).unwrap();
    let body = |name: &str| {
        format!("[[body]]\nname = \"{name}\"\nmesh = \"two.msh\"\nvolume = \"{name}\"\nyoung = {E:?}\npoisson = {NU:?}\n\n")
    };
    let case = format!(
        "{}{}[[interface]]\nmaster = \"lower:mid\"\nslave = \"upper:mid\"\nkind = \"glue\"\n\n\
         [[dirichlet]]\nboundary = \"lower:bottom\"\nuz = 0.0\n\n[[dirichlet]]\nboundary = \"lower:xmin\"\nux = 0.0\n\n\
         [[dirichlet]]\nboundary = \"lower:ymin\"\nuy = 0.0\n\n[[traction]]\nboundary = \"upper:top\"\nt = [0.0, 0.0, -{P:?}]\n",
        body("lower"),
        body("upper")
    );
    std::fs::write(tmp.path().join("case.toml"), &case).unwrap();
    let o = seam(&["solve", "case.toml"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let per_body = 3 * (n + 1) * (n + 1) * (n + 1);
    assert_eq!(json(&tmp.path().join("out/summary.json"))["dofs"], 2 * per_body);
    for (name, z) in [("lower", 0.0..=1.0), ("upper", 1.0..=2.0)] {
        let (points, u) = vtu_field(&tmp.path().join(format!("out/{name}.vtu")), "displacement", false);
        assert_eq!(points.len(), (n + 1) * (n + 1) * (2 * n + 1), "the file's nodes");
        for (x, u) in points.iter().zip(u.chunks(3)) {
            let exact = match z.contains(&x[2]) {
                true => [NU * P * x[0] / E, NU * P * x[1] / E, -P * x[2] / E],
                false => [0.0; 3],
            };
            assert!(
                (0..3).all(|k| (u[k] - exact[k]).abs() < 1e-12 * P / E),
                "{name} at {x:?}: {u:?} vs {exact:?}"
            );
        }
    }
    // A surface of the other volume is named as such.
    std::fs::remove_dir_all(tmp.path().join("out")).unwrap();
    let bad = case.replace("boundary = \"upper:top\"", "boundary = \"lower:top\"");
    assert_rejected(
        tmp.path(),
        &[(bad, "element 19 of physical group \"top\" (7) is not on physical group \"lower\" (1): its node 5 is in no cell")],
    );
}
