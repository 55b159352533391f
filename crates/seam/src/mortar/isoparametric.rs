//! (C2)–(D5) for pairs with a second-order (curved) face.
//!
//! The projections of curved faces onto the slave plane have curved edges, so
//! the exact intersection is not a polygon. Each face is replaced, for the
//! segmentation only, by k × k first-order sub-faces through points of the
//! true face (C3; k = 1: its corners); sub-face pairs are clipped as convex
//! polygons (C4) and fan-triangulated; quadrature points are placed in the
//! plane on each triangle.
//!
//! - Slave side: a point p of the projected slave sub-face S (a triangle or a
//!   quad of the plane) is taken back to the slave's reference cell by the
//!   inverse of S's own first-order map χ_S (reference sub-face → projected
//!   sub-face, affine or bilinear): a bijection, so the pieces of a fully
//!   covered face tile its reference cell exactly, and the covered area is the
//!   true area of the curved slave face. The weight is the slave's true area
//!   element, ω'_l = ω_l |T| |J_s(ξ_s)| / |det ∂χ_S/∂ξ| (D3–D4).
//! - Master side: the slave point x_s(ξ_s) is inverse-projected along the
//!   slave normal onto the *true* curved master face (D1–D2, Newton on
//!   P x_m(ξ_m) = P x_s(ξ_s)).
//!
//! So D and B integrate ψ_p λ_q over the covered part of the true slave
//! surface; the chords only decide which master face a point belongs to and
//! where the coverage ends. A projected edge leaves its chord by its in-plane
//! sagitta δ ≈ κ_g h²/(8k²) (κ_g the edge's geodesic curvature: zero for the
//! straight lines of a cylinder). Between two master faces this is invisible
//! to a continuous master field: a point δ beyond the shared edge reads the
//! neighbour's polynomial, which differs from the face's by O(δ h² |f'''|)
//! (single entries of B do move, by O(δ/h) of their size, between the nodes
//! of the two faces).
//! Where the coverage ends (the master surface's boundary, a feature edge, a
//! gap or angle cut-off) it moves the covered area by O(δ) per unit length.
//! So a slave face is segmented with k = 1 first, and again with
//! k = [`SUBDIVISION`] only if that leaves part of its chord polygon
//! uncovered (BENCHMARKS.md: the covered area of partly covered faces
//! converges like h² with a constant ∝ 1/k²; the k = 1 pass makes the
//! general path about 3.4× faster).
//!
//! I1 (D·1 = B·1) and I2 hold to round-off whatever the rule, since D and B
//! use the same points and Σ_q λ^m_q = 1.

use super::pieces::{add_point, barycentric, edge_midpoints, signed_area, Piece};
use super::{FaceStats, Facing, Segment};
use crate::catalogue::{shape_and_gradients, shape_values, FaceKind, Xi};
use crate::clip::{face_polygon, polygon_area, stable_fan, ConvexClipper, Frame, MAX_POLYGON};
use crate::curved::{monomials_of, CurvedFace, MonomialMap, ProjectedFace};
use crate::element::{cross, dot, norm, PlaneFace};
use crate::mesh::Point3;
use crate::quadrature::TriangleRule;
use arrayvec::ArrayVec;

/// The most nodes of a face (Quad9).
pub(super) const MAX_NODES: usize = 9;

/// Sub-faces per reference edge for the segmentation (C3) of a slave face
/// that the end of the coverage crosses.
pub(super) const SUBDIVISION: usize = 2;

const MAX_SUB: usize = SUBDIVISION * SUBDIVISION;

/// (D3) on the curved path: the triangle-rule degree by the fold ratio r of a
/// plane triangle under the chords' first-order maps ([`PlaneFace::fold_ratio`],
/// the larger of the slave's and the master's), (largest r, degree); above the
/// last entry the triangle is cut into four. Degree 8 integrates ψ_p ψ_q of D
/// exactly on affine Quad9 faces (r = 0: triangles and parallelograms); on
/// other quads ψ_p(χ⁻¹(q)) is analytic but not a polynomial in the plane point
/// q. Calibrated by the lowest degree that integrates the hardest integrand,
/// the Quad9 products λ_p λ_r(χ⁻¹(q)) of D, to 1e-12 of the largest moment per
/// range of r, one rung finer; test `curved_ladder_accuracy` checks it on
/// another sample (worst 8.7e-13).
pub(super) const CURVED_LADDER: [(f64, usize); 6] =
    [(5e-4, 8), (5e-3, 10), (0.03, 12), (0.1, 14), (0.3, 18), (0.8, 20)];

/// Most levels of cutting a plane triangle into four.
pub(super) const CURVED_MAX_DEPTH: u32 = 8;

/// A sub-face of the reference cell: its corners in reference coordinates.
type SubFace = ArrayVec<Xi, 4>;

/// The first-order sub-faces of the reference cell of `kind`, `k` (1 or
/// [`SUBDIVISION`]) per edge, corners counter-clockwise (tabulated once).
fn reference_subfaces(kind: FaceKind, k: usize) -> &'static [SubFace] {
    type Table = [[ArrayVec<SubFace, MAX_SUB>; 2]; FaceKind::ALL.len()];
    static TABLE: std::sync::OnceLock<Table> = std::sync::OnceLock::new();
    let table = TABLE.get_or_init(|| FaceKind::ALL.map(|kind| [1, SUBDIVISION].map(|k| subdivide(kind, k))));
    &table[kind as usize][usize::from(k != 1)]
}

fn subdivide(kind: FaceKind, k: usize) -> ArrayVec<SubFace, MAX_SUB> {
    // A first-order face's projection is its own polygon: no sub-faces.
    let k = if kind.order() == 1 { 1 } else { k };
    let at = |i: usize, j: usize| [i as f64 / k as f64, j as f64 / k as f64];
    let mut out = ArrayVec::new();
    for j in 0..k {
        for i in 0..k {
            if kind.is_triangle() {
                if i + j < k {
                    out.push([at(i, j), at(i + 1, j), at(i, j + 1)].into_iter().collect());
                }
                if i + j + 1 < k {
                    out.push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)].into_iter().collect());
                }
            } else {
                out.push([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)].into_iter().collect());
            }
        }
    }
    out
}

fn centroid(sub: &SubFace) -> Xi {
    let n = sub.len() as f64;
    let s = sub.iter().fold([0.0; 2], |a, x| [a[0] + x[0], a[1] + x[1]]);
    [s[0] / n, s[1] / n]
}

/// The projected sub-faces of `face` of `kind`: (reference corners, convex
/// polygon, the first-order map of a quad sub-face for its fold ratio).
fn projected_subfaces(
    kind: FaceKind,
    face: &ProjectedFace,
    k: usize,
) -> ArrayVec<(&'static SubFace, crate::clip::Polygon, Option<PlaneFace>), MAX_SUB> {
    reference_subfaces(kind, k)
        .iter()
        .map(|sub| {
            let q: ArrayVec<[f64; 2], 4> = sub.iter().map(|&xi| face.map.map(xi)).collect();
            let chord = (q.len() == 4).then(|| PlaneFace::new(FaceKind::Quad4, [q[0], q[1], q[2], q[3]]));
            (sub, face_polygon(&q), chord)
        })
        .collect()
}

/// A projected slave sub-face: where it lies in the reference cell, its map
/// χ_S from there to the plane, and its clipper.
struct SlaveSub {
    /// The first corner ξ₀ and the reference edge vectors (ξ₁ − ξ₀, ξ_last − ξ₀).
    origin: Xi,
    edges: [Xi; 2],
    /// |det| of the reference sub-face's map from the unit cell.
    ref_det: f64,
    /// χ_S as a map from the unit triangle or square.
    chord: PlaneFace,
    clipper: ConvexClipper,
}

impl SlaveSub {
    /// The chord's coordinates u = χ_S⁻¹(p) of plane point `p`, ξ_s there and
    /// the area ratio |det ∂ξ_s/∂p|.
    #[inline]
    fn pull_back(&self, p: [f64; 2], stats: &mut FaceStats) -> (Xi, Xi, f64) {
        let r = self.chord.inverse(p);
        if matches!(r, crate::element::InverseMap::NotConverged { .. }) {
            stats.inverse_failures += 1;
        }
        let u = r.xi();
        let xi = [
            self.origin[0] + u[0] * self.edges[0][0] + u[1] * self.edges[1][0],
            self.origin[1] + u[0] * self.edges[0][1] + u[1] * self.edges[1][1],
        ];
        (u, xi, self.ref_det / self.chord.det(u).abs())
    }
}

/// A slave face prepared for pairing on the general path.
pub(super) struct CurvedSlave {
    pub(super) face: CurvedFace,
    /// The face's map in monomials, for the quadrature points.
    map: MonomialMap<3>,
    pub(super) frame: Frame,
    subfaces: ArrayVec<SlaveSub, MAX_SUB>,
    /// Sub-faces per reference edge, of this face and of its masters.
    pub(super) subdivision: usize,
    /// Area of the chord polygons in the plane.
    pub(super) chord_area: f64,
    pub(super) gap_tol: f64,
    area_tol: f64,
}

impl CurvedSlave {
    /// (B1)–(C2): the frame at the face centre, normal the true normal there;
    /// `k` sub-faces per reference edge.
    pub(super) fn new(face: CurvedFace, k: usize, gap_tol: f64, area_rtol: f64) -> CurvedSlave {
        let centre = face.kind.centre();
        let frame = Frame::householder(face.normal(centre), face.map(centre));
        let mut area = 0.0;
        let subfaces = reference_subfaces(face.kind, k)
            .iter()
            .map(|sub| {
                let mut q = [[0.0; 2]; 4];
                for (i, &xi) in sub.iter().enumerate() {
                    q[i] = frame.project(face.map(xi));
                }
                let kind = if sub.len() == 3 { FaceKind::Tri3 } else { FaceKind::Quad4 };
                if kind == FaceKind::Tri3 {
                    q[3] = q[2];
                }
                let polygon = face_polygon(&q[..sub.len()]);
                area += polygon_area(&polygon);
                let last = sub[sub.len() - 1];
                let edges = [
                    [sub[1][0] - sub[0][0], sub[1][1] - sub[0][1]],
                    [last[0] - sub[0][0], last[1] - sub[0][1]],
                ];
                SlaveSub {
                    origin: sub[0],
                    edges,
                    ref_det: (edges[0][0] * edges[1][1] - edges[0][1] * edges[1][0]).abs(),
                    chord: PlaneFace::new(kind, q),
                    clipper: ConvexClipper::new(&polygon),
                }
            })
            .collect();
        CurvedSlave {
            face,
            map: MonomialMap::new(face.kind, &face.x),
            frame,
            subfaces,
            subdivision: k,
            chord_area: area,
            gap_tol,
            area_tol: area_rtol * area,
        }
    }

    /// The unit normal of the frame (C2).
    pub(super) fn normal(&self) -> Point3 {
        self.frame.normal()
    }
}

/// What one curved pair contributes: n_s × n_s and n_s × n_m blocks.
#[derive(Clone, Copy)]
pub(super) struct CurvedBlock {
    pub(super) d: [[f64; MAX_NODES]; MAX_NODES],
    pub(super) b: [[f64; MAX_NODES]; MAX_NODES],
    pub(super) covered_area: f64,
    /// Area of the clipped polygons in the plane.
    pub(super) plane_area: f64,
    pub(super) segments: u32,
}

/// The angle filter of (C1): whether master normal `nm` faces the slave normal.
pub(super) fn facing_ok(facing: Facing, ns: Point3, nm: Point3, cos_max: f64) -> bool {
    let cos = dot(ns, nm);
    let aligned = match facing {
        Facing::Any => cos.abs(),
        Facing::Opposite => -cos,
    };
    aligned >= cos_max
}

impl CurvedBlock {
    /// All zero.
    pub(super) const ZERO: CurvedBlock = CurvedBlock {
        d: [[0.0; MAX_NODES]; MAX_NODES],
        b: [[0.0; MAX_NODES]; MAX_NODES],
        covered_area: 0.0,
        plane_area: 0.0,
        segments: 0,
    };
}

/// (C3)–(D5) for the slave face `cs` against master face `master` into
/// `block` (overwritten); false when the projections do not overlap
/// (`stats.empty`) or a point pair is farther apart than the gap limit
/// (`stats.rejected_gap`).
pub(super) fn pair(
    cs: &CurvedSlave,
    master: &CurvedFace,
    ladder: &[TriangleRule; CURVED_LADDER.len()],
    stats: &mut FaceStats,
    mut record: Option<(&mut Vec<Segment>, usize, usize)>,
    block: &mut CurvedBlock,
) -> bool {
    let (ks, km) = (cs.face.kind, master.kind);
    let n_s = ks.n_nodes();
    *block = CurvedBlock::ZERO;
    let (mut gap, mut overlap) = (0.0f64, 0.0f64);
    let mut any = false;
    let projected = ProjectedFace::new(master, &cs.frame);
    for (msub, q, master_chord) in projected_subfaces(km, &projected, cs.subdivision) {
        let guess_m = centroid(msub);
        // ξ_m ↦ the master chord's coordinates (quad sub-faces are squares).
        let side = msub[1][0] - msub[0][0];
        let master_chord = master_chord.map(|chord| (chord, msub[0], side));
        for sub in &cs.subfaces {
            let polygon = sub.clipper.clip(&q);
            let piece_area = polygon_area(&polygon);
            if polygon.len() < 3 || piece_area <= cs.area_tol {
                continue;
            }
            any = true;
            block.plane_area += piece_area;
            let mut us = [[0.0; 2]; MAX_POLYGON];
            let mut xs = [[0.0; 2]; MAX_POLYGON];
            let mut xm = [[0.0; 2]; MAX_POLYGON];
            for (v, &p) in polygon.iter().enumerate() {
                (us[v], xs[v], _) = sub.pull_back(p, stats);
                let x = cs.map.map(xs[v]);
                xm[v] = inverse(&projected, cs.frame.project(x), guess_m, stats);
                let g = projected.height.map(xm[v])[0] - cs.frame.height(x);
                if g.abs() > cs.gap_tol {
                    stats.rejected_gap += 1;
                    return false;
                }
                gap = gap.max(g);
                overlap = overlap.max(-g);
            }
            for [a, b, c] in stable_fan(&polygon, cs.frame.apex_direction()) {
                let plane = [polygon[a], polygon[b], polygon[c]];
                if signed_area(plane) <= 0.0 {
                    continue;
                }
                block.segments += 1;
                let triangle = Piece { q: plane, xs: [us[a], us[b], us[c]], xm: [xm[a], xm[b], xm[c]] };
                let mut segment = CurvedSegment {
                    cs,
                    sub,
                    master: &projected,
                    master_chord: master_chord.as_ref(),
                    kinds: (ks, km),
                    ladder,
                    stats: &mut *stats,
                };
                segment.integrate_kinds(triangle, block);
                if let Some((segments, s, m)) = record.as_mut() {
                    let corners = [xs[a], xs[b], xs[c]].map(|xi| cs.map.map(xi));
                    segments.push(Segment { slave: *s, master: *m, corners });
                }
            }
        }
    }
    if !any || block.segments == 0 {
        stats.empty += 1;
        return false;
    }
    stats.max_gap = stats.max_gap.max(gap);
    stats.max_overlap = stats.max_overlap.max(overlap);
    for p in 0..n_s {
        for q in 0..p {
            block.d[p][q] = block.d[q][p];
        }
    }
    true
}

/// (D3)–(D5) on the plane triangles of one clipped polygon of a curved pair.
struct CurvedSegment<'a> {
    cs: &'a CurvedSlave,
    sub: &'a SlaveSub,
    master: &'a ProjectedFace,
    /// The master sub-face's first-order map, its corner ξ₀ and side (quads).
    master_chord: Option<&'a (PlaneFace, Xi, f64)>,
    kinds: (FaceKind, FaceKind),
    ladder: &'a [TriangleRule; CURVED_LADDER.len()],
    stats: &'a mut FaceStats,
}

impl CurvedSegment<'_> {
    /// The larger fold ratio of the slave's and the master's chord over `t`.
    fn fold_ratio(&self, t: &Piece) -> f64 {
        let slave = self.sub.chord.fold_ratio(&t.xs);
        let master = self.master_chord.map_or(0.0, |(chord, o, side)| {
            chord.fold_ratio(&t.xm.map(|x| [(x[0] - o[0]) / side, (x[1] - o[1]) / side]))
        });
        slave.max(master)
    }

    /// [`CurvedSegment::integrate`] specialised on the node counts of the
    /// pair's kinds (fixed-size shape arrays, face maps over the monomials
    /// they use).
    fn integrate_kinds(&mut self, t: Piece, block: &mut CurvedBlock) {
        macro_rules! by_nodes {
            ($(($ns:literal, $nm:literal)),*) => {
                match (self.kinds.0.n_nodes(), self.kinds.1.n_nodes()) {
                    $(($ns, $nm) => self.integrate::<$ns, $nm>(t, 0, block),)*
                    _ => unreachable!("faces have 3, 4, 6, 7, 8 or 9 nodes"),
                }
            };
        }
        by_nodes!(
            (3, 3),
            (3, 4),
            (3, 6),
            (3, 8),
            (3, 9),
            (4, 3),
            (4, 4),
            (4, 6),
            (4, 8),
            (4, 9),
            (6, 3),
            (6, 4),
            (6, 6),
            (6, 8),
            (6, 9),
            (8, 3),
            (8, 4),
            (8, 6),
            (8, 8),
            (8, 9),
            (9, 3),
            (9, 4),
            (9, 6),
            (9, 8),
            (9, 9),
            (3, 7),
            (4, 7),
            (6, 7),
            (8, 7),
            (9, 7),
            (7, 3),
            (7, 4),
            (7, 6),
            (7, 7),
            (7, 8),
            (7, 9)
        )
    }

    /// The rule of [`CURVED_LADDER`] for `t`, or its four children.
    fn integrate<const NS: usize, const NM: usize>(&mut self, t: Piece, depth: u32, block: &mut CurvedBlock) {
        let r = self.fold_ratio(&t);
        let rule = match CURVED_LADDER.iter().position(|&(max, _)| r <= max) {
            Some(i) => Some(&self.ladder[i]),
            None if depth == CURVED_MAX_DEPTH => self.ladder.last(),
            None => None,
        };
        if let Some(rule) = rule {
            return self.accumulate::<NS, NM>(&t, rule, block);
        }
        let (m, guesses) = (t.midpoints(), edge_midpoints(t.xm));
        let mut mu = [[0.0; 2]; 3];
        let mut mm = [[0.0; 2]; 3];
        for k in 0..3 {
            let (u, xi_s, _) = self.sub.pull_back(m[k], self.stats);
            let target = self.cs.frame.project(self.cs.map.map(xi_s));
            (mu[k], mm[k]) = (u, inverse(self.master, target, guesses[k], self.stats));
        }
        let children = t.children(mu, mm);
        for child in children {
            self.integrate::<NS, NM>(child, depth + 1, block);
        }
    }

    /// The points of `rule` on `t`: ξ_s by the slave chord's inverse, ξ_m by
    /// Newton onto the true master face from the interpolated corners; an
    /// `NS`-node slave and an `NM`-node master face.
    #[inline(always)]
    fn accumulate<const NS: usize, const NM: usize>(
        &mut self,
        t: &Piece,
        rule: &TriangleRule,
        block: &mut CurvedBlock,
    ) {
        let cs = self.cs;
        let area = signed_area(t.q);
        let (slave_monomials, master_monomials) = (monomials_of(NS), monomials_of(NM));
        for (pt, &w) in rule.points.iter().zip(rule.weights) {
            let (_, xi_s, ratio) = self.sub.pull_back(barycentric(t.q, *pt), self.stats);
            let phi: [f64; NS] = shape_values(xi_s);
            let (x, ta, tb) = cs.map.map_and_tangents_first(xi_s, slave_monomials);
            let target = cs.frame.project(x);
            let (xi_m, converged) =
                self.master.inverse_first(target, barycentric(t.xm, *pt), master_monomials);
            self.stats.inverse_failures += u32::from(!converged);
            let wj = w * area * ratio * norm(cross(ta, tb));
            let lam: [f64; NM] = shape_values(xi_m);
            block.covered_area += wj;
            add_point(&mut block.d, &mut block.b, wj, &phi, &lam);
        }
    }
}

fn inverse(face: &ProjectedFace, p: [f64; 2], guess: Xi, stats: &mut FaceStats) -> Xi {
    let (xi, converged) = face.inverse(p, guess);
    if !converged {
        stats.inverse_failures += 1;
    }
    xi
}

/// ∫_e λ_p |J| over the whole curved face, with `rule` on its reference
/// triangles (one for a triangle, two for a quad); these only tell how much
/// of each node's support is covered.
pub(super) fn face_integrals(face: &CurvedFace, rule: &TriangleRule) -> [f64; MAX_NODES] {
    let triangles: &[[Xi; 3]] = if face.kind.is_triangle() {
        &[[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]]
    } else {
        &[[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]]
    };
    let map = MonomialMap::new(face.kind, &face.x);
    let mut full = [0.0; MAX_NODES];
    for t in triangles {
        for (pt, &w) in rule.points.iter().zip(rule.weights) {
            let xi = barycentric(*t, *pt);
            let phi = shape_and_gradients(face.kind, xi).0;
            let (_, a, b) = map.map_and_tangents(xi);
            let wj = 0.5 * w * norm(cross(a, b));
            for p in 0..face.kind.n_nodes() {
                full[p] += wj * phi[p];
            }
        }
    }
    full
}

/// The box of the face's control net (which encloses the curved face) moved
/// by ±`reach` along `normal` (A1).
pub(super) fn control_box(face: &CurvedFace, normal: Point3, reach: f64) -> (Point3, Point3) {
    let (net, n) = face.control_net();
    crate::search::swept_box(&net[..n], normal, reach)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sub_faces_tile_the_reference_cell() {
        for kind in [FaceKind::Tri6, FaceKind::Quad9] {
            let area: f64 = reference_subfaces(kind, SUBDIVISION)
                .iter()
                .map(|s| {
                    let p: ArrayVec<[f64; 2], 4> = s.iter().copied().collect();
                    polygon_area(&p)
                })
                .sum();
            let expected = if kind.is_triangle() { 0.5 } else { 1.0 };
            assert!((area - expected).abs() < 1e-15, "{kind:?}: {area}");
        }
    }
}
