//! Reading Abaqus and CalculiX input files (`.inp`) into an [`Msh`].
//!
//! [`read_inp_file`] (or [`read_inp`] for bytes in memory) gives the model's
//! mesh as an [`Msh`] whose [`MshFormat::version`](crate::MshFormat) is
//! [`MshVersion::AbaqusInp`](crate::MshVersion::AbaqusInp), so that
//! [`Msh::volume`], [`Msh::surface_of_volume`] and the rest select from it as
//! from a Gmsh file:
//!
//! - **Nodes** (`*NODE`, rectangular coordinates) keep their ids as
//!   [`Msh::node_tags`], in file order.
//! - **Elements** (`*ELEMENT, TYPE=…`) of the solid types C3D4, C3D10, C3D8,
//!   C3D20, C3D27, C3D6 and C3D15 (with any of the letters R, I, H, M, T, S
//!   after them: C3D8R, C3D20RH, C3D10M, …) become cells with their ids as
//!   element tags, nodes in Gmsh's order (the node orders and face numbering
//!   are in the table of `abaqus/types.rs`). Elements of any other type
//!   (S4, B31, CPS4, SPRING1, unknown names…) are skipped; a set or surface
//!   that contains one cannot be selected, and the message names its type.
//! - **Element sets** (`*ELSET`, with `GENERATE`, names of other sets and
//!   ids; `ELSET=` of `*ELEMENT`) are volume (dimension-3) physical groups
//!   named as the file writes them. In a `GENERATE` range, ids that are no
//!   element are left out.
//! - **Surfaces** (`*SURFACE, TYPE=ELEMENT`, lines `element or set, Sk`,
//!   `_S1`-style sets included) are dimension-2 physical groups of face
//!   elements: face `Sk` of element `E` is one element whose tag is
//!   [`face_tag`]`(E, k)` = 10¹⁸ + 10·E + k (shown as "element E face Sk" in
//!   messages), with the nodes of the cell's face in Gmsh's face order
//!   (Tri6, Quad8 or Quad9 for second-order cells). A face in several
//!   surfaces is one element in several groups. `TYPE=NODE` and other
//!   surface types cannot be selected, with a message that says why.
//! - Every other keyword (`*MATERIAL`, `*STEP`, `*BOUNDARY`, `*NSET`, …) is
//!   skipped with its data lines.
//!
//! # Syntax
//!
//! Keywords and option names in any case and with any blanks (`*Solid
//! Section`); keyword lines continued by a trailing comma; `**` comments and
//! blank lines anywhere; quoted option values. An element's data may go on
//! over several lines (C3D20's 20 nodes over two): a line continues until the
//! type's node count is read. Numbers as Abaqus writes them (`1.`, `.5`,
//! `1.5E+3`, `1.5D3`; an empty coordinate is 0). `*INCLUDE, INPUT=FILE` reads
//! `FILE` relative to the including file ([`read_inp_file`] only).
//!
//! # Names
//!
//! Abaqus names are case-insensitive: sets and surfaces keep the spelling of
//! their first definition, later definitions of the same name in any case
//! add to them, and [`Msh::group_tag`] matches names without regard to ASCII
//! case for these files.
//!
//! # Parts, instances and assembly
//!
//! A `*PART` is a template: its nodes, elements, sets and surfaces are in the
//! mesh once per `*INSTANCE` of it (plus whatever the `*INSTANCE` block
//! defines itself), moved by the instance's translation, with names
//! qualified by the instance: `Part-1-1.Set-1`. Rotated instances are
//! refused. Definitions outside parts and instances (the assembly level, or
//! a file without parts) are named as written; an `*ELSET, INSTANCE=…` of the
//! assembly refers to that instance's elements, and `Instance.Set` or
//! `Instance.12` to an instance's set or element.
//!
//! Ids: when only one instance (or the top level) has nodes or elements, the
//! ids are the file's. Otherwise the `j`-th of those (`j` = 0, 1, …;
//! instances in file order, then the top level) adds `j·10^k` to its node and
//! element ids, `10^k` the smallest power of ten above every id of the file:
//! with ids below 1000, instance 2's node 17 is node 1017.
//!
//! # Errors and limits
//!
//! An [`InpError`] is one line, `FILE:LINE: cause`: a malformed number,
//! an element with too many or too few nodes, an element referring to a node
//! that is not defined, an id defined twice, a rotated instance, an include
//! cycle or missing include file, … Memory stays within a small multiple of
//! the input's size: a `GENERATE` range longer than the input's byte count,
//! instances repeating more nodes and elements than it, or sets holding more
//! than four elements per byte are refused before they are built.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use crate::msh::Msh;

mod build;
mod input;
mod read;
mod types;

pub(crate) use build::face_element;
pub(crate) use types::face_with_corners;

/// Where a line is: the file (index into the files read) and the 1-based line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Loc {
    file: u32,
    line: u32,
}

/// The smallest element tag of a face element: face `Sk` of element `E` is
/// `FACE_TAG_BASE + 10·E + k`.
pub const FACE_TAG_BASE: u64 = 1_000_000_000_000_000_000;

/// The element tag of face `S{face}` of element `element` in an [`Msh`] read
/// from an `.inp` file: 10¹⁸ + 10·element + face.
pub fn face_tag(element: u64, face: u8) -> u64 {
    FACE_TAG_BASE + 10 * element + u64::from(face)
}

/// The element and face number of a tag made by [`face_tag`], if it is one
/// (tags from 10¹⁸ on whose last digit is 1 to 6).
pub fn split_face_tag(tag: u64) -> Option<(u64, u8)> {
    let rest = tag.checked_sub(FACE_TAG_BASE)?;
    let face = (rest % 10) as u8;
    (1..=6).contains(&face).then_some((rest / 10, face))
}

/// How messages name an element: "element 17", or for a face tag made by
/// [`face_tag`] "element 17 face S3".
pub fn element_label(tag: u64) -> String {
    match split_face_tag(tag) {
        Some((element, face)) => format!("element {element} face S{face}"),
        None => format!("element {tag}"),
    }
}

/// An error reading an `.inp` file: the file and line, when known, and the
/// cause. Displays on one line, `part.inp:12: cause` (`line 12: cause` for
/// bytes in memory).
#[derive(Debug)]
pub struct InpError {
    path: Option<PathBuf>,
    line: Option<usize>,
    message: String,
    io_kind: Option<io::ErrorKind>,
}

impl InpError {
    fn new(message: impl Into<String>) -> InpError {
        InpError { path: None, line: None, message: message.into(), io_kind: None }
    }

    /// The same error at `line` (0: no line) of the file at `path`.
    fn at(mut self, path: Option<PathBuf>, line: u32) -> InpError {
        self.path = path;
        self.line = (line > 0).then_some(line as usize);
        self
    }

    /// The file the error is in (an included file for an error there), if
    /// read from a path.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The 1-based line, if the error is about one.
    pub fn line(&self) -> Option<usize> {
        self.line
    }

    /// The cause, without file and line.
    pub fn message(&self) -> &str {
        &self.message
    }

    /// The I/O error kind, if the input file itself could not be read.
    pub fn io_kind(&self) -> Option<io::ErrorKind> {
        self.io_kind
    }
}

impl fmt::Display for InpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.path, self.line) {
            (Some(path), Some(line)) => write!(f, "{}:{line}: ", path.display())?,
            (Some(path), None) => write!(f, "{}: ", path.display())?,
            (None, Some(line)) => write!(f, "line {line}: ")?,
            (None, None) => {}
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for InpError {}

/// Reads an Abaqus or CalculiX input file from memory (see the
/// [module documentation](self)).
///
/// # Errors
/// An [`InpError`] naming the line; `*INCLUDE` is refused, as bytes in memory
/// have no directory to find the included file in (use [`read_inp_file`]).
pub fn read_inp(bytes: &[u8]) -> Result<Msh, InpError> {
    read_sources(input::Sources::new(bytes.to_vec(), None))
}

/// Reads an Abaqus or CalculiX input file and the files it includes (see the
/// [module documentation](self)).
///
/// # Errors
/// An [`InpError`] naming the file (the included one for an error there) and
/// the line, or the I/O error of the file itself ([`InpError::io_kind`]).
pub fn read_inp_file(path: impl AsRef<Path>) -> Result<Msh, InpError> {
    let path = path.as_ref();
    let bytes = crate::read_regular_file(path).map_err(|e| {
        let mut error = InpError::new(format!("cannot read the file: {}", e.to_string().to_lowercase()))
            .at(Some(path.to_path_buf()), 0);
        error.io_kind = Some(e.kind());
        error
    })?;
    read_inp_read_from(bytes, path)
}

/// Reads the bytes of the input file at `path`, already read (its
/// `*INCLUDE`s relative to it): [`read_inp_file`] after the read.
pub(crate) fn read_inp_read_from(bytes: Vec<u8>, path: &Path) -> Result<Msh, InpError> {
    read_sources(input::Sources::new(bytes, Some(path.to_path_buf())))
}

fn read_sources(mut sources: input::Sources) -> Result<Msh, InpError> {
    let model = read::read_model(&mut sources)?;
    build::build(&model, &sources)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_tags_round_trip() {
        assert_eq!(face_tag(17, 3), 1_000_000_000_000_000_173);
        assert_eq!(split_face_tag(face_tag(17, 3)), Some((17, 3)));
        assert_eq!(split_face_tag(face_tag(0, 6)), Some((0, 6)));
        assert_eq!(split_face_tag(17), None);
        assert_eq!(split_face_tag(FACE_TAG_BASE + 170), None);
        assert_eq!(split_face_tag(FACE_TAG_BASE + 177), None);
        assert_eq!(element_label(face_tag(17, 3)), "element 17 face S3");
        assert_eq!(element_label(17), "element 17");
    }

    #[test]
    fn errors_read_file_line_cause() {
        let e = InpError::new("bad").at(Some("a.inp".into()), 3);
        assert_eq!(e.to_string(), "a.inp:3: bad");
        assert_eq!(InpError::new("bad").at(None, 3).to_string(), "line 3: bad");
        assert_eq!(InpError::new("bad").at(Some("a.inp".into()), 0).to_string(), "a.inp: bad");
    }
}
