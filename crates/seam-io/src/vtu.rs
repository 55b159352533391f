//! VTK XML UnstructuredGrid (`.vtu`) files
//! ([format](https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html#xml-file-formats)),
//! read and written with [vtkio].
//!
//! # Writing
//!
//! [`write_vtu`] writes one piece with every point of the mesh, in order, and one
//! cell per face: `VTK_TRIANGLE` (5) for [`Face::Tri3`] and `VTK_QUAD` (9) for
//! [`Face::Quad4`], in face order, so point and cell numbers in ParaView are seam's
//! 0-based indices. Every data array is inline binary (`format="binary"`): base64,
//! uncompressed, little-endian, with a `UInt64` size header (`version="1.0"`),
//! which ParaView/VTK and meshio both read. Points and fields are `Float64` (values
//! round-trip bit for bit), connectivity and offsets `Int64` (as VTK writes them), cell types `UInt8`.
//! The first 1-component field of the point (cell) data is marked as the active
//! scalars, the first 3-component one as the active vectors.
//!
//! # Reading
//!
//! [`read_vtu_file`] reads what vtkio reads: ASCII, inline binary or appended
//! base64 data, uncompressed or compressed (zlib, LZ4, LZMA), with `UInt32` or
//! `UInt64` headers, in one or more pieces (concatenated). Appended *raw* binary
//! data (the default of VTK's and ParaView's writers), which vtkio does not read,
//! is re-encoded as base64 first. Triangles and quads become faces; vertex,
//! poly-vertex, line and poly-line cells are skipped (with their cell data); any
//! other cell type is an error. Point and cell arrays of any numeric type become
//! [`Field`]s of `f64`.
//!
//! ```no_run
//! use seam_io::vtu::{read_vtu_file, write_vtu_file, Field};
//! let surface = seam_io::read_surface_file("slave.msh", None)?;
//! let gap = Field::scalars("gap", vec![0.0; surface.n_points()]);
//! write_vtu_file("slave.vtu", &surface, &[gap], &[])?;
//! let back = read_vtu_file("slave.vtu")?;
//! assert_eq!(back.point_field("gap").map(|f| f.components), Some(1));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod error;
mod normalize;

use std::fs::File;
use std::io::{self, Read, Write};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use seam::{Cell, Face, MeshError, SurfaceMesh, VolumeMesh};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, IOBuffer, Piece,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};
use vtkio::xml::{Compressor, DataSetType, VTKFile};

pub use error::{VtuError, VtuErrorKind};

/// A named field on the points or the cells of a mesh: `components` values per
/// entry, row-major (entry 0's components, then entry 1's, ...).
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The name ParaView shows.
    pub name: String,
    /// Values per entry (1 for a scalar, 3 for a vector...).
    pub components: usize,
    /// `entries × components` values.
    pub values: Vec<f64>,
}

impl Field {
    /// A field of `components` values per entry.
    pub fn new(name: impl Into<String>, components: usize, values: Vec<f64>) -> Field {
        Field { name: name.into(), components, values }
    }

    /// A scalar field: one value per entry.
    pub fn scalars(name: impl Into<String>, values: Vec<f64>) -> Field {
        Field::new(name, 1, values)
    }

    /// A 3-vector field (shown as a vector in ParaView).
    pub fn vectors(name: impl Into<String>, values: &[[f64; 3]]) -> Field {
        Field::new(name, 3, values.iter().flatten().copied().collect())
    }

    /// The number of entries (`values.len() / components`; 0 if `components` is 0).
    pub fn n_entries(&self) -> usize {
        self.values.len().checked_div(self.components).unwrap_or(0)
    }

    /// The values of entry `i`.
    ///
    /// # Panics
    /// If `i` is out of range.
    pub fn entry(&self, i: usize) -> &[f64] {
        &self.values[i * self.components..(i + 1) * self.components]
    }
}

/// A surface mesh with its point and cell fields, read from a VTU file.
///
/// `point_data` fields have one entry per point of `mesh`, `cell_data` fields one
/// per face (cells that are not faces are dropped with their values), in file
/// order.
#[derive(Clone, Debug, PartialEq)]
pub struct VtuMesh {
    /// The triangles and quads of the file, on all of its points.
    pub mesh: SurfaceMesh,
    /// The point fields.
    pub point_data: Vec<Field>,
    /// The cell fields, restricted to the faces.
    pub cell_data: Vec<Field>,
}

impl VtuMesh {
    /// The first point field called `name`.
    pub fn point_field(&self, name: &str) -> Option<&Field> {
        self.point_data.iter().find(|f| f.name == name)
    }

    /// The first cell field called `name`.
    pub fn cell_field(&self, name: &str) -> Option<&Field> {
        self.cell_data.iter().find(|f| f.name == name)
    }
}

/// Writes `mesh` as a VTU file: `VTK_TRIANGLE` (5) / `VTK_QUAD` (9) cells, all
/// points in order, with the given point fields and cell fields (1, 2, 3, 6 or 9
/// components; 3 → a vector in ParaView). See the [module docs](self) for the
/// encoding.
///
/// The whole file is built in memory, then written with one `write_all` and a
/// `flush`.
///
/// # Errors
/// - [`VtuErrorKind::WrongFieldLength`] if a point field does not have
///   `n_points × components` values or a cell field `n_faces × components`;
/// - [`VtuErrorKind::UnsupportedComponents`], [`VtuErrorKind::BadFieldName`]
///   (empty, or used twice among the point fields or among the cell fields);
/// - [`VtuErrorKind::Io`] from `w`.
pub fn write_vtu(
    mut w: impl Write,
    mesh: &SurfaceMesh,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<(), VtuError> {
    let bytes = vtu_bytes(mesh, point_data, cell_data)?;
    w.write_all(&bytes).and_then(|()| w.flush()).map_err(|e| VtuError::io(true, e))
}

/// Writes `mesh` to the file `path` (created or truncated); see [`write_vtu`].
///
/// # Errors
/// As [`write_vtu`], with the path. Nothing is created when a field is wrong.
pub fn write_vtu_file(
    path: impl AsRef<Path>,
    mesh: &SurfaceMesh,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<(), VtuError> {
    write_file(path.as_ref(), vtu_bytes(mesh, point_data, cell_data))
}

/// Writes the encoded file (created or truncated); nothing is created when the
/// encoding failed.
fn write_file(path: &Path, bytes: Result<Vec<u8>, VtuError>) -> Result<(), VtuError> {
    let bytes = bytes.map_err(|e| e.with_path(path))?;
    let mut file = File::create(path).map_err(|e| VtuError::io(true, e).with_path(path))?;
    file.write_all(&bytes).and_then(|()| file.flush()).map_err(|e| VtuError::io(true, e).with_path(path))
}

/// Writes a volume mesh (tetrahedra, hexahedra, prisms, pyramids, mixed) as a
/// VTU file, with point fields and cell fields, encoded as [`write_vtu`] does.
///
/// # Errors
/// As [`write_vtu`], with cell fields of `n_cells × components` values.
pub fn write_volume_vtu(
    mut w: impl Write,
    mesh: &VolumeMesh,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<(), VtuError> {
    let bytes = grid_bytes(mesh.points(), GridCells::of_volume(mesh), point_data, cell_data)?;
    w.write_all(&bytes).and_then(|()| w.flush()).map_err(|e| VtuError::io(true, e))
}

/// Writes a volume mesh to the file `path`; see [`write_volume_vtu`].
///
/// # Errors
/// As [`write_volume_vtu`], with the path. Nothing is created when a field is wrong.
pub fn write_volume_vtu_file(
    path: impl AsRef<Path>,
    mesh: &VolumeMesh,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<(), VtuError> {
    write_file(path.as_ref(), grid_bytes(mesh.points(), GridCells::of_volume(mesh), point_data, cell_data))
}

/// Reads a VTU file; see the [module docs](self) for what is read.
///
/// # Errors
/// A [`VtuError`] with the path: [`VtuErrorKind::Io`] if the file cannot be read,
/// [`VtuErrorKind::Parse`] or [`VtuErrorKind::Malformed`] if it is not a readable
/// VTU file, [`VtuErrorKind::UnsupportedCell`] for a cell that is neither a
/// triangle nor a quad (nor a vertex or line), [`VtuErrorKind::InvalidMesh`],
/// [`VtuErrorKind::NoCells`].
pub fn read_vtu_file(path: impl AsRef<Path>) -> Result<VtuMesh, VtuError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| VtuError::io(false, e).with_path(path))?;
    parse_vtu(&bytes).map_err(|e| e.with_path(path))
}

/// Reads VTU data from `r` (to its end); see [`read_vtu_file`].
///
/// # Errors
/// As [`read_vtu_file`], without path.
pub fn read_vtu(mut r: impl Read) -> Result<VtuMesh, VtuError> {
    let mut bytes = Vec::new();
    r.read_to_end(&mut bytes).map_err(|e| VtuError::io(false, e))?;
    parse_vtu(&bytes)
}

// ---------------------------------------------------------------------------
// Writing

const COMPONENTS: [usize; 5] = [1, 2, 3, 6, 9];

fn check_fields(fields: &[Field], n_entries: usize, on_cells: bool) -> Result<(), VtuError> {
    for (i, field) in fields.iter().enumerate() {
        if field.name.is_empty() || fields[..i].iter().any(|f| f.name == field.name) {
            return Err(VtuErrorKind::BadFieldName { name: field.name.clone(), on_cells }.into());
        }
        if !COMPONENTS.contains(&field.components) {
            return Err(VtuErrorKind::UnsupportedComponents {
                name: field.name.clone(),
                components: field.components,
            }
            .into());
        }
        let expected = n_entries * field.components;
        if field.values.len() != expected {
            return Err(VtuErrorKind::WrongFieldLength {
                name: field.name.clone(),
                expected,
                found: field.values.len(),
            }
            .into());
        }
    }
    Ok(())
}

fn attributes(fields: &[Field]) -> Vec<Attribute> {
    fields
        .iter()
        .map(|f| {
            let elem = match f.components {
                1 => ElementType::Scalars { num_comp: 1, lookup_table: None },
                3 => ElementType::Vectors,
                // Components are checked to be 1, 2, 3, 6 or 9.
                n => ElementType::Generic(n as u32),
            };
            Attribute::DataArray(DataArray {
                name: f.name.clone(),
                elem,
                data: IOBuffer::F64(f.values.clone()),
            })
        })
        .collect()
}

/// The cells of a grid to write: VTK types and connectivity.
#[derive(Default)]
struct GridCells {
    types: Vec<CellType>,
    connectivity: Vec<u64>,
    offsets: Vec<u64>,
}

impl GridCells {
    fn push(&mut self, kind: CellType, nodes: &[usize]) {
        self.connectivity.extend(nodes.iter().map(|&n| n as u64));
        self.offsets.push(self.connectivity.len() as u64);
        self.types.push(kind);
    }

    fn of_surface(mesh: &SurfaceMesh) -> GridCells {
        let mut cells = GridCells::default();
        for face in mesh.faces() {
            let kind = match face {
                Face::Tri3(_) => CellType::Triangle,
                Face::Quad4(_) => CellType::Quad,
            };
            cells.push(kind, face.nodes());
        }
        cells
    }

    /// Volume cells. Gmsh's node orders of the tetrahedron, hexahedron, prism
    /// (VTK's wedge) and pyramid are VTK's: VTK computes a positive volume for
    /// cells that are positive in Gmsh (checked by `tests/python`).
    fn of_volume(mesh: &VolumeMesh) -> GridCells {
        let mut cells = GridCells::default();
        for cell in mesh.cells() {
            let kind = match cell {
                Cell::Tet4(_) => CellType::Tetra,
                Cell::Hex8(_) => CellType::Hexahedron,
                Cell::Prism6(_) => CellType::Wedge,
                Cell::Pyramid5(_) => CellType::Pyramid,
            };
            cells.push(kind, cell.nodes());
        }
        cells
    }
}

fn vtu_bytes(mesh: &SurfaceMesh, point_data: &[Field], cell_data: &[Field]) -> Result<Vec<u8>, VtuError> {
    grid_bytes(mesh.points(), GridCells::of_surface(mesh), point_data, cell_data)
}

fn grid_bytes(
    points: &[[f64; 3]],
    cells: GridCells,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<Vec<u8>, VtuError> {
    check_fields(point_data, points.len(), false)?;
    check_fields(cell_data, cells.types.len(), true)?;
    let GridCells { types, connectivity, offsets } = cells;
    let points: Vec<f64> = points.iter().flatten().copied().collect();
    let vtk = Vtk {
        version: Version::new_xml(1, 0),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: IOBuffer::F64(points),
            cells: Cells { cell_verts: VertexNumbers::XML { connectivity, offsets }, types },
            data: Attributes { point: attributes(point_data), cell: attributes(cell_data) },
        }),
    };
    let vtkio_failed = |e: vtkio::xml::Error| VtuError::io(true, io::Error::other(format!("vtkio: {e}")));
    let xml = vtk.try_into_xml_format(Compressor::None, 0).map_err(vtkio_failed)?;
    // vtkio writes through `Write::write` and drops its `BufWriter` without checking
    // the flush, so it writes to memory here and the caller uses `write_all`.
    let mut bytes = b"<?xml version=\"1.0\"?>\n".to_vec();
    xml.write(&mut bytes).map_err(vtkio_failed)?;
    bytes.push(b'\n');
    Ok(declare_cells_signed(bytes))
}

/// vtkio declares connectivity and offsets `UInt64`; VTK writes `Int64`, and
/// meshio turns unsigned offsets into floats (numpy promotes uint64 with int64 to
/// float64). Node indices are far below 2⁶³, so the bytes are the same either
/// way: only the declared type changes.
fn declare_cells_signed(bytes: Vec<u8>) -> Vec<u8> {
    let text = String::from_utf8(bytes).expect("vtkio writes UTF-8");
    text.replace(
        r#"<DataArray type="UInt64" Name="connectivity""#,
        r#"<DataArray type="Int64" Name="connectivity""#,
    )
    .replace(r#"<DataArray type="UInt64" Name="offsets""#, r#"<DataArray type="Int64" Name="offsets""#)
    .into_bytes()
}

// ---------------------------------------------------------------------------
// Reading

/// Runs vtkio code that may panic on malformed input (it slices and unwraps):
/// the panic becomes an error, and the panic hook is silenced meanwhile so that
/// no panic message reaches stderr (the caller reports the error in one line).
fn guard<T>(f: impl FnOnce() -> T) -> Result<T, VtuError> {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let result = catch_unwind(AssertUnwindSafe(f));
    std::panic::set_hook(hook);
    result.map_err(|payload| {
        let why = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown reason".to_string());
        VtuError::malformed(format!("vtkio failed on the file: {}", error::one_line(&why)))
    })
}

fn parse_vtu(bytes: &[u8]) -> Result<VtuMesh, VtuError> {
    let bytes = normalize::normalize(bytes)?;
    let parse_error = |e: vtkio::xml::Error| VtuError::new(VtuErrorKind::Parse(vtkio::Error::XML(e)));
    let file = guard(|| VTKFile::parse(&bytes[..]))?.map_err(parse_error)?;
    if file.data_set_type != DataSetType::UnstructuredGrid {
        return Err(VtuError::malformed(format!(
            "a VTK {:?} file, not a serial UnstructuredGrid (.vtu) file",
            file.data_set_type
        )));
    }
    let vtk = guard(|| Vtk::try_from(file))?.map_err(parse_error)?;
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        return Err(VtuError::malformed("not an UnstructuredGrid data set"));
    };
    let declared = normalize::declared_fields(&bytes);
    let mut builder = Builder::default();
    for (p, piece) in pieces.into_iter().enumerate() {
        let Piece::Inline(piece) = piece else {
            return Err(VtuError::malformed(format!("piece {p} refers to another file")));
        };
        if let Some([point, cell]) = declared.get(p) {
            check_decoded(point, &piece.data.point, "point")?;
            check_decoded(cell, &piece.data.cell, "cell")?;
        }
        builder.add_piece(p, *piece)?;
    }
    builder.finish()
}

/// Fails if vtkio has skipped one of the `declared` arrays (it does so silently
/// when it cannot decode one).
fn check_decoded(declared: &[String], decoded: &[Attribute], what: &str) -> Result<(), VtuError> {
    if declared.len() == decoded.len() {
        return Ok(());
    }
    let mut missing: Vec<&String> = declared.iter().collect();
    for a in decoded {
        if let Some(i) = missing.iter().position(|name| *name == a.name()) {
            missing.remove(i);
        }
    }
    let names: Vec<String> = missing.iter().map(|name| format!("{name:?}")).collect();
    Err(VtuError::malformed(format!("vtkio cannot decode the {what} data array(s) {}", names.join(", "))))
}

/// Accumulates pieces.
#[derive(Default)]
struct Builder {
    points: Vec<[f64; 3]>,
    faces: Vec<Face>,
    /// The file's (global) cell index of each face.
    face_cells: Vec<usize>,
    n_cells: usize,
    point_data: Vec<Field>,
    cell_data: Vec<Field>,
}

impl Builder {
    fn add_piece(&mut self, p: usize, piece: UnstructuredGridPiece) -> Result<(), VtuError> {
        let UnstructuredGridPiece { points, cells, data } = piece;
        let coords: Vec<f64> = points
            .cast_into()
            .ok_or_else(|| VtuError::malformed(format!("the points of piece {p} are not numbers")))?;
        if coords.len() % 3 != 0 {
            return Err(VtuError::malformed(format!(
                "piece {p} has {} point coordinates, not a multiple of 3",
                coords.len()
            )));
        }
        let point_base = self.points.len();
        let n_points = coords.len() / 3;
        self.points.extend(coords.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));

        let Cells { cell_verts, types } = cells;
        let (connectivity, offsets) = cell_verts.into_xml();
        if offsets.len() != types.len() {
            return Err(VtuError::malformed(format!(
                "piece {p} has {} cell offsets but {} cell types",
                offsets.len(),
                types.len()
            )));
        }
        let cell_base = self.n_cells;
        let mut kept = Vec::with_capacity(types.len());
        let mut start = 0usize;
        for (i, (&ty, &end)) in types.iter().zip(&offsets).enumerate() {
            let cell = cell_base + i;
            let end = usize::try_from(end).unwrap_or(usize::MAX);
            if end < start || end > connectivity.len() {
                return Err(VtuError::malformed(format!(
                    "cell {cell}: offset {end} is out of order or past the {} connectivity entries",
                    connectivity.len()
                )));
            }
            let nodes = &connectivity[start..end];
            start = end;
            let corners = match ty {
                CellType::Triangle => 3,
                CellType::Quad => 4,
                CellType::Vertex | CellType::PolyVertex | CellType::Line | CellType::PolyLine => continue,
                other => return Err(VtuErrorKind::UnsupportedCell { cell, vtk_type: other as u8 }.into()),
            };
            if nodes.len() != corners {
                return Err(VtuError::malformed(format!(
                    "cell {cell} is {} but lists {} points",
                    error::describe_cell_type(ty as u8),
                    nodes.len()
                )));
            }
            let mut face = [0usize; 4];
            for (corner, (&node, slot)) in nodes.iter().zip(&mut face).enumerate() {
                let node = usize::try_from(node).unwrap_or(usize::MAX);
                if node >= n_points {
                    let problem = MeshError::IndexOutOfRange {
                        what: "cell",
                        element: cell,
                        corner,
                        index: node,
                        n_nodes: n_points,
                    };
                    return Err(VtuErrorKind::InvalidMesh(problem).into());
                }
                *slot = point_base + node;
            }
            self.faces.push(Face::from_nodes(&face[..corners]));
            self.face_cells.push(cell);
            kept.push(i);
        }
        self.n_cells += types.len();

        let point_fields = fields(data.point, n_points)?;
        let cell_fields: Vec<Field> = fields(data.cell, types.len())?
            .into_iter()
            .map(|f| {
                let values = kept.iter().flat_map(|&i| f.entry(i).iter().copied()).collect();
                Field { values, ..f }
            })
            .collect();
        if p == 0 {
            self.point_data = point_fields;
            self.cell_data = cell_fields;
        } else {
            append_fields(&mut self.point_data, point_fields, p, "point")?;
            append_fields(&mut self.cell_data, cell_fields, p, "cell")?;
        }
        Ok(())
    }

    fn finish(self) -> Result<VtuMesh, VtuError> {
        if self.faces.is_empty() {
            return Err(VtuErrorKind::NoCells.into());
        }
        let face_cells = self.face_cells;
        let mesh = SurfaceMesh::new(self.points, self.faces)
            .map_err(|e| VtuError::new(VtuErrorKind::InvalidMesh(renumber(e, &face_cells))))?;
        Ok(VtuMesh { mesh, point_data: self.point_data, cell_data: self.cell_data })
    }
}

/// The data arrays of `attributes` as fields of `n_entries` entries (legacy field
/// attributes do not occur in XML files).
fn fields(attributes: Vec<Attribute>, n_entries: usize) -> Result<Vec<Field>, VtuError> {
    let mut fields = Vec::with_capacity(attributes.len());
    for attribute in attributes {
        let Attribute::DataArray(DataArray { name, elem, data }) = attribute else { continue };
        let components = elem.num_comp() as usize;
        let Some(values) = data.cast_into::<f64>() else {
            return Err(VtuError::malformed(format!("field {name:?} does not hold numbers")));
        };
        // vtkio has checked this; a wrong length would make `Field::entry` panic.
        if components == 0 || values.len() != n_entries * components {
            let expected = n_entries * components;
            return Err(VtuErrorKind::WrongFieldLength { name, expected, found: values.len() }.into());
        }
        fields.push(Field { name, components, values });
    }
    Ok(fields)
}

fn append_fields(all: &mut [Field], more: Vec<Field>, p: usize, what: &str) -> Result<(), VtuError> {
    let same = all.len() == more.len()
        && all.iter().zip(&more).all(|(a, b)| a.name == b.name && a.components == b.components);
    if !same {
        return Err(VtuError::malformed(format!("piece {p} has other {what} fields than piece 0")));
    }
    for (a, b) in all.iter_mut().zip(more) {
        a.values.extend(b.values);
    }
    Ok(())
}

/// `e` with face indices replaced by the file's cell indices.
fn renumber(e: MeshError, face_cells: &[usize]) -> MeshError {
    match e {
        MeshError::IndexOutOfRange { element, corner, index, n_nodes, .. } => {
            MeshError::IndexOutOfRange { what: "cell", element: face_cells[element], corner, index, n_nodes }
        }
        MeshError::RepeatedNode { element, node, .. } => {
            MeshError::RepeatedNode { what: "cell", element: face_cells[element], node }
        }
        MeshError::ZeroArea { face } => MeshError::ZeroArea { face: face_cells[face] },
        other => other,
    }
}
