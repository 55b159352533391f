//! Paper steps (C2)–(C4): the Householder frame of a slave face, projection of
//! both faces onto its plane, convex hulls, convex–convex polygon intersection
//! and its fan triangulation. Everything is on the stack; nothing allocates.
//!
//! Conventions: polygons are counter-clockwise (positive signed area) in the
//! frame's (e1, e2) coordinates; a point is *inside* a directed edge when it lies
//! on its left, within a tolerance.

use crate::element::{dot, sub};
use crate::mesh::Point3;
use arrayvec::ArrayVec;

/// A point of the projection plane.
pub type Point2 = [f64; 2];

/// Capacity of a [`Polygon`]. Two convex quadrilaterals intersect in at most 8
/// vertices (each clipping edge adds at most one); the margin absorbs
/// near-duplicates created by round-off.
pub const MAX_POLYGON: usize = 12;

/// A convex polygon on the stack, counter-clockwise.
pub type Polygon = ArrayVec<Point2, MAX_POLYGON>;

/// (C2) An orthonormal frame (e1, e2, n) with the slave normal n as third axis,
/// from the Householder reflection H = I − 2vvᵀ/vᵀv that takes n to ±e3
/// (v = n ∓ e3, the sign chosen to avoid cancellation; the third row is then
/// set to n so that H n = e3 exactly).
///
/// Coordinates are taken relative to `origin` (the slave face centre), so the
/// projected coordinates are of the size of the face whatever the model offset.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    rows: [Point3; 3],
    origin: Point3,
}

impl Frame {
    /// The frame of unit normal `n` at `origin`.
    pub fn householder(n: Point3, origin: Point3) -> Frame {
        // v = n + s e3 with s = sign(n3): H n = −s e3; rows 1 and 2 of H span n⊥.
        let s = if n[2] >= 0.0 { 1.0 } else { -1.0 };
        let v = [n[0], n[1], n[2] + s];
        let beta = 2.0 / dot(v, v);
        let row = |i: usize| -> Point3 {
            let e = |j: usize| if i == j { 1.0 } else { 0.0 };
            [e(0) - beta * v[i] * v[0], e(1) - beta * v[i] * v[1], e(2) - beta * v[i] * v[2]]
        };
        Frame { rows: [row(0), row(1), n], origin }
    }

    /// (C3) Projection onto the plane: the first two frame coordinates.
    #[inline]
    pub fn project(&self, p: Point3) -> Point2 {
        let d = sub(p, self.origin);
        [dot(self.rows[0], d), dot(self.rows[1], d)]
    }

    /// The in-plane components of a vector (the projection's derivative).
    #[inline]
    pub fn project_vector(&self, v: Point3) -> Point2 {
        [dot(self.rows[0], v), dot(self.rows[1], v)]
    }

    /// Height of `p` along the normal, n·(p − origin).
    #[inline]
    pub fn height(&self, p: Point3) -> f64 {
        dot(self.rows[2], sub(p, self.origin))
    }

    /// The unit normal n.
    pub fn normal(&self) -> Point3 {
        self.rows[2]
    }
}

/// Signed area of a polygon (positive when counter-clockwise).
pub fn polygon_area(p: &[Point2]) -> f64 {
    let mut a = 0.0;
    for i in 0..p.len() {
        let (u, w) = (p[i], p[(i + 1) % p.len()]);
        a += u[0] * w[1] - u[1] * w[0];
    }
    0.5 * a
}

/// (C3) Convex hull of at most [`MAX_POLYGON`] points, counter-clockwise, by the
/// monotone chain; collinear points are dropped. Fewer than 3 hull points means
/// the points are collinear (the hull is then returned as it is, with area 0).
pub fn convex_hull(points: &[Point2]) -> Polygon {
    let mut p: ArrayVec<Point2, MAX_POLYGON> = points.iter().copied().collect();
    p.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let turn =
        |o: Point2, a: Point2, b: Point2| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hull = Polygon::new();
    for pass in 0..2 {
        let start = hull.len();
        let pts: &mut dyn Iterator<Item = &Point2> =
            if pass == 0 { &mut p.iter() } else { &mut p.iter().rev() };
        for &q in pts {
            while hull.len() >= start + 2 && turn(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0 {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

/// (C3) The convex polygon of a projected face: its corners counter-clockwise,
/// or their convex hull when the projection is not convex.
pub fn face_polygon(q: &[Point2]) -> Polygon {
    if let [a, b, c] = *q {
        // A triangle is convex: only its orientation is in question.
        let turn = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        return Polygon::from_iter(if turn < 0.0 { [c, b, a] } else { [a, b, c] });
    }
    let mut p: Polygon = q.iter().copied().collect();
    if polygon_area(&p) < 0.0 {
        p.reverse();
    }
    if p.len() == 3 || is_convex(&p) {
        p
    } else {
        convex_hull(&p)
    }
}

fn is_convex(p: &[Point2]) -> bool {
    (0..p.len()).all(|i| {
        let (a, b, c) = (p[i], p[(i + 1) % p.len()], p[(i + 2) % p.len()]);
        (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) > 0.0
    })
}

/// (C4) A convex counter-clockwise polygon prepared for clipping others
/// against it: its edges as (point, inward unit normal), computed once and used
/// for every polygon clipped (every candidate master face of a slave face).
#[derive(Clone, Debug)]
pub struct ConvexClipper {
    edges: ArrayVec<(Point2, Point2), MAX_POLYGON>,
    lo: Point2,
    hi: Point2,
    tol: f64,
}

impl ConvexClipper {
    /// The clipper of `clip`; points within `tol` (a length) of an edge's line
    /// count as inside.
    pub fn new(clip: &[Point2], tol: f64) -> ConvexClipper {
        let mut edges = ArrayVec::new();
        for i in 0..clip.len() {
            let (a, b) = (clip[i], clip[(i + 1) % clip.len()]);
            let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            if len > tol {
                edges.push((a, [-(b[1] - a[1]) / len, (b[0] - a[0]) / len]));
            }
        }
        let (lo, hi) = bounding_box(clip);
        ConvexClipper { edges, lo, hi, tol }
    }

    /// Intersection of the convex counter-clockwise `subject` with the clip
    /// polygon by Sutherland–Hodgman: `subject` is cut by each edge in turn.
    ///
    /// Shared edges, collinear edges, touching vertices and identical polygons
    /// give the exact overlap (or a zero-area sliver) instead of spurious
    /// vertices: the inside test has the tolerance, and consecutive vertices
    /// closer than it are merged. Fewer than 3 vertices: empty or degenerate.
    ///
    /// # Performance
    /// O(|subject|·|clip|), no allocation; disjoint bounding boxes return at once.
    pub fn clip(&self, subject: &[Point2]) -> Polygon {
        let tol = self.tol;
        let (lo, hi) = bounding_box(subject);
        if lo[0] > self.hi[0] + tol
            || self.lo[0] > hi[0] + tol
            || lo[1] > self.hi[1] + tol
            || self.lo[1] > hi[1] + tol
        {
            return Polygon::new();
        }
        // Two buffers used in turn: the input of one edge is the output of the last.
        let mut buffers = [Polygon::new(), Polygon::new()];
        buffers[0].extend(subject.iter().take(MAX_POLYGON).copied());
        let mut current = 0;
        let mut cuts = 0;
        for &(a, n) in &self.edges {
            // Signed distance to the edge's line: positive inside.
            let dist = |p: Point2| n[0] * (p[0] - a[0]) + n[1] * (p[1] - a[1]);
            // An edge with every vertex inside leaves the polygon as it is (the
            // common case: a face crosses one or two edges of the other).
            if buffers[current].iter().all(|&q| dist(q) >= -tol) {
                continue;
            }
            cuts += 1;
            let [first, second] = &mut buffers;
            let (input, out) = if current == 0 { (&*first, second) } else { (&*second, first) };
            out.clear();
            let mut p = input[input.len() - 1];
            let mut dp = dist(p);
            for &q in input {
                let dq = dist(q);
                let (p_in, q_in) = (dp >= -tol, dq >= -tol);
                if p_in != q_in && dp != dq {
                    let t = dp / (dp - dq);
                    push_distinct(out, [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])], tol);
                }
                if q_in {
                    push_distinct(out, q, tol);
                }
                (p, dp) = (q, dq);
            }
            close_ring(out, tol);
            if out.len() < 3 {
                return Polygon::new();
            }
            current = 1 - current;
        }
        if cuts == 0 {
            // The subject lies inside: merge its near-duplicate vertices as a cut would.
            let [input, out] = &mut buffers;
            for &q in input.iter() {
                push_distinct(out, q, tol);
            }
            close_ring(out, tol);
            current = 1;
            if out.len() < 3 {
                return Polygon::new();
            }
        }
        std::mem::take(&mut buffers[current])
    }
}

/// Appends `x` to `out` unless it is within `tol` of its last point (or
/// `out` is full).
#[inline]
fn push_distinct(out: &mut Polygon, x: Point2, tol: f64) {
    if !out.is_full() && out.last().is_none_or(|&l| !close(l, x, tol)) {
        out.push(x);
    }
}

/// Drops the last points of the ring `out` that are within `tol` of its first.
#[inline]
fn close_ring(out: &mut Polygon, tol: f64) {
    while out.len() > 1 && close(out[0], out[out.len() - 1], tol) {
        out.pop();
    }
}

/// (C4) Intersection of two convex counter-clockwise polygons; see
/// [`ConvexClipper::clip`].
pub fn clip_polygon_polygon(subject: &[Point2], clip: &[Point2], tol: f64) -> Polygon {
    ConvexClipper::new(clip, tol).clip(subject)
}

fn close(p: Point2, q: Point2, tol: f64) -> bool {
    (p[0] - q[0]).abs() <= tol && (p[1] - q[1]).abs() <= tol
}

fn bounding_box(p: &[Point2]) -> (Point2, Point2) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for q in p {
        lo = [lo[0].min(q[0]), lo[1].min(q[1])];
        hi = [hi[0].max(q[0]), hi[1].max(q[1])];
    }
    (lo, hi)
}

/// (C4) Fan triangulation of a convex polygon: triangles (0, k, k+1), k = 1..n−2,
/// as vertex index triples.
pub fn fan_triangles(n: usize) -> impl Iterator<Item = [usize; 3]> {
    (1..n.saturating_sub(1)).map(|k| [0, k, k + 1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const TOL: f64 = 1e-12;

    fn unit(v: Point3) -> Point3 {
        let n = dot(v, v).sqrt();
        [v[0] / n, v[1] / n, v[2] / n]
    }

    fn square(x0: f64, y0: f64, s: f64) -> Polygon {
        [[x0, y0], [x0 + s, y0], [x0 + s, y0 + s], [x0, y0 + s]].into_iter().collect()
    }

    fn area_of(a: &[Point2], b: &[Point2]) -> f64 {
        polygon_area(&clip_polygon_polygon(a, b, TOL))
    }

    #[test]
    fn householder_frame_is_orthonormal_and_maps_n_to_e3() {
        for n in [[0., 0., 1.], [0., 0., -1.], [1., 0., 0.], [0.3, -0.4, 0.5], [1e-9, 0., -1.]] {
            let n = unit(n);
            let f = Frame::householder(n, [0.0; 3]);
            for i in 0..3 {
                for j in 0..3 {
                    let expect = if i == j { 1.0 } else { 0.0 };
                    assert!((dot(f.rows[i], f.rows[j]) - expect).abs() < 1e-15, "{n:?}");
                }
            }
            assert!((f.height(n) - 1.0).abs() < 1e-15);
            let p = f.project(n);
            assert!(p[0].abs() < 1e-15 && p[1].abs() < 1e-15);
        }
    }

    #[test]
    fn identical() {
        let s = square(0.0, 0.0, 1.0);
        let c = clip_polygon_polygon(&s, &s, TOL);
        assert_eq!(c.len(), 4);
        assert!((polygon_area(&c) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn disjoint() {
        assert_eq!(clip_polygon_polygon(&square(0.0, 0.0, 1.0), &square(2.0, 0.0, 1.0), TOL).len(), 0);
    }

    #[test]
    fn shared_edge() {
        let c = clip_polygon_polygon(&square(0.0, 0.0, 1.0), &square(1.0, 0.0, 1.0), TOL);
        assert!(c.len() < 3 || polygon_area(&c).abs() < 1e-15);
    }

    #[test]
    fn touching_vertex() {
        let c = clip_polygon_polygon(&square(0.0, 0.0, 1.0), &square(1.0, 1.0, 1.0), TOL);
        assert!(c.len() < 3);
    }

    #[test]
    fn collinear_edges_partial_overlap() {
        // Same bottom edge line, half overlap in x.
        assert!((area_of(&square(0.0, 0.0, 1.0), &square(0.5, 0.0, 1.0)) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn full_inclusion() {
        assert!((area_of(&square(0.0, 0.0, 4.0), &square(1.0, 1.0, 1.0)) - 1.0).abs() < 1e-15);
        assert!((area_of(&square(1.0, 1.0, 1.0), &square(0.0, 0.0, 4.0)) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn triangle_against_quad_has_eight_or_fewer_vertices() {
        // A rotated square against a square: the octagon.
        let r = 0.5f64.sqrt() * 1.2;
        let diamond: Polygon = (0..4)
            .map(|k| {
                let a = std::f64::consts::FRAC_PI_2 * k as f64;
                [0.5 + r * a.cos(), 0.5 + r * a.sin()]
            })
            .collect();
        let c = clip_polygon_polygon(&diamond, &square(0.0, 0.0, 1.0), TOL);
        assert_eq!(c.len(), 8);
    }

    #[test]
    fn hull_of_non_convex_quad() {
        let h = convex_hull(&[[0., 0.], [2., 0.], [0.5, 0.5], [0., 2.]]);
        assert_eq!(h.len(), 3);
        assert!((polygon_area(&h) - 2.0).abs() < 1e-15);
    }

    #[test]
    fn fan_covers_polygon() {
        let p = square(0.0, 0.0, 1.0);
        let sum: f64 = fan_triangles(p.len()).map(|[a, b, c]| polygon_area(&[p[a], p[b], p[c]])).sum();
        assert!((sum - 1.0).abs() < 1e-15);
        assert_eq!(fan_triangles(2).count(), 0);
    }

    /// Reference: area of the intersection of two convex polygons by the
    /// half-plane integration of a fine grid's cell areas (straightforward,
    /// independent of Sutherland–Hodgman): exact polygon area of intersection
    /// via Green's theorem over the boundary pieces of each polygon lying in the
    /// other.
    fn reference_area(a: &[Point2], b: &[Point2]) -> f64 {
        fn inside(p: Point2, poly: &[Point2]) -> bool {
            (0..poly.len()).all(|i| {
                let (u, w) = (poly[i], poly[(i + 1) % poly.len()]);
                (w[0] - u[0]) * (p[1] - u[1]) - (w[1] - u[1]) * (p[0] - u[0]) >= 0.0
            })
        }
        // Boundary integral ½∮(x dy − y dx) over the intersection's boundary =
        // pieces of ∂a inside b plus pieces of ∂b inside a. Each edge is cut at
        // its crossings with the other polygon and midpoints are tested.
        fn part(a: &[Point2], b: &[Point2]) -> f64 {
            let mut s = 0.0;
            for i in 0..a.len() {
                let (p, q) = (a[i], a[(i + 1) % a.len()]);
                let mut ts = vec![0.0, 1.0];
                for j in 0..b.len() {
                    let (u, w) = (b[j], b[(j + 1) % b.len()]);
                    let d = [q[0] - p[0], q[1] - p[1]];
                    let e = [w[0] - u[0], w[1] - u[1]];
                    let den = d[0] * e[1] - d[1] * e[0];
                    if den.abs() > 1e-300 {
                        let t = ((u[0] - p[0]) * e[1] - (u[1] - p[1]) * e[0]) / den;
                        if t > 0.0 && t < 1.0 {
                            ts.push(t);
                        }
                    }
                }
                ts.sort_by(f64::total_cmp);
                for k in 0..ts.len() - 1 {
                    let m = 0.5 * (ts[k] + ts[k + 1]);
                    let mid = [p[0] + m * (q[0] - p[0]), p[1] + m * (q[1] - p[1])];
                    if inside(mid, b) {
                        let x0 = [p[0] + ts[k] * (q[0] - p[0]), p[1] + ts[k] * (q[1] - p[1])];
                        let x1 = [p[0] + ts[k + 1] * (q[0] - p[0]), p[1] + ts[k + 1] * (q[1] - p[1])];
                        s += 0.5 * (x0[0] * x1[1] - x0[1] * x1[0]);
                    }
                }
            }
            s
        }
        part(a, b) + part(b, a)
    }

    fn convex_polygon() -> impl Strategy<Value = Polygon> {
        prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0), 3..=4).prop_filter_map("degenerate", |pts| {
            let pts: Vec<Point2> = pts.into_iter().map(|(x, y)| [x, y]).collect();
            let h = convex_hull(&pts);
            (h.len() >= 3 && polygon_area(&h) > 1e-3).then_some(h)
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1000))]

        #[test]
        fn intersection_area_is_symmetric_bounded_and_exact(a in convex_polygon(), b in convex_polygon()) {
            let ab = area_of(&a, &b);
            let ba = area_of(&b, &a);
            let reference = reference_area(&a, &b);
            prop_assert!((ab - ba).abs() < 1e-12, "{ab} vs {ba}");
            prop_assert!(ab <= polygon_area(&a) + 1e-12 && ab <= polygon_area(&b) + 1e-12);
            prop_assert!((ab - reference).abs() < 1e-11, "{ab} vs reference {reference}");
            prop_assert!(ab >= 0.0);
        }

        #[test]
        fn disjoint_polygons_have_zero_area(a in convex_polygon(), b in convex_polygon()) {
            let shifted: Polygon = b.iter().map(|p| [p[0] + 2.5, p[1]]).collect();
            prop_assert_eq!(clip_polygon_polygon(&a, &shifted, TOL).len(), 0);
        }
    }
}
