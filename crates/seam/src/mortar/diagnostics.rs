//! What a user checks before trusting a coupling: nodal normals, signed normal
//! gaps per slave node, and face quality.

use super::Transfer;
use crate::element::{cross, dot, norm, sub, FaceElement};
use crate::mesh::{Point3, SurfaceMesh};

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
    let txm = transfer.apply(&xm, 3);
    let normals = nodal_normals(slave);
    (0..slave.n_points())
        .map(|p| {
            let n = normals[p];
            if !covered[p] || n == [0.0; 3] {
                return f64::NAN;
            }
            let x = slave.points()[p];
            dot(n, [txm[3 * p] - x[0], txm[3 * p + 1] - x[1], txm[3 * p + 2] - x[2]])
        })
        .collect()
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
