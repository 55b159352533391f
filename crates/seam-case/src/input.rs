//! Reading a surface with its point fields from a Gmsh MSH file ($NodeData),
//! an Abaqus / CalculiX input file (`.inp`, no fields) or a VTU file (point
//! data), and the nodal values to transfer: a field of the
//! file or an expression evaluated at its nodes, every value checked finite.
//! [`Pair`]: the two surfaces of `seam assemble` and `seam check`.

use crate::{Expression, ExpressionError};
use anyhow::{anyhow, bail, Result};
use seam::SurfaceMesh;
use seam_io::Field;
use std::path::{Path, PathBuf};

/// A surface mesh, the nodal fields its file carries, and how its file names
/// its nodes.
pub struct Surface {
    /// The file read.
    pub path: PathBuf,
    /// The surface (a physical group's faces, or all of them).
    pub mesh: SurfaceMesh,
    /// The point fields of the file.
    pub fields: Vec<Field>,
    /// Node ids: Gmsh tags (MSH files) or Abaqus ids (`.inp`); `None` for
    /// VTU files, whose points are named by their 0-based index, as in
    /// ParaView.
    node_tags: Option<Vec<u64>>,
    /// Element tags of the faces ([`seam_io::Msh::surface_face_tags`]; for an
    /// `.inp` file [`seam_io::abaqus::face_tag`]); `None` for VTU files and
    /// for the boundary of a file's cells.
    face_tags: Option<Vec<u64>>,
}

impl Surface {
    /// Reads `path`: `.vtu` as VTU (point data), `.inp` as Abaqus input
    /// (`group` selects a `*SURFACE`), anything else as Gmsh MSH ($NodeData;
    /// `group` selects a physical surface).
    ///
    /// # Errors
    /// An unreadable file, or a group in a VTU file or missing from the MSH file.
    pub fn read(path: &Path, group: Option<&str>) -> Result<Surface> {
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("vtu")) {
            if let Some(g) = group {
                bail!(
                    "{}: physical groups exist in MSH and .inp files only, but --*-group {g} was given",
                    path.display()
                );
            }
            let vtu = seam_io::read_vtu_file(path)?;
            return Ok(Surface {
                path: path.into(),
                mesh: vtu.mesh,
                fields: vtu.point_data,
                node_tags: None,
                face_tags: None,
            });
        }
        let msh = seam_io::read_model_file(path, None)?;
        let mesh = msh.surface(group).map_err(|e| e.with_path(path))?;
        let face_tags = msh.surface_face_tags(group).map_err(|e| e.with_path(path))?;
        let fields = msh
            .node_data
            .iter()
            .map(|d| Field::new(d.name.clone(), d.components, d.values.clone()))
            .collect();
        Ok(Surface { path: path.into(), mesh, fields, node_tags: Some(msh.node_tags), face_tags })
    }

    /// The element tag of each face, when the faces are elements of an MSH
    /// or `.inp` file.
    pub fn face_tags(&self) -> Option<&[u64]> {
        self.face_tags.as_deref()
    }

    /// Node `p` (0-based, file order) as the file names it: "node 17" (its Gmsh
    /// tag or Abaqus id) or "point 16" (VTU, 0-based).
    pub fn node(&self, p: usize) -> String {
        match self.node_tags.as_ref().and_then(|t| t.get(p)) {
            Some(tag) => format!("node {tag}"),
            None => format!("point {p}"),
        }
    }

    /// The field `name`, checked to be finite at every point of the surface.
    pub fn field(&self, name: &str) -> Result<&Field> {
        let path = self.path.display();
        let field = self.fields.iter().find(|f| f.name == name).ok_or_else(|| {
            let known: Vec<&str> = self.fields.iter().map(|f| f.name.as_str()).collect();
            let known = if known.is_empty() { "none".to_string() } else { known.join(", ") };
            anyhow!("{path}: no field named '{name}' (fields: {known})")
        })?;
        let k = field.components;
        if k == 0 || field.values.len() != self.mesh.n_points() * k {
            bail!(
                "{path}: field '{name}' has {} values, but {} points × {k} components were expected",
                field.values.len(),
                self.mesh.n_points()
            );
        }
        let used = self.mesh.used_points();
        if let Some((p, v)) = (0..used.len())
            .filter(|&p| used[p])
            .find_map(|p| field.entry(p).iter().find(|v| !v.is_finite()).map(|&v| (p, v)))
        {
            bail!("{path}: field '{name}' has no finite value at {} ({v}; only finite values can be transferred)", self.node(p));
        }
        Ok(field)
    }

    /// `e` at every node of the surface (0 at nodes no face uses).
    pub fn sample(&self, e: &Expression) -> Result<Vec<f64>> {
        e.sample(self.mesh.points(), &self.mesh.used_points()).map_err(|err| match err {
            ExpressionError::NotFinite { text, point, value, index: Some(p), .. } => anyhow!(
                "{}: the expression '{text}' is {value} at {} ({}, {}, {}); only finite values can be transferred",
                self.path.display(),
                self.node(p),
                point[0],
                point[1],
                point[2]
            ),
            other => anyhow!("{}: {other}", self.path.display()),
        })
    }
}

/// The first non-finite value of a result `values` (`k` per node), named by
/// `surface`'s nodes, as an error saying what `what` is; `Ok` if all are finite.
pub fn check_finite(values: &[f64], k: usize, surface: &Surface, what: &str) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => bail!(
            "{}: {what} is {} at {}: nothing non-finite is written",
            surface.path.display(),
            values[i],
            surface.node(i / k.max(1))
        ),
    }
}

/// Two surfaces: the files and, for MSH files, their physical groups.
#[derive(Clone, Debug)]
pub struct Pair {
    /// The master side's file.
    pub master: PathBuf,
    /// The slave side's file.
    pub slave: PathBuf,
    /// The master's physical surface (MSH files only).
    pub master_group: Option<String>,
    /// The slave's physical surface (MSH files only).
    pub slave_group: Option<String>,
}
