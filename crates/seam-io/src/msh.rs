//! Reading Gmsh MSH files, versions 4.1 and 2.2, ASCII and binary.
//!
//! [`read_msh`] gives the file's content as an [`Msh`]: nodes in the order the
//! file lists them, elements with 0-based node indices and physical tags,
//! physical names and `$NodeData` fields. [`Msh::surface`] and [`Msh::volume`]
//! turn it into seam's [`SurfaceMesh`] and [`VolumeMesh`].
//!
//! # Node numbering
//!
//! Node `i` of an [`Msh`], and point `i` of the meshes built from it, is the
//! `i`-th node the file lists (MSH 4.1: block after block), whatever its tag.
//! Tags may be sparse; [`Msh::node_tags`] keeps them. Gmsh writes the nodes of a
//! mesh in the same order in 2.2 and 4.1 (its 2.2 writer renumbers their tags
//! 1..n, though). Elements also keep the file order, which differs: the 2.2 writer
//! groups them by type across entities, the 4.1 writer by entity.
//!
//! # Physical groups
//!
//! MSH 4.1 gives physical tags per entity in `$Entities`; each element gets those
//! of its entity. MSH 2.2 gives one physical tag per element (its first tag) and
//! writes an element once per physical group it belongs to; such consecutive
//! copies (same type, entity and nodes) are merged into one element with all the
//! physical tags, keeping the first copy's element tag.
//!
//! # Other sections
//!
//! `$NodeData` is read (see [`NodeData`]); `$Periodic`, `$ElementData`,
//! `$PartitionedEntities`, `$InterpolationScheme`, `$Comments` and any other
//! section are skipped. Elements of a partitioned 4.1 file get no physical tags
//! (they live in `$PartitionedEntities`).

use std::path::Path;

use seam::{Point3, SurfaceMesh, VolumeMesh};

mod builder;
mod cursor;
mod element_types;
mod error;
mod parse;
mod select;
mod write;

pub use error::{Degeneracy, GroupId, Location, MshError, MshErrorKind};
pub use write::{cell_type, face_type, write_msh, write_msh_file, write_volume_msh, write_volume_msh_file};

/// The content of a Gmsh MSH file.
#[derive(Clone, Debug, PartialEq)]
pub struct Msh {
    /// The version and encoding of the file.
    pub format: MshFormat,
    /// Node coordinates, in the order the file lists them (MSH 4.1: block order,
    /// then in-block order).
    pub nodes: Vec<Point3>,
    /// The Gmsh tag of each node, in the same order; tags may be non-contiguous.
    pub node_tags: Vec<u64>,
    /// All elements of every dimension, in file order.
    pub elements: Vec<MshElement>,
    /// The `$PhysicalNames` entries.
    pub physical_names: Vec<PhysicalName>,
    /// One entry per `$NodeData` name; for a name given for several time steps,
    /// the last one in the file.
    pub node_data: Vec<NodeData>,
    /// Physical groups the file names but that cannot be selected, with why
    /// (always empty for MSH files; an Abaqus set that contains a shell
    /// element, a `*SURFACE, TYPE=NODE`, …, see [`crate::abaqus`]). Selecting
    /// one is [`MshErrorKind::UnusableGroup`].
    pub unusable_groups: Vec<UnusableGroup>,
}

/// A physical group that cannot be selected ([`Msh::unusable_groups`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnusableGroup {
    /// The dimension of the group.
    pub dim: u8,
    /// The physical tag.
    pub tag: i32,
    /// Why, in words, with the file and line that define it.
    pub reason: String,
}

/// The version and encoding of an MSH file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MshFormat {
    /// The format version.
    pub version: MshVersion,
    /// Binary (`true`) or ASCII.
    pub binary: bool,
}

/// The MSH versions seam reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MshVersion {
    /// MSH 2.2 (also 2.0 and 2.1, which share its layout).
    V2_2,
    /// MSH 4.1.
    V4_1,
    /// Not an MSH file: an Abaqus or CalculiX input file, read by
    /// [`crate::read_inp`] (`binary` is false). Its group names match
    /// case-insensitively, as Abaqus's do.
    AbaqusInp,
    /// Not an MSH file: an Exodus II file, read by [`crate::read_exodus`]
    /// (`binary` is false).
    ExodusII,
}

/// One element of an MSH file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MshElement {
    /// The Gmsh element tag.
    pub tag: u64,
    /// The Gmsh element type number (2 = 3-node triangle, 3 = 4-node quadrangle, ...).
    pub gmsh_type: u32,
    /// The dimension of the element type (0 to 3).
    pub dim: u8,
    /// The tag of the geometric (elementary) entity the element belongs to.
    pub entity: i32,
    /// The nodes in Gmsh order, as 0-based indices into [`Msh::nodes`].
    pub nodes: Vec<usize>,
    /// The physical groups the element belongs to.
    pub physical_tags: Vec<i32>,
}

impl MshElement {
    /// Its type in words, for messages: "an 8-node hexahedron", "a 3-node triangle".
    pub fn type_name(&self) -> String {
        element_types::describe_type(self.gmsh_type)
    }
}

/// An entry of `$PhysicalNames`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PhysicalName {
    /// The dimension of the group.
    pub dim: u8,
    /// The physical tag.
    pub tag: i32,
    /// The name, without quotes.
    pub name: String,
}

/// A `$NodeData` field over the nodes of the file.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeData {
    /// The name (the first string tag).
    pub name: String,
    /// The time step index (the first integer tag).
    pub time_step: i32,
    /// Values per node (1, 3 or 9 in Gmsh).
    pub components: usize,
    /// `n_nodes * components` values in node order (the order of [`Msh::nodes`]);
    /// NaN for nodes the file gives no value for.
    pub values: Vec<f64>,
}

impl NodeData {
    /// The values of node `i` (0-based index into [`Msh::nodes`]).
    pub fn node_values(&self, i: usize) -> &[f64] {
        &self.values[i * self.components..(i + 1) * self.components]
    }
}

impl Msh {
    /// A mesh of this format without nodes, elements or groups.
    pub(crate) fn empty(format: MshFormat) -> Msh {
        Msh {
            format,
            nodes: Vec::new(),
            node_tags: Vec::new(),
            elements: Vec::new(),
            physical_names: Vec::new(),
            node_data: Vec::new(),
            unusable_groups: Vec::new(),
        }
    }

    /// The `$NodeData` field called `name`, if any.
    pub fn node_data(&self, name: &str) -> Option<&NodeData> {
        self.node_data.iter().find(|d| d.name == name)
    }
}

/// Reads an MSH 4.1 or 2.2 file, ASCII or binary, from memory.
///
/// # Errors
/// An [`MshError`] with the line (ASCII) or byte offset (binary) of the problem:
/// not an MSH file, unsupported version, truncated file, malformed value,
/// non-finite coordinate, element referring to an unknown node, ...
pub fn read_msh(bytes: &[u8]) -> Result<Msh, MshError> {
    parse::parse_msh(bytes)
}

/// Reads an MSH file from disk; every error names the path.
///
/// # Errors
/// As [`read_msh`], plus I/O errors (see [`MshError::io_kind`]), among them a
/// path that is not a regular file ("is a directory", "is not a regular file").
pub fn read_msh_file(path: impl AsRef<Path>) -> Result<Msh, MshError> {
    let path = path.as_ref();
    let bytes =
        crate::read_regular_file(path).map_err(|e| MshError::new(MshErrorKind::Io(e)).with_path(path))?;
    read_msh(&bytes).map_err(|e| e.with_path(path))
}

/// Reads the surface to couple from an MSH file, or an Abaqus input file
/// by its extension `.inp`: [`read_model_file`](crate::read_model_file) then
/// [`Msh::surface`]. Every error names the path.
///
/// # Errors
/// As [`read_model_file`](crate::read_model_file) and [`Msh::surface`].
pub fn read_surface_file(path: impl AsRef<Path>, group: Option<&str>) -> Result<SurfaceMesh, MshError> {
    let path = path.as_ref();
    crate::read_model_file(path, None)?.surface(group).map_err(|e| e.with_path(path))
}

/// [`read_surface_file`], with the element tag of each face
/// ([`Msh::surface_face_tags`]: `None` for the boundary of the volume cells;
/// for `.inp` files [`crate::abaqus::face_tag`]).
///
/// # Errors
/// As [`read_surface_file`].
pub fn read_tagged_surface_file(
    path: impl AsRef<Path>,
    group: Option<&str>,
) -> Result<(SurfaceMesh, Option<Vec<u64>>), MshError> {
    let path = path.as_ref();
    let msh = crate::read_model_file(path, None)?;
    let surface = msh.surface(group).map_err(|e| e.with_path(path))?;
    Ok((surface, msh.surface_face_tags(group).map_err(|e| e.with_path(path))?))
}

/// Reads the volume cells from an MSH file, or an Abaqus input file by its
/// extension `.inp`: [`read_model_file`](crate::read_model_file) then
/// [`Msh::volume`]. Every error names the path.
///
/// # Errors
/// As [`read_model_file`](crate::read_model_file) and [`Msh::volume`].
pub fn read_volume_file(path: impl AsRef<Path>, group: Option<&str>) -> Result<VolumeMesh, MshError> {
    let path = path.as_ref();
    crate::read_model_file(path, None)?.volume(group).map_err(|e| e.with_path(path))
}
