//! From an [`Msh`] to seam's meshes: physical group lookup, element type
//! checks, outward orientation, and [`MeshError`]s translated to Gmsh tags.

use std::collections::BTreeMap;

use seam::{Cell, CellKind, Face, FaceKind, FaceOwner, MeshError, SurfaceMesh, VolumeMesh};

use super::{Degeneracy, GroupId, Msh, MshElement, MshError, MshErrorKind, MshVersion};

const FACE_TYPES: &str = "triangles (3 or 6 nodes) and quadrangles (4, 8 or 9 nodes)";
const CELL_TYPES: &str =
    "tetrahedra (4 or 10 nodes), hexahedra (8, 20 or 27), prisms (6, 15 or 18) and pyramids (5, 13 or 14)";

impl Msh {
    /// The surface to couple, with all nodes of the file as its points (in file
    /// order, unused ones included).
    ///
    /// - `group = Some(g)`: the elements of the dimension-2 physical group named
    ///   `g`, or else numbered `g` (`"top"` or `"3"`). If the file has volume
    ///   cells (see [`Msh::volume`]), each face is oriented outward from the
    ///   cell it bounds.
    /// - `group = None`: with volume elements in the file, the boundary of all of
    ///   them, outward (second-order faces for second-order cells, see
    ///   [`VolumeMesh::boundary`]); otherwise all 2D elements (lines and points
    ///   are ignored).
    ///
    /// Faces may be 3-node triangles and 4-node quadrangles (Gmsh types 2, 3)
    /// and their second-order versions, 6-node triangles (9), 8-node (16) and
    /// 9-node (10) quadrangles, mixed in any way; nodes keep Gmsh's order.
    ///
    /// # Errors
    /// Unknown group (the message lists the available ones), an element of
    /// another type (for example third order), no faces, or a degenerate face
    /// or non-finite node, named by its Gmsh tag.
    pub fn surface(&self, group: Option<&str>) -> Result<SurfaceMesh, MshError> {
        match group {
            Some(group) => self.group_surface(group, None),
            None if self.elements.iter().any(|e| e.dim == 3) => {
                let tags = tags_of(&self.volume_elements(None)?);
                self.volume(None)?.boundary().map_err(|e| self.mesh_error(e, &tags))
            }
            None => self.all_faces(),
        }
    }

    /// The Gmsh element tags of the faces of [`Msh::surface`]`(group)`, in its
    /// face order; `None` when those faces are the boundary of the volume
    /// cells (`group = None` in a file with volume elements), which are no
    /// elements of the file.
    ///
    /// # Errors
    /// Unknown group, as [`Msh::surface`].
    pub fn surface_face_tags(&self, group: Option<&str>) -> Result<Option<Vec<u64>>, MshError> {
        Ok(match group {
            Some(group) => Some(tags_of(&self.group_elements(2, self.group_tag(2, group)?))),
            None if self.elements.iter().any(|e| e.dim == 3) => None,
            None => Some(self.elements.iter().filter(|e| e.dim == 2).map(|e| e.tag).collect()),
        })
    }

    /// The faces of the dimension-2 physical group `group` (as in
    /// [`Msh::surface`]) as a surface of the body made of the cells of
    /// `volume` (see [`Msh::volume`]; `None`: all cells): each face is oriented
    /// outward from the body's cells, so a surface between two physical volumes
    /// faces out of the one selected.
    ///
    /// # Errors
    /// Those of [`Msh::surface`] and [`Msh::volume`], and
    /// [`MshErrorKind::NotOnVolume`] for a face with a node that no cell of
    /// `volume` has.
    pub fn surface_of_volume(&self, group: &str, volume: Option<&str>) -> Result<SurfaceMesh, MshError> {
        let cells = self.volume_elements(volume)?;
        let body = match volume {
            Some(volume) => self.describe_group(3, self.group_tag(3, volume)?),
            None => "the file's cells".to_string(),
        };
        let mut used = vec![false; self.nodes.len()];
        for &n in cells.iter().flat_map(|e| &e.nodes) {
            if let Some(u) = used.get_mut(n) {
                *u = true; // an index out of range is VolumeMesh::new's to report
            }
        }
        let tag = self.group_tag(2, group)?;
        if let Some((face, &node)) = self
            .group_elements(2, tag)
            .iter()
            .find_map(|e| e.nodes.iter().find(|&&n| !used.get(n).copied().unwrap_or(false)).map(|n| (e, n)))
        {
            return Err(MshErrorKind::NotOnVolume {
                surface: self.describe_group(2, tag),
                volume: body,
                element_tag: face.tag,
                node_tag: self.node_tags.get(node).copied().unwrap_or(node as u64),
            }
            .into());
        }
        self.group_surface(group, Some((&cells, body)))
    }

    /// The volume cells: all of them, or those of the dimension-3 physical group
    /// named or numbered `group`. Points are all nodes of the file.
    ///
    /// Cells may be 4-node tetrahedra, 8-node hexahedra, 6-node prisms, 5-node
    /// pyramids (Gmsh types 4 to 7) and their second-order versions: 10-node
    /// tetrahedra (11), 20- and 27-node hexahedra (17, 12), 15- and 18-node
    /// prisms (18, 13), 13- and 14-node pyramids (19, 14), mixed in any way;
    /// nodes keep Gmsh's order.
    ///
    /// # Errors
    /// Unknown group, an element of another type (for example third order),
    /// no cells, or a degenerate cell.
    pub fn volume(&self, group: Option<&str>) -> Result<VolumeMesh, MshError> {
        let selected = self.volume_elements(group)?;
        let cells = selected.iter().map(|e| cell_of(e)).collect::<Result<Vec<_>, _>>()?;
        let tags = tags_of(&selected);
        VolumeMesh::new(self.nodes.clone(), cells).map_err(|e| self.mesh_error(e, &tags))
    }

    /// The elements [`Msh::volume`] makes its cells of, in the same order: cell
    /// `i` of the volume is `volume_elements(group)?[i]`, so its Gmsh tag is
    /// `.tag` (for messages about cells).
    ///
    /// # Errors
    /// Unknown group, or no cells in the selection.
    pub fn volume_elements(&self, group: Option<&str>) -> Result<Vec<&MshElement>, MshError> {
        let (selected, selection) = match group {
            Some(group) => {
                let tag = self.group_tag(3, group)?;
                (self.group_elements(3, tag), self.describe_group(3, tag))
            }
            None => (self.elements.iter().filter(|e| e.dim == 3).collect(), "the file".to_string()),
        };
        if selected.is_empty() {
            return Err(MshErrorKind::NoCells { selection }.into());
        }
        Ok(selected)
    }

    /// The physical groups of dimension `dim`: those named in `$PhysicalNames`
    /// and those elements of that dimension belong to, by tag.
    pub fn physical_groups(&self, dim: u8) -> Vec<GroupId> {
        let mut groups: BTreeMap<i32, Option<String>> = BTreeMap::new();
        for element in self.elements.iter().filter(|e| e.dim == dim) {
            for &tag in &element.physical_tags {
                groups.entry(tag).or_default();
            }
        }
        for unusable in self.unusable_groups.iter().filter(|u| u.dim == dim) {
            groups.entry(unusable.tag).or_default();
        }
        for name in self.physical_names.iter().filter(|n| n.dim == dim) {
            groups.insert(name.tag, Some(name.name.clone()));
        }
        groups.into_iter().map(|(tag, name)| GroupId { tag, name }).collect()
    }

    /// The tag of the dimension-`dim` physical group named `group`, or else
    /// numbered `group`. Names read from an Abaqus file
    /// ([`MshVersion::AbaqusInp`]) match without regard to ASCII case.
    ///
    /// # Errors
    /// [`MshErrorKind::UnknownGroup`], listing the groups of that dimension;
    /// [`MshErrorKind::UnusableGroup`] for a group of
    /// [`Msh::unusable_groups`].
    pub fn group_tag(&self, dim: u8, group: &str) -> Result<i32, MshError> {
        let groups = self.physical_groups(dim);
        let any_case = self.format.version == MshVersion::AbaqusInp;
        let same = |name: &str| name == group || (any_case && name.eq_ignore_ascii_case(group));
        let by_name = groups.iter().find(|g| g.name.as_deref().is_some_and(same));
        let number = group.trim().parse::<i32>().ok();
        let by_number = || groups.iter().find(|g| Some(g.tag) == number);
        let Some(found) = by_name.or_else(by_number) else {
            return Err(
                MshErrorKind::UnknownGroup { dim, group: group.to_string(), available: groups }.into()
            );
        };
        match self.unusable_groups.iter().find(|u| u.dim == dim && u.tag == found.tag) {
            Some(unusable) => Err(MshErrorKind::UnusableGroup {
                group: self.describe_group(dim, found.tag),
                reason: unusable.reason.clone(),
            }
            .into()),
            None => Ok(found.tag),
        }
    }

    /// The faces of group `group`, oriented outward from `cells` (`None`: all
    /// cells of the file).
    /// The faces of group `group`, oriented out of `body` (its cells and how
    /// to name them; every face must then be a face of exactly one of them),
    /// or else out of the file's cells (a face of none keeps its orientation).
    fn group_surface(
        &self,
        group: &str,
        body: Option<(&[&MshElement], String)>,
    ) -> Result<SurfaceMesh, MshError> {
        let tag = self.group_tag(2, group)?;
        let selected = self.group_elements(2, tag);
        if selected.is_empty() {
            return Err(MshErrorKind::NoFaces { selection: self.describe_group(2, tag) }.into());
        }
        let faces = selected.iter().map(|e| face_of(e)).collect::<Result<Vec<_>, _>>()?;
        let face_tags = tags_of(&selected);
        let (cells, cell_tags): (Vec<Cell>, Vec<u64>) = match &body {
            Some((cells, _)) => (cells.iter().map(|e| cell_of(e)).collect::<Result<_, _>>()?, tags_of(cells)),
            None => self
                .elements
                .iter()
                .filter(|e| e.dim == 3)
                .filter_map(|e| Some((cell_of(e).ok()?, e.tag)))
                .unzip(),
        };
        if cells.is_empty() {
            return SurfaceMesh::new(self.nodes.clone(), faces).map_err(|e| self.mesh_error(e, &face_tags));
        }
        let volume =
            VolumeMesh::new(self.nodes.clone(), cells).map_err(|e| self.mesh_error(e, &cell_tags))?;
        let owners = volume.face_owners(&faces);
        if let Some((_, body)) = body {
            // A body's surface carries the traces of its cells' functions
            // (loads, interfaces): a face no cell has (a surface meshed apart,
            // or quads cut along the other diagonal) would carry others.
            let stray = owners.iter().position(|o| !matches!(o, FaceOwner::Cell(_)));
            if let Some(i) = stray {
                return Err(MshErrorKind::NotACellFace {
                    surface: self.describe_group(2, tag),
                    volume: body,
                    element_tag: face_tags[i],
                    interior: owners[i] == FaceOwner::Interior,
                }
                .into());
            }
        }
        volume.orient_outward_of(&faces, &owners).map_err(|e| self.mesh_error(e, &face_tags))
    }

    fn all_faces(&self) -> Result<SurfaceMesh, MshError> {
        let selected: Vec<&MshElement> = self.elements.iter().filter(|e| e.dim == 2).collect();
        if selected.is_empty() {
            let selection = "the file (it has no 2D or 3D elements)".to_string();
            return Err(MshErrorKind::NoFaces { selection }.into());
        }
        let faces = selected.iter().map(|e| face_of(e)).collect::<Result<Vec<_>, _>>()?;
        SurfaceMesh::new(self.nodes.clone(), faces).map_err(|e| self.mesh_error(e, &tags_of(&selected)))
    }

    fn group_elements(&self, dim: u8, tag: i32) -> Vec<&MshElement> {
        self.elements.iter().filter(|e| e.dim == dim && e.physical_tags.contains(&tag)).collect()
    }

    fn describe_group(&self, dim: u8, tag: i32) -> String {
        let name = self.physical_names.iter().find(|n| n.dim == dim && n.tag == tag).map(|n| n.name.clone());
        format!("physical group {}", GroupId { tag, name })
    }

    /// A [`MeshError`] about face or cell `i` of a mesh built from elements with
    /// tags `element_tags`, in terms of Gmsh element and node tags.
    fn mesh_error(&self, error: MeshError, element_tags: &[u64]) -> MshError {
        let element_tag = error.element().and_then(|i| element_tags.get(i).copied());
        let node_tag = |i: usize| self.node_tags.get(i).copied().unwrap_or(i as u64);
        let kind = match error {
            MeshError::NonFiniteCoordinate { node } => {
                MshErrorKind::NonFiniteCoordinate { node_tag: node_tag(node) }
            }
            MeshError::CoordinateOutOfRange { node, value } => {
                MshErrorKind::CoordinateOutOfRange { node_tag: node_tag(node), value }
            }
            MeshError::TooSmall { diameter, .. } => {
                MshErrorKind::Degenerate { element_tag, reason: Degeneracy::TooSmall { diameter } }
            }
            MeshError::DegenerateCellFace { local_face, why, .. } => {
                MshErrorKind::Degenerate { element_tag, reason: Degeneracy::BoundaryFace { local_face, why } }
            }
            MeshError::RepeatedNode { node, .. } => MshErrorKind::Degenerate {
                element_tag,
                reason: Degeneracy::RepeatedNode { node_tag: node_tag(node) },
            },
            MeshError::ZeroArea { .. } => {
                MshErrorKind::Degenerate { element_tag, reason: Degeneracy::ZeroArea }
            }
            MeshError::Empty => MshErrorKind::NoFaces { selection: "the mesh".into() },
            problem => MshErrorKind::InvalidMesh { element_tag, problem },
        };
        kind.into()
    }
}

fn tags_of(elements: &[&MshElement]) -> Vec<u64> {
    elements.iter().map(|e| e.tag).collect()
}

/// The face of a 2D element (seam's node order is Gmsh's).
fn face_of(element: &MshElement) -> Result<Face, MshError> {
    let kind = FaceKind::from_gmsh(element.gmsh_type).ok_or_else(|| unsupported(element, FACE_TYPES))?;
    Face::new(kind, &element.nodes).ok_or_else(|| wrong_node_count(element))
}

/// The cell of a 3D element (seam's node order is Gmsh's).
fn cell_of(element: &MshElement) -> Result<Cell, MshError> {
    let kind = CellKind::from_gmsh(element.gmsh_type).ok_or_else(|| unsupported(element, CELL_TYPES))?;
    Cell::new(kind, &element.nodes).ok_or_else(|| wrong_node_count(element))
}

/// An element whose node list is not as long as its type needs.
fn wrong_node_count(element: &MshElement) -> MshError {
    let kind = MshErrorKind::WrongNodeCount {
        element_tag: element.tag,
        gmsh_type: element.gmsh_type,
        found: element.nodes.len(),
    };
    kind.into()
}

fn unsupported(element: &MshElement, supported: &'static str) -> MshError {
    let kind = MshErrorKind::UnsupportedElement {
        element_tag: element.tag,
        gmsh_type: element.gmsh_type,
        supported,
    };
    kind.into()
}
