//! What a user checks before trusting a coupling: nodal normals, signed normal
//! gaps per slave node, the master's side of an operator, and face quality.

use super::isoparametric::{self, MAX_NODES};
use super::rows::basis_transformation;
use super::{face_integrals, warped_quad_degree, Mortar, Transfer, COVERED_FRACTION};
use crate::catalogue::FaceKind;
use crate::curved::CurvedFace;
use crate::element::{cross, dot, norm, sub, FaceElement, PLANAR_WARP};
use crate::mesh::{Point3, SurfaceMesh};
use rayon::prelude::*;

/// Unit nodal normals: the area-weighted mean of the normals of the faces around
/// each point, n_p ∝ Σ_e A_e n_e (following each face's own orientation); the
/// zero vector for points no face uses.
pub fn nodal_normals(mesh: &SurfaceMesh) -> Vec<Point3> {
    let mut n = vec![[0.0; 3]; mesh.n_points()];
    for (f, face) in mesh.faces().iter().enumerate() {
        let c = mesh.corners(f);
        let a = crate::mesh::area_vector(&c[..face.n_corners()]);
        for &p in face.nodes() {
            for k in 0..3 {
                n[p][k] += a[k];
            }
        }
    }
    for v in &mut n {
        let l = norm(*v);
        if l > 0.0 {
            *v = [v[0] / l, v[1] / l, v[2] / l];
        }
    }
    n
}

/// The signed normal gap at each slave point, g_p = n_p·((T x_m)_p − x_p): the
/// weighted distance along the slave nodal normal to the master surface,
/// positive when the master lies on the side n_p points to (a gap), negative for
/// an overlap. NaN where `covered` is false or the point is off the surface.
pub fn normal_gaps(
    slave: &SurfaceMesh,
    master: &SurfaceMesh,
    transfer: &Transfer,
    covered: &[bool],
) -> Vec<f64> {
    let xm: Vec<f64> = master.points().iter().flat_map(|p| p.iter().copied()).collect();
    normal_gaps_from(slave, &transfer.apply(&xm, 3), covered)
}

/// [`normal_gaps`] from the master's points already transferred,
/// `transferred` = T x_m (slave points × 3), e.g. along with a field.
pub fn normal_gaps_from(slave: &SurfaceMesh, transferred: &[f64], covered: &[bool]) -> Vec<f64> {
    let normals = nodal_normals(slave);
    (0..slave.n_points())
        .map(|p| {
            let n = normals[p];
            if !covered[p] || n == [0.0; 3] {
                return f64::NAN;
            }
            let x = slave.points()[p];
            let t = &transferred[3 * p..3 * p + 3];
            dot(n, [t[0] - x[0], t[1] - x[1], t[2] - x[2]])
        })
        .collect()
}

/// ∫Γ λ_q per point of `mesh` (0 at points no face uses): the lumped mass,
/// with the rules of the kernel's full-face integrals (exact on flat faces,
/// to [`super::WARPED_RTOL`] on warped quads, degree 8 on curved faces).
pub fn nodal_areas(mesh: &SurfaceMesh) -> Vec<f64> {
    let per_face: Vec<[f64; MAX_NODES]> = (0..mesh.n_faces())
        .into_par_iter()
        .map(|f| {
            if mesh.faces()[f].is_curved() {
                let rule = crate::quadrature::triangle_rule(isoparametric::CURVED_LADDER[0].1)
                    .expect("tabulated degree");
                return isoparametric::face_integrals(&CurvedFace::of(mesh, f), &rule);
            }
            let e = FaceElement::of(mesh, f);
            let warped = e.kind == FaceKind::Quad4 && e.warp() >= PLANAR_WARP;
            let full = face_integrals(&e, if warped { warped_quad_degree(&e) } else { 3 });
            std::array::from_fn(|p| if p < 4 { full[p] } else { 0.0 })
        })
        .collect();
    let mut a = vec![0.0; mesh.n_points()];
    for (face, full) in mesh.faces().iter().zip(&per_face) {
        for (&p, &v) in face.nodes().iter().zip(full) {
            a[p] += v;
        }
    }
    a
}

/// The master's side of an operator, from B alone, so that one assembly
/// serves both surfaces (the target of a conservative transfer is the
/// master of the operator that moves its loads). See [`master_side`].
#[derive(Clone, Debug, PartialEq)]
pub struct MasterSide {
    /// Per master point q: the covered fraction ã_q / m̃_q of its support
    /// (below), at most 1; 0 off the surface.
    pub coverage: Vec<f64>,
    /// Per master point: covered, `coverage` > [`COVERED_FRACTION`].
    pub covered: Vec<bool>,
    /// Per master point: the signed normal gap g_q = n_q·(c_q − x_q), c_q the
    /// λ̃_q-weighted mean of the slave points over the footprint of λ̃_q on the
    /// slave; positive when the slave lies on the side n_q points to. NaN
    /// where not covered.
    pub normal_gaps: Vec<f64>,
    /// ∫Γm 1.
    pub area: f64,
    /// Σ_q coverage_q m̃_q: the covered part of Γm.
    pub covered_area: f64,
}

/// The coverage and normal gaps of the master's points by the slave surface,
/// from the operator's B (no second assembly). The multiplier functions ψ_p
/// sum to one on the covered slave surface (standard, dual and lumped alike),
/// so the column sums a_q = Σ_p B_pq = ∫Γs λ_q∘Φ measure the slave area over
/// which master function q is seen, and Σ_p B_pq x_p its λ_q-weighted slave
/// points. Against m_q = ∫Γm λ_q ([`nodal_areas`]) that gives a covered
/// fraction ã_q / m̃_q (capped at 1: the two areas differ by the projection's
/// stretch, O(gap × curvature) where covered). On masters with Tri6 or
/// Quad8 faces both are taken for the positive functions λ̃ = Q λ of the
/// basis transformation ([`super::BASIS_ALPHA`]), since ∫λ_q of their corners
/// is not positive, as the slave's own coverage is ([`Mortar::node_coverage`]).
/// Where second-order master faces bow in the slave's plane, the columns of
/// B, and so these, carry the O(δ/h) error of the straight chords of the
/// segmentation (C3), δ the edges' in-plane sagitta: up to 6 % on flat Tri6
/// patches whose diagonals bow by a fifth of a face, O(hκ) on curved
/// surfaces meshed with mid-edge nodes on the surface.
///
/// # Panics
/// If `mortar` was not assembled between `slave` and `master`.
pub fn master_side(mortar: &Mortar, slave: &SurfaceMesh, master: &SurfaceMesh) -> MasterSide {
    let b = &mortar.b;
    assert!(
        b.nrows == slave.n_points() && b.ncols == master.n_points(),
        "the operator couples other surfaces"
    );
    let xs: Vec<f64> = slave.points().iter().flat_map(|p| p.iter().copied()).collect();
    let mut a = b.transpose_mul_vec(&vec![1.0; b.nrows], 1);
    let mut c = b.transpose_mul_vec(&xs, 3);
    let mut m = nodal_areas(master);
    if let Some(alpha) = super::multiplier::transformation_weight(master, super::BasisTransformation::Needed)
    {
        let q = basis_transformation(master, alpha);
        (a, c, m) = (q.mul_vec(&a, 1), q.mul_vec(&c, 3), q.mul_vec(&m, 1));
    }
    let used = master.used_points();
    let coverage: Vec<f64> = (0..m.len())
        .map(|q| if used[q] && m[q] > 0.0 { (a[q] / m[q]).clamp(0.0, 1.0) } else { 0.0 })
        .collect();
    let covered: Vec<bool> = coverage.iter().map(|&f| f > COVERED_FRACTION).collect();
    let normals = nodal_normals(master);
    let normal_gaps = (0..m.len())
        .map(|q| {
            if !covered[q] || a[q] <= 0.0 {
                return f64::NAN;
            }
            let x = master.points()[q];
            let centre = [c[3 * q] / a[q], c[3 * q + 1] / a[q], c[3 * q + 2] / a[q]];
            dot(normals[q], sub(centre, x))
        })
        .collect();
    let area = m.iter().sum();
    let covered_area = coverage.iter().zip(&m).map(|(f, m)| f * m).sum();
    MasterSide { coverage, covered, normal_gaps, area, covered_area }
}

/// The number of interior edges whose two faces run through them in the same
/// direction: 0 when the normals of the sheet are consistently oriented (edges
/// shared by more than two faces are not counted).
pub fn orientation_conflicts(mesh: &SurfaceMesh) -> usize {
    let mut edges: Vec<(usize, usize, bool)> = Vec::with_capacity(mesh.n_faces() * 4);
    for face in mesh.faces() {
        let n = face.nodes();
        for k in 0..n.len() {
            let (a, b) = (n[k], n[(k + 1) % n.len()]);
            edges.push((a.min(b), a.max(b), a < b));
        }
    }
    edges.sort_unstable();
    edges
        .chunk_by(|x, y| (x.0, x.1) == (y.0, y.1))
        .filter(|run| run.len() == 2 && run[0].2 == run[1].2)
        .count()
}

/// Shape measures of one face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceQuality {
    /// Smallest interior angle at a corner, in degrees.
    pub min_angle_degrees: f64,
    /// Largest interior angle at a corner, in degrees.
    pub max_angle_degrees: f64,
    /// Relative warp of a quad (0 for a triangle), see `FaceElement::warp`.
    pub warp: f64,
}

/// The quality of every face of `mesh`.
pub fn face_quality(mesh: &SurfaceMesh) -> Vec<FaceQuality> {
    (0..mesh.n_faces())
        .map(|f| {
            let e = FaceElement::of(mesh, f);
            let c = e.corners();
            let n = c.len();
            let angles = (0..n).map(|k| {
                let (a, b, d) = (c[(k + n - 1) % n], c[k], c[(k + 1) % n]);
                let (u, v) = (sub(a, b), sub(d, b));
                norm(cross(u, v)).atan2(dot(u, v)).to_degrees()
            });
            let (min, max) = angles.fold((f64::INFINITY, 0.0f64), |(lo, hi), t| (lo.min(t), hi.max(t)));
            FaceQuality { min_angle_degrees: min, max_angle_degrees: max, warp: e.warp() }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{cylinder, flat, patch, Pattern};
    use crate::{assemble, MortarOptions};

    #[test]
    fn normals_of_a_cylinder_are_radial() {
        // 6 cells over 1 rad: interior points see two symmetric face columns, so
        // their normal is radial; points on the straight edges θ = 0, 1 see one,
        // whose normal is tilted by half a cell, Δθ/2 = 1/12.
        let m = patch(6, 3, Pattern::Quads, cylinder(2.0, 1.0, 1.0));
        for (k, (p, n)) in m.points().iter().zip(nodal_normals(&m)).enumerate() {
            let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
            let cos = n[0] * p[0] / r + n[1] * p[1] / r;
            let i = k % 7;
            let expected = if i == 0 || i == 6 { (1.0f64 / 12.0).cos() } else { 1.0 };
            assert!((cos - expected).abs() < 1e-12 && n[2].abs() < 1e-12, "point {k}: cos {cos}");
        }
    }

    #[test]
    fn gap_of_parallel_planes_is_their_distance() {
        let slave = patch(4, 4, Pattern::Quads, flat(1.0, 1.0));
        for offset in [0.05, -0.03] {
            let master = patch(5, 3, Pattern::Triangles, move |u, v| [u, v, offset]);
            let m = assemble(&master, &slave, &MortarOptions::default()).unwrap();
            let g = normal_gaps(&slave, &master, &m.transfer().unwrap(), &m.covered);
            for v in g {
                assert!((v - offset).abs() < 1e-13, "{v} vs {offset}");
            }
        }
    }

    #[test]
    fn flipped_faces_are_orientation_conflicts() {
        let m = patch(3, 3, Pattern::Quads, flat(1.0, 1.0));
        assert_eq!(orientation_conflicts(&m), 0);
        let (points, mut faces) = m.into_parts();
        faces[4] = faces[4].reversed(); // the centre face: its 4 edges now conflict
        assert_eq!(orientation_conflicts(&SurfaceMesh::new(points, faces).unwrap()), 4);
    }

    #[test]
    fn quality_of_a_right_triangle() {
        let m = SurfaceMesh::new(
            vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]],
            vec![crate::Face::Tri3([0, 1, 2])],
        )
        .unwrap();
        let q = face_quality(&m)[0];
        assert!((q.min_angle_degrees - 45.0).abs() < 1e-12 && (q.max_angle_degrees - 90.0).abs() < 1e-12);
        assert_eq!(q.warp, 0.0);
    }
}
