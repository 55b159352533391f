//! The Abaqus / CalculiX reader: files from Gmsh and meshio against Gmsh's
//! MSH of the same mesh, the face numbering of every element type, the
//! keywords of CalculiX's test decks, the syntax, and one-line errors.

use std::path::{Path, PathBuf};

use seam::{area_vector, CellKind, Point3, SurfaceMesh, VolumeMesh};
use seam_io::{read_inp, read_inp_file, read_msh_file, Msh, MshVersion};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/abaqus").join(name)
}

fn inp(text: &str) -> Msh {
    read_inp(text.as_bytes()).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn inp_error(text: &str) -> String {
    let e = read_inp(text.as_bytes()).err().unwrap_or_else(|| panic!("read without error:\n{text}"));
    let e = e.to_string();
    assert!(!e.contains('\n'), "{e}");
    e
}

pub(crate) fn close(a: Point3, b: Point3, tol: f64) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() <= tol)
}

pub(crate) fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn mean(points: &[Point3]) -> Point3 {
    let n = points.len() as f64;
    let mut m = [0.0; 3];
    for p in points {
        (0..3).for_each(|i| m[i] += p[i] / n);
    }
    m
}

/// The volume of every cell, by a quadrature exact for the meshes here.
pub(crate) fn volumes(mesh: &VolumeMesh) -> Vec<f64> {
    mesh.cells()
        .iter()
        .map(|cell| {
            let kind = cell.kind();
            let rule = seam::volume_rule(kind.reference_shape(), 4);
            let mut volume = 0.0;
            for (xi, w) in rule.points.iter().zip(&rule.weights) {
                let g = kind.gradients(*xi);
                let mut j = [[0.0; 3]; 3];
                for (a, &n) in cell.nodes().iter().enumerate() {
                    let x = mesh.points()[n];
                    for r in 0..3 {
                        for c in 0..3 {
                            j[r][c] += x[r] * g[a][c];
                        }
                    }
                }
                let det = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
                    - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
                    + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
                volume += w * det;
            }
            volume
        })
        .collect()
}

/// The faces of a surface as (sorted node tags, area vector of the corners).
/// Surface `surface` of `volume` read from another format (`other`) and
/// from its MSH twin (`msh`): the same faces by node tags, their area
/// vectors to `tol`, and a unit area along `normal`.
pub(crate) fn assert_same_unit_surface(
    (other, msh): (&Msh, &Msh),
    (surface, volume, normal): (&str, &str, Point3),
    tol: f64,
    what: &str,
) {
    let o = other.surface_of_volume(surface, Some(volume)).unwrap();
    let m = msh.surface_of_volume(surface, Some(volume)).unwrap();
    let (o, m) = (faces_by_tags(other, &o), faces_by_tags(msh, &m));
    assert_eq!(o.len(), m.len(), "{what} {surface}");
    let mut area = 0.0;
    for ((o_tags, o_area), (m_tags, m_area)) in o.iter().zip(&m) {
        assert_eq!(o_tags, m_tags, "{what} {surface}");
        assert!(close(*o_area, *m_area, tol), "{what} {surface}: {o_area:?} {m_area:?}");
        area += dot(*o_area, normal);
    }
    assert!((area - 1.0).abs() < 1e-12, "{what} {surface} of {volume}: {area}");
}

pub(crate) fn faces_by_tags(msh: &Msh, surface: &SurfaceMesh) -> Vec<(Vec<u64>, Point3)> {
    let mut faces: Vec<(Vec<u64>, Point3)> = surface
        .faces()
        .iter()
        .map(|f| {
            let mut tags: Vec<u64> = f.nodes().iter().map(|&n| msh.node_tags[n]).collect();
            tags.sort_unstable();
            let corners: Vec<Point3> = f.corner_nodes().iter().map(|&n| surface.points()[n]).collect();
            (tags, area_vector(&corners))
        })
        .collect();
    faces.sort_by(|a, b| a.0.cmp(&b.0));
    faces
}

const BOXES: [&str; 7] =
    ["box_tet", "box_tet_o2", "box_hex", "box_hex20", "box_hex27", "box_prism", "box_prism15"];

/// Gmsh writes each mesh as MSH and as .inp (make_fixtures.py): the reader
/// gives the same nodes (ids and coordinates), the same cells by element id
/// (nodes in the same order, so the same corners and volumes), the same
/// volume groups and the same surfaces, oriented alike.
#[test]
fn gmsh_inp_gives_the_cells_and_surfaces_of_gmsh_msh() {
    for name in BOXES {
        let msh = read_msh_file(data(&format!("{name}.msh"))).unwrap();
        let abq = read_inp_file(data(&format!("{name}.inp"))).unwrap();
        assert_eq!(abq.format.version, MshVersion::AbaqusInp);
        assert_eq!(abq.node_tags, msh.node_tags, "{name}");
        for (a, b) in abq.nodes.iter().zip(&msh.nodes) {
            assert!(close(*a, *b, 1e-14), "{name}: {a:?} {b:?}");
        }
        let cells = |m: &Msh| m.volume_elements(None).unwrap().into_iter().cloned().collect::<Vec<_>>();
        let (a_cells, m_cells) = (cells(&abq), cells(&msh));
        assert_eq!(a_cells.len(), m_cells.len(), "{name}");
        for m in &m_cells {
            let a = a_cells
                .iter()
                .find(|a| a.tag == m.tag)
                .unwrap_or_else(|| panic!("{name}: element {}", m.tag));
            assert_eq!((a.gmsh_type, &a.nodes), (m.gmsh_type, &m.nodes), "{name}: element {}", m.tag);
        }
        let (a_volume, m_volume) = (abq.volume(None).unwrap(), msh.volume(None).unwrap());
        let (a_v, m_v) = (volumes(&a_volume), volumes(&m_volume));
        assert!(a_v.iter().all(|&v| v > 0.0), "{name}");
        assert!((a_v.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{name}");
        // Gmsh's .inp gives coordinates to 16 digits, not 17.
        assert!(a_v.iter().zip(&m_v).all(|(a, m)| (a - m).abs() < 1e-13 * m), "{name}");
        for group in ["lower", "upper", "LOWER"] {
            let tags = |m: &Msh, g: &str| {
                m.volume_elements(Some(g)).unwrap().iter().map(|e| e.tag).collect::<Vec<_>>()
            };
            assert_eq!(tags(&abq, group), tags(&msh, &group.to_lowercase()), "{name} {group}");
        }
        for (surface, volume, normal) in [
            ("top", "upper", [0.0, 0.0, 1.0]),
            ("interface", "lower", [0.0, 0.0, 1.0]),
            ("interface", "upper", [0.0, 0.0, -1.0]),
        ] {
            assert_same_unit_surface((&abq, &msh), (surface, volume, normal), 1e-14, name);
        }
        // The plane-stress or membrane elements Gmsh writes for its surfaces
        // are skipped, and their sets say so.
        let e = abq.volume(Some("top")).unwrap_err().to_string();
        assert!(
            e.contains("element set top: element ")
                && e.contains("is of type ")
                && e.contains(", not a solid seam reads"),
            "{e}"
        );
    }
}

/// meshio's Abaqus writer (VTK node order, other type names: C3D8RH,
/// C3D20RH, C3D10MH, one element a line) gives the cells of the MSH file it
/// converted, in order, and its element sets.
#[test]
fn meshio_inp_gives_the_cells_of_the_msh_it_converted() {
    for name in ["box_tet", "box_tet_o2", "box_hex", "box_hex20", "box_prism"] {
        let msh = read_msh_file(data(&format!("{name}.msh"))).unwrap();
        let abq = read_inp_file(data(&format!("{name}.meshio.inp"))).unwrap();
        let (a, m) = (abq.volume(None).unwrap(), msh.volume(None).unwrap());
        assert_eq!(a.cells().len(), m.cells().len(), "{name}");
        for (ac, mc) in a.cells().iter().zip(m.cells()) {
            assert_eq!(ac.kind(), mc.kind(), "{name}");
            for (&i, &j) in ac.nodes().iter().zip(mc.nodes()) {
                assert!(close(a.points()[i], m.points()[j], 1e-15), "{name}");
            }
        }
        assert_eq!(volumes(&a), volumes(&m), "{name}");
        for group in ["lower", "upper"] {
            let count = |m: &Msh| m.volume(Some(group)).unwrap().cells().len();
            assert_eq!(count(&abq), count(&msh), "{name} {group}");
        }
    }
}

/// One element of an Abaqus type on the box [0,1]×[0,2]×[0,3] (tetrahedra
/// and wedges on its corner), its nodes numbered as the Abaqus manual
/// numbers them: corners, then mid-edge nodes as the means of the corners
/// listed (1-based), then (C3D27, as Gmsh writes it) the centre and the
/// face centres of S1…S6.
struct Element {
    name: &'static str,
    kind: CellKind,
    corners: Vec<Point3>,
    /// Every further node, as the corners it is the mean of.
    more: Vec<Vec<usize>>,
    /// Faces S1, S2, … by corners (1-based), from the manual.
    faces: Vec<Vec<usize>>,
}

fn scaled(points: &[[f64; 3]]) -> Vec<Point3> {
    points.iter().map(|p| [p[0], 2.0 * p[1], 3.0 * p[2]]).collect()
}

fn elements() -> Vec<Element> {
    let tet = scaled(&[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]]);
    let tet_faces = vec![vec![1, 2, 3], vec![1, 4, 2], vec![2, 4, 3], vec![3, 4, 1]];
    let tet_edges = vec![vec![1, 2], vec![2, 3], vec![3, 1], vec![1, 4], vec![2, 4], vec![3, 4]];
    // The square 1-2-3-4 at z = 0, then at z = 1.
    let square = [[0., 0.], [1., 0.], [1., 1.], [0., 1.]];
    let hex = scaled(&[0., 1.].iter().flat_map(|&z| square.map(|[x, y]| [x, y, z])).collect::<Vec<_>>());
    let hex_faces = vec![
        vec![1, 2, 3, 4],
        vec![5, 8, 7, 6],
        vec![1, 5, 6, 2],
        vec![2, 6, 7, 3],
        vec![3, 7, 8, 4],
        vec![4, 8, 5, 1],
    ];
    let hex_edges: Vec<Vec<usize>> =
        [[1, 2], [2, 3], [3, 4], [4, 1], [5, 6], [6, 7], [7, 8], [8, 5], [1, 5], [2, 6], [3, 7], [4, 8]]
            .iter()
            .map(|e| e.to_vec())
            .collect();
    let mut hex27 = hex_edges.clone();
    hex27.push((1..=8).collect());
    hex27.extend(hex_faces.iter().cloned());
    let wedge = scaled(&[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.], [1., 0., 1.], [0., 1., 1.]]);
    let wedge_faces =
        vec![vec![1, 2, 3], vec![4, 6, 5], vec![1, 4, 5, 2], vec![2, 5, 6, 3], vec![3, 6, 4, 1]];
    let wedge_edges: Vec<Vec<usize>> =
        [[1, 2], [2, 3], [3, 1], [4, 5], [5, 6], [6, 4], [1, 4], [2, 5], [3, 6]]
            .iter()
            .map(|e| e.to_vec())
            .collect();
    let e = |name, kind, corners: &Vec<Point3>, more: Vec<Vec<usize>>, faces: &Vec<Vec<usize>>| Element {
        name,
        kind,
        corners: corners.clone(),
        more,
        faces: faces.clone(),
    };
    vec![
        e("C3D4", CellKind::Tet4, &tet, vec![], &tet_faces),
        e("C3D10", CellKind::Tet10, &tet, tet_edges, &tet_faces),
        e("C3D8R", CellKind::Hex8, &hex, vec![], &hex_faces),
        e("C3D20R", CellKind::Hex20, &hex, hex_edges, &hex_faces),
        e("C3D27", CellKind::Hex27, &hex, hex27, &hex_faces),
        e("C3D6", CellKind::Prism6, &wedge, vec![], &wedge_faces),
        e("C3D15", CellKind::Prism15, &wedge, wedge_edges, &wedge_faces),
    ]
}

impl Element {
    fn nodes(&self) -> Vec<Point3> {
        let more =
            self.more.iter().map(|c| mean(&c.iter().map(|&i| self.corners[i - 1]).collect::<Vec<_>>()));
        self.corners.iter().copied().chain(more).collect()
    }

    /// The deck: the nodes numbered 1…n, the element (its nodes 8 a line, so
    /// that second-order ones go on over lines), face `face` as surface F.
    fn deck(&self, face: usize) -> String {
        let mut deck = String::from("*NODE\n");
        for (i, p) in self.nodes().iter().enumerate() {
            deck += &format!("{}, {}, {}, {}\n", i + 1, p[0], p[1], p[2]);
        }
        deck += &format!("*ELEMENT, TYPE={}, ELSET=ONE\n7", self.name);
        for (i, n) in (1..=self.nodes().len()).enumerate() {
            deck += &format!(",{}{n}", if i > 0 && i % 8 == 0 { "\n" } else { " " });
        }
        deck + &format!("\n*SURFACE, NAME=F, TYPE=ELEMENT\n7, S{face}\n")
    }
}

/// Every node of every type lands where seam's reference cell has it (so the
/// node order is Gmsh's), and every face S1…Sn selected alone is the face
/// the Abaqus manual defines: its corners and further nodes, its area,
/// outward.
#[test]
fn every_face_of_every_type_is_the_manuals() {
    for element in elements() {
        let all = element.nodes();
        for face in 1..=element.faces.len() {
            let msh = inp(&element.deck(face));
            let volume = msh.volume(Some("one")).unwrap();
            let cell = &volume.cells()[0];
            assert_eq!(cell.kind(), element.kind, "{}", element.name);
            // The reference node ξ maps to the box affinely.
            for (&n, xi) in cell.nodes().iter().zip(element.kind.reference_nodes()) {
                let unit = match element.kind.reference_shape() {
                    seam::Shape::Hexahedron => xi.map(|x| (x + 1.0) / 2.0),
                    seam::Shape::Prism => [xi[0], xi[1], (xi[2] + 1.0) / 2.0],
                    _ => *xi,
                };
                let want = scaled(&[unit])[0];
                assert!(
                    close(volume.points()[n], want, 1e-15),
                    "{}: {:?} {want:?}",
                    element.name,
                    volume.points()[n]
                );
            }
            let surface = msh.surface_of_volume("f", None).unwrap();
            assert_eq!(surface.n_faces(), 1);
            let f = &surface.faces()[0];
            let corners: Vec<Point3> =
                element.faces[face - 1].iter().map(|&c| element.corners[c - 1]).collect();
            let got: Vec<Point3> = f.corner_nodes().iter().map(|&n| surface.points()[n]).collect();
            let area = area_vector(&got);
            let want = area_vector(&corners);
            let outward = dot(want, sub(mean(&corners), mean(&element.corners))) > 0.0;
            let want = if outward { want } else { want.map(|x| -x) };
            assert!(close(area, want, 1e-14), "{} S{face}: {area:?}, manual {want:?}", element.name);
            let on_face = |p: &Point3| dot(sub(*p, corners[0]), want).abs() < 1e-12;
            let mut expected: Vec<Point3> = all.iter().copied().filter(on_face).collect();
            let mut found: Vec<Point3> = f.nodes().iter().map(|&n| surface.points()[n]).collect();
            for list in [&mut expected, &mut found] {
                list.sort_by(|a, b| a.partial_cmp(b).unwrap());
            }
            assert_eq!(found, expected, "{} S{face}", element.name);
            assert_eq!(
                msh.surface_face_tags(Some("F")).unwrap(),
                Some(vec![seam_io::abaqus::face_tag(7, face as u8)])
            );
        }
        let e = inp_error_at_selection(&element.deck(element.faces.len() + 1));
        assert!(
            e.contains(&format!("has faces S1…S{}, not S{}", element.faces.len(), element.faces.len() + 1)),
            "{e}"
        );
    }
}

/// The error of selecting surface F of a deck.
fn inp_error_at_selection(text: &str) -> String {
    let msh = inp(text);
    let e = msh.surface_of_volume("F", None).unwrap_err().to_string();
    assert!(!e.contains('\n'), "{e}");
    e
}

const DECKS: &str = "/usr/share/doc/calculix-ccx-test/examples/test";

/// The decks of CalculiX's test suite (`.inp` and `.inp.gz`; those with
/// `*INCLUDE` read where they are, the others from memory).
fn calculix_decks() -> Vec<(PathBuf, Vec<u8>)> {
    let dir = Path::new(DECKS);
    assert!(
        dir.is_dir(),
        "CalculiX's test decks are missing: apt-get install calculix-ccx-test (they go to {DECKS})"
    );
    let mut decks: Vec<(PathBuf, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter_map(|p| {
            let name = p.file_name()?.to_str()?.to_string();
            let bytes = std::fs::read(&p).ok()?;
            if name.ends_with(".inp") {
                Some((p, bytes))
            } else if name.ends_with(".inp.gz") {
                let mut text = Vec::new();
                std::io::Read::read_to_end(&mut flate2::read::GzDecoder::new(&bytes[..]), &mut text).ok()?;
                Some((p, text))
            } else {
                None
            }
        })
        .collect();
    decks.sort();
    decks
}

/// Every deck of CalculiX's test suite is read (their shells, beams, 2D
/// elements, springs… skipped), except three whose elements have more nodes
/// than their type. Those with solids give cells.
#[test]
fn calculix_test_decks_are_read() {
    let decks = calculix_decks();
    assert!(decks.len() > 300, "{} decks", decks.len());
    let (mut read, mut with_cells, mut refused) = (0, 0, Vec::new());
    for (path, bytes) in &decks {
        let result = match path.extension().and_then(|e| e.to_str()) {
            Some("inp") => read_inp_file(path),
            _ => read_inp(bytes),
        };
        match result {
            Ok(msh) => {
                read += 1;
                if msh.volume(None).is_ok() {
                    with_cells += 1;
                }
            }
            Err(e) => refused.push(format!("{}: {e}", path.display())),
        }
    }
    // Three decks give C3D8 elements 10 nodes (CalculiX reads the first 8).
    let expected = |e: &String| {
        ["beampsensfreq.inp.gz", "dloadlinI.inp.gz", "dloadlinIf.inp.gz"].iter().any(|d| e.contains(d))
            && e.contains("has 8 nodes, but its data list 10")
    };
    let unexpected: Vec<&String> = refused.iter().filter(|e| !expected(e)).collect();
    assert!(
        unexpected.is_empty(),
        "{} decks refused:\n{}",
        unexpected.len(),
        unexpected.iter().map(|s| s.as_str()).collect::<Vec<_>>().join("\n")
    );
    assert!(read > 340 && with_cells > 200, "{read} decks read, {with_cells} with cells");
}

/// Facts of two decks of two cubes on top of each other in contact:
/// contact1 (C3D8; master surface "element 1, S5", slave surface TYPE=NODE)
/// and contact4 (C3D20; slave "2, S3", master "1, S5"; the upper cube is
/// smaller). The faces CalculiX puts in contact are the facing faces: the
/// lower cube's top (outward +z) and the upper cube's bottom (−z), in one
/// plane.
#[test]
fn calculix_contact_decks_face_each_other() {
    let one = read_inp_file(Path::new(DECKS).join("contact1.inp")).unwrap();
    assert_eq!((one.nodes.len(), one.volume(None).unwrap().cells().len()), (16, 2));
    let master = one.surface_of_volume("SMAST", None).unwrap();
    assert_eq!(master.n_faces(), 1);
    let a = area_vector(&master.corners(0));
    assert!(close(a, [0.0, 0.0, 1.0], 1e-6), "{a:?}");
    assert!(master.corners(0).iter().all(|p| (p[2] - 1.0).abs() < 1e-6));
    let e = one.surface(Some("Sslav")).unwrap_err().to_string();
    assert!(e.contains("contact1.inp:62) is TYPE=NODE"), "{e}");

    let four = read_inp_file(Path::new(DECKS).join("contact4.inp")).unwrap();
    let cells = four.volume(None).unwrap();
    assert_eq!(cells.cells().len(), 2);
    assert!(cells.cells().iter().all(|c| c.kind() == CellKind::Hex20));
    let slave = four.surface_of_volume("Sslav", None).unwrap();
    let master = four.surface_of_volume("Smast", None).unwrap();
    assert_eq!((slave.faces()[0].nodes().len(), master.faces()[0].nodes().len()), (8, 8));
    let (s, m) = (area_vector(&slave.corners(0)), area_vector(&master.corners(0)));
    let along_z = |a: Point3| a[2].signum() * (a[2].abs() - dot(a, a).sqrt()).abs().max(a[0].abs());
    assert!(s[2] < 0.0 && m[2] > 0.0 && along_z(s).abs() < 1e-9 && along_z(m).abs() < 1e-9, "{s:?} {m:?}");
    let height = |surface: &SurfaceMesh| {
        surface.faces()[0].nodes().iter().map(|&n| surface.points()[n][2]).collect::<Vec<f64>>()
    };
    let (hs, hm) = (height(&slave), height(&master));
    assert!(hs.iter().chain(&hm).all(|z| (z - hm[0]).abs() < 1e-6), "{hs:?} {hm:?}");
}

/// The syntax: mixed case, comments and blank lines, continued keyword
/// lines, an element over two lines, `GENERATE`, sets of sets, quoted names.
#[test]
fn syntax_is_read() {
    let msh = inp(
        "** a comment\n*Heading\n any title, with commas\n*Node, nset=ALL\n\
         1, 0., 0., 0.\n2, 1.0, 0, 0\n3, 1, 1, 0\n4, 0, 1.D0, 0\n5, 0, 0, 1\n6, 1E0, 0, 1\n7, 1, 1, 1.0e0\n8, , 1, 1\n\n\
         9, 2, 0, 0\n10, 2, 1, 0\n11, 2, 0, 1\n12, 2, 1, 1\n\
         *element, type=c3d8r,\n  elset=\"Left Half\"\n1, 1, 2, 3, 4,\n5, 6, 7, 8\n\
         *ELEMENT, TYPE=C3D8I\n2, 2, 9, 10, 3, 6, 11, 12, 7\n\
         *Elset, elset=RIGHT, generate\n2, 2, 1\n*ELSET, ELSET=both\n\"left half\", right\n\
         *material, name=steel\n*elastic\n210000., 0.3\n*Step\n*Static\n*End Step\n",
    );
    assert_eq!(msh.nodes.len(), 12);
    assert_eq!(msh.nodes[7], [0.0, 1.0, 1.0]);
    assert_eq!(msh.volume(Some("LEFT HALF")).unwrap().cells().len(), 1);
    assert_eq!(msh.volume(Some("Right")).unwrap().cells().len(), 1);
    let both: Vec<u64> = msh.volume_elements(Some("BOTH")).unwrap().iter().map(|e| e.tag).collect();
    assert_eq!(both, [1, 2]);
    assert!(volumes(&msh.volume(None).unwrap()).iter().all(|v| (v - 1.0).abs() < 1e-14));
}

/// `*PART` / `*INSTANCE` / `*ASSEMBLY` as Abaqus/CAE writes them: two
/// instances of one part (the second translated), the part's sets and
/// surfaces qualified by instance, assembly sets with `INSTANCE=`, `_S1`-style
/// sets in an assembly surface, ids offset by instance.
#[test]
fn parts_and_instances_are_placed_and_named() {
    let msh = inp("*Part, name=Block\n*Node\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n\
         *Element, type=C3D4\n1, 1, 2, 3, 4\n*Elset, elset=Set-1\n1\n\
         *Surface, type=ELEMENT, name=Bottom\nSet-1, S1\n*End Part\n\
         *Assembly, name=Assembly\n*Instance, name=Block-1, part=Block\n*End Instance\n\
         *Instance, name=Block-2, part=BLOCK\n 10., 0., 0.\n 0, 0, 0, 0, 0, 1, 0.\n*End Instance\n\
         *Elset, elset=_Top_S3, internal, instance=Block-2\n1,\n\
         *Surface, type=ELEMENT, name=Top\n_Top_S3, S3\n\
         *Elset, elset=Pair\nBlock-1.Set-1, Block-2.1\n*End Assembly\n");
    assert_eq!(msh.node_tags, [1, 2, 3, 4, 11, 12, 13, 14]);
    assert_eq!(msh.nodes[5], [11.0, 0.0, 0.0]);
    let tags =
        |group: &str| msh.volume_elements(Some(group)).unwrap().iter().map(|e| e.tag).collect::<Vec<_>>();
    assert_eq!(tags("Block-1.Set-1"), [1]);
    assert_eq!(tags("block-2.set-1"), [11]);
    assert_eq!(tags("Pair"), [1, 11]);
    assert!(msh.volume(Some("Set-1")).is_err());
    let bottom = msh.surface_of_volume("Block-2.Bottom", None).unwrap();
    assert!(close(area_vector(&bottom.corners(0)[..3]), [0.0, 0.0, -0.5], 1e-15));
    let top = msh.surface_of_volume("Top", None).unwrap();
    let n = area_vector(&top.corners(0)[..3]);
    assert!(close(n, [0.5, 0.5, 0.5], 1e-15) && top.corners(0)[0][0] >= 10.0, "{n:?}");
    assert_eq!(msh.surface_face_tags(Some("Top")).unwrap(), Some(vec![seam_io::abaqus::face_tag(11, 3)]));
    // Messages name a face by its element and label.
    let e = msh.surface_of_volume("Top", Some("Block-1.Set-1")).unwrap_err().to_string();
    assert!(e.starts_with("element 11 face S3 of physical group \"Top\""), "{e}");
}

/// `*INCLUDE` relative to the including file, nested.
#[test]
fn includes_are_read_relative_to_the_including_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("mesh")).unwrap();
    std::fs::write(
        dir.path().join("main.inp"),
        "*INCLUDE, INPUT=mesh/nodes.inp\n*ELEMENT, TYPE=C3D4, ELSET=E\n1, 1, 2, 3, 4\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("mesh/nodes.inp"),
        "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*include, input=\"more.inp\"\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("mesh/more.inp"), "3, 0, 1, 0\n4, 0, 0, 1\n").unwrap();
    let msh = read_inp_file(dir.path().join("main.inp")).unwrap();
    assert_eq!(msh.nodes.len(), 4);
    assert_eq!(msh.volume(Some("E")).unwrap().cells().len(), 1);
}

/// Each error is one line with the file, the line and the cause.
#[test]
fn bad_input_is_refused_on_one_line() {
    let nodes = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n";
    for (text, want) in [
        (
            format!("{nodes}*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 9\n"),
            "line 7: element 1 refers to node 9, which is not defined",
        ),
        (
            format!("{nodes}3, 0, 1.2.3, 0\n"),
            "line 6: expected a number for coordinate 2 of node 3, found \"1.2.3\"",
        ),
        (format!("{nodes}5, 0, nan, 0\n"), "line 6: expected a number for coordinate 2 of node 5"),
        (
            format!("{nodes}*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4, 5\n"),
            "line 7: element 1 of type C3D4 has 4 nodes, but its data list 5",
        ),
        (
            format!("{nodes}*ELEMENT, TYPE=C3D8\n1, 1, 2, 3, 4\n*STEP\n"),
            "line 7: element 1 of type C3D8 has 8 nodes, but its data end after 4",
        ),
        (format!("{nodes}1, 0, 0, 0\n"), "line 6: node 1 is defined twice"),
        (
            format!("{nodes}*ELSET, ELSET=A, GENERATE\n1, 1000000000, 1\n"),
            "line 7: GENERATE from 1 to 1000000000 by 1 names 1000000000 elements, more than the input's",
        ),
        (format!("{nodes}*ELSET, ELSET=A, GENERATE\n5, 1\n"), "line 7: GENERATE from 5 down to 1"),
        (
            format!("{nodes}*ELSET, ELSET=A, GENERATE\n1, 5, 0\n"),
            "line 7: a GENERATE step must be at least 1",
        ),
        (
            "*PART, NAME=P\n*END PART\n*INSTANCE, NAME=I, PART=P\n0, 0, 0\n0, 0, 0, 1, 0, 0, 90\n"
                .to_string(),
            "line 5: *INSTANCE I is rotated",
        ),
        ("*INSTANCE, NAME=I, PART=Q\n".to_string(), "line 1: *INSTANCE I: no *PART Q before it"),
        ("*NODE, SYSTEM=C\n1, 1, 0, 0\n".to_string(), "line 1: *NODE, SYSTEM=C: only rectangular"),
        ("*ELEMENT\n1, 1\n".to_string(), "line 1: *ELEMENT without TYPE="),
        (
            "*INCLUDE, INPUT=mesh.inp\n".to_string(),
            "line 1: *INCLUDE, INPUT=mesh.inp: input read from memory",
        ),
    ] {
        let e = inp_error(&text);
        assert!(e.starts_with(want), "{e}\nwanted: {want}");
    }
}

/// Errors that come when a set or surface is selected: an element type seam
/// does not read, named; `TYPE=NODE` surfaces; missing face labels.
#[test]
fn unusable_sets_and_surfaces_say_why() {
    let text = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n\
                *ELEMENT, TYPE=C3D4, ELSET=ALL\n1, 1, 2, 3, 4\n*ELEMENT, TYPE=S3R, ELSET=ALL\n2, 1, 2, 3\n\
                *ELEMENT, TYPE=FOO7, ELSET=ODD\n3, 1, 2,\n3, 4\n\
                *SURFACE, NAME=N, TYPE=NODE\n1\n*SURFACE, NAME=NOLABEL\n1\n*SURFACE, NAME=SHELL\nALL, SPOS\n";
    let msh = inp(text);
    assert_eq!(msh.volume(None).unwrap().cells().len(), 1);
    let error = |r: Result<(), seam_io::MshError>| {
        let e = r.unwrap_err().to_string();
        assert!(!e.contains('\n'));
        e
    };
    let e = error(msh.volume(Some("all")).map(drop));
    assert!(e.contains("element set ALL: element 2 (line 9) is of type S3R, not a solid seam reads"), "{e}");
    let e = error(msh.volume(Some("ODD")).map(drop));
    assert!(e.contains("element 3 (line 11) is of type FOO7"), "{e}");
    let e = error(msh.surface_of_volume("N", None).map(drop));
    assert!(e.contains("*SURFACE N (line 13) is TYPE=NODE, a set of nodes"), "{e}");
    let e = error(msh.surface(Some("NoLabel")).map(drop));
    assert!(e.contains("line 16 gives no face label"), "{e}");
    let e = error(msh.surface(Some("shell")).map(drop));
    assert!(e.contains("its set ALL cannot be used: element 2 (line 9) is of type S3R"), "{e}");
}

/// Include cycles and missing included files are named with the including
/// line.
#[test]
fn include_cycles_and_missing_files_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.inp");
    std::fs::write(&a, "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=b.inp\n").unwrap();
    std::fs::write(dir.path().join("b.inp"), "** b\n*INCLUDE, INPUT=a.inp\n").unwrap();
    let e = read_inp_file(&a).unwrap_err();
    assert_eq!((e.path(), e.line()), (Some(dir.path().join("b.inp").as_path()), Some(2)));
    assert!(e.to_string().contains("b.inp:2: include cycle: ") && e.message().ends_with("a.inp"), "{e}");
    std::fs::write(&a, "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=missing.inp\n").unwrap();
    let e = read_inp_file(&a).unwrap_err().to_string();
    assert!(e.contains("a.inp:3: cannot read the included file") && e.contains("missing.inp"), "{e}");
    let e = read_inp_file(dir.path().join("none.inp")).unwrap_err();
    assert_eq!(e.io_kind(), Some(std::io::ErrorKind::NotFound));
}

/// The fuzz seeds and every input the fuzzer once failed on
/// (`fuzz/seeds/abaqus`, `fuzz/regressions/abaqus`) are read or refused in
/// one short line, and so are their selections.
#[test]
fn abaqus_fuzz_inputs_are_read_or_refused() {
    let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz");
    let mut n = 0;
    for dir in ["seeds", "regressions"] {
        let Ok(entries) = std::fs::read_dir(fuzz.join(dir).join("abaqus")) else { continue };
        for path in entries.map(|e| e.unwrap().path()).filter(|p| p.is_file()) {
            n += 1;
            let bytes = std::fs::read(&path).unwrap();
            let one_line =
                |e: String| assert!(!e.contains('\n') && e.len() < 1000, "{}: {e}", path.display());
            match read_inp(&bytes) {
                Ok(msh) => {
                    for dim in [2, 3] {
                        for group in msh.physical_groups(dim) {
                            let name = group.tag.to_string();
                            if let Err(e) = if dim == 2 {
                                msh.surface(Some(&name)).map(drop)
                            } else {
                                msh.volume(Some(&name)).map(drop)
                            } {
                                one_line(e.to_string());
                            }
                        }
                    }
                }
                Err(e) => one_line(e.to_string()),
            }
        }
    }
    assert!(n >= 5, "{n} fuzz inputs");
}

/// `read_model_file` chooses the reader by extension (`.inp` in any case)
/// or by `ModelFormat`; `.inp` errors keep their one line `FILE:LINE: cause`
/// with the file and line as the `MshError`'s; the surface and volume
/// readers take `.inp` files too.
#[test]
fn read_model_file_reads_inp_by_extension_or_format() {
    use seam_io::{read_model_file, read_surface_file, read_volume_file, ModelFormat, MshErrorKind};
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read(data("box_hex.inp")).unwrap();
    let upper = dir.path().join("BOX.INP");
    std::fs::write(&upper, &text).unwrap();
    let other = dir.path().join("box.model");
    std::fs::write(&other, &text).unwrap();
    let want = read_inp_file(&upper).unwrap();
    assert_eq!(read_model_file(&upper, None).unwrap(), want);
    assert_eq!(read_model_file(&other, Some(ModelFormat::Abaqus)).unwrap(), read_inp_file(&other).unwrap());
    assert!(matches!(read_model_file(&other, None).unwrap_err().kind(), MshErrorKind::NotMsh { .. }));
    assert_eq!(
        read_model_file(data("box_hex.msh"), None).unwrap(),
        read_msh_file(data("box_hex.msh")).unwrap()
    );
    let surface = read_surface_file(&upper, Some("INTERFACE")).unwrap();
    assert_eq!(surface.n_faces(), want.surface(Some("interface")).unwrap().n_faces());
    assert_eq!(read_volume_file(&upper, Some("lower")).unwrap().cells().len(), 8);

    let bad = dir.path().join("bad.inp");
    std::fs::write(&bad, "*NODE\n1, 0, 0, 0\n2, 1, x, 0\n").unwrap();
    let e = read_model_file(&bad, None).unwrap_err();
    assert!(matches!(e.kind(), MshErrorKind::Abaqus(_)));
    assert_eq!((e.path(), e.location()), (Some(bad.as_path()), Some(seam_io::Location::Line(3))));
    let message = e.to_string();
    assert!(message.starts_with(&format!("{}:3: ", bad.display())) && !message.contains('\n'), "{message}");
    let e = read_model_file(dir.path().join("none.inp"), None).unwrap_err();
    assert_eq!(e.io_kind(), Some(std::io::ErrorKind::NotFound));
    assert!(e.to_string().contains("none.inp: cannot read the file"), "{e}");
}
