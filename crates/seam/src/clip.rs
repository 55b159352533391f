//! Paper steps (C2)–(C4): the Householder frame of a slave face, projection of
//! both faces onto its plane, convex hulls, convex–convex polygon intersection
//! and its fan triangulation. Everything is on the stack; nothing allocates.
//!
//! Conventions: polygons are counter-clockwise (positive signed area) in the
//! frame's (e1, e2) coordinates; a point is *inside* a directed edge a→b when
//! it lies on its left or on its line.
//!
//! # Near-degenerate configurations
//! Nearly matching meshes put master vertices within round-off of slave edges
//! and master edges along slave edges; every such configuration is decided
//! exactly, on the projected coordinates as they are, never by a tolerance:
//!
//! | configuration | decision |
//! |---|---|
//! | point in / on / out of an edge's half-plane | sign of [`orient`] (Shewchuk's adaptive exact predicate): on the line counts as inside |
//! | edge crossing an edge's line | only for end points strictly on opposite sides; the crossing is computed from the end points in lexicographic order, so the two faces sharing the edge get the same point bit for bit, and lies on the edge (its parameter is in \[0, 1\] by construction) |
//! | coincident or collinear edges, vertices on edges | "on" is inside: no crossing is made, the vertex is kept as it is |
//! | polygon entirely on or outside one line | empty (no positive-area overlap) |
//! | a face's corners: a fold, a straight corner, collinear corners | by the exact turns: the convex hull, the corner dropped, an empty polygon ([`face_polygon`]); so every subject and clip polygon is strictly convex |
//! | crossings rounded next to a vertex | at most a dent of round-off size (a fan triangle of round-off area and either sign); a ring dented so that a later line meets it more than twice is made strictly convex at once ([`make_strictly_convex`]), so no polygon outgrows [`MAX_POLYGON`] |
//! | sliver polygons | kept, with their true (tiny) area; the caller may drop pieces whose contribution is below round-off |
//! | how pieces are triangulated | a fan from the vertex lowest along a fixed generic direction of space ([`Frame::apex_direction`]); for rules that are not exact, vertices within 1e-8 of their neighbours' chord are covered by slivers instead ([`stable_fan`]): noise then changes the triangles, and the quadrature on them, continuously |
//!
//! Consequences: the pieces of one convex polygon clipped by the master
//! polygons that tile the plane tile it up to the rounding of crossing points
//! (O(ε_mach) of its size), whatever the configuration; no piece reaches out
//! of either polygon by more than that; and the result is a continuous
//! function of the coordinates, so coordinate noise of size ε moves any area
//! by O(ε · size). There is no snapping: two vertices 1e-13 apart stay two
//! vertices, and the sliver between them is integrated as what it is.

use crate::element::{dot, sub};
use crate::mesh::Point3;
use arrayvec::ArrayVec;

/// A point of the projection plane.
pub type Point2 = [f64; 2];

/// Capacity of a [`Polygon`]. Two convex quadrilaterals intersect in at most 8
/// vertices (each clipping edge adds at most one, and [`ConvexClipper::clip`]
/// keeps every intermediate polygon strictly convex); the margin serves
/// clip polygons of more corners.
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

    /// The in-plane direction along which a piece's lowest vertex is the
    /// apex of its fan ([`stable_fan`]): a fixed direction of space
    /// projected, the same for neighbouring faces whatever way their frames
    /// turn.
    pub fn apex_direction(&self) -> Point2 {
        self.project_vector(SPACE_APEX)
    }
}

/// Exact orientation of `c` relative to the directed line a→b: positive when
/// `c` lies on its left, zero on it, negative on its right; the value
/// approximates twice the signed area of (a, b, c) to a relative round-off,
/// and its sign is exact for the given floating-point coordinates.
///
/// Shewchuk's filter first: the determinant of the rounded differences
/// (b − a, c − a) has the sign of the exact one when its magnitude exceeds
/// (3ε + 16ε²)(|t₁| + |t₂|), t₁, t₂ its two products (ε = 2⁻⁵³; Shewchuk 1997,
/// ccwerrboundA); otherwise his adaptive exact predicate decides (the
/// `robust` crate).
#[inline(always)]
pub fn orient(a: Point2, b: Point2, c: Point2) -> f64 {
    let t1 = (b[0] - a[0]) * (c[1] - a[1]);
    let t2 = (b[1] - a[1]) * (c[0] - a[0]);
    let det = t1 - t2;
    let bound = ORIENT_BOUND * (t1.abs() + t2.abs());
    if det > bound || -det > bound {
        det
    } else {
        orient_exact(a, b, c)
    }
}

/// Shewchuk's ccwerrboundA, (3ε + 16ε²), ε = 2⁻⁵³.
const ORIENT_BOUND: f64 = 3.3306690621773722e-16;

/// [`ORIENT_BOUND`] with room for the rounding of a bound computed from
/// magnitudes that majorise the products (a relative 1e-15 is ample: four
/// roundings need 4.4e-16).
const ORIENT_BOUND_MAJORISED: f64 = ORIENT_BOUND * (1.0 + 1e-15);

/// The adaptive exact stage of [`orient`].
#[cold]
#[inline(never)]
fn orient_exact(a: Point2, b: Point2, c: Point2) -> f64 {
    let coord = |p: Point2| robust::Coord { x: p[0], y: p[1] };
    robust::orient2d(coord(a), coord(b), coord(c))
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
/// monotone chain with the exact [`orient`]; duplicate and collinear points are
/// dropped. Fewer than 3 hull points means the points are collinear.
pub fn convex_hull(points: &[Point2]) -> Polygon {
    let mut p: ArrayVec<Point2, MAX_POLYGON> = points.iter().take(MAX_POLYGON).copied().collect();
    p.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let mut hull = Polygon::new();
    for pass in 0..2 {
        let start = hull.len();
        let pts: &mut dyn Iterator<Item = &Point2> =
            if pass == 0 { &mut p.iter() } else { &mut p.iter().rev() };
        for &q in pts {
            while hull.len() >= start + 2 && orient(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0 {
                hull.pop();
            }
            if !hull.is_full() {
                hull.push(q);
            }
        }
        hull.pop();
    }
    if hull.len() < 3 {
        hull.clear();
    }
    hull
}

/// (C3) The convex polygon of a projected face: its corners counter-clockwise,
/// or their convex hull when the projection is not convex; strictly convex
/// (duplicate and collinear corners dropped), empty when the corners are
/// collinear.
pub fn face_polygon(q: &[Point2]) -> Polygon {
    match *q {
        [a, b, c] => {
            // A triangle is convex: only its orientation is in question.
            let o = orient(a, b, c);
            if o > 0.0 {
                Polygon::from_iter([a, b, c])
            } else if o < 0.0 {
                Polygon::from_iter([a, c, b])
            } else {
                Polygon::new()
            }
        }
        [a, b, c, d] => {
            // All four turns left: convex counter-clockwise; all right:
            // convex clockwise; else (a fold, a straight corner) the hull.
            let turns = [orient(d, a, b), orient(a, b, c), orient(b, c, d), orient(c, d, a)];
            if turns.iter().all(|&t| t > 0.0) {
                Polygon::from_iter([a, b, c, d])
            } else if turns.iter().all(|&t| t < 0.0) {
                Polygon::from_iter([d, c, b, a])
            } else {
                convex_hull(q)
            }
        }
        _ => convex_hull(q),
    }
}

/// Removes, until none is left, every vertex of the counter-clockwise ring `p`
/// at which the boundary does not turn strictly left by the exact [`orient`]:
/// duplicates, collinear vertices and the dents that rounded crossing points
/// can make in a convex polygon. Empties `p` if fewer than 3 vertices remain.
///
/// On a ring that is a convex polygon up to round-off (the case of a clipped
/// polygon) only vertices within round-off of their neighbours' chord go, so
/// the area changes by round-off; the result is strictly convex.
pub fn make_strictly_convex(p: &mut Polygon) {
    let (mut i, mut checked) = (0, 0);
    while p.len() >= 3 && checked < p.len() {
        let n = p.len();
        let (prev, next) = (if i == 0 { n - 1 } else { i - 1 }, if i + 1 == n { 0 } else { i + 1 });
        if orient(p[prev], p[i], p[next]) > 0.0 {
            (i, checked) = (next, checked + 1);
        } else {
            p.remove(i);
            // The previous vertex has a new neighbour: check it again.
            (i, checked) = (if prev == n - 1 { n - 2 } else { prev }, 0);
        }
    }
    if p.len() < 3 {
        p.clear();
    }
}

/// (C4) A strictly convex counter-clockwise polygon prepared for clipping
/// others against it: its edges and bounding box, computed once and used for
/// every polygon clipped (every candidate master face of a slave face).
#[derive(Clone, Debug)]
pub struct ConvexClipper {
    edges: ArrayVec<ClipEdge, MAX_POLYGON>,
    lo: Point2,
    hi: Point2,
    /// The zone of the static filter: the box [lo, hi] grown by its size on
    /// every side.
    zone: (Point2, Point2),
}

/// An edge a→b of a [`ConvexClipper`].
#[derive(Clone, Copy, Debug)]
struct ClipEdge {
    a: Point2,
    b: Point2,
    /// b − a, rounded.
    e: Point2,
    /// The static filter's bound for points of the zone: a value of
    /// e × (q − a) beyond it has the exact sign (Shewchuk's bound with the
    /// products majorised over the zone).
    bound: f64,
}

impl ClipEdge {
    /// [`orient`]`(a, b, q)`: e × (q − a) if beyond the static bound (for
    /// `q` in the zone) or else beyond its own error bound, otherwise the
    /// adaptive exact predicate.
    #[inline(always)]
    fn side(&self, q: Point2, in_zone: bool) -> f64 {
        let (a, e) = (self.a, self.e);
        let t1 = e[0] * (q[1] - a[1]);
        let t2 = e[1] * (q[0] - a[0]);
        let det = t1 - t2;
        if in_zone && (det > self.bound || -det > self.bound) {
            return det;
        }
        let bound = ORIENT_BOUND * (t1.abs() + t2.abs());
        if det > bound || -det > bound {
            det
        } else {
            orient_exact(a, self.b, q)
        }
    }
}

impl ConvexClipper {
    /// The clipper of `clip`, a polygon from [`face_polygon`] (strictly convex,
    /// counter-clockwise); an empty `clip` clips everything away.
    pub fn new(clip: &[Point2]) -> ConvexClipper {
        let n = clip.len();
        let (lo, hi) = bounding_box(clip);
        let size = [hi[0] - lo[0], hi[1] - lo[1]];
        let zone = ([lo[0] - size[0], lo[1] - size[1]], [hi[0] + size[0], hi[1] + size[1]]);
        let edges = (0..n)
            .map(|i| {
                let (a, b) = (clip[i], clip[(i + 1) % n]);
                let e = [b[0] - a[0], b[1] - a[1]];
                // |q − a| over the zone, per axis (its corners bound the rounded differences).
                let r0 = (zone.0[0] - a[0]).abs().max((zone.1[0] - a[0]).abs());
                let r1 = (zone.0[1] - a[1]).abs().max((zone.1[1] - a[1]).abs());
                let bound = ORIENT_BOUND_MAJORISED * (e[0].abs() * r1 + e[1].abs() * r0);
                ClipEdge { a, b, e, bound }
            })
            .collect();
        ConvexClipper { edges, lo, hi, zone }
    }

    /// Intersection of the strictly convex counter-clockwise `subject` (from
    /// [`face_polygon`]) with the clip polygon by Sutherland–Hodgman: `subject`
    /// is cut by each edge's closed half-plane in turn, every decision made by
    /// the exact [`orient`] (module doc: near-degenerate configurations).
    /// The result is convex up to the rounding of its crossing points, or
    /// empty when the overlap has no area.
    ///
    /// # Performance
    /// O(|subject|·|clip|) predicates, no allocation; disjoint bounding boxes
    /// return at once.
    pub fn clip(&self, subject: &[Point2]) -> Polygon {
        let (lo, hi) = bounding_box(subject);
        if self.edges.len() < 3
            || subject.len() < 3
            || lo[0] > self.hi[0]
            || self.lo[0] > hi[0]
            || lo[1] > self.hi[1]
            || self.lo[1] > hi[1]
        {
            return Polygon::new();
        }
        // Every point met below lies in the subject's box (crossings lie on
        // its edges, to rounding: the zone's margin is the clip's size).
        let (zlo, zhi) = self.zone;
        let in_zone = lo[0] >= zlo[0] && lo[1] >= zlo[1] && hi[0] <= zhi[0] && hi[1] <= zhi[1];
        // Two buffers used in turn: the input of one edge is the output of the last.
        let mut buffers = [Polygon::new(), Polygon::new()];
        buffers[0].extend(subject.iter().take(MAX_POLYGON).copied());
        let mut current = 0;
        let mut side = [0.0; MAX_POLYGON];
        for edge in &self.edges {
            let input = &buffers[current];
            let (mut any_in, mut any_out) = (false, false);
            for (s, &q) in side.iter_mut().zip(input.iter()) {
                *s = edge.side(q, in_zone);
                any_in |= *s > 0.0;
                any_out |= *s < 0.0;
            }
            if !any_out {
                // Every vertex inside or on the line: nothing to cut (the
                // common case: a face crosses one or two edges of the other).
                continue;
            }
            if !any_in {
                // Every vertex outside or on the line: no area left.
                return Polygon::new();
            }
            let [first, second] = &mut buffers;
            let (input, out) = if current == 0 { (&*first, second) } else { (&*second, first) };
            out.clear();
            let n = input.len();
            // At most two crossings on a convex input; more, on a ring that
            // rounding has dented, and it is made strictly convex at once.
            let mut count = 0;
            let (mut p, mut sp) = (input[n - 1], side[n - 1]);
            for (&q, &sq) in input.iter().zip(&side[..n]) {
                if (sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0) {
                    count += 1;
                    push(out, crossing(p, sp, q, sq));
                }
                if sq >= 0.0 {
                    push(out, q);
                }
                (p, sp) = (q, sq);
            }
            if count > 2 {
                make_strictly_convex(out);
                if out.is_empty() {
                    return Polygon::new();
                }
            }
            current = 1 - current;
        }
        std::mem::take(&mut buffers[current])
    }
}

/// The 3D direction whose projection onto a slave face's plane orders its
/// pieces' vertices for the apex of their fans ([`Frame::apex_direction`]):
/// (1, √3, √7)/√11, parallel to no normal of a structured mesh. A direction
/// of 3D space, not of the frame, because the Householder frame flips its
/// in-plane axes where the normal's third component changes sign, and noise
/// makes it do so on faces whose normal lies in the xy plane.
const SPACE_APEX: Point3 = [0.301_511_344_577_763_63, 0.522_232_967_867_093_5, 0.797_724_035_217_465_7];

/// Appends `x` to `out`. A strictly convex n-gon cut by a line gives at most
/// n + 1 vertices, so an n-gon clipped by an m-gon never has more than n + m
/// ([`MAX_POLYGON`] ≥ 8 for two quadrilaterals).
#[inline]
fn push(out: &mut Polygon, x: Point2) {
    debug_assert!(!out.is_full(), "a clipped polygon outgrew MAX_POLYGON");
    if !out.is_full() {
        out.push(x);
    }
}

/// The point where the edge p–q, whose end points lie strictly on opposite
/// sides of a line (`sp`, `sq` their [`orient`] values), crosses it. Computed
/// from the end point that comes first lexicographically, so that both
/// directions of the edge give the same bits; the parameter
/// t = s_u / (s_u − s_v) has operands of opposite signs, so t ∈ \[0, 1\] and
/// the point lies on the edge whatever the rounding.
#[inline]
fn crossing(p: Point2, sp: f64, q: Point2, sq: f64) -> Point2 {
    let ((u, su), (v, sv)) =
        if (p[0], p[1]) <= (q[0], q[1]) { ((p, sp), (q, sq)) } else { ((q, sq), (p, sp)) };
    let t = su / (su - sv);
    [u[0] + t * (v[0] - u[0]), u[1] + t * (v[1] - u[1])]
}

/// (C4) Intersection of two convex counter-clockwise polygons (from
/// [`face_polygon`]); see [`ConvexClipper::clip`].
pub fn clip_polygon_polygon(subject: &[Point2], clip: &[Point2]) -> Polygon {
    ConvexClipper::new(clip).clip(subject)
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

/// A vertex within this fraction of its neighbours' chord length from the
/// chord is left out of [`stable_fan`]'s fan (and covered by a sliver): far
/// above the noise of coordinates (1e-16…1e-9 of a face), far below any
/// intended kink.
pub const NEAR_COLLINEAR: f64 = 1e-8;

/// (C4) Triangles covering the convex polygon `p`, for rules that are not
/// exact on the pieces: a fan from the vertex lowest along `apex` (a
/// slave face's [`Frame::apex_direction`]) over the vertices that are not
/// within [`NEAR_COLLINEAR`] of the chord between their neighbours, then, for
/// each run of vertices left out between two fan vertices a and b, the
/// slivers (a, r₁, r₂), …, (a, r_k, b) between the chord and the polyline.
/// The signed areas add up to the polygon's exactly, and the fan's triangles
/// change continuously with noise on the coordinates: a vertex that noise
/// splits in two adds a sliver instead of moving the apex to another corner,
/// and one that noise adds in the middle of an edge (where two nearly
/// collinear edges cross) makes a sliver instead of splitting a fan triangle
/// in two; either would move an inexact quadrature by its own error. n − 2
/// triangles for n vertices, as [`fan_triangles`].
pub fn stable_fan(p: &[Point2], apex: Point2) -> ArrayVec<[usize; 3], MAX_POLYGON> {
    let n = p.len();
    let mut out = ArrayVec::new();
    if n < 3 {
        return out;
    }
    let height = |q: Point2| q[0] * apex[0] + q[1] * apex[1];
    let first = (1..n).fold(0, |k, i| if height(p[i]) < height(p[k]) { i } else { k });
    // Vertex k of the ring that starts at the apex.
    let at = |k: usize| (first + k) % n;
    let mut fan: ArrayVec<usize, MAX_POLYGON> = ArrayVec::new();
    fan.push(at(0));
    let mut run: ArrayVec<usize, MAX_POLYGON> = ArrayVec::new();
    for k in 1..=n {
        let a = fan[fan.len() - 1];
        if k < n {
            let (pa, v, pb) = (p[a], p[at(k)], p[at(k + 1)]);
            let e = [pb[0] - pa[0], pb[1] - pa[1]];
            let twice_area = (e[0] * (v[1] - pa[1]) - e[1] * (v[0] - pa[0])).abs();
            if twice_area <= NEAR_COLLINEAR * (e[0] * e[0] + e[1] * e[1]) {
                run.push(at(k));
                continue;
            }
        }
        // The slivers between the chord a → b and the run left out.
        let b = at(k);
        for (j, &r) in run.iter().enumerate() {
            let next = run.get(j + 1).copied().unwrap_or(b);
            if next != a {
                out.push([a, r, next]);
            }
        }
        run.clear();
        if k < n {
            fan.push(b);
        }
    }
    for k in 1..fan.len().saturating_sub(1) {
        out.push([fan[0], fan[k], fan[k + 1]]);
    }
    out
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

    fn unit(v: Point3) -> Point3 {
        let n = dot(v, v).sqrt();
        [v[0] / n, v[1] / n, v[2] / n]
    }

    fn square(x0: f64, y0: f64, s: f64) -> Polygon {
        [[x0, y0], [x0 + s, y0], [x0 + s, y0 + s], [x0, y0 + s]].into_iter().collect()
    }

    fn area_of(a: &[Point2], b: &[Point2]) -> f64 {
        polygon_area(&clip_polygon_polygon(a, b))
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
        let c = clip_polygon_polygon(&s, &s);
        assert_eq!(c.len(), 4);
        assert!((polygon_area(&c) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn disjoint() {
        assert_eq!(clip_polygon_polygon(&square(0.0, 0.0, 1.0), &square(2.0, 0.0, 1.0)).len(), 0);
    }

    #[test]
    fn shared_edge() {
        let c = clip_polygon_polygon(&square(0.0, 0.0, 1.0), &square(1.0, 0.0, 1.0));
        assert!(c.len() < 3 || polygon_area(&c).abs() < 1e-15);
    }

    #[test]
    fn touching_vertex() {
        let c = clip_polygon_polygon(&square(0.0, 0.0, 1.0), &square(1.0, 1.0, 1.0));
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
        let c = clip_polygon_polygon(&diamond, &square(0.0, 0.0, 1.0));
        assert_eq!(c.len(), 8);
    }

    /// The defect of issue 31: a subject edge nearly along a clip edge, one end
    /// within the old tolerance of the line and the other beyond it, gave a
    /// crossing far outside the edge (t = −1/3) and a polygon reaching a third
    /// of a face into the neighbour. Exactly decided, the square below the
    /// line y = 0 meets the unit square in nothing, and one reaching 1e-13
    /// above it in a sliver of that height.
    #[test]
    fn an_edge_along_a_clip_edge_gives_no_wild_vertex() {
        let unit = square(0.0, 0.0, 1.0);
        let below: Polygon = [[0.0, -1.0], [1.0, -1.0], [1.0, -5e-13], [0.0, -2e-12]].into_iter().collect();
        assert!(clip_polygon_polygon(&below, &unit).is_empty());
        let sliver: Polygon = [[0.0, -1.0], [1.0, -1.0], [1.0, 1e-13], [0.0, -2e-12]].into_iter().collect();
        let c = clip_polygon_polygon(&sliver, &unit);
        let exact = 0.5 * 1e-13 * (1e-13 / (1e-13 + 2e-12));
        assert!((polygon_area(&c) - exact).abs() < 1e-27, "{c:?}");
        assert!(c.iter().all(|p| p[1] >= 0.0 && p[1] <= 1e-13 && (0.0..=1.0).contains(&p[0])), "{c:?}");
    }

    /// Vertices on edges and collinear edges are inside: a square with a
    /// corner on the clip square's edge, and one whose edge runs along it.
    #[test]
    fn on_the_line_is_inside_and_makes_no_new_vertex() {
        let unit = square(0.0, 0.0, 1.0);
        let diamond: Polygon = [[0.5, 0.0], [1.0, 0.5], [0.5, 1.0], [0.0, 0.5]].into_iter().collect();
        assert!(same_ring(&clip_polygon_polygon(&diamond, &unit), &diamond));
        let along = square(0.25, 0.0, 0.5);
        assert!(same_ring(&clip_polygon_polygon(&along, &unit), &along));
    }

    /// The two faces sharing an edge get the same crossing bits, whichever
    /// way each runs the edge.
    #[test]
    fn a_shared_edge_crosses_at_the_same_point_from_both_sides() {
        let clip = square(0.0, 0.0, 1.0);
        let (p, q) = ([0.3, -0.7], [0.9, 1.0 + 1e-9]);
        let left: Polygon = [[-1.0, -0.5], p, q, [-1.0, 2.0]].into_iter().collect();
        let right: Polygon = [p, [2.0, -0.5], [2.0, 2.0], q].into_iter().collect();
        let (a, b) = (clip_polygon_polygon(&left, &clip), clip_polygon_polygon(&right, &clip));
        let on_edge = |c: &Polygon| -> Vec<Point2> {
            c.iter()
                .copied()
                .filter(|x| x[1] == 0.0 || x[1] == 1.0)
                .filter(|x| x[0] > 0.2 && x[0] < 1.0)
                .collect()
        };
        let (mut ea, mut eb) = (on_edge(&a), on_edge(&b));
        ea.sort_by(|x, y| x[1].total_cmp(&y[1]));
        eb.sort_by(|x, y| x[1].total_cmp(&y[1]));
        assert_eq!(ea.len(), 2, "{a:?}");
        assert_eq!(ea, eb, "{a:?} {b:?}");
        assert!((polygon_area(&a) + polygon_area(&b) - 1.0).abs() < 4.0 * f64::EPSILON);
    }

    #[test]
    fn degenerate_faces_have_empty_polygons() {
        assert!(face_polygon(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).is_empty());
        assert!(face_polygon(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]]).is_empty());
        // A quad with a straight corner is its triangle.
        assert_eq!(face_polygon(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0]]).len(), 3);
    }

    #[test]
    fn strictly_convex_cleanup_removes_duplicates_collinear_points_and_dents() {
        let mut p: Polygon =
            [[0.0, 0.0], [0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.0, 1.0], [0.5, 1.0 - 1e-17], [0.0, 1.0]]
                .into_iter()
                .collect();
        make_strictly_convex(&mut p);
        assert_eq!(p.as_slice(), square(0.0, 0.0, 1.0).as_slice());
    }

    /// The stable fan covers the polygon (signed areas), keeps nearly
    /// collinear vertices out of its fan, and is the plain fan otherwise.
    #[test]
    fn stable_fan_covers_and_leaves_nearly_collinear_vertices_to_slivers() {
        let area = |p: &[Point2], t: &[[usize; 3]]| {
            t.iter().map(|&[a, b, c]| polygon_area(&[p[a], p[b], p[c]])).sum::<f64>()
        };
        let p: Polygon = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].into_iter().collect();
        let down = [0.0, 1.0];
        assert_eq!(stable_fan(&p, down).as_slice(), fan_triangles(4).collect::<Vec<_>>().as_slice());
        // Noise made vertices in the middle of the edges 1–2 and 3–0, 1e-12 off the chords.
        let q: Polygon = [[0.0, 0.0], [1.0, 0.0], [1.0 + 1e-12, 0.4], [1.0, 1.0], [0.0, 1.0], [-1e-12, 0.7]]
            .into_iter()
            .collect();
        let t = stable_fan(&q, down);
        assert_eq!(t.len(), 4);
        assert!((area(&q, &t) - polygon_area(&q)).abs() < 1e-15);
        // The fan is that of the square: the two slivers hold the rest.
        let fan: Vec<[usize; 3]> =
            t.iter().copied().filter(|&[_, b, c]| ![2, 5].contains(&b) && ![2, 5].contains(&c)).collect();
        assert_eq!(fan, vec![[0, 1, 3], [0, 3, 4]]);
    }

    /// The same vertices in the same cyclic order.
    fn same_ring(a: &[Point2], b: &[Point2]) -> bool {
        a.len() == b.len() && (0..a.len()).any(|k| (0..a.len()).all(|i| a[(i + k) % a.len()] == b[i]))
    }

    /// The fan's apex is the vertex lowest along the direction, wherever the
    /// ring starts; a vertex split in two by noise keeps it.
    #[test]
    fn the_fan_starts_at_the_lowest_vertex() {
        let apex = [0.6, 0.8];
        let h = |q: Point2| q[0] * apex[0] + q[1] * apex[1];
        let unit = square(0.0, 0.0, 1.0);
        for shift in [[0.0, 0.0], [0.3, -0.2], [-0.4, 0.5]] {
            let c = clip_polygon_polygon(&square(shift[0], shift[1], 1.0), &unit);
            let t = stable_fan(&c, apex);
            let first = c[t[t.len() - 1][0]];
            assert!(c.iter().all(|&q| h(q) >= h(first)), "{c:?} {t:?}");
        }
        let split: Polygon =
            [[1.0, 1.0], [0.0, 1.0], [-1e-13, 1e-13], [1e-13, -1e-13], [1.0, 0.0]].into_iter().collect();
        let t = stable_fan(&split, apex);
        let first = split[t[t.len() - 1][0]];
        assert!(first[0].abs() < 1e-12 && first[1].abs() < 1e-12, "{t:?}");
        assert_eq!(t.len(), 3);
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
            prop_assert_eq!(clip_polygon_polygon(&a, &shifted).len(), 0);
        }
    }
}
