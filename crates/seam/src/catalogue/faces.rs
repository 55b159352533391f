//! The face tables: Tri3, Quad4 and their second-order versions Tri6, Quad8
//! and Quad9, with their shape functions.
//!
//! | face | reference cell | shape functions |
//! |---|---|---|
//! | Tri3 | {(0,0), (1,0), (0,1)} | 1−ξ−η, ξ, η |
//! | Quad4 | \[0,1\]² | (1−ξ)(1−η), ξ(1−η), ξη, (1−ξ)η |
//! | Tri6 | {(0,0), (1,0), (0,1)} | L_i(2L_i − 1) at vertices, 4 L_i L_j at mid-edges (L = 1−ξ−η, ξ, η) |
//! | Quad9 | \[0,1\]² | tensor products of ℓ₀ = (1−s)(1−2s), ℓ₁ = s(2s−1), ℓ_m = 4s(1−s) |
//! | Quad8 | \[0,1\]² | serendipity: Quad9 without the centre bubble, its share given to the others |
//! | Tri7 | {(0,0), (1,0), (0,1)} | Tri6 enriched by the cubic bubble b = 27 L₀L₁L₂ at the centre, nodal: Tri6's minus their values at the centre times b |
//!
//! Tri6 and Quad9 reproduce every quadratic polynomial in (ξ, η), Quad8 every
//! one of degree 2 (and ξ²η, ξη²), Tri7 every quadratic one and the bubble.

use super::{FaceKind, FaceType, Shape, Xi};

/// The largest number of nodes of a face (Quad9).
pub const MAX_FACE_NODES: usize = 9;

/// The biquadratic monomials m(ξ) = (1, s, t, s², st, t², s²t, st², s²t²) in
/// which every face map is a polynomial ([`FaceType::monomials`]).
pub(crate) const MONOMIALS: usize = 9;

const TRI7_NODES: [Xi; 7] =
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5], [1.0 / 3.0, 1.0 / 3.0]];
const TRI6_NODES: &[Xi] = TRI7_NODES.as_slice().split_at(6).0;
const QUAD9_NODES: [Xi; 9] = [
    [0.0, 0.0],
    [1.0, 0.0],
    [1.0, 1.0],
    [0.0, 1.0],
    [0.5, 0.0],
    [1.0, 0.5],
    [0.5, 1.0],
    [0.0, 0.5],
    [0.5, 0.5],
];
const TRIANGLE_EDGES: [[usize; 2]; 3] = [[0, 1], [1, 2], [2, 0]];
const QUAD_EDGES: [[usize; 2]; 4] = [[0, 1], [1, 2], [2, 3], [3, 0]];
/// Reversal keeps the first corner; mid-edge nodes follow their edges.
const TRI7_REVERSED: [usize; 7] = [0, 2, 1, 5, 4, 3, 6];
const TRI6_REVERSED: &[usize] = TRI7_REVERSED.as_slice().split_at(6).0;
const QUAD9_REVERSED: [usize; 9] = [0, 3, 2, 1, 7, 6, 5, 4, 8];
/// Gmsh and VTK number the nodes of every face kind alike.
const IDENTITY: [usize; 9] = [0, 1, 2, 3, 4, 5, 6, 7, 8];

pub(super) const TRI3: FaceType = FaceType {
    name: "Tri3",
    shape: Shape::Triangle,
    linear: FaceKind::Tri3,
    nodes: TRI7_NODES.as_slice().split_at(3).0,
    corners: 3,
    edges: &TRIANGLE_EDGES,
    reversed: TRI7_REVERSED.as_slice().split_at(3).0,
    pieces: &[&[0, 1, 2]],
    gmsh_type: Some(2),
    vtk_type: 5,
    vtk_order: IDENTITY.as_slice().split_at(3).0,
    shape_and_gradients: tri3,
    monomials: {
        let mut c = [[0.0; MONOMIALS]; MAX_FACE_NODES];
        c[0] = [1.0, -1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        c[1][1] = 1.0;
        c[2][2] = 1.0;
        c
    },
    n_monomials: 3,
    enriched: None,
    positive_integrals: true,
};

pub(super) const QUAD4: FaceType = FaceType {
    name: "Quad4",
    shape: Shape::Quadrangle,
    linear: FaceKind::Quad4,
    nodes: QUAD9_NODES.as_slice().split_at(4).0,
    corners: 4,
    edges: &QUAD_EDGES,
    reversed: QUAD9_REVERSED.as_slice().split_at(4).0,
    pieces: &[&[0, 1, 2, 3]],
    gmsh_type: Some(3),
    vtk_type: 9,
    vtk_order: IDENTITY.as_slice().split_at(4).0,
    shape_and_gradients: quad4,
    monomials: {
        let mut c = [[0.0; MONOMIALS]; MAX_FACE_NODES];
        c[0] = [1.0, -1.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0];
        c[1] = [0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0];
        c[2][4] = 1.0;
        c[3] = [0.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0];
        c
    },
    n_monomials: 5,
    enriched: None,
    positive_integrals: true,
};

pub(super) const TRI6: FaceType = FaceType {
    name: "Tri6",
    shape: Shape::Triangle,
    linear: FaceKind::Tri3,
    nodes: TRI6_NODES,
    corners: 3,
    edges: &TRIANGLE_EDGES,
    reversed: TRI6_REVERSED,
    pieces: &[&[0, 3, 5], &[3, 1, 4], &[5, 4, 2], &[3, 4, 5]],
    gmsh_type: Some(9),
    vtk_type: 22,
    vtk_order: IDENTITY.as_slice().split_at(6).0,
    shape_and_gradients: tri6,
    monomials: {
        let mut c = [[0.0; MONOMIALS]; MAX_FACE_NODES];
        c[0] = [1.0, -3.0, -3.0, 2.0, 4.0, 2.0, 0.0, 0.0, 0.0];
        c[1] = [0.0, -1.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        c[2] = [0.0, 0.0, -1.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0];
        c[3] = [0.0, 4.0, 0.0, -4.0, -4.0, 0.0, 0.0, 0.0, 0.0];
        c[4][4] = 4.0;
        c[5] = [0.0, 0.0, 4.0, 0.0, -4.0, -4.0, 0.0, 0.0, 0.0];
        c
    },
    n_monomials: 6,
    enriched: Some(FaceKind::Tri7),
    positive_integrals: false,
};

pub(super) const QUAD8: FaceType = FaceType {
    name: "Quad8",
    shape: Shape::Quadrangle,
    linear: FaceKind::Quad4,
    nodes: QUAD9_NODES.as_slice().split_at(8).0,
    corners: 4,
    edges: &QUAD_EDGES,
    reversed: QUAD9_REVERSED.as_slice().split_at(8).0,
    pieces: &[&[0, 4, 1, 5, 2, 6, 3, 7]],
    gmsh_type: Some(16),
    vtk_type: 23,
    vtk_order: IDENTITY.as_slice().split_at(8).0,
    shape_and_gradients: quad8,
    monomials: quadratic_quad_monomials(true),
    n_monomials: 8,
    enriched: Some(FaceKind::Quad9),
    positive_integrals: false,
};

pub(super) const QUAD9: FaceType = FaceType {
    name: "Quad9",
    shape: Shape::Quadrangle,
    linear: FaceKind::Quad4,
    nodes: &QUAD9_NODES,
    corners: 4,
    edges: &QUAD_EDGES,
    reversed: &QUAD9_REVERSED,
    pieces: &[&[0, 4, 8, 7], &[4, 1, 5, 8], &[8, 5, 2, 6], &[7, 8, 6, 3]],
    gmsh_type: Some(10),
    vtk_type: 28,
    vtk_order: &IDENTITY,
    shape_and_gradients: quad9,
    monomials: quadratic_quad_monomials(false),
    n_monomials: 9,
    enriched: None,
    positive_integrals: true,
};

/// Seven-node triangle: Tri6 enriched by the cubic face bubble, which the
/// dual multipliers of an enriched slave space need ([`crate::mesh::SurfaceMesh::enriched`]):
/// every function has a positive integral (corners A/20, mid-edge nodes 2A/15,
/// centre 9A/20) and, on a flat face, its weighted centroid at its node. VTK's
/// biquadratic triangle; Gmsh has no such type.
pub(super) const TRI7: FaceType = FaceType {
    name: "Tri7",
    shape: Shape::Triangle,
    linear: FaceKind::Tri3,
    nodes: &TRI7_NODES,
    corners: 3,
    edges: &TRIANGLE_EDGES,
    reversed: &TRI7_REVERSED,
    pieces: &[&[0, 3, 6], &[3, 1, 6], &[1, 4, 6], &[4, 2, 6], &[2, 5, 6], &[5, 0, 6]],
    gmsh_type: None,
    vtk_type: 34,
    vtk_order: IDENTITY.as_slice().split_at(7).0,
    shape_and_gradients: tri7,
    monomials: {
        // Tri6's rows, plus 3P at corners, −12P at mid-edge nodes and 27P at
        // the centre, P = L₀L₁L₂ = st − s²t − st².
        let mut c = TRI6.monomials;
        let w = [3.0, 3.0, 3.0, -12.0, -12.0, -12.0, 27.0];
        let mut i = 0;
        while i < 7 {
            c[i][4] += w[i];
            c[i][6] -= w[i];
            c[i][7] -= w[i];
            i += 1;
        }
        c
    },
    n_monomials: 8,
    enriched: None,
    positive_integrals: true,
};

/// (index along ξ, index along η) of each Quad9 node in the 3 × 3 tensor grid
/// of 1D Lagrange functions.
pub(crate) const QUAD9_GRID: [(usize, usize); 9] =
    [(0, 0), (1, 0), (1, 1), (0, 1), (2, 0), (1, 2), (2, 1), (0, 2), (2, 2)];

/// Quadratic Lagrange polynomials on [0, 1] with nodes 0, 1, 1/2 and their
/// derivatives: ([ℓ₀, ℓ₁, ℓ_m], [ℓ₀', ℓ₁', ℓ_m']).
#[inline]
fn lagrange(s: f64) -> ([f64; 3], [f64; 3]) {
    (
        [(1.0 - s) * (1.0 - 2.0 * s), s * (2.0 * s - 1.0), 4.0 * s * (1.0 - s)],
        [4.0 * s - 3.0, 4.0 * s - 1.0, 4.0 - 8.0 * s],
    )
}

/// Shape function values N_i(ξ) and gradients ∂N_i/∂(ξ, η) of a face, entries
/// past its node count 0.
pub type ShapeAndGradients = ([f64; MAX_FACE_NODES], [[f64; 2]; MAX_FACE_NODES]);

/// Shape functions N_i(ξ) and gradients ∂N_i/∂(ξ, η) of `kind`; entries past
/// `kind.n_nodes()` are 0.
#[inline]
pub fn shape_and_gradients(kind: FaceKind, xi: Xi) -> ShapeAndGradients {
    kind.shape_and_gradients(xi)
}

fn tri3(xi: Xi) -> ShapeAndGradients {
    let (mut n, mut g) = ([0.0; 9], [[0.0; 2]; 9]);
    n[..3].copy_from_slice(&shape_values::<3>(xi));
    g[..3].copy_from_slice(&[[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]);
    (n, g)
}

fn quad4(xi: Xi) -> ShapeAndGradients {
    let (mut n, mut g) = ([0.0; 9], [[0.0; 2]; 9]);
    let [s, t] = xi;
    n[..4].copy_from_slice(&shape_values::<4>(xi));
    g[..4].copy_from_slice(&[[t - 1.0, s - 1.0], [1.0 - t, -s], [t, s], [-t, 1.0 - s]]);
    (n, g)
}

/// Barycentric l = (1 − s − t, s, t): vertices l_i (2 l_i − 1), mid-edge
/// nodes 4 l_i l_(i+1).
fn tri6(xi: Xi) -> ShapeAndGradients {
    let (mut n, mut g) = ([0.0; 9], [[0.0; 2]; 9]);
    let [s, t] = xi;
    let l0 = 1.0 - s - t;
    n[..6].copy_from_slice(&shape_values::<6>(xi));
    let (c0, c1, c2) = (4.0 * l0 - 1.0, 4.0 * s - 1.0, 4.0 * t - 1.0);
    g[..6].copy_from_slice(&[
        [-c0, -c0],
        [c1, 0.0],
        [0.0, c2],
        [4.0 * (l0 - s), -4.0 * s],
        [4.0 * t, 4.0 * s],
        [-4.0 * t, 4.0 * (l0 - t)],
    ]);
    (n, g)
}

/// Tri6's functions minus their values at the centre (−1/9 at vertices, 4/9
/// at mid-edge nodes) times the bubble b = 27 L₀L₁L₂, and b.
fn tri7(xi: Xi) -> ShapeAndGradients {
    let (mut n, mut g) = tri6(xi);
    let [s, t] = xi;
    let l0 = 1.0 - s - t;
    let (b, db) = (27.0 * l0 * s * t, [27.0 * t * (l0 - s), 27.0 * s * (l0 - t)]);
    for i in 0..6 {
        let w = if i < 3 { 1.0 / 9.0 } else { -4.0 / 9.0 };
        n[i] += w * b;
        g[i] = [g[i][0] + w * db[0], g[i][1] + w * db[1]];
    }
    (n[6], g[6]) = (b, db);
    (n, g)
}

fn quad8(xi: Xi) -> ShapeAndGradients {
    quadratic_quad(xi, true)
}

fn quad9(xi: Xi) -> ShapeAndGradients {
    quadratic_quad(xi, false)
}

/// Quad9's tensor-product functions, or with `serendipity` Quad8's: the
/// bubble N₈ = ℓ_m ℓ_m goes back to the other nodes by its values there (−1/4
/// at vertices, +1/2 at mid-edges).
#[inline]
fn quadratic_quad(xi: Xi, serendipity: bool) -> ShapeAndGradients {
    let (mut n, mut g) = ([0.0; 9], [[0.0; 2]; 9]);
    let ((a, da), (b, db)) = (lagrange(xi[0]), lagrange(xi[1]));
    for (i, &(p, q)) in QUAD9_GRID.iter().enumerate() {
        n[i] = a[p] * b[q];
        g[i] = [da[p] * b[q], a[p] * db[q]];
    }
    if serendipity {
        let (bubble, grad) = (n[8], g[8]);
        for i in 0..8 {
            let w = if i < 4 { -0.25 } else { 0.5 };
            n[i] += w * bubble;
            g[i] = [g[i][0] + w * grad[0], g[i][1] + w * grad[1]];
        }
        n[8] = 0.0;
        g[8] = [0.0; 2];
    }
    (n, g)
}

/// The first-order shape functions at ξ: Tri3's (`triangle`, fourth entry 0)
/// or Quad4's; the form the first-order kernel computes with.
#[inline(always)]
pub(crate) fn first_order_values(triangle: bool, xi: Xi) -> [f64; 4] {
    let [s, t] = xi;
    if triangle {
        [1.0 - s - t, s, t, 0.0]
    } else {
        [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t]
    }
}

/// Shape function values N_i(ξ) of the kind with `N` nodes (3 Tri3, 4 Quad4,
/// 6 Tri6, 7 Tri7, 8 Quad8, 9 Quad9): [`shape_and_gradients`] without the gradients,
/// sized for the quadrature loops.
#[inline(always)]
pub fn shape_values<const N: usize>(xi: Xi) -> [f64; N] {
    let [s, t] = xi;
    let mut n = [0.0; N];
    match N {
        3 | 4 => n.copy_from_slice(&first_order_values(N == 3, xi)[..N]),
        6 | 7 => {
            let l0 = 1.0 - s - t;
            let mut all = [
                l0 * (2.0 * l0 - 1.0),
                s * (2.0 * s - 1.0),
                t * (2.0 * t - 1.0),
                4.0 * l0 * s,
                4.0 * s * t,
                4.0 * t * l0,
                0.0,
            ];
            if N == 7 {
                // Tri7: the bubble takes its values at the centre from the others.
                let b = 27.0 * l0 * s * t;
                for (i, v) in all.iter_mut().enumerate().take(6) {
                    *v += if i < 3 { 1.0 / 9.0 } else { -4.0 / 9.0 } * b;
                }
                all[6] = b;
            }
            n.copy_from_slice(&all[..N]);
        }
        8 | 9 => {
            let (a, b) = (lagrange(s).0, lagrange(t).0);
            let mut all = [0.0; 9];
            for (i, &(p, q)) in QUAD9_GRID.iter().enumerate() {
                all[i] = a[p] * b[q];
            }
            if N == 8 {
                // Serendipity: the bubble goes back to the other nodes.
                let bubble = all[8];
                for (i, v) in all.iter_mut().enumerate().take(8) {
                    *v += if i < 4 { -0.25 } else { 0.5 } * bubble;
                }
            }
            n.copy_from_slice(&all[..N]);
        }
        _ => unreachable!("faces have 3, 4, 6, 7, 8 or 9 nodes"),
    }
    n
}

/// Row i: the coefficients of N_i of Quad9 (or with `serendipity` Quad8) in
/// the monomials: N_i = L_p(s) L_q(t) ([`QUAD9_GRID`]), L ([`lagrange`]) in
/// powers of its variable.
const fn quadratic_quad_monomials(serendipity: bool) -> [[f64; MONOMIALS]; MAX_FACE_NODES] {
    // INDEX[a][b] is the monomial s^a t^b.
    const L: [[f64; 3]; 3] = [[1.0, -3.0, 2.0], [0.0, -1.0, 2.0], [0.0, 4.0, -4.0]];
    const INDEX: [[usize; 3]; 3] = [[0, 2, 5], [1, 4, 7], [3, 6, 8]];
    let mut c = [[0.0; MONOMIALS]; MAX_FACE_NODES];
    let mut i = 0;
    while i < 9 {
        let (p, q) = QUAD9_GRID[i];
        let mut a = 0;
        while a < 3 {
            let mut b = 0;
            while b < 3 {
                c[i][INDEX[a][b]] = L[p][a] * L[q][b];
                b += 1;
            }
            a += 1;
        }
        i += 1;
    }
    if serendipity {
        // The bubble goes back to the other nodes.
        let mut i = 0;
        while i < 8 {
            let w = if i < 4 { -0.25 } else { 0.5 };
            let mut k = 0;
            while k < MONOMIALS {
                c[i][k] += w * c[8][k];
                k += 1;
            }
            i += 1;
        }
        c[8] = [0.0; MONOMIALS];
    }
    c
}
