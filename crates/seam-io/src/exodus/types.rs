//! The Exodus II element types seam reads: their cells and side numbering.
//!
//! | Exodus (`elem_type`, any case) | nodes | seam / Gmsh |
//! |---|---|---|
//! | TETRA, TETRA4, TET, TET4 | 4 | Tet4 (4) |
//! | TETRA10, TET10 | 10 | Tet10 (11) |
//! | HEX, HEX8, HEXAHEDRON | 8 | Hex8 (5) |
//! | HEX20 | 20 | Hex20 (17) |
//! | HEX27 | 27 | Hex27 (12) |
//! | WEDGE, WEDGE6 | 6 | Prism6 (6) |
//! | WEDGE15 | 15 | Prism15 (18) |
//! | WEDGE18 | 18 | Prism18 (13) |
//! | PYRAMID, PYRAMID5, PYRA5 | 5 | Pyramid5 (7) |
//! | PYRAMID13 | 13 | Pyramid13 (19) |
//! | PYRAMID14 | 14 | Pyramid14 (14) |
//!
//! TETRA14/15, WEDGE21 and PYRAMID18/19 are refused by name: the SEACAS
//! library does not say where their face-centre nodes are.
//!
//! The corners are numbered as in Gmsh. Sides and the places of the other
//! nodes come from one table, [`SEACAS_SIDES`]: the nodes of each side as
//! the SEACAS Exodus library's `ex_get_side_set_node_list` (libexodusII
//! 6.02, Debian's `libexodusii-dev`) gives them, printed by
//! `tests/data/exodus/exo_write.c` into `tests/data/exodus/sides.txt`, which
//! a test compares with this table. A side lists its corners outward
//! (counter-clockwise seen from outside), then the node on the edge from
//! corner `j` to corner `j + 1` for each `j`, then (HEX27) the face centre.
//! So every mid-edge node is placed by the corners of its edge, every face
//! centre by its side, and the one node left (HEX27's centre, PYRAMID14's
//! base centre, which the library leaves out of side 5) is the one Gmsh
//! node left. The library lists no face centre of WEDGE18: its nodes 16, 17
//! and 18 are those of sides 1, 2 and 3, as [`FACE_CENTRES`] says after
//! SEACAS's IOSS (`Ioss_Wedge18.C`) and libMesh's Prism18. By corners (1-based), as in the Exodus II manual:
//!
//! | side | tetrahedron | hexahedron | wedge | pyramid |
//! |---|---|---|---|---|
//! | 1 | 1-2-4 | 1-2-6-5 | 1-2-5-4 | 1-2-5 |
//! | 2 | 2-3-4 | 2-3-7-6 | 2-3-6-5 | 2-3-5 |
//! | 3 | 1-4-3 | 3-4-8-7 | 1-4-6-3 | 3-4-5 |
//! | 4 | 1-3-2 | 1-5-8-4 | 1-3-2 | 1-5-4 |
//! | 5 | | 1-4-3-2 | 4-5-6 | 1-4-3-2 |
//! | 6 | | 5-6-7-8 | | |
//!
//! Each side is matched once, by its corners, to the local face of seam's
//! cell ([`seam::CellType::faces`]), which is oriented out of the cell.

use seam::{CellKind, LocalFace, Shape};

/// What an `elem_type` with a node count is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ExodusType {
    /// A solid seam reads.
    Solid(CellKind),
    /// A higher-order solid whose node order is not known.
    Unverified,
    /// Anything else (shells, beams, 2D types, unknown names).
    Other,
}

/// The type of a block: its `elem_type` and nodes per element.
pub(crate) fn exodus_type(name: &str, nodes: usize) -> ExodusType {
    let upper = name.trim().to_ascii_uppercase();
    let base = upper.trim_end_matches(|c: char| c.is_ascii_digit());
    let digits = &upper[base.len()..];
    if !digits.is_empty() && digits.parse::<usize>().ok() != Some(nodes) {
        return ExodusType::Other;
    }
    let kind = match (base, nodes) {
        ("TETRA" | "TET", 4) => CellKind::Tet4,
        ("TETRA" | "TET", 10) => CellKind::Tet10,
        ("HEX" | "HEXAHEDRON", 8) => CellKind::Hex8,
        ("HEX" | "HEXAHEDRON", 20) => CellKind::Hex20,
        ("HEX" | "HEXAHEDRON", 27) => CellKind::Hex27,
        ("WEDGE", 6) => CellKind::Prism6,
        ("WEDGE", 15) => CellKind::Prism15,
        ("WEDGE", 18) => CellKind::Prism18,
        ("PYRAMID" | "PYRA", 5) => CellKind::Pyramid5,
        ("PYRAMID" | "PYRA", 13) => CellKind::Pyramid13,
        ("PYRAMID" | "PYRA", 14) => CellKind::Pyramid14,
        ("TETRA" | "TET", 11 | 14 | 15) | ("WEDGE", 21) | ("PYRAMID" | "PYRA", 18 | 19) => {
            return ExodusType::Unverified
        }
        _ => return ExodusType::Other,
    };
    ExodusType::Solid(kind)
}

/// The kinds seam reads from Exodus files.
#[cfg(test)]
const READ: [CellKind; 11] = [
    CellKind::Tet4,
    CellKind::Tet10,
    CellKind::Hex8,
    CellKind::Hex20,
    CellKind::Hex27,
    CellKind::Prism6,
    CellKind::Prism15,
    CellKind::Prism18,
    CellKind::Pyramid5,
    CellKind::Pyramid13,
    CellKind::Pyramid14,
];

/// The types seam reads, in words, for messages.
pub(crate) const SUPPORTED: &str =
    "TETRA4, TETRA10, HEX8, HEX20, HEX27, WEDGE6, WEDGE15, WEDGE18, PYRAMID5, PYRAMID13, PYRAMID14";

/// The nodes (1-based) of sides 1, 2, … of the largest type of each shape
/// seam reads, as SEACAS's `ex_get_side_set_node_list` lists them
/// (`tests/data/exodus/sides.txt`): TETRA10, HEX27, WEDGE15, PYRAMID13. A
/// smaller type of the shape uses the nodes it has (HEX20: the first 8 of
/// each HEX27 side; first-order types: the corners).
pub(crate) const SEACAS_SIDES: [(Shape, &[&[usize]]); 4] = [
    (
        Shape::Tetrahedron,
        &[&[1, 2, 4, 5, 9, 8], &[2, 3, 4, 6, 10, 9], &[1, 4, 3, 8, 10, 7], &[1, 3, 2, 7, 6, 5]],
    ),
    (
        Shape::Hexahedron,
        &[
            &[1, 2, 6, 5, 9, 14, 17, 13, 26],
            &[2, 3, 7, 6, 10, 15, 18, 14, 25],
            &[3, 4, 8, 7, 11, 16, 19, 15, 27],
            &[1, 5, 8, 4, 13, 20, 16, 12, 24],
            &[1, 4, 3, 2, 12, 11, 10, 9, 22],
            &[5, 6, 7, 8, 17, 18, 19, 20, 23],
        ],
    ),
    (
        Shape::Prism,
        &[
            &[1, 2, 5, 4, 7, 11, 13, 10],
            &[2, 3, 6, 5, 8, 12, 14, 11],
            &[1, 4, 6, 3, 10, 15, 12, 9],
            &[1, 3, 2, 9, 8, 7],
            &[4, 5, 6, 13, 14, 15],
        ],
    ),
    (
        Shape::Pyramid,
        &[
            &[1, 2, 5, 6, 11, 10],
            &[2, 3, 5, 7, 12, 11],
            &[3, 4, 5, 8, 13, 12],
            &[1, 5, 4, 10, 13, 9],
            &[1, 4, 3, 2, 9, 8, 7, 6],
        ],
    ),
];

/// The face-centre nodes the library's side lists leave out, as (side,
/// node), both 1-based: WEDGE18's, as SEACAS's IOSS places them
/// (`Ioss_Wedge18.C`, `face_node_order`) and libMesh's Prism18 does.
pub(crate) const FACE_CENTRES: [(CellKind, &[(usize, usize)]); 1] =
    [(CellKind::Prism18, &[(1, 16), (2, 17), (3, 18)])];

/// The sides of a shape, each as its node list (1-based).
fn seacas_sides(shape: Shape) -> &'static [&'static [usize]] {
    SEACAS_SIDES.iter().find(|(s, _)| *s == shape).map_or(&[], |(_, sides)| sides)
}

/// Exodus node `i` (0-based) of a cell kind is node `gmsh_positions(kind)[i]`
/// of the Gmsh-ordered cell: corners in place, every mid-edge node at
/// Gmsh's node of the same edge, every face centre at the centre of seam's
/// local face of that side, and the one node left at the one left.
pub(crate) fn gmsh_positions(kind: CellKind) -> Vec<usize> {
    let info = kind.info();
    let n = info.nodes.len();
    let corners = info.corners;
    let mut position: Vec<Option<usize>> = (0..n).map(|i| (i < corners).then_some(i)).collect();
    for (k, side) in seacas_sides(info.shape).iter().enumerate() {
        let nc = n_corners(side);
        let c: Vec<usize> = side[..nc].iter().map(|&v| v - 1).collect();
        for (j, &node) in side.iter().enumerate().skip(nc) {
            let node = node - 1;
            if node >= n {
                continue;
            }
            let gmsh = if j < 2 * nc {
                let (a, b) = (c[j - nc], c[(j - nc + 1) % nc]);
                let edge = [a.min(b), a.max(b)];
                info.edges.iter().position(|e| *e == edge).map(|e| corners + e)
            } else {
                local_face(kind, k + 1).and_then(|f| f.nodes().get(8).copied())
            };
            position[node] = gmsh;
        }
    }
    let centres = FACE_CENTRES.iter().filter(|(k, _)| *k == kind).flat_map(|(_, c)| c.iter());
    for &(side, node) in centres {
        position[node - 1] = local_face(kind, side).and_then(|f| f.nodes().get(8).copied());
    }
    let used: Vec<usize> = position.iter().flatten().copied().collect();
    let left: Vec<usize> = (0..n).filter(|g| !used.contains(g)).collect();
    let mut left = left.into_iter();
    position.into_iter().map(|p| p.or_else(|| left.next()).expect("a node for every place")).collect()
}

/// The corners (1-based) of a side's node list: 3 for a triangle (3 or 6
/// nodes), else 4.
fn n_corners(side: &[usize]) -> usize {
    if matches!(side.len(), 3 | 6) {
        3
    } else {
        4
    }
}

/// The number of sides of a cell kind.
pub(crate) fn n_sides(kind: CellKind) -> usize {
    seacas_sides(kind.reference_shape()).len()
}

/// Side `side` (1-based) of a cell kind as seam's local face.
pub(crate) fn local_face(kind: CellKind, side: usize) -> Option<&'static LocalFace> {
    let nodes = seacas_sides(kind.reference_shape()).get(side.checked_sub(1)?)?;
    let corners: Vec<usize> = nodes[..n_corners(nodes)].iter().map(|&c| c - 1).collect();
    crate::abaqus::face_with_corners(kind, &corners)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_node_counts() {
        for (name, n, t) in [
            ("HEX8", 8, ExodusType::Solid(CellKind::Hex8)),
            ("hex", 8, ExodusType::Solid(CellKind::Hex8)),
            ("HEXAHEDRON", 8, ExodusType::Solid(CellKind::Hex8)),
            ("TETRA", 4, ExodusType::Solid(CellKind::Tet4)),
            ("tet4", 4, ExodusType::Solid(CellKind::Tet4)),
            ("WEDGE6", 6, ExodusType::Solid(CellKind::Prism6)),
            ("PYRAMID", 5, ExodusType::Solid(CellKind::Pyramid5)),
            ("HEX20", 20, ExodusType::Solid(CellKind::Hex20)),
            ("TETRA10", 10, ExodusType::Solid(CellKind::Tet10)),
            ("WEDGE18", 18, ExodusType::Solid(CellKind::Prism18)),
            ("WEDGE21", 21, ExodusType::Unverified),
            ("HEX8", 20, ExodusType::Other),
            ("SHELL4", 4, ExodusType::Other),
            ("QUAD4", 4, ExodusType::Other),
        ] {
            assert_eq!(exodus_type(name, n), t, "{name} {n}");
        }
    }

    #[test]
    fn positions_are_permutations() {
        for kind in READ {
            let p = gmsh_positions(kind);
            let mut sorted = p.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..kind.info().nodes.len()).collect::<Vec<_>>(), "{kind:?}");
        }
        // HEX20: Exodus's 13–16 are the vertical edges, 17–20 the top ones.
        let hex20 = gmsh_positions(CellKind::Hex20);
        assert_eq!(&hex20[8..], &[8, 11, 13, 9, 10, 12, 14, 15, 16, 18, 19, 17]);
        // WEDGE18's face centres on sides 1, 2, 3 (faces 0-1-4-3, 1-2-5-4,
        // 0-3-5-2) are Gmsh's 15, 17, 16.
        assert_eq!(&gmsh_positions(CellKind::Prism18)[15..], &[15, 17, 16]);
        // TETRA10 is VTK's order.
        assert_eq!(gmsh_positions(CellKind::Tet10), CellKind::Tet10.info().vtk_order);
    }

    /// The table is the library's output (sides.txt, make_fixtures.py).
    #[test]
    fn the_side_table_is_the_librarys() {
        let text = include_str!("../../tests/data/exodus/sides.txt");
        for (name, shape) in [
            ("TETRA10", Shape::Tetrahedron),
            ("HEX27", Shape::Hexahedron),
            ("WEDGE15", Shape::Prism),
            ("PYRAMID13", Shape::Pyramid),
        ] {
            let listed: Vec<Vec<usize>> = text
                .lines()
                .filter_map(|l| l.strip_prefix(name)?.strip_prefix(' '))
                .map(|l| {
                    l.split_once(':').unwrap().1.split_whitespace().map(|v| v.parse().unwrap()).collect()
                })
                .collect();
            let table: Vec<Vec<usize>> = seacas_sides(shape).iter().map(|s| s.to_vec()).collect();
            assert_eq!(listed, table, "{name}");
        }
    }

    /// Every side is one local face of seam's cell, each found once.
    #[test]
    fn every_side_maps_to_one_local_face() {
        for kind in READ {
            let found: Vec<_> = (1..=n_sides(kind)).map(|f| local_face(kind, f).unwrap()).collect();
            assert_eq!(found.len(), kind.info().faces.len());
            for (i, a) in found.iter().enumerate() {
                assert!(found[i + 1..].iter().all(|b| a != b), "{kind:?}");
            }
            assert!(local_face(kind, 0).is_none() && local_face(kind, n_sides(kind) + 1).is_none());
        }
    }
}
