//! The cell tables: Tet4, Hex8, Prism6, Pyramid5 and their second-order
//! versions, with their shape functions.
//!
//! | element | reference cell | nodes (Gmsh order) | N_i |
//! |---|---|---|---|
//! | Tet4 | ξ, η, ζ ≥ 0, ξ+η+ζ ≤ 1 | (0,0,0) (1,0,0) (0,1,0) (0,0,1) | 1−ξ−η−ζ, ξ, η, ζ |
//! | Hex8 | \[−1,1\]³ | bottom ζ=−1: (−1,−1) (1,−1) (1,1) (−1,1), then top ζ=1 | ⅛(1+ξ_iξ)(1+η_iη)(1+ζ_iζ) |
//! | Prism6 | triangle {(0,0),(1,0),(0,1)} × \[−1,1\] | bottom ζ=−1: (0,0) (1,0) (0,1), then top | L_i(ξ,η)·½(1∓ζ) |
//! | Pyramid5 | base \[−1,1\]² at ζ=0, apex (0,0,1) | (−1,−1,0) (1,−1,0) (1,1,0) (−1,1,0) (0,0,1) | see below |
//!
//! **Pyramid** (Bedrosian's rational functions = the trilinear hex collapsed onto
//! its apex): with s = 1−ζ,
//!
//! ```text
//! N_i = ¼ (s + ξ_i ξ + η_i η + ξ_i η_i ξη/s)   (base corners i = 0..3),    N_4 = ζ.
//! ```
//!
//! In the collapsed coordinates ξ = a·s, η = b·s (a, b ∈ \[−1,1\]) they read
//! ¼(1+ξ_i a)(1+η_i b)·s: polynomial, and so are their physical gradients times
//! the Jacobian. At the apex itself (s = 0) the rational term is taken as 0, its
//! limit along the axis; quadrature never evaluates it there.
//!
//! # Second-order elements
//!
//! Tet10, Hex20, Hex27, Prism15, Prism18, Pyramid13 and Pyramid14 live on the
//! reference cells of their first-order families with Gmsh's nodes (corners,
//! mid-edge nodes in Gmsh's edge order, quadrilateral face centres, the Hex27
//! centre). Their shape functions are the nodal (Lagrange) basis of a space V
//! spanned by terms φ_k = ξ^a η^b ζ^c / (1−ζ)^d ([`Space`]): N_i = Σ_k C_ki φ_k
//! with C = V⁻¹, V_jk = φ_k(node_j), so that N_i(node_j) = δ_ij by construction
//! (C is computed once, by Gaussian elimination with partial pivoting).
//!
//! | element | space V | dim |
//! |---|---|---:|
//! | Tet10 | P₂ | 10 |
//! | Hex27 | Q₂ (degree ≤ 2 in each variable) | 27 |
//! | Hex20 | serendipity S₂: Q₂ monomials with at most one squared variable | 20 |
//! | Prism18 | P₂(ξ, η) ⊗ P₂(ζ) | 18 |
//! | Prism15 | P₂(ξ, η) ⊗ P₁(ζ) ⊕ P₁(ξ, η) ζ² | 15 |
//! | Pyramid14 | P₂ ⊕ span{ξη/s, ξ²η/s, ξη²/s, ξ²η²/s²}, s = 1−ζ | 14 |
//! | Pyramid13 | P₂ ⊕ span{ξη/s, ξ²η/s, ξη²/s} | 13 |
//!
//! Pyramid14 is the rational space of Bergot, Cohen & Duruflé (2010) for r = 2,
//! B₂ = P₂ ⊕ Σ_{k<2} (ξη/s)^{2−k} P_k(ξ, η), which contains the Pyramid5 space of
//! Bedrosian (1992); Pyramid13 drops its ξ²η²/s² term, which leaves the
//! serendipity (Quad8) trace on the base. Both contain P₂, so every quadratic
//! field is reproduced; on a triangular face (e.g. η = −s) every term is a
//! quadratic polynomial of the face coordinates, on the base (s = 1) the traces
//! are Q₂ (Pyramid14) and S₂ (Pyramid13): the traces are those of Tri6, Quad9
//! and Quad8, determined by the face's nodes, so neighbouring cells match. At
//! the apex (s = 0) the rational terms and their gradients are taken as 0, their
//! limits along the axis. In collapsed coordinates (a, b, ζ) every term and
//! s·gradient is polynomial.

use std::sync::LazyLock;

use super::{CellKind, CellType, FaceKind, LocalFace, Shape, StiffnessRule, Xi3, MAX_FACE_NODES};

/// The largest number of nodes of a cell (Hex27).
pub const MAX_CELL_NODES: usize = 27;

/// How a cell kind's shape functions are computed ([`CellType::basis`]).
#[derive(Clone, Copy, Debug)]
pub enum CellBasis {
    /// Closed forms (the first-order kinds); entries past the node count are 0.
    Closed {
        /// N_i(ξ).
        shape: fn(Xi3) -> [f64; MAX_CELL_NODES],
        /// ∇_ξ N_i(ξ).
        gradients: fn(Xi3) -> [[f64; 3]; MAX_CELL_NODES],
    },
    /// The nodal basis of a space at the kind's nodes (the second-order kinds).
    Nodal(Space),
}

/// A term φ = ξ^a η^b ζ^c / (1−ζ)^d of a second-order space, as \[a, b, c, d\].
pub type Term = [u8; 4];

/// A space of shape functions: the monomials ξ^a η^b ζ^c with a, b, c ≤ 2 that
/// `keep` accepts (ordered by c, then b, then a), then the `rational` terms.
#[derive(Clone, Copy, Debug)]
pub struct Space {
    /// Which monomials \[a, b, c\] the space has.
    pub keep: fn([u8; 3]) -> bool,
    /// Rational terms after the monomials (pyramids).
    pub rational: &'static [Term],
}

impl Space {
    /// The terms, in order.
    pub fn terms(&self) -> Vec<Term> {
        let mut t = Vec::new();
        for c in 0..=2u8 {
            for b in 0..=2u8 {
                for a in 0..=2u8 {
                    if (self.keep)([a, b, c]) {
                        t.push([a, b, c, 0]);
                    }
                }
            }
        }
        t.extend_from_slice(self.rational);
        t
    }
}

/// Tet14 in seam's order: Tet10's nodes (Gmsh's), then the centroids of the
/// faces in [`TET_FACES`] order; Tet4 and Tet10 are its first 4 and 10.
const TET14_NODES: [Xi3; 14] = [
    [0., 0., 0.],
    [1., 0., 0.],
    [0., 1., 0.],
    [0., 0., 1.],
    [0.5, 0., 0.],
    [0.5, 0.5, 0.],
    [0., 0.5, 0.],
    [0., 0., 0.5],
    [0., 0.5, 0.5],
    [0.5, 0., 0.5],
    [1. / 3., 1. / 3., 0.],
    [1. / 3., 0., 1. / 3.],
    [0., 1. / 3., 1. / 3.],
    [1. / 3., 1. / 3., 1. / 3.],
];
/// Hex27 in Gmsh order; Hex8 and Hex20 are its first 8 and 20 nodes.
const HEX27_NODES: [Xi3; 27] = [
    [-1., -1., -1.],
    [1., -1., -1.],
    [1., 1., -1.],
    [-1., 1., -1.],
    [-1., -1., 1.],
    [1., -1., 1.],
    [1., 1., 1.],
    [-1., 1., 1.],
    [0., -1., -1.],
    [-1., 0., -1.],
    [-1., -1., 0.],
    [1., 0., -1.],
    [1., -1., 0.],
    [0., 1., -1.],
    [1., 1., 0.],
    [-1., 1., 0.],
    [0., -1., 1.],
    [-1., 0., 1.],
    [1., 0., 1.],
    [0., 1., 1.],
    [0., 0., -1.],
    [0., -1., 0.],
    [-1., 0., 0.],
    [1., 0., 0.],
    [0., 1., 0.],
    [0., 0., 1.],
    [0., 0., 0.],
];
/// Prism18 in Gmsh order; Prism6 and Prism15 are its first 6 and 15 nodes.
const PRISM18_NODES: [Xi3; 18] = [
    [0., 0., -1.],
    [1., 0., -1.],
    [0., 1., -1.],
    [0., 0., 1.],
    [1., 0., 1.],
    [0., 1., 1.],
    [0.5, 0., -1.],
    [0., 0.5, -1.],
    [0., 0., 0.],
    [0.5, 0.5, -1.],
    [1., 0., 0.],
    [0., 1., 0.],
    [0.5, 0., 1.],
    [0., 0.5, 1.],
    [0.5, 0.5, 1.],
    [0.5, 0., 0.],
    [0., 0.5, 0.],
    [0.5, 0.5, 0.],
];
/// Pyramid14 in Gmsh order; Pyramid5 and Pyramid13 are its first 5 and 13 nodes.
const PYRAMID14_NODES: [Xi3; 14] = [
    [-1., -1., 0.],
    [1., -1., 0.],
    [1., 1., 0.],
    [-1., 1., 0.],
    [0., 0., 1.],
    [0., -1., 0.],
    [-1., 0., 0.],
    [-0.5, -0.5, 0.5],
    [1., 0., 0.],
    [0.5, -0.5, 0.5],
    [0., 1., 0.],
    [0.5, 0.5, 0.5],
    [-0.5, 0.5, 0.5],
    [0., 0., 0.],
];

const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [0, 2], [0, 3], [2, 3], [1, 3]];
const HEX_EDGES: [[usize; 2]; 12] =
    [[0, 1], [0, 3], [0, 4], [1, 2], [1, 5], [2, 3], [2, 6], [3, 7], [4, 5], [4, 7], [5, 6], [6, 7]];
const PRISM_EDGES: [[usize; 2]; 9] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 4], [2, 5], [3, 4], [3, 5], [4, 5]];
const PYRAMID_EDGES: [[usize; 2]; 8] = [[0, 1], [0, 3], [0, 4], [1, 2], [1, 4], [2, 3], [2, 4], [3, 4]];

/// The faces' corners, outward for a positively oriented cell.
const TET_FACES: [&[usize]; 4] = [&[0, 2, 1], &[0, 1, 3], &[0, 3, 2], &[1, 2, 3]];
const HEX_FACES: [&[usize]; 6] =
    [&[0, 3, 2, 1], &[4, 5, 6, 7], &[0, 1, 5, 4], &[1, 2, 6, 5], &[2, 3, 7, 6], &[3, 0, 4, 7]];
const PRISM_FACES: [&[usize]; 5] = [&[0, 2, 1], &[3, 4, 5], &[0, 1, 4, 3], &[1, 2, 5, 4], &[2, 0, 3, 5]];
const PYRAMID_FACES: [&[usize]; 5] = [&[0, 3, 2, 1], &[0, 1, 4], &[1, 2, 4], &[2, 3, 4], &[3, 0, 4]];

/// The centre nodes of the quadrilateral faces, by the faces' sorted corners.
const HEX27_CENTRES: [(usize, [usize; 4]); 6] = [
    (20, [0, 1, 2, 3]),
    (21, [0, 1, 4, 5]),
    (22, [0, 3, 4, 7]),
    (23, [1, 2, 5, 6]),
    (24, [2, 3, 6, 7]),
    (25, [4, 5, 6, 7]),
];
const PRISM18_CENTRES: [(usize, [usize; 4]); 3] =
    [(15, [0, 1, 3, 4]), (16, [0, 2, 3, 5]), (17, [1, 2, 4, 5])];
const PYRAMID14_CENTRES: [(usize, [usize; 4]); 1] = [(13, [0, 1, 2, 3])];

/// VTK's node order of the second-order cells as positions in Gmsh's order;
/// the first-order cells are their prefixes (VTK numbers corners as Gmsh does).
const TET10_VTK: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];
const HEX27_VTK: [usize; 27] =
    [0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15, 22, 23, 21, 24, 20, 25, 26];
const PRISM18_VTK: [usize; 18] = [0, 1, 2, 3, 4, 5, 6, 9, 7, 12, 14, 13, 8, 10, 11, 15, 17, 16];
const PYRAMID13_VTK: [usize; 13] = [0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12];

/// The first `n` entries of `a`.
const fn first<T>(a: &[T], n: usize) -> &[T] {
    a.split_at(n).0
}

/// The local faces of a cell: the corner lists `corners` and, at second order
/// (`second_order`), the mid-edge nodes (edge k of `edges` carries node
/// `n_corners + k`) and the face centres `centres`.
const fn local_faces<const F: usize>(
    corners: [&[usize]; F],
    n_corners: usize,
    edges: &[[usize; 2]],
    second_order: bool,
    centres: &[(usize, [usize; 4])],
) -> [LocalFace; F] {
    let mut faces = [LocalFace { kind: FaceKind::Tri3, nodes: [0; MAX_FACE_NODES] }; F];
    let mut f = 0;
    while f < F {
        let c = corners[f];
        let k = c.len();
        let mut nodes = [0; MAX_FACE_NODES];
        let mut i = 0;
        while i < k {
            nodes[i] = c[i];
            i += 1;
        }
        let mut kind = if k == 3 { FaceKind::Tri3 } else { FaceKind::Quad4 };
        if second_order {
            let mut i = 0;
            while i < k {
                let (a, b) = (c[i], c[(i + 1) % k]);
                let key = if a < b { [a, b] } else { [b, a] };
                let mut e = 0;
                while edges[e][0] != key[0] || edges[e][1] != key[1] {
                    e += 1;
                }
                nodes[k + i] = n_corners + e;
                i += 1;
            }
            kind = if k == 3 { FaceKind::Tri6 } else { FaceKind::Quad8 };
            let mut j = 0;
            while j < centres.len() {
                if k == 4 && same_set(c, &centres[j].1) {
                    nodes[2 * k] = centres[j].0;
                    kind = FaceKind::Quad9;
                }
                j += 1;
            }
        }
        faces[f] = LocalFace { kind, nodes };
        f += 1;
    }
    faces
}

/// Whether the four corners `c` are the set `sorted`.
const fn same_set(c: &[usize], sorted: &[usize; 4]) -> bool {
    let mut i = 0;
    while i < 4 {
        let mut found = false;
        let mut j = 0;
        while j < 4 {
            found |= c[i] == sorted[j];
            j += 1;
        }
        if !found {
            return false;
        }
        i += 1;
    }
    true
}

/// The faces made Tri7 with centre nodes `first`, `first` + 1, … in face order.
const fn with_triangle_centres<const F: usize>(mut faces: [LocalFace; F], first: usize) -> [LocalFace; F] {
    let mut f = 0;
    while f < F {
        faces[f].kind = FaceKind::Tri7;
        faces[f].nodes[6] = first + f;
        f += 1;
    }
    faces
}

pub(super) const TET4: CellType = CellType {
    name: "Tet4",
    shape: Shape::Tetrahedron,
    linear: CellKind::Tet4,
    nodes: first(&TET14_NODES, 4),
    corners: 4,
    edges: &TET_EDGES,
    faces: &local_faces(TET_FACES, 4, &TET_EDGES, false, &[]),
    gmsh_type: Some(4),
    vtk_type: 10,
    vtk_order: first(&TET10_VTK, 4),
    enriched: None,
    basis: CellBasis::Closed { shape: tet4_shape, gradients: tet4_gradients },
    stiffness: StiffnessRule::Degree(1),
};

pub(super) const HEX8: CellType = CellType {
    name: "Hex8",
    shape: Shape::Hexahedron,
    linear: CellKind::Hex8,
    nodes: first(&HEX27_NODES, 8),
    corners: 8,
    edges: &HEX_EDGES,
    faces: &local_faces(HEX_FACES, 8, &HEX_EDGES, false, &[]),
    gmsh_type: Some(5),
    vtk_type: 12,
    vtk_order: first(&HEX27_VTK, 8),
    enriched: None,
    basis: CellBasis::Closed { shape: hex8_shape, gradients: hex8_gradients },
    stiffness: StiffnessRule::Degree(3),
};

pub(super) const PRISM6: CellType = CellType {
    name: "Prism6",
    shape: Shape::Prism,
    linear: CellKind::Prism6,
    nodes: first(&PRISM18_NODES, 6),
    corners: 6,
    edges: &PRISM_EDGES,
    faces: &local_faces(PRISM_FACES, 6, &PRISM_EDGES, false, &[]),
    gmsh_type: Some(6),
    vtk_type: 13,
    vtk_order: first(&PRISM18_VTK, 6),
    enriched: None,
    basis: CellBasis::Closed { shape: prism6_shape, gradients: prism6_gradients },
    stiffness: StiffnessRule::Degree(2),
};

pub(super) const PYRAMID5: CellType = CellType {
    name: "Pyramid5",
    shape: Shape::Pyramid,
    linear: CellKind::Pyramid5,
    nodes: first(&PYRAMID14_NODES, 5),
    corners: 5,
    edges: &PYRAMID_EDGES,
    faces: &local_faces(PYRAMID_FACES, 5, &PYRAMID_EDGES, false, &[]),
    gmsh_type: Some(7),
    vtk_type: 14,
    vtk_order: first(&PYRAMID13_VTK, 5),
    enriched: None,
    basis: CellBasis::Closed { shape: pyramid5_shape, gradients: pyramid5_gradients },
    stiffness: StiffnessRule::Collapsed(2),
};

/// P₂: total degree ≤ 2.
const P2: fn([u8; 3]) -> bool = |[a, b, c]| a + b + c <= 2;

pub(super) const TET10: CellType = CellType {
    name: "Tet10",
    shape: Shape::Tetrahedron,
    linear: CellKind::Tet4,
    nodes: first(&TET14_NODES, 10),
    corners: 4,
    edges: &TET_EDGES,
    faces: &local_faces(TET_FACES, 4, &TET_EDGES, true, &[]),
    gmsh_type: Some(11),
    vtk_type: 24,
    vtk_order: &TET10_VTK,
    enriched: Some(CellKind::Tet14),
    basis: CellBasis::Nodal(Space { keep: P2, rational: &[] }),
    stiffness: StiffnessRule::Degree(2),
};

/// Tet10 enriched by the cubic bubbles of its four faces: the volume cell of
/// an enriched slave space ([`crate::SurfaceMesh::enriched`]), whose faces
/// are Tri7. Neither Gmsh nor VTK has it: VTK is given the Tet10.
pub(super) const TET14: CellType = CellType {
    name: "Tet14",
    shape: Shape::Tetrahedron,
    linear: CellKind::Tet4,
    nodes: &TET14_NODES,
    corners: 4,
    edges: &TET_EDGES,
    faces: &with_triangle_centres(local_faces(TET_FACES, 4, &TET_EDGES, true, &[]), 10),
    gmsh_type: None,
    vtk_type: 24,
    vtk_order: &TET10_VTK,
    enriched: None,
    basis: CellBasis::Closed { shape: tet14_shape, gradients: tet14_gradients },
    // ∇N is quadratic: the stiffness of an affine cell has degree 4.
    stiffness: StiffnessRule::Degree(4),
};

pub(super) const HEX20: CellType = CellType {
    name: "Hex20",
    shape: Shape::Hexahedron,
    linear: CellKind::Hex8,
    nodes: first(&HEX27_NODES, 20),
    corners: 8,
    edges: &HEX_EDGES,
    faces: &local_faces(HEX_FACES, 8, &HEX_EDGES, true, &[]),
    gmsh_type: Some(17),
    vtk_type: 25,
    vtk_order: first(&HEX27_VTK, 20),
    // Serendipity: at most one squared variable.
    enriched: Some(CellKind::Hex27),
    basis: CellBasis::Nodal(Space { keep: |e| e.iter().filter(|&&e| e == 2).count() <= 1, rational: &[] }),
    stiffness: StiffnessRule::Degree(4),
};

pub(super) const HEX27: CellType = CellType {
    name: "Hex27",
    shape: Shape::Hexahedron,
    linear: CellKind::Hex8,
    nodes: &HEX27_NODES,
    corners: 8,
    edges: &HEX_EDGES,
    faces: &local_faces(HEX_FACES, 8, &HEX_EDGES, true, &HEX27_CENTRES),
    gmsh_type: Some(12),
    vtk_type: 29,
    vtk_order: &HEX27_VTK,
    enriched: None,
    basis: CellBasis::Nodal(Space { keep: |_| true, rational: &[] }),
    stiffness: StiffnessRule::Degree(4),
};

pub(super) const PRISM15: CellType = CellType {
    name: "Prism15",
    shape: Shape::Prism,
    linear: CellKind::Prism6,
    nodes: first(&PRISM18_NODES, 15),
    corners: 6,
    edges: &PRISM_EDGES,
    faces: &local_faces(PRISM_FACES, 6, &PRISM_EDGES, true, &[]),
    gmsh_type: Some(18),
    vtk_type: 26,
    vtk_order: first(&PRISM18_VTK, 15),
    enriched: None,
    basis: CellBasis::Nodal(Space {
        keep: |[a, b, c]| (a + b <= 2 && c <= 1) || (a + b <= 1 && c == 2),
        rational: &[],
    }),
    stiffness: StiffnessRule::Degree(4),
};

pub(super) const PRISM18: CellType = CellType {
    name: "Prism18",
    shape: Shape::Prism,
    linear: CellKind::Prism6,
    nodes: &PRISM18_NODES,
    corners: 6,
    edges: &PRISM_EDGES,
    faces: &local_faces(PRISM_FACES, 6, &PRISM_EDGES, true, &PRISM18_CENTRES),
    gmsh_type: Some(13),
    vtk_type: 32,
    vtk_order: &PRISM18_VTK,
    enriched: None,
    basis: CellBasis::Nodal(Space { keep: |[a, b, _]| a + b <= 2, rational: &[] }),
    stiffness: StiffnessRule::Degree(4),
};

/// The rational terms of the pyramids: ξη/s, ξ²η/s, ξη²/s (and ξ²η²/s²).
const PYRAMID_RATIONAL: [Term; 4] = [[1, 1, 0, 1], [2, 1, 0, 1], [1, 2, 0, 1], [2, 2, 0, 2]];

pub(super) const PYRAMID13: CellType = CellType {
    name: "Pyramid13",
    shape: Shape::Pyramid,
    linear: CellKind::Pyramid5,
    nodes: first(&PYRAMID14_NODES, 13),
    corners: 5,
    edges: &PYRAMID_EDGES,
    faces: &local_faces(PYRAMID_FACES, 5, &PYRAMID_EDGES, true, &[]),
    gmsh_type: Some(19),
    vtk_type: 27,
    vtk_order: &PYRAMID13_VTK,
    enriched: None,
    basis: CellBasis::Nodal(Space { keep: P2, rational: first(&PYRAMID_RATIONAL, 3) }),
    stiffness: StiffnessRule::Collapsed(3),
};

pub(super) const PYRAMID14: CellType = CellType {
    name: "Pyramid14",
    shape: Shape::Pyramid,
    linear: CellKind::Pyramid5,
    nodes: &PYRAMID14_NODES,
    corners: 5,
    edges: &PYRAMID_EDGES,
    faces: &local_faces(PYRAMID_FACES, 5, &PYRAMID_EDGES, true, &PYRAMID14_CENTRES),
    gmsh_type: Some(14),
    // VTK has no 14-node pyramid: the base centre stays a point of the grid.
    vtk_type: 27,
    vtk_order: &PYRAMID13_VTK,
    enriched: None,
    basis: CellBasis::Nodal(Space { keep: P2, rational: &PYRAMID_RATIONAL }),
    stiffness: StiffnessRule::Collapsed(3),
};

/// 1 − ζ below which a point counts as the pyramid apex.
const APEX_TOL: f64 = 1e-14;

fn tet4_shape([x, y, z]: Xi3) -> [f64; MAX_CELL_NODES] {
    let mut n = [0.0; MAX_CELL_NODES];
    n[..4].copy_from_slice(&[1.0 - x - y - z, x, y, z]);
    n
}

fn tet4_gradients(_: Xi3) -> [[f64; 3]; MAX_CELL_NODES] {
    let mut g = [[0.0; 3]; MAX_CELL_NODES];
    g[0] = [-1.0, -1.0, -1.0];
    g[1] = [1.0, 0.0, 0.0];
    g[2] = [0.0, 1.0, 0.0];
    g[3] = [0.0, 0.0, 1.0];
    g
}

fn hex8_shape([x, y, z]: Xi3) -> [f64; MAX_CELL_NODES] {
    let mut n = [0.0; MAX_CELL_NODES];
    for (i, p) in HEX27_NODES[..8].iter().enumerate() {
        n[i] = 0.125 * (1.0 + p[0] * x) * (1.0 + p[1] * y) * (1.0 + p[2] * z);
    }
    n
}

fn hex8_gradients([x, y, z]: Xi3) -> [[f64; 3]; MAX_CELL_NODES] {
    let mut g = [[0.0; 3]; MAX_CELL_NODES];
    for (i, p) in HEX27_NODES[..8].iter().enumerate() {
        let (a, b, c) = (1.0 + p[0] * x, 1.0 + p[1] * y, 1.0 + p[2] * z);
        g[i] = [0.125 * p[0] * b * c, 0.125 * a * p[1] * c, 0.125 * a * b * p[2]];
    }
    g
}

fn prism6_shape([x, y, z]: Xi3) -> [f64; MAX_CELL_NODES] {
    let mut n = [0.0; MAX_CELL_NODES];
    let l = [1.0 - x - y, x, y];
    for i in 0..3 {
        n[i] = l[i] * 0.5 * (1.0 - z);
        n[i + 3] = l[i] * 0.5 * (1.0 + z);
    }
    n
}

fn prism6_gradients([x, y, z]: Xi3) -> [[f64; 3]; MAX_CELL_NODES] {
    let mut g = [[0.0; 3]; MAX_CELL_NODES];
    let l = [1.0 - x - y, x, y];
    let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    for i in 0..3 {
        let (lo, hi) = (0.5 * (1.0 - z), 0.5 * (1.0 + z));
        g[i] = [dl[i][0] * lo, dl[i][1] * lo, -0.5 * l[i]];
        g[i + 3] = [dl[i][0] * hi, dl[i][1] * hi, 0.5 * l[i]];
    }
    g
}

fn pyramid5_shape([x, y, z]: Xi3) -> [f64; MAX_CELL_NODES] {
    let mut n = [0.0; MAX_CELL_NODES];
    let s = 1.0 - z;
    let q = if s > APEX_TOL { x * y / s } else { 0.0 };
    for (i, p) in PYRAMID14_NODES[..4].iter().enumerate() {
        n[i] = 0.25 * (s + p[0] * x + p[1] * y + p[0] * p[1] * q);
    }
    n[4] = z;
    n
}

fn pyramid5_gradients([x, y, z]: Xi3) -> [[f64; 3]; MAX_CELL_NODES] {
    let mut g = [[0.0; 3]; MAX_CELL_NODES];
    let s = 1.0 - z;
    let (a, b) = if s > APEX_TOL { (x / s, y / s) } else { (0.0, 0.0) };
    for (i, p) in PYRAMID14_NODES[..4].iter().enumerate() {
        let pq = p[0] * p[1];
        g[i] = [0.25 * (p[0] + pq * b), 0.25 * (p[1] + pq * a), 0.25 * (-1.0 + pq * a * b)];
    }
    g[4] = [0.0, 0.0, 1.0];
    g
}

/// Tet14's functions and gradients: with barycentrics L = (1−ξ−η−ζ, ξ, η,
/// ζ), the Tet10 functions (L_i(2L_i − 1) at corners, 4 L_a L_b at mid-edge
/// nodes) minus their values at each face centroid (−1/9 at the face's
/// corners, 4/9 at its mid-edge nodes) times that face's bubble
/// B_f = 27 L_a L_b L_c, and the four B_f, which vanish on the other faces.
fn tet14(xi: Xi3) -> ([f64; MAX_CELL_NODES], [[f64; 3]; MAX_CELL_NODES]) {
    let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
    let dl = [[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let (mut n, mut g) = ([0.0; MAX_CELL_NODES], [[0.0; 3]; MAX_CELL_NODES]);
    for i in 0..4 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        g[i] = dl[i].map(|d| d * (4.0 * l[i] - 1.0));
    }
    for (e, &[a, b]) in TET_EDGES.iter().enumerate() {
        n[4 + e] = 4.0 * l[a] * l[b];
        g[4 + e] = std::array::from_fn(|k| 4.0 * (dl[a][k] * l[b] + l[a] * dl[b][k]));
    }
    for (f, c) in TET_FACES.iter().enumerate() {
        let (a, b, d) = (c[0], c[1], c[2]);
        let bubble = 27.0 * l[a] * l[b] * l[d];
        let grad: [f64; 3] = std::array::from_fn(|k| {
            27.0 * (dl[a][k] * l[b] * l[d] + l[a] * dl[b][k] * l[d] + l[a] * l[b] * dl[d][k])
        });
        let on_face = |i: usize| c.contains(&i);
        for i in 0..10 {
            let w = match i {
                i if i < 4 && on_face(i) => -1.0 / 9.0,
                i if i >= 4 && on_face(TET_EDGES[i - 4][0]) && on_face(TET_EDGES[i - 4][1]) => 4.0 / 9.0,
                _ => continue,
            };
            n[i] -= w * bubble;
            g[i] = std::array::from_fn(|k| g[i][k] - w * grad[k]);
        }
        n[10 + f] = bubble;
        g[10 + f] = grad;
    }
    (n, g)
}

fn tet14_shape(xi: Xi3) -> [f64; MAX_CELL_NODES] {
    tet14(xi).0
}

fn tet14_gradients(xi: Xi3) -> [[f64; 3]; MAX_CELL_NODES] {
    tet14(xi).1
}

/// The Lagrange basis of a second-order kind: its terms and C = V⁻¹ (module doc),
/// N_i = Σ_k coef\[k\]\[i\] φ_k.
struct NodalBasis {
    terms: Vec<Term>,
    coef: Box<[[f64; MAX_CELL_NODES]; MAX_CELL_NODES]>,
}

/// The terms φ_k(ξ) and their gradients (module doc); at the pyramid apex the
/// rational terms are 0 with gradient 0.
fn eval_terms(terms: &[Term], xi: Xi3) -> ([f64; MAX_CELL_NODES], [[f64; 3]; MAX_CELL_NODES]) {
    // p[k][e] = ξ_k^e, dp[k][e] = e ξ_k^(e−1).
    let p = xi.map(|x| [1.0, x, x * x]);
    let dp = xi.map(|x| [0.0, 1.0, 2.0 * x]);
    let s = 1.0 - xi[2];
    let (mut v, mut g) = ([0.0; MAX_CELL_NODES], [[0.0; 3]; MAX_CELL_NODES]);
    for (k, &[a, b, c, d]) in terms.iter().enumerate() {
        let (a, b, c) = (a as usize, b as usize, c as usize);
        if d > 0 && s <= APEX_TOL {
            continue;
        }
        let r = s.powi(-(d as i32));
        let (x, y, z) = (p[0][a], p[1][b], p[2][c]);
        v[k] = x * y * z * r;
        g[k] = [dp[0][a] * y * z * r, x * dp[1][b] * z * r, x * y * (dp[2][c] * r + z * d as f64 * r / s)];
    }
    (v, g)
}

/// C = V⁻¹ for the nodes and terms of `kind` by Gauss–Jordan elimination with
/// partial pivoting.
fn nodal_basis(kind: CellKind, space: &Space) -> NodalBasis {
    let terms = space.terms();
    let nodes = kind.reference_nodes();
    let n = nodes.len();
    assert_eq!(terms.len(), n, "{kind:?}: the space has one term per node");
    // Augmented [V | I], V_jk = φ_k(node_j).
    let mut m = vec![vec![0.0; 2 * n]; n];
    for (j, &x) in nodes.iter().enumerate() {
        m[j][..n].copy_from_slice(&eval_terms(&terms, x).0[..n]);
        m[j][n + j] = 1.0;
    }
    for col in 0..n {
        let piv = (col..n).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs())).unwrap_or(col);
        assert!(m[piv][col].abs() > 1e-10, "{kind:?}: the nodes are unisolvent for the space");
        m.swap(col, piv);
        let d = m[col][col];
        m[col].iter_mut().for_each(|v| *v /= d);
        let pivot_row = m[col].clone();
        for (r, row) in m.iter_mut().enumerate() {
            if r != col && row[col] != 0.0 {
                let f = row[col];
                row.iter_mut().zip(&pivot_row).for_each(|(v, p)| *v -= f * p);
            }
        }
    }
    let mut coef = Box::new([[0.0; MAX_CELL_NODES]; MAX_CELL_NODES]);
    for (k, row) in m.iter().enumerate() {
        coef[k][..n].copy_from_slice(&row[n..]);
    }
    NodalBasis { terms, coef }
}

/// The nodal bases of the kinds with [`CellBasis::Nodal`], by `kind as usize`.
static NODAL_BASES: LazyLock<[Option<NodalBasis>; CellKind::ALL.len()]> = LazyLock::new(|| {
    CellKind::ALL.map(|kind| match kind.info().basis {
        CellBasis::Nodal(space) => Some(nodal_basis(kind, &space)),
        CellBasis::Closed { .. } => None,
    })
});

/// N_i(ξ) and ∇_ξ N_i(ξ) of a kind with a nodal basis.
///
/// # Panics
/// If `kind` has closed-form shape functions.
pub(super) fn nodal_shape(kind: CellKind, xi: Xi3) -> ([f64; MAX_CELL_NODES], [[f64; 3]; MAX_CELL_NODES]) {
    let basis = NODAL_BASES[kind as usize].as_ref().expect("a kind with a nodal basis");
    let n = basis.terms.len();
    let (v, g) = eval_terms(&basis.terms, xi);
    let (mut sh, mut gr) = ([0.0; MAX_CELL_NODES], [[0.0; 3]; MAX_CELL_NODES]);
    for k in 0..n {
        let row = &basis.coef[k];
        for i in 0..n {
            sh[i] += row[i] * v[k];
            for l in 0..3 {
                gr[i][l] += row[i] * g[k][l];
            }
        }
    }
    (sh, gr)
}
