//! Integration tests of the MSH reader: Gmsh-written fixtures in four flavours
//! (see `tests/data/make_fixtures.py`, `tests/data/expected.txt` and
//! `tests/data/second_order.txt`), hand-written
//! inputs for every error, and truncation / corruption robustness.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use seam::{area_vector, Face, Point3, SurfaceMesh};
use seam_io::{
    read_msh, read_msh_file, read_surface_file, read_volume_file, Degeneracy, Location, Msh, MshErrorKind,
    MshVersion,
};

const FLAVOURS: [&str; 4] = ["v22.ascii", "v22.bin", "v41.ascii", "v41.bin"];
const FIXTURES: [&str; 8] = [
    "square_tri",
    "square_mixed",
    "box_tet",
    "box_hex",
    "slab_prism",
    "hybrid_pyramid",
    "sparse_tags",
    "square_tri6",
];

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn fixture_path(name: &str, flavour: &str) -> PathBuf {
    data_dir().join(format!("{name}.{flavour}.msh"))
}

fn read(name: &str, flavour: &str) -> Msh {
    read_msh_file(fixture_path(name, flavour)).unwrap_or_else(|e| panic!("{e}"))
}

/// One line of `expected.txt`.
struct Expected {
    what: String,
    fixture: String,
    group: Option<String>,
    fields: HashMap<String, String>,
}

impl Expected {
    fn count(&self, key: &str) -> usize {
        self.fields[key].parse().unwrap()
    }

    fn number(&self, key: &str) -> f64 {
        self.fields[key].parse().unwrap()
    }

    fn centre(&self) -> Option<Point3> {
        let c: Vec<f64> = self.fields.get("centre")?.split(',').map(|x| x.parse().unwrap()).collect();
        Some([c[0], c[1], c[2]])
    }
}

fn expectations(what: &str) -> Vec<Expected> {
    let text = std::fs::read_to_string(data_dir().join("expected.txt")).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|line| {
            let words: Vec<&str> = line.split_whitespace().collect();
            let fields =
                words[3..].iter().map(|kv| kv.split_once('=').unwrap()).map(|(k, v)| (k.into(), v.into()));
            Expected {
                what: words[0].into(),
                fixture: words[1].into(),
                group: (words[2] != "-").then(|| words[2].to_string()),
                fields: fields.collect(),
            }
        })
        .filter(|e| e.what == what)
        .collect()
}

fn count_faces(surface: &SurfaceMesh) -> (usize, usize) {
    let tris = surface.faces().iter().filter(|f| matches!(f, Face::Tri3(_))).count();
    (tris, surface.n_faces() - tris)
}

fn face_area_and_outwardness(surface: &SurfaceMesh, f: usize, centre: Point3) -> (f64, f64) {
    let n = surface.faces()[f].n_corners();
    let corners = surface.corners(f);
    let a = area_vector(&corners[..n]);
    let mut centroid = [0.0; 3];
    for c in &corners[..n] {
        for k in 0..3 {
            centroid[k] += c[k] / n as f64;
        }
    }
    let out: f64 = (0..3).map(|k| a[k] * (centroid[k] - centre[k])).sum();
    ((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt(), out)
}

fn total_area(surface: &SurfaceMesh) -> f64 {
    (0..surface.n_faces()).map(|f| face_area_and_outwardness(surface, f, [0.0; 3]).0).sum()
}

fn assert_close_points(a: &[Point3], b: &[Point3], context: &str) {
    assert_eq!(a.len(), b.len(), "{context}: number of nodes");
    for (i, (p, q)) in a.iter().zip(b).enumerate() {
        for k in 0..3 {
            // Gmsh writes ASCII coordinates with 16 significant digits.
            assert!((p[k] - q[k]).abs() <= 1e-15 * (1.0 + p[k].abs()), "{context}: node {i}: {p:?} vs {q:?}");
        }
    }
}

/// Type, dimension, entity, nodes and physical tags of an element.
type ElementKey = (u32, u8, i32, Vec<usize>, Vec<i32>);

/// Element properties that do not depend on the file's element order.
fn sorted_elements(msh: &Msh) -> Vec<ElementKey> {
    let mut elements: Vec<_> = msh
        .elements
        .iter()
        .map(|e| (e.gmsh_type, e.dim, e.entity, e.nodes.clone(), e.physical_tags.clone()))
        .collect();
    elements.sort();
    elements
}

fn assert_same_node_data(a: &Msh, b: &Msh, context: &str) {
    assert_eq!(a.node_data.len(), b.node_data.len(), "{context}");
    for (d, r) in a.node_data.iter().zip(&b.node_data) {
        assert_eq!((&d.name, d.time_step, d.components), (&r.name, r.time_step, r.components), "{context}");
        let same = |(x, y): (&f64, &f64)| x.to_bits() == y.to_bits() || (x - y).abs() <= 1e-15;
        assert!(d.values.iter().zip(&r.values).all(same), "{context}: {}", d.name);
    }
}

/// ASCII and binary files of one version hold the same mesh, tags and order
/// included (coordinates up to the 16 digits Gmsh writes in ASCII).
#[test]
fn ascii_and_binary_files_of_a_version_read_the_same() {
    for name in FIXTURES {
        for version in ["v22", "v41"] {
            let ascii = read(name, &format!("{version}.ascii"));
            let binary = read(name, &format!("{version}.bin"));
            let context = format!("{name}.{version}");
            assert_eq!((ascii.format.binary, binary.format.binary), (false, true), "{context}");
            assert_eq!(ascii.format.version, binary.format.version, "{context}");
            assert_close_points(&ascii.nodes, &binary.nodes, &context);
            assert_eq!(ascii.node_tags, binary.node_tags, "{context}");
            assert_eq!(ascii.elements, binary.elements, "{context}");
            assert_eq!(ascii.physical_names, binary.physical_names, "{context}");
            assert_same_node_data(&ascii, &binary, &context);
        }
    }
}

/// Versions 2.2 and 4.1 hold the same nodes in the same order and the same
/// elements; Gmsh's 2.2 writer lists elements by type across entities and numbers
/// them (and, for `sparse_tags`, the nodes) 1..n, so only their order and tags
/// may differ.
#[test]
fn versions_2_2_and_4_1_read_the_same_mesh() {
    for name in FIXTURES {
        let v22 = read(name, "v22.bin");
        let v41 = read(name, "v41.bin");
        assert_eq!((v22.format.version, v41.format.version), (MshVersion::V2_2, MshVersion::V4_1));
        assert_eq!(v22.nodes, v41.nodes, "{name}");
        if name != "sparse_tags" {
            assert_eq!(v22.node_tags, v41.node_tags, "{name}");
        }
        assert_eq!(sorted_elements(&v22), sorted_elements(&v41), "{name}");
        assert_eq!(v22.physical_names, v41.physical_names, "{name}");
        assert_same_node_data(&v22, &v41, name);
    }
    for name in ["square_tri", "box_tet", "box_hex", "slab_prism"] {
        assert_eq!(read(name, "v22.ascii").elements, read(name, "v41.ascii").elements, "{name}");
    }
}

#[test]
fn surfaces_have_the_counts_areas_and_orientation_the_script_made() {
    let expected = expectations("surface");
    assert!(expected.len() >= 10);
    for e in &expected {
        let mut faces_of_flavours = vec![];
        for flavour in FLAVOURS {
            let context = format!("{}.{flavour} group {:?}", e.fixture, e.group);
            let surface =
                read(&e.fixture, flavour).surface(e.group.as_deref()).unwrap_or_else(|err| panic!("{err}"));
            assert_eq!(surface.n_points(), e.count("nodes"), "{context}");
            assert_eq!(count_faces(&surface), (e.count("tri3"), e.count("quad4")), "{context}");
            assert!(
                (total_area(&surface) - e.number("area")).abs() < 1e-12,
                "{context}: {}",
                total_area(&surface)
            );
            if let Some(centre) = e.centre() {
                for f in 0..surface.n_faces() {
                    let (_, out) = face_area_and_outwardness(&surface, f, centre);
                    assert!(out > 0.0, "{context}: face {f} points inward");
                }
            }
            faces_of_flavours.push(surface.faces().to_vec());
        }
        let context = format!("{} {:?}", e.fixture, e.group);
        assert_eq!(faces_of_flavours[0], faces_of_flavours[1], "{context}: 2.2 ASCII and binary");
        assert_eq!(faces_of_flavours[2], faces_of_flavours[3], "{context}: 4.1 ASCII and binary");
        for faces in &mut faces_of_flavours {
            faces.sort_by_key(|f| f.nodes().to_vec());
        }
        assert_eq!(faces_of_flavours[0], faces_of_flavours[2], "{context}: 2.2 and 4.1, up to order");
    }
}

#[test]
fn volumes_have_the_cells_the_script_made() {
    for e in expectations("volume") {
        for flavour in FLAVOURS {
            let volume = read(&e.fixture, flavour).volume(e.group.as_deref()).unwrap();
            let mut counts = [0; 4];
            for cell in volume.cells() {
                counts[match cell {
                    seam::Cell::Tet4(_) => 0,
                    seam::Cell::Hex8(_) => 1,
                    seam::Cell::Prism6(_) => 2,
                    seam::Cell::Pyramid5(_) => 3,
                    other => panic!("a first-order fixture has a second-order cell {other:?}"),
                }] += 1;
            }
            let wanted = ["tet4", "hex8", "prism6", "pyramid5"].map(|k| e.count(k));
            assert_eq!(counts, wanted, "{}.{flavour}", e.fixture);
        }
    }
}

#[test]
fn groups_by_name_and_by_number_are_the_same() {
    let box_tet = read("box_tet", "v41.bin");
    assert_eq!(box_tet.surface(Some("top")).unwrap(), box_tet.surface(Some("2")).unwrap());
    assert_eq!(box_tet.surface(Some("bottom")).unwrap(), box_tet.surface(Some("1")).unwrap());
    assert_ne!(box_tet.surface(Some("top")).unwrap(), box_tet.surface(Some("bottom")).unwrap());
    assert_eq!(box_tet.volume(Some("body")).unwrap(), box_tet.volume(Some("3")).unwrap());
    assert_eq!(box_tet.volume(Some("body")).unwrap(), box_tet.volume(None).unwrap());
    let square = read("square_tri", "v22.bin");
    assert_eq!(square.surface(Some("interface")).unwrap(), square.surface(Some("7")).unwrap());
    assert_eq!(square.surface(Some("interface")).unwrap(), square.surface(None).unwrap());
}

/// Face i of `surface(group)` is the element tagged `surface_face_tags(group)[i]`:
/// the same nodes (in an order the outward orientation may reverse).
#[test]
fn surface_face_tags_name_the_faces_of_the_surface() {
    for (fixture, group) in [("box_tet", Some("top")), ("box_hex", Some("12")), ("square_tri", None)] {
        let msh = read(fixture, "v41.ascii");
        let surface = msh.surface(group).unwrap();
        let tags = msh.surface_face_tags(group).unwrap().expect("faces that are elements");
        assert_eq!(tags.len(), surface.n_faces(), "{fixture}");
        for (face, tag) in surface.faces().iter().zip(&tags) {
            let element = msh.elements.iter().find(|e| e.tag == *tag).unwrap();
            assert_eq!(element.dim, 2, "{fixture}: element {tag}");
            let (mut a, mut b) = (face.nodes().to_vec(), element.nodes.clone());
            a.sort_unstable();
            b.sort_unstable();
            assert_eq!(a, b, "{fixture}: element {tag}");
        }
    }
    // The boundary of the volume cells: faces that are no elements of the file.
    assert_eq!(read("box_tet", "v41.ascii").surface_face_tags(None).unwrap(), None);
    assert!(read("box_tet", "v41.ascii").surface_face_tags(Some("lid")).is_err());
}

#[test]
fn an_unknown_group_lists_the_available_ones() {
    let path = fixture_path("box_tet", "v22.ascii");
    let err = read_surface_file(&path, Some("lid")).unwrap_err();
    let message = err.to_string();
    assert!(matches!(err.kind(), MshErrorKind::UnknownGroup { dim: 2, .. }), "{message}");
    assert!(message.starts_with(&format!("{}: ", path.display())), "{message}");
    assert!(message.contains("no physical group \"lid\" of dimension 2"), "{message}");
    assert!(message.contains("available: \"bottom\" (1), \"top\" (2)"), "{message}");
    // The volume "body" (3) is not a surface group.
    let err = read("box_tet", "v41.ascii").surface(Some("3")).unwrap_err();
    assert!(err.to_string().ends_with("available: \"bottom\" (1), \"top\" (2)"), "{err}");
    let err = read("square_tri", "v41.ascii").volume(Some("interface")).unwrap_err();
    assert!(err.to_string().contains("the file has no physical groups of dimension 3"), "{err}");
}

#[test]
fn volume_files_without_cells_say_so() {
    let err = read_volume_file(fixture_path("square_tri", "v41.bin"), None).unwrap_err();
    assert!(err.to_string().ends_with("no volume cells found in the file"), "{err}");
}

#[test]
fn node_data_follows_the_node_order_and_keeps_the_last_step() {
    for flavour in FLAVOURS {
        let msh = read("box_hex", flavour);
        let temperature = msh.node_data("temperature").unwrap();
        assert_eq!(temperature.components, 1);
        for (i, &tag) in msh.node_tags.iter().enumerate() {
            assert_eq!(temperature.node_values(i), &[tag as f64]);
        }
        let displacement = msh.node_data("displacement").unwrap();
        assert_eq!((displacement.time_step, displacement.components), (1, 3));
        let given: Vec<usize> = (0..msh.nodes.len())
            .filter(|&i| displacement.node_values(i).iter().all(|v| !v.is_nan()))
            .collect();
        assert_eq!(given.len(), 5, "{flavour}");
        for i in given {
            let minus: Vec<f64> = msh.nodes[i].iter().map(|x| -x).collect();
            assert_eq!(displacement.node_values(i), minus.as_slice());
        }
    }
}

#[test]
fn sparse_tags_are_kept_and_nodes_keep_their_file_position() {
    for flavour in ["v41.ascii", "v41.bin"] {
        let msh = read("sparse_tags", flavour);
        assert!(msh.node_tags.iter().all(|t| t % 10 == 3), "{:?}", msh.node_tags);
        assert!(msh.elements.iter().all(|e| (e.tag - 100) % 7 == 0));
        assert!(msh.node_tags.windows(2).any(|w| w[1] != w[0] + 1));
    }
    let v22 = read("sparse_tags", "v22.ascii");
    assert_eq!(v22.node_tags, (1..=v22.nodes.len() as u64).collect::<Vec<_>>());
}

#[test]
fn second_order_triangles_read_as_tri6_with_mid_edge_nodes_on_their_edges() {
    for flavour in FLAVOURS {
        let msh = read("square_tri6", flavour);
        let n_tri6 = msh.elements.iter().filter(|e| e.gmsh_type == 9).count();
        assert!(n_tri6 > 0);
        for group in [Some("interface"), None] {
            let surface = msh.surface(group).unwrap_or_else(|e| panic!("{flavour}: {e}"));
            assert_eq!(surface.n_faces(), n_tri6, "{flavour}");
            assert!(surface.faces().iter().all(|f| matches!(f, Face::Tri6(_))), "{flavour}");
            assert!((total_area(&surface) - 1.0).abs() < 1e-12, "{flavour}");
            assert_straight_sided(&surface, flavour);
        }
    }
}

/// The fixtures and their element counts per Gmsh type, from `second_order.txt`.
fn second_order_fixtures() -> Vec<(String, Vec<(u32, usize)>)> {
    let text = std::fs::read_to_string(data_dir().join("second_order.txt")).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("ref "))
        .map(|l| {
            let mut words = l.split_whitespace();
            let name = words.next().unwrap().to_string();
            let counts = words
                .map(|w| {
                    let (t, n) = w.strip_prefix("type").unwrap().split_once('=').unwrap();
                    (t.parse().unwrap(), n.parse().unwrap())
                })
                .collect();
            (name, counts)
        })
        .collect()
}

/// The fixtures have flat sides, where Gmsh puts each mid-edge node in the
/// middle of its edge and a Quad9's centre at the mean of its corners: checks
/// that every second-order face of `surface` has its nodes where Gmsh's order
/// says.
fn assert_straight_sided(surface: &SurfaceMesh, context: &str) {
    let p = surface.points();
    for (f, face) in surface.faces().iter().enumerate() {
        let n = face.nodes();
        let k = face.n_corners();
        let mut expected: Vec<Point3> = (0..k)
            .map(|i| {
                let (a, b) = (p[n[i]], p[n[(i + 1) % k]]);
                [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])]
            })
            .collect();
        if n.len() == 9 {
            let mean = |c: usize| (0..4).map(|i| p[n[i]][c]).sum::<f64>() / 4.0;
            expected.push([mean(0), mean(1), mean(2)]);
        }
        for (i, e) in expected.iter().enumerate() {
            let q = p[n[k + i]];
            let far = (0..3).any(|c| (q[c] - e[c]).abs() > 1e-12);
            assert!(!far, "{context}: face {f} ({face:?}) node {}: {q:?}, expected {e:?}", k + i);
        }
    }
}

/// A face with its nodes rotated so that its smallest corner comes first
/// (the mid-edge nodes follow their edges): equal for the same face listed
/// from another corner, with the same orientation.
fn canonical(face: &Face) -> Vec<usize> {
    let n = face.nodes();
    let k = face.n_corners();
    let r = (0..k).min_by_key(|&i| n[i]).unwrap();
    let mut out: Vec<usize> = (0..k).map(|i| n[(i + r) % k]).collect();
    if face.is_curved() {
        out.extend((0..k).map(|i| n[k + (i + r) % k]));
    }
    out.extend_from_slice(&n[out.len()..]);
    out
}

/// The second-order fixtures of `second_order.txt` (Gmsh `setOrder(2)`,
/// complete and incomplete, made from the first-order fixtures of the same
/// name): every flavour reads with the element counts Gmsh recorded; the
/// volume has one cell per 3D element, of the matching type; the surfaces of
/// `expected.txt` (boundary and physical groups) have the face counts, areas
/// and outward orientation of the first-order fixture, all faces second order,
/// nodes where Gmsh's order puts them; each face of a physical surface is the
/// boundary face of its cell, node for node (up to the starting corner).
#[test]
fn second_order_fixtures_read_with_gmsh_counts_and_second_order_boundaries() {
    let fixtures = second_order_fixtures();
    assert_eq!(fixtures.len(), 7);
    let surfaces = expectations("surface");
    let mut types = std::collections::BTreeSet::new();
    for (name, counts) in &fixtures {
        let base = name.trim_end_matches("_o2s").trim_end_matches("_o2");
        let mut faces_of_flavours = vec![];
        for flavour in FLAVOURS {
            let context = format!("{name}.{flavour}");
            let msh = read(name, flavour);
            for &(gmsh_type, count) in counts {
                let found = msh.elements.iter().filter(|e| e.gmsh_type == gmsh_type).count();
                assert_eq!(found, count, "{context}: type {gmsh_type}");
                types.insert(gmsh_type);
            }
            let volume = msh.volume(None).unwrap_or_else(|e| panic!("{context}: {e}"));
            let mut cell_counts = std::collections::BTreeMap::new();
            for cell in volume.cells() {
                assert!(cell.is_second_order(), "{context}");
                *cell_counts.entry(seam_io::msh::cell_type(cell).unwrap()).or_insert(0) += 1;
            }
            let wanted: std::collections::BTreeMap<u32, usize> =
                counts.iter().copied().filter(|&(t, _)| ![9, 10, 16].contains(&t)).collect();
            assert_eq!(cell_counts, wanted, "{context}");
            let boundary = msh.surface(None).unwrap_or_else(|e| panic!("{context}: {e}"));
            let boundary_faces: std::collections::HashSet<Vec<usize>> =
                boundary.faces().iter().map(canonical).collect();
            let mut faces = vec![];
            for e in surfaces.iter().filter(|e| e.fixture == base) {
                let context = format!("{context} group {:?}", e.group);
                let surface =
                    msh.surface(e.group.as_deref()).unwrap_or_else(|err| panic!("{context}: {err}"));
                assert!(surface.faces().iter().all(Face::is_curved), "{context}");
                let tris = surface.faces().iter().filter(|f| f.n_corners() == 3).count();
                assert_eq!(
                    (tris, surface.n_faces() - tris),
                    (e.count("tri3"), e.count("quad4")),
                    "{context}"
                );
                assert!((total_area(&surface) - e.number("area")).abs() < 1e-12, "{context}");
                let centre = e.centre().expect("volume fixtures give their centre");
                for f in 0..surface.n_faces() {
                    assert!(face_area_and_outwardness(&surface, f, centre).1 > 0.0, "{context}: face {f}");
                }
                assert_straight_sided(&surface, &context);
                for face in surface.faces() {
                    assert!(
                        boundary_faces.contains(&canonical(face)),
                        "{context}: {face:?} is no boundary face"
                    );
                }
                faces.push(surface.faces().to_vec());
            }
            assert!(faces.len() >= 2, "{context}: the boundary and a physical surface");
            faces_of_flavours.push(faces);
        }
        assert_eq!(faces_of_flavours[0], faces_of_flavours[1], "{name}: 2.2 ASCII and binary");
        assert_eq!(faces_of_flavours[2], faces_of_flavours[3], "{name}: 4.1 ASCII and binary");
    }
    // Every second-order face and cell type of Gmsh appears.
    assert_eq!(types.into_iter().collect::<Vec<_>>(), vec![9, 10, 11, 12, 13, 14, 16, 17, 18, 19]);
}

/// Elements of both orders in one mesh: a second-order fixture with every
/// other face of its top and every other cell lowered to first order reads,
/// the faces keep their orders and are oriented outward.
#[test]
fn first_and_second_order_elements_mix() {
    let mut msh = read("box_tet_o2", "v41.bin");
    let top = msh.group_tag(2, "top").unwrap();
    // Every other face of the top first order.
    for e in msh.elements.iter_mut().filter(|e| e.dim == 2 && e.physical_tags.contains(&top)).step_by(2) {
        e.gmsh_type = 2;
        e.nodes.truncate(3);
    }
    // Half the cells first order too.
    for e in msh.elements.iter_mut().filter(|e| e.dim == 3).step_by(2) {
        e.gmsh_type = 4;
        e.nodes.truncate(4);
    }
    let surface = msh.surface(Some("top")).unwrap();
    let tri3 = surface.faces().iter().filter(|f| matches!(f, Face::Tri3(_))).count();
    let tri6 = surface.faces().iter().filter(|f| matches!(f, Face::Tri6(_))).count();
    assert_eq!((tri3, tri6), (7, 7));
    assert!((total_area(&surface) - 1.0).abs() < 1e-12);
    for f in 0..surface.n_faces() {
        assert!(face_area_and_outwardness(&surface, f, [0.5; 3]).1 > 0.0, "face {f}");
    }
    let volume = msh.volume(None).unwrap();
    assert_eq!(volume.cells().iter().filter(|c| c.is_second_order()).count(), 50);
    let boundary = msh.surface(None).unwrap();
    assert_eq!(boundary.n_faces(), 84);
    assert!((total_area(&boundary) - 6.0).abs() < 1e-12);
}

#[test]
fn read_surface_file_reads_and_selects() {
    let surface = read_surface_file(fixture_path("hybrid_pyramid", "v41.bin"), Some("top")).unwrap();
    assert_eq!(count_faces(&surface), (14, 4));
    let volume = read_volume_file(fixture_path("hybrid_pyramid", "v22.bin"), Some("body")).unwrap();
    assert_eq!(volume.cells().len(), 106 + 8 + 4);
}

// ----- hand-written inputs ---------------------------------------------------------

/// A unit square of two triangles, MSH 4.1 ASCII, nodes tagged 10..40, in the
/// physical surface "lid" (5). Line numbers are given next to the lines the tests
/// edit.
const SQUARE: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
1
2 5 \"lid\"
$EndPhysicalNames
$Entities
0 0 1 0
1 0 0 0 1 1 0 1 5 0
$EndEntities
$Nodes
1 4 10 40
2 1 0 4
10
20
30
40
0 0 0
1 0 0
1 1 0
0 1 0
$EndNodes
$Elements
1 2 1 2
2 1 2 2
1 10 20 30
2 10 30 40
$EndElements
";
// line 21: "1 1 0" (node 30); line 22: "0 1 0" (node 40); line 23: $EndNodes;
// line 24: $Elements; line 28: "2 10 30 40".

/// The coordinate lines of nodes 30 and 40, with enough context to be unique.
const NODE_30: &str = "1 1 0\n0 1 0\n$EndNodes";
const NODE_40: &str = "0 1 0\n$EndNodes";

fn edited(from: &str, to: &str) -> String {
    assert!(SQUARE.contains(from), "{from}");
    SQUARE.replacen(from, to, 1)
}

fn read_err(text: &str) -> seam_io::MshError {
    read_msh(text.as_bytes()).unwrap_err()
}

#[test]
fn crlf_line_ends_read_alike() {
    let crlf = SQUARE.replace('\n', "\r\n");
    assert_eq!(read_msh(crlf.as_bytes()).unwrap(), read_msh(SQUARE.as_bytes()).unwrap());
    let err = read_err(&crlf.replacen("2 10 30 40\r\n", "2 10 30 41\r\n", 1));
    assert_eq!(err.location(), Some(Location::Line(28)));
}

#[test]
fn the_hand_written_square_reads() {
    let msh = read_msh(SQUARE.as_bytes()).unwrap();
    assert_eq!(msh.node_tags, vec![10, 20, 30, 40]);
    assert_eq!(msh.elements[1].nodes, vec![0, 2, 3]);
    assert_eq!(msh.elements[1].physical_tags, vec![5]);
    let surface = msh.surface(Some("lid")).unwrap();
    assert_eq!(surface, msh.surface(None).unwrap());
    assert!((total_area(&surface) - 1.0).abs() < 1e-15);
}

#[test]
fn a_truncated_file_names_the_section() {
    let cut = &SQUARE[..SQUARE.find(NODE_30).unwrap()];
    let err = read_err(cut);
    assert!(matches!(err.kind(), MshErrorKind::Truncated { section } if section == "Nodes"));
    assert_eq!(
        err.to_string(),
        "line 20: truncated file: it ends inside the $Nodes section, before $EndNodes"
    );
    let err = read_err(&SQUARE[..SQUARE.len() - 5]);
    assert!(err
        .to_string()
        .ends_with("expected $EndElements to close the $Elements section, found \"$EndElem\""));
}

#[test]
fn a_missing_end_marker_is_reported_where_the_next_section_starts() {
    let err = read_err(&edited("$EndNodes\n", ""));
    assert!(matches!(err.kind(), MshErrorKind::MissingEnd { section, .. } if section == "Nodes"));
    assert_eq!(err.location(), Some(Location::Line(23)));
    assert_eq!(
        err.to_string(),
        "line 23: expected $EndNodes to close the $Nodes section, found \"$Elements\""
    );
}

#[test]
fn a_nan_coordinate_names_the_node() {
    let err = read_err(&edited(NODE_30, "1 nan 0\n0 1 0\n$EndNodes"));
    assert_eq!(err.to_string(), "line 21: node 30 has a non-finite coordinate");
    let err = read_err(&edited(NODE_30, "1 1e999 0\n0 1 0\n$EndNodes"));
    assert!(matches!(err.kind(), MshErrorKind::NonFiniteCoordinate { node_tag: 30 }));
}

#[test]
fn a_malformed_coordinate_line_is_quoted() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mesh.msh");
    std::fs::write(&path, edited(NODE_40, "1.0 abc\n$EndNodes")).unwrap();
    let err = read_msh_file(&path).unwrap_err();
    let expected =
        format!("{}: line 22: expected 3 coordinates for node 40, found \"1.0 abc\"", path.display());
    assert_eq!(err.to_string(), expected);
    assert_eq!(err.path(), Some(path.as_path()));
}

#[test]
fn extra_values_on_a_line_are_reported() {
    let err = read_err(&edited("2 10 30 40\n", "2 10 30 40 50\n"));
    assert_eq!(err.to_string(), "line 28: expected the end of the line after element 2, found \"50\"");
}

#[test]
fn an_element_with_an_unknown_node_tag_is_reported() {
    let err = read_err(&edited("2 10 30 40\n", "2 10 30 41\n"));
    assert!(matches!(err.kind(), MshErrorKind::UnknownNode { element_tag: 2, node_tag: 41 }));
    assert_eq!(
        err.to_string(),
        "line 28: element 2 refers to node 41, which the $Nodes section does not define"
    );
}

#[test]
fn duplicate_node_tags_are_reported() {
    let err = read_err(&edited("40\n0 0 0", "30\n0 0 0"));
    assert_eq!(err.to_string(), "line 18: node 30 is defined twice");
}

#[test]
fn degenerate_faces_are_named_by_element_and_node_tag() {
    let msh = read_msh(edited("2 10 30 40\n", "2 10 30 10\n").as_bytes()).unwrap();
    let err = msh.surface(Some("lid")).unwrap_err();
    assert_eq!(err.to_string(), "element 2 is degenerate: node 10 appears twice");
    let reason = Degeneracy::RepeatedNode { node_tag: 10 };
    assert!(
        matches!(err.kind(), MshErrorKind::Degenerate { element_tag: Some(2), reason: r } if *r == reason)
    );
    // Node 40 on the diagonal through nodes 10 and 30: element 2 has zero area.
    let msh = read_msh(edited(NODE_40, "2 2 0\n$EndNodes").as_bytes()).unwrap();
    let err = msh.surface(None).unwrap_err();
    assert_eq!(err.to_string(), "element 2 is degenerate: its area is zero");
}

/// Ten nodes of a triangle (the corners, two nodes per edge, the centre) and,
/// as element 57 of physical surface 3, `element` (type and node tags).
fn triangle_file(element: &str) -> String {
    format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0.5 0 0\n\
         5 0.5 0.5 0\n6 0 0.5 0\n7 0.7 0 0\n8 0.3 0.7 0\n9 0 0.3 0\n10 0.3 0.3 0\n$EndNodes\n\
         $Elements\n1\n57 {element}\n$EndElements\n"
    )
}

#[test]
fn a_second_order_triangle_in_a_selected_group_reads() {
    let text = triangle_file("9 2 3 1 1 2 3 4 5 6");
    let surface = read_msh(text.as_bytes()).unwrap().surface(Some("3")).unwrap();
    assert_eq!(surface.faces(), &[Face::Tri6([0, 1, 2, 3, 4, 5])]);
}

#[test]
fn third_order_elements_are_refused_by_element_tag_and_type() {
    let text = triangle_file("21 2 3 1 1 2 3 4 7 5 8 6 9 10");
    let err = read_msh(text.as_bytes()).unwrap().surface(Some("3")).unwrap_err();
    assert_eq!(
        err.to_string(),
        "element 57 is a 10-node triangle (type 21); only triangles (3 or 6 nodes) and quadrangles \
         (4, 8 or 9 nodes) are supported"
    );
    let mut msh = read("box_tet_o2", "v22.ascii");
    let cell = msh.elements.iter_mut().find(|e| e.dim == 3).unwrap();
    cell.gmsh_type = 29;
    cell.nodes.extend_from_slice(&[0; 10]);
    let tag = cell.tag;
    for err in [msh.volume(None).unwrap_err(), msh.surface(None).unwrap_err()] {
        assert_eq!(
            err.to_string(),
            format!(
                "element {tag} is a 20-node tetrahedron (type 29); only tetrahedra (4 or 10 nodes), \
                 hexahedra (8, 20 or 27), prisms (6, 15 or 18) and pyramids (5, 13 or 14) are supported"
            )
        );
    }
}

#[test]
fn an_unknown_group_in_the_hand_written_square() {
    let err = read_msh(SQUARE.as_bytes()).unwrap().surface(Some("top")).unwrap_err();
    let expected = "no physical group \"top\" of dimension 2 (by name or number); available: \"lid\" (5)";
    assert_eq!(err.to_string(), expected);
}

#[test]
fn a_missing_file_names_the_path_and_keeps_the_io_kind() {
    let path = data_dir().join("no_such_mesh.msh");
    let err = read_msh_file(&path).unwrap_err();
    assert_eq!(err.io_kind(), Some(std::io::ErrorKind::NotFound));
    let message = err.to_string();
    assert!(message.starts_with(&format!("{}: cannot read the file: ", path.display())), "{message}");
    assert!(!message.ends_with('.'), "{message}");
}

#[test]
fn other_files_are_not_msh() {
    let err = read_err("solid cube\nfacet normal 0 0 1\n");
    assert_eq!(
        err.to_string(),
        "line 1: not a Gmsh MSH file: expected $MeshFormat at the start, found \"solid cube\""
    );
    let err = read_err("");
    assert!(matches!(err.kind(), MshErrorKind::NotMsh { .. }));
    let err = read_err("$NOD\n3\n");
    assert!(matches!(err.kind(), MshErrorKind::UnsupportedVersion { version } if version == "1"));
}

#[test]
fn other_versions_are_unsupported() {
    let err = read_err("$MeshFormat\n4.0 0 8\n$EndMeshFormat\n");
    assert_eq!(
        err.to_string(),
        "line 2: unsupported MSH version 4.0: seam reads versions 2.2 and 4.1 (set Mesh.MshFileVersion in Gmsh)"
    );
    let err = read_err("$MeshFormat\n4.1 0 2\n$EndMeshFormat\n");
    assert_eq!(err.to_string(), "line 2: expected data size 4 or 8, found \"2\"");
}

#[test]
fn unknown_sections_are_skipped() {
    let extra = "$Comments\nanything $EndNodes\n$EndComments\n$Periodic\n1\n1 2 1\n$EndPeriodic\n";
    let text = SQUARE.replacen("$Nodes\n", &format!("{extra}$Nodes\n"), 1)
        + "$ElementData\n1\n\"e\"\n$EndElementData\n";
    assert_eq!(read_msh(text.as_bytes()).unwrap(), read_msh(SQUARE.as_bytes()).unwrap());
    let err = read_err(&(SQUARE.to_string() + "$Periodic\n1\n"));
    assert_eq!(
        err.to_string(),
        "line 31: truncated file: it ends inside the $Periodic section, before $EndPeriodic"
    );
}

#[test]
fn parametric_nodes_skip_their_extra_coordinates() {
    let text = SQUARE.replacen(
        "2 1 0 4\n10\n20\n30\n40\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n",
        "2 1 1 4\n10\n20\n30\n40\n0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n",
        1,
    );
    assert_eq!(read_msh(text.as_bytes()).unwrap().nodes, read_msh(SQUARE.as_bytes()).unwrap().nodes);
    let short = text.replacen("0 1 0 0 1\n", "0 1 0 0\n", 1);
    let err = read_err(&short);
    assert_eq!(
        err.to_string(),
        "line 22: expected 3 coordinates and 2 parametric coordinates for node 40, found \"0 1 0 0\""
    );
}

/// Writes binary MSH data in a chosen byte order and `size_t` width.
struct Binary {
    bytes: Vec<u8>,
    big_endian: bool,
    size_bytes: usize,
}

impl Binary {
    fn new(version: &str, big_endian: bool, size_bytes: usize) -> Self {
        let mut b = Binary { bytes: vec![], big_endian, size_bytes };
        b.text(&format!("$MeshFormat\n{version} 1 {size_bytes}\n"));
        b.int(1);
        b.text("\n$EndMeshFormat\n");
        b
    }

    fn text(&mut self, text: &str) -> &mut Self {
        self.bytes.extend(text.as_bytes());
        self
    }

    fn raw(&mut self, le: &[u8]) -> &mut Self {
        if self.big_endian {
            self.bytes.extend(le.iter().rev());
        } else {
            self.bytes.extend(le);
        }
        self
    }

    fn int(&mut self, v: i32) -> &mut Self {
        self.raw(&v.to_le_bytes())
    }

    fn size(&mut self, v: u64) -> &mut Self {
        let n = self.size_bytes;
        self.raw(&v.to_le_bytes()[..n])
    }

    fn double(&mut self, v: f64) -> &mut Self {
        self.raw(&v.to_le_bytes())
    }

    fn point(&mut self, p: Point3) -> &mut Self {
        p.iter().fold(self, |b, &x| b.double(x))
    }
}

const CORNERS: [Point3; 4] = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];

/// The hand-written square in MSH 4.1 binary, with parametric nodes.
fn binary_square_v41(big_endian: bool, size_bytes: usize) -> Vec<u8> {
    let mut b = Binary::new("4.1", big_endian, size_bytes);
    b.text("$PhysicalNames\n1\n2 5 \"lid\"\n$EndPhysicalNames\n$Entities\n");
    b.size(0).size(0).size(1).size(0);
    b.int(1).point([0.; 3]).point([1., 1., 0.]).size(1).int(5).size(0);
    b.text("\n$EndEntities\n$Nodes\n");
    b.size(1).size(4).size(10).size(40);
    b.int(2).int(1).int(1).size(4);
    for tag in [10, 20, 30, 40] {
        b.size(tag);
    }
    for p in CORNERS {
        b.point(p).double(p[0]).double(p[1]);
    }
    b.text("\n$EndNodes\n$Elements\n");
    b.size(1).size(2).size(1).size(2);
    b.int(2).int(1).int(2).size(2);
    for element in [[1, 10, 20, 30], [2, 10, 30, 40]] {
        element.iter().fold(&mut b, |b, &t| b.size(t));
    }
    b.text("\n$EndElements\n");
    b.bytes
}

/// The hand-written square in MSH 2.2 binary, with node data.
fn binary_square_v22(big_endian: bool) -> Vec<u8> {
    let mut b = Binary::new("2.2", big_endian, 8);
    b.text("$PhysicalNames\n1\n2 5 \"lid\"\n$EndPhysicalNames\n$Nodes\n4\n");
    for (tag, p) in [10, 20, 30, 40].into_iter().zip(CORNERS) {
        b.int(tag).point(p);
    }
    b.text("\n$EndNodes\n$Elements\n2\n");
    b.int(2).int(2).int(2);
    for element in [[1, 5, 1, 10, 20, 30], [2, 5, 1, 10, 30, 40]] {
        element.iter().fold(&mut b, |b, &t| b.int(t));
    }
    b.text("\n$EndElements\n$NodeData\n1\n\"t\"\n1\n0.5\n3\n2\n1\n1\n");
    b.int(30).double(7.0);
    b.text("\n$EndNodeData\n");
    b.bytes
}

#[test]
fn binary_files_of_either_byte_order_and_size_t_width_read_alike() {
    let ascii = read_msh(SQUARE.as_bytes()).unwrap();
    for big_endian in [false, true] {
        for size_bytes in [4, 8] {
            let msh = read_msh(&binary_square_v41(big_endian, size_bytes)).unwrap();
            assert_eq!((&msh.nodes, &msh.node_tags), (&ascii.nodes, &ascii.node_tags));
            assert_eq!((&msh.elements, &msh.physical_names), (&ascii.elements, &ascii.physical_names));
        }
        let msh = read_msh(&binary_square_v22(big_endian)).unwrap();
        assert_eq!((&msh.nodes, &msh.node_tags), (&ascii.nodes, &ascii.node_tags));
        assert_eq!(msh.surface(Some("lid")).unwrap(), ascii.surface(Some("lid")).unwrap());
        let t = msh.node_data("t").unwrap();
        assert_eq!(t.time_step, 2);
        assert!(t.values[..2].iter().all(|v| v.is_nan()) && t.values[2] == 7.0 && t.values[3].is_nan());
    }
}

#[test]
fn binary_errors_are_located_by_byte_offset() {
    let bytes = binary_square_v41(false, 8);
    let cut = bytes.len() - 30;
    let err = read_msh(&bytes[..cut]).unwrap_err();
    assert_eq!(err.location(), Some(Location::Offset(cut)));
    assert!(err
        .to_string()
        .starts_with(&format!("byte {cut}: truncated file: it ends inside the $Elements")));
    let mut wrong_order = binary_square_v22(false);
    let at = wrong_order.iter().position(|&b| b == 1).unwrap();
    wrong_order[at] = 2;
    let err = read_msh(&wrong_order).unwrap_err();
    assert_eq!(err.location(), Some(Location::Offset(at)));
    assert!(err.to_string().contains("expected the binary integer 1 (byte order check)"), "{err}");
}

/// A count that the rest of its section cannot hold is reported where it is
/// written, before anything is read or allocated for it.
#[test]
fn a_count_beyond_its_section_is_named_at_its_line_or_byte() {
    let err = read_err(&edited("2 1 0 4\n", "2 1 0 99999999999\n"));
    assert!(matches!(err.kind(), MshErrorKind::CountTooLarge { count: 99_999_999_999, .. }), "{err:?}");
    assert_eq!(
        err.to_string(),
        "line 14: the number of nodes of entity (2, 1) is 99999999999, more than the 36 bytes before \
         $EndNodes can hold (at most 4)"
    );
    let err = read_err(&edited("1 4 10 40\n", "1 99999999999 10 40\n"));
    assert!(err.to_string().starts_with("line 13: the number of nodes is 99999999999, more than"), "{err}");
    let err = read_err(&edited("2 1 2 2\n", "2 1 2 99999999999\n"));
    assert!(
        err.to_string().starts_with("line 26: the number of elements of entity (2, 1) is 99999999999"),
        "{err}"
    );
    // Binary: at the count's byte offset.
    let mut bytes = binary_square_v41(false, 8);
    let at = bytes.windows(8).position(|w| w == 4u64.to_le_bytes()).unwrap();
    bytes[at..at + 8].copy_from_slice(&99_999_999_999u64.to_le_bytes());
    let err = read_msh(&bytes).unwrap_err();
    assert_eq!(err.location(), Some(Location::Offset(at)));
    assert!(err.to_string().contains("the number of nodes is 99999999999, more than"), "{err}");
    // A cut file is still called truncated.
    assert!(read_err(&SQUARE[..SQUARE.find("30\n").unwrap()]).to_string().contains("truncated file"));
}

/// Binary data in the other byte order than the check integer announces
/// (the check alone swapped) are named as byte-swapped, not as truncated.
#[test]
fn byte_swapped_data_are_named() {
    for (version, big_endian) in [("4.1", true), ("4.1", false), ("2.2", false)] {
        let mut bytes = match version {
            "4.1" => binary_square_v41(big_endian, 8),
            _ => binary_square_v22(big_endian),
        };
        let check = bytes.windows(4).position(|w| w == [1, 0, 0, 0] || w == [0, 0, 0, 1]).unwrap();
        bytes[check..check + 4].reverse();
        let err = read_msh(&bytes).unwrap_err();
        assert!(matches!(err.kind(), MshErrorKind::ByteSwapped { .. }), "{version} {big_endian}: {err}");
        let announced = if big_endian { "little-endian" } else { "big-endian" };
        let text = err.to_string();
        assert!(text.contains(&format!("in the {announced} byte order that the check integer")), "{text}");
        assert!(text.contains("the data and the check disagree"), "{text}");
        if version == "4.1" {
            assert!(text.contains("byte-swapped data: the number of entities of dimension 2 is"), "{text}");
        } else {
            assert!(text.contains("the number of elements of an element header is 33554432"), "{text}");
        }
    }
}

// ----- robustness ------------------------------------------------------------------

fn all_fixture_bytes() -> Vec<(String, Vec<u8>)> {
    let mut files = vec![];
    for name in FIXTURES {
        for flavour in FLAVOURS {
            files.push((format!("{name}.{flavour}"), std::fs::read(fixture_path(name, flavour)).unwrap()));
        }
    }
    files.push(("square".into(), SQUARE.as_bytes().to_vec()));
    files.push(("square.v41.bin".into(), binary_square_v41(true, 4)));
    files.push(("square.v22.bin".into(), binary_square_v22(false)));
    files
}

/// Reads `bytes` and, if that works, builds the meshes: none of it may panic.
fn read_everything(bytes: &[u8]) -> bool {
    match read_msh(bytes) {
        Ok(msh) => {
            let _ = msh.surface(None);
            let _ = msh.volume(None);
            true
        }
        Err(e) => {
            assert!(!e.to_string().is_empty());
            false
        }
    }
}

#[test]
fn truncated_fixtures_give_errors_not_panics() {
    for (name, bytes) in all_fixture_bytes() {
        let step = (bytes.len() / 400).max(1);
        let offsets = (0..bytes.len().min(300)).chain((300..bytes.len()).step_by(step));
        for len in offsets {
            let result = std::panic::catch_unwind(|| read_everything(&bytes[..len]));
            assert!(result.is_ok(), "{name} truncated to {len} bytes panics");
        }
        assert!(read_everything(&bytes), "{name}");
    }
}

#[test]
fn corrupted_fixtures_give_errors_not_panics() {
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut random = move |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    let bytes_of_interest = b"0123456789 \n$.-e\xff\x00\x01";
    for (name, bytes) in all_fixture_bytes() {
        for _ in 0..150 {
            let mut corrupted = bytes.clone();
            for _ in 0..1 + random(3) {
                let at = random(corrupted.len());
                corrupted[at] = bytes_of_interest[random(bytes_of_interest.len())];
            }
            let result = std::panic::catch_unwind(|| read_everything(&corrupted));
            assert!(result.is_ok(), "{name} corrupted panics: {:?}", String::from_utf8_lossy(&corrupted));
        }
    }
}

/// A body's surface must be made of its cells' faces: two Hex8 stacked, the
/// top face as the hex's quad (accepted, oriented out of the body), as two
/// triangles (no cell has them) and the face between the hexes (inside the
/// body) each refused with one line naming the element and the groups.
#[test]
fn a_body_surface_that_is_no_face_of_its_cells_is_named() {
    let node = |i: usize, j: usize, k: usize| 1 + i + 2 * j + 4 * k;
    let nodes: Vec<String> =
        (0..12).map(|n| format!("{} {} {} {}", n + 1, n % 2, (n / 2) % 2, n / 4)).collect();
    let hex = |k: usize| {
        [(0, 0), (1, 0), (1, 1), (0, 1)]
            .iter()
            .chain(&[(0, 0), (1, 0), (1, 1), (0, 1)])
            .enumerate()
            .map(|(c, &(i, j))| node(i, j, k + c / 4).to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    let top = [node(0, 0, 2), node(1, 0, 2), node(1, 1, 2), node(0, 1, 2)];
    let mid = [node(0, 0, 1), node(1, 0, 1), node(1, 1, 1), node(0, 1, 1)];
    let elements = [
        format!("1 5 2 1 1 {}", hex(0)),
        format!("2 5 2 1 1 {}", hex(1)),
        format!("3 3 2 2 2 {} {} {} {}", top[0], top[1], top[2], top[3]),
        format!("4 2 2 3 3 {} {} {}", top[0], top[1], top[2]),
        format!("5 2 2 3 3 {} {} {}", top[0], top[2], top[3]),
        format!("6 3 2 4 4 {} {} {} {}", mid[0], mid[1], mid[2], mid[3]),
    ];
    let text = format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n3 1 \"block\"\n2 2 \"top\"\n2 3 \"split\"\n\
         2 4 \"mid\"\n$EndPhysicalNames\n$Nodes\n12\n{}\n$EndNodes\n$Elements\n6\n{}\n$EndElements\n",
        nodes.join("\n"),
        elements.join("\n")
    );
    let msh = read_msh(text.as_bytes()).unwrap();
    for volume in [None, Some("block")] {
        let surface = msh.surface_of_volume("top", volume).unwrap();
        assert!(area_vector(&surface.corners(0))[2] > 0.0, "oriented out of the body");
        let body =
            volume.map_or("the file's cells".to_string(), |_| "physical group \"block\" (1)".to_string());
        let e = msh.surface_of_volume("split", volume).unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "element 4 of physical group \"split\" (3) is not a face of any cell of {body}: \
                 a body's surface must be made of its cells' faces"
            )
        );
        let e = msh.surface_of_volume("mid", volume).unwrap_err().to_string();
        assert!(
            e.starts_with("element 6 of physical group \"mid\" (4) is a face between two cells of"),
            "{e}"
        );
    }
    // The operator's surfaces (no body) take any faces.
    assert_eq!(msh.surface(Some("split")).unwrap().n_faces(), 2);
}
