//! `seam example bulging-contact` and `seam example hertz`, run as a user
//! would (at small sizes): the files they leave, the contact results in
//! summary.json, the pictures, Hertz's comparison, and no overwriting without
//! `--force`.

use crate::common;

use common::{json, seam, stderr};
use std::path::Path;

/// Decodes a PNG file completely and returns its size.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes)).read_info().unwrap();
    let mut buffer = vec![0; reader.output_buffer_size().unwrap()];
    let frame = reader.next_frame(&mut buffer).unwrap();
    (frame.width, frame.height)
}

/// The contact object of a summary: steps, active points, KKT residual,
/// and the multiplier.
fn check_contact(summary: &serde_json::Value, multiplier: &str) {
    let c = &summary["contact"];
    assert!(c["iterations"].as_u64().unwrap() >= 1, "{c}");
    assert!(c["active_points"].as_u64().unwrap() > 0, "{c}");
    assert!(c["kkt"]["max"].as_f64().unwrap() <= 1e-8, "{c}");
    assert_eq!(summary["multiplier"], multiplier);
}

/// `files` in `dir`, and per body its mesh `<body>.msh` and result `out/<body>.vtu`.
fn assert_files(dir: &Path, bodies: &[&str], files: &[&str]) {
    let per_body = bodies.iter().flat_map(|b| [format!("{b}.msh"), format!("out/{b}.vtu")]);
    for file in per_body
        .chain(files.iter().map(|f| f.to_string()))
        .chain(["case.toml".into(), "out/summary.json".into()])
    {
        assert!(dir.join(&file).is_file(), "{file} in {}", dir.display());
    }
}

#[test]
fn bulging_contact_writes_its_case_results_and_picture() {
    let tmp = tempfile::tempdir().unwrap();
    let args = ["example", "bulging-contact", "-o", "ex", "--slave-cells", "8"];
    let o = seam(&args, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let report = String::from_utf8_lossy(&o.stdout);
    for part in
        ["12×12×6 hexahedra (master)", "8×8×4 hexahedra (slave)", "active-set step", "bulging-contact.png"]
    {
        assert!(report.contains(part), "'{part}' in:\n{report}");
    }
    let ex = tmp.path().join("ex");
    assert_files(&ex, &["lower", "upper"], &["out/upper_bottom_interface.vtu", "bulging-contact.png"]);
    let case = std::fs::read_to_string(ex.join("case.toml")).unwrap();
    assert!(case.contains("kind = \"contact\"\nmultiplier = \"lumped\""), "{case}");
    assert_eq!(png_size(&ex.join("bulging-contact.png")), (1560, 1164));
    let first = json(&ex.join("out/summary.json"));
    check_contact(&first, "lumped");
    let (_, pressure) =
        common::vtu_field(&ex.join("out/upper_bottom_interface.vtu"), "contact_pressure", false);
    assert!(pressure.iter().any(|&p| p > 0.0) && pressure.iter().all(|&p| p >= 0.0));

    // Nothing is overwritten without --force, not even the picture alone.
    let picture = std::fs::read(ex.join("bulging-contact.png")).unwrap();
    let o = seam(&args, tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("already exists; pass --force"), "{}", stderr(&o));
    for file in ["lower.msh", "upper.msh", "case.toml"] {
        std::fs::remove_file(ex.join(file)).unwrap();
    }
    std::fs::remove_dir_all(ex.join("out")).unwrap();
    let o = seam(&args, tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("bulging-contact.png already exists"), "{}", stderr(&o));
    assert!(!ex.join("case.toml").exists(), "nothing written");
    assert_eq!(std::fs::read(ex.join("bulging-contact.png")).unwrap(), picture);
    // With --force it runs again; `seam solve` on its case gives the same result.
    let o = seam(&[&args[..], &["--force"]].concat(), tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let o = seam(&["solve", "ex/case.toml", "--force"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let again = json(&ex.join("out/summary.json"));
    assert_eq!(again["dofs"], first["dofs"]);
    assert_eq!(again["contact"]["active_points"], first["contact"]["active_points"]);
    assert_eq!(again["contact"]["interfaces"][0]["force"], first["contact"]["interfaces"][0]["force"]);
}

/// A row of hertz.csv.
struct Node {
    axis: String,
    r: f64,
    pressure: f64,
    hertz: f64,
    active: bool,
}

#[test]
fn hertz_matches_the_analytic_solution_within_a_slave_element() {
    let tmp = tempfile::tempdir().unwrap();
    let cells = 4;
    let o = seam(&["example", "hertz", "-o", "hz", "--slave-cells", &cells.to_string()], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let report = String::from_utf8_lossy(&o.stdout);
    for part in ["| contact radius a |", "| peak pressure p0 |", "| force on the quarter F/4 |"] {
        assert!(report.contains(part), "'{part}' in:\n{report}");
    }
    let hz = tmp.path().join("hz");
    assert_files(&hz, &["indenter", "block"], &["hertz.md", "hertz.csv", "out/block_top_interface.vtu"]);
    assert_eq!(png_size(&hz.join("hertz.png")), (1000, 680));
    let summary = json(&hz.join("out/summary.json"));
    check_contact(&summary, "lumped");
    let md = std::fs::read_to_string(hz.join("hertz.md")).unwrap();
    assert!(md.contains("| quantity | analytic (Hertz) | seam | error |"), "{md}");

    let params = seam_fem::scene::Hertz { fine_cells: cells, ..Default::default() };
    let (a, p0, h) = (params.contact_radius, params.peak_pressure(), params.slave_size());
    let csv = std::fs::read_to_string(hz.join("hertz.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("axis,x,y,r,contact_pressure,hertz_pressure,active"));
    let nodes: Vec<Node> = lines
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let num = |k: usize| f[k].parse::<f64>().unwrap();
            Node { axis: f[0].into(), r: num(3), pressure: num(4), hertz: num(5), active: f[6] == "1" }
        })
        .collect();
    for axis in ["x", "y"] {
        let on: Vec<&Node> = nodes.iter().filter(|n| n.axis == axis).collect();
        assert!(on.len() > 2 * cells, "axis {axis}: {} nodes", on.len());
        // The pole: the peak pressure within 5 %.
        let pole = on.iter().find(|n| n.r == 0.0).expect("a node at the pole");
        assert!((pole.pressure / p0 - 1.0).abs() < 0.05, "p0: seam {}, Hertz {p0}", pole.pressure);
        assert!((pole.hertz - p0).abs() < 1e-12 * p0);
        // The contact radius: the outermost active node within one slave
        // element of a, and every node beyond a + h inactive and unloaded.
        let outermost = on.iter().filter(|n| n.active).map(|n| n.r).fold(0.0, f64::max);
        assert!(
            (outermost - a).abs() <= h,
            "axis {axis}: outermost active node at {outermost}, a = {a}, h = {h}"
        );
        for n in on.iter().filter(|n| n.r > a + h) {
            assert!(!n.active && n.pressure == 0.0 && n.hertz == 0.0, "axis {axis}: r = {}", n.r);
        }
    }
    // The contact force on the quarter is F/4.
    let force = -summary["contact"]["interfaces"][0]["force"][2].as_f64().unwrap();
    assert!((force / (params.force() / 4.0) - 1.0).abs() < 1e-8, "force {force}");
}

#[test]
fn cattaneo_mindlin_writes_every_load_step_and_compares_the_partial_slip() {
    let tmp = tempfile::tempdir().unwrap();
    let o = seam(&["example", "cattaneo-mindlin", "-o", "cm", "--slave-cells", "3"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let report = String::from_utf8_lossy(&o.stdout);
    for part in ["| stick radius c |", "| contact radius a |", "| tangential traction q |"] {
        assert!(report.contains(part), "'{part}' in:\n{report}");
    }
    let cm = tmp.path().join("cm");
    let steps = ["out/steps/block_0005.vtu", "out/block.pvd", "out/block_top_interface.pvd"];
    let files = ["cattaneo-mindlin.md", "cattaneo-mindlin.csv", "out/block_top_interface.vtu"];
    assert_files(&cm, &["indenter", "block"], &[&files[..], &steps[..]].concat());
    assert_eq!(png_size(&cm.join("cattaneo-mindlin.png")), (1000, 680));
    let summary = json(&cm.join("out/summary.json"));
    check_contact(&summary, "dual");
    // One step presses, four shear; the last has sticking and slipping points.
    let steps = summary["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 5);
    let last = &steps[4];
    assert!(last["stick"].as_u64().unwrap() > 0 && last["slip"].as_u64().unwrap() > 0, "{last}");
    let csv = std::fs::read_to_string(cm.join("cattaneo-mindlin.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("x,contact_pressure,tangential_traction_x,cattaneo_mindlin,stick"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert!(rows.iter().any(|r| r[0] == 0.0 && r[4] == 1.0), "the centre sticks: {csv}");
    // Coulomb's cone, μ = 0.3.
    assert!(rows.iter().all(|r| r[2].abs() <= 0.3 * r[1] * (1.0 + 1e-9) + 1e-12), "{csv}");
}

/// `seam example ironing` (coarse): both runs written as cases with their
/// results, every load step converged by Newton, the forces over the steps
/// in the CSV and the picture; while the indenter slides, F_x / F_z is about
/// −μ with friction (within 0.05, the slab's ploughing) and about 0 without.
#[test]
fn ironing_writes_both_runs_and_the_forces_over_the_load_steps() {
    let tmp = tempfile::tempdir().unwrap();
    let o = seam(&["example", "ironing", "-o", "iron", "--slave-cells", "2"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let iron = tmp.path().join("iron");
    for run in ["frictionless", "friction"] {
        let files = ["out/steps/indenter_0020.vtu", "out/indenter.pvd", "out/indenter_bottom_interface.pvd"];
        assert_files(&iron.join(run), &["slab", "indenter"], &files);
        let case = std::fs::read_to_string(iron.join(run).join("case.toml")).unwrap();
        assert_eq!(case.matches("material = \"neo-hookean\"").count(), 2, "{case}");
        let summary = json(&iron.join(run).join("out/summary.json"));
        for step in summary["steps"].as_array().unwrap() {
            assert!(
                step["residuals"].as_array().unwrap().last().unwrap().as_f64().unwrap() <= 1e-10,
                "{step}"
            );
            assert!(step["active"].as_u64().unwrap() > 0, "{step}");
        }
    }
    for file in ["ironing.md", "ironing.csv"] {
        assert!(iron.join(file).is_file(), "{file}");
    }
    assert_eq!(png_size(&iron.join("ironing.png")), (1680, 564));
    let csv = std::fs::read_to_string(iron.join("ironing.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("friction,t,force_x,force_y,force_z"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), 40);
    for r in rows.iter().filter(|r| r[1] > 0.3) {
        let expected = -r[0];
        assert!(r[4] > 0.0 && (r[2] / r[4] - expected).abs() < 0.05, "{r:?}");
    }
}
