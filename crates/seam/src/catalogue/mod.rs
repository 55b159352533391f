//! The element catalogue: every kind of face and cell seam knows, each with one
//! static description, and the node-carrying [`Face`] and [`Cell`] built from
//! the same list.
//!
//! | face | Gmsh | VTK | nodes | cell | Gmsh | VTK | nodes |
//! |---|---:|---:|---:|---|---:|---:|---:|
//! | Tri3 | 2 | 5 | 3 | Tet4 | 4 | 10 | 4 |
//! | Quad4 | 3 | 9 | 4 | Hex8 | 5 | 12 | 8 |
//! | Tri6 | 9 | 22 | 6 | Prism6 | 6 | 13 | 6 |
//! | Quad8 | 16 | 23 | 8 | Pyramid5 | 7 | 14 | 5 |
//! | Quad9 | 10 | 28 | 9 | Tet10 | 11 | 24 | 10 |
//! | Tri7 | – | 34 | 7 | Hex20 | 17 | 25 | 20 |
//! | | | | | Hex27 | 12 | 29 | 27 |
//! | | | | | Prism15 | 18 | 26 | 15 |
//! | | | | | Prism18 | 13 | 32 | 18 |
//! | | | | | Pyramid13 | 19 | 27 | 13 |
//! | | | | | Pyramid14 | 14 | 27 (13 nodes) | 14 |
//! | | | | | Tet14 | – | 24 (10 nodes) | 14 |
//!
//! A kind answers every question about its reference element through
//! [`FaceKind::info`] ([`FaceType`]) or [`CellKind::info`] ([`CellType`]):
//! node count, reference coordinates in Gmsh's node order, corners, edges and
//! their mid-edge nodes, face centres, local faces, shape functions and
//! gradients, Gmsh type number, VTK type and node permutation. Readers,
//! writers and integrators ask the kind instead of matching on it. Adding a
//! kind is one table and one line of the list that makes the enums (a face
//! kind with a new node count also needs its values in [`shape_values`], the
//! fixed-size form the quadrature loops use).
//!
//! # Node order and reference cells
//! Nodes are numbered as Gmsh numbers them: corners first (a face's corners in
//! cyclic order, its normal by the right-hand rule), then one node per edge in
//! the order of [`CellType::edges`] (faces: edge k joins corners k and k + 1),
//! then the centres of quadrilateral faces, then (Hex27) the cell centre.
//!
//! | shape | reference cell | convention |
//! |---|---|---|
//! | triangle | (0,0), (1,0), (0,1) | Gmsh's |
//! | quadrangle (faces) | \[0,1\]² | seam's: Gmsh's \[−1,1\]² mapped by ξ ↦ (ξ+1)/2 |
//! | tetrahedron | ξ, η, ζ ≥ 0, ξ+η+ζ ≤ 1 | Gmsh's |
//! | hexahedron | \[−1,1\]³ | Gmsh's |
//! | prism | triangle × \[−1,1\] | Gmsh's |
//! | pyramid | base \[−1,1\]² at ζ = 0, apex (0,0,1) | Gmsh's |
//!
//! A face's reference coordinates ([`FaceType::nodes`]) are those of the
//! surface kernels (quads on \[0,1\]²); a cell's ([`CellType::nodes`]) are
//! Gmsh's reference nodes exactly.

mod cells;
pub(crate) mod faces;
#[cfg(test)]
pub(crate) mod tests;

pub use cells::{CellBasis, Space, Term, MAX_CELL_NODES};
pub use faces::{shape_and_gradients, shape_values, ShapeAndGradients, MAX_FACE_NODES};

/// Reference coordinates (ξ, η) on a face.
pub type Xi = [f64; 2];

/// Reference coordinates (ξ, η, ζ) in a cell.
pub type Xi3 = [f64; 3];

/// The reference shapes of Gmsh's element families (also those seam does not
/// compute on, which readers name in their messages).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shape {
    /// A point.
    Point,
    /// A line segment.
    Line,
    /// A triangle.
    Triangle,
    /// A quadrilateral ("quadrangle" in Gmsh).
    Quadrangle,
    /// A tetrahedron.
    Tetrahedron,
    /// A hexahedron.
    Hexahedron,
    /// A triangular prism (VTK's wedge).
    Prism,
    /// A pyramid over a quadrilateral base.
    Pyramid,
}

impl Shape {
    /// The dimension: 0 to 3.
    pub const fn dim(self) -> u8 {
        match self {
            Shape::Point => 0,
            Shape::Line => 1,
            Shape::Triangle | Shape::Quadrangle => 2,
            Shape::Tetrahedron | Shape::Hexahedron | Shape::Prism | Shape::Pyramid => 3,
        }
    }

    /// The shape in words, as Gmsh names it: "point", "triangle", "quadrangle", ….
    pub const fn noun(self) -> &'static str {
        match self {
            Shape::Point => "point",
            Shape::Line => "line",
            Shape::Triangle => "triangle",
            Shape::Quadrangle => "quadrangle",
            Shape::Tetrahedron => "tetrahedron",
            Shape::Hexahedron => "hexahedron",
            Shape::Prism => "prism",
            Shape::Pyramid => "pyramid",
        }
    }
}

/// One local face of a cell: its kind and its nodes as local node numbers of
/// the cell, in the face's own Gmsh order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LocalFace {
    /// The face kind.
    pub kind: FaceKind,
    nodes: [usize; MAX_FACE_NODES],
}

impl LocalFace {
    /// The local node numbers (corners, mid-edge nodes, centre).
    pub fn nodes(&self) -> &[usize] {
        &self.nodes[..self.kind.n_nodes()]
    }

    /// The local corner numbers, in cyclic order.
    pub fn corners(&self) -> &[usize] {
        &self.nodes[..self.kind.n_corners()]
    }
}

/// The description of a face kind ([`FaceKind::info`]).
#[derive(Debug)]
pub struct FaceType {
    /// The name: "Tri3", "Quad4", "Tri6", "Quad8", "Quad9" or "Tri7".
    pub name: &'static str,
    /// Triangle or quadrangle.
    pub shape: Shape,
    /// The first-order kind through the same corners (itself at first order).
    pub linear: FaceKind,
    /// Reference coordinates of the nodes in Gmsh order (quads on \[0,1\]²).
    pub nodes: &'static [Xi],
    /// The number of corners: 3 or 4.
    pub corners: usize,
    /// The edges as corner pairs; edge k joins corners k and k + 1 and (second
    /// order) carries node `corners + k`.
    pub edges: &'static [[usize; 2]],
    /// The node permutation that reverses the orientation: the first corner
    /// stays, mid-edge nodes follow their edges.
    pub reversed: &'static [usize],
    /// The face cut into first-order polygons through its nodes, for drawing:
    /// itself at first order, four triangles (Tri6), four quads (Quad9), six
    /// triangles about the centre (Tri7), or the polygon of its eight nodes
    /// (Quad8).
    pub pieces: &'static [&'static [usize]],
    /// The Gmsh element type number (Tri7 has none).
    pub gmsh_type: Option<u32>,
    /// The VTK cell type number.
    pub vtk_type: u8,
    /// VTK's node order: VTK node i is node `vtk_order[i]` (VTK numbers the
    /// nodes of these faces as Gmsh does).
    pub vtk_order: &'static [usize],
    /// Shape functions N_i(ξ) and gradients ∂N_i/∂(ξ, η); entries past the
    /// node count are 0.
    pub shape_and_gradients: fn(Xi) -> ShapeAndGradients,
    /// Row i: the coefficients of N_i in the monomials (1, s, t, s², st, t²,
    /// s²t, st², s²t²) in which every face map is a polynomial.
    pub monomials: [[f64; faces::MONOMIALS]; MAX_FACE_NODES],
    /// How many of those monomials the kind's map uses (the others have zero
    /// coefficients): Tri3 3, Quad4 5 (no s², but st), Tri6 6, Quad8 8, Quad9
    /// 9, Tri7 8.
    pub n_monomials: usize,
    /// The kind one node larger whose extra function is the face bubble
    /// (Tri6 → Tri7, Quad8 → Quad9), for the faces whose own functions lack a
    /// positive integral ([`crate::SurfaceMesh::enriched`]).
    pub enriched: Option<FaceKind>,
    /// Whether every shape function has a positive integral over the face.
    /// False for Tri6 and Quad8, whose corner functions integrate to 0 and to
    /// −1/12 of the area: lumped and dual multipliers need positive ones.
    pub positive_integrals: bool,
}

/// The description of a cell kind ([`CellKind::info`]).
#[derive(Debug)]
pub struct CellType {
    /// The name: "Tet4", "Hex8", …, "Pyramid14".
    pub name: &'static str,
    /// Tetrahedron, hexahedron, prism or pyramid.
    pub shape: Shape,
    /// The first-order kind with the same reference cell and corners (the
    /// family; itself at first order).
    pub linear: CellKind,
    /// Gmsh's reference coordinates of the nodes, in Gmsh order.
    pub nodes: &'static [Xi3],
    /// The number of corners: 4, 5, 6 or 8.
    pub corners: usize,
    /// The edges as sorted corner pairs in Gmsh's order: at second order edge
    /// k carries node `corners + k`.
    pub edges: &'static [[usize; 2]],
    /// The local faces, outward for a positively oriented cell
    /// ([`crate::VolumeMesh::boundary`] orients geometrically and does not rely
    /// on it): first-order faces for first-order cells; Tri6, Quad8 or Quad9
    /// (where the cell has the face centre) for second-order cells.
    pub faces: &'static [LocalFace],
    /// The Gmsh element type number (every cell kind has one).
    pub gmsh_type: Option<u32>,
    /// The VTK cell type number.
    pub vtk_type: u8,
    /// VTK's node order: VTK node i is node `vtk_order[i]`. Both put the corners
    /// first and differ in how they number edges and face centres; a Pyramid14
    /// is written as VTK's 13-node pyramid (VTK has no 14-node one).
    pub vtk_order: &'static [usize],
    /// The kind with the centres (and for hexahedra the cell centre) that give
    /// each Tri6 or Quad8 face its bubble (Tet10 → Tet14, Hex20 → Hex27), for
    /// the cells of an enriched slave surface; `None` for kinds without such
    /// faces and for Prism15 and Pyramid13, which have no such kind.
    pub enriched: Option<CellKind>,
    /// The shape functions.
    pub basis: CellBasis,
    /// The rule the stiffness is integrated with ([`CellKind::stiffness_rule`]).
    pub stiffness: StiffnessRule,
}

/// Which rule integrates a cell kind's stiffness: exact for the stiffness of
/// affine cells, and for ∫_e ∇N_i dV and the volume of any (trilinear,
/// prismatic, collapsed) cell, which is what the patch test needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StiffnessRule {
    /// [`CellKind::rule`] of this degree.
    Degree(usize),
    /// The collapsed pyramid rule with this many Gauss points in each of a, b
    /// and ζ (ξ = a(1−ζ), η = b(1−ζ), the Duffy factor (1−ζ)² in the weights).
    Collapsed(usize),
}

/// Declares a kind enum, the node-carrying element enum of the same variants
/// and their links to the description tables: the one list of kinds.
macro_rules! catalogue {
    (
        $(#[$kind_doc:meta])* kind $Kind:ident;
        $(#[$elem_doc:meta])* element $Elem:ident;
        $Type:ident {
            $( $(#[$doc:meta])* $Variant:ident($n:literal) = $table:path, )*
        }
    ) => {
        $(#[$kind_doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum $Kind {
            $( $(#[$doc])* $Variant, )*
        }

        $(#[$elem_doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum $Elem {
            $( $(#[$doc])* $Variant([usize; $n]), )*
        }

        impl $Kind {
            /// Every kind, in declaration order (`kind as usize` indexes it).
            pub const ALL: [$Kind; [$($n),*].len()] = [$($Kind::$Variant),*];

            /// The kind's description.
            #[inline]
            pub const fn info(self) -> &'static $Type {
                static TYPES: [$Type; [$($n),*].len()] = [$($table),*];
                &TYPES[self as usize]
            }

            // The counts below are read from the tables at compile time, one
            // constant per kind: as cheap as a hand-written match in the
            // kernels' inner loops.

            /// The number of nodes.
            #[inline]
            pub const fn n_nodes(self) -> usize {
                match self {
                    $( $Kind::$Variant => $n, )*
                }
            }

            /// The number of corners.
            #[inline]
            pub const fn n_corners(self) -> usize {
                match self {
                    $( $Kind::$Variant => $table.corners, )*
                }
            }

            /// The polynomial order: 1 or 2.
            #[inline]
            pub const fn order(self) -> usize {
                match self {
                    $( $Kind::$Variant => if $n > $table.corners { 2 } else { 1 }, )*
                }
            }

            /// The first-order kind with the same reference cell and corners
            /// (itself at first order).
            #[inline]
            pub const fn linear(self) -> $Kind {
                match self {
                    $( $Kind::$Variant => $table.linear, )*
                }
            }

            /// The kind of an element.
            #[inline]
            pub const fn of(element: &$Elem) -> $Kind {
                element.kind()
            }

            /// The kind with this Gmsh element type number, if seam has it.
            pub fn from_gmsh(gmsh_type: u32) -> Option<$Kind> {
                $Kind::ALL.into_iter().find(|k| k.info().gmsh_type == Some(gmsh_type))
            }

            /// The name, as in the enum.
            pub const fn name(self) -> &'static str {
                self.info().name
            }

        }

        $( const _: () = assert!($table.nodes.len() == $n, "the table lists the kind's nodes"); )*

        impl $Elem {
            /// The kind.
            #[inline]
            pub const fn kind(&self) -> $Kind {
                match self {
                    $( $Elem::$Variant(_) => $Kind::$Variant, )*
                }
            }

            /// All node indices, in Gmsh order.
            #[inline]
            pub fn nodes(&self) -> &[usize] {
                match self {
                    $( $Elem::$Variant(n) => n, )*
                }
            }

            /// The corner indices, in cyclic (faces) or Gmsh (cells) order.
            #[inline]
            pub fn corner_nodes(&self) -> &[usize] {
                match self {
                    $( $Elem::$Variant(n) => &n[..$table.corners], )*
                }
            }

            /// The number of corners.
            #[inline]
            pub fn n_corners(&self) -> usize {
                self.kind().n_corners()
            }

            /// The node indices, to change in place.
            #[inline]
            pub fn nodes_mut(&mut self) -> &mut [usize] {
                match self {
                    $( $Elem::$Variant(n) => n, )*
                }
            }

            /// The element of `kind` with these node indices (Gmsh order);
            /// `None` unless there are as many as the kind has nodes.
            pub fn new(kind: $Kind, nodes: &[usize]) -> Option<$Elem> {
                Some(match kind {
                    $( $Kind::$Variant => $Elem::$Variant(nodes.try_into().ok()?), )*
                })
            }
        }
    };
}

catalogue! {
    /// A face kind: a linear triangle, a bilinear quadrilateral, or one of
    /// their second-order (curved) versions.
    kind FaceKind;
    /// A surface face: its kind and its nodes, 0-based point indices in Gmsh
    /// order (the corners in cyclic order, the face normal by the right-hand
    /// rule; for second-order faces then the mid-edge nodes of edges 0–1, 1–2,
    /// … and, for Quad9, the centre).
    element Face;
    FaceType {
        /// Three-node linear triangle.
        Tri3(3) = faces::TRI3,
        /// Four-node bilinear quadrilateral, possibly warped.
        Quad4(4) = faces::QUAD4,
        /// Six-node quadratic triangle: corners, then the mid-edge nodes.
        Tri6(6) = faces::TRI6,
        /// Eight-node serendipity quadrilateral: corners, then the mid-edge nodes.
        Quad8(8) = faces::QUAD8,
        /// Nine-node biquadratic quadrilateral: corners, mid-edge nodes, centre.
        Quad9(9) = faces::QUAD9,
        /// Seven-node triangle: Tri6 and the centre, whose function is the
        /// cubic bubble (the enriched slave space of dual multipliers).
        Tri7(7) = faces::TRI7,
    }
}

catalogue! {
    /// A cell kind: four first-order and seven second-order ones as meshes
    /// have them, and the Tet14 of enriched slave bodies.
    kind CellKind;
    /// A volume cell: its kind and its nodes in Gmsh order (corners first,
    /// then at second order the mid-edge nodes, face centres and cell centre
    /// as Gmsh numbers them).
    element Cell;
    CellType {
        /// Four-node tetrahedron.
        Tet4(4) = cells::TET4,
        /// Eight-node hexahedron: bottom 0-1-2-3, top 4-5-6-7.
        Hex8(8) = cells::HEX8,
        /// Six-node prism: bottom triangle 0-1-2, top 3-4-5.
        Prism6(6) = cells::PRISM6,
        /// Five-node pyramid: base 0-1-2-3, apex 4.
        Pyramid5(5) = cells::PYRAMID5,
        /// Ten-node quadratic tetrahedron (P₂).
        Tet10(10) = cells::TET10,
        /// Twenty-node serendipity hexahedron (S₂).
        Hex20(20) = cells::HEX20,
        /// Twenty-seven-node triquadratic hexahedron (Q₂).
        Hex27(27) = cells::HEX27,
        /// Fifteen-node serendipity prism.
        Prism15(15) = cells::PRISM15,
        /// Eighteen-node prism (P₂ triangle × quadratic segment), with
        /// quadrilateral face centres.
        Prism18(18) = cells::PRISM18,
        /// Thirteen-node rational serendipity pyramid.
        Pyramid13(13) = cells::PYRAMID13,
        /// Fourteen-node rational pyramid (Bergot–Cohen–Duruflé B₂), with the
        /// base centre.
        Pyramid14(14) = cells::PYRAMID14,
        /// Fourteen-node tetrahedron: Tet10 and the centroids of its faces,
        /// whose functions are the cubic face bubbles (enriched slave bodies).
        Tet14(14) = cells::TET14,
    }
}

impl FaceKind {
    /// The kind with this VTK cell type number, if seam has it.
    pub fn from_vtk(vtk_type: u8) -> Option<FaceKind> {
        FaceKind::ALL.into_iter().find(|k| k.info().vtk_type == vtk_type)
    }

    /// The kind with `n` nodes (3, 4, 6, 7, 8 or 9), if any.
    pub const fn with_nodes(n: usize) -> Option<FaceKind> {
        let mut i = 0;
        while i < FaceKind::ALL.len() {
            if FaceKind::ALL[i].n_nodes() == n {
                return Some(FaceKind::ALL[i]);
            }
            i += 1;
        }
        None
    }

    /// The reference coordinates of the nodes, in node order.
    pub const fn nodes(self) -> &'static [Xi] {
        self.info().nodes
    }

    /// True for Tri3, Tri6 and Tri7.
    #[inline]
    pub const fn is_triangle(self) -> bool {
        self.n_corners() == 3
    }

    /// True for a point of the reference cell, enlarged by `tol`.
    pub fn contains(self, xi: Xi, tol: f64) -> bool {
        let [s, t] = xi;
        if self.is_triangle() {
            s >= -tol && t >= -tol && s + t <= 1.0 + tol
        } else {
            (-tol..=1.0 + tol).contains(&s) && (-tol..=1.0 + tol).contains(&t)
        }
    }

    /// The reference centroid: (⅓, ⅓) or (½, ½).
    pub const fn centre(self) -> Xi {
        if self.is_triangle() {
            [1.0 / 3.0, 1.0 / 3.0]
        } else {
            [0.5, 0.5]
        }
    }

    /// The reference cell as triangles: itself, or the two halves of the unit
    /// square cut along its diagonal from (0,0) to (1,1).
    pub const fn reference_triangles(self) -> &'static [[Xi; 3]] {
        const TRIANGLE: [[Xi; 3]; 1] = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
        const SQUARE: [[Xi; 3]; 2] =
            [[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]];
        if self.is_triangle() {
            &TRIANGLE
        } else {
            &SQUARE
        }
    }

    /// Shape functions N_i(ξ) and gradients ∂N_i/∂(ξ, η) ([`FaceType::shape_and_gradients`]).
    #[inline]
    pub fn shape_and_gradients(self, xi: Xi) -> ShapeAndGradients {
        (self.info().shape_and_gradients)(xi)
    }
}

impl Face {
    /// Builds a face from its nodes: 3 (Tri3), 4 (Quad4), 6 (Tri6), 7 (Tri7),
    /// 8 (Quad8) or 9 (Quad9).
    ///
    /// # Panics
    /// If `nodes.len()` is none of these.
    pub fn from_nodes(nodes: &[usize]) -> Face {
        FaceKind::with_nodes(nodes.len())
            .and_then(|kind| Face::new(kind, nodes))
            .unwrap_or_else(|| panic!("a face has 3, 4, 6, 7, 8 or 9 nodes, got {}", nodes.len()))
    }

    /// Number of nodes (3, 4, 6, 7, 8 or 9).
    #[inline]
    pub fn len(&self) -> usize {
        self.nodes().len()
    }

    /// Always false: a face has at least three nodes.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// True for the second-order faces Tri6, Quad8, Quad9 and Tri7.
    #[inline]
    pub fn is_curved(&self) -> bool {
        self.kind().order() == 2
    }

    /// The same face with reversed orientation (first corner kept; mid-edge
    /// nodes follow their edges).
    #[must_use]
    pub fn reversed(&self) -> Face {
        self.permuted(self.kind().info().reversed)
    }

    /// The face with node i replaced by node `order[i]`.
    fn permuted(&self, order: &[usize]) -> Face {
        let mut face = *self;
        for (new, &old) in face.nodes_mut().iter_mut().zip(order) {
            *new = self.nodes()[old];
        }
        face
    }

    /// The face cut into first-order faces through its nodes, for drawing
    /// ([`FaceType::pieces`]).
    pub fn linear_pieces(&self) -> Vec<Vec<usize>> {
        let n = self.nodes();
        self.kind().info().pieces.iter().map(|piece| piece.iter().map(|&i| n[i]).collect()).collect()
    }
}

impl std::fmt::Display for Face {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}{:?}", self.kind().name(), self.nodes())
    }
}

impl CellKind {
    /// The four first-order kinds (the reference cell families).
    pub const FIRST_ORDER: [CellKind; 4] =
        [CellKind::Tet4, CellKind::Hex8, CellKind::Prism6, CellKind::Pyramid5];

    /// The seven second-order kinds.
    pub const SECOND_ORDER: [CellKind; 7] = [
        CellKind::Tet10,
        CellKind::Hex20,
        CellKind::Hex27,
        CellKind::Prism15,
        CellKind::Prism18,
        CellKind::Pyramid13,
        CellKind::Pyramid14,
    ];

    /// The mesh cell of this kind with the point indices `nodes` (Gmsh order);
    /// `None` unless `nodes.len() == self.n_nodes()`.
    pub fn cell(self, nodes: &[usize]) -> Option<Cell> {
        Cell::new(self, nodes)
    }

    /// The family: the first-order kind with the same reference cell and
    /// corners ([`CellKind::linear`]).
    #[inline]
    pub const fn family(self) -> CellKind {
        self.linear()
    }

    /// The reference shape.
    pub const fn reference_shape(self) -> Shape {
        self.info().shape
    }

    /// The reference coordinates of the nodes, in Gmsh order.
    pub const fn reference_nodes(self) -> &'static [Xi3] {
        self.info().nodes
    }

    /// The second-order kind of this family: the complete one (Tet10, Hex27,
    /// Prism18, Pyramid14) or the serendipity one (Tet10, Hex20, Prism15,
    /// Pyramid13); `None` for a second-order kind.
    pub fn second_order(self, complete: bool) -> Option<CellKind> {
        if self.order() == 2 {
            return None;
        }
        let family = CellKind::SECOND_ORDER.into_iter().filter(|k| k.family() == self);
        if complete {
            family.max_by_key(|k| k.n_nodes())
        } else {
            family.min_by_key(|k| k.n_nodes())
        }
    }

    /// The local corners whose mean is each node's reference position, per
    /// node in Gmsh order: the corner itself, the two ends of a mid-edge node's
    /// edge, the corners of a face centre (in the face's order), all corners
    /// for the Hex27 centre.
    pub fn node_supports(self) -> Vec<Vec<usize>> {
        let info = self.info();
        (0..self.n_nodes())
            .map(|i| {
                if i < info.corners {
                    return vec![i];
                }
                if let Some(edge) = info.edges.get(i - info.corners) {
                    return edge.to_vec();
                }
                match info.faces.iter().find(|f| {
                    f.kind.n_nodes() > 2 * f.kind.n_corners() && f.nodes()[2 * f.kind.n_corners()] == i
                }) {
                    Some(face) => face.corners().to_vec(),
                    None => (0..info.corners).collect(),
                }
            })
            .collect()
    }

    /// Volume of the reference cell: 1/6, 8, 1, 4/3 (tets, hexes, prisms, pyramids).
    pub fn reference_volume(self) -> f64 {
        match self.reference_shape() {
            Shape::Tetrahedron => 1.0 / 6.0,
            Shape::Hexahedron => 8.0,
            Shape::Prism => 1.0,
            _ => 4.0 / 3.0,
        }
    }

    /// Centroid of the reference cell: (¼,¼,¼), 0, (⅓,⅓,0), (0,0,¼). For an
    /// affine cell it maps to the physical centroid.
    pub fn centroid(self) -> Xi3 {
        match self.reference_shape() {
            Shape::Tetrahedron => [0.25; 3],
            Shape::Hexahedron => [0.0; 3],
            Shape::Prism => [1.0 / 3.0, 1.0 / 3.0, 0.0],
            _ => [0.0, 0.0, 0.25],
        }
    }

    /// Shape functions N_i(ξ); entries past [`CellKind::n_nodes`] are 0.
    #[inline]
    pub fn shape(self, xi: Xi3) -> [f64; MAX_CELL_NODES] {
        match self.info().basis {
            CellBasis::Closed { shape, .. } => shape(xi),
            CellBasis::Nodal(_) => cells::nodal_shape(self, xi).0,
        }
    }

    /// Gradients ∇_ξ N_i(ξ) = (∂N_i/∂ξ, ∂N_i/∂η, ∂N_i/∂ζ); entries past
    /// [`CellKind::n_nodes`] are 0.
    #[inline]
    pub fn gradients(self, xi: Xi3) -> [[f64; 3]; MAX_CELL_NODES] {
        match self.info().basis {
            CellBasis::Closed { gradients, .. } => gradients(xi),
            CellBasis::Nodal(_) => cells::nodal_shape(self, xi).1,
        }
    }
}

impl Cell {
    /// The same cell with node `n` replaced by `map(n)` (a renumbering of the
    /// points).
    pub fn map_nodes(&self, map: impl Fn(usize) -> usize) -> Cell {
        let mut cell = *self;
        cell.nodes_mut().iter_mut().for_each(|n| *n = map(*n));
        cell
    }

    /// True for second-order cells.
    pub fn is_second_order(&self) -> bool {
        self.kind().order() == 2
    }

    /// The cell's faces as [`Face`]s of global point indices ([`CellType::faces`]).
    pub fn faces(&self) -> impl Iterator<Item = Face> + '_ {
        let n = self.nodes();
        self.kind().info().faces.iter().map(move |local| {
            let mut global = [0usize; MAX_FACE_NODES];
            for (g, &l) in global.iter_mut().zip(local.nodes()) {
                *g = n[l];
            }
            Face::new(local.kind, &global[..local.kind.n_nodes()]).expect("the node count of the face kind")
        })
    }
}
