//! [`VtuError`]: what went wrong, and in which file.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use seam::MeshError;

/// What is wrong, without the file name (see [`VtuError`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VtuErrorKind {
    /// The file could not be read or written.
    #[error("cannot {} the file: {}", if *.writing { "write" } else { "read" }, one_line(&.source.to_string()))]
    Io {
        /// True when writing, false when reading.
        writing: bool,
        /// The I/O error.
        source: io::Error,
    },
    /// The file is not well-formed XML, or not a VTK XML file (no `<VTKFile>` root
    /// element), or it ends early.
    ///
    /// ```
    /// use seam_io::{read_vtu, VtuErrorKind};
    /// let e = read_vtu(&b"<VTKFile type=\"UnstructuredGrid\" version=\"1.0\">\n<Unstr"[..]).unwrap_err();
    /// assert!(matches!(e.kind(), VtuErrorKind::Parse { line: Some(2), .. }), "{e}");
    /// ```
    #[error("not a readable VTU file: {message}{}", .line.map(|l| format!(" (line {l})")).unwrap_or_default())]
    Parse {
        /// The 1-based line of the file where the problem was found, if known.
        line: Option<usize>,
        /// What is wrong, one line.
        message: String,
    },
    /// A valid VTK XML file that uses something this reader does not read: another
    /// data set type (`PolyData`, a parallel `PUnstructuredGrid`...), an unknown
    /// file version, compressor, header type, data type or encoding, or pieces in
    /// other files.
    ///
    /// ```
    /// use seam_io::{read_vtu, VtuErrorKind};
    /// let text = r#"<VTKFile type="UnstructuredGrid" version="1.0" compressor="vtkZstdDataCompressor"/>"#;
    /// let e = read_vtu(text.as_bytes()).unwrap_err();
    /// assert!(matches!(e.kind(), VtuErrorKind::Unsupported { .. }));
    /// assert!(e.to_string().starts_with("compressor \"vtkZstdDataCompressor\" is not supported"));
    /// ```
    #[error("{message}")]
    Unsupported {
        /// What is not supported, one line.
        message: String,
    },
    /// The file is well-formed XML, but its content is inconsistent: a data array
    /// whose size, header or compressed data does not match what the piece
    /// declares, bad numbers, cell offsets out of order...
    ///
    /// ```
    /// use seam_io::{read_vtu, VtuErrorKind};
    /// let text = r#"<VTKFile type="UnstructuredGrid" version="0.1"><UnstructuredGrid>
    ///   <Piece NumberOfPoints="99999999999999" NumberOfCells="0"><Points>
    ///     <DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0</DataArray>
    ///   </Points></Piece></UnstructuredGrid></VTKFile>"#;
    /// let e = read_vtu(text.as_bytes()).unwrap_err();
    /// assert!(matches!(e.kind(), VtuErrorKind::Malformed { .. }));
    /// assert_eq!(
    ///     e.to_string(),
    ///     "piece 0, the points array (299999999999997 Float32 values): 3 values, expected 299999999999997"
    /// );
    /// ```
    #[error("{message}")]
    Malformed {
        /// What is wrong, one line, naming the piece, array or cell at fault.
        message: String,
    },
    /// A cell of a type seam cannot use (anything but linear and quadratic
    /// triangles and quads, apart from vertex and line cells, which are
    /// skipped).
    #[error("cell {cell} is {} (VTK type {vtk_type}); only triangles (5, 22, 34) and quads (9, 23, 28) are read, vertices and lines are skipped", describe_cell_type(*.vtk_type))]
    UnsupportedCell {
        /// The 0-based cell index in the file.
        cell: usize,
        /// The VTK cell type number.
        vtk_type: u8,
    },
    /// A field does not have entries × components values.
    #[error("field {name:?} has {found} values, expected {expected}")]
    WrongFieldLength {
        /// The field name.
        name: String,
        /// Entries (points or cells) × components.
        expected: usize,
        /// The number of values it has.
        found: usize,
    },
    /// A field to write has a number of components VTU output does not support.
    #[error("field {name:?} has {components} components; seam writes fields of 1, 2, 3, 6 or 9 components")]
    UnsupportedComponents {
        /// The field name.
        name: String,
        /// Its number of components.
        components: usize,
    },
    /// A field to write has an empty name or the name of another field on the same
    /// entities (readers would drop one of them).
    #[error("{} field name {name:?} {}", if *.on_cells { "cell" } else { "point" }, if .name.is_empty() { "is empty" } else { "is used twice" })]
    BadFieldName {
        /// The name.
        name: String,
        /// True for a cell field, false for a point field.
        on_cells: bool,
    },
    /// The triangles and quads do not form a valid [`seam::SurfaceMesh`]. Face
    /// indices in the [`MeshError`] are 0-based cell indices of the file (as in
    /// ParaView's spreadsheet view), so [`MeshError::element`] names the cell.
    #[error("invalid mesh: {0}")]
    InvalidMesh(MeshError),
    /// The file has no triangle or quad cells.
    #[error("no triangle or quad cells in the file")]
    NoCells,
}

/// An error reading or writing a VTU file: the file (when there is a path) and
/// the [`VtuErrorKind`].
///
/// Displays on one line, for example
/// `result.vtu: cell 3 is a tetrahedron (VTK type 10); only triangles (5, 22, 34) and quads (9, 23, 28) are read, ...`.
#[derive(Debug)]
pub struct VtuError {
    path: Option<PathBuf>,
    kind: VtuErrorKind,
}

impl VtuError {
    /// An error without path.
    pub fn new(kind: VtuErrorKind) -> Self {
        VtuError { path: None, kind }
    }

    /// The same error, attributed to the file at `path`.
    #[must_use]
    pub fn with_path(mut self, path: impl AsRef<Path>) -> Self {
        self.path = Some(path.as_ref().to_path_buf());
        self
    }

    /// What went wrong.
    pub fn kind(&self) -> &VtuErrorKind {
        &self.kind
    }

    /// The file, if the error came from reading or writing a path.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The I/O error kind, if the file could not be read or written.
    pub fn io_kind(&self) -> Option<io::ErrorKind> {
        match &self.kind {
            VtuErrorKind::Io { source, .. } => Some(source.kind()),
            _ => None,
        }
    }

    pub(crate) fn io(writing: bool, source: io::Error) -> Self {
        VtuError::new(VtuErrorKind::Io { writing, source })
    }

    pub(crate) fn malformed(message: impl Into<String>) -> Self {
        VtuError::new(VtuErrorKind::Malformed { message: message.into() })
    }

    pub(crate) fn unsupported(message: impl Into<String>) -> Self {
        VtuError::new(VtuErrorKind::Unsupported { message: message.into() })
    }

    pub(crate) fn parse(line: Option<usize>, message: impl Into<String>) -> Self {
        VtuError::new(VtuErrorKind::Parse { line, message: message.into() })
    }
}

impl From<VtuErrorKind> for VtuError {
    fn from(kind: VtuErrorKind) -> Self {
        VtuError::new(kind)
    }
}

impl fmt::Display for VtuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(path) = &self.path {
            write!(f, "{}: ", path.display())?;
        }
        write!(f, "{}", self.kind)
    }
}

impl std::error::Error for VtuError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            VtuErrorKind::Io { source, .. } => Some(source),
            VtuErrorKind::InvalidMesh(e) => Some(e),
            _ => None,
        }
    }
}

/// A message on one line, starting lowercase, without final period.
pub(crate) fn one_line(text: &str) -> String {
    let text: String = text.split_whitespace().collect::<Vec<_>>().join(" ");
    let text = text.trim_end_matches('.');
    let mut chars = text.chars();
    match chars.next() {
        // Keep acronyms such as "XML" or "IO" as they are.
        Some(c) if !chars.clone().next().is_some_and(char::is_uppercase) => {
            c.to_lowercase().chain(chars).collect()
        }
        _ => text.to_string(),
    }
}

/// "a tetrahedron", "a quadratic triangle", ... for a VTK cell type number.
pub(crate) fn describe_cell_type(vtk_type: u8) -> String {
    let name = match vtk_type {
        1 => "a vertex",
        2 => "a poly-vertex",
        3 => "a line",
        4 => "a poly-line",
        5 => "a triangle",
        6 => "a triangle strip",
        7 => "a polygon",
        8 => "a pixel",
        9 => "a quad",
        10 => "a tetrahedron",
        11 => "a voxel",
        12 => "a hexahedron",
        13 => "a wedge",
        14 => "a pyramid",
        21 => "a quadratic edge",
        22 => "a quadratic triangle",
        23 => "a quadratic quad",
        24 => "a quadratic tetrahedron",
        25 => "a quadratic hexahedron",
        26 => "a quadratic wedge",
        27 => "a quadratic pyramid",
        28 => "a biquadratic quad",
        34 => "a biquadratic triangle",
        42 => "a polyhedron",
        69 => "a Lagrange triangle",
        70 => "a Lagrange quadrilateral",
        _ => return format!("a cell of VTK type {vtk_type}"),
    };
    name.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_is_path_and_kind() {
        let e = VtuError::new(VtuErrorKind::UnsupportedCell { cell: 3, vtk_type: 10 }).with_path("m.vtu");
        assert_eq!(
            e.to_string(),
            "m.vtu: cell 3 is a tetrahedron (VTK type 10); only triangles (5, 22, 34) and quads (9, 23, 28) \
             are read, vertices and lines are skipped"
        );
        let e = VtuError::new(VtuErrorKind::WrongFieldLength { name: "p".into(), expected: 8, found: 7 });
        assert_eq!(e.to_string(), "field \"p\" has 7 values, expected 8");
    }

    #[test]
    fn parse_errors_give_the_line_when_known() {
        let e = VtuError::parse(Some(12), "the file ends inside <Piece>").with_path("m.vtu");
        assert_eq!(e.to_string(), "m.vtu: not a readable VTU file: the file ends inside <Piece> (line 12)");
        assert_eq!(
            VtuError::parse(None, "no <VTKFile> element").to_string(),
            "not a readable VTU file: no <VTKFile> element"
        );
    }

    #[test]
    fn io_errors_keep_their_kind_and_read_lowercase() {
        let e = VtuError::io(false, io::Error::new(io::ErrorKind::NotFound, "No such file."));
        assert_eq!(e.io_kind(), Some(io::ErrorKind::NotFound));
        assert_eq!(e.to_string(), "cannot read the file: no such file");
        let e = VtuError::io(true, io::Error::new(io::ErrorKind::StorageFull, "Disk\nfull"));
        assert_eq!(e.to_string(), "cannot write the file: disk full");
    }

    #[test]
    fn one_line_keeps_acronyms() {
        assert_eq!(one_line("XML syntax: bad."), "XML syntax: bad");
        assert_eq!(one_line("Invalid data\n format"), "invalid data format");
    }
}
