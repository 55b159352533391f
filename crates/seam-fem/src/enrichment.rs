//! The enriched slave space of dual multipliers on quadratic slave faces
//! (Lamichhane, Stevenson and Wohlmuth, Numer. Math. 102 (2005)).
//!
//! On Tri6 and Quad8 faces no dual basis with the supports of the nodal
//! functions contains the linear functions (Popp's transformed basis only
//! has the constants, [`seam::BASIS_ALPHA`]), and glued bodies lose half an
//! order in H1. With one bubble per slave face — the cubic L₀L₁L₂ on a
//! triangle, the biquadratic centre function on a quadrilateral — every face
//! function has a positive integral and its weighted centroid at its node, and
//! the plain dual basis of the Tri7 and Quad9 faces contains them
//! ([`seam::SurfaceMesh::enriched`]).
//!
//! The slave body gets those bubbles through its cells: each cell with a face
//! on the surface is raised (Tet10 → Tet14, Hex20 → Hex27), and every point
//! the raising adds off the surface — the centres of its other faces, the
//! Hex27 centre — is tied to the cell's own interpolant there,
//! u_t = Σ_i N_i(ξ_t) u_i ([`Tie`]). The raised cells then span the original
//! space plus the bubbles of the surface faces, and their other faces keep the
//! traces their neighbours, supports and tractions see.

use crate::assembly::map_point;
use seam::{Face, Point3, SurfaceMesh, VolumeMesh};
use std::collections::HashMap;

/// A point whose displacement is fixed by others of its body:
/// u_point = Σ (q, w) ∈ `to`: w u_q, in every component.
#[derive(Clone, Debug, PartialEq)]
pub struct Tie {
    /// The tied point.
    pub point: usize,
    /// The points it follows, with their weights (summing to one).
    pub to: Vec<(usize, f64)>,
}

/// A body raised for enriched slave surfaces ([`enrich`]).
#[derive(Clone, Debug)]
pub struct Enriched {
    /// The mesh: the cells with a face on a surface raised, the points they
    /// add appended after the original ones (whose indices are kept).
    pub mesh: VolumeMesh,
    /// The surfaces with Tri7 and Quad9 faces through those points, indexing
    /// `mesh`, in the order given.
    pub surfaces: Vec<SurfaceMesh>,
    /// The added points off the surfaces, tied to their cells' interpolants.
    pub ties: Vec<Tie>,
}

/// Raises `mesh` for the enriched space of `surfaces` (module doc); `None`
/// when no surface has a Tri6 or Quad8 face.
///
/// # Errors
/// A line naming the first Tri6 or Quad8 face of a surface that is no face of
/// a cell, or whose cell has no enriched kind (Prism15, Pyramid13).
pub fn enrich(mesh: &VolumeMesh, surfaces: &[&SurfaceMesh]) -> Result<Option<Enriched>, String> {
    let needs = |f: &Face| f.kind().info().enriched.is_some();
    if !surfaces.iter().any(|s| s.faces().iter().any(needs)) {
        return Ok(None);
    }
    let owner = face_owners(mesh);
    let mut raise = vec![false; mesh.cells().len()];
    for (k, surface) in surfaces.iter().enumerate() {
        for (f, face) in surface.faces().iter().enumerate().filter(|(_, f)| needs(f)) {
            let Some(&c) = owner.get(&sorted(face.corner_nodes())) else {
                return Err(format!("surface {}: face {f} ({face}) is no face of a cell of the body", k + 1));
            };
            let kind = mesh.cells()[c].kind();
            if kind.info().enriched.is_none() {
                return Err(format!(
                    "surface {}: face {f} belongs to cell {c}, a {}, which has no enriched kind (only Tet10 and \
                     Hex20 cells are raised)",
                    k + 1,
                    kind.name()
                ));
            }
            raise[c] = true;
        }
    }
    let mut points = mesh.points().to_vec();
    // Added points by the sorted corners they are the centre of.
    let mut added: HashMap<Vec<usize>, usize> = HashMap::new();
    let mut weights: Vec<(usize, Vec<(usize, f64)>)> = Vec::new();
    let mut cells = mesh.cells().to_vec();
    for (c, cell) in mesh.cells().iter().enumerate().filter(|&(c, _)| raise[c]) {
        let (kind, nodes) = (cell.kind(), cell.nodes());
        let raised = kind.info().enriched.expect("checked above");
        let x: Vec<Point3> = nodes.iter().map(|&p| mesh.points()[p]).collect();
        let supports = raised.node_supports();
        let mut all = nodes.to_vec();
        for (j, &xi) in raised.reference_nodes().iter().enumerate().skip(kind.n_nodes()) {
            let key = sorted(&supports[j].iter().map(|&i| nodes[i]).collect::<Vec<_>>());
            let p = *added.entry(key).or_insert_with(|| {
                points.push(map_point(kind, &x, xi));
                let n = kind.shape(xi);
                let to =
                    (0..kind.n_nodes()).filter(|&i| n[i].abs() > 1e-14).map(|i| (nodes[i], n[i])).collect();
                weights.push((points.len() - 1, to));
                points.len() - 1
            });
            all.push(p);
        }
        cells[c] = raised.cell(&all).expect("the raised kind's node count");
    }
    let mut on_surface = vec![false; points.len()];
    let surfaces = surfaces
        .iter()
        .map(|surface| {
            let faces = surface
                .faces()
                .iter()
                .map(|face| {
                    let Some(larger) = face.kind().info().enriched else { return *face };
                    let centre = added[&sorted(face.corner_nodes())];
                    on_surface[centre] = true;
                    let nodes: Vec<usize> = face.nodes().iter().copied().chain([centre]).collect();
                    Face::new(larger, &nodes).expect("one node more than the face")
                })
                .collect();
            SurfaceMesh::new(points.clone(), faces)
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let ties =
        weights.into_iter().filter(|(p, _)| !on_surface[*p]).map(|(point, to)| Tie { point, to }).collect();
    let mesh = VolumeMesh::new(points, cells).map_err(|e| e.to_string())?;
    Ok(Some(Enriched { mesh, surfaces, ties }))
}

/// The cell of each face of the mesh's cells, by its sorted corners (a face
/// of two cells keeps the first; surfaces are on the boundary).
fn face_owners(mesh: &VolumeMesh) -> HashMap<Vec<usize>, usize> {
    let mut owner = HashMap::new();
    for (c, cell) in mesh.cells().iter().enumerate() {
        for face in cell.kind().info().faces {
            let corners: Vec<usize> = face.corners().iter().map(|&i| cell.nodes()[i]).collect();
            owner.entry(sorted(&corners)).or_insert(c);
        }
    }
    owner
}

fn sorted(nodes: &[usize]) -> Vec<usize> {
    let mut v = nodes.to_vec();
    v.sort_unstable();
    v
}
