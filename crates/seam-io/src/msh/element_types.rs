//! The Gmsh element types: shape, number of nodes and a name in words.
//!
//! The table lists every fixed-size type Gmsh 4.15 knows (from
//! `gmsh.model.mesh.getElementProperties`); binary files need it to know how many
//! node tags follow an element tag.

/// The reference shape of an element type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shape {
    Point,
    Line,
    Triangle,
    Quadrangle,
    Tetrahedron,
    Hexahedron,
    Prism,
    Pyramid,
}

use Shape::*;

/// What the reader needs to know about one Gmsh element type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ElementType {
    /// The Gmsh type number.
    pub number: u32,
    /// The reference shape.
    pub shape: Shape,
    /// How many nodes an element of this type lists.
    pub nodes: usize,
    /// Whether it is an "incomplete" high-order type (Gmsh names ending in `I`).
    pub incomplete: bool,
}

/// `(type number, shape, nodes, incomplete)`.
#[rustfmt::skip]
const TYPES: &[(u32, Shape, u16, bool)] = &[
    (1, Line, 2, false), (2, Triangle, 3, false), (3, Quadrangle, 4, false),
    (4, Tetrahedron, 4, false), (5, Hexahedron, 8, false), (6, Prism, 6, false),
    (7, Pyramid, 5, false), (8, Line, 3, false), (9, Triangle, 6, false),
    (10, Quadrangle, 9, false), (11, Tetrahedron, 10, false), (12, Hexahedron, 27, false),
    (13, Prism, 18, false), (14, Pyramid, 14, false), (15, Point, 1, false),
    (16, Quadrangle, 8, false), (17, Hexahedron, 20, false), (18, Prism, 15, false),
    (19, Pyramid, 13, false), (20, Triangle, 9, false), (21, Triangle, 10, false),
    (22, Triangle, 12, false), (23, Triangle, 15, false), (24, Triangle, 15, true),
    (25, Triangle, 21, false), (26, Line, 4, false), (27, Line, 5, false),
    (28, Line, 6, false), (29, Tetrahedron, 20, false), (30, Tetrahedron, 35, false),
    (31, Tetrahedron, 56, false), (32, Tetrahedron, 22, false), (33, Tetrahedron, 28, false),
    (36, Quadrangle, 16, false), (37, Quadrangle, 25, false), (38, Quadrangle, 36, false),
    (39, Quadrangle, 12, false), (40, Quadrangle, 16, true), (41, Quadrangle, 20, false),
    (42, Triangle, 28, false), (43, Triangle, 36, false), (44, Triangle, 45, false),
    (45, Triangle, 55, false), (46, Triangle, 66, false), (47, Quadrangle, 49, false),
    (48, Quadrangle, 64, false), (49, Quadrangle, 81, false), (50, Quadrangle, 100, false),
    (51, Quadrangle, 121, false), (52, Triangle, 18, false), (53, Triangle, 21, true),
    (54, Triangle, 24, false), (55, Triangle, 27, false), (56, Triangle, 30, false),
    (57, Quadrangle, 24, false), (58, Quadrangle, 28, false), (59, Quadrangle, 32, false),
    (60, Quadrangle, 36, true), (61, Quadrangle, 40, false), (62, Line, 7, false),
    (63, Line, 8, false), (64, Line, 9, false), (65, Line, 10, false), (66, Line, 11, false),
    (71, Tetrahedron, 84, false), (72, Tetrahedron, 120, false), (73, Tetrahedron, 165, false),
    (74, Tetrahedron, 220, false), (75, Tetrahedron, 286, false), (79, Tetrahedron, 34, false),
    (80, Tetrahedron, 40, false), (81, Tetrahedron, 46, false), (82, Tetrahedron, 52, false),
    (83, Tetrahedron, 58, false), (84, Line, 1, false), (85, Triangle, 1, false),
    (86, Quadrangle, 1, false), (87, Tetrahedron, 1, false), (88, Hexahedron, 1, false),
    (89, Prism, 1, false), (92, Hexahedron, 64, false), (93, Hexahedron, 125, false),
    (94, Hexahedron, 216, false), (95, Hexahedron, 343, false), (96, Hexahedron, 512, false),
    (97, Hexahedron, 729, false), (98, Hexahedron, 1000, false), (99, Hexahedron, 32, false),
    (100, Hexahedron, 44, false), (101, Hexahedron, 56, false), (102, Hexahedron, 68, false),
    (103, Hexahedron, 80, false), (104, Hexahedron, 92, false), (105, Hexahedron, 104, false),
    (118, Pyramid, 30, false), (119, Pyramid, 55, false), (120, Pyramid, 91, false),
    (121, Pyramid, 140, false), (122, Pyramid, 204, false), (123, Pyramid, 285, false),
    (124, Pyramid, 385, false), (125, Pyramid, 21, false), (126, Pyramid, 29, false),
    (127, Pyramid, 37, false), (128, Pyramid, 45, false), (129, Pyramid, 53, false),
    (130, Pyramid, 61, false), (131, Pyramid, 69, false), (132, Pyramid, 1, false),
    (137, Tetrahedron, 16, false),
];

/// Gmsh type number of the 3-node triangle.
pub(crate) const TRI3: u32 = 2;
/// Gmsh type number of the 4-node quadrangle.
pub(crate) const QUAD4: u32 = 3;
/// Gmsh type number of the 4-node tetrahedron.
pub(crate) const TET4: u32 = 4;
/// Gmsh type number of the 8-node hexahedron.
pub(crate) const HEX8: u32 = 5;
/// Gmsh type number of the 6-node prism.
pub(crate) const PRISM6: u32 = 6;
/// Gmsh type number of the 5-node pyramid.
pub(crate) const PYRAMID5: u32 = 7;
/// Gmsh type number of the 6-node (second-order) triangle.
pub(crate) const TRI6: u32 = 9;
/// Gmsh type number of the 8-node (serendipity) quadrangle.
pub(crate) const QUAD8: u32 = 16;
/// Gmsh type number of the 9-node (biquadratic) quadrangle.
pub(crate) const QUAD9: u32 = 10;
/// Gmsh type number of the 10-node tetrahedron.
pub(crate) const TET10: u32 = 11;
/// Gmsh type number of the 20-node (serendipity) hexahedron.
pub(crate) const HEX20: u32 = 17;
/// Gmsh type number of the 27-node (triquadratic) hexahedron.
pub(crate) const HEX27: u32 = 12;
/// Gmsh type number of the 15-node (serendipity) prism.
pub(crate) const PRISM15: u32 = 18;
/// Gmsh type number of the 18-node prism.
pub(crate) const PRISM18: u32 = 13;
/// Gmsh type number of the 13-node (serendipity) pyramid.
pub(crate) const PYRAMID13: u32 = 19;
/// Gmsh type number of the 14-node pyramid.
pub(crate) const PYRAMID14: u32 = 14;

/// Looks up a Gmsh element type number.
pub(crate) fn element_type(number: u32) -> Option<ElementType> {
    TYPES.iter().find(|&&(n, ..)| n == number).map(|&(number, shape, nodes, incomplete)| ElementType {
        number,
        shape,
        nodes: usize::from(nodes),
        incomplete,
    })
}

impl ElementType {
    /// The dimension of the reference shape (0 to 3).
    pub fn dim(&self) -> u8 {
        match self.shape {
            Point => 0,
            Line => 1,
            Triangle | Quadrangle => 2,
            Tetrahedron | Hexahedron | Prism | Pyramid => 3,
        }
    }

    /// The type in words with its article: "a point", "a 6-node triangle",
    /// "an 8-node hexahedron".
    pub fn describe(&self) -> String {
        let shape = match self.shape {
            Point => return "a point".to_string(),
            Line => "line",
            Triangle => "triangle",
            Quadrangle => "quadrangle",
            Tetrahedron => "tetrahedron",
            Hexahedron => "hexahedron",
            Prism => "prism",
            Pyramid => "pyramid",
        };
        let incomplete = if self.incomplete { " (incomplete)" } else { "" };
        format!("{} {}-node {shape}{incomplete}", article(self.nodes), self.nodes)
    }
}

/// "a" or "an" before a number said in English (8, 11, 18, 80-89, 800-899 take "an").
fn article(n: usize) -> &'static str {
    if n.to_string().starts_with('8') || n == 11 || n == 18 {
        "an"
    } else {
        "a"
    }
}

/// The type in words for an error message, also for numbers missing from the table.
pub(crate) fn describe_type(number: u32) -> String {
    match element_type(number) {
        Some(t) => t.describe(),
        None => "an unknown element type".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn supported_types_have_their_node_counts() {
        let corners = [(TRI3, 3), (QUAD4, 4), (TET4, 4), (HEX8, 8), (PRISM6, 6), (PYRAMID5, 5), (15, 1)];
        let second_order = [
            (TRI6, 6),
            (QUAD8, 8),
            (QUAD9, 9),
            (TET10, 10),
            (HEX20, 20),
            (HEX27, 27),
            (PRISM15, 15),
            (PRISM18, 18),
            (PYRAMID13, 13),
            (PYRAMID14, 14),
        ];
        for (number, nodes) in corners.into_iter().chain(second_order) {
            assert_eq!(element_type(number).unwrap().nodes, nodes);
        }
        assert_eq!(element_type(TET4).unwrap().dim(), 3);
        assert_eq!(element_type(15).unwrap().dim(), 0);
    }

    #[test]
    fn unknown_and_variable_size_types_are_absent() {
        for number in [0, 34, 35, 69, 133, 1000] {
            assert!(element_type(number).is_none(), "type {number}");
        }
    }

    #[test]
    fn types_read_in_words() {
        assert_eq!(describe_type(9), "a 6-node triangle");
        assert_eq!(describe_type(HEX8), "an 8-node hexahedron");
        assert_eq!(describe_type(10), "a 9-node quadrangle");
        assert_eq!(describe_type(18), "a 15-node prism");
        assert_eq!(describe_type(24), "a 15-node triangle (incomplete)");
        assert_eq!(describe_type(15), "a point");
        assert_eq!(describe_type(66), "an 11-node line");
        assert_eq!(describe_type(999), "an unknown element type");
    }
}
