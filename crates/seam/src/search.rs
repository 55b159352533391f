//! (A1) Proximity search: a bounding-volume tree (an R*-tree, bulk-loaded) over
//! the axis-aligned boxes of the master faces.
//!
//! A master point paired with a slave point x_s lies at x_s + g·n_s with |g| ≤ g_max
//! (the projection is along the slave normal n_s), so a slave face asks for every
//! master face whose box meets the box of its corners moved by ±g_max·n_s
//! ([`swept_box`]): exact, and much tighter than growing the box by g_max in
//! every direction.
//!
//! # Performance
//! Build O(N log N) (sort-tile-recursive bulk load). A query costs O(log N + k)
//! for k hits on average and allocates nothing but the caller's output vector.

use crate::mesh::{Point3, SurfaceMesh};
use rstar::{RTree, RTreeObject, AABB};

/// The R*-tree over the faces of a surface mesh.
pub struct FaceTree {
    tree: RTree<FaceBox>,
}

struct FaceBox {
    envelope: AABB<Point3>,
    face: usize,
}

impl RTreeObject for FaceBox {
    type Envelope = AABB<Point3>;

    fn envelope(&self) -> Self::Envelope {
        self.envelope
    }
}

impl FaceTree {
    /// Builds the tree over the boxes of all faces of `mesh`.
    pub fn new(mesh: &SurfaceMesh) -> FaceTree {
        let boxes = (0..mesh.n_faces())
            .map(|f| {
                let (lo, hi) = face_box(&mesh.corners(f), 0.0);
                FaceBox { envelope: AABB::from_corners(lo, hi), face: f }
            })
            .collect();
        FaceTree { tree: RTree::bulk_load(boxes) }
    }

    /// Clears `out`, then fills it with the faces whose boxes meet the box
    /// [lo, hi], in increasing face order (so results never depend on the
    /// tree's internal layout).
    pub fn faces_meeting_box_into(&self, lo: Point3, hi: Point3, out: &mut Vec<usize>) {
        out.clear();
        let _ = self.tree.locate_in_envelope_intersecting_int(AABB::from_corners(lo, hi), |b| {
            out.push(b.face);
            std::ops::ControlFlow::<()>::Continue(())
        });
        out.sort_unstable();
    }
}

impl rstar::PointDistance for FaceBox {
    fn distance_2(&self, point: &Point3) -> f64 {
        self.envelope.distance_2(point)
    }
}

impl FaceTree {
    /// Distance from `point` to the nearest face box (0 inside a box).
    pub fn distance_to(&self, point: Point3) -> f64 {
        self.tree
            .nearest_neighbor(point)
            .map_or(f64::INFINITY, |b| rstar::PointDistance::distance_2(b, &point).sqrt())
    }
}

/// The axis-aligned box of the corners moved by ±`reach`·`normal`: the region a
/// face sweeps when moved along its normal by up to `reach` either way.
pub fn swept_box(corners: &[Point3], normal: Point3, reach: f64) -> (Point3, Point3) {
    let (lo, hi) = face_box(corners, 0.0);
    let mut lo2 = lo;
    let mut hi2 = hi;
    for k in 0..3 {
        let d = (reach * normal[k]).abs();
        lo2[k] = lo[k] - d;
        hi2[k] = hi[k] + d;
    }
    // Round-off: a flat face's box has zero thickness; keep a sliver of slack.
    let slack = 1e-12 * (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    ([lo2[0] - slack, lo2[1] - slack, lo2[2] - slack], [hi2[0] + slack, hi2[1] + slack, hi2[2] + slack])
}

/// The axis-aligned box of `corners`, grown by `margin` on every side.
pub fn face_box(corners: &[Point3], margin: f64) -> (Point3, Point3) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for c in corners {
        for k in 0..3 {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
    }
    ([lo[0] - margin, lo[1] - margin, lo[2] - margin], [hi[0] + margin, hi[1] + margin, hi[2] + margin])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Face;

    /// A strip of unit squares along x at height z.
    fn strip(n: usize, z: f64) -> SurfaceMesh {
        let mut p = Vec::new();
        for i in 0..=n {
            p.push([i as f64, 0.0, z]);
            p.push([i as f64, 1.0, z]);
        }
        let faces = (0..n).map(|i| Face::Quad4([2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1])).collect();
        SurfaceMesh::new(p, faces).unwrap()
    }

    #[test]
    fn query_matches_brute_force() {
        let m = strip(50, 0.0);
        let tree = FaceTree::new(&m);
        let mut out = Vec::new();
        for (x, margin) in [(3.5, 0.0), (10.0, 0.0), (20.2, 0.5), (60.0, 0.1), (-0.5, 0.6)] {
            let (lo, hi) = face_box(&[[x, 0.2, 0.1], [x + 0.3, 0.8, 0.1]], margin);
            tree.faces_meeting_box_into(lo, hi, &mut out);
            let brute: Vec<usize> = (0..m.n_faces())
                .filter(|&f| {
                    let (a, b) = face_box(&m.corners(f), 0.0);
                    (0..3).all(|k| a[k] <= hi[k] && lo[k] <= b[k])
                })
                .collect();
            assert_eq!(out, brute, "query at x = {x}");
        }
    }

    #[test]
    fn margin_reaches_across_a_gap() {
        let tree = FaceTree::new(&strip(4, 0.0));
        let mut out = Vec::new();
        let (lo, hi) = face_box(&[[1.2, 0.2, 0.3], [1.8, 0.8, 0.3]], 0.0);
        tree.faces_meeting_box_into(lo, hi, &mut out);
        assert!(out.is_empty());
        let (lo, hi) = face_box(&[[1.2, 0.2, 0.3], [1.8, 0.8, 0.3]], 0.3);
        tree.faces_meeting_box_into(lo, hi, &mut out);
        assert_eq!(out, vec![0, 1, 2]);
    }
}
