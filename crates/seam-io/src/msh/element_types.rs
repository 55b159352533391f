//! The Gmsh element types: shape, number of nodes and a name in words.
//!
//! The table lists every fixed-size type Gmsh 4.15 knows (from
//! `gmsh.model.mesh.getElementProperties`); binary files need it to know how many
//! node tags follow an element tag, also of the types seam does not compute on.
//! Those it does are the kinds of seam's element catalogue
//! ([`seam::FaceKind::from_gmsh`], [`seam::CellKind::from_gmsh`]).

use seam::Shape::{self, *};

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
        self.shape.dim()
    }

    /// The type in words with its article: "a point", "a 6-node triangle",
    /// "an 8-node hexahedron".
    pub fn describe(&self) -> String {
        if self.shape == Point {
            return "a point".to_string();
        }
        let incomplete = if self.incomplete { " (incomplete)" } else { "" };
        format!("{} {}-node {}{incomplete}", article(self.nodes), self.nodes, self.shape.noun())
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

    /// The catalogue's Gmsh numbers name the types of its kinds' shapes and
    /// node counts.
    #[test]
    fn supported_types_have_their_node_counts() {
        let faces = seam::FaceKind::ALL.map(|k| (k.info().gmsh_type, k.info().shape, k.n_nodes()));
        let cells = seam::CellKind::ALL.map(|k| (k.info().gmsh_type, k.reference_shape(), k.n_nodes()));
        for (number, shape, nodes) in faces.into_iter().chain(cells).filter_map(|(t, s, n)| Some((t?, s, n)))
        {
            let t = element_type(number).unwrap();
            assert_eq!((t.shape, t.nodes, t.incomplete), (shape, nodes, false), "type {number}");
        }
        assert_eq!(element_type(4).unwrap().dim(), 3);
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
        assert_eq!(describe_type(5), "an 8-node hexahedron");
        assert_eq!(describe_type(10), "a 9-node quadrangle");
        assert_eq!(describe_type(18), "a 15-node prism");
        assert_eq!(describe_type(24), "a 15-node triangle (incomplete)");
        assert_eq!(describe_type(15), "a point");
        assert_eq!(describe_type(66), "an 11-node line");
        assert_eq!(describe_type(999), "an unknown element type");
    }
}
