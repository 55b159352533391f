//! Reference volume elements in Gmsh node order: shape functions N_i(ξ), their
//! gradients ∇_ξ N_i, and quadrature rules on the reference cell.
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
//! # Quadrature
//!
//! [`ElementKind::stiffness_rule`] is the rule used for the stiffness: exact for
//! the stiffness of affine cells, and for ∫_e ∇N_i dV and the volume of any
//! (trilinear, prismatic, collapsed) cell, which is what the patch test needs:
//!
//! | element | points | why it is enough |
//! |---|---:|---|
//! | Tet4 | 1 (centroid) | ∇N constant |
//! | Hex8 | 2×2×2 Gauss | cof(J)ᵀ∇_ξN and det J are of degree ≤ 3 in each variable |
//! | Prism6 | 3-point triangle (degree 2) × 2 Gauss | degree ≤ 2 in (ξ, η), ≤ 3 in ζ |
//! | Pyramid5 | 2×2×2 collapsed Gauss | in (a, b, ζ) the cell is a degenerate trilinear hex |
//!
//! The pyramid rule is the 2×2×2 Gauss rule of the cube (a, b, ζ) ∈ \[−1,1\]²×\[0,1\]
//! mapped by ξ = a(1−ζ), η = b(1−ζ), the Duffy factor (1−ζ)² folded into the
//! weights. For an affine pyramid the stiffness integrand ∇N_i·C∇N_j(1−ζ)² has
//! degree ≤ 2 in each of a, b, ζ, so 2 points per direction are exact; 3×3×3
//! would cost 27/8 as much for no gain on affine cells, and the rule is of full
//! rank (the element stiffness has exactly the 6 rigid-body zero modes).
//!
//! [`ElementKind::rule`] gives rules of any degree (loads, error norms).
//!
//! # Second-order elements
//!
//! Tet10, Hex20, Hex27, Prism15, Prism18, Pyramid13 and Pyramid14 live on the
//! reference cells of their first-order families with Gmsh's nodes (corners,
//! mid-edge nodes in Gmsh's edge order, quadrilateral face centres, the Hex27
//! centre). Their shape functions are the nodal (Lagrange) basis of a space V
//! spanned by terms φ_k = ξ^a η^b ζ^c / (1−ζ)^d: N_i = Σ_k C_ki φ_k with
//! C = V⁻¹, V_jk = φ_k(node_j), so that N_i(node_j) = δ_ij by construction (C is
//! computed once, by Gaussian elimination with partial pivoting).
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
//!
//! Stiffness rules of the second-order kinds (exact for affine cells):
//!
//! | element | rule | integrand degree (affine) |
//! |---|---|---|
//! | Tet10 | 4-point, degree 2 | ∇N_i·∇N_j of degree 2 |
//! | Hex20, Hex27 | 3×3×3 Gauss | ≤ 4 in each variable |
//! | Prism15, Prism18 | degree-4 triangle rule × 3 Gauss | ≤ 4 in (ξ, η), ≤ 4 in ζ |
//! | Pyramid13, Pyramid14 | 3×3×3 collapsed Gauss | ≤ 4 in each of a, b, ζ with (1−ζ)² |
//!
//! On isoparametric (curved) hexes and prisms cof(J)ᵀ∇_ξN_i is of degree ≤ 5
//! in each hex variable (prisms: ≤ 4 in (ξ, η), ≤ 5 in ζ), so these rules also
//! give ∫_e ∇N_i dV exactly there: curved Hex20/27 and Prism15/18 meshes pass
//! the patch test. Tet10 and the pyramids are exact on straight-sided cells.

use seam::triangle_rule;
use std::sync::LazyLock;

/// The largest number of nodes of an element (Hex27).
pub const MAX_NODES: usize = 27;

/// Reference coordinates (ξ, η, ζ).
pub type Xi = [f64; 3];

/// The volume element types: four first-order, seven second-order ones.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ElementKind {
    /// Four-node linear tetrahedron.
    Tet4,
    /// Eight-node trilinear hexahedron.
    Hex8,
    /// Six-node prism (linear triangle × linear segment).
    Prism6,
    /// Five-node pyramid (rational, collapsed hex).
    Pyramid5,
    /// Ten-node quadratic tetrahedron (P₂).
    Tet10,
    /// Twenty-node serendipity hexahedron (S₂).
    Hex20,
    /// Twenty-seven-node triquadratic hexahedron (Q₂).
    Hex27,
    /// Fifteen-node serendipity prism.
    Prism15,
    /// Eighteen-node prism (P₂ triangle × quadratic segment).
    Prism18,
    /// Thirteen-node rational serendipity pyramid.
    Pyramid13,
    /// Fourteen-node rational pyramid (Bergot–Cohen–Duruflé B₂).
    Pyramid14,
}

/// A quadrature rule on a reference cell: ∫ f dξ ≈ Σ_q w_q f(ξ_q).
///
/// Weights sum to the volume of the reference cell ([`ElementKind::reference_volume`]).
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeRule {
    /// Points ξ_q in reference coordinates, all inside the cell.
    pub points: Vec<Xi>,
    /// Weights w_q, all positive.
    pub weights: Vec<f64>,
}

impl VolumeRule {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True for a rule without points (never returned by this module).
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// (ξ_q, w_q) pairs.
    pub fn iter(&self) -> impl Iterator<Item = (Xi, f64)> + '_ {
        self.points.iter().copied().zip(self.weights.iter().copied())
    }
}

const TET4_NODES: [Xi; 4] = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
const PRISM6_NODES: [Xi; 6] =
    [[0., 0., -1.], [1., 0., -1.], [0., 1., -1.], [0., 0., 1.], [1., 0., 1.], [0., 1., 1.]];
const PYRAMID5_NODES: [Xi; 5] = [[-1., -1., 0.], [1., -1., 0.], [1., 1., 0.], [-1., 1., 0.], [0., 0., 1.]];

const TET10_NODES: [Xi; 10] = [
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
];
/// Hex27 in Gmsh order; Hex20 is its first 20 nodes.
const HEX27_NODES: [Xi; 27] = [
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
/// Prism18 in Gmsh order; Prism15 is its first 15 nodes.
const PRISM18_NODES: [Xi; 18] = [
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
/// Pyramid14 in Gmsh order; Pyramid13 is its first 13 nodes.
const PYRAMID14_NODES: [Xi; 14] = [
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

/// 1 − ζ below which a point counts as the pyramid apex.
const APEX_TOL: f64 = 1e-14;

/// Number of element kinds.
const N_KINDS: usize = 11;

static STIFFNESS_RULES: LazyLock<[VolumeRule; N_KINDS]> = LazyLock::new(|| {
    ElementKind::ALL.map(|kind| match kind {
        ElementKind::Tet4 => kind.rule(1),
        ElementKind::Hex8 => kind.rule(3),
        ElementKind::Prism6 | ElementKind::Tet10 => kind.rule(2),
        ElementKind::Pyramid5 => pyramid_rule(2, 2),
        ElementKind::Hex20 | ElementKind::Hex27 | ElementKind::Prism15 | ElementKind::Prism18 => kind.rule(4),
        ElementKind::Pyramid13 | ElementKind::Pyramid14 => pyramid_rule(3, 3),
    })
});

/// A term φ = ξ^a η^b ζ^c / (1−ζ)^d of a second-order space, as \[a, b, c, d\].
type Term = [u8; 4];

/// The Lagrange basis of a second-order kind: its terms and C = V⁻¹ (module doc),
/// N_i = Σ_k coef\[k\]\[i\] φ_k.
struct NodalBasis {
    terms: Vec<Term>,
    coef: Box<[[f64; MAX_NODES]; MAX_NODES]>,
}

/// The terms of the space of a second-order kind (module doc table).
fn terms(kind: ElementKind) -> Vec<Term> {
    let mut t = Vec::new();
    for c in 0..=2u8 {
        for b in 0..=2u8 {
            for a in 0..=2u8 {
                let squared = [a, b, c].iter().filter(|&&e| e == 2).count();
                let keep = match kind {
                    ElementKind::Tet10 | ElementKind::Pyramid13 | ElementKind::Pyramid14 => a + b + c <= 2,
                    ElementKind::Hex27 => true,
                    ElementKind::Hex20 => squared <= 1,
                    ElementKind::Prism18 => a + b <= 2,
                    ElementKind::Prism15 => (a + b <= 2 && c <= 1) || (a + b <= 1 && c == 2),
                    _ => false,
                };
                if keep {
                    t.push([a, b, c, 0]);
                }
            }
        }
    }
    if matches!(kind, ElementKind::Pyramid13 | ElementKind::Pyramid14) {
        t.extend([[1, 1, 0, 1], [2, 1, 0, 1], [1, 2, 0, 1]]);
    }
    if kind == ElementKind::Pyramid14 {
        t.push([2, 2, 0, 2]);
    }
    t
}

/// The terms φ_k(ξ) and their gradients (module doc); at the pyramid apex the
/// rational terms are 0 with gradient 0.
fn eval_terms(terms: &[Term], xi: Xi) -> ([f64; MAX_NODES], [[f64; 3]; MAX_NODES]) {
    // p[k][e] = ξ_k^e, dp[k][e] = e ξ_k^(e−1).
    let p = xi.map(|x| [1.0, x, x * x]);
    let dp = xi.map(|x| [0.0, 1.0, 2.0 * x]);
    let s = 1.0 - xi[2];
    let (mut v, mut g) = ([0.0; MAX_NODES], [[0.0; 3]; MAX_NODES]);
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

/// C = V⁻¹ for the nodes `nodes` and `terms` by Gauss–Jordan elimination with
/// partial pivoting.
fn nodal_basis(kind: ElementKind) -> NodalBasis {
    let terms = terms(kind);
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
    let mut coef = Box::new([[0.0; MAX_NODES]; MAX_NODES]);
    for (k, row) in m.iter().enumerate() {
        coef[k][..n].copy_from_slice(&row[n..]);
    }
    NodalBasis { terms, coef }
}

static SECOND_ORDER_BASES: LazyLock<Vec<NodalBasis>> =
    LazyLock::new(|| ElementKind::SECOND_ORDER.iter().map(|&k| nodal_basis(k)).collect());

/// N_i(ξ) and ∇_ξ N_i(ξ) of a second-order kind.
fn second_order_shape(kind: ElementKind, xi: Xi) -> ([f64; MAX_NODES], [[f64; 3]; MAX_NODES]) {
    let basis = &SECOND_ORDER_BASES[kind as usize - ElementKind::FIRST_ORDER.len()];
    let n = basis.terms.len();
    let (v, g) = eval_terms(&basis.terms, xi);
    let (mut sh, mut gr) = ([0.0; MAX_NODES], [[0.0; 3]; MAX_NODES]);
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

impl ElementKind {
    /// All kinds, in declaration order (`kind as usize` indexes it).
    pub const ALL: [ElementKind; N_KINDS] = [
        ElementKind::Tet4,
        ElementKind::Hex8,
        ElementKind::Prism6,
        ElementKind::Pyramid5,
        ElementKind::Tet10,
        ElementKind::Hex20,
        ElementKind::Hex27,
        ElementKind::Prism15,
        ElementKind::Prism18,
        ElementKind::Pyramid13,
        ElementKind::Pyramid14,
    ];

    /// The four first-order kinds (the reference cell families).
    pub const FIRST_ORDER: [ElementKind; 4] =
        [ElementKind::Tet4, ElementKind::Hex8, ElementKind::Prism6, ElementKind::Pyramid5];

    /// The seven second-order kinds.
    pub const SECOND_ORDER: [ElementKind; 7] = [
        ElementKind::Tet10,
        ElementKind::Hex20,
        ElementKind::Hex27,
        ElementKind::Prism15,
        ElementKind::Prism18,
        ElementKind::Pyramid13,
        ElementKind::Pyramid14,
    ];

    /// The element type of a mesh cell.
    pub fn of(cell: &seam::Cell) -> ElementKind {
        match cell {
            seam::Cell::Tet4(_) => ElementKind::Tet4,
            seam::Cell::Hex8(_) => ElementKind::Hex8,
            seam::Cell::Prism6(_) => ElementKind::Prism6,
            seam::Cell::Pyramid5(_) => ElementKind::Pyramid5,
            seam::Cell::Tet10(_) => ElementKind::Tet10,
            seam::Cell::Hex20(_) => ElementKind::Hex20,
            seam::Cell::Hex27(_) => ElementKind::Hex27,
            seam::Cell::Prism15(_) => ElementKind::Prism15,
            seam::Cell::Prism18(_) => ElementKind::Prism18,
            seam::Cell::Pyramid13(_) => ElementKind::Pyramid13,
            seam::Cell::Pyramid14(_) => ElementKind::Pyramid14,
        }
    }

    /// The mesh cell of this kind with the point indices `nodes` (Gmsh order);
    /// `None` unless `nodes.len() == self.n_nodes()`.
    pub fn cell(self, nodes: &[usize]) -> Option<seam::Cell> {
        use seam::Cell as C;
        Some(match self {
            ElementKind::Tet4 => C::Tet4(nodes.try_into().ok()?),
            ElementKind::Hex8 => C::Hex8(nodes.try_into().ok()?),
            ElementKind::Prism6 => C::Prism6(nodes.try_into().ok()?),
            ElementKind::Pyramid5 => C::Pyramid5(nodes.try_into().ok()?),
            ElementKind::Tet10 => C::Tet10(nodes.try_into().ok()?),
            ElementKind::Hex20 => C::Hex20(nodes.try_into().ok()?),
            ElementKind::Hex27 => C::Hex27(nodes.try_into().ok()?),
            ElementKind::Prism15 => C::Prism15(nodes.try_into().ok()?),
            ElementKind::Prism18 => C::Prism18(nodes.try_into().ok()?),
            ElementKind::Pyramid13 => C::Pyramid13(nodes.try_into().ok()?),
            ElementKind::Pyramid14 => C::Pyramid14(nodes.try_into().ok()?),
        })
    }

    /// The first-order kind with the same reference cell and corners.
    pub fn family(self) -> ElementKind {
        match self {
            ElementKind::Tet4 | ElementKind::Tet10 => ElementKind::Tet4,
            ElementKind::Hex8 | ElementKind::Hex20 | ElementKind::Hex27 => ElementKind::Hex8,
            ElementKind::Prism6 | ElementKind::Prism15 | ElementKind::Prism18 => ElementKind::Prism6,
            ElementKind::Pyramid5 | ElementKind::Pyramid13 | ElementKind::Pyramid14 => ElementKind::Pyramid5,
        }
    }

    /// The polynomial order: 1 or 2.
    pub fn order(self) -> usize {
        if self.family() == self {
            1
        } else {
            2
        }
    }

    /// Number of nodes.
    pub fn n_nodes(self) -> usize {
        self.reference_nodes().len()
    }

    /// The reference coordinates of the nodes, in Gmsh order.
    pub fn reference_nodes(self) -> &'static [Xi] {
        match self {
            ElementKind::Tet4 => &TET4_NODES,
            ElementKind::Hex8 => &HEX27_NODES[..8],
            ElementKind::Prism6 => &PRISM6_NODES,
            ElementKind::Pyramid5 => &PYRAMID5_NODES,
            ElementKind::Tet10 => &TET10_NODES,
            ElementKind::Hex20 => &HEX27_NODES[..20],
            ElementKind::Hex27 => &HEX27_NODES,
            ElementKind::Prism15 => &PRISM18_NODES[..15],
            ElementKind::Prism18 => &PRISM18_NODES,
            ElementKind::Pyramid13 => &PYRAMID14_NODES[..13],
            ElementKind::Pyramid14 => &PYRAMID14_NODES,
        }
    }

    /// Volume of the reference cell: 1/6, 8, 1, 4/3 (tets, hexes, prisms, pyramids).
    pub fn reference_volume(self) -> f64 {
        match self.family() {
            ElementKind::Tet4 => 1.0 / 6.0,
            ElementKind::Hex8 => 8.0,
            ElementKind::Prism6 => 1.0,
            _ => 4.0 / 3.0,
        }
    }

    /// Centroid of the reference cell: (¼,¼,¼), 0, (⅓,⅓,0), (0,0,¼). For an
    /// affine cell it maps to the physical centroid.
    pub fn centroid(self) -> Xi {
        match self.family() {
            ElementKind::Tet4 => [0.25; 3],
            ElementKind::Hex8 => [0.0; 3],
            ElementKind::Prism6 => [1.0 / 3.0, 1.0 / 3.0, 0.0],
            _ => [0.0, 0.0, 0.25],
        }
    }

    /// Shape functions N_i(ξ); entries past [`ElementKind::n_nodes`] are 0.
    pub fn shape(self, xi: Xi) -> [f64; MAX_NODES] {
        let [x, y, z] = xi;
        let mut n = [0.0; MAX_NODES];
        match self {
            ElementKind::Tet4 => n[..4].copy_from_slice(&[1.0 - x - y - z, x, y, z]),
            ElementKind::Hex8 => {
                for (i, p) in HEX27_NODES[..8].iter().enumerate() {
                    n[i] = 0.125 * (1.0 + p[0] * x) * (1.0 + p[1] * y) * (1.0 + p[2] * z);
                }
            }
            ElementKind::Prism6 => {
                let l = [1.0 - x - y, x, y];
                for i in 0..3 {
                    n[i] = l[i] * 0.5 * (1.0 - z);
                    n[i + 3] = l[i] * 0.5 * (1.0 + z);
                }
            }
            ElementKind::Pyramid5 => {
                let s = 1.0 - z;
                let q = if s > APEX_TOL { x * y / s } else { 0.0 };
                for (i, p) in PYRAMID5_NODES[..4].iter().enumerate() {
                    n[i] = 0.25 * (s + p[0] * x + p[1] * y + p[0] * p[1] * q);
                }
                n[4] = z;
            }
            _ => n = second_order_shape(self, xi).0,
        }
        n
    }

    /// Gradients ∇_ξ N_i(ξ) = (∂N_i/∂ξ, ∂N_i/∂η, ∂N_i/∂ζ); entries past
    /// [`ElementKind::n_nodes`] are 0.
    pub fn gradients(self, xi: Xi) -> [[f64; 3]; MAX_NODES] {
        let [x, y, z] = xi;
        let mut g = [[0.0; 3]; MAX_NODES];
        match self {
            ElementKind::Tet4 => {
                g[0] = [-1.0, -1.0, -1.0];
                g[1] = [1.0, 0.0, 0.0];
                g[2] = [0.0, 1.0, 0.0];
                g[3] = [0.0, 0.0, 1.0];
            }
            ElementKind::Hex8 => {
                for (i, p) in HEX27_NODES[..8].iter().enumerate() {
                    let (a, b, c) = (1.0 + p[0] * x, 1.0 + p[1] * y, 1.0 + p[2] * z);
                    g[i] = [0.125 * p[0] * b * c, 0.125 * a * p[1] * c, 0.125 * a * b * p[2]];
                }
            }
            ElementKind::Prism6 => {
                let l = [1.0 - x - y, x, y];
                let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
                for i in 0..3 {
                    let (lo, hi) = (0.5 * (1.0 - z), 0.5 * (1.0 + z));
                    g[i] = [dl[i][0] * lo, dl[i][1] * lo, -0.5 * l[i]];
                    g[i + 3] = [dl[i][0] * hi, dl[i][1] * hi, 0.5 * l[i]];
                }
            }
            ElementKind::Pyramid5 => {
                let s = 1.0 - z;
                let (a, b) = if s > APEX_TOL { (x / s, y / s) } else { (0.0, 0.0) };
                for (i, p) in PYRAMID5_NODES[..4].iter().enumerate() {
                    let pq = p[0] * p[1];
                    g[i] = [0.25 * (p[0] + pq * b), 0.25 * (p[1] + pq * a), 0.25 * (-1.0 + pq * a * b)];
                }
                g[4] = [0.0, 0.0, 1.0];
            }
            _ => g = second_order_shape(self, xi).1,
        }
        g
    }

    /// The rule the stiffness is integrated with (see the module tables):
    /// 1, 8, 6 and 8 points for first-order kinds; 4 (Tet10), 27 (hexes),
    /// 18 (prisms) and 27 (pyramids) for second-order kinds.
    pub fn stiffness_rule(self) -> &'static VolumeRule {
        &STIFFNESS_RULES[self as usize]
    }

    /// A rule exact for polynomials of total degree ≤ `degree` on the reference
    /// cell (for the pyramid: polynomials in (ξ, η, ζ), and also every function
    /// of degree ≤ `degree` in each collapsed coordinate a, b, ζ times (1−ζ)²,
    /// e.g. products of its shape functions).
    ///
    /// - Tet4: centroid (degree ≤ 1), 4-point rule (degree 2), otherwise the
    ///   collapsed (Duffy) Gauss rule with n = ⌈(degree+3)/2⌉ points per direction.
    /// - Hex8: n × n × n Gauss, n = ⌈(degree+1)/2⌉.
    /// - Prism6: `seam::triangle_rule(degree)` × n Gauss, n = ⌈(degree+1)/2⌉.
    /// - Pyramid5: n × n Gauss in (a, b) and ⌈(degree+3)/2⌉ in ζ, collapsed.
    ///
    /// # Panics
    /// Prism6 with `degree > seam::MAX_TRIANGLE_DEGREE`.
    ///
    /// Second-order kinds use the rule of their [`ElementKind::family`].
    pub fn rule(self, degree: usize) -> VolumeRule {
        match self.family() {
            ElementKind::Tet4 => match degree {
                0 | 1 => VolumeRule { points: vec![[0.25; 3]], weights: vec![1.0 / 6.0] },
                2 => {
                    let a = (5.0 + 3.0 * 5f64.sqrt()) / 20.0;
                    let b = (5.0 - 5f64.sqrt()) / 20.0;
                    VolumeRule {
                        points: vec![[b, b, b], [a, b, b], [b, a, b], [b, b, a]],
                        weights: vec![1.0 / 24.0; 4],
                    }
                }
                _ => tet_collapsed_rule((degree + 4) / 2),
            },
            ElementKind::Hex8 => {
                let (x, w) = gauss_legendre(degree / 2 + 1);
                let mut rule = VolumeRule { points: Vec::new(), weights: Vec::new() };
                for k in 0..x.len() {
                    for j in 0..x.len() {
                        for i in 0..x.len() {
                            rule.points.push([x[i], x[j], x[k]]);
                            rule.weights.push(w[i] * w[j] * w[k]);
                        }
                    }
                }
                rule
            }
            ElementKind::Prism6 => {
                let tri = triangle_rule(degree).expect("triangle rule degree within the tabulated range");
                let (x, w) = gauss_legendre(degree / 2 + 1);
                let mut rule = VolumeRule { points: Vec::new(), weights: Vec::new() };
                for k in 0..x.len() {
                    for (p, wt) in tri.points.iter().zip(tri.weights) {
                        rule.points.push([p[0], p[1], x[k]]);
                        rule.weights.push(0.5 * wt * w[k]);
                    }
                }
                rule
            }
            _ => pyramid_rule(degree / 2 + 1, (degree + 4) / 2),
        }
    }
}

/// Gauss points on \[0,1\]: (points, weights summing to 1).
fn gauss_unit(n: usize) -> (Vec<f64>, Vec<f64>) {
    let (x, w) = gauss_legendre(n);
    (x.iter().map(|x| 0.5 * (1.0 + x)).collect(), w.iter().map(|w| 0.5 * w).collect())
}

/// The collapsed tet rule with n points per direction: (u, v, w) ∈ \[0,1\]³ ↦
/// ξ = u(1−v)(1−w), η = v(1−w), ζ = w, Jacobian (1−v)(1−w)²; exact for total
/// degree ≤ 2n − 3.
fn tet_collapsed_rule(n: usize) -> VolumeRule {
    let (x, w) = gauss_unit(n);
    let mut rule = VolumeRule { points: Vec::new(), weights: Vec::new() };
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let (u, v, t) = (x[i], x[j], x[k]);
                rule.points.push([u * (1.0 - v) * (1.0 - t), v * (1.0 - t), t]);
                rule.weights.push(w[i] * w[j] * w[k] * (1.0 - v) * (1.0 - t) * (1.0 - t));
            }
        }
    }
    rule
}

/// The collapsed pyramid rule: n_ab × n_ab Gauss in (a, b) ∈ \[−1,1\]², n_z Gauss
/// in ζ ∈ \[0,1\]; ξ = a(1−ζ), η = b(1−ζ), weight w_a w_b w_ζ (1−ζ)².
fn pyramid_rule(n_ab: usize, n_z: usize) -> VolumeRule {
    let (a, wa) = gauss_legendre(n_ab);
    let (z, wz) = gauss_unit(n_z);
    let mut rule = VolumeRule { points: Vec::new(), weights: Vec::new() };
    for k in 0..n_z {
        let s = 1.0 - z[k];
        for j in 0..n_ab {
            for i in 0..n_ab {
                rule.points.push([a[i] * s, a[j] * s, z[k]]);
                rule.weights.push(wa[i] * wa[j] * wz[k] * s * s);
            }
        }
    }
    rule
}

/// The n-point Gauss–Legendre rule on \[−1,1\], points ascending: exact for
/// polynomials of degree ≤ 2n − 1. Newton's iteration on P_n from Chebyshev-like
/// initial guesses; weights w_i = 2 / ((1 − x_i²) P_n'(x_i)²).
///
/// # Panics
/// If `n == 0`.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    assert!(n > 0, "a Gauss rule needs at least one point");
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        let mut t = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (p, d) = legendre(n, t);
            dp = d;
            let dt = p / d;
            t -= dt;
            if dt.abs() < 1e-16 {
                break;
            }
        }
        let (_, d) = legendre(n, t);
        if d != 0.0 {
            dp = d;
        }
        x[n - 1 - i] = t;
        w[n - 1 - i] = 2.0 / ((1.0 - t * t) * dp * dp);
    }
    (x, w)
}

/// (P_n(t), P_n'(t)) by the three-term recurrence.
fn legendre(n: usize, t: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, t);
    for k in 2..=n {
        let p2 = ((2 * k - 1) as f64 * t * p1 - (k - 1) as f64 * p0) / k as f64;
        p0 = p1;
        p1 = p2;
    }
    // n = 1: P_0 = 1, P_1 = t.
    let d = n as f64 * (t * p1 - p0) / (t * t - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points strictly inside each reference cell.
    fn samples(kind: ElementKind) -> Vec<Xi> {
        match kind.family() {
            ElementKind::Tet4 => vec![[0.1, 0.2, 0.3], [0.25, 0.25, 0.25], [0.6, 0.1, 0.05]],
            ElementKind::Hex8 => vec![[0.1, -0.7, 0.3], [0.0; 3], [0.9, 0.8, -0.95]],
            ElementKind::Prism6 => vec![[0.1, 0.2, 0.3], [0.5, 0.3, -0.9], [0.2, 0.7, 0.6]],
            _ => vec![[0.1, -0.2, 0.3], [0.5, 0.3, 0.1], [-0.05, 0.02, 0.9]],
        }
    }

    #[test]
    fn partition_of_unity_and_zero_gradient_sum() {
        for kind in ElementKind::ALL {
            // First order: closed forms, exact to 1e-14. Second order: bases
            // from an inverted 10–27-term interpolation matrix, whose round-off
            // is larger (values 1e-13, gradients 1e-12).
            let (tol, gtol) = if kind.order() == 1 { (1e-14, 1e-14) } else { (1e-13, 1e-12) };
            for xi in samples(kind) {
                let n = kind.shape(xi);
                assert!((n.iter().sum::<f64>() - 1.0).abs() < tol, "{kind:?} at {xi:?}");
                let g = kind.gradients(xi);
                for k in 0..3 {
                    let s: f64 = g.iter().map(|gi| gi[k]).sum();
                    assert!(s.abs() < gtol, "{kind:?} at {xi:?}: Σ ∂N/∂ξ_{k} = {s}");
                }
                // Linear completeness: Σ N_i ξ_i = ξ, Σ ξ_i ⊗ ∇N_i = I.
                let nodes = kind.reference_nodes();
                for k in 0..3 {
                    let s: f64 = nodes.iter().zip(&n).map(|(p, n)| p[k] * n).sum();
                    assert!((s - xi[k]).abs() < tol, "{kind:?}: Σ N_i ξ_i ≠ ξ");
                    for l in 0..3 {
                        let s: f64 = nodes.iter().zip(&g).map(|(p, g)| p[k] * g[l]).sum();
                        assert!((s - (k == l) as u8 as f64).abs() < gtol, "{kind:?}: Σ ξ_i ∇N_i ≠ I");
                    }
                }
            }
        }
    }

    #[test]
    fn nodal_interpolation() {
        for kind in ElementKind::ALL {
            for (j, &p) in kind.reference_nodes().iter().enumerate() {
                let n = kind.shape(p);
                for (i, &v) in n[..kind.n_nodes()].iter().enumerate() {
                    let expected = if i == j { 1.0 } else { 0.0 };
                    // First-order kinds are closed forms; second-order ones go through V⁻¹.
                    let tol = if kind.order() == 1 { 1e-15 } else { 1e-13 };
                    assert!((v - expected).abs() < tol, "{kind:?}: N_{i}(node {j}) = {v}");
                }
            }
        }
    }

    #[test]
    fn gradients_match_finite_differences() {
        let h = 1e-6;
        for kind in ElementKind::ALL {
            for xi in samples(kind) {
                let g = kind.gradients(xi);
                for k in 0..3 {
                    let (mut a, mut b) = (xi, xi);
                    a[k] += h;
                    b[k] -= h;
                    let (na, nb) = (kind.shape(a), kind.shape(b));
                    for i in 0..kind.n_nodes() {
                        let fd = (na[i] - nb[i]) / (2.0 * h);
                        assert!(
                            (fd - g[i][k]).abs() < 1e-8,
                            "{kind:?} N_{i} ∂_{k} at {xi:?}: {fd} vs {}",
                            g[i][k]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
        for n in 1..=6 {
            let (x, w) = gauss_legendre(n);
            assert!(x.windows(2).all(|p| p[0] < p[1]));
            for d in 0..2 * n {
                let exact = if d % 2 == 0 { 2.0 / (d as f64 + 1.0) } else { 0.0 };
                let q: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(d as i32)).sum();
                assert!((q - exact).abs() < 1e-14, "n = {n}, degree {d}: {q} vs {exact}");
            }
        }
    }

    fn factorial(n: usize) -> f64 {
        (1..=n).map(|k| k as f64).product()
    }

    /// ∫ ξ^a η^b ζ^c over the reference cell.
    fn monomial_integral(kind: ElementKind, a: usize, b: usize, c: usize) -> f64 {
        let sym = |p: usize| if p % 2 == 0 { 2.0 / (p as f64 + 1.0) } else { 0.0 };
        match kind.family() {
            ElementKind::Tet4 => factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3),
            ElementKind::Hex8 => sym(a) * sym(b) * sym(c),
            ElementKind::Prism6 => factorial(a) * factorial(b) / factorial(a + b + 2) * sym(c),
            // ∫_0^1 ζ^c (1−ζ)^{a+b+2} dζ · ∫ a^a ∫ b^b
            _ => sym(a) * sym(b) * factorial(c) * factorial(a + b + 2) / factorial(a + b + c + 3),
        }
    }

    #[test]
    fn rules_integrate_monomials_of_their_degree() {
        for kind in ElementKind::FIRST_ORDER {
            for degree in 0..=7 {
                let rule = kind.rule(degree);
                assert!(rule.weights.iter().all(|&w| w > 0.0));
                for a in 0..=degree {
                    for b in 0..=degree - a {
                        for c in 0..=degree - a - b {
                            let q: f64 = rule
                                .iter()
                                .map(|(p, w)| {
                                    w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32)
                                })
                                .sum();
                            let exact = monomial_integral(kind, a, b, c);
                            assert!(
                                (q - exact).abs() < 1e-14 * kind.reference_volume(),
                                "{kind:?} rule({degree}): ξ^{a}η^{b}ζ^{c}: {q} vs {exact}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn stiffness_rules() {
        let sizes: Vec<usize> = ElementKind::ALL.iter().map(|k| k.stiffness_rule().len()).collect();
        assert_eq!(sizes, [1, 8, 6, 8, 4, 27, 27, 18, 18, 27, 27]);
        for kind in ElementKind::ALL {
            let v: f64 = kind.stiffness_rule().weights.iter().sum();
            // 27-point rules on the volume-8 hex sum to 8 within 1.1e-14: relative there.
            let tol = if kind.order() == 1 { 1e-14 } else { 1e-14 * kind.reference_volume() };
            assert!((v - kind.reference_volume()).abs() < tol, "{kind:?}: Σw = {v}");
        }
    }
}
