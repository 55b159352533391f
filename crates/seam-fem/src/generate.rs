//! Structured blocks: the unit cube \[0,1\]³ cut into nx × ny × nz hexahedra (or
//! tets, prisms, pyramids filling them), mapped by x = map(u, v, w).
//!
//! # Numbering
//!
//! - Grid point (i, j, k), 0 ≤ i ≤ nx, …, at reference (i/nx, j/ny, k/nz):
//!   point `i + (nx+1)·(j + (ny+1)·k)` ([`Grid::point`]).
//! - Grid cell (i, j, k), 0 ≤ i < nx, …: `c = i + nx·(j + ny·k)`. Its cells are
//!   numbered `c·m + l` with m cells per grid cell (1 hex, 6 tets, 2 prisms or
//!   6 pyramids) and l as below.
//! - Hex (Gmsh order): (i,j,k) (i+1,j,k) (i+1,j+1,k) (i,j+1,k), then the same at k+1.
//! - Tets: the Kuhn (Freudenthal) split: for each of the 6 orders of the axes
//!   (xyz, yzx, zxy, xzy, zyx, yxz), the path 000 → one step → two steps → 111
//!   along the cube edges. All 6 share the diagonal 000–111; every cube face is
//!   cut along its diagonal through its 000-most corner, the same from both
//!   sides, so the tets are conforming. Positively oriented in (u, v, w).
//! - Prisms: the (u, v) square cut along its diagonal (i,j)–(i+1,j+1) into
//!   (00, 10, 11) and (00, 11, 01), extruded from k to k+1 (bottom triangle
//!   first, Gmsh order).
//! - Pyramids: one per face of the grid cell (faces in the order bottom, top,
//!   −v, +u, +v, −u), apex at the cell centre. The centres are extra points,
//!   numbered after the grid points: `n_grid_points + c`, at map(centre).
//!
//! A map with positive Jacobian keeps every cell positively oriented.
//!
//! [`raise_order`] turns a first-order mesh into a second-order one with the
//! same geometry (module doc of the function).

use seam::CellKind;
use seam::{Cell, Face, MeshError, Point3, SurfaceMesh, VolumeMesh};
use std::collections::HashMap;

/// How each grid cell is filled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlockKind {
    /// One Hex8.
    Hex,
    /// Six Tet4 (Kuhn split).
    Tet,
    /// Two Prism6 (extruded along w).
    Prism,
    /// Six Pyramid5 around an extra centre point.
    Pyramid,
}

impl BlockKind {
    /// Cells per grid cell: 1, 6, 2, 6.
    pub fn cells_per_grid_cell(self) -> usize {
        match self {
            BlockKind::Hex => 1,
            BlockKind::Tet | BlockKind::Pyramid => 6,
            BlockKind::Prism => 2,
        }
    }
}

/// A side of the unit cube.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// u = 0.
    XMin,
    /// u = 1.
    XMax,
    /// v = 0.
    YMin,
    /// v = 1.
    YMax,
    /// w = 0.
    ZMin,
    /// w = 1.
    ZMax,
}

impl Side {
    /// All six sides.
    pub const ALL: [Side; 6] = [Side::XMin, Side::XMax, Side::YMin, Side::YMax, Side::ZMin, Side::ZMax];
}

/// The numbering of an nx × ny × nz block (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Grid {
    /// Cells along u.
    pub nx: usize,
    /// Cells along v.
    pub ny: usize,
    /// Cells along w.
    pub nz: usize,
}

impl Grid {
    /// The grid of nx × ny × nz cells.
    pub fn new(nx: usize, ny: usize, nz: usize) -> Grid {
        Grid { nx, ny, nz }
    }

    /// Number of grid points (nx+1)(ny+1)(nz+1).
    pub fn n_grid_points(&self) -> usize {
        (self.nx + 1) * (self.ny + 1) * (self.nz + 1)
    }

    /// Number of grid cells nx·ny·nz.
    pub fn n_grid_cells(&self) -> usize {
        self.nx * self.ny * self.nz
    }

    /// The point of grid node (i, j, k): i + (nx+1)(j + (ny+1)k).
    pub fn point(&self, i: usize, j: usize, k: usize) -> usize {
        i + (self.nx + 1) * (j + (self.ny + 1) * k)
    }

    /// (i, j, k) of a grid point; `None` for the pyramids' centre points.
    pub fn ijk(&self, p: usize) -> Option<[usize; 3]> {
        (p < self.n_grid_points()).then(|| {
            let (a, b) = (self.nx + 1, self.ny + 1);
            [p % a, (p / a) % b, p / (a * b)]
        })
    }

    /// True when grid point `p` lies on `side`.
    pub fn on_side(&self, p: usize, side: Side) -> bool {
        let Some([i, j, k]) = self.ijk(p) else { return false };
        match side {
            Side::XMin => i == 0,
            Side::XMax => i == self.nx,
            Side::YMin => j == 0,
            Side::YMax => j == self.ny,
            Side::ZMin => k == 0,
            Side::ZMax => k == self.nz,
        }
    }

    /// True when grid point `p` lies on the boundary of the block.
    pub fn on_boundary(&self, p: usize) -> bool {
        Side::ALL.iter().any(|&s| self.on_side(p, s))
    }

    /// The grid points on `side`, increasing.
    pub fn side_points(&self, side: Side) -> Vec<usize> {
        (0..self.n_grid_points()).filter(|&p| self.on_side(p, side)).collect()
    }

    /// The grid points on the boundary, increasing.
    pub fn boundary_points(&self) -> Vec<usize> {
        (0..self.n_grid_points()).filter(|&p| self.on_boundary(p)).collect()
    }

    /// The boundary faces of `mesh` (a block of this grid, possibly raised by
    /// [`raise_order`]) on `side`, outward, chosen by their corners; the points
    /// are the mesh's points.
    ///
    /// # Errors
    /// [`MeshError`] from [`VolumeMesh::boundary`].
    pub fn side_faces(&self, mesh: &VolumeMesh, side: Side) -> Result<SurfaceMesh, MeshError> {
        let boundary = mesh.boundary()?;
        let faces: Vec<Face> = boundary
            .faces()
            .iter()
            .filter(|f| f.corner_nodes().iter().all(|&p| self.on_side(p, side)))
            .copied()
            .collect();
        SurfaceMesh::new(mesh.points().to_vec(), faces)
    }
}

/// Kuhn paths: the axis orders and whether they are odd permutations.
const KUHN: [([usize; 3], bool); 6] = [
    ([0, 1, 2], false),
    ([1, 2, 0], false),
    ([2, 0, 1], false),
    ([0, 2, 1], true),
    ([2, 1, 0], true),
    ([1, 0, 2], true),
];

/// The hex's local faces, outward, bottom, top, −v, +u, +v, −u (Gmsh order corners).
const HEX_FACES: [[usize; 4]; 6] =
    [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];

/// An nx × ny × nz block of `kind` cells on \[0,1\]³ mapped by `map` (numbering
/// in the module doc).
///
/// # Panics
/// If a size is zero or the map gives a non-finite point.
pub fn block(
    nx: usize,
    ny: usize,
    nz: usize,
    map: impl Fn(f64, f64, f64) -> Point3,
    kind: BlockKind,
) -> VolumeMesh {
    assert!(nx > 0 && ny > 0 && nz > 0, "a block needs at least one cell in each direction");
    let grid = Grid::new(nx, ny, nz);
    let (fx, fy, fz) = (nx as f64, ny as f64, nz as f64);
    let mut points = Vec::with_capacity(grid.n_grid_points());
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                points.push(map(i as f64 / fx, j as f64 / fy, k as f64 / fz));
            }
        }
    }
    let mut cells = Vec::with_capacity(grid.n_grid_cells() * kind.cells_per_grid_cell());
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let corner = |d: [usize; 3]| grid.point(i + d[0], j + d[1], k + d[2]);
                let hex = [
                    corner([0, 0, 0]),
                    corner([1, 0, 0]),
                    corner([1, 1, 0]),
                    corner([0, 1, 0]),
                    corner([0, 0, 1]),
                    corner([1, 0, 1]),
                    corner([1, 1, 1]),
                    corner([0, 1, 1]),
                ];
                match kind {
                    BlockKind::Hex => cells.push(Cell::Hex8(hex)),
                    BlockKind::Tet => {
                        for (axes, odd) in KUHN {
                            let mut d = [0usize; 3];
                            let v0 = corner(d);
                            d[axes[0]] = 1;
                            let v1 = corner(d);
                            d[axes[1]] = 1;
                            let v2 = corner(d);
                            let v3 = corner([1, 1, 1]);
                            cells.push(Cell::Tet4(if odd { [v0, v2, v1, v3] } else { [v0, v1, v2, v3] }));
                        }
                    }
                    BlockKind::Prism => {
                        for tri in [[0, 1, 2], [0, 2, 3]] {
                            let t = tri.map(|l| hex[l]);
                            let b = tri.map(|l| hex[l + 4]);
                            cells.push(Cell::Prism6([t[0], t[1], t[2], b[0], b[1], b[2]]));
                        }
                    }
                    BlockKind::Pyramid => {
                        let apex = points.len();
                        points.push(map((i as f64 + 0.5) / fx, (j as f64 + 0.5) / fy, (k as f64 + 0.5) / fz));
                        for f in HEX_FACES {
                            // The outward face reversed: counter-clockwise seen from the apex.
                            let [a, b, c, d] = f.map(|l| hex[l]);
                            cells.push(Cell::Pyramid5([a, d, c, b, apex]));
                        }
                    }
                }
            }
        }
    }
    VolumeMesh::new(points, cells).expect("block meshes are valid by construction")
}

/// Why [`raise_order`] failed.
#[derive(Debug, thiserror::Error)]
pub enum RaiseError {
    /// The input has a cell that is already of second order.
    #[error("cell {cell} is already of second order")]
    SecondOrder {
        /// The cell index.
        cell: usize,
    },
    /// The raised mesh is invalid (it cannot be when the input is valid).
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// The local corners whose mean is each node's reference position, per node of
/// `kind` in Gmsh order ([`CellKind::node_supports`]).
pub fn node_supports(kind: CellKind) -> Vec<Vec<usize>> {
    kind.node_supports()
}

/// The second-order mesh of a first-order one: Tet4 → Tet10, Hex8 → Hex20
/// (Hex27 if `complete`), Prism6 → Prism15 (Prism18), Pyramid5 → Pyramid13
/// (Pyramid14).
///
/// Each new node is placed at the mean of its supporting corners
/// ([`node_supports`]): edge midpoints, quadrilateral face centres and the hex
/// centre, which are the images of the reference nodes under the first-order
/// map, so the raised mesh has exactly the geometry of the input. Existing points
/// keep their indices; new points are appended in the order they are first met
/// (cells in order, nodes in Gmsh order) and shared between the cells that share
/// the edge or face.
///
/// # Errors
/// [`RaiseError::SecondOrder`] for a cell that is already of second order.
pub fn raise_order(mesh: &VolumeMesh, complete: bool) -> Result<VolumeMesh, RaiseError> {
    let target = |kind: CellKind| kind.second_order(complete);
    let supports: Vec<Vec<Vec<usize>>> =
        CellKind::ALL.iter().map(|&k| target(k).map(node_supports).unwrap_or_default()).collect();
    let mut points = mesh.points().to_vec();
    // Key: the sorted global corners of a support, padded with usize::MAX.
    let mut index: HashMap<[usize; 8], usize> = HashMap::new();
    let mut cells = Vec::with_capacity(mesh.cells().len());
    for (c, cell) in mesh.cells().iter().enumerate() {
        let kind = CellKind::of(cell);
        let high = target(kind).ok_or(RaiseError::SecondOrder { cell: c })?;
        let corners = cell.nodes();
        let mut nodes = [0usize; 27];
        for (i, support) in supports[kind as usize].iter().enumerate() {
            if let [single] = support[..] {
                nodes[i] = corners[single];
                continue;
            }
            let mut key = [usize::MAX; 8];
            for (k, &l) in key.iter_mut().zip(support) {
                *k = corners[l];
            }
            key.sort_unstable();
            nodes[i] = *index.entry(key).or_insert_with(|| {
                let x = std::array::from_fn(|k| {
                    support.iter().map(|&l| mesh.points()[corners[l]][k]).sum::<f64>() / support.len() as f64
                });
                points.push(x);
                points.len() - 1
            });
        }
        cells.push(high.cell(&nodes[..high.n_nodes()]).expect("node count of the target kind"));
    }
    Ok(VolumeMesh::new(points, cells)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn identity(u: f64, v: f64, w: f64) -> Point3 {
        [u, v, w]
    }

    #[test]
    fn counts_and_conformity() {
        let (nx, ny, nz) = (3, 2, 4);
        let grid = Grid::new(nx, ny, nz);
        // Boundary faces: 2(nx ny + ny nz + nx nz) grid squares, 1 quad or 2 triangles each.
        let squares = 2 * (nx * ny + ny * nz + nx * nz);
        for (kind, faces) in [
            (BlockKind::Hex, squares),
            (BlockKind::Tet, 2 * squares),
            (BlockKind::Prism, squares + 2 * nx * ny),
            (BlockKind::Pyramid, squares),
        ] {
            let mesh = block(nx, ny, nz, identity, kind);
            assert_eq!(mesh.cells().len(), grid.n_grid_cells() * kind.cells_per_grid_cell());
            let b = mesh.boundary().unwrap();
            assert_eq!(b.n_faces(), faces, "{kind:?}: a non-conforming face shows up as boundary");
            let sides: usize = Side::ALL.iter().map(|&s| grid.side_faces(&mesh, s).unwrap().n_faces()).sum();
            assert_eq!(sides, faces, "{kind:?}");
        }
        assert_eq!(grid.ijk(grid.point(2, 1, 3)), Some([2, 1, 3]));
        assert_eq!(grid.boundary_points().len(), grid.n_grid_points() - (nx - 1) * (ny - 1) * (nz - 1));
        assert_eq!(grid.side_points(Side::XMax).len(), (ny + 1) * (nz + 1));
    }
}
