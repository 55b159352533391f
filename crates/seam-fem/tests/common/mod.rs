//! Shared helpers of the integration tests.
#![allow(dead_code)]

use seam::{Cell, Point3, VolumeMesh};
use seam_fem::generate::{block, BlockKind, Grid};
use seam_fem::Material;

/// A smooth, non-affine map of the unit cube (positive Jacobian).
pub fn warp(u: f64, v: f64, w: f64) -> Point3 {
    use std::f64::consts::PI;
    [
        1.2 * u + 0.1 * (PI * v).sin() * w,
        0.9 * v + 0.15 * u * u + 0.05 * w,
        0.8 * w + 0.1 * (PI * u).sin() * v + 0.05 * u,
    ]
}

/// SplitMix64 in [-1, 1).
pub struct Rng(pub u64);

impl Rng {
    pub fn symmetric(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        2.0 * ((z >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }
}

/// An n³ block of `kind` on the warped cube with interior points (and pyramid
/// centres) moved at random by up to `jitter` cell sizes: general, non-affine cells.
pub fn distorted(kind: BlockKind, n: usize, jitter: f64) -> (VolumeMesh, Grid) {
    let grid = Grid::new(n, n, n);
    let mesh = block(n, n, n, warp, kind);
    let mut rng = Rng(n as u64 * 31 + kind as u64);
    let h = 1.0 / n as f64;
    let points: Vec<Point3> = mesh
        .points()
        .iter()
        .enumerate()
        .map(|(p, x)| {
            if grid.on_boundary(p) {
                *x
            } else {
                let d = [rng.symmetric(), rng.symmetric(), rng.symmetric()];
                [x[0] + jitter * h * d[0], x[1] + jitter * h * d[1], x[2] + jitter * h * d[2]]
            }
        })
        .collect();
    (VolumeMesh::new(points, mesh.cells().to_vec()).unwrap(), grid)
}

/// The affine field u = A x + c of the patch tests.
pub const A: [[f64; 3]; 3] = [[1e-3, 2e-4, -3e-4], [-1e-4, -5e-4, 4e-4], [3e-4, 1e-4, 7e-4]];
/// Its translation.
pub const C: [f64; 3] = [1e-3, -2e-3, 5e-4];

pub fn affine(x: Point3) -> [f64; 3] {
    std::array::from_fn(|i| C[i] + A[i][0] * x[0] + A[i][1] * x[1] + A[i][2] * x[2])
}

/// The constant stress of the affine field (Voigt xx yy zz yz xz xy).
pub fn affine_stress(m: &Material) -> [f64; 6] {
    m.stress([A[0][0], A[1][1], A[2][2], A[1][2] + A[2][1], A[0][2] + A[2][0], A[0][1] + A[1][0]])
}

/// σ as a 3×3 tensor from Voigt.
pub fn tensor(s: &[f64; 6]) -> [[f64; 3]; 3] {
    [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]]
}

pub fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The kind name of a cell.
pub fn kind_name(c: &Cell) -> &'static str {
    match c {
        Cell::Tet4(_) => "tet",
        Cell::Hex8(_) => "hex",
        Cell::Prism6(_) => "prism",
        Cell::Pyramid5(_) => "pyramid",
    }
}

pub const KINDS: [BlockKind; 4] = [BlockKind::Hex, BlockKind::Tet, BlockKind::Prism, BlockKind::Pyramid];

/// The mixed Gmsh mesh (tets, hexes, pyramids) from seam-io's fixtures.
pub fn hybrid() -> VolumeMesh {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../seam-io/tests/data/hybrid_pyramid.v41.ascii.msh");
    seam_io::read_volume_file(path, None).unwrap()
}
