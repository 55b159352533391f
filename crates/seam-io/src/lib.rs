//! File formats for seam.
//!
//! | format | versions | read | write |
//! |---|---|---|---|
//! | [Abaqus / CalculiX input](crate::abaqus) (`.inp`) | `*NODE`, `*ELEMENT` (C3D4, C3D10, C3D8, C3D20, C3D27, C3D6, C3D15 and their R/I/H/M/T variants), `*ELSET`, `*SURFACE, TYPE=ELEMENT`, `*INCLUDE`, `*PART`/`*INSTANCE` (translated); as an [`Msh`] | [`read_inp_file`], [`read_inp`]; by extension or [`ModelFormat`]: [`read_model_file`], [`read_surface_file`], [`read_volume_file`] | no |
//! | [Exodus II](crate::exodus) (`.e`, `.exo`, `.ex2`, `.g`) | classic, 64-bit offset and NetCDF-4; element blocks (TETRA, HEX, WEDGE, PYRAMID, first and second order), side sets, `node_num_map`/`elem_num_map` ids; as an [`Msh`] | [`read_exodus_file`], [`read_exodus`]; by extension or [`ModelFormat`]: [`read_model_file`] | no |
//! | [Gmsh MSH](https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format) | 4.1 and 2.2, ASCII and binary; first- and second-order triangles, quadrangles, tetrahedra, hexahedra, prisms, pyramids | [`read_msh`], [`read_msh_file`], [`read_model_file`], [`read_surface_file`], [`read_volume_file`] | 4.1 ASCII: surfaces [`write_msh`], volumes with named boundaries [`write_volume_msh`] |
//! | [Matrix Market](https://math.nist.gov/MatrixMarket/formats.html) | coordinate real general, 1-based | [`read_matrix_market_str`] | [`write_matrix_market`] |
//! | [VTU](https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html#unstructuredgrid) (VTK XML UnstructuredGrid) | ASCII, binary, appended (base64 or raw), compressed (zlib, LZ4, LZMA) or not, 0.1 to 2.x; linear and quadratic triangles and quads | [`read_vtu_file`], [`read_vtu`] | inline base64, uncompressed: surfaces [`write_vtu`], [`write_vtu_file`], volumes (first and second order, VTK node order) [`write_volume_vtu`] |
//!
//! MSH 2.2 is described in the [legacy section](https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format-version-2-_0028Legacy_0029)
//! of the Gmsh manual. Meshes from Gmsh 4.x are 4.1 by default; set
//! `Mesh.MshFileVersion` (or `-format msh22`) for 2.2.
//!
//! ```no_run
//! let surface = seam_io::read_surface_file("slave.msh", Some("interface"))?;
//! println!("{} faces on {} nodes", surface.n_faces(), surface.n_points());
//! # Ok::<(), seam_io::MshError>(())
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod abaqus;
pub mod exodus;
pub mod model;
pub mod msh;
pub mod mtx;
pub mod vtu;

use std::io;
use std::path::Path;

/// The bytes of the regular file at `path` (symbolic links followed). Anything
/// else is an error before it is opened: a directory (`IsADirectory`, "is a
/// directory"), a device or pipe (`InvalidInput`, "is not a regular file"),
/// which would fail late, never end (`/dev/zero`) or block (a pipe without a
/// writer).
pub(crate) fn read_regular_file(path: &Path) -> io::Result<Vec<u8>> {
    let meta = std::fs::metadata(path)?;
    if meta.is_dir() {
        return Err(io::Error::new(io::ErrorKind::IsADirectory, "is a directory"));
    }
    if !meta.is_file() {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, "is not a regular file"));
    }
    std::fs::read(path)
}

pub use abaqus::{read_inp, read_inp_file, InpError};
pub use exodus::{read_exodus, read_exodus_file, ExodusError};
pub use model::{read_model_file, ModelFormat};
pub use msh::{
    read_msh, read_msh_file, read_surface_file, read_tagged_surface_file, read_volume_file, write_msh,
    write_msh_file, write_volume_msh, write_volume_msh_file, Degeneracy, GroupId, Location, Msh, MshElement,
    MshError, MshErrorKind, MshFormat, MshVersion, NodeData, PhysicalName, UnusableGroup,
};
pub use mtx::{read_matrix_market_str, write_matrix_market, write_matrix_market_file, MatrixMarketError};
pub use vtu::{
    read_vtu, read_vtu_file, write_pvd_file, write_pvtu_file, write_volume_vtu, write_volume_vtu_file,
    write_vtu, write_vtu_file, Field, VtuError, VtuErrorKind, VtuMesh,
};
