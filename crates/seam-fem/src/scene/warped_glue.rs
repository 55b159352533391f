//! The paper's first example (Fig. 2), glued.

use super::{block_body, BOTTOM_TOP};
use crate::generate::{block, raise_order, BlockKind, Grid};
use crate::material::Material;
use crate::multibody::Coupling;
use crate::problem::{Load, Problem, ProblemInterface, Support, SurfaceId};
use seam::{Facing, MeshError, MortarOptions, Multiplier, Point3};

/// Parameters of [`warped_glue`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WarpedGlue {
    /// Slave (upper) cells across x and y; (n + 1)² slave interface nodes.
    pub slave_cells: usize,
    /// h_s / h_m: master (lower) cells across = `ratio · slave_cells`.
    pub ratio: usize,
    /// Slave cell layers (upper body, uniform in z).
    pub slave_layers: usize,
    /// Master cell layers (lower body, graded towards the interface).
    pub master_layers: usize,
    /// Amplitude of the interface: s(x, y) = 1/2 + a sin(2πx) sin(πy).
    pub amplitude: f64,
    /// The multiplier.
    pub multiplier: Multiplier,
    /// Traction on the top face.
    pub traction: [f64; 3],
    /// 1: Hex8 cells; 2: Hex27 cells, every node (mid-edge, face and cell
    /// centres too) on the blocks' maps, so the interface faces are curved
    /// Quad9 faces of the true warped surface. Cell counts are those of the
    /// cells of either order: for equal numbers of nodes halve them at order 2.
    pub order: usize,
}

impl Default for WarpedGlue {
    /// The paper's proportions: 8 × 8 slave faces (81 nodes), h_s/h_m = 8.
    fn default() -> Self {
        WarpedGlue {
            slave_cells: 8,
            ratio: 8,
            slave_layers: 8,
            master_layers: 8,
            amplitude: 0.1,
            multiplier: Multiplier::Standard,
            traction: [0.2, 0.0, -1.0],
            order: 1,
        }
    }
}

impl WarpedGlue {
    /// The interface height s(x, y).
    pub fn interface(&self, x: f64, y: f64) -> f64 {
        use std::f64::consts::PI;
        0.5 + self.amplitude * (2.0 * PI * x).sin() * (PI * y).sin()
    }

    /// The lower body's map: layers graded as 1 − (1 − w)^1.5, so the cells at
    /// the interface are about as thick as they are wide.
    fn lower(&self, u: f64, v: f64, w: f64) -> Point3 {
        [u, v, self.interface(u, v) * (1.0 - (1.0 - w).powf(1.5))]
    }

    /// The upper body's map, uniform between the interface and z = 1.
    fn upper(&self, u: f64, v: f64, w: f64) -> Point3 {
        let s = self.interface(u, v);
        [u, v, s + (1.0 - s) * w]
    }
}

/// The warped-glue problem (module doc): bodies "lower" (master, surfaces
/// "bottom", "top") and "upper" (slave, "bottom", "top"), E = 1000, ν = 0.3 both.
///
/// # Errors
/// [`MeshError`] only for degenerate parameters (e.g. an amplitude ≥ 1/2).
///
/// # Panics
/// If a cell count is zero.
pub fn warped_glue(p: &WarpedGlue) -> Result<Problem, MeshError> {
    let material = Material::new(1000.0, 0.3).expect("valid constants");
    let nm = p.slave_cells * p.ratio;
    let lower = hexes(nm, p.master_layers, p.order, |u, v, w| p.lower(u, v, w));
    let lower_grid = Grid::new(nm, nm, p.master_layers);
    let ns = p.slave_cells;
    let upper = hexes(ns, p.slave_layers, p.order, |u, v, w| p.upper(u, v, w));
    let upper_grid = Grid::new(ns, ns, p.slave_layers);
    let bodies = vec![
        block_body("lower", lower, &lower_grid, material, &BOTTOM_TOP)?,
        block_body("upper", upper, &upper_grid, material, &BOTTOM_TOP)?,
    ];
    let (bottom, top) = (0, 1);
    let options =
        MortarOptions { multiplier: p.multiplier, facing: Facing::Opposite, ..MortarOptions::default() };
    Ok(Problem {
        bodies,
        interfaces: vec![ProblemInterface {
            master: SurfaceId { body: 0, surface: top },
            slave: SurfaceId { body: 1, surface: bottom },
            options,
            kind: Coupling::Glue,
            friction: 0.0,
        }],
        supports: vec![Support::new(SurfaceId { body: 0, surface: bottom }, [Some(0.0); 3])],
        loads: vec![Load::new(SurfaceId { body: 1, surface: top }, p.traction)],
        ..Problem::default()
    })
}

/// An n × n × `layers` block of hexahedra of `order` 1 (Hex8) or 2 (Hex27) on
/// `map`: at order 2 the block is raised on the unit cube and every node mapped,
/// so that the higher-order nodes lie on the map, not on straight edges.
fn hexes(n: usize, layers: usize, order: usize, map: impl Fn(f64, f64, f64) -> Point3) -> seam::VolumeMesh {
    if order < 2 {
        return block(n, n, layers, map, BlockKind::Hex);
    }
    let unit = block(n, n, layers, |u, v, w| [u, v, w], BlockKind::Hex);
    let raised = raise_order(&unit, true).expect("a first-order block");
    let points = raised.points().iter().map(|&[u, v, w]| map(u, v, w)).collect();
    seam::VolumeMesh::new(points, raised.cells().to_vec()).expect("finite points, valid cells")
}
