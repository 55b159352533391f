//! The Abaqus solid element types seam reads: their cells, node orders and
//! face numbering.
//!
//! | Abaqus | seam / Gmsh | node order |
//! |---|---|---|
//! | C3D4 | Tet4 (4) | Gmsh's |
//! | C3D10 | Tet10 (11) | VTK's (Gmsh's with nodes 9 and 10 swapped) |
//! | C3D8 | Hex8 (5) | Gmsh's |
//! | C3D20 | Hex20 (17) | VTK's |
//! | C3D27 | Hex27 (12) | C3D20's, then the centre, then the centres of faces S1…S6 (Gmsh's writer) |
//! | C3D6 | Prism6 (6) | Gmsh's |
//! | C3D15 | Prism15 (18) | VTK's |
//!
//! Letters after the name (`R`, `I`, `H`, `M`, `T`, `S`: reduced
//! integration, incompatible modes, hybrid, modified, coupled temperature)
//! change the formulation, not the geometry: C3D8R is read as C3D8.
//!
//! Faces, from the Abaqus Analysis User's Guide ("three-dimensional solid
//! element library"), by corner nodes (1-based):
//!
//! | face | tetrahedron | hexahedron | wedge |
//! |---|---|---|---|
//! | S1 | 1-2-3 | 1-2-3-4 | 1-2-3 |
//! | S2 | 1-4-2 | 5-8-7-6 | 4-6-5 |
//! | S3 | 2-4-3 | 1-5-6-2 | 1-4-5-2 |
//! | S4 | 3-4-1 | 2-6-7-3 | 2-5-6-3 |
//! | S5 | | 3-7-8-4 | 3-6-4-1 |
//! | S6 | | 4-8-5-1 | |
//!
//! Each is matched once, by its corners, to the local face of seam's cell
//! ([`seam::CellType::faces`]), whose nodes (mid-edge and centre nodes
//! included) make the face element.

use seam::{CellKind, LocalFace, Shape};

/// A solid element type seam reads.
#[derive(Debug)]
pub(super) struct SolidType {
    /// The cell kind.
    pub kind: CellKind,
    /// Abaqus node `i` is node `gmsh_position[i]` of the Gmsh-ordered cell.
    pub gmsh_position: &'static [usize],
}

/// Hex27 as Gmsh writes C3D27: Hex20's nodes, then the centre (Gmsh's node
/// 26), then the centres of faces S1…S6 (Gmsh's 20, 25, 21, 23, 24, 22).
const C3D27_POSITIONS: [usize; 27] =
    [0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15, 26, 20, 25, 21, 23, 24, 22];

/// The solid types by node count.
fn solid(nodes: u32) -> Option<SolidType> {
    let kind = match nodes {
        4 => CellKind::Tet4,
        10 => CellKind::Tet10,
        8 => CellKind::Hex8,
        20 => CellKind::Hex20,
        27 => CellKind::Hex27,
        6 => CellKind::Prism6,
        15 => CellKind::Prism15,
        _ => return None,
    };
    // The Abaqus order of every type but C3D27 is VTK's, which seam's
    // catalogue gives as positions in Gmsh's order.
    let gmsh_position = match kind {
        CellKind::Hex27 => &C3D27_POSITIONS[..],
        _ => kind.info().vtk_order,
    };
    Some(SolidType { kind, gmsh_position })
}

/// The solid type of an Abaqus element type name (any case): `C3D` and a node
/// count seam reads, then any of the formulation letters.
pub(super) fn solid_type(name: &str) -> Option<SolidType> {
    let name = name.to_ascii_uppercase();
    let rest = name.strip_prefix("C3D")?;
    let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    let (count, letters) = rest.split_at(digits);
    if !letters.chars().all(|c| "RIHMTS".contains(c)) {
        return None;
    }
    solid(count.parse().ok()?)
}

/// The types seam reads, in words, for messages.
pub(super) const SUPPORTED: &str =
    "C3D4, C3D10, C3D8, C3D20, C3D27, C3D6, C3D15, also with the letters R, I, H, M, \
                                    T, S after them";

/// The corners (0-based) of faces S1, S2, … per shape.
const TET_FACES: [&[usize]; 4] = [&[0, 1, 2], &[0, 3, 1], &[1, 3, 2], &[2, 3, 0]];
const HEX_FACES: [&[usize]; 6] =
    [&[0, 1, 2, 3], &[4, 7, 6, 5], &[0, 4, 5, 1], &[1, 5, 6, 2], &[2, 6, 7, 3], &[3, 7, 4, 0]];
const WEDGE_FACES: [&[usize]; 5] = [&[0, 1, 2], &[3, 5, 4], &[0, 3, 4, 1], &[1, 4, 5, 2], &[2, 5, 3, 0]];

/// The Abaqus faces of a shape, by corners.
fn abaqus_faces(shape: Shape) -> &'static [&'static [usize]] {
    match shape {
        Shape::Tetrahedron => &TET_FACES,
        Shape::Hexahedron => &HEX_FACES,
        Shape::Prism => &WEDGE_FACES,
        _ => &[],
    }
}

/// The number of faces (S1…Sn) of a cell kind.
pub(super) fn n_faces(kind: CellKind) -> usize {
    abaqus_faces(kind.reference_shape()).len()
}

/// Face `S{face}` (1-based) of a cell kind as seam's local face.
pub(super) fn local_face(kind: CellKind, face: usize) -> Option<&'static LocalFace> {
    face_with_corners(kind, abaqus_faces(kind.reference_shape()).get(face.checked_sub(1)?)?)
}

/// The local face of a cell kind whose corners (0-based) are `corners`, in
/// any order.
pub(crate) fn face_with_corners(kind: CellKind, corners: &[usize]) -> Option<&'static LocalFace> {
    let mut wanted = corners.to_vec();
    wanted.sort_unstable();
    kind.info().faces.iter().find(|local| {
        let mut have = local.corners().to_vec();
        have.sort_unstable();
        have == wanted
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_with_formulation_letters_are_read() {
        for (name, kind) in [
            ("C3D8R", CellKind::Hex8),
            ("c3d10mh", CellKind::Tet10),
            ("C3D20RH", CellKind::Hex20),
            ("C3D15", CellKind::Prism15),
            ("C3D27", CellKind::Hex27),
            ("C3D4", CellKind::Tet4),
            ("C3D6T", CellKind::Prism6),
        ] {
            assert_eq!(solid_type(name).map(|t| t.kind), Some(kind), "{name}");
        }
        for name in ["C3D5", "S4R", "C3D8X", "DC3D8", "C3D", "C3D18", "CPS4"] {
            assert!(solid_type(name).is_none(), "{name}");
        }
    }

    /// Every Abaqus face is a face of seam's cell, and each is found once.
    #[test]
    fn every_face_maps_to_one_local_face() {
        for kind in [CellKind::Tet10, CellKind::Hex27, CellKind::Hex20, CellKind::Prism15, CellKind::Hex8] {
            let found: Vec<_> = (1..=n_faces(kind)).map(|f| local_face(kind, f).unwrap()).collect();
            assert_eq!(found.len(), kind.info().faces.len());
            for (i, a) in found.iter().enumerate() {
                assert!(found[i + 1..].iter().all(|b| a != b), "{kind:?}");
            }
            assert!(local_face(kind, 0).is_none() && local_face(kind, n_faces(kind) + 1).is_none());
        }
    }

    #[test]
    fn positions_are_permutations() {
        for n in [4, 10, 8, 20, 27, 6, 15] {
            let t = solid(n).unwrap();
            let mut p = t.gmsh_position.to_vec();
            p.sort_unstable();
            assert_eq!(p, (0..n as usize).collect::<Vec<_>>());
        }
    }
}
