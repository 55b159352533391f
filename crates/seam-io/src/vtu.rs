//! VTK XML UnstructuredGrid (`.vtu`) files
//! ([format](https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html#xml-file-formats)),
//! read and written by seam itself (quick-xml for the XML, flate2, lz4_flex and
//! xz2 for the compressed data).
//!
//! # Writing
//!
//! [`write_vtu`] writes one piece with every point of the mesh, in order, and one
//! cell per face, of the face kind's VTK type ([`seam::FaceType::vtk_type`]):
//! `VTK_TRIANGLE` (5) for [`Face::Tri3`], `VTK_QUAD` (9) for
//! [`Face::Quad4`], `VTK_QUADRATIC_TRIANGLE` (22) for [`Face::Tri6`],
//! `VTK_QUADRATIC_QUAD` (23) for [`Face::Quad8`] and `VTK_BIQUADRATIC_QUAD` (28)
//! for [`Face::Quad9`] (VTK numbers the nodes of these as Gmsh and seam do), in
//! face order, so point and cell numbers in ParaView are seam's 0-based indices.
//! [`write_volume_vtu`] writes the cells of a volume mesh, the second-order ones
//! as VTK's quadratic cells with their nodes in VTK's order
//! ([`seam::CellType::vtk_order`]; a
//! [`Cell::Pyramid14`](seam::Cell::Pyramid14) as the 13-node `VTK_QUADRATIC_PYRAMID`,
//! VTK having no 14-node pyramid: its base centre is left out). Every data array is inline binary (`format="binary"`): base64,
//! uncompressed, little-endian, with a `UInt64` size header (`version="1.0"`),
//! which ParaView/VTK and meshio both read. Points and fields are `Float64` (values
//! round-trip bit for bit), connectivity and offsets `Int64` (as VTK writes them), cell types `UInt8`.
//! The first 1-component field of the point (cell) data is marked as the active
//! scalars, the first 3-component one as the active vectors.
//!
//! # Reading
//!
//! [`read_vtu_file`] reads the VTU files seam, ParaView/VTK and meshio write:
//!
//! | | read |
//! |---|---|
//! | `<VTKFile>` | `type="UnstructuredGrid"`, `version` 0.1, 1.0 or 2.x, either `byte_order`, `header_type` `UInt32` (default) or `UInt64` |
//! | data arrays | `format="ascii"`, `"binary"` (inline base64), `"appended"` with `<AppendedData encoding="raw">` or `"base64"` |
//! | compression | none, `vtkZLibDataCompressor`, `vtkLZ4DataCompressor`, `vtkLZMADataCompressor` |
//! | values | `Int8` … `UInt64`, `Float32`, `Float64`, becoming `f64` [`Field`]s |
//! | pieces | one or more, concatenated (not pieces in other files) |
//! | cells | triangles (5), quads (9), quadratic triangles (22), quadratic quads (23) and biquadratic quads (28) become faces; vertex, poly-vertex, line and poly-line cells (1–4) are skipped with their cell data; any other type is an error naming the cell |
//!
//! Anything else (another data set type, compressor, encoding...) is an
//! [`VtuErrorKind::Unsupported`] error.
//!
//! Binary data ([VTK XML formats](https://vtk.org/Wiki/VTK_XML_Formats#Compressed_Data)):
//! an uncompressed array is a header integer (its byte count) followed by the
//! bytes; a compressed one is the header `[nb][nu][np][nc_1]…[nc_nb]` (block
//! count, block size before compression, size of the last block before
//! compression — 0 when it is a full block — and the compressed size of each
//! block) followed by the blocks, each a zlib stream, an LZ4 block (no frame) or
//! an `.xz` stream. Header integers and values are in the file's byte order.
//! Inline base64 data may encode the header on its own (padded) before the
//! blocks, as VTK and meshio do; appended `offset`s count bytes (raw) or
//! characters (base64) from the one after the `_` that starts the appended data.
//!
//! Every size in the file is checked against what it holds before anything is
//! allocated from it: each array must hold exactly the values that
//! `NumberOfPoints`, `NumberOfCells`, `NumberOfComponents` and the cell offsets
//! imply (the size headers must agree), the bytes an array needs must be present,
//! and a block decompresses into a buffer that grows as data comes out, up to its
//! declared size and no further. So reading a corrupt or hostile file fails with
//! an error naming the piece, array or cell, in memory within a small multiple of
//! the file size plus what its data actually decompresses to; it does not panic,
//! and it touches no process-wide state. Cell connectivity must refer to points
//! of the piece, offsets must not decrease. Non-finite coordinates are an
//! [`VtuErrorKind::InvalidMesh`] error; non-finite field values are read as they
//! are.
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

mod decode;
mod error;
mod read;
mod write;

use std::fs::File;
use std::io::{Read, Write};
use std::path::Path;

use seam::{Face, FaceKind, MeshError, SurfaceMesh, VolumeMesh, MAX_FACE_NODES};

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

/// Writes `mesh` as a VTU file: a cell per face (`VTK_TRIANGLE` (5),
/// `VTK_QUAD` (9), or for second-order faces 22, 23, 28), all points in order, with the given point fields and cell fields (1, 2, 3, 6 or 9
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
    let bytes = write::surface_bytes(mesh, point_data, cell_data)?;
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
    write_file(path.as_ref(), write::surface_bytes(mesh, point_data, cell_data))
}

/// Writes the encoded file (created or truncated); nothing is created when the
/// encoding failed.
fn write_file(path: &Path, bytes: Result<Vec<u8>, VtuError>) -> Result<(), VtuError> {
    let bytes = bytes.map_err(|e| e.with_path(path))?;
    let mut file = File::create(path).map_err(|e| VtuError::io(true, e).with_path(path))?;
    file.write_all(&bytes).and_then(|()| file.flush()).map_err(|e| VtuError::io(true, e).with_path(path))
}

/// Writes a volume mesh (tetrahedra, hexahedra, prisms, pyramids, first or
/// second order, mixed) as a VTU file, in VTK's node order, with point fields and cell fields, encoded as [`write_vtu`] does.
///
/// # Errors
/// As [`write_vtu`], with cell fields of `n_cells × components` values.
pub fn write_volume_vtu(
    mut w: impl Write,
    mesh: &VolumeMesh,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<(), VtuError> {
    let bytes = write::volume_bytes(mesh, point_data, cell_data)?;
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
    write_file(path.as_ref(), write::volume_bytes(mesh, point_data, cell_data))
}

/// Writes a parallel VTU file (`.pvtu`, VTK's `PUnstructuredGrid`, what
/// ParaView opens as one data set): the point and cell fields every piece
/// holds (their names and components; the values are not read) and the
/// pieces' VTU files, named relative to the `.pvtu` file's directory, in
/// order. The pieces are written separately ([`write_volume_vtu_file`],
/// [`write_vtu_file`]), with the same fields.
///
/// # Errors
/// [`VtuErrorKind::UnsupportedComponents`], [`VtuErrorKind::BadFieldName`]
/// as [`write_vtu`]; [`VtuErrorKind::Io`], with the path.
pub fn write_pvtu_file(
    path: impl AsRef<Path>,
    pieces: &[String],
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<(), VtuError> {
    write_file(path.as_ref(), write::parallel_bytes(pieces, point_data, cell_data))
}

/// Writes a ParaView collection (`.pvd`) of the files `entries` (time,
/// file name relative to the collection's directory), in the order given:
/// ParaView shows the files as one series over time.
///
/// # Errors
/// [`VtuErrorKind::Io`], with the path.
pub fn write_pvd_file(path: impl AsRef<Path>, entries: &[(f64, String)]) -> Result<(), VtuError> {
    write_file(path.as_ref(), Ok(write::collection_bytes(entries)))
}

/// Reads a VTU file; see the [module docs](self) for what is read.
///
/// # Errors
/// A [`VtuError`] with the path: [`VtuErrorKind::Io`] if the file cannot be read
/// (also: it is a directory, a device or a pipe),
/// [`VtuErrorKind::Parse`] if it is not well-formed VTK XML,
/// [`VtuErrorKind::Unsupported`] for a feature the reader does not read,
/// [`VtuErrorKind::Malformed`] if its content is inconsistent (sizes, headers,
/// compressed data, numbers, cell offsets and point indices),
/// [`VtuErrorKind::UnsupportedCell`] for a cell that is not a face (a linear,
/// quadratic or biquadratic triangle or quad), a vertex or a line, [`VtuErrorKind::InvalidMesh`],
/// [`VtuErrorKind::NoCells`].
pub fn read_vtu_file(path: impl AsRef<Path>) -> Result<VtuMesh, VtuError> {
    let path = path.as_ref();
    let bytes = crate::read_regular_file(path).map_err(|e| VtuError::io(false, e).with_path(path))?;
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
// Reading

fn parse_vtu(bytes: &[u8]) -> Result<VtuMesh, VtuError> {
    let document = read::Document::parse(bytes)?;
    let mut builder = Builder::default();
    for p in 0..document.n_pieces() {
        builder.add_piece(p, document.piece(p)?)?;
    }
    builder.finish()
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
    /// Adds the faces of a piece (whose array sizes and offsets
    /// [`read::Document::piece`] has checked) and its fields; checks the point
    /// indices of every cell.
    fn add_piece(&mut self, p: usize, piece: read::Piece) -> Result<(), VtuError> {
        let read::Piece { n_points, points, offsets, connectivity, types, point_data, cell_data } = piece;
        let point_base = self.points.len();
        self.points.extend(points.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));

        let cell_base = self.n_cells;
        let mut kept = Vec::new();
        let mut start = 0usize;
        for (i, (&ty, &end)) in types.iter().zip(&offsets).enumerate() {
            let cell = cell_base + i;
            let nodes = connectivity.get(start..end).unwrap_or_default();
            start = end;
            if let Some((corner, &index)) = nodes.iter().enumerate().find(|(_, &n)| n >= n_points) {
                let problem = MeshError::IndexOutOfRange {
                    what: "cell",
                    element: cell,
                    corner,
                    index,
                    n_nodes: n_points,
                };
                return Err(VtuErrorKind::InvalidMesh(problem).into());
            }
            let kind = match FaceKind::from_vtk(ty) {
                Some(kind) => kind,
                // Vertices and lines.
                None if (1..=4).contains(&ty) => continue,
                None => return Err(VtuErrorKind::UnsupportedCell { cell, vtk_type: ty }.into()),
            };
            let order = kind.info().vtk_order;
            if nodes.len() != order.len() {
                return Err(VtuError::malformed(format!(
                    "cell {cell} is {} but lists {} points",
                    error::describe_cell_type(ty),
                    nodes.len()
                )));
            }
            // VTK node i is seam's node order[i].
            let mut face = [0usize; MAX_FACE_NODES];
            for (&node, &slot) in nodes.iter().zip(order) {
                face[slot] = point_base + node;
            }
            self.faces.push(Face::new(kind, &face[..order.len()]).expect("the kind's node count"));
            self.face_cells.push(cell);
            kept.push(i);
        }
        self.n_cells += types.len();
        let n_faces = kept.len();

        let cell_data: Vec<Field> = cell_data
            .into_iter()
            .map(|f| {
                let mut values = Vec::with_capacity(n_faces * f.components);
                for &i in &kept {
                    values.extend_from_slice(
                        f.values.get(i * f.components..(i + 1) * f.components).unwrap_or_default(),
                    );
                }
                Field { values, ..f }
            })
            .collect();
        debug_assert!(point_data.iter().all(|f| f.values.len() == n_points * f.components));
        if p == 0 {
            self.point_data = point_data;
            self.cell_data = cell_data;
        } else {
            append_fields(&mut self.point_data, point_data, p, "point")?;
            append_fields(&mut self.cell_data, cell_data, p, "cell")?;
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
    let cell = |face: usize| face_cells.get(face).copied().unwrap_or(face);
    match e {
        MeshError::IndexOutOfRange { element, corner, index, n_nodes, .. } => {
            MeshError::IndexOutOfRange { what: "cell", element: cell(element), corner, index, n_nodes }
        }
        MeshError::RepeatedNode { element, node, .. } => {
            MeshError::RepeatedNode { what: "cell", element: cell(element), node }
        }
        MeshError::ZeroArea { face } => MeshError::ZeroArea { face: cell(face) },
        MeshError::TooSmall { face, diameter } => MeshError::TooSmall { face: cell(face), diameter },
        other => other,
    }
}
