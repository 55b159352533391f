//! Models from Exodus II files (feature `exodus`) through `seam solve` and
//! `seam assemble`: the same model as MSH and as Exodus (written by the
//! SEACAS library from Gmsh's mesh, seam-io's fixtures) gives byte-identical
//! operators and solutions, glued and in contact; bad files are one line
//! naming the body and file.

use crate::common;

use common::{assert_rejected, seam, stacked_case, stderr, vtu_field};
use seam::{Face, SurfaceMesh};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../seam-io/tests/data").join(name)
}

/// Runs `seam ARGS` in `dir` and asserts success.
fn run(args: &[&str], dir: &Path) {
    let o = seam(args, dir);
    assert!(o.status.success(), "seam {args:?}: {}", stderr(&o));
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Writes the MSH twin of an Exodus body with seam's MSH writer: its points
/// and cells, and each side set as the faces the reader makes of it (each
/// starts at the corner the cell's face starts at, where Gmsh's own boundary
/// elements start anywhere, which changes the order of quadrature sums and
/// so the last bits). Faces come first, so the cells keep Gmsh's tags.
fn write_msh_twin(exodus: &Path, msh: &Path, sides: &[&str]) {
    let model = seam_io::read_model_file(exodus, None).unwrap();
    let volume = model.volume(None).unwrap();
    let bits = |p: &[f64; 3]| p.map(f64::to_bits);
    let index: HashMap<[u64; 3], usize> =
        volume.points().iter().enumerate().map(|(i, p)| (bits(p), i)).collect();
    let surfaces: Vec<(&str, SurfaceMesh)> = sides
        .iter()
        .map(|&side| {
            let s = model.surface_of_volume(side, None).unwrap();
            let faces = s
                .faces()
                .iter()
                .map(|f| {
                    Face::from_nodes(
                        &f.nodes().iter().map(|&n| index[&bits(&s.points()[n])]).collect::<Vec<_>>(),
                    )
                })
                .collect();
            (side, SurfaceMesh::new(volume.points().to_vec(), faces).unwrap())
        })
        .collect();
    let refs: Vec<(&str, &SurfaceMesh)> = surfaces.iter().map(|(n, s)| (*n, s)).collect();
    seam_io::write_volume_msh_file(msh, &volume, "body", &refs).unwrap();
}

/// The blocks (non-matching hexahedra meshed by Gmsh, written by the
/// SEACAS library: classic lower.e, NetCDF-4 upper.ex2; side sets bottom,
/// top, xmin, ymin), glued and in contact (dual multipliers, the upper block
/// on rollers and pressed), and their MSH twins: the Exodus case writes
/// byte-identical files, ids included; so does one whose upper body is a
/// `.mesh` file read with `format = "exodus"` and whose volumes are chosen
/// by block name and id. Gmsh's own MSH of the blocks gives the same
/// solution but for the last bits.
#[test]
fn glued_and_contact_blocks_from_exodus_files_solve_as_their_msh_files() {
    let glue = ("kind = \"glue\"", "[[traction]]\nboundary = \"upper:top\"\nt = [0.1, 0.0, -1.0]\n");
    let rollers = "[[dirichlet]]\nboundary = \"upper:xmin\"\nux = 0.0\n\n[[dirichlet]]\nboundary = \"upper:ymin\"\nuy = 0.0\n\n";
    let pressed = format!("{rollers}[[traction]]\nboundary = \"upper:top\"\nt = [0.0, 0.0, -1.0]\n");
    for (interface, rest) in [glue, ("kind = \"contact\"\nmultiplier = \"dual\"", pressed.as_str())] {
        blocks_from_exodus_files(interface, rest);
    }
}

/// [`glued_and_contact_blocks_from_exodus_files_solve_as_their_msh_files`]
/// for the interface keys `interface` and the loads `rest`.
fn blocks_from_exodus_files(interface: &str, rest: &str) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for (from, to) in [
        ("glue_lower.msh", "gmsh_lower.msh"),
        ("glue_upper.msh", "gmsh_upper.msh"),
        ("glue_lower.e", "lower.e"),
        ("glue_upper.ex2", "upper.ex2"),
        ("glue_upper.ex2", "upper.mesh"),
    ] {
        std::fs::copy(fixture(&format!("exodus/{from}")), dir.join(to)).unwrap();
    }
    for body in ["lower", "upper"] {
        let exodus = dir.join(if body == "lower" { "lower.e" } else { "upper.ex2" });
        write_msh_twin(&exodus, &dir.join(format!("{body}.msh")), &["bottom", "top", "xmin", "ymin"]);
    }
    let case = stacked_case((1000.0, 0.25), (500.0, 0.3), interface, rest);
    let with = |lower: &str, upper: &str, out: &str| {
        case.replace("mesh = \"lower.msh\"", lower).replace("mesh = \"upper.msh\"", upper)
            + &format!("[output]\ndir = \"{out}\"\n")
    };
    let cases = [
        ("msh", with("mesh = \"lower.msh\"", "mesh = \"upper.msh\"", "msh")),
        ("exo", with("mesh = \"lower.e\"", "mesh = \"upper.ex2\"", "exo")),
        (
            "named",
            with(
                "mesh = \"lower.e\"\nvolume = \"body\"",
                "mesh = \"upper.mesh\"\nformat = \"exodus\"\nvolume = \"1\"",
                "named",
            ),
        ),
        ("gmsh", with("mesh = \"gmsh_lower.msh\"", "mesh = \"gmsh_upper.msh\"", "gmsh")),
    ];
    for (name, text) in &cases {
        std::fs::write(dir.join(format!("{name}.toml")), text).unwrap();
        run(&["solve", &format!("{name}.toml")], dir);
    }
    for file in ["lower.vtu", "upper.vtu", "upper_bottom_interface.vtu"] {
        let msh = read(&dir.join("msh").join(file));
        for other in ["exo", "named"] {
            assert!(msh == read(&dir.join(other).join(file)), "{interface}: {other}/{file} differs");
        }
    }
    let (_, u) = vtu_field(&dir.join("exo/upper.vtu"), "displacement", false);
    assert!(u.iter().any(|&v| v.abs() > 1e-4), "a load moved the body");
    if interface.contains("contact") {
        let summary = common::json(&dir.join("exo/summary.json"));
        assert!(summary["contact"]["active_points"].as_u64().unwrap() > 0, "{summary}");
    }
    let (_, g) = vtu_field(&dir.join("gmsh/upper.vtu"), "displacement", false);
    let scale = u.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(
        u.iter().zip(&g).all(|(a, b)| (a - b).abs() <= 1e-12 * scale),
        "{interface}: Gmsh's MSH solves alike"
    );
}

/// `seam assemble` between the "top" side sets of Gmsh's boxes written by
/// the SEACAS library (HEX8 in a 64-bit-offset file, HEX20 in a classic
/// one) and between their MSH twins: the same Matrix Market files but for
/// the file names in their headers.
#[test]
fn seacas_written_exodus_assembles_as_its_msh() {
    let tmp = tempfile::tempdir().unwrap();
    let pairs = [
        ("msh", fixture("abaqus/box_hex.msh"), fixture("abaqus/box_hex20.msh")),
        ("exo", fixture("exodus/box_hex.seacas.exo"), fixture("exodus/box_hex20.seacas.e")),
    ];
    for (out, m, s) in &pairs {
        let (m, s) = (m.to_str().unwrap(), s.to_str().unwrap());
        run(&["assemble", m, s, "--master-group", "top", "--slave-group", "top", "-o", out], tmp.path());
    }
    let names = |text: String| {
        text.replace(pairs[1].1.to_str().unwrap(), pairs[0].1.to_str().unwrap())
            .replace(pairs[1].2.to_str().unwrap(), pairs[0].2.to_str().unwrap())
    };
    for file in ["B.mtx", "D.mtx"] {
        let exo = String::from_utf8(read(&tmp.path().join("exo").join(file))).unwrap();
        let msh = String::from_utf8(read(&tmp.path().join("msh").join(file))).unwrap();
        assert!(names(exo) == msh, "{file}");
    }
}

/// A bad Exodus file in a case is one line naming the case, the body, the
/// file and the cause, exit 2 and nothing written.
#[test]
fn bad_exodus_models_are_one_line_naming_the_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for (from, to) in [("glue_lower.msh", "lower.msh"), ("glue_upper.ex2", "upper.ex2")] {
        std::fs::copy(fixture(&format!("exodus/{from}")), dir.join(to)).unwrap();
    }
    std::fs::write(dir.join("text.e"), "not an exodus file\n").unwrap();
    let case = stacked_case((1000.0, 0.25), (500.0, 0.3), "kind = \"glue\"", "");
    let with = |mesh: &str| case.replace("mesh = \"upper.msh\"", mesh);
    assert_rejected(
        dir,
        &[
            (with("mesh = \"text.e\""), "body \"upper\": text.e: not an Exodus II file"),
            (with("mesh = \"upper.ex2\"\nvolume = \"steel\""), "no physical group \"steel\""),
            (with("mesh = \"upper.ex2\"\nformat = \"gmsh\""), "upper.ex2:"),
        ],
    );
}
