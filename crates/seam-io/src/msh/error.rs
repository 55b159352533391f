//! [`MshError`]: what went wrong, in which file, and where.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use seam::MeshError;

use super::element_types::describe_type;
use crate::abaqus::element_label;

/// Where in a file an error is: a line for ASCII files, a byte offset for binary
/// ones (where lines mean nothing).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// 1-based line number.
    Line(usize),
    /// 0-based byte offset.
    Offset(usize),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(n) => write!(f, "line {n}"),
            Location::Offset(n) => write!(f, "byte {n}"),
        }
    }
}

/// A physical group as an error message lists it: its number and, if the file
/// names it in `$PhysicalNames`, its name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GroupId {
    /// The physical tag.
    pub tag: i32,
    /// The name from `$PhysicalNames`, if any.
    pub name: Option<String>,
}

impl fmt::Display for GroupId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.name {
            Some(name) => write!(f, "{name:?} ({})", self.tag),
            None => write!(f, "{}", self.tag),
        }
    }
}

/// Why a face or cell is degenerate.
#[derive(Clone, Debug, PartialEq)]
pub enum Degeneracy {
    /// The element lists the same node twice.
    RepeatedNode {
        /// The Gmsh tag of the repeated node.
        node_tag: u64,
    },
    /// The face has (numerically) zero area.
    ZeroArea,
    /// The face is smaller than [`seam::MIN_FACE_SIZE`].
    TooSmall {
        /// Its diameter.
        diameter: f64,
    },
    /// A face of the cell on the boundary of the volume is degenerate.
    BoundaryFace {
        /// The face within the cell, in the order of [`seam::CellType::faces`].
        local_face: usize,
        /// "has zero area" or "is too small".
        why: &'static str,
    },
}

impl fmt::Display for Degeneracy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Degeneracy::RepeatedNode { node_tag } => write!(f, "node {node_tag} appears twice"),
            Degeneracy::ZeroArea => write!(f, "its area is zero"),
            Degeneracy::TooSmall { diameter } => write!(
                f,
                "its diameter {diameter:.3e} is below the smallest size seam computes with ({:e})",
                seam::MIN_FACE_SIZE
            ),
            Degeneracy::BoundaryFace { local_face, why } => write!(f, "its boundary face {local_face} {why}"),
        }
    }
}

/// What is wrong, without the file name and location (see [`MshError`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MshErrorKind {
    /// The file could not be read.
    #[error("cannot read the file: {}", lowercase_first(&.0.to_string()))]
    Io(io::Error),
    /// The input does not start with `$MeshFormat`.
    #[error("not a Gmsh MSH file: expected $MeshFormat at the start, found {found}")]
    NotMsh {
        /// What the file starts with (quoted), or "an empty file".
        found: String,
    },
    /// An MSH version other than 2.2 and 4.1 (or a data size other than 4/8).
    #[error("unsupported MSH version {version}: seam reads versions 2.2 and 4.1 (set Mesh.MshFileVersion in Gmsh)")]
    UnsupportedVersion {
        /// The version as the file gives it.
        version: String,
    },
    /// The file ends inside a section.
    #[error("truncated file: it ends inside the ${section} section, before $End{section}")]
    Truncated {
        /// The section name without `$`, for example `Nodes`.
        section: String,
    },
    /// A section is not closed by its `$End...` line.
    #[error("expected $End{section} to close the ${section} section, found {found}")]
    MissingEnd {
        /// The section name without `$`.
        section: String,
        /// What the file has instead (quoted).
        found: String,
    },
    /// The text or data does not have the expected form.
    #[error("expected {expected}, found {found}")]
    Parse {
        /// What the reader expected.
        expected: String,
        /// What the file has instead (quoted, or for example "end of line").
        found: String,
    },
    /// A count is more than the rest of its section can hold.
    #[error("{what} is {count}, more than the {bytes} bytes before $End{section} can hold (at most {room})")]
    CountTooLarge {
        /// What the count counts, for example `the number of nodes of entity (0, 1)`.
        what: String,
        /// The count.
        count: u64,
        /// The bytes from the count to the section's `$End` line.
        bytes: u64,
        /// The most records these bytes can hold.
        room: u64,
        /// The section name without `$`.
        section: String,
    },
    /// Binary data that make sense only in the byte order the byte-order
    /// check of `$MeshFormat` does not announce.
    #[error(
        "byte-swapped data: {what} is {announced} in the {} byte order that the check integer of \
         $MeshFormat announces, {other} in the other; the data and the check disagree (write the file \
         again with Gmsh)",
        if *.big_endian { "big-endian" } else { "little-endian" }
    )]
    ByteSwapped {
        /// What was read, for example `the number of entities of dimension 0`.
        what: String,
        /// What it is in the announced byte order.
        announced: String,
        /// What it is in the other.
        other: String,
        /// Whether the check announces big-endian.
        big_endian: bool,
    },
    /// A node coordinate is NaN or infinite.
    #[error("node {node_tag} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// The Gmsh node tag.
        node_tag: u64,
    },
    /// A node coordinate is finite but beyond [`seam::MAX_MAGNITUDE`].
    #[error("node {node_tag} has coordinate {value:e}, out of range (|x| ≤ {:e})", seam::MAX_MAGNITUDE)]
    CoordinateOutOfRange {
        /// The Gmsh node tag.
        node_tag: u64,
        /// The coordinate.
        value: f64,
    },
    /// Two nodes have the same tag.
    #[error("node {node_tag} is defined twice")]
    DuplicateNode {
        /// The Gmsh node tag.
        node_tag: u64,
    },
    /// An element lists a node tag that `$Nodes` does not define.
    #[error("element {element_tag} refers to node {node_tag}, which the $Nodes section does not define")]
    UnknownNode {
        /// The Gmsh element tag.
        element_tag: u64,
        /// The unknown node tag.
        node_tag: u64,
    },
    /// A `$NodeData` entry names a node tag that `$Nodes` does not define.
    #[error("node data {name:?} refers to node {node_tag}, which the $Nodes section does not define")]
    UnknownDataNode {
        /// The name of the data (its first string tag).
        name: String,
        /// The unknown node tag.
        node_tag: u64,
    },
    /// No physical group of the wanted dimension has this name or number.
    #[error("no physical group {group:?} of dimension {dim} (by name or number); {}", list_groups(*.dim, .available))]
    UnknownGroup {
        /// The wanted dimension (2 for surfaces, 3 for volumes).
        dim: u8,
        /// The name or number asked for.
        group: String,
        /// The groups of that dimension the file has.
        available: Vec<GroupId>,
    },
    /// A selected element has a type seam cannot use there.
    #[error("{} is {} (type {gmsh_type}); only {supported} are supported", element_label(*.element_tag), describe_type(*.gmsh_type))]
    UnsupportedElement {
        /// The Gmsh element tag.
        element_tag: u64,
        /// The Gmsh element type number.
        gmsh_type: u32,
        /// The supported types in words.
        supported: &'static str,
    },
    /// An element lists a number of nodes that does not fit its type (only
    /// possible for an [`Msh`](super::Msh) built by hand).
    #[error("{} is {} (type {gmsh_type}) but lists {found} nodes", element_label(*.element_tag), describe_type(*.gmsh_type))]
    WrongNodeCount {
        /// The Gmsh element tag.
        element_tag: u64,
        /// The Gmsh element type number.
        gmsh_type: u32,
        /// The number of nodes it lists.
        found: usize,
    },
    /// A face or cell is degenerate.
    #[error("{} is degenerate: {reason}", element_or_face(*.element_tag))]
    Degenerate {
        /// The Gmsh element tag (`None` only for an [`Msh`](super::Msh) built by hand).
        element_tag: Option<u64>,
        /// What is degenerate about it.
        reason: Degeneracy,
    },
    /// Any other mesh inconsistency [`seam`] reports (for example a node index out
    /// of range in an [`Msh`](super::Msh) built by hand).
    #[error("invalid mesh at {}: {problem}", element_or_face(*.element_tag))]
    InvalidMesh {
        /// The Gmsh element tag, if known.
        element_tag: Option<u64>,
        /// The error from [`seam`], with 0-based indices.
        problem: MeshError,
    },
    /// The selection has no faces.
    #[error("no faces found in {selection}")]
    NoFaces {
        /// What was selected, for example `physical group "top" (2)`.
        selection: String,
    },
    /// A face of a body's surface is no face of the body's cells (its
    /// corners are their nodes): a surface meshed apart from the volume, or
    /// quadrilaterals cut along the other diagonal than the cells' faces, or
    /// a face inside the body.
    #[error(
        "{} of {surface} is {} of {volume}: a body's surface must be made of its cells' faces",
        element_label(*.element_tag),
        if *interior { "a face between two cells" } else { "not a face of any cell" }
    )]
    NotACellFace {
        /// The surface's group, for example `physical group "top" (2)`.
        surface: String,
        /// The body's cells, for example `physical group "lower" (1)`.
        volume: String,
        /// The Gmsh tag of the face.
        element_tag: u64,
        /// The face is one of two cells (inside the body), not of none.
        interior: bool,
    },
    /// A face of a surface has a node that no cell of the selected volume has.
    #[error("{} of {surface} is not on {volume}: its node {node_tag} is in no cell of that volume", element_label(*.element_tag))]
    NotOnVolume {
        /// The surface's group, for example `physical group "top" (2)`.
        surface: String,
        /// The volume's group.
        volume: String,
        /// The Gmsh tag of the face.
        element_tag: u64,
        /// The Gmsh tag of the node.
        node_tag: u64,
    },
    /// The selection has no volume cells.
    #[error("no volume cells found in {selection}")]
    NoCells {
        /// What was selected.
        selection: String,
    },
    /// The group is one of [`Msh::unusable_groups`](super::Msh::unusable_groups).
    #[error("{group} cannot be used: {reason}")]
    UnusableGroup {
        /// The group, for example `physical group "SLAVE" (4)`.
        group: String,
        /// Why, with the file and line that define it.
        reason: String,
    },
    /// An Abaqus or CalculiX input file could not be read
    /// ([`crate::read_model_file`]): the reader's error, which names the file
    /// (an included one for an error there) and the line.
    #[error("{0}")]
    Abaqus(crate::InpError),
    /// An Exodus II file could not be read ([`crate::read_model_file`]): the
    /// reader's error, which names the file, the block or side set and the
    /// cause.
    #[error("{0}")]
    Exodus(crate::ExodusError),
}

fn lowercase_first(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(c) => c.to_lowercase().chain(chars).collect(),
        None => String::new(),
    }
}

fn list_groups(dim: u8, groups: &[GroupId]) -> String {
    if groups.is_empty() {
        return format!("the file has no physical groups of dimension {dim}");
    }
    let list: Vec<String> = groups.iter().map(GroupId::to_string).collect();
    format!("available: {}", list.join(", "))
}

fn element_or_face(element_tag: Option<u64>) -> String {
    match element_tag {
        Some(tag) => element_label(tag),
        None => "a boundary face".to_string(),
    }
}

/// An error reading or interpreting a Gmsh MSH file, or selecting from an
/// [`Msh`](super::Msh) of any file ([`crate::read_model_file`]: an Abaqus
/// input file's reading errors are [`MshErrorKind::Abaqus`]): the file (when
/// read from a path), the location in it (when known) and the
/// [`MshErrorKind`].
///
/// Displays on one line, for example
/// `mesh.msh: line 17: expected 3 coordinates for node 4, found "1.0 abc"`,
/// or `part.inp:12: cause` for an `.inp` file's reading error.
#[derive(Debug)]
pub struct MshError {
    path: Option<PathBuf>,
    location: Option<Location>,
    kind: MshErrorKind,
}

impl MshError {
    /// An error without path or location.
    pub fn new(kind: MshErrorKind) -> Self {
        MshError { path: None, location: None, kind }
    }

    /// An error at a location in the input.
    pub fn at(location: Location, kind: MshErrorKind) -> Self {
        MshError { path: None, location: Some(location), kind }
    }

    /// The same error, attributed to the file at `path`.
    #[must_use]
    pub fn with_path(mut self, path: impl AsRef<Path>) -> Self {
        self.path = Some(path.as_ref().to_path_buf());
        self
    }

    /// What went wrong.
    pub fn kind(&self) -> &MshErrorKind {
        &self.kind
    }

    /// The file, if the error came from reading a path.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// Where in the file, if known.
    pub fn location(&self) -> Option<Location> {
        self.location
    }

    /// The I/O error kind, if the file could not be read.
    pub fn io_kind(&self) -> Option<io::ErrorKind> {
        match &self.kind {
            MshErrorKind::Io(e) => Some(e.kind()),
            MshErrorKind::Abaqus(e) => e.io_kind(),
            MshErrorKind::Exodus(e) => e.io_kind(),
            _ => None,
        }
    }
}

/// An `.inp` reader's error as an [`MshErrorKind::Abaqus`], with its file
/// and line as [`MshError::path`] and [`MshError::location`]; it displays as
/// the reader's error does (`part.inp:12: cause`).
impl From<crate::InpError> for MshError {
    fn from(e: crate::InpError) -> Self {
        MshError {
            path: e.path().map(Path::to_path_buf),
            location: e.line().map(Location::Line),
            kind: MshErrorKind::Abaqus(e),
        }
    }
}

/// An Exodus reader's error as an [`MshErrorKind::Exodus`], with its file as
/// [`MshError::path`]; it displays as the reader's error does.
impl From<crate::ExodusError> for MshError {
    fn from(e: crate::ExodusError) -> Self {
        MshError { path: e.path().map(Path::to_path_buf), location: None, kind: MshErrorKind::Exodus(e) }
    }
}

impl From<MshErrorKind> for MshError {
    fn from(kind: MshErrorKind) -> Self {
        MshError::new(kind)
    }
}

impl fmt::Display for MshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.kind {
            // They name their file (and line) themselves.
            MshErrorKind::Abaqus(e) => return write!(f, "{e}"),
            MshErrorKind::Exodus(e) => return write!(f, "{e}"),
            _ => {}
        }
        if let Some(path) = &self.path {
            write!(f, "{}: ", path.display())?;
        }
        if let Some(location) = self.location {
            write!(f, "{location}: ")?;
        }
        write!(f, "{}", self.kind)
    }
}

impl std::error::Error for MshError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_is_path_location_kind() {
        let e = MshError::at(Location::Line(17), MshErrorKind::NonFiniteCoordinate { node_tag: 4 })
            .with_path("m.msh");
        assert_eq!(e.to_string(), "m.msh: line 17: node 4 has a non-finite coordinate");
        let e = MshError::at(Location::Offset(99), MshErrorKind::Truncated { section: "Nodes".into() });
        assert_eq!(
            e.to_string(),
            "byte 99: truncated file: it ends inside the $Nodes section, before $EndNodes"
        );
    }

    #[test]
    fn io_errors_keep_their_kind_and_read_lowercase() {
        let io = io::Error::new(io::ErrorKind::NotFound, "No such file");
        let e = MshError::new(MshErrorKind::Io(io));
        assert_eq!(e.io_kind(), Some(io::ErrorKind::NotFound));
        assert_eq!(e.to_string(), "cannot read the file: no such file");
    }

    #[test]
    fn unknown_group_lists_the_available_ones() {
        let available = vec![GroupId { tag: 2, name: Some("top".into()) }, GroupId { tag: 5, name: None }];
        let e = MshErrorKind::UnknownGroup { dim: 2, group: "lid".into(), available };
        assert_eq!(
            e.to_string(),
            "no physical group \"lid\" of dimension 2 (by name or number); available: \"top\" (2), 5"
        );
        let e = MshErrorKind::UnknownGroup { dim: 3, group: "1".into(), available: vec![] };
        assert!(e.to_string().ends_with("the file has no physical groups of dimension 3"));
    }
}
