//! Models from Abaqus / CalculiX input files (`.inp`) through every command
//! that reads meshes: the same model as MSH and as `.inp` gives the same
//! operators, transfers, checks and solutions; the `.inp` ids are kept in
//! the outputs (`node_id`, `element_id`); bad inputs are one line.

use crate::common;

use common::{assert_rejected, seam, stacked_case, stderr, vtu_field, write_block, write_stacked_blocks};
use seam_fem::generate::Side;
use std::fmt::Write as _;
use std::path::Path;

/// The corners (0-based, Abaqus's order, which is Gmsh's for C3D8) of faces
/// S1…S6 of a C3D8, from the Abaqus manual.
const HEX_FACES: [[usize; 4]; 6] =
    [[0, 1, 2, 3], [4, 7, 6, 5], [0, 4, 5, 1], [1, 5, 6, 2], [2, 6, 7, 3], [3, 7, 4, 0]];

/// Writes the hexahedral MSH file `msh` as the Abaqus input file `inp`: the
/// same nodes in the same order with ids `node_id(tag)`, its cells as C3D8
/// elements with ids `element_id(tag)` in the element set BODY, and each
/// physical surface as a `*SURFACE` of the cells' faces (in the order of its
/// face elements).
fn write_inp_twin(msh: &Path, inp: &Path, node_id: fn(u64) -> u64, element_id: fn(u64) -> u64) {
    let m = seam_io::read_msh_file(msh).unwrap();
    let mut text = String::from("*HEADING\nwritten from an MSH file by seam's tests\n*NODE\n");
    for (tag, p) in m.node_tags.iter().zip(&m.nodes) {
        writeln!(text, "{}, {}, {}, {}", node_id(*tag), p[0], p[1], p[2]).unwrap();
    }
    let cells: Vec<_> = m.elements.iter().filter(|e| e.dim == 3).collect();
    text.push_str("*ELEMENT, TYPE=C3D8, ELSET=BODY\n");
    for c in &cells {
        assert_eq!(c.gmsh_type, 5, "hexahedra only");
        let nodes: Vec<String> = c.nodes.iter().map(|&n| node_id(m.node_tags[n]).to_string()).collect();
        writeln!(text, "{}, {}", element_id(c.tag), nodes.join(", ")).unwrap();
    }
    let sorted = |mut v: Vec<usize>| {
        v.sort_unstable();
        v
    };
    for group in m.physical_names.iter().filter(|g| g.dim == 2) {
        writeln!(text, "*SURFACE, NAME={}, TYPE=ELEMENT", group.name).unwrap();
        for face in m.elements.iter().filter(|e| e.dim == 2 && e.physical_tags.contains(&group.tag)) {
            let corners = sorted(face.nodes[..4].to_vec());
            let (cell, k) = cells
                .iter()
                .find_map(|c| {
                    HEX_FACES
                        .iter()
                        .position(|f| sorted(f.iter().map(|&i| c.nodes[i]).collect()) == corners)
                        .map(|k| (c, k))
                })
                .expect("a face of a cell");
            writeln!(text, "{}, S{}", element_id(cell.tag), k + 1).unwrap();
        }
    }
    std::fs::write(inp, text).unwrap();
}

/// [`write_inp_twin`] of lower.msh and upper.msh in `dir`: lower.inp and upper.inp.
fn write_twins(dir: &Path, node_id: fn(u64) -> u64, element_id: fn(u64) -> u64) {
    for body in ["lower", "upper"] {
        let path = |ext: &str| dir.join(format!("{body}.{ext}"));
        write_inp_twin(&path("msh"), &path("inp"), node_id, element_id);
    }
}

/// A map of the unit cube onto a block.
type Map = fn(f64, f64, f64) -> [f64; 3];

fn same_ids(tag: u64) -> u64 {
    tag
}

/// Node ids of the renumbered twins: sparse, far from the MSH tags.
fn node_ids(tag: u64) -> u64 {
    1000 + 3 * tag
}

/// Element ids of the renumbered twins.
fn element_ids(tag: u64) -> u64 {
    500 + 7 * tag
}

/// Runs `seam ARGS` in `dir` and asserts success.
fn run(args: &[&str], dir: &Path) {
    let o = seam(args, dir);
    assert!(o.status.success(), "seam {args:?}: {}", stderr(&o));
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A Matrix Market file of `seam assemble` from `.inp` surfaces is that of
/// their MSH twins byte for byte, but for the names of the files in its
/// header (`% rows: nodes of upper.inp in file order`).
fn same_operator(msh: &Path, inp: &Path) -> bool {
    let inp = String::from_utf8(read(inp)).unwrap();
    let header = inp.lines().take_while(|l| l.starts_with('%')).count();
    let named: String = inp.lines().take(header).map(|l| l.replace(".inp ", ".msh ") + "\n").collect();
    read(msh)
        == [
            named.as_bytes(),
            inp.lines().skip(header).map(|l| l.to_string() + "\n").collect::<String>().as_bytes(),
        ]
        .concat()
}

/// The stacked glued blocks of the solve tests as MSH and as `.inp` twins
/// with the same ids: the two runs write byte-identical files (same nodes,
/// cells, faces, ids and so the same numbers), the `.inp` case also with a
/// `.mesh` file read by `format = "abaqus"` and the volume chosen by its
/// element set (`volume = "body"`, in another case than the file's).
#[test]
fn glued_blocks_from_inp_files_solve_as_their_msh_files() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    write_stacked_blocks(dir);
    write_twins(dir, same_ids, same_ids);
    std::fs::copy(dir.join("upper.inp"), dir.join("upper.mesh")).unwrap();
    let rest = "[[traction]]\nboundary = \"upper:top\"\nt = [0.1, 0.0, -1.0]\n";
    let case = stacked_case((1000.0, 0.25), (500.0, 0.3), "kind = \"glue\"", rest);
    std::fs::write(dir.join("msh.toml"), case.replace("[output]", "") + "[output]\ndir = \"msh\"\n").unwrap();
    let inp = case
        .replace("mesh = \"lower.msh\"", "mesh = \"lower.inp\"\nvolume = \"body\"")
        .replace("mesh = \"upper.msh\"", "mesh = \"upper.mesh\"\nformat = \"abaqus\"");
    std::fs::write(dir.join("inp.toml"), inp + "[output]\ndir = \"inp\"\n").unwrap();
    run(&["solve", "msh.toml"], dir);
    run(&["solve", "inp.toml"], dir);
    for file in ["lower.vtu", "upper.vtu", "upper_bottom_interface.vtu"] {
        assert!(read(&dir.join("msh").join(file)) == read(&dir.join("inp").join(file)), "{file} differs");
    }
    let (_, u) = vtu_field(&dir.join("inp/upper.vtu"), "displacement", false);
    assert!(u.iter().any(|&v| v.abs() > 1e-4), "a load moved the body");
}

/// Blocks in frictionless contact, pressed together, as MSH and as `.inp`
/// twins renumbered (node ids 1000 + 3·tag, element ids 500 + 7·tag): equal
/// displacements and interface results; `node_id` and `element_id` give the
/// `.inp` ids, and the MSH tags for the MSH bodies.
#[test]
fn contact_blocks_from_inp_files_keep_their_ids() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // Both on rollers (xmin, ymin), the upper one graded along x.
    let sides = [("bottom", Side::ZMin), ("top", Side::ZMax), ("xmin", Side::XMin), ("ymin", Side::YMin)];
    let blocks: [(&str, usize, Map); 2] = [
        ("lower.msh", 3, |u, v, w| [u, v, 0.5 * w]),
        ("upper.msh", 2, |u, v, w| [0.8 * u + 0.2 * u * u, v, 0.5 + 0.5 * w]),
    ];
    for (file, n, map) in blocks {
        write_block(&dir.join(file), [n, n, 1], map, &sides);
    }
    write_twins(dir, node_ids, element_ids);
    let rest = "[[dirichlet]]\nboundary = \"upper:xmin\"\nux = 0.0\n\n[[dirichlet]]\nboundary = \"upper:ymin\"\nuy = 0.0\n\n\
                [[traction]]\nboundary = \"upper:top\"\nt = [0.0, 0.0, -2.0]\n";
    let case = stacked_case((1000.0, 0.25), (500.0, 0.3), "kind = \"contact\"", rest);
    std::fs::write(dir.join("msh.toml"), case.clone() + "[output]\ndir = \"msh\"\n").unwrap();
    let inp = case.replace(".msh\"", ".inp\"");
    std::fs::write(dir.join("inp.toml"), inp + "[output]\ndir = \"inp\"\n").unwrap();
    run(&["solve", "msh.toml"], dir);
    run(&["solve", "inp.toml"], dir);
    let field =
        |run: &str, file: &str, name: &str, cell: bool| vtu_field(&dir.join(run).join(file), name, cell).1;
    let tags = |name: &str| seam_io::read_msh_file(dir.join(name)).unwrap();
    for body in ["lower", "upper"] {
        let file = format!("{body}.vtu");
        for name in ["displacement", "stress", "von_mises"] {
            assert_eq!(field("msh", &file, name, false), field("inp", &file, name, false), "{file} {name}");
        }
        let msh = tags(&format!("{body}.msh"));
        let want: Vec<f64> = msh.node_tags.iter().map(|&t| t as f64).collect();
        assert_eq!(field("msh", &file, "node_id", false), want, "{file}");
        let want: Vec<f64> = msh.node_tags.iter().map(|&t| node_ids(t) as f64).collect();
        assert_eq!(field("inp", &file, "node_id", false), want, "{file}");
        let cells: Vec<u64> = msh.volume_elements(None).unwrap().iter().map(|e| e.tag).collect();
        let want: Vec<f64> = cells.iter().map(|&t| t as f64).collect();
        assert_eq!(field("msh", &file, "element_id", true), want, "{file}");
        let want: Vec<f64> = cells.iter().map(|&t| element_ids(t) as f64).collect();
        assert_eq!(field("inp", &file, "element_id", true), want, "{file}");
    }
    let file = "upper_bottom_interface.vtu";
    for name in ["displacement", "contact_pressure", "active", "body_point", "traction"] {
        assert_eq!(field("msh", file, name, false), field("inp", file, name, false), "{name}");
    }
    let pressure = field("inp", file, "contact_pressure", false);
    assert!(pressure.iter().all(|&p| (p - 2.0).abs() < 1e-9), "{pressure:?}");
    // body_point is the 0-based index, node_id the file's id of that node.
    let upper = tags("upper.msh");
    let body_point = field("inp", file, "body_point", false);
    for (run, id) in [("msh", same_ids as fn(u64) -> u64), ("inp", node_ids)] {
        let want: Vec<f64> = body_point.iter().map(|&p| id(upper.node_tags[p as usize]) as f64).collect();
        assert_eq!(field(run, file, "node_id", false), want, "{run}");
    }
}

/// `seam assemble`, `seam check` and `seam transfer` read `.inp` surfaces
/// (selected by `*SURFACE` name) as their MSH twins: byte-identical
/// operators (B, D, T), transfers and checks.
#[test]
fn assemble_check_and_transfer_read_inp_surfaces_as_msh() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    write_stacked_blocks(dir);
    write_twins(dir, node_ids, element_ids);
    for ext in ["msh", "inp"] {
        let (m, s) = (format!("lower.{ext}"), format!("upper.{ext}"));
        let groups = ["--master-group", "top", "--slave-group", "bottom"];
        let out = format!("{ext}_ops");
        run(&[&["assemble", &m, &s, "-o", &out, "--multiplier", "dual"][..], &groups].concat(), dir);
        run(&[&["check", &m, &s, "--json", &format!("{ext}_check.json")][..], &groups].concat(), dir);
        let target = format!("{ext}_f.vtu");
        run(
            &[
                "transfer",
                &m,
                &s,
                "-o",
                &target,
                "--expr",
                "sin(x) * y + z",
                "--source-group",
                "top",
                "--target-group",
                "bottom",
            ],
            dir,
        );
    }
    for file in ["B.mtx", "D.mtx", "T.mtx"] {
        assert!(
            same_operator(&dir.join("msh_ops").join(file), &dir.join("inp_ops").join(file)),
            "{file} differs"
        );
    }
    assert!(read(&dir.join("msh_f.vtu")) == read(&dir.join("inp_f.vtu")), "the transfers differ");
    let check = |ext: &str| {
        let mut v = common::json(&dir.join(format!("{ext}_check.json")));
        for key in ["master", "slave", "face_ids"] {
            v.as_object_mut().unwrap().remove(key);
        }
        v
    };
    assert_eq!(check("msh"), check("inp"));
    // A *SURFACE name in any case; an unknown one is listed with the file's.
    run(
        &[
            "assemble",
            "lower.inp",
            "upper.inp",
            "--master-group",
            "TOP",
            "--slave-group",
            "Bottom",
            "-o",
            "any",
        ],
        dir,
    );
    let o = seam(&["assemble", "lower.inp", "upper.inp", "--master-group", "lid", "-o", "none"], dir);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("lower.inp") && err.contains("\"lid\"") && err.contains("top"), "{err}");
    assert!(!dir.join("none").exists());
}

/// Gmsh's own `.inp` of a mesh and its MSH (the seam-io fixtures, same nodes
/// in the same order, coordinates that both give exactly): the same operator
/// between their "interface" surfaces, by `seam assemble`.
#[test]
fn gmsh_written_inp_assembles_as_its_msh() {
    let tmp = tempfile::tempdir().unwrap();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../seam-io/tests/data/abaqus");
    for ext in ["msh", "inp"] {
        let (m, s) = (data.join(format!("box_hex.{ext}")), data.join(format!("box_hex20.{ext}")));
        let (m, s) = (m.to_str().unwrap(), s.to_str().unwrap());
        let groups = ["--master-group", "top", "--slave-group", "top"];
        run(&[&["assemble", m, s, "-o", ext][..], &groups].concat(), tmp.path());
    }
    for file in ["B.mtx", "D.mtx"] {
        assert!(
            same_operator(&tmp.path().join("msh").join(file), &tmp.path().join("inp").join(file)),
            "{file}"
        );
    }
}

/// A bad `.inp` in a case is one line naming the case, the body and the
/// file with its line, exit 2 and nothing written; so are an unknown
/// `format`, and cells or faces at fault, named by element id.
#[test]
fn bad_inp_models_are_one_line_naming_file_and_line() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    write_stacked_blocks(dir);
    write_inp_twin(&dir.join("upper.msh"), &dir.join("upper.inp"), node_ids, element_ids);
    let good = std::fs::read_to_string(dir.join("upper.inp")).unwrap();
    let line = good.lines().position(|l| l.starts_with("1003,")).unwrap() + 1;
    std::fs::write(dir.join("bad.inp"), good.replace("1003, ", "1003, 0.x")).unwrap();
    // The first cell in a set of its own, which the bottom surface is not on.
    let msh = seam_io::read_msh_file(dir.join("upper.msh")).unwrap();
    let first = element_ids(msh.volume_elements(None).unwrap()[0].tag);
    let half = good
        .replace("*SURFACE, NAME=bottom", &format!("*ELSET, ELSET=FIRST\n{first}\n*SURFACE, NAME=bottom"));
    std::fs::write(dir.join("half.inp"), half).unwrap();
    // A flat hexahedron: zero volume.
    let flat = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n5, 0, 0, 0\n6, 1, 0, 0\n7, 1, 1, 0\n\
                8, 0, 1, 0\n*ELEMENT, TYPE=C3D8R\n42, 1, 2, 3, 4, 5, 6, 7, 8\n";
    std::fs::write(dir.join("flat.inp"), flat).unwrap();
    let case = stacked_case((1000.0, 0.25), (500.0, 0.3), "kind = \"glue\"", "");
    let with = |mesh: &str| case.replace("mesh = \"upper.msh\"", mesh);
    assert_rejected(
        dir,
        &[
            (
                with("mesh = \"bad.inp\""),
                &format!("body \"upper\": bad.inp:{line}: expected a number for coordinate 1 of node 1003"),
            ),
            (with("mesh = \"upper.inp\"\nformat = \"ansys\""), "body \"upper\": unknown format \"ansys\""),
            (with("mesh = \"upper.msh\"\nformat = \"abaqus\""), "upper.msh:"),
            (
                with("mesh = \"half.inp\"\nvolume = \"first\""),
                " face S1 of physical group \"bottom\" (3) is not on physical group \"FIRST\"",
            ),
            (with("mesh = \"upper.inp\"\nvolume = \"second\""), "no physical group \"second\""),
            (with("mesh = \"flat.inp\""), "body \"upper\": flat.inp: element 42 "),
        ],
    );
}
