//! Surface patches on parametric maps (u, v) ∈ \[0,1\]² ↦ x(u, v): the meshes of
//! seam's built-in examples, tests and benchmarks.
//!
//! Points are numbered row by row, `j·(nu+1) + i` for the grid point (i, j).
//! Faces are counter-clockwise in (u, v), so their normals follow ∂x/∂u × ∂x/∂v.

use crate::catalogue::FaceKind;
use crate::mesh::{Face, Point3, SurfaceMesh};

/// How the grid cells are filled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pattern {
    /// One bilinear quad per cell (warped wherever the map is not affine).
    Quads,
    /// Two triangles per cell, the diagonal alternating like a chequerboard.
    Triangles,
    /// As `Triangles`, with interior grid points moved at random by up to
    /// `amplitude` cell sizes (boundary points slide along the boundary only), so
    /// that the mesh matches no structured one.
    JitteredTriangles {
        /// Largest move, in cell sizes (keep below 0.3 for valid triangles).
        amplitude: f64,
        /// Seed of the deterministic generator.
        seed: u64,
    },
    /// As `Quads`, with the grid points moved as for `JitteredTriangles`: general
    /// convex quads, not parallelograms.
    JitteredQuads {
        /// Largest move, in cell sizes, along each axis (up to about 0.3 the quads
        /// stay convex; larger moves can fold them).
        amplitude: f64,
        /// Seed of the deterministic generator.
        seed: u64,
    },
}

/// A patch of `nu × nv` cells on the map `x`.
///
/// # Panics
/// If `nu` or `nv` is zero, or the map makes a degenerate face.
pub fn patch(nu: usize, nv: usize, pattern: Pattern, x: impl Fn(f64, f64) -> Point3) -> SurfaceMesh {
    assert!(nu > 0 && nv > 0, "a patch needs at least one cell in each direction");
    let jitter = match pattern {
        Pattern::JitteredTriangles { amplitude, seed } | Pattern::JitteredQuads { amplitude, seed } => {
            Some((amplitude, seed))
        }
        Pattern::Quads | Pattern::Triangles => None,
    };
    let points: Vec<Point3> = grid_parameters(nu, nv, jitter).into_iter().map(|[u, v]| x(u, v)).collect();
    let id = |i: usize, j: usize| j * (nu + 1) + i;
    let mut faces = Vec::with_capacity(nu * nv * 2);
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            match pattern {
                Pattern::Quads | Pattern::JitteredQuads { .. } => faces.push(Face::Quad4([a, b, c, d])),
                _ if (i + j) % 2 == 0 => faces.extend([Face::Tri3([a, b, c]), Face::Tri3([a, c, d])]),
                _ => faces.extend([Face::Tri3([a, b, d]), Face::Tri3([b, c, d])]),
            }
        }
    }
    SurfaceMesh::new(points, faces).expect("the parametric map makes a valid patch")
}

/// The (u, v) of the grid points, row by row, interior points moved at random
/// by up to `amplitude` cell sizes when `jitter = Some((amplitude, seed))`
/// (boundary points slide along the boundary only).
fn grid_parameters(nu: usize, nv: usize, jitter: Option<(f64, u64)>) -> Vec<[f64; 2]> {
    let (amplitude, mut rng) = jitter.map_or((0.0, SplitMix64(0)), |(a, seed)| (a, SplitMix64(seed)));
    let mut uv = Vec::with_capacity((nu + 1) * (nv + 1));
    for j in 0..=nv {
        for i in 0..=nu {
            let mut du = amplitude * rng.symmetric() / nu as f64;
            let mut dv = amplitude * rng.symmetric() / nv as f64;
            if i == 0 || i == nu {
                du = 0.0;
            }
            if j == 0 || j == nv {
                dv = 0.0;
            }
            uv.push([i as f64 / nu as f64 + du, j as f64 / nv as f64 + dv]);
        }
    }
    uv
}

/// A patch of `nu × nv` cells of second-order faces on the map `x`: every
/// node, mid-edge and centre ones included, is a point of the surface, at the
/// parameter midpoint of its edge or cell (so faces are curved where the map
/// is; a Tri6 diagonal's mid node is the cell's centre point). With `jitter = Some((amplitude, seed))` the cell corners move as in
/// [`Pattern::JitteredTriangles`]. Points are numbered row by row on the
/// refined grid, `j·(2nu+1) + i` for the grid point (i, j), corners at even
/// (i, j).
///
/// # Panics
/// If `nu` or `nv` is zero, `kind` is not of second order, or the map makes a
/// degenerate face.
pub fn quadratic_patch(
    nu: usize,
    nv: usize,
    kind: FaceKind,
    jitter: Option<(f64, u64)>,
    x: impl Fn(f64, f64) -> Point3,
) -> SurfaceMesh {
    assert!(nu > 0 && nv > 0, "a patch needs at least one cell in each direction");
    assert!(kind.order() == 2, "a quadratic patch has Tri6, Quad8 or Quad9 faces, not {kind:?}");
    let corners = grid_parameters(nu, nv, jitter);
    let (mu, mv) = (2 * nu + 1, 2 * nv + 1);
    let corner = |i: usize, j: usize| corners[j * (nu + 1) + i];
    // Parameters of refined grid point (i, j): the mean of the corners around it.
    let parameter = |i: usize, j: usize| -> [f64; 2] {
        let is = if i % 2 == 0 { vec![i / 2] } else { vec![i / 2, i / 2 + 1] };
        let js = if j % 2 == 0 { vec![j / 2] } else { vec![j / 2, j / 2 + 1] };
        let n = (is.len() * js.len()) as f64;
        let mut p = [0.0; 2];
        for &a in &is {
            for &b in &js {
                let c = corner(a, b);
                p = [p[0] + c[0] / n, p[1] + c[1] / n];
            }
        }
        p
    };
    let points: Vec<Point3> = (0..mu * mv)
        .map(|k| {
            let [u, v] = parameter(k % mu, k / mu);
            x(u, v)
        })
        .collect();
    let id = |i: usize, j: usize| j * mu + i;
    let mut faces = Vec::with_capacity(nu * nv * 2);
    for j in 0..nv {
        for i in 0..nu {
            let (i, j) = (2 * i, 2 * j);
            let [c0, c1, c2, c3] = [id(i, j), id(i + 2, j), id(i + 2, j + 2), id(i, j + 2)];
            let [m0, m1, m2, m3] = [id(i + 1, j), id(i + 2, j + 1), id(i + 1, j + 2), id(i, j + 1)];
            let centre = id(i + 1, j + 1);
            if !kind.is_triangle() {
                // Quad9's nodes; Quad8 has all but the centre.
                let nodes = [c0, c1, c2, c3, m0, m1, m2, m3, centre];
                faces.push(Face::new(kind, &nodes[..kind.n_nodes()]).expect("the kind's node count"));
            } else if (i + j) % 4 == 0 {
                // The diagonal's mid node is the cell's centre point.
                faces.extend([
                    Face::Tri6([c0, c1, c2, m0, m1, centre]),
                    Face::Tri6([c0, c2, c3, centre, m2, m3]),
                ]);
            } else {
                faces.extend([
                    Face::Tri6([c0, c1, c3, m0, centre, m3]),
                    Face::Tri6([c1, c2, c3, m1, m2, centre]),
                ]);
            }
        }
    }
    SurfaceMesh::new(points, faces).expect("the parametric map makes a valid patch")
}

/// The plane z = 0 over [0, a] × [0, b].
pub fn flat(a: f64, b: f64) -> impl Fn(f64, f64) -> Point3 {
    move |u, v| [a * u, b * v, 0.0]
}

/// The hyperbolic paraboloid z = c·x·y over \[0,1\]²: its bilinear quads are the
/// exact surface, every one of them warped.
pub fn hyperbolic_paraboloid(c: f64) -> impl Fn(f64, f64) -> Point3 {
    move |u, v| [u, v, c * u * v]
}

/// A cylinder patch of radius `r` about the z axis: angle θ ∈ [0, `angle`],
/// height z ∈ [0, `height`].
pub fn cylinder(r: f64, angle: f64, height: f64) -> impl Fn(f64, f64) -> Point3 {
    move |u, v| {
        let t = angle * u;
        [r * t.cos(), r * t.sin(), height * v]
    }
}

/// SplitMix64: a tiny deterministic generator, enough for jitter.
struct SplitMix64(u64);

impl SplitMix64 {
    /// A number in [−1, 1).
    fn symmetric(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_numbering() {
        let q = patch(3, 2, Pattern::Quads, flat(3.0, 2.0));
        assert_eq!((q.n_points(), q.n_faces()), (12, 6));
        assert_eq!(q.points()[5], [1.0, 1.0, 0.0]);
        let t = patch(3, 2, Pattern::JitteredTriangles { amplitude: 0.25, seed: 7 }, flat(1.0, 1.0));
        assert_eq!(t.n_faces(), 12);
        // Corners stay put; boundary points stay on the boundary.
        assert_eq!(t.points()[0], [0.0, 0.0, 0.0]);
        assert_eq!(t.points()[11], [1.0, 1.0, 0.0]);
        assert_eq!(t.points()[1][1], 0.0);
    }
}
