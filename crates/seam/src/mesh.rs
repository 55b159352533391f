//! Plain mesh data: surface meshes of Tri3/Quad4 faces and their second-order
//! versions Tri6/Quad8/Quad9, and volume meshes of Tet4/Hex8/Prism6/Pyramid5
//! cells and their second-order versions (Tet10, Hex20/27, Prism15/18,
//! Pyramid13/14), with extraction of outward boundary faces.
//!
//! # Storage
//!
//! A [`SurfaceMesh`] is a point array and a face array; faces refer to points by
//! 0-based index. Points that no face uses are allowed and kept, so that matrix rows
//! and columns can follow the numbering of the file a mesh came from.
//!
//! ```text
//! points: [p0, p1, p2, p3, p4, p5]          faces: [Quad4([0, 1, 4, 3]),
//!                                                    Tri3([1, 2, 4])]
//!   3 ---- 4                                  corners listed counter-clockwise
//!   |  q0  | \   t1                            seen from the side the normal
//!   0 ---- 1 - 2                               points to (right-hand rule)
//! ```
//!
//! Quads are bilinear surface patches and may be warped (non-planar); seam never
//! splits or flattens them.

use rayon::prelude::*;

pub use crate::catalogue::{Cell, Face};

/// A point or vector in 3D space.
pub type Point3 = [f64; 3];

/// What is wrong with a mesh; the payload locates it (0-based face, cell or node).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// A point coordinate is NaN or infinite.
    #[error("node {node} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// The point index.
        node: usize,
    },
    /// A point coordinate is finite but beyond [`MAX_MAGNITUDE`]: areas and
    /// Jacobians computed from it would overflow.
    #[error("node {node} has coordinate {value:e}, out of range (|x| ≤ {MAX_MAGNITUDE:e})")]
    CoordinateOutOfRange {
        /// The point index.
        node: usize,
        /// The coordinate.
        value: f64,
    },
    /// A face or cell refers to a point that does not exist.
    #[error("{what} {element} corner {corner} refers to node {index}, but there are only {n_nodes} nodes")]
    IndexOutOfRange {
        /// "face" or "cell".
        what: &'static str,
        /// The face or cell index.
        element: usize,
        /// The corner position within the element.
        corner: usize,
        /// The offending point index.
        index: usize,
        /// The number of points.
        n_nodes: usize,
    },
    /// A face or cell lists the same point twice.
    #[error("{what} {element} is degenerate: node {node} appears twice")]
    RepeatedNode {
        /// "face" or "cell".
        what: &'static str,
        /// The face or cell index.
        element: usize,
        /// The repeated point index.
        node: usize,
    },
    /// A face has (numerically) zero area.
    #[error("face {face} is degenerate: its area is zero")]
    ZeroArea {
        /// The face index.
        face: usize,
    },
    /// A face is smaller than [`MIN_FACE_SIZE`]: its area and quadrature
    /// weights would underflow.
    #[error("face {face} has diameter {diameter:.3e}, below the smallest size seam computes with ({MIN_FACE_SIZE:e})")]
    TooSmall {
        /// The face index.
        face: usize,
        /// Its diameter (largest corner distance).
        diameter: f64,
    },
    /// A boundary face of a cell (a face no other cell shares) is degenerate or
    /// too small, so the cell is.
    #[error("cell {cell} is degenerate: its boundary face {local_face} {why}")]
    DegenerateCellFace {
        /// The cell index.
        cell: usize,
        /// The face within the cell ([`CellType::faces`](crate::CellType::faces) order).
        local_face: usize,
        /// Why the face is degenerate: "has zero area", "is too small".
        why: &'static str,
    },
    /// A mesh has no faces at all.
    #[error("the mesh has no faces")]
    Empty,
}

impl MeshError {
    /// The face or cell index the error is about, if any.
    pub fn element(&self) -> Option<usize> {
        match *self {
            MeshError::IndexOutOfRange { element, .. } => Some(element),
            MeshError::RepeatedNode { element, .. } => Some(element),
            MeshError::ZeroArea { face } | MeshError::TooSmall { face, .. } => Some(face),
            MeshError::DegenerateCellFace { cell, .. } => Some(cell),
            MeshError::NonFiniteCoordinate { .. }
            | MeshError::CoordinateOutOfRange { .. }
            | MeshError::Empty => None,
        }
    }
}

/// A surface mesh of Tri3, Quad4, Tri6, Quad8, Quad9 and Tri7 faces, possibly mixed.
///
/// # Invariants (checked by [`SurfaceMesh::new`])
/// - every coordinate is finite, of magnitude at most [`MAX_MAGNITUDE`];
/// - every corner index is `< points.len()`;
/// - no face repeats a corner;
/// - no face has zero area (relative to its size, see [`ZERO_AREA_RTOL`]) or a
///   diameter below [`MIN_FACE_SIZE`];
/// - at least one face.
///
/// Consistent orientation of neighbouring faces is *not* required.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceMesh {
    points: Vec<Point3>,
    faces: Vec<Face>,
}

/// A face counts as zero-area when `area < ZERO_AREA_RTOL · diameter²`.
pub const ZERO_AREA_RTOL: f64 = 1e-12;

/// The largest coordinate magnitude a mesh may have (and, in `seam-fem`, the
/// largest modulus, load or prescribed value): products of four such numbers,
/// as in squared areas and Jacobian determinants, stay far from overflow.
pub const MAX_MAGNITUDE: f64 = 1e50;

/// The smallest face diameter: squared areas of faces this small stay far
/// from underflow.
pub const MIN_FACE_SIZE: f64 = 1e-50;

impl SurfaceMesh {
    /// Builds a mesh after checking the invariants listed on the type.
    ///
    /// # Errors
    /// The first violated invariant, as a [`MeshError`] naming the node or face.
    pub fn new(points: Vec<Point3>, faces: Vec<Face>) -> Result<Self, MeshError> {
        let mesh = SurfaceMesh { points, faces };
        mesh.check()?;
        Ok(mesh)
    }

    /// A mesh of faces taken from a valid mesh (their shapes are checked
    /// there): only the node indices are checked, not the shapes.
    pub(crate) fn from_valid_faces(points: Vec<Point3>, faces: Vec<Face>) -> Result<Self, MeshError> {
        for (f, face) in faces.iter().enumerate() {
            check_element("face", f, face.nodes(), points.len())?;
        }
        match faces.is_empty() {
            true => Err(MeshError::Empty),
            false => Ok(SurfaceMesh { points, faces }),
        }
    }

    /// Checks the invariants; returns the first violation.
    ///
    /// # Errors
    /// See [`SurfaceMesh::new`].
    pub fn check(&self) -> Result<(), MeshError> {
        check_points(&self.points)?;
        if self.faces.is_empty() {
            return Err(MeshError::Empty);
        }
        for (f, face) in self.faces.iter().enumerate() {
            check_element("face", f, face.nodes(), self.points.len())?;
            check_face_shape(&self.corners(f)[..face.n_corners()], f)?;
        }
        Ok(())
    }

    /// The enriched slave space of dual multipliers on quadratic faces
    /// (Lamichhane, Stevenson and Wohlmuth, Numer. Math. 102 (2005)): every
    /// Tri6 becomes a Tri7 and every Quad8 a Quad9 through a new point at the
    /// image x(ξ_c) of its reference centre, appended after the points in face
    /// order; other faces stay. The maps are unchanged (Tri7 and Quad9
    /// interpolate a Tri6 and a Quad8 map exactly), the basis gains the face
    /// bubble. On it every shape function has a positive integral and, on a
    /// flat affine face, its weighted centroid at its node, so the dual basis
    /// contains the linear functions, which the Popp transformation of Tri6 and
    /// Quad8 faces cannot give ([`crate::BASIS_ALPHA`]). Returns the mesh and,
    /// per new point, the face it enriches.
    pub fn enriched(&self) -> (SurfaceMesh, Vec<usize>) {
        let mut points = self.points.clone();
        let mut owners = Vec::new();
        let faces = self
            .faces
            .iter()
            .enumerate()
            .map(|(f, face)| {
                let Some(larger) = face.kind().info().enriched else { return *face };
                let centre = crate::curved::CurvedFace::of(self, f).map(face.kind().centre());
                let nodes: Vec<usize> = face.nodes().iter().copied().chain([points.len()]).collect();
                points.push(centre);
                owners.push(f);
                Face::new(larger, &nodes).expect("one node more than the face")
            })
            .collect();
        (SurfaceMesh { points, faces }, owners)
    }

    /// All points, including those no face uses.
    pub fn points(&self) -> &[Point3] {
        &self.points
    }

    /// All faces.
    pub fn faces(&self) -> &[Face] {
        &self.faces
    }

    /// Number of points.
    pub fn n_points(&self) -> usize {
        self.points.len()
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.faces.len()
    }

    /// Corner coordinates of face `f`; a triangle leaves the fourth entry as its third.
    pub fn corners(&self, f: usize) -> [Point3; 4] {
        let n = self.faces[f].corner_nodes();
        let p = |i: usize| self.points[n[i.min(n.len() - 1)]];
        [p(0), p(1), p(2), p(3)]
    }

    /// Which points some face uses (`true`) and which are off the surface.
    pub fn used_points(&self) -> Vec<bool> {
        used_points(self.points.len(), self.faces.iter().map(Face::nodes))
    }

    /// Consumes the mesh, returning its points and faces.
    pub fn into_parts(self) -> (Vec<Point3>, Vec<Face>) {
        (self.points, self.faces)
    }
}

/// A volume mesh of first- and second-order cells ([`Cell`]), possibly mixed.
///
/// # Invariants (checked by [`VolumeMesh::new`])
/// finite coordinates of magnitude at most [`MAX_MAGNITUDE`], corner indices in
/// range, no repeated corner in a cell.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeMesh {
    points: Vec<Point3>,
    cells: Vec<Cell>,
}

impl VolumeMesh {
    /// Builds a volume mesh after checking its invariants.
    ///
    /// # Errors
    /// The first violated invariant, naming the node or cell.
    pub fn new(points: Vec<Point3>, cells: Vec<Cell>) -> Result<Self, MeshError> {
        check_points(&points)?;
        for (c, cell) in cells.iter().enumerate() {
            check_element("cell", c, cell.nodes(), points.len())?;
        }
        Ok(VolumeMesh { points, cells })
    }

    /// All points.
    pub fn points(&self) -> &[Point3] {
        &self.points
    }

    /// All cells.
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// Which points some cell uses (`true`); the others (nodes of a file's
    /// other volumes, say) carry no unknowns.
    pub fn used_points(&self) -> Vec<bool> {
        used_points(self.points.len(), self.cells.iter().map(Cell::nodes))
    }

    /// The boundary: every cell face that belongs to exactly one cell, oriented
    /// with its normal pointing out of that cell. Points keep their numbering.
    ///
    /// # Errors
    /// [`MeshError::Empty`] if the boundary is empty;
    /// [`MeshError::DegenerateCellFace`] naming the cell of a degenerate face.
    pub fn boundary(&self) -> Result<SurfaceMesh, MeshError> {
        let faces = self.cell_faces();
        let mut boundary: Vec<(usize, usize, Face)> = Vec::new();
        for run in faces.chunk_by(|a, b| a.key == b.key) {
            if let [only] = run {
                boundary.push((only.cell, only.local, only.face));
            }
        }
        boundary.sort_unstable_by_key(|&(c, l, _)| (c, l));
        for &(cell, local_face, face) in &boundary {
            let corners: Vec<Point3> = face.corner_nodes().iter().map(|&i| self.points[i]).collect();
            if let Err(e) = check_face_shape(&corners, 0) {
                let why =
                    if matches!(e, MeshError::TooSmall { .. }) { "is too small" } else { "has zero area" };
                return Err(MeshError::DegenerateCellFace { cell, local_face, why });
            }
        }
        let faces = boundary.into_iter().map(|(c, _, f)| self.outward(f, c)).collect();
        SurfaceMesh::new(self.points.clone(), faces)
    }

    /// Orients the given faces (for example a physical surface) outward with
    /// respect to the one cell each belongs to. A face that belongs to no cell, or
    /// to two cells (an interior face), keeps the orientation it was given
    /// ([`VolumeMesh::face_owners`] tells which).
    ///
    /// # Errors
    /// [`MeshError`] if the faces are empty, out of range or degenerate.
    pub fn orient_outward(&self, faces: &[Face]) -> Result<SurfaceMesh, MeshError> {
        self.orient_outward_of(faces, &self.face_owners(faces))
    }

    /// [`VolumeMesh::orient_outward`] with the faces' owners known.
    ///
    /// # Errors
    /// As [`VolumeMesh::orient_outward`].
    pub fn orient_outward_of(&self, faces: &[Face], owners: &[FaceOwner]) -> Result<SurfaceMesh, MeshError> {
        let oriented = faces
            .iter()
            .zip(owners)
            .map(|(f, &owner)| match owner {
                FaceOwner::Cell(cell) => self.outward(*f, cell),
                FaceOwner::NoCell | FaceOwner::Interior => *f,
            })
            .collect();
        SurfaceMesh::new(self.points.clone(), oriented)
    }

    /// Which cell each of `faces` is a face of (by its corner nodes).
    pub fn face_owners(&self, faces: &[Face]) -> Vec<FaceOwner> {
        let all = self.cell_faces();
        faces
            .iter()
            .map(|f| {
                let key = face_key(f.corner_nodes());
                let start = all.partition_point(|e| e.key < key);
                match &all[start..] {
                    [first, rest @ ..] if first.key == key => match rest.first() {
                        Some(second) if second.key == key => FaceOwner::Interior,
                        _ => FaceOwner::Cell(first.cell),
                    },
                    _ => FaceOwner::NoCell,
                }
            })
            .collect()
    }

    /// Every face of every cell, sorted by its node set (then cell, local face):
    /// a face shared by two cells appears as a run of two.
    ///
    /// # Performance
    /// O(F log F) for F cell faces, a parallel sort; deterministic.
    fn cell_faces(&self) -> Vec<CellFace> {
        let mut faces: Vec<CellFace> = self
            .cells
            .par_iter()
            .enumerate()
            .flat_map_iter(|(c, cell)| {
                cell.faces().enumerate().map(move |(l, face)| CellFace {
                    key: face_key(face.corner_nodes()),
                    cell: c,
                    local: l,
                    face,
                })
            })
            .collect();
        faces.par_sort_unstable_by_key(|e| (e.key, e.cell, e.local));
        faces
    }

    /// `face` flipped if needed so that its normal points away from the centroid
    /// of `cell` (a geometric test, independent of the cell's node order).
    fn outward(&self, face: Face, cell: usize) -> Face {
        let cn = self.cells[cell].corner_nodes();
        let centre = centroid(cn.iter().map(|&i| self.points[i]));
        let fc: Vec<Point3> = face.corner_nodes().iter().map(|&i| self.points[i]).collect();
        let normal = area_vector(&fc);
        let out = sub(centroid(fc.iter().copied()), centre);
        if dot(normal, out) < 0.0 {
            face.reversed()
        } else {
            face
        }
    }
}

/// Which cells a face is a face of ([`VolumeMesh::face_owners`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceOwner {
    /// Exactly one cell, this one: a boundary face.
    Cell(usize),
    /// No cell has a face with these corners.
    NoCell,
    /// Two cells: a face inside the mesh.
    Interior,
}

struct CellFace {
    key: [usize; 4],
    cell: usize,
    local: usize,
    face: Face,
}

/// Sorted corner list, padded with `usize::MAX`: equal for a face and its reverse.
fn face_key(nodes: &[usize]) -> [usize; 4] {
    let mut k = [usize::MAX; 4];
    k[..nodes.len()].copy_from_slice(nodes);
    k.sort_unstable();
    k
}

fn check_points(points: &[Point3]) -> Result<(), MeshError> {
    for (node, p) in points.iter().enumerate() {
        for &value in p {
            if !value.is_finite() {
                return Err(MeshError::NonFiniteCoordinate { node });
            }
            if value.abs() > MAX_MAGNITUDE {
                return Err(MeshError::CoordinateOutOfRange { node, value });
            }
        }
    }
    Ok(())
}

/// Whether a face of corners `c` (3 or 4, finite and in range) passes the
/// shape checks of [`SurfaceMesh::new`]: not smaller than [`MIN_FACE_SIZE`], not
/// of zero area (relative to its size, [`ZERO_AREA_RTOL`]).
pub fn is_proper_face(c: &[Point3]) -> bool {
    check_face_shape(c, 0).is_ok()
}

/// A face of corners `c` (3 or 4, finite and in range) is neither too small
/// nor of zero area; `f` names it in the error.
fn check_face_shape(c: &[Point3], f: usize) -> Result<(), MeshError> {
    let diam = diameter(c);
    if diam < MIN_FACE_SIZE {
        return Err(MeshError::TooSmall { face: f, diameter: diam });
    }
    let area = face_area_estimate(c);
    if area.is_nan() || area <= ZERO_AREA_RTOL * diam * diam {
        return Err(MeshError::ZeroArea { face: f });
    }
    Ok(())
}

fn check_element(what: &'static str, e: usize, nodes: &[usize], n_nodes: usize) -> Result<(), MeshError> {
    for (corner, &index) in nodes.iter().enumerate() {
        if index >= n_nodes {
            return Err(MeshError::IndexOutOfRange { what, element: e, corner, index, n_nodes });
        }
        if nodes[..corner].contains(&index) {
            return Err(MeshError::RepeatedNode { what, element: e, node: index });
        }
    }
    Ok(())
}

/// Per point of `n`, whether one of `elements` (node lists) uses it.
fn used_points<'a>(n: usize, elements: impl Iterator<Item = &'a [usize]>) -> Vec<bool> {
    let mut used = vec![false; n];
    for &p in elements.flatten() {
        used[p] = true;
    }
    used
}

/// Vector area ½ Σ x_i × x_{i+1} of a closed polygon (exact for planar polygons;
/// for a warped quad, the area vector of its bilinear surface).
pub fn area_vector(c: &[Point3]) -> Point3 {
    let mut a = [0.0; 3];
    for i in 0..c.len() {
        let x = cross(c[i], c[(i + 1) % c.len()]);
        a = [a[0] + 0.5 * x[0], a[1] + 0.5 * x[1], a[2] + 0.5 * x[2]];
    }
    a
}

fn face_area_estimate(c: &[Point3]) -> f64 {
    // The area of a bilinear quad is ≥ |area vector|; both vanish together only
    // for degenerate faces, which is all this test needs.
    norm(area_vector(c))
}

fn diameter(c: &[Point3]) -> f64 {
    let mut d: f64 = 0.0;
    for i in 0..c.len() {
        for j in i + 1..c.len() {
            d = d.max(norm(sub(c[i], c[j])));
        }
    }
    d
}

fn centroid(points: impl Iterator<Item = Point3>) -> Point3 {
    let (mut s, mut n) = ([0.0; 3], 0.0);
    for p in points {
        s = [s[0] + p[0], s[1] + p[1], s[2] + p[2]];
        n += 1.0;
    }
    [s[0] / n, s[1] / n, s[2] / n]
}

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: Point3, b: Point3) -> Point3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn norm(a: Point3) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_cube() -> VolumeMesh {
        let p = vec![
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0., 0., 1.],
            [1., 0., 1.],
            [1., 1., 1.],
            [0., 1., 1.],
        ];
        VolumeMesh::new(p, vec![Cell::Hex8([0, 1, 2, 3, 4, 5, 6, 7])]).unwrap()
    }

    fn outward_normals_point_away(surface: &SurfaceMesh, centre: Point3) {
        for f in 0..surface.n_faces() {
            let c = surface.corners(f);
            let n = surface.faces()[f].len();
            let a = area_vector(&c[..n]);
            let out = sub(centroid(c[..n].iter().copied()), centre);
            assert!(dot(a, out) > 0.0, "face {f} points inward");
        }
    }

    #[test]
    fn hex_boundary_is_six_outward_quads() {
        let b = unit_cube().boundary().unwrap();
        assert_eq!(b.n_faces(), 6);
        outward_normals_point_away(&b, [0.5; 3]);
    }

    #[test]
    fn inverted_cells_still_give_outward_faces() {
        // A tet with negative orientation, a prism and a pyramid.
        let p = vec![[0., 0., 0.], [0., 1., 0.], [1., 0., 0.], [0., 0., 1.]];
        let tet = VolumeMesh::new(p, vec![Cell::Tet4([0, 1, 2, 3])]).unwrap();
        outward_normals_point_away(&tet.boundary().unwrap(), [0.25; 3]);
        let p = vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.], [1., 0., 1.], [0., 1., 1.]];
        let prism = VolumeMesh::new(p, vec![Cell::Prism6([0, 1, 2, 3, 4, 5])]).unwrap();
        let b = prism.boundary().unwrap();
        assert_eq!(b.n_faces(), 5);
        outward_normals_point_away(&b, [1. / 3., 1. / 3., 0.5]);
        let p = vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [0.5, 0.5, 1.]];
        let pyr = VolumeMesh::new(p, vec![Cell::Pyramid5([0, 1, 2, 3, 4])]).unwrap();
        let b = pyr.boundary().unwrap();
        assert_eq!(b.n_faces(), 5);
        outward_normals_point_away(&b, [0.5, 0.5, 0.25]);
    }

    #[test]
    fn shared_faces_are_not_boundary() {
        // Two hexes stacked: 10 boundary faces, the shared one is interior.
        let mut p = unit_cube().points().to_vec();
        p.extend([[0., 0., 2.], [1., 0., 2.], [1., 1., 2.], [0., 1., 2.]]);
        let cells = vec![Cell::Hex8([0, 1, 2, 3, 4, 5, 6, 7]), Cell::Hex8([4, 5, 6, 7, 8, 9, 10, 11])];
        let b = VolumeMesh::new(p, cells).unwrap().boundary().unwrap();
        assert_eq!(b.n_faces(), 10);
        outward_normals_point_away(&b, [0.5, 0.5, 1.0]);
    }

    #[test]
    fn orient_outward_flips_an_inward_face() {
        let cube = unit_cube();
        let s = cube.orient_outward(&[Face::Quad4([4, 7, 6, 5])]).unwrap();
        assert_eq!(s.faces()[0], Face::Quad4([4, 5, 6, 7]));
    }

    #[test]
    fn invalid_meshes_name_the_culprit() {
        let p = vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]];
        let e = SurfaceMesh::new(p.clone(), vec![Face::Tri3([0, 1, 3])]).unwrap_err();
        assert!(matches!(e, MeshError::IndexOutOfRange { element: 0, corner: 2, index: 3, .. }));
        let e = SurfaceMesh::new(p.clone(), vec![Face::Tri3([0, 1, 1])]).unwrap_err();
        assert_eq!(e, MeshError::RepeatedNode { what: "face", element: 0, node: 1 });
        let collinear = vec![[0., 0., 0.], [1., 0., 0.], [2., 0., 0.]];
        let e = SurfaceMesh::new(collinear, vec![Face::Tri3([0, 1, 2])]).unwrap_err();
        assert_eq!(e, MeshError::ZeroArea { face: 0 });
        let mut nan = p;
        nan[2][1] = f64::NAN;
        let e = SurfaceMesh::new(nan.clone(), vec![Face::Tri3([0, 1, 2])]).unwrap_err();
        assert_eq!(e, MeshError::NonFiniteCoordinate { node: 2 });
        assert_eq!(e.to_string(), "node 2 has a non-finite coordinate");
        let mut huge = nan;
        huge[2][1] = -1e300;
        let e = SurfaceMesh::new(huge, vec![Face::Tri3([0, 1, 2])]).unwrap_err();
        assert_eq!(e, MeshError::CoordinateOutOfRange { node: 2, value: -1e300 });
        assert_eq!(e.to_string(), "node 2 has coordinate -1e300, out of range (|x| ≤ 1e50)");
        let tiny = vec![[0., 0., 0.], [1e-60, 0., 0.], [0., 1e-60, 0.]];
        let e = SurfaceMesh::new(tiny, vec![Face::Tri3([0, 1, 2])]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "face 0 has diameter 1.414e-60, below the smallest size seam computes with (1e-50)"
        );
    }

    #[test]
    fn meshes_at_extreme_but_valid_scales_are_accepted() {
        for scale in [1e-45, 1e45] {
            let p = vec![[scale, 0., 0.], [2.0 * scale, 0., 0.], [scale, scale, 0.]];
            SurfaceMesh::new(p, vec![Face::Tri3([0, 1, 2])]).unwrap();
        }
    }

    #[test]
    fn a_flat_cell_names_the_cell_of_its_degenerate_boundary_face() {
        // A tetrahedron whose apex lies in the plane of its base, on the line
        // between corners 1 and 2: its face 1-2-3 has zero area.
        let p = vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0.5, 0.5, 0.]];
        let tet = VolumeMesh::new(p, vec![Cell::Tet4([0, 1, 2, 3])]).unwrap();
        let e = tet.boundary().unwrap_err();
        assert!(matches!(e, MeshError::DegenerateCellFace { cell: 0, why: "has zero area", .. }), "{e:?}");
        assert_eq!(e.element(), Some(0));
    }

    /// Gmsh's reference nodes of the second-order cells (from
    /// `crates/seam-io/tests/data/second_order.txt`, written by Gmsh).
    fn gmsh_reference(cell: &str) -> Vec<Point3> {
        let text = include_str!("../../seam-io/tests/data/second_order.txt");
        let line = text.lines().find(|l| l.starts_with("ref ") && l.contains(cell)).unwrap();
        let coords = line.rsplit(' ').next().unwrap();
        coords
            .split(';')
            .map(|p| {
                let v: Vec<f64> = p.split(',').map(|c| c.parse().unwrap()).collect();
                [v[0], v[1], v[2]]
            })
            .collect()
    }

    #[test]
    fn second_order_cells_have_second_order_boundary_faces_through_their_edge_midpoints() {
        type MakeCell = fn(&[usize]) -> Cell;
        let cells: [(&str, MakeCell, usize, usize); 7] = [
            ("Tetrahedron_10", |n| Cell::Tet10(n.try_into().unwrap()), 4, 0),
            ("Hexahedron_20", |n| Cell::Hex20(n.try_into().unwrap()), 6, 0),
            ("Hexahedron_27", |n| Cell::Hex27(n.try_into().unwrap()), 6, 6),
            ("Prism_15", |n| Cell::Prism15(n.try_into().unwrap()), 5, 0),
            ("Prism_18", |n| Cell::Prism18(n.try_into().unwrap()), 5, 3),
            ("Pyramid_13", |n| Cell::Pyramid13(n.try_into().unwrap()), 5, 0),
            ("Pyramid_14", |n| Cell::Pyramid14(n.try_into().unwrap()), 5, 1),
        ];
        for (name, make, n_faces, n_centres) in cells {
            let points = gmsh_reference(name);
            let nodes: Vec<usize> = (0..points.len()).collect();
            let cell = make(&nodes);
            assert!(cell.is_second_order());
            let mesh = VolumeMesh::new(points.clone(), vec![cell]).unwrap();
            let boundary = mesh.boundary().unwrap();
            assert_eq!(boundary.n_faces(), n_faces, "{name}");
            let mut centres = 0;
            for face in boundary.faces() {
                assert!(face.is_curved(), "{name}: {face}");
                let n = face.nodes();
                let k = face.n_corners();
                for i in 0..k {
                    let (a, b) = (points[n[i]], points[n[(i + 1) % k]]);
                    let mid = points[n[k + i]];
                    for c in 0..3 {
                        assert_eq!(mid[c], 0.5 * (a[c] + b[c]), "{name}: {face} edge {i}");
                    }
                }
                if let Face::Quad9(n) = face {
                    centres += 1;
                    for c in 0..3 {
                        let mean = n[..4].iter().map(|&i| points[i][c]).sum::<f64>() / 4.0;
                        assert_eq!(points[n[8]][c], mean, "{name}: {face} centre");
                    }
                }
                // Outward: the reversed face is the same face read the other way.
                assert_eq!(face.reversed().reversed(), *face);
            }
            assert_eq!(centres, n_centres, "{name}");
            // The boundary covers all but the interior nodes (Hex27's centre).
            let used = boundary.used_points().iter().filter(|&&u| u).count();
            assert_eq!(used, points.len() - usize::from(name == "Hexahedron_27"), "{name}");
        }
    }
}
