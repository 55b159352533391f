//! The Exodus II reader (feature `exodus`): files of the SEACAS library's
//! own writer and of meshio against Gmsh's MSH of the same mesh, the sides
//! of every element type against the library's side node lists, the three
//! netCDF flavours, and one-line errors (make_fixtures.py writes the files).

use std::path::{Path, PathBuf};

use seam::{area_vector, CellKind, Point3, Shape};
use seam_io::{read_exodus, read_exodus_file, read_model_file, read_msh_file, ModelFormat, Msh, MshVersion};

use crate::abaqus::{assert_same_unit_surface, close, dot, mean, sub, volumes};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/exodus").join(name)
}

fn abaqus_data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/abaqus").join(name)
}

/// The fixture whose name starts with `stem.` (one flavour per file).
fn find(stem: &str) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(data(""))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_str().unwrap();
            name.strip_prefix(stem).is_some_and(|rest| {
                rest.strip_prefix('.').is_some_and(|ext| ["e", "exo", "ex2", "g"].contains(&ext))
            })
        })
        .collect();
    found.sort();
    assert!(!found.is_empty(), "no fixture {stem}.*");
    found
}

/// The side node lists of sides.txt: (type, side) → nodes (1-based).
fn seacas_sides() -> Vec<(String, usize, Vec<usize>)> {
    std::fs::read_to_string(data("sides.txt"))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let (head, nodes) = l.split_once(':').unwrap();
            let (t, side) = head.split_once(' ').unwrap();
            let nodes = nodes.split_whitespace().map(|v| v.parse().unwrap()).collect();
            (t.to_string(), side.parse().unwrap(), nodes)
        })
        .collect()
}

/// Gmsh's reference node coordinates mapped onto the fixtures' cells: the
/// unit cube, and the corner tetrahedron, wedge and pyramid of it.
fn physical(shape: Shape, xi: [f64; 3]) -> Point3 {
    match shape {
        Shape::Tetrahedron => xi,
        Shape::Hexahedron => xi.map(|x| (x + 1.0) / 2.0),
        Shape::Prism => [xi[0], xi[1], (xi[2] + 1.0) / 2.0],
        _ => [(xi[0] + 1.0) / 2.0, (xi[1] + 1.0) / 2.0, xi[2]],
    }
}

const TYPES: [(&str, CellKind, f64); 11] = [
    ("TETRA4", CellKind::Tet4, 1.0 / 6.0),
    ("TETRA10", CellKind::Tet10, 1.0 / 6.0),
    ("HEX8", CellKind::Hex8, 1.0),
    ("HEX20", CellKind::Hex20, 1.0),
    ("HEX27", CellKind::Hex27, 1.0),
    ("WEDGE6", CellKind::Prism6, 0.5),
    ("WEDGE15", CellKind::Prism15, 0.5),
    ("WEDGE18", CellKind::Prism18, 0.5),
    ("PYRAMID5", CellKind::Pyramid5, 1.0 / 3.0),
    ("PYRAMID13", CellKind::Pyramid13, 1.0 / 3.0),
    ("PYRAMID14", CellKind::Pyramid14, 1.0 / 3.0),
];

/// Sides by corners (1-based) from the Exodus II manual, per shape.
fn manual_sides(shape: Shape) -> Vec<Vec<usize>> {
    let sides: &[&[usize]] = match shape {
        Shape::Tetrahedron => &[&[1, 2, 4], &[2, 3, 4], &[1, 4, 3], &[1, 3, 2]],
        Shape::Hexahedron => {
            &[&[1, 2, 6, 5], &[2, 3, 7, 6], &[3, 4, 8, 7], &[1, 5, 8, 4], &[1, 4, 3, 2], &[5, 6, 7, 8]]
        }
        Shape::Prism => &[&[1, 2, 5, 4], &[2, 3, 6, 5], &[1, 4, 6, 3], &[1, 3, 2], &[4, 5, 6]],
        _ => &[&[1, 2, 5], &[2, 3, 5], &[3, 4, 5], &[1, 5, 4], &[1, 4, 3, 2]],
    };
    sides.iter().map(|s| s.to_vec()).collect()
}

/// One element of every type, written by the SEACAS library with its nodes
/// where the library's side lists put them (sides.txt): read, its nodes
/// are Gmsh's reference nodes of the kind on the cell (so every node is in
/// its place), its volume is the cell's, its ids are the file's, and each
/// side set k (one side, selected alone by name and by id) is the outward
/// face the manual defines, with the nodes the library lists for it.
#[test]
fn every_side_of_every_type_is_the_manuals_and_the_librarys() {
    let sides = seacas_sides();
    for (name, kind, volume) in TYPES {
        let path = &find(&format!("cube_{name}"))[0];
        let msh = read_exodus_file(path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(msh.format.version, MshVersion::ExodusII);
        let n = kind.info().nodes.len();
        assert_eq!(msh.node_tags, (0..n as u64).map(|i| 100 + 7 * i).collect::<Vec<_>>(), "{name}");
        let cells = msh.volume_elements(Some("body")).unwrap();
        assert_eq!(cells.len(), 1, "{name}");
        assert_eq!((cells[0].tag, cells[0].gmsh_type), (42, kind.info().gmsh_type.unwrap()), "{name}");
        let shape = kind.reference_shape();
        for (i, &node) in cells[0].nodes.iter().enumerate() {
            let want = physical(shape, kind.info().nodes[i]);
            assert!(
                close(msh.nodes[node], want, 1e-14),
                "{name}: Gmsh node {i} at {:?}, not {want:?}",
                msh.nodes[node]
            );
        }
        let v = volumes(&msh.volume(Some("5")).unwrap());
        assert!((v[0] - volume).abs() < 1e-13, "{name}: volume {v:?}");
        let corners: Vec<Point3> = msh.nodes[..kind.info().corners].to_vec();
        let centre = mean(&corners);
        for (k, manual) in manual_sides(shape).iter().enumerate() {
            let side = k + 1;
            let by_name = msh.surface(Some(&format!("side{side}"))).unwrap();
            assert_eq!(by_name, msh.surface(Some(&side.to_string())).unwrap(), "{name} side {side}");
            assert_eq!(by_name.faces().len(), 1, "{name} side {side}");
            let face = &by_name.faces()[0];
            let want = area_vector(&manual.iter().map(|&c| corners[c - 1]).collect::<Vec<_>>());
            let have =
                area_vector(&face.corner_nodes().iter().map(|&i| by_name.points()[i]).collect::<Vec<_>>());
            assert!(close(have, want, 1e-14), "{name} side {side}: {have:?}, manual {want:?}");
            let face_centre = mean(&manual.iter().map(|&c| corners[c - 1]).collect::<Vec<_>>());
            assert!(dot(want, sub(face_centre, centre)) > 0.0, "{name} side {side} points inward");
            let mut tags: Vec<u64> = face
                .nodes()
                .iter()
                .map(|&i| by_name.points()[i])
                .map(|p| {
                    let at = msh.nodes.iter().position(|q| close(*q, p, 0.0)).unwrap();
                    msh.node_tags[at]
                })
                .collect();
            tags.sort_unstable();
            let (_, _, library) = sides.iter().find(|(t, s, _)| t == name && *s == side).unwrap();
            let mut want: Vec<u64> = library.iter().map(|&i| 100 + 7 * (i as u64 - 1)).collect();
            if name == "PYRAMID14" && side == 5 {
                // The library leaves the base's centre, node 14, out of it.
                want.push(100 + 7 * 13);
            }
            if name == "WEDGE18" && side <= 3 {
                // And WEDGE18's face centres, 16, 17 and 18 (IOSS's places).
                want.push(100 + 7 * (15 + side as u64 - 1));
            }
            want.sort_unstable();
            assert_eq!(tags, want, "{name} side {side}: the library's nodes");
        }
        let e = msh.surface(Some("side7")).unwrap_err().to_string();
        assert!(e.contains("side7"), "{e}");
    }
}

/// TETRA14's face-centre nodes are placed neither by the library nor by
/// IOSS's tables seam follows: its block is refused, by name, when selected.
#[test]
fn unverified_types_are_refused_by_name() {
    let msh = read_exodus_file(&find("cube_TETRA14")[0]).unwrap();
    let e = msh.volume(Some("body")).unwrap_err().to_string();
    assert!(e.contains("element block 5 (\"body\"): element type TETRA14 is not read yet"), "{e}");
    let e = msh.surface(Some("side1")).unwrap_err().to_string();
    assert!(e.contains("side set 1 (\"side1\")") && e.contains("whose type seam does not read"), "{e}");
    assert!(!e.contains('\n'));
}

/// Gmsh's boxes written by the SEACAS library (classic, 64-bit offset and
/// NetCDF-4) with Gmsh's tags as number maps: the same nodes, the same cells
/// by element id with their nodes in Gmsh's order, the same blocks (by name
/// and by id) and the same surfaces, oriented alike, as Gmsh's MSH.
#[test]
fn seacas_files_give_the_cells_and_surfaces_of_gmsh_msh() {
    let mut flavours = std::collections::BTreeSet::new();
    for name in ["box_tet", "box_tet_o2", "box_hex", "box_hex20", "box_hex27", "box_prism", "box_prism15"] {
        let msh = read_msh_file(abaqus_data(&format!("{name}.msh"))).unwrap();
        for path in find(&format!("{name}.seacas")) {
            let bytes = std::fs::read(&path).unwrap();
            flavours.insert(if bytes.starts_with(b"CDF\x01") {
                1
            } else if bytes.starts_with(b"CDF\x02") {
                2
            } else {
                4
            });
            let exo = read_exodus(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let what = path.display().to_string();
            assert_eq!(exo.node_tags, msh.node_tags, "{what}");
            assert_eq!(exo.nodes, msh.nodes, "{what}");
            let cells = |m: &Msh| {
                let mut c = m.volume_elements(None).unwrap().into_iter().cloned().collect::<Vec<_>>();
                c.sort_by_key(|e| e.tag);
                c.into_iter().map(|e| (e.tag, e.gmsh_type, e.nodes)).collect::<Vec<_>>()
            };
            assert_eq!(cells(&exo), cells(&msh), "{what}");
            for (group, id) in [("lower", "1"), ("upper", "2")] {
                let tags = |m: &Msh, g: &str| {
                    let mut t = m.volume_elements(Some(g)).unwrap().iter().map(|e| e.tag).collect::<Vec<_>>();
                    t.sort_unstable();
                    t
                };
                assert_eq!(tags(&exo, group), tags(&msh, group), "{what} {group}");
                assert_eq!(tags(&exo, id), tags(&msh, group), "{what} {id}");
            }
            let v = volumes(&exo.volume(None).unwrap());
            assert!(v.iter().all(|&v| v > 0.0) && (v.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{what}");
            for (surface, id, volume, normal) in [
                ("top", "10", "upper", [0.0, 0.0, 1.0]),
                ("interface", "20", "lower", [0.0, 0.0, 1.0]),
                ("interface", "20", "upper", [0.0, 0.0, -1.0]),
            ] {
                let e = exo.surface_of_volume(surface, Some(volume)).unwrap();
                assert_eq!(e, exo.surface_of_volume(id, Some(volume)).unwrap(), "{what}");
                assert_same_unit_surface((&exo, &msh), (surface, volume, normal), 1e-15, &what);
            }
        }
    }
    assert_eq!(flavours.into_iter().collect::<Vec<_>>(), [1, 2, 4], "classic, 64-bit offset, NetCDF-4");
}

/// meshio's Exodus writer (NetCDF-4, blocks numbered from 0 without names,
/// Gmsh's surface elements as TRI3 / QUAD blocks): the cells of the MSH it
/// converted, in order; the surface blocks are refused with their type.
#[test]
fn meshio_files_give_the_cells_of_the_msh_they_converted() {
    for name in ["box_tet", "box_tet_o2", "box_hex", "box_prism"] {
        let msh = read_msh_file(abaqus_data(&format!("{name}.msh"))).unwrap();
        let exo = read_exodus_file(data(&format!("{name}.meshio.exo"))).unwrap();
        let (a, m) = (exo.volume(None).unwrap(), msh.volume(None).unwrap());
        assert_eq!(a.cells().len(), m.cells().len(), "{name}");
        for (ac, mc) in a.cells().iter().zip(m.cells()) {
            assert_eq!(ac.kind(), mc.kind(), "{name}");
            for (&i, &j) in ac.nodes().iter().zip(mc.nodes()) {
                assert_eq!(a.points()[i], m.points()[j], "{name}");
            }
        }
        assert_eq!(volumes(&a), volumes(&m), "{name}");
        let surface = exo.unusable_groups.iter().find(|g| g.dim == 3).expect("a surface block");
        let e = exo.volume(Some(&surface.tag.to_string())).unwrap_err().to_string();
        let named = e.contains("element type \"TRI") || e.contains("element type \"QUAD");
        assert!(named && e.contains("is not a solid seam reads"), "{e}");
    }
}

/// Bytes of a fixture with `from` replaced by `to` (same length) once.
fn patched(name: &str, from: &[u8], to: &[u8]) -> Vec<u8> {
    let mut bytes = std::fs::read(data(name)).unwrap();
    let at = bytes.windows(from.len()).position(|w| w == from).unwrap_or_else(|| panic!("{from:?}"));
    bytes[at..at + from.len()].copy_from_slice(to);
    bytes
}

/// Bad files are refused on one line naming the file, the block or side
/// set and the cause; huge declared counts are refused before allocating.
#[test]
fn bad_files_are_refused_on_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let write = |name: &str, bytes: &[u8]| {
        let path = tmp.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    };
    let good = std::fs::read(data("cube_HEX8.ex2")).unwrap();
    let classic = std::fs::read(data("cube_TETRA4.e")).unwrap();
    // num_nodes (0x0000000b in the header) declared as 2^31 - 1.
    let mut huge = classic.clone();
    let at = huge.windows(9).position(|w| w == b"num_nodes").unwrap();
    huge[at + 12..at + 16].copy_from_slice(&0x7fff_ffff_u32.to_be_bytes());
    let cases: Vec<(PathBuf, &str)> = vec![
        (write("text.e", b"not an exodus file\n"), "not an Exodus II file"),
        (write("half.ex2", &good[..good.len() / 2]), ""),
        (write("half.e", &classic[..classic.len() / 2]), ""),
        (write("huge.e", &huge), ""),
        (write("empty.exo", b""), "not an Exodus II file"),
    ];
    for (path, want) in cases {
        let e = read_exodus_file(&path).unwrap_err().to_string();
        let prefix = format!("{}: {want}", path.display());
        assert!(e.starts_with(&prefix) && !e.contains('\n'), "{e}");
    }
    // Dimensions of 2^40 nodes and elements in a 3 kB NetCDF-4 file.
    let e = read_exodus_file(data("huge_counts.ex2")).unwrap_err().to_string();
    assert!(
        e.ends_with(
            "huge_counts.ex2: dimension num_nodes = 1099511627776 is more than a file of this size can hold"
        ),
        "{e}"
    );
    // An unknown type is named when its block is selected.
    let bytes = patched("cube_TETRA4.e", b"TETRA4", b"TETRAX");
    let msh = read_exodus(&bytes).unwrap();
    let e = msh.volume(Some("body")).unwrap_err().to_string();
    assert!(
        e.contains("element block 5 (\"body\"): element type \"TETRAX\" with 4 nodes is not a solid"),
        "{e}"
    );
    let e = read_exodus_file(tmp.path().join("missing.e")).unwrap_err();
    assert_eq!(e.io_kind(), Some(std::io::ErrorKind::NotFound));
}

/// read_model_file reads `.e`, `.exo`, `.ex2` and `.g` as Exodus II, and any
/// name with `ModelFormat::Exodus`.
#[test]
fn read_model_file_reads_exodus_by_extension_or_format() {
    for path in find("box_hex.seacas").into_iter().chain(find("cube_PYRAMID5")) {
        assert_eq!(read_model_file(&path, None).unwrap(), read_exodus_file(&path).unwrap());
    }
    let tmp = tempfile::tempdir().unwrap();
    let other = tmp.path().join("model.nc");
    std::fs::copy(data("box_hex.seacas.e"), &other).unwrap();
    assert_eq!(
        read_model_file(&other, Some(ModelFormat::Exodus)).unwrap(),
        read_exodus_file(data("box_hex.seacas.e")).unwrap()
    );
    let e = read_model_file(&other, None).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}: ", other.display())), "{e}");
}
