//! Integration tests of VTU reading and writing: bit-exact round trips, field and
//! cell errors, files written by meshio and VTK (`tests/data/vtu/make_fixtures.py`),
//! every encoding the reader supports, corrupt and hostile input (regressions of a
//! hostile-input campaign, every truncation, random mutations, memory use in a
//! child process under an address-space limit), and the fixtures
//! `tests/python/test_vtu_meshio.py` checks with meshio (and VTK, the reader of
//! ParaView).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use seam::generate::{flat, patch, Pattern};
use seam::{Face, MeshError, SurfaceMesh};
use seam_io::{read_vtu, read_vtu_file, write_vtu, write_vtu_file, Field, VtuErrorKind, VtuMesh};

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/vtu")
}

/// A quad, two triangles and an off-surface point (6), with awkward coordinates.
fn mixed_mesh() -> SurfaceMesh {
    let points = vec![
        [0.0, 0.0, 0.0],
        [1.0 / 3.0, -0.0, 1e-300],
        [2.0, 0.1, 0.2],
        [0.0, 1.0, -3e-7],
        [1.0, 1.0, 5e-324],
        [2.0, 1.0, 0.3],
        [7.0, 7.0, 7.0],
    ];
    let faces = vec![Face::Quad4([0, 1, 4, 3]), Face::Tri3([1, 2, 4]), Face::Tri3([2, 5, 4])];
    SurfaceMesh::new(points, faces).unwrap()
}

fn wavy(n: usize, k: usize, offset: f64) -> Vec<f64> {
    (0..n * k).map(|i| ((i as f64 + offset) * 0.7).sin() / 3.0).collect()
}

/// Point fields p (scalar), u (vector), w (2), s (6); cell fields c (scalar), T (9).
fn mixed_fields(mesh: &SurfaceMesh) -> (Vec<Field>, Vec<Field>) {
    let (np, nf) = (mesh.n_points(), mesh.n_faces());
    let mut p = wavy(np, 1, 0.0);
    p[1] = -0.0;
    p[2] = f64::MIN_POSITIVE / 8.0; // subnormal
    p[3] = -1e300;
    let point_data = vec![
        Field::scalars("p", p),
        Field::new("u", 3, wavy(np, 3, 1.0)),
        Field::new("w", 2, wavy(np, 2, 2.0)),
        Field::new("s", 6, wavy(np, 6, 3.0)),
    ];
    let cell_data = vec![Field::scalars("c", vec![1.5, -2.25, 1e-17]), Field::new("T", 9, wavy(nf, 9, 4.0))];
    (point_data, cell_data)
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

fn assert_fields_identical(read: &[Field], written: &[Field]) {
    let names = |f: &[Field]| f.iter().map(|f| (f.name.clone(), f.components)).collect::<Vec<_>>();
    assert_eq!(names(read), names(written));
    for (r, w) in read.iter().zip(written) {
        assert_eq!(bits(&r.values), bits(&w.values), "field {}", r.name);
    }
}

fn assert_identical(read: &VtuMesh, mesh: &SurfaceMesh, point_data: &[Field], cell_data: &[Field]) {
    let flat_bits = |m: &SurfaceMesh| m.points().iter().flatten().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(flat_bits(&read.mesh), flat_bits(mesh));
    assert_eq!(read.mesh.faces(), mesh.faces());
    assert_fields_identical(&read.point_data, point_data);
    assert_fields_identical(&read.cell_data, cell_data);
}

#[test]
fn round_trip_of_a_mixed_mesh_is_bit_exact() {
    let mesh = mixed_mesh();
    let (point_data, cell_data) = mixed_fields(&mesh);
    let mut bytes = Vec::new();
    write_vtu(&mut bytes, &mesh, &point_data, &cell_data).unwrap();
    let read = read_vtu(&bytes[..]).unwrap();
    assert_identical(&read, &mesh, &point_data, &cell_data);
    assert_eq!(read.point_field("u").unwrap().components, 3);
    assert_eq!(read.cell_field("c").unwrap().values, [1.5, -2.25, 1e-17]);
    assert!(read.point_field("nope").is_none());

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mixed.vtu");
    write_vtu_file(&path, &mesh, &point_data, &cell_data).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), bytes);
    assert_identical(&read_vtu_file(&path).unwrap(), &mesh, &point_data, &cell_data);
}

#[test]
fn round_trip_without_fields_and_of_a_larger_patch() {
    let mesh = patch(30, 20, Pattern::JitteredTriangles { amplitude: 0.2, seed: 7 }, flat(2.0, 1.0));
    let mut bytes = Vec::new();
    write_vtu(&mut bytes, &mesh, &[], &[]).unwrap();
    let read = read_vtu(&bytes[..]).unwrap();
    assert_identical(&read, &mesh, &[], &[]);
}

#[test]
fn written_files_are_inline_uncompressed_base64_with_vtk_cell_types() {
    let mesh = mixed_mesh();
    let (point_data, cell_data) = mixed_fields(&mesh);
    let mut bytes = Vec::new();
    write_vtu(&mut bytes, &mesh, &point_data, &cell_data).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    assert!(text.starts_with("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\""));
    assert!(text.contains("byte_order=\"LittleEndian\"") && text.contains("header_type=\"UInt64\""));
    assert!(!text.contains("compressor") && !text.contains("AppendedData") && !text.contains("ascii"));
    assert!(text.contains("NumberOfPoints=\"7\"") && text.contains("NumberOfCells=\"3\""));
    assert!(
        text.contains("<DataArray type=\"Float64\" Name=\"u\" NumberOfComponents=\"3\" format=\"binary\"")
    );
    // Cell types 9, 5, 5 as UInt8: the 8-byte size header (3) then the bytes.
    let types = [3u8, 0, 0, 0, 0, 0, 0, 0, 9, 5, 5];
    assert!(text.contains(&format!(">{}<", base64(&types))), "{text}");
}

/// Standard base64 with padding (enough for the test above).
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().enumerate().fold(0u32, |n, (i, &b)| n | (u32::from(b) << (16 - 8 * i)));
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[test]
fn a_wrong_field_length_is_an_error_and_writes_nothing() {
    let mesh = mixed_mesh();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.vtu");
    let short = Field::new("u", 3, vec![0.0; 3 * 7 - 1]);
    let e = write_vtu_file(&path, &mesh, &[short], &[]).unwrap_err();
    assert!(
        matches!(e.kind(), VtuErrorKind::WrongFieldLength { name, expected: 21, found: 20 } if name == "u"),
        "{e:?}"
    );
    assert_eq!(e.to_string(), format!("{}: field \"u\" has 20 values, expected 21", path.display()));
    assert!(!path.exists());

    // A cell field must have one entry per face, not per point.
    let e = write_vtu(Vec::new(), &mesh, &[], &[Field::scalars("c", vec![0.0; 7])]).unwrap_err();
    assert!(matches!(e.kind(), VtuErrorKind::WrongFieldLength { expected: 3, found: 7, .. }), "{e:?}");
}

#[test]
fn unsupported_components_and_bad_names_are_errors() {
    let mesh = mixed_mesh();
    let e = write_vtu(Vec::new(), &mesh, &[Field::new("q", 4, vec![0.0; 28])], &[]).unwrap_err();
    assert!(matches!(e.kind(), VtuErrorKind::UnsupportedComponents { components: 4, .. }), "{e:?}");
    let e = write_vtu(Vec::new(), &mesh, &[Field::new("z", 0, vec![])], &[]).unwrap_err();
    assert!(matches!(e.kind(), VtuErrorKind::UnsupportedComponents { components: 0, .. }), "{e:?}");
    let e = write_vtu(Vec::new(), &mesh, &[], &[Field::scalars("", vec![0.0; 3])]).unwrap_err();
    assert_eq!(e.to_string(), "cell field name \"\" is empty");
    let twice = [Field::scalars("p", vec![0.0; 7]), Field::scalars("p", vec![1.0; 7])];
    let e = write_vtu(Vec::new(), &mesh, &twice, &[]).unwrap_err();
    assert_eq!(e.to_string(), "point field name \"p\" is used twice");
    // The same name on points and on cells is fine, and so are XML special characters.
    let odd = "a<b & \"c\" 'd'>";
    let point_data = [Field::scalars("p", vec![0.0; 7]), Field::scalars(odd, vec![2.0; 7])];
    let mut bytes = Vec::new();
    write_vtu(&mut bytes, &mesh, &point_data, &[Field::scalars("p", vec![1.0; 3])]).unwrap();
    let read = read_vtu(&bytes[..]).unwrap();
    assert_eq!(read.point_field(odd).unwrap().values, [2.0; 7]);
    assert_eq!(read.cell_field("p").unwrap().values, [1.0; 3]);
}

/// An ASCII VTU file with the given points (x y z per point), cells (type and
/// nodes) and extra XML inside the piece.
fn ascii_vtu(points: &[[f64; 3]], cells: &[(u8, &[usize])], extra: &str) -> String {
    let join = |v: Vec<String>| v.join(" ");
    let coords = join(points.iter().flatten().map(|x| x.to_string()).collect());
    let connectivity = join(cells.iter().flat_map(|c| c.1).map(|n| n.to_string()).collect());
    let mut end = 0;
    let offsets = join(
        cells
            .iter()
            .map(|c| {
                end += c.1.len();
                end.to_string()
            })
            .collect(),
    );
    let types = join(cells.iter().map(|c| c.0.to_string()).collect());
    let mut s = String::new();
    write!(
        s,
        r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <UnstructuredGrid>
    <Piece NumberOfPoints="{}" NumberOfCells="{}">
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">{coords}</DataArray>
      </Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="ascii">{connectivity}</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">{offsets}</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">{types}</DataArray>
      </Cells>
      {extra}
    </Piece>
  </UnstructuredGrid>
</VTKFile>
"#,
        points.len(),
        cells.len()
    )
    .unwrap();
    s
}

const SQUARE: [[f64; 3]; 5] =
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn write_temp(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_tetra_cell_is_an_error_naming_the_cell() {
    let dir = tempfile::tempdir().unwrap();
    let text = ascii_vtu(&SQUARE, &[(5, &[0, 1, 2]), (10, &[0, 1, 2, 4]), (9, &[0, 1, 2, 3])], "");
    let path = write_temp(&dir, "tet.vtu", &text);
    let e = read_vtu_file(&path).unwrap_err();
    assert!(matches!(e.kind(), VtuErrorKind::UnsupportedCell { cell: 1, vtk_type: 10 }), "{e:?}");
    assert_eq!(e.path(), Some(path.as_path()));
    assert_eq!(
        e.to_string(),
        format!(
            "{}: cell 1 is a tetrahedron (VTK type 10); only triangles (5, 22, 34) and quads (9, 23, 28) are \
             read, vertices and lines are skipped",
            path.display()
        )
    );
    let text = ascii_vtu(&SQUARE, &[(24, &[0, 1, 2, 3, 4, 0, 1, 2, 3, 4])], "");
    let e = read_vtu(text.as_bytes()).unwrap_err();
    assert!(e.to_string().starts_with("cell 0 is a quadratic tetrahedron (VTK type 24)"), "{e}");
    // A second-order face listing the wrong number of points.
    let text = ascii_vtu(&SQUARE, &[(22, &[0, 1, 2, 3, 4])], "");
    let e = read_vtu(text.as_bytes()).unwrap_err();
    assert!(e.to_string().contains("cell 0 is a quadratic triangle but lists 5 points"), "{e}");
}

#[test]
fn vertex_and_line_cells_are_skipped_with_their_cell_data() {
    let cells: [(u8, &[usize]); 5] =
        [(1, &[4]), (5, &[0, 1, 2]), (3, &[2, 4]), (4, &[0, 4, 3]), (9, &[0, 2, 3, 4])];
    let data = r#"<PointData><DataArray type="Int32" Name="id" format="ascii">10 11 12 13 14</DataArray></PointData>
      <CellData><DataArray type="Float32" Name="c" NumberOfComponents="2" format="ascii">
        0 0.5 1 1.5 2 2.5 3 3.5 4 4.5</DataArray></CellData>"#;
    let read = read_vtu(ascii_vtu(&SQUARE, &cells, data).as_bytes()).unwrap();
    assert_eq!(read.mesh.faces(), [Face::Tri3([0, 1, 2]), Face::Quad4([0, 2, 3, 4])]);
    assert_eq!(read.mesh.n_points(), 5);
    assert_eq!(read.point_field("id").unwrap().values, [10.0, 11.0, 12.0, 13.0, 14.0]);
    let c = read.cell_field("c").unwrap();
    assert_eq!((c.components, &c.values[..]), (2, &[1.0, 1.5, 4.0, 4.5][..]));
}

#[test]
fn mesh_errors_name_the_cell_of_the_file() {
    // Cell 2 (face 1, after a skipped vertex cell) repeats node 1.
    let cells: [(u8, &[usize]); 3] = [(5, &[0, 1, 2]), (1, &[4]), (5, &[1, 1, 3])];
    let e = read_vtu(ascii_vtu(&SQUARE, &cells, "").as_bytes()).unwrap_err();
    let VtuErrorKind::InvalidMesh(problem) = e.kind() else { panic!("{e:?}") };
    assert_eq!(problem.element(), Some(2));
    assert_eq!(e.to_string(), "invalid mesh: cell 2 is degenerate: node 1 appears twice");
    // Cell 1 refers to point 9 of 5.
    let cells: [(u8, &[usize]); 2] = [(5, &[0, 1, 2]), (5, &[0, 9, 2])];
    let e = read_vtu(ascii_vtu(&SQUARE, &cells, "").as_bytes()).unwrap_err();
    assert!(
        matches!(
            e.kind(),
            VtuErrorKind::InvalidMesh(MeshError::IndexOutOfRange { element: 1, index: 9, .. })
        ),
        "{e:?}"
    );
    // Cell 3 (face 1) has zero area: points 0, 1, 2 are on a line.
    let line_points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let cells: [(u8, &[usize]); 4] = [(5, &[0, 1, 3]), (3, &[0, 1]), (1, &[0]), (5, &[0, 1, 2])];
    let e = read_vtu(ascii_vtu(&line_points, &cells, "").as_bytes()).unwrap_err();
    assert!(matches!(e.kind(), VtuErrorKind::InvalidMesh(MeshError::ZeroArea { face: 3 })), "{e:?}");
}

#[test]
fn a_file_without_faces_is_an_error() {
    let cells: [(u8, &[usize]); 2] = [(1, &[0]), (3, &[0, 1])];
    let e = read_vtu(ascii_vtu(&SQUARE, &cells, "").as_bytes()).unwrap_err();
    assert!(matches!(e.kind(), VtuErrorKind::NoCells), "{e:?}");
    assert_eq!(e.to_string(), "no triangle or quad cells in the file");
}

#[test]
fn a_missing_file_names_the_path() {
    let path = Path::new("no/such/dir/result.vtu");
    let e = read_vtu_file(path).unwrap_err();
    assert_eq!(e.io_kind(), Some(std::io::ErrorKind::NotFound));
    assert_eq!(e.path(), Some(path));
    let text = e.to_string();
    assert!(text.starts_with("no/such/dir/result.vtu: cannot read the file: no such file"), "{text}");

    let mesh = mixed_mesh();
    let e = write_vtu_file(path, &mesh, &[], &[]).unwrap_err();
    assert!(e.to_string().starts_with("no/such/dir/result.vtu: cannot write the file: "), "{e}");
}

#[test]
fn other_files_are_errors_not_panics() {
    let mesh = mixed_mesh();
    let (point_data, cell_data) = mixed_fields(&mesh);
    let mut good = Vec::new();
    write_vtu(&mut good, &mesh, &point_data, &cell_data).unwrap();
    let good = String::from_utf8(good).unwrap();

    let e = read_vtu(&b"solid nothing\n"[..]).unwrap_err();
    assert!(matches!(e.kind(), VtuErrorKind::Parse { .. }), "{e:?}");
    assert_eq!(e.to_string(), "not a readable VTU file: no <VTKFile> element");
    let poly = r#"<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian"><PolyData><Piece NumberOfPoints="0"/></PolyData></VTKFile>"#;
    let e = read_vtu(poly.as_bytes()).unwrap_err();
    assert!(matches!(e.kind(), VtuErrorKind::Unsupported { .. }), "{e:?}");
    assert_eq!(e.to_string(), "a VTK PolyData file, not a serial UnstructuredGrid (.vtu) file");

    // vtkio panicked on these (it sliced and unwrapped); now they are precise errors.
    let no_points = good.replace(&good[good.find("<Points>").unwrap()..good.find("<Cells>").unwrap()], "");
    let e = read_vtu(no_points.as_bytes()).unwrap_err();
    assert_eq!(e.to_string(), "piece 0 has no <Points> array");
    let cells: [(u8, &[usize]); 1] = [(5, &[0, 1, 2])];
    let text = ascii_vtu(&SQUARE, &cells, "");
    let (start, end) = (text.find("<Points>").unwrap(), text.find("</Points>").unwrap());
    let binary =
        r#"<Points><DataArray type="Float64" NumberOfComponents="3" format="binary">AAAA</DataArray>"#;
    let short = format!("{}{binary}{}", &text[..start], &text[end..]);
    let e = read_vtu(short.as_bytes()).unwrap_err();
    assert!(matches!(e.kind(), VtuErrorKind::Malformed { .. }), "{e:?}");
    assert_eq!(
        e.to_string(),
        "piece 0, the points array (15 Float64 values): needs 4 more bytes but at most 3 are left in the data"
    );

    // Every truncation, and a corrupted base64 byte in every position of the
    // first kilobyte: an error or (rarely) a different mesh, never a panic that
    // escapes. One line, no final period.
    let check = |text: &[u8]| {
        if let Err(e) = read_vtu(text) {
            let message = e.to_string();
            assert!(!message.contains('\n') && !message.ends_with('.'), "{message}");
        }
    };
    for cut in (0..good.len()).step_by(7) {
        check(&good.as_bytes()[..cut]);
    }
    for at in (0..good.len().min(1024)).step_by(3) {
        let mut bad = good.clone().into_bytes();
        bad[at] = if bad[at] == b'A' { b'#' } else { b'A' };
        check(&bad);
    }
}

#[test]
fn a_field_with_missing_data_is_an_error_not_dropped() {
    let mesh = mixed_mesh();
    let (point_data, _) = mixed_fields(&mesh);
    let mut bytes = Vec::new();
    write_vtu(&mut bytes, &mesh, &point_data[..1], &[]).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    // Cut the base64 data of field "p" short (vtkio skipped such arrays silently).
    let start = text.find("Name=\"p\"").unwrap();
    let data = start + text[start..].find('>').unwrap() + 1;
    let bad = format!("{}{}", &text[..data + 8], &text[data + 20..]);
    let e = read_vtu(bad.as_bytes()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "piece 0, point data array \"p\" (7 Float64 values): needs 56 more bytes but at most 49 are left in the data"
    );
}

/// The mesh of `tests/data/vtu/make_fixtures.py`: cells tri, quad, vertex, line,
/// tri; the vertex and line are skipped.
fn fixture_expected() -> (Vec<[f64; 3]>, Vec<Face>, Vec<Field>, Vec<Field>) {
    let points = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.5],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.25],
        [2.0, 1.0, -0.5],
        [3.0, 3.0, 3.0],
    ];
    let faces = vec![Face::Tri3([0, 1, 4]), Face::Quad4([1, 2, 5, 4]), Face::Tri3([0, 4, 3])];
    let n = points.len();
    let point_data = vec![
        Field::scalars("p", (0..n).map(|i| 0.5 * i as f64).collect()),
        Field::new("u", 3, (0..n).flat_map(|i| [i as f64, 0.0 - i as f64, 0.25 * i as f64]).collect()),
        Field::scalars("id", (0..n).map(|i| 10.0 + i as f64).collect()),
    ];
    let kept = [0usize, 1, 4];
    let cell_data = vec![
        Field::scalars("c", vec![1.5, 2.5, 4.25]),
        Field::new("g", 2, kept.iter().flat_map(|&i| [i as f64, 2.0 * i as f64]).collect()),
    ];
    (points, faces, point_data, cell_data)
}

/// Reads every `.vtu` file of `SEAM_VTU_IN` (set by the pytest file, which writes
/// them with the installed meshio and VTK), or else of `tests/data/vtu`.
#[test]
fn files_written_by_meshio_and_vtk_are_read() {
    let dir = std::env::var_os("SEAM_VTU_IN").map(PathBuf::from).unwrap_or_else(data_dir);
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "vtu"))
        .collect();
    paths.sort();
    let names: Vec<String> =
        paths.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    for required in ["meshio_ascii.vtu", "meshio_binary.vtu"] {
        assert!(names.iter().any(|n| n == required), "{required} missing in {}", dir.display());
    }
    if std::env::var_os("SEAM_VTU_IN").is_none() {
        assert_eq!(names.len(), 4, "{names:?}");
    }
    let (points, faces, point_data, cell_data) = fixture_expected();
    for path in &paths {
        let read = read_vtu_file(path).unwrap_or_else(|e| panic!("{e}"));
        let mesh = SurfaceMesh::new(points.clone(), faces.clone()).unwrap();
        assert_identical(&read, &mesh, &point_data, &cell_data);
        eprintln!("read {}", path.display());
    }
}

/// Writes VTU files and `expected.json` (what they hold) into `SEAM_VTU_OUT`, or a
/// temporary directory, for `tests/python/test_vtu_meshio.py`.
#[test]
fn write_fixtures_for_python() {
    let temp = tempfile::tempdir().unwrap();
    let dir =
        std::env::var_os("SEAM_VTU_OUT").map(PathBuf::from).unwrap_or_else(|| temp.path().to_path_buf());
    std::fs::create_dir_all(&dir).unwrap();
    let mixed = mixed_mesh();
    let (point_data, cell_data) = mixed_fields(&mixed);
    let patch = patch(12, 9, Pattern::JitteredQuads { amplitude: 0.2, seed: 3 }, flat(1.0, 0.75));
    let patch_data =
        [Field::vectors("x", patch.points()), Field::scalars("i", wavy(patch.n_points(), 1, 0.5))];
    let patch_cells = [Field::scalars("one", vec![1.0; patch.n_faces()])];
    let files = [
        ("mixed.vtu", &mixed, &point_data[..], &cell_data[..]),
        ("patch.vtu", &patch, &patch_data[..], &patch_cells[..]),
        ("bare.vtu", &mixed, &[][..], &[][..]),
    ];
    let mut json = String::from("{\n");
    for (i, (name, mesh, point_data, cell_data)) in files.iter().enumerate() {
        write_vtu_file(dir.join(name), mesh, point_data, cell_data).unwrap();
        let numbers =
            |v: &mut dyn Iterator<Item = f64>| v.map(|x| format!("{x:?}")).collect::<Vec<_>>().join(", ");
        let fields = |fields: &[Field]| {
            let entries: Vec<String> = fields
                .iter()
                .map(|f| {
                    let values = numbers(&mut f.values.iter().copied());
                    format!("{:?}: {{\"components\": {}, \"values\": [{values}]}}", f.name, f.components)
                })
                .collect();
            format!("{{{}}}", entries.join(", "))
        };
        let cells: Vec<String> = mesh
            .faces()
            .iter()
            .map(|f| {
                let kind = if f.len() == 3 { "triangle" } else { "quad" };
                let nodes: Vec<String> = f.nodes().iter().map(usize::to_string).collect();
                format!("[\"{kind}\", [{}]]", nodes.join(", "))
            })
            .collect();
        writeln!(
            json,
            "  {name:?}: {{\n    \"points\": [{}],\n    \"cells\": [{}],\n    \"point_data\": {},\n    \"cell_data\": {}\n  }}{}",
            numbers(&mut mesh.points().iter().flatten().copied()),
            cells.join(", "),
            fields(point_data),
            fields(cell_data),
            if i + 1 < files.len() { "," } else { "" }
        )
        .unwrap();
        // What we hand to Python must read back identically here too.
        let read = read_vtu_file(dir.join(name)).unwrap();
        assert_identical(&read, mesh, point_data, cell_data);
    }
    json.push_str("}\n");
    std::fs::write(dir.join("expected.json"), json).unwrap();
}

/// One positively oriented cell of each volume type (Gmsh node order), with a
/// point field and a cell field, for `tests/python/test_vtu_meshio.py` (written to
/// `$SEAM_VTU_OUT` when set).
#[test]
fn write_volume_fixture_for_python() {
    use seam::{Cell, VolumeMesh};
    let temp = tempfile::tempdir().unwrap();
    let dir =
        std::env::var_os("SEAM_VTU_OUT").map(PathBuf::from).unwrap_or_else(|| temp.path().to_path_buf());
    std::fs::create_dir_all(&dir).unwrap();
    let mut points = Vec::new();
    let mut cells = Vec::new();
    let mut add = |corners: &[[f64; 3]], dx: f64, make: fn(Vec<usize>) -> Cell| {
        let first = points.len();
        points.extend(corners.iter().map(|p| [p[0] + dx, p[1], p[2]]));
        cells.push(make((first..first + corners.len()).collect()));
    };
    add(&[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]], 0.0, |n| {
        Cell::Tet4([n[0], n[1], n[2], n[3]])
    });
    add(
        &[
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0., 0., 1.],
            [1., 0., 1.],
            [1., 1., 1.],
            [0., 1., 1.],
        ],
        2.0,
        |n| Cell::Hex8([n[0], n[1], n[2], n[3], n[4], n[5], n[6], n[7]]),
    );
    add(&[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.], [1., 0., 1.], [0., 1., 1.]], 4.0, |n| {
        Cell::Prism6([n[0], n[1], n[2], n[3], n[4], n[5]])
    });
    add(&[[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [0.5, 0.5, 1.]], 6.0, |n| {
        Cell::Pyramid5([n[0], n[1], n[2], n[3], n[4]])
    });
    let mesh = VolumeMesh::new(points, cells).unwrap();
    let z: Vec<f64> = mesh.points().iter().map(|p| p[2]).collect();
    let id = Field::scalars("cell_id", vec![0.0, 1.0, 2.0, 3.0]);
    seam_io::write_volume_vtu_file(dir.join("volume.vtu"), &mesh, &[Field::scalars("z", z)], &[id]).unwrap();
    // A wrong cell-field length is an error, and no file is created.
    let bad =
        seam_io::write_volume_vtu_file(dir.join("bad.vtu"), &mesh, &[], &[Field::scalars("c", vec![1.0])]);
    assert!(bad.is_err() && !dir.join("bad.vtu").exists());
}

// ---------------------------------------------------------------------------
// Every encoding the reader supports, written by a small encoder here.

/// The fixture mesh of `make_fixtures.py` (cells tri, quad, vertex, line, tri)
/// as (name, VTK type, components, values) per array: points, cells, point
/// data, cell data, in several value types.
type TestArray = (&'static str, &'static str, usize, Vec<f64>);

fn fixture_arrays() -> [Vec<TestArray>; 4] {
    let (points, _, point_data, _) = fixture_expected();
    let n = points.len() as f64;
    let points = vec![("Points", "Float64", 3, points.iter().flatten().copied().collect())];
    let cells = vec![
        ("connectivity", "Int32", 1, vec![0., 1., 4., 1., 2., 5., 4., 6., 3., 6., 0., 4., 3.]),
        ("offsets", "Int64", 1, vec![3., 7., 8., 10., 13.]),
        ("types", "UInt8", 1, vec![5., 9., 1., 3., 5.]),
    ];
    let point_data = vec![
        ("p", "Float32", 1, point_data[0].values.clone()),
        ("u", "Float64", 3, point_data[1].values.clone()),
        ("id", "Int16", 1, (0..n as usize).map(|i| 10.0 + i as f64).collect()),
    ];
    let cell_data = vec![
        ("c", "Float64", 1, vec![1.5, 2.5, -1.0, -2.0, 4.25]),
        ("g", "UInt16", 2, (0..5).flat_map(|i| [i as f64, 2.0 * i as f64]).collect()),
    ];
    [points, cells, point_data, cell_data]
}

#[derive(Clone, Copy, Debug)]
enum TestFormat {
    Ascii,
    Binary,
    AppendedRaw,
    AppendedBase64,
}

/// One encoding: format, compressor (`"zlib"`, `"lz4"`, `"lzma"`), header bytes,
/// byte order, block size before compression.
#[derive(Clone, Copy, Debug)]
struct TestEncoding {
    format: TestFormat,
    compressor: Option<&'static str>,
    header: usize,
    big_endian: bool,
    block: usize,
}

impl TestEncoding {
    fn word(&self, value: usize) -> Vec<u8> {
        match (self.header, self.big_endian) {
            (4, false) => (value as u32).to_le_bytes().to_vec(),
            (4, true) => (value as u32).to_be_bytes().to_vec(),
            (_, false) => (value as u64).to_le_bytes().to_vec(),
            (_, true) => (value as u64).to_be_bytes().to_vec(),
        }
    }

    fn value_bytes(&self, ty: &str, values: &[f64]) -> Vec<u8> {
        let mut out = Vec::new();
        for &v in values {
            let mut b = match ty {
                "Float32" => (v as f32).to_le_bytes().to_vec(),
                "Float64" => v.to_le_bytes().to_vec(),
                "Int16" => (v as i16).to_le_bytes().to_vec(),
                "UInt16" => (v as u16).to_le_bytes().to_vec(),
                "Int32" => (v as i32).to_le_bytes().to_vec(),
                "Int64" => (v as i64).to_le_bytes().to_vec(),
                "UInt8" => vec![v as u8],
                other => panic!("no type {other}"),
            };
            if self.big_endian {
                b.reverse();
            }
            out.extend(b);
        }
        out
    }

    /// The array's binary form as chunks, each base64-encoded on its own: the
    /// size header and data together (uncompressed), or the compression header,
    /// then the blocks.
    fn binary_chunks(&self, data: &[u8]) -> Vec<Vec<u8>> {
        use std::io::Write;
        let Some(compressor) = self.compressor else {
            let mut chunk = self.word(data.len());
            chunk.extend_from_slice(data);
            return vec![chunk];
        };
        let blocks: Vec<Vec<u8>> = data
            .chunks(self.block)
            .map(|block| match compressor {
                "zlib" => {
                    let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
                    e.write_all(block).unwrap();
                    e.finish().unwrap()
                }
                "lz4" => lz4_flex::block::compress(block),
                _ => {
                    let mut e = xz2::write::XzEncoder::new(Vec::new(), 1);
                    e.write_all(block).unwrap();
                    e.finish().unwrap()
                }
            })
            .collect();
        let last = data.len() % self.block; // 0 when the last block is full, as VTK writes
        let mut header = [self.word(blocks.len()), self.word(self.block), self.word(last)].concat();
        for b in &blocks {
            header.extend(self.word(b.len()));
        }
        vec![header, blocks.concat()]
    }
}

fn base64_std(bytes: &[u8]) -> String {
    use base64::Engine as _;
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

fn encode_fixture(enc: TestEncoding) -> Vec<u8> {
    let order = if enc.big_endian { "BigEndian" } else { "LittleEndian" };
    let header = if enc.header == 8 { "UInt64" } else { "UInt32" };
    let compressor = match enc.compressor {
        Some("zlib") => r#" compressor="vtkZLibDataCompressor""#,
        Some("lz4") => r#" compressor="vtkLZ4DataCompressor""#,
        Some(_) => r#" compressor="vtkLZMADataCompressor""#,
        None => "",
    };
    let mut xml = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"{order}\" \
         header_type=\"{header}\"{compressor}>\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"7\" NumberOfCells=\"5\">\n"
    );
    let mut appended: Vec<u8> = Vec::new();
    let [points, cells, point_data, cell_data] = fixture_arrays();
    for (section, arrays) in
        [("Points", points), ("Cells", cells), ("PointData", point_data), ("CellData", cell_data)]
    {
        xml.push_str(&format!("<{section}>\n"));
        for (name, ty, components, values) in arrays {
            let head =
                format!("<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{components}\"");
            let chunks = enc.binary_chunks(&enc.value_bytes(ty, &values));
            match enc.format {
                TestFormat::Ascii => {
                    let text: Vec<String> = values.iter().map(f64::to_string).collect();
                    xml.push_str(&format!("{head} format=\"ascii\">\n{}\n</DataArray>\n", text.join(" ")));
                }
                TestFormat::Binary => {
                    let text: String = chunks.iter().map(|c| base64_std(c)).collect();
                    xml.push_str(&format!("{head} format=\"binary\">\n  {text}\n</DataArray>\n"));
                }
                TestFormat::AppendedRaw | TestFormat::AppendedBase64 => {
                    xml.push_str(&format!("{head} format=\"appended\" offset=\"{}\"/>\n", appended.len()));
                    for chunk in chunks {
                        match enc.format {
                            TestFormat::AppendedRaw => appended.extend(chunk),
                            _ => appended.extend(base64_std(&chunk).into_bytes()),
                        }
                    }
                }
            }
        }
        xml.push_str(&format!("</{section}>\n"));
    }
    xml.push_str("</Piece>\n</UnstructuredGrid>\n");
    let mut bytes = xml.into_bytes();
    if let TestFormat::AppendedRaw | TestFormat::AppendedBase64 = enc.format {
        let encoding = if matches!(enc.format, TestFormat::AppendedRaw) { "raw" } else { "base64" };
        bytes.extend(format!("<AppendedData encoding=\"{encoding}\">\n   _").into_bytes());
        bytes.extend(appended);
        bytes.extend(b"\n</AppendedData>\n");
    }
    bytes.extend(b"</VTKFile>\n");
    bytes
}

#[test]
fn every_encoding_of_every_value_type_reads_the_same() {
    let (points, faces, point_data, cell_data) = fixture_expected();
    let mesh = SurfaceMesh::new(points, faces).unwrap();
    let mut n = 0;
    for format in [TestFormat::Ascii, TestFormat::Binary, TestFormat::AppendedRaw, TestFormat::AppendedBase64]
    {
        for compressor in [None, Some("zlib"), Some("lz4"), Some("lzma")] {
            for header in [4, 8] {
                for big_endian in [false, true] {
                    if matches!(format, TestFormat::Ascii)
                        && (compressor.is_some() || header == 8 || big_endian)
                    {
                        continue;
                    }
                    let enc = TestEncoding { format, compressor, header, big_endian, block: 8 };
                    let bytes = encode_fixture(enc);
                    let read = read_vtu(&bytes[..]).unwrap_or_else(|e| panic!("{enc:?}: {e}"));
                    assert_identical(&read, &mesh, &point_data, &cell_data);
                    n += 1;
                }
            }
        }
    }
    assert_eq!(n, 49);
}

// ---------------------------------------------------------------------------
// Hostile input: the committed fixtures changed as a corrupt or malicious file
// can be. Each must be a one-line error (never a panic or an abort), in memory
// bounded by the file, not by the sizes it claims.

const FIXTURES: [&str; 4] =
    ["meshio_ascii.vtu", "meshio_binary.vtu", "vtk_appended_raw_zlib.vtu", "vtk_binary_lz4.vtu"];

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(data_dir().join(name)).unwrap()
}

fn find(hay: &[u8], needle: &[u8]) -> usize {
    hay.windows(needle.len())
        .position(|w| w == needle)
        .unwrap_or_else(|| panic!("{:?} not found", String::from_utf8_lossy(needle)))
}

/// `bytes` with the first `from` replaced by `to`.
fn replace(bytes: &[u8], from: &str, to: &str) -> Vec<u8> {
    let at = find(bytes, from.as_bytes());
    [&bytes[..at], to.as_bytes(), &bytes[at + from.len()..]].concat()
}

/// The range of the (trimmed) text of the inline data array `name`.
fn array_text(bytes: &[u8], name: &str) -> std::ops::Range<usize> {
    let at = find(bytes, format!("Name=\"{name}\"").as_bytes());
    let start = at + find(&bytes[at..], b">") + 1;
    let start = start + bytes[start..].iter().take_while(|c| c.is_ascii_whitespace()).count();
    let end = start + bytes[start..].iter().take_while(|&&c| c != b'<' && !c.is_ascii_whitespace()).count();
    start..end
}

/// `bytes` with the text of the inline data array `name` replaced.
fn replace_array(bytes: &[u8], name: &str, text: &str) -> Vec<u8> {
    let range = array_text(bytes, name);
    [&bytes[..range.start], text.as_bytes(), &bytes[range.end..]].concat()
}

fn words(bytes: &[u8], h: usize) -> Vec<u64> {
    bytes
        .chunks(h)
        .map(|c| {
            if h == 4 {
                u32::from_le_bytes(c.try_into().unwrap()).into()
            } else {
                u64::from_le_bytes(c.try_into().unwrap())
            }
        })
        .collect()
}

fn to_bytes(words: &[u64], h: usize) -> Vec<u8> {
    words
        .iter()
        .flat_map(|&w| if h == 4 { (w as u32).to_le_bytes().to_vec() } else { w.to_le_bytes().to_vec() })
        .collect()
}

/// `bytes` with the compression header (little-endian words of `h` bytes,
/// base64-encoded on its own) of the inline data array `name` changed by `edit`.
fn edit_header(bytes: &[u8], name: &str, h: usize, edit: impl FnOnce(&mut Vec<u64>)) -> Vec<u8> {
    use base64::Engine as _;
    let b64 = base64::engine::general_purpose::STANDARD;
    let range = array_text(bytes, name);
    let text = &bytes[range.clone()];
    let nb = words(&b64.decode(&text[..4 * h]).unwrap()[..h], h)[0] as usize;
    let chars = ((3 + nb) * h).div_ceil(3) * 4;
    let mut header = words(&b64.decode(&text[..chars]).unwrap(), h);
    edit(&mut header);
    let new = base64_std(&to_bytes(&header, h));
    [&bytes[..range.start], new.as_bytes(), &bytes[range.start + chars..]].concat()
}

/// `n` zero bytes, compressed.
fn zeros_lz4(n: usize) -> Vec<u8> {
    lz4_flex::block::compress(&vec![0; n])
}

fn zlib(data: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    e.write_all(data).unwrap();
    e.finish().unwrap()
}

fn xz(data: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut e = xz2::write::XzEncoder::new(Vec::new(), 6);
    e.write_all(data).unwrap();
    e.finish().unwrap()
}

/// An `.xz` stream whose block header asks for a 4 GiB dictionary (the block
/// header CRC32 recomputed).
fn xz_with_huge_dictionary(data: &[u8]) -> Vec<u8> {
    let mut stream = xz(data);
    let size = (usize::from(stream[12]) + 1) * 4; // the block header follows the 12-byte stream header
    let header = 12..12 + size;
    let filter = 12 + find(&stream[header.clone()], &[0x21, 0x01]); // LZMA2, 1 property byte
    stream[filter + 2] = 40; // dictionary size 4 GiB − 1
    let mut crc = flate2::Crc::new();
    crc.update(&stream[12..header.end - 4]);
    stream[header.end - 4..header.end].copy_from_slice(&crc.sum().to_le_bytes());
    stream
}

/// A compressed inline array: its header (one block) and the block, base64.
fn one_block(h: usize, size: u64, block: &[u8]) -> String {
    format!("{}{}", base64_std(&to_bytes(&[1, size, size, block.len() as u64], h)), base64_std(block))
}

/// A file, what it is, and words its error message must contain.
struct Hostile {
    name: &'static str,
    bytes: Vec<u8>,
    message: &'static [&'static str],
}

fn hostile_files() -> Vec<Hostile> {
    let ascii = fixture("meshio_ascii.vtu");
    let zlib_file = fixture("meshio_binary.vtu");
    let raw = fixture("vtk_appended_raw_zlib.vtu");
    let lz4 = fixture("vtk_binary_lz4.vtu");
    let lzma = replace(&lz4, "vtkLZ4DataCompressor", "vtkLZMADataCompressor");
    let tb = 7_696_581_394_416u64; // 7.7 TB: 320 690 891 434 points × 24 bytes
    let h = |name, bytes, message| Hostile { name, bytes, message };
    vec![
        // Finding 1: an LZ4 block header claiming terabytes (vtkio aborted).
        h(
            "lz4_block_size_7_7_tb",
            edit_header(&lz4, "p", 8, |w| w[1] = 7_696_581_394_432),
            &["point data array \"p\"", "declares 53876069761024 bytes (7 blocks of 7696581394432, the last of 0)", "expected 56"],
        ),
        h("lz4_block_count_huge", edit_header(&lz4, "p", 8, |w| w[0] = 1 << 40), &["claims 1099511627776 blocks"]),
        h(
            "lz4_compressed_size_huge",
            edit_header(&lz4, "p", 8, |w| w[3] = 1 << 62),
            &["\"p\"", "compressed blocks take 4611686018427387958 bytes but at most 69 are left"],
        ),
        h(
            "lz4_last_block_larger_than_block",
            edit_header(&lz4, "p", 8, |w| w[2] = 9),
            &["\"p\"", "last block size 9 exceeds the block size 8"],
        ),
        h(
            "lz4_points_claim_7_7_tb",
            replace_array(
                &replace(&lz4, "NumberOfPoints=\"7\"", "NumberOfPoints=\"320690891434\""),
                "Points",
                &one_block(8, tb, &zeros_lz4(1 << 20)),
            ),
            &["the points array", "block 0 decompresses to 1048576 bytes, expected 7696581394416"],
        ),
        h(
            "zlib_points_claim_4_gb",
            replace_array(
                &replace(&zlib_file, "NumberOfPoints=\"7\"", "NumberOfPoints=\"178956970\""),
                "Points",
                &one_block(4, 4_294_967_280, &zlib(&vec![0; 1 << 20])),
            ),
            &["the points array", "block 0 decompresses to 1048576 bytes, expected 4294967280"],
        ),
        h(
            "lzma_points_claim_7_7_tb",
            replace_array(
                &replace(&lzma, "NumberOfPoints=\"7\"", "NumberOfPoints=\"320690891434\""),
                "Points",
                &one_block(8, tb, &xz(&vec![0; 1 << 20])),
            ),
            &["the points array", "block 0 decompresses to 1048576 bytes, expected 7696581394416"],
        ),
        h(
            "lzma_dictionary_4_gib",
            replace_array(&lzma, "Points", &one_block(8, 168, &xz_with_huge_dictionary(&[0; 168]))),
            &["the points array", "block 0: bad LZMA data"],
        ),
        // Finding 2: one flipped base64 character in the header of an offsets array
        // (`AQAA` → `AQAI`: 524 289 blocks; vtkio took 16.8 GB for 35 s).
        h(
            "zlib_offsets_header_one_flipped_character",
            {
                let range = array_text(&zlib_file, "offsets");
                let mut bytes = zlib_file.clone();
                assert_eq!(&bytes[range.start..range.start + 4], b"AQAA");
                bytes[range.start + 3] = b'I';
                bytes
            },
            &["piece 0, the offsets array", "claims 524289 blocks"],
        ),
        // The same in the uncompressed UInt64 size header of a file seam wrote
        // (`GAAAAAAA` → `GAAAAAQA`: 2 147 483 651 offsets).
        h(
            "uncompressed_offsets_header_one_flipped_character",
            {
                let mut bytes = Vec::new();
                let mesh = mixed_mesh();
                write_vtu(&mut bytes, &mesh, &[], &[]).unwrap();
                let range = array_text(&bytes, "offsets");
                assert_eq!(&bytes[range.start..range.start + 8], b"GAAAAAAA");
                bytes[range.start + 6] = b'Q';
                bytes
            },
            &["piece 0, the offsets array", "the size header says 17179869208 bytes, expected 24"],
        ),
        // Finding 3: a binary header that decodes to 7 bytes (a panic in our code).
        h(
            "header_decodes_to_7_bytes",
            br#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64" compressor="vtkZLibDataCompressor"><UnstructuredGrid><Piece NumberOfPoints="1" NumberOfCells="0"><Points><DataArray type="Float64" NumberOfComponents="3" format="binary">AAAAAAAAAA==</DataArray></Points></Piece></UnstructuredGrid></VTKFile>"#.to_vec(),
            &["the points array", "needs 24 more bytes but at most 9 are left"],
        ),
        h(
            "uncompressed_header_decodes_to_7_bytes",
            br#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64"><UnstructuredGrid><Piece NumberOfPoints="1" NumberOfCells="0"><Points><DataArray type="Float64" NumberOfComponents="3" format="binary">AAAAAAAAAA==</DataArray></Points></Piece></UnstructuredGrid></VTKFile>"#.to_vec(),
            &["the points array", "the base64 data ends early"],
        ),
        // Sizes in attributes.
        h(
            "number_of_points_99999999999999_binary",
            replace(&zlib_file, "NumberOfPoints=\"7\"", "NumberOfPoints=\"99999999999999\""),
            &["the points array", "declares 168 bytes", "expected 2399999999999976"],
        ),
        h(
            "number_of_points_99999999999999_ascii",
            replace(&ascii, "NumberOfPoints=\"7\"", "NumberOfPoints=\"99999999999999\""),
            &["the points array", "21 values, expected 299999999999997"],
        ),
        h(
            "number_of_points_99999999999999_raw",
            replace(&raw, "NumberOfPoints=\"7\"", "NumberOfPoints=\"99999999999999\""),
            &["the points array", "declares 168 bytes", "expected 2399999999999976"],
        ),
        h(
            "appended_offset_past_the_end",
            replace(&raw, "offset=\"1091\"", "offset=\"99999999999\""),
            &["the points array", "offset 99999999999 is past the end of the appended data (1976 bytes)"],
        ),
        h(
            "negative_number_of_cells",
            replace(&ascii, "NumberOfCells=\"5\"", "NumberOfCells=\"-5\""),
            &["piece 0: NumberOfCells=\"-5\" is not a count"],
        ),
        h(
            "overflowing_number_of_points",
            replace(&ascii, "NumberOfPoints=\"7\"", "NumberOfPoints=\"18446744073709551616\""),
            &["NumberOfPoints=\"18446744073709551616\" is not a count"],
        ),
        h(
            "overflowing_number_of_components",
            replace(&zlib_file, "Name=\"u\" NumberOfComponents=\"3\"", "Name=\"u\" NumberOfComponents=\"4611686018427387904\""),
            &["point data array \"u\"", "is too many"],
        ),
        h(
            "negative_appended_offset",
            replace(&raw, "offset=\"0\"", "offset=\"-8\""),
            &["point data array \"p\": offset=\"-8\" is not a count"],
        ),
        h(
            "negative_point_index",
            replace(&ascii, "Name=\"connectivity\" format=\"ascii\">\n0\n", "Name=\"connectivity\" format=\"ascii\">\n-1\n"),
            &["the connectivity array", "value 0 is -1, not an index"],
        ),
        h(
            "overflowing_cell_offset",
            replace(&ascii, "\n10\n13\n", "\n10\n99999999999999999999\n"),
            &["the offsets array", "value 4 \"99999999999999999999\" is not a Int64 number"],
        ),
        h(
            "huge_last_cell_offset",
            replace(&ascii, "\n10\n13\n", "\n10\n99999999999999\n"),
            &["the connectivity array", "13 values, expected 99999999999999"],
        ),
        h(
            "decreasing_cell_offsets",
            replace(&ascii, "\n3\n7\n8\n", "\n3\n7\n5\n"),
            &["piece 0, cell 2: offset 5 is less than the previous offset 7"],
        ),
        h(
            "a_million_nested_elements",
            format!(
                "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\"><UnstructuredGrid>{}",
                "<a>".repeat(1_000_000)
            )
            .into_bytes(),
            &["not a readable VTU file: the file ends inside an element"],
        ),
        h(
            "cell_type_300",
            replace(&ascii, "Name=\"types\" format=\"ascii\">\n5\n", "Name=\"types\" format=\"ascii\">\n300\n"),
            &["piece 0, cell 0 has type 300, not a VTK cell type"],
        ),
    ]
}

/// A one-line message without final period, as the crate promises, and short
/// (what it quotes from the file is cut).
fn assert_one_line(message: &str) {
    assert!(!message.contains('\n') && !message.ends_with('.') && !message.is_empty(), "{message:?}");
    assert!(message.len() < 400, "{} characters: {message:?}", message.len());
}

#[test]
fn messages_quote_little_of_the_file() {
    let ascii = fixture("meshio_ascii.vtu");
    let long = "x".repeat(5000);
    let bad = replace(&ascii, "</Cells>", &format!("</{long}>"));
    let e = read_vtu(&bad[..]).unwrap_err().to_string();
    assert!(
        e.starts_with("not a readable VTU file: ill-formed document: expected `</Cells>`, but `</xxx"),
        "{e}"
    );
    assert!(e.ends_with("... (line 65)"), "{e}");
    let bad = replace(&ascii, "Name=\"p\"", &format!("Name=\"p{long}\""));
    let bad = replace(
        &bad,
        "\n3.00000000000e+00\n\n</DataArray>\n<DataArray type=\"Float64\" Name=\"u\"",
        "\n\n</DataArray>\n<DataArray type=\"Float64\" Name=\"u\"",
    );
    let e = read_vtu(&bad[..]).unwrap_err().to_string();
    assert_eq!(
        e,
        format!("piece 0, point data array \"p{}...\" (7 Float64 values): 6 values, expected 7", &long[..39])
    );
    assert_one_line(&e);
}

#[test]
fn hostile_files_are_precise_errors() {
    let mut wrong = Vec::new();
    for file in hostile_files() {
        let e = match read_vtu(&file.bytes[..]) {
            Ok(_) => panic!("{} was read", file.name),
            Err(e) => e.to_string(),
        };
        assert_one_line(&e);
        if let Some(words) = file.message.iter().find(|words| !e.contains(*words)) {
            wrong.push(format!("{}: {e:?} lacks {words:?}", file.name));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The `VmRSS` and `VmHWM` (peak) lines of `/proc/self/status`, in kB.
fn resident_kb() -> (u64, u64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb = |key: &str| {
        let line = status.lines().find_map(|l| l.strip_prefix(key)).unwrap_or("0 kB");
        line.trim().trim_end_matches(" kB").parse().unwrap_or(0)
    };
    (kb("VmRSS:"), kb("VmHWM:"))
}

/// Reads the hostile file named by `SEAM_VTU_HOSTILE` and reports the error and
/// the resident memory before reading and at its peak while reading: the child
/// process of `hostile_files_are_read_in_bounded_memory` (does nothing otherwise).
#[test]
fn hostile_file_child() {
    let Ok(name) = std::env::var("SEAM_VTU_HOSTILE") else { return };
    let file = hostile_files().into_iter().find(|f| f.name == name).unwrap();
    // Resets the peak to the current resident size (Linux ≥ 4.0).
    let _ = std::fs::write("/proc/self/clear_refs", "5");
    let (before, _) = resident_kb();
    let result = read_vtu(&file.bytes[..]);
    let (_, peak) = resident_kb();
    match result {
        // After a newline: libtest has written "test vtu::hostile_file_child ... ".
        Ok(_) => println!("\nread without error"),
        Err(e) => println!("\nerror: {e}"),
    }
    println!("resident: {before} {peak}");
}

/// Each hostile file is read by a child process (this test binary, running
/// `hostile_file_child`) limited to 400 MB of address space: it must report the
/// error and exit normally, not be killed or abort, with a small peak RSS.
#[cfg(target_os = "linux")]
#[test]
fn hostile_files_are_read_in_bounded_memory() {
    let exe = std::env::current_exe().unwrap();
    let mut report = String::new();
    for file in hostile_files() {
        let output = std::process::Command::new("sh")
            .arg("-c")
            .arg(r#"ulimit -v 400000 && exec "$0" "$@""#)
            .arg(&exe)
            .args(["vtu::hostile_file_child", "--exact", "--nocapture", "--test-threads=1"])
            .env("SEAM_VTU_HOSTILE", file.name)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&output.stdout);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(0), "{}: {:?}\n{stdout}\n{stderr}", file.name, output.status);
        let error = stdout.lines().find_map(|l| l.strip_prefix("error: "));
        let error = error.unwrap_or_else(|| panic!("{}: no error reported\n{stdout}", file.name));
        assert!(file.message.iter().all(|w| error.contains(w)), "{}: {error}", file.name);
        let resident = stdout.lines().find_map(|l| l.strip_prefix("resident: ")).unwrap();
        let [before, peak] = [0, 1].map(|i| resident.split(' ').nth(i).unwrap().parse::<u64>().unwrap());
        // Reading takes far less than what the files claim (gigabytes to terabytes):
        // a small multiple of the file size plus twice what their data actually
        // decompresses to (at most 1 MiB).
        let growth = peak.saturating_sub(before);
        let bound = 4 * 1024 + 8 * file.bytes.len() as u64 / 1024;
        assert!(growth < bound, "{}: reading took {growth} kB, more than {bound} kB", file.name);
        writeln!(
            report,
            "{:>42} {:>6} bytes: peak RSS {peak} kB, {growth} kB over the {before} kB before reading",
            file.name,
            file.bytes.len()
        )
        .unwrap();
    }
    eprintln!("{report}");
}

#[test]
fn every_truncation_of_the_fixtures_is_an_error() {
    for name in FIXTURES {
        let bytes = fixture(name);
        let end = bytes.trim_ascii_end().len();
        for cut in 0..end {
            let result = std::panic::catch_unwind(|| read_vtu(&bytes[..cut]));
            match result {
                Ok(Err(e)) => assert_one_line(&e.to_string()),
                Ok(Ok(_)) => panic!("{name} cut to {cut} bytes was read"),
                Err(_) => panic!("{name} cut to {cut} bytes: the reader panicked"),
            }
        }
        assert!(read_vtu(&bytes[..]).is_ok());
    }
}

/// The seed of the mutation test.
const MUTATION_SEED: u64 = 0x005E_A30F_2024;

/// xorshift64*: a small deterministic generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Changes `bytes` at a random place: a random byte or bit, a truncation, a
/// deleted or repeated range, a base64 character (often in a header) or a digit
/// (counts, offsets, numbers) replaced by another, a digit run made huge.
fn mutate(bytes: &mut Vec<u8>, rng: &mut Rng) {
    const B64: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let at = rng.below(bytes.len());
    match rng.below(8) {
        0 => bytes[at] = rng.next() as u8,
        1 => bytes[at] ^= 1 << rng.below(8),
        2 => bytes.truncate(at),
        3 => {
            let end = (at + 1 + rng.below(16)).min(bytes.len());
            bytes.drain(at..end);
        }
        4 => {
            let end = (at + 1 + rng.below(64)).min(bytes.len());
            let copy = bytes[at..end].to_vec();
            bytes.splice(at..at, copy);
        }
        5 => {
            // A base64 character among the first ones of an array (its header).
            let arrays: Vec<usize> =
                bytes.windows(2).enumerate().filter(|(_, w)| w == b"\">").map(|(i, _)| i + 2).collect();
            if let Some(&start) = arrays.get(rng.below(arrays.len())) {
                let i = (start + rng.below(40)).min(bytes.len() - 1);
                if B64.contains(&bytes[i]) {
                    bytes[i] = B64[rng.below(64)];
                }
            }
        }
        6 => {
            if let Some(i) = (at..bytes.len()).find(|&i| bytes[i].is_ascii_digit()) {
                bytes[i] = b'0' + rng.below(10) as u8;
            }
        }
        _ => {
            if let Some(i) = (at..bytes.len()).find(|&i| bytes[i].is_ascii_digit()) {
                let digits = ["9", "99999", "4294967295", "18446744073709551615", "99999999999999999999"];
                bytes.splice(i..i + 1, digits[rng.below(digits.len())].bytes());
            }
        }
    }
}

#[test]
fn random_mutations_of_the_fixtures_are_errors_not_panics() {
    let mut sources: Vec<(String, Vec<u8>)> = FIXTURES.iter().map(|&n| (n.to_string(), fixture(n))).collect();
    let mut ours = Vec::new();
    let mesh = mixed_mesh();
    let (point_data, cell_data) = mixed_fields(&mesh);
    write_vtu(&mut ours, &mesh, &point_data, &cell_data).unwrap();
    sources.push(("written by seam".to_string(), ours));
    let mut rng = Rng(MUTATION_SEED);
    let (mut errors, mut read) = (0, 0);
    for (name, bytes) in &sources {
        for round in 0..2000 {
            let mut bytes = bytes.clone();
            for _ in 0..1 + rng.below(3) {
                if !bytes.is_empty() {
                    mutate(&mut bytes, &mut rng);
                }
            }
            match std::panic::catch_unwind(|| read_vtu(&bytes[..])) {
                Ok(Err(e)) => {
                    assert_one_line(&e.to_string());
                    errors += 1;
                }
                Ok(Ok(_)) => read += 1,
                Err(_) => panic!("{name}, mutation {round} (seed {MUTATION_SEED:#x}): the reader panicked"),
            }
        }
    }
    // Most mutations break the file; some (in RangeMin, a comment...) do not.
    assert!(errors > 4 * read, "{errors} errors, {read} read");
}

/// Gmsh's reference nodes of an element type, from `second_order.txt`.
fn gmsh_reference_nodes(gmsh_type: u32) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(data_dir().join("../second_order.txt")).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with(&format!("ref {gmsh_type} ")))
        .unwrap_or_else(|| panic!("no reference nodes of type {gmsh_type}"));
    let coordinates = line.split_whitespace().nth(3).unwrap();
    coordinates
        .split(';')
        .map(|p| {
            let mut x = [0.0; 3];
            for (slot, v) in x.iter_mut().zip(p.split(',')) {
                *slot = v.parse().unwrap();
            }
            x
        })
        .collect()
}

/// One cell of every second-order type, in Gmsh's node order: Gmsh's reference
/// cell (nodes from `second_order.txt`), when `curved` first bent by a shear
/// quadratic in the reference coordinates (u, v, w) — `w ↦ w + g(u, v)`, and
/// for pyramids `(u, v) ↦ (u, v) + w² (0.3, −0.2)` (VTK's pyramid does not
/// represent the other) — which keeps volumes (its Jacobian is 1) and which
/// the quadratic cells represent exactly, then mapped by `x ↦ A x + b`
/// (det A > 0). Returns the mesh, the Gmsh types and the exact volumes
/// (reference volume × det A).
fn second_order_cells(curved: bool) -> (seam::VolumeMesh, Vec<u32>, Vec<f64>) {
    use seam::{Cell, VolumeMesh};
    const A: [[f64; 3]; 3] = [[1.0, 0.3, 0.1], [0.2, 1.5, -0.2], [0.1, 0.1, 0.8]];
    let det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1])
        - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0])
        + A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
    assert!(det > 0.0);
    // (Gmsh type, reference volume)
    let types =
        [(11, 1.0 / 6.0), (17, 8.0), (12, 8.0), (18, 1.0), (13, 1.0), (19, 4.0 / 3.0), (14, 4.0 / 3.0)];
    let cell = |gmsh_type: u32, n: &[usize]| match gmsh_type {
        11 => Cell::Tet10(n.try_into().unwrap()),
        17 => Cell::Hex20(n.try_into().unwrap()),
        12 => Cell::Hex27(n.try_into().unwrap()),
        18 => Cell::Prism15(n.try_into().unwrap()),
        13 => Cell::Prism18(n.try_into().unwrap()),
        19 => Cell::Pyramid13(n.try_into().unwrap()),
        _ => Cell::Pyramid14(n.try_into().unwrap()),
    };
    let (mut points, mut cells, mut gmsh_types, mut volumes) = (vec![], vec![], vec![], vec![]);
    for (k, &(gmsh_type, reference_volume)) in types.iter().enumerate() {
        let first = points.len();
        let pyramid = matches!(gmsh_type, 14 | 19);
        for [u, v, w] in gmsh_reference_nodes(gmsh_type) {
            let r = match (curved, pyramid) {
                (false, _) => [u, v, w],
                (true, false) => [u, v, w + 0.3 * u * u - 0.2 * u * v + 0.25 * v * v],
                (true, true) => [u + 0.3 * w * w, v - 0.2 * w * w, w],
            };
            let mut x = [0.0; 3];
            for (i, xi) in x.iter_mut().enumerate() {
                *xi = A[i][0] * r[0] + A[i][1] * r[1] + A[i][2] * r[2];
            }
            x[0] += 4.0 * k as f64;
            points.push(x);
        }
        let nodes: Vec<usize> = (first..points.len()).collect();
        cells.push(cell(gmsh_type, &nodes));
        gmsh_types.push(gmsh_type);
        volumes.push(reference_volume * det);
    }
    (VolumeMesh::new(points, cells).unwrap(), gmsh_types, volumes)
}

/// The boundary of the straight-sided second-order cells: flat Tri6, Quad8 and
/// Quad9 faces.
fn second_order_faces() -> SurfaceMesh {
    second_order_cells(false).0.boundary().unwrap()
}

/// One cell of each second-order type, straight-sided (`second_order_affine.vtu`)
/// and curved (`second_order_curved.vtu`), with the cell fields `gmsh_type` and
/// `volume` (exact), and the faces of [`second_order_faces`]
/// (`second_order_faces.vtu`), for `tests/python/test_vtu_second_order.py`,
/// which checks the volumes and areas VTK computes (written to `$SEAM_VTU_OUT`
/// when set).
#[test]
fn write_second_order_cells_for_python() {
    let temp = tempfile::tempdir().unwrap();
    let dir =
        std::env::var_os("SEAM_VTU_OUT").map(PathBuf::from).unwrap_or_else(|| temp.path().to_path_buf());
    std::fs::create_dir_all(&dir).unwrap();
    for (name, curved) in [("second_order_affine.vtu", false), ("second_order_curved.vtu", true)] {
        let (mesh, types, volumes) = second_order_cells(curved);
        let types = Field::scalars("gmsh_type", types.iter().map(|&t| f64::from(t)).collect());
        let volumes = Field::scalars("volume", volumes);
        seam_io::write_volume_vtu_file(dir.join(name), &mesh, &[], &[types, volumes]).unwrap();
    }
    write_vtu_file(dir.join("second_order_faces.vtu"), &second_order_faces(), &[], &[]).unwrap();
}

/// Reads every `.vtu` file of `SEAM_VTU_IN` (set by
/// `tests/python/test_vtu_second_order.py`, which rewrites
/// `second_order_faces.vtu` with VTK's writer in several encodings): each holds
/// the faces of [`second_order_faces`]. Without `SEAM_VTU_IN`, reads what seam
/// writes.
#[test]
fn second_order_faces_written_by_vtk_are_read() {
    let expected = second_order_faces();
    let temp = tempfile::tempdir().unwrap();
    let dir = match std::env::var_os("SEAM_VTU_IN") {
        Some(dir) => PathBuf::from(dir),
        None => {
            write_vtu_file(temp.path().join("seam.vtu"), &expected, &[], &[]).unwrap();
            temp.path().to_path_buf()
        }
    };
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "vtu") {
            let read = read_vtu_file(&path).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(read.mesh, expected, "{}", path.display());
            n += 1;
        }
    }
    assert!(n > 0, "no .vtu file in {}", dir.display());
}

/// Second-order faces (VTK's quadratic triangle and quad, biquadratic quad) read
/// back as written, mixed with first-order ones.
#[test]
fn round_trip_of_second_order_faces_is_bit_exact() {
    let (volume, _, _) = second_order_cells(true);
    let boundary = volume.boundary().unwrap();
    let kinds: Vec<usize> = boundary.faces().iter().map(Face::len).collect();
    for n in [6, 8, 9] {
        assert!(kinds.contains(&n), "a face of {n} nodes");
    }
    let mut faces = boundary.faces().to_vec();
    faces.push(Face::Tri3([0, 1, 2]));
    let mesh = SurfaceMesh::new(boundary.points().to_vec(), faces).unwrap();
    let point_data = vec![Field::scalars("p", wavy(mesh.n_points(), 1, 0.0))];
    let cell_data = vec![Field::new("T", 9, wavy(mesh.n_faces(), 9, 4.0))];
    let mut bytes = Vec::new();
    write_vtu(&mut bytes, &mesh, &point_data, &cell_data).unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    assert!(text.contains("<DataArray type=\"UInt8\" Name=\"types\""));
    let read = read_vtu(bytes.as_slice()).unwrap();
    assert_identical(&read, &mesh, &point_data, &cell_data);
}

#[test]
fn a_parallel_file_declares_the_pieces_fields_and_names_its_pieces() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = mixed_mesh();
    let (point, cell) = mixed_fields(&mesh);
    let pieces = ["a_0.vtu".to_string(), "a_1.vtu".to_string()];
    for piece in &pieces {
        write_vtu_file(dir.path().join(piece), &mesh, &point, &cell).unwrap();
    }
    let path = dir.path().join("a.pvtu");
    seam_io::write_pvtu_file(&path, &pieces, &point, &cell).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains("<VTKFile type=\"PUnstructuredGrid\"") && text.contains("GhostLevel=\"0\""),
        "{text}"
    );
    for (element, fields) in [("PPointData", &point), ("PCellData", &cell)] {
        let start = text.find(&format!("<{element}")).unwrap();
        let block = &text[start..text.find(&format!("</{element}>")).unwrap()];
        assert_eq!(block.matches("<PDataArray").count(), fields.len(), "{block}");
        for f in fields.iter() {
            let components = match f.components {
                1 => String::new(),
                c => format!(" NumberOfComponents=\"{c}\""),
            };
            assert!(block.contains(&format!("Name=\"{}\"{components}/>", f.name)), "{}: {block}", f.name);
        }
    }
    assert!(text.contains("<PPoints><PDataArray type=\"Float64\" NumberOfComponents=\"3\"/></PPoints>"));
    let sources: Vec<&str> =
        text.match_indices("<Piece Source=\"").map(|(i, _)| &text[i + 15..i + 22]).collect();
    assert_eq!(sources, ["a_0.vtu", "a_1.vtu"]);
    // Not a serial file: the reader says so; a field named twice is refused.
    let e = read_vtu_file(&path).unwrap_err();
    assert!(e.to_string().contains("PUnstructuredGrid"), "{e}");
    let twice = [point[0].clone(), point[0].clone()];
    let e = seam_io::write_pvtu_file(dir.path().join("b.pvtu"), &pieces, &twice, &[]).unwrap_err();
    assert!(matches!(e.kind(), VtuErrorKind::BadFieldName { .. }), "{e}");
    assert!(!dir.path().join("b.pvtu").exists());
}
