//! Reading Exodus II model files (`.e`, `.exo`, `.ex2`, `.g`) into an
//! [`Msh`].
//!
//! Exodus II is a convention over netCDF; seam reads it with the pure-Rust
//! [`netcdf-reader`](https://crates.io/crates/netcdf-reader) crate (and its
//! HDF5 reader, `hdf5-reader`), from the bytes in memory, in all three
//! flavours Cubit, MOOSE and SEACAS write: classic, 64-bit offset and
//! NetCDF-4 (HDF5). It replaced the netCDF C library (the `netcdf` crate
//! over libnetcdf and libhdf5), in which a damaged NetCDF-4 file read after a
//! valid one in the same process crashed HDF5 (found by the `exodus` fuzz
//! target): a Rust reader returns an error instead, needs no system library,
//! and is fuzzed with seam. It is part of every build (the cargo feature
//! `exodus` of the C library's days is kept, and does nothing).
//!
//! [`read_exodus_file`] (or [`read_exodus`] for bytes in memory) gives an
//! [`Msh`] whose [`MshFormat::version`](crate::MshFormat) is
//! [`MshVersion::ExodusII`](crate::MshVersion::ExodusII):
//!
//! - **Nodes** (`coord` or `coordx`/`coordy`/`coordz`, `num_dim` = 3) keep
//!   the ids of `node_num_map` (1, 2, … without one) as [`Msh::node_tags`].
//! - **Element blocks** of the types TETRA4, TETRA10, HEX8, HEX20, HEX27,
//!   WEDGE6, WEDGE15, WEDGE18, PYRAMID5, PYRAMID13 and PYRAMID14 (also spelled TETRA,
//!   TET4, HEX, HEXAHEDRON, WEDGE, PYRAMID, PYRA5…: the name without digits
//!   and the block's nodes per element decide) are cells with the ids of
//!   `elem_num_map` (1, 2, … without one) as element tags, nodes in Gmsh's
//!   order (the table of `exodus/types.rs`). Each block is a volume
//!   (dimension-3) physical group whose tag is the block id (`eb_prop1`;
//!   meshio numbers blocks from 0) and whose name is its `eb_names` entry:
//!   `volume = "block name or id"`. A block of any other type (SHELL4,
//!   BEAM2, TRI3, TETRA14, an unknown name) has no cells: selecting it, or a
//!   side set on it, is refused with a message naming its type.
//! - **Side sets** are surface (dimension-2) physical groups tagged by their
//!   id (`ss_prop1`) and named by `ss_names`: side `k` of element `E` is one
//!   face element whose tag is [`face_tag`](crate::abaqus::face_tag)`(E, k)`
//!   (E the element's id; messages say "element E face Sk"), its nodes
//!   those of the cell's face. A side in several side sets is one element in
//!   several groups. Node sets, attributes, variables and time steps are
//!   not read.
//!
//! The node orders and side numbering come from the SEACAS Exodus library
//! itself (`ex_get_side_set_node_list`, see `exodus/types.rs`), WEDGE18's
//! face centres (which the library does not place) from SEACAS's IOSS;
//! TETRA14/15, WEDGE21 and PYRAMID18/19 are refused by name.
//!
//! # Errors and limits
//!
//! An [`ExodusError`] is one line: the file, the block or side set, and the
//! cause (`body.exo: element block 2 ("steel"): connect2 refers to node 91,
//! the file has 90 nodes`). Before an array is read its declared length is
//! checked against the file's size (a classic file stores every value; a
//! NetCDF-4 file compresses at most about 1000 to 1), so that a file
//! declaring huge counts is refused before memory is allocated for them;
//! the same bound, in bytes, limits what the HDF5 reader decodes for one
//! array or one chunk. A file whose header (or HDF5 metadata) is damaged is
//! refused when opened: `not a readable netCDF file (truncated or corrupt):`
//! and netcdf-reader's cause.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use crate::msh::Msh;

mod read;
mod types;

/// An error reading an Exodus II file: the file, when known, and the cause
/// (which names the block or side set). Displays on one line,
/// `body.exo: cause`.
#[derive(Debug)]
pub struct ExodusError {
    path: Option<PathBuf>,
    message: String,
    io_kind: Option<io::ErrorKind>,
}

impl ExodusError {
    pub(crate) fn new(message: impl Into<String>) -> ExodusError {
        ExodusError { path: None, message: message.into(), io_kind: None }
    }

    fn with_path(mut self, path: &Path) -> ExodusError {
        self.path = Some(path.to_path_buf());
        self
    }

    /// The file, if read from a path.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The cause, without the file.
    pub fn message(&self) -> &str {
        &self.message
    }

    /// The I/O error kind, if the file itself could not be read.
    pub fn io_kind(&self) -> Option<io::ErrorKind> {
        self.io_kind
    }
}

impl fmt::Display for ExodusError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(path) = &self.path {
            write!(f, "{}: ", path.display())?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for ExodusError {}

/// Reads an Exodus II file from memory (see the [module documentation](self)).
///
/// # Errors
/// An [`ExodusError`] naming the block or side set and the cause.
pub fn read_exodus(bytes: &[u8]) -> Result<Msh, ExodusError> {
    read::read(bytes)
}

/// Reads an Exodus II file (see the [module documentation](self)).
///
/// # Errors
/// As [`read_exodus`], naming the file; or the I/O error of the file
/// ([`ExodusError::io_kind`]).
pub fn read_exodus_file(path: impl AsRef<Path>) -> Result<Msh, ExodusError> {
    let path = path.as_ref();
    let bytes = crate::read_regular_file(path).map_err(|e| {
        let mut error = ExodusError::new(format!("cannot read the file: {}", e.to_string().to_lowercase()))
            .with_path(path);
        error.io_kind = Some(e.kind());
        error
    })?;
    read_exodus_read_from(&bytes, path)
}

/// [`read_exodus_file`] after the read.
pub(crate) fn read_exodus_read_from(bytes: &[u8], path: &Path) -> Result<Msh, ExodusError> {
    read_exodus(bytes).map_err(|e| e.with_path(path))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_read_file_cause() {
        let e = ExodusError::new("bad").with_path(Path::new("a.exo"));
        assert_eq!(e.to_string(), "a.exo: bad");
        assert_eq!(ExodusError::new("bad").to_string(), "bad");
    }
}
