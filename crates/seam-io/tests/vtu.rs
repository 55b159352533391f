//! Integration tests of VTU reading and writing: bit-exact round trips, field and
//! cell errors, files written by meshio and VTK (`tests/data/vtu/make_fixtures.py`),
//! corrupt input, and the fixtures `tests/python/test_vtu_meshio.py` checks with
//! meshio (and VTK, the reader of ParaView).

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
            "{}: cell 1 is a tetrahedron (VTK type 10); only triangles (5) and quads (9) are read, \
             vertices and lines are skipped",
            path.display()
        )
    );
    let text = ascii_vtu(&SQUARE, &[(22, &[0, 1, 2, 3, 4, 0])], "");
    let e = read_vtu(text.as_bytes()).unwrap_err();
    assert!(e.to_string().starts_with("cell 0 is a quadratic triangle (VTK type 22)"), "{e}");
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
    assert!(matches!(e.kind(), VtuErrorKind::Parse(_)), "{e:?}");
    let poly = r#"<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian"><PolyData><Piece NumberOfPoints="0"/></PolyData></VTKFile>"#;
    let e = read_vtu(poly.as_bytes()).unwrap_err();
    assert!(e.to_string().contains("not a serial UnstructuredGrid"), "{e}");

    // vtkio panics on these (it slices and unwraps); the reader turns that into an error.
    let no_points = good.replace(&good[good.find("<Points>").unwrap()..good.find("<Cells>").unwrap()], "");
    let e = read_vtu(no_points.as_bytes()).unwrap_err();
    assert!(e.to_string().starts_with("vtkio failed on the file: "), "{e}");
    let cells: [(u8, &[usize]); 1] = [(5, &[0, 1, 2])];
    let text = ascii_vtu(&SQUARE, &cells, "");
    let (start, end) = (text.find("<Points>").unwrap(), text.find("</Points>").unwrap());
    let binary =
        r#"<Points><DataArray type="Float64" NumberOfComponents="3" format="binary">AAAA</DataArray>"#;
    let short = format!("{}{binary}{}", &text[..start], &text[end..]);
    let e = read_vtu(short.as_bytes()).unwrap_err();
    assert!(e.to_string().starts_with("vtkio failed on the file: "), "{e}");

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
fn a_field_vtkio_cannot_decode_is_an_error_not_dropped() {
    let mesh = mixed_mesh();
    let (point_data, _) = mixed_fields(&mesh);
    let mut bytes = Vec::new();
    write_vtu(&mut bytes, &mesh, &point_data[..1], &[]).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    // Cut the base64 data of field "p" short: vtkio skips such arrays silently.
    let start = text.find("Name=\"p\"").unwrap();
    let data = start + text[start..].find('>').unwrap() + 1;
    let bad = format!("{}{}", &text[..data + 8], &text[data + 20..]);
    let e = read_vtu(bad.as_bytes()).unwrap_err();
    assert_eq!(e.to_string(), "vtkio cannot decode the point data array(s) \"p\"");
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
