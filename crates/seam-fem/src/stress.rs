//! Stress recovery from a displacement field.
//!
//! Per cell, at the centroid ξ_c of the reference cell ([`CellKind::centroid`],
//! the physical centroid for affine cells):
//!
//! ```text
//! ε = (∂_x u_x, ∂_y u_y, ∂_z u_z, ∂_z u_y + ∂_y u_z, ∂_z u_x + ∂_x u_z, ∂_y u_x + ∂_x u_y),   σ = C ε,
//! ```
//!
//! Voigt order xx yy zz yz xz xy. Nodal stresses (at every point a cell uses:
//! corners and, on second-order cells, mid-edge and centre nodes alike) are
//! volume-weighted averages of the cells around each point, σ_p = Σ_{e∋p} |e| σ_e / Σ_{e∋p} |e|; von Mises
//!
//! ```text
//! σ_vm = √(½[(σxx−σyy)² + (σyy−σzz)² + (σzz−σxx)²] + 3(τyz² + τxz² + τxy²)).
//! ```

use crate::assembly::{cell_volumes, corners as node_coordinates, geometry, point_cells, AssemblyError};
use crate::material::Material;
use rayon::prelude::*;
use seam::CellKind;
use seam::{Point3, VolumeMesh};

/// Stresses of a displacement field (Voigt order xx yy zz yz xz xy).
#[derive(Clone, Debug, PartialEq)]
pub struct Stresses {
    /// Per cell, at its reference centroid.
    pub cell: Vec<[f64; 6]>,
    /// Von Mises stress of each cell stress.
    pub cell_von_mises: Vec<f64>,
    /// Per point, the volume-weighted average of its cells (0 for a point no
    /// cell uses).
    pub nodal: Vec<[f64; 6]>,
    /// Von Mises stress of each nodal stress (not the average of cell values).
    pub nodal_von_mises: Vec<f64>,
}

/// The von Mises stress of a Voigt stress (module doc).
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let d = (s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2);
    (0.5 * d + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])).sqrt()
}

/// The Voigt strain at the reference centroid of the cell with corners `x` and
/// point indices `nodes`, from the displacement dofs `u`.
fn strain_at(kind: CellKind, x: &[Point3], nodes: &[usize], u: &[f64]) -> Option<[f64; 6]> {
    let g = geometry(kind, x, kind.centroid())?;
    // du[a][k] = ∂u_a/∂x_k
    let mut du = [[0.0; 3]; 3];
    for (i, &p) in nodes.iter().enumerate() {
        for a in 0..3 {
            for k in 0..3 {
                du[a][k] += u[3 * p + a] * g.grads[i][k];
            }
        }
    }
    Some([du[0][0], du[1][1], du[2][2], du[1][2] + du[2][1], du[0][2] + du[2][0], du[0][1] + du[1][0]])
}

/// Cell and nodal stresses of the displacement `u` (dofs 3·point + component).
///
/// # Errors
/// [`AssemblyError::DegenerateCell`] for the first degenerate cell.
///
/// # Panics
/// If `u.len() != 3 · mesh.points().len()`.
pub fn recover_stresses(
    mesh: &VolumeMesh,
    material: &Material,
    u: &[f64],
) -> Result<Stresses, AssemblyError> {
    assert_eq!(u.len(), 3 * mesh.points().len(), "u must have 3 entries per point");
    let strains: Vec<Option<[f64; 6]>> = mesh
        .cells()
        .par_iter()
        .enumerate()
        .map(|(c, cell)| {
            let (x, kind) = node_coordinates(mesh, c);
            strain_at(kind, &x[..kind.n_nodes()], cell.nodes(), u)
        })
        .collect();
    if let Some(cell) = strains.iter().position(Option::is_none) {
        return Err(AssemblyError::DegenerateCell { cell });
    }
    let cell: Vec<[f64; 6]> = strains.into_iter().flatten().map(|e| material.stress(e)).collect();
    Stresses::of_cells(mesh, cell)
}

impl Stresses {
    /// The stresses of the cell values `cell` (one per cell of `mesh`): the
    /// nodal ones their volume-weighted averages (module doc), and von Mises
    /// of both.
    ///
    /// # Errors
    /// [`AssemblyError::DegenerateCell`] for the first degenerate cell.
    pub fn of_cells(mesh: &VolumeMesh, cell: Vec<[f64; 6]>) -> Result<Stresses, AssemblyError> {
        assert_eq!(cell.len(), mesh.cells().len(), "one stress per cell");
        let volumes = cell_volumes(mesh)?;
        let (offsets, around) = point_cells(mesh);
        let nodal: Vec<[f64; 6]> = (0..mesh.points().len())
            .into_par_iter()
            .map(|p| {
                let (mut s, mut v) = ([0.0; 6], 0.0);
                for &(c, _) in &around[offsets[p]..offsets[p + 1]] {
                    for k in 0..6 {
                        s[k] += volumes[c] * cell[c][k];
                    }
                    v += volumes[c];
                }
                if v > 0.0 {
                    s.map(|x| x / v)
                } else {
                    s
                }
            })
            .collect();
        Ok(Stresses {
            cell_von_mises: cell.iter().map(von_mises).collect(),
            nodal_von_mises: nodal.iter().map(von_mises).collect(),
            cell,
            nodal,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn von_mises_of_simple_states() {
        assert!((von_mises(&[2.0, 0.0, 0.0, 0.0, 0.0, 0.0]) - 2.0).abs() < 1e-15);
        assert!((von_mises(&[0.0, 0.0, 0.0, 0.0, 0.0, 1.0]) - 3f64.sqrt()).abs() < 1e-15);
        assert!(von_mises(&[-5.0, -5.0, -5.0, 0.0, 0.0, 0.0]).abs() < 1e-15);
    }
}
