//! The per-slave-face kernel: (B1)–(C6) for one slave face against its
//! candidate master faces.
//!
//! Symbols: `es`, `em` slave and master elements; `frame` the Householder frame
//! of `es` (C2); `xs`, `xm` reference coordinates on the slave and master face of
//! each polygon vertex (D1–D2); `phi` = slave shape values λ^s, `lam` = master
//! shape values λ^m; `wj` = ω'_l (D4). Blocks are built for ψ = λ (standard);
//! dual and lumped multipliers transform them per face afterwards
//! (`multiplier`).

use super::isoparametric::{self, CurvedBlock, CurvedSlave, MAX_NODES};
use super::multiplier::{apply_multiplier, FaceMeasures};
use super::pieces::{add_b, add_d, add_point, barycentric, signed_area, Piece};
use super::rows::Blocks;
use super::{face_integrals, warped_quad_degree, FaceStats, MortarOptions, Segment};
use crate::catalogue::{FaceKind, Xi};
use crate::clip::{face_polygon, fan_triangles, polygon_area, stable_fan, ConvexClipper, Frame, MAX_POLYGON};
use crate::curved::CurvedFace;
use crate::element::{FaceElement, InverseMap, JacobianField, PlaneFace, PLANAR_WARP};
use crate::mesh::{Point3, SurfaceMesh};
use crate::quadrature::{triangle_rule, TriangleRule};
use crate::search::{swept_box, FaceTree};
use rayon::prelude::*;

/// Intersection polygons with area below `AREA_RTOL ·` (projected slave area)
/// are dropped: slivers along shared edges of nearly matching meshes, whose
/// share of any entry is below round-off of the face's. The clipping (C4)
/// itself decides every configuration exactly ([`crate::clip`]); this is the
/// only threshold of the segmentation, and it can only drop area (never add
/// it).
const AREA_RTOL: f64 = 1e-12;

/// A first-order slave face with an affine |J| whose pairs cover its area to
/// this relative tolerance (round-off of the segments' tiling) is fully
/// covered: its D block is the face's own mass matrix ([`face_mass`]) instead
/// of the sum over its segments. D·1 and B·1 then differ by at most this
/// relative amount, so I1 keeps holding to round-off; a face with a sliver
/// uncovered beyond it takes its D from the segments, as B.
const FULL_COVER_RTOL: f64 = 1e-14;

/// A curved slave face whose clipped polygons cover less than 1 − this of its
/// chord polygons is segmented again with sub-faces (the coverage ends inside).
const COVER_RTOL: f64 = 1e-9;

/// Neighbouring first-order slave faces (consecutive indices, aligned so
/// that a group never spans two chunks of the assembly) whose candidates come
/// from one tree query of their union box, each face then filtering the
/// union's candidates by its own box (A1): the same candidates as a query
/// per face, for about a third of the tree walks.
const GROUP: usize = 4;

/// A group is queried as one only if the sum of its union box's extents is at
/// most this many times the largest of its faces': consecutive faces that are
/// not neighbours (a scattered numbering) are queried one by one.
const GROUP_SPREAD: f64 = 3.5;

/// The quadrature rules by integrand (D3): exact for polynomial integrands.
pub(super) struct Rules {
    /// Slave Tri3 × master Tri3: ψλ is degree 2.
    tri_tri: TriangleRule,
    /// Slave Tri3 × master Quad4: degree 1 × 2.
    tri_quad: TriangleRule,
    /// Planar slave quad: ψ (2) × λ (2) × |J| (1, affine on a planar quad).
    planar_quad: TriangleRule,
    /// Parallelogram slave quad: |J| is constant, ψ (2) × λ (≤ 2).
    parallelogram: TriangleRule,
    /// Warped slave quad: |J| is not a polynomial; the rule is fixed by the
    /// options or chosen per face.
    fixed_warped: Option<TriangleRule>,
    /// Pairs with a second-order face ([`isoparametric::CURVED_LADDER`]).
    curved: [TriangleRule; isoparametric::CURVED_LADDER.len()],
    /// The rules of [`PLANE_LADDER`], in its order.
    plane: [TriangleRule; PLANE_LADDER.len()],
}

/// (D3) in the projection plane, for pairs whose projected faces are not both
/// affine: the triangle-rule degree by the fold ratio r of a plane triangle
/// ([`PlaneFace::fold_ratio`], the larger of the slave's and the master's),
/// (largest r, degree); a triangle with r above the last entry is cut into
/// four. The integrand ψ_p(ξ_s(q)) λ_q(ξ_m(q)) is analytic but not polynomial
/// in the plane point q, singular on the fold; test `plane_ladder_accuracy`
/// shows each piece integrated to 1e-12 of its largest moment, for the
/// hardest integrand, λ_p λ_q (ξ_s(q)) of D.
pub(super) const PLANE_LADDER: [(f64, usize); 4] = [(0.2, 12), (0.4, 14), (0.6, 18), (0.8, 20)];

/// Most levels of cutting a plane triangle into four (a fold through a
/// vertex, det = 0 there, would ask for infinitely many).
const PLANE_MAX_DEPTH: u32 = 8;

impl Rules {
    fn new(warped_degree: Option<usize>) -> Rules {
        Rules {
            tri_tri: rule(2),
            tri_quad: rule(3),
            planar_quad: rule(5),
            parallelogram: rule(4),
            fixed_warped: warped_degree.map(rule),
            curved: isoparametric::CURVED_LADDER.map(|(_, degree)| rule(degree)),
            plane: PLANE_LADDER.map(|(_, degree)| rule(degree)),
        }
    }

    /// The plane rule for fold ratio `r`, at least as fine as `base` (the
    /// polynomial or warped-quad rule); `None` when the triangle must be cut.
    fn plane(&self, r: f64, base: &TriangleRule) -> Option<TriangleRule> {
        let i = PLANE_LADDER.iter().position(|&(max, _)| r <= max)?;
        Some(if base.degree > self.plane[i].degree { *base } else { self.plane[i] })
    }

    fn select(&self, slave: &SlaveFace, master: FaceKind) -> TriangleRule {
        match (slave.element.kind, master) {
            (FaceKind::Tri3, FaceKind::Tri3) => self.tri_tri,
            (FaceKind::Tri3, _) => self.tri_quad,
            _ => match slave.warped_rule {
                Some(warped) => warped,
                None if slave.jacobian.is_constant() => self.parallelogram,
                None => self.planar_quad,
            },
        }
    }
}

/// (A1) The search box of first-order slave face `f`: its corners' box swept
/// by the gap limit along its normal.
fn flat_search_box(slave: &SurfaceMesh, f: usize, options: &MortarOptions) -> (Point3, Point3) {
    let element = FaceElement::of(slave, f);
    swept_box(element.corners(), element.normal(), options.max_gap.at(element.diameter()))
}

/// The gap limit of slave face `face` on the curved path, for its size h:
/// the largest distance of a node from the first corner.
fn curved_gap_tol(face: &CurvedFace, options: &MortarOptions) -> f64 {
    let x0 = face.x[0];
    let h = face.nodes().iter().fold(0.0f64, |m, &x| m.max(crate::element::norm(crate::element::sub(x, x0))));
    options.max_gap.at(h)
}

/// A box enclosing every search box the kernel may use for slave face `f`
/// (a first-order face takes the curved path against a curved master).
pub(super) fn search_box(slave: &SurfaceMesh, f: usize, options: &MortarOptions) -> (Point3, Point3) {
    let face = CurvedFace::of(slave, f);
    // (A1) on the curved path: the control net's box swept by the gap limit
    // along the normal at the centre.
    let (lo, hi) =
        isoparametric::control_box(&face, face.normal(face.kind.centre()), curved_gap_tol(&face, options));
    match slave.faces()[f].is_curved() {
        true => (lo, hi),
        false => {
            let (a, b) = flat_search_box(slave, f, options);
            (std::array::from_fn(|k| lo[k].min(a[k])), std::array::from_fn(|k| hi[k].max(b[k])))
        }
    }
}

fn rule(degree: usize) -> TriangleRule {
    triangle_rule(degree).expect("degree checked against MAX_TRIANGLE_DEGREE")
}

/// Everything the per-face work reads.
pub(super) struct Kernel<'a> {
    master: &'a SurfaceMesh,
    tree: &'a FaceTree,
    slave: &'a SurfaceMesh,
    options: &'a MortarOptions,
    rules: Rules,
    cos_max_angle: f64,
    /// Unit normals of the master faces (at the centre for curved faces).
    master_normals: Vec<Point3>,
    /// The master surface has second-order faces: every pair takes the
    /// general path of [`isoparametric`].
    curved_master: bool,
    /// The weight α of the basis transformation of the slave's second-order
    /// faces, if they get one ([`super::BASIS_ALPHA`]).
    transform: Option<f64>,
}

/// Buffers reused from face to face (one per chunk of faces, never per pair).
#[derive(Default)]
pub(super) struct Scratch {
    candidates: Vec<usize>,
    /// The straight segments of the current slave face (slave reference
    /// triangle, signed reference area): their D is integrated only if the
    /// face turns out partly covered.
    straight: Vec<([Xi; 3], f64)>,
    /// The slave faces of the current group ([`GROUP`]) and their swept boxes;
    /// when `grouped`, `slots` holds the tree slots meeting their union,
    /// otherwise the faces are queried one by one.
    group: std::ops::Range<usize>,
    group_boxes: [(Point3, Point3); GROUP],
    grouped: bool,
    slots: Vec<u32>,
    /// Master points touched by this slave face (the block's columns): one
    /// per pair and master node while pairs are added, then merged.
    cols: Vec<usize>,
    /// Column-major n_s × |cols| block of B: `b[j * n_s + p]`.
    b: Vec<f64>,
    /// The merge's order, as keys (master point << 32 | position; points fit
    /// in 32 bits, checked in `assemble_with_tree`), and output.
    order: Vec<u64>,
    merged_cols: Vec<usize>,
    merged_b: Vec<f64>,
}

/// A slave face prepared for pairing: its element, frame and projection.
struct SlaveFace {
    element: FaceElement,
    /// The rule of a warped quad (`None` for triangles and planar quads).
    warped_rule: Option<TriangleRule>,
    jacobian: JacobianField,
    /// Heights n·(x_i − o) of the corners above the frame's plane.
    heights: [f64; 4],
    /// ±1: the orientation of the slave's map ξ ↦ plane, at the face centre.
    orientation: f64,
    /// On a planar face, the constant |J_s| / |det ∂χ_s/∂ξ| (area of the face
    /// over area of its projection), taken as the ratio of the two areas so
    /// that pieces tiling the face add up to its area to round-off.
    area_ratio: Option<f64>,
    /// ∫_e λ_p |J| over the whole face.
    full: [f64; 4],
    frame: Frame,
    plane: PlaneFace,
    clipper: ConvexClipper,
    gap_tol: f64,
    area_tol: f64,
}

/// What one pair (F_s, F_m) contributes, on the stack.
#[derive(Default)]
struct PairBlock {
    /// n_s × n_s: `d[p][q]`.
    d: [[f64; 4]; 4],
    /// B's n_s × n_m block by columns: `b[q][p]`.
    b: [[f64; 4]; 4],
    covered_area: f64,
    segments: u32,
    /// Whether `d` holds the pair's D (segments in the plane; a straight
    /// segment's D is left to [`Kernel::flat_face`]).
    has_d: bool,
}

impl PairBlock {
    /// Adds `other`'s blocks and covered area (not its segment count).
    fn add(&mut self, other: &PairBlock) {
        for p in 0..4 {
            for q in 0..4 {
                self.d[p][q] += other.d[p][q];
                self.b[p][q] += other.b[p][q];
            }
        }
        self.covered_area += other.covered_area;
    }
}

impl<'a> Kernel<'a> {
    pub(super) fn new(
        master: &'a SurfaceMesh,
        tree: &'a FaceTree,
        slave: &'a SurfaceMesh,
        options: &'a MortarOptions,
        transform: Option<f64>,
    ) -> Self {
        Kernel {
            master,
            tree,
            slave,
            options,
            rules: Rules::new(options.warped_quad_degree),
            cos_max_angle: options.max_angle_degrees.to_radians().cos(),
            master_normals: (0..master.n_faces())
                .into_par_iter()
                .map(|m| match master.faces()[m].is_curved() {
                    true => {
                        let face = CurvedFace::of(master, m);
                        face.normal(face.kind.centre())
                    }
                    false => FaceElement::of(master, m).normal(),
                })
                .collect(),
            curved_master: master.faces().iter().any(|f| f.is_curved()),
            transform,
        }
    }

    /// (B1)–(B2) for slave face `s`; appends its block to `out`.
    pub(super) fn face(&self, s: usize, scratch: &mut Scratch, out: &mut Blocks) {
        let n_s = self.slave.faces()[s].len();
        let mut stats = FaceStats::default();
        let mut d = [0.0; MAX_NODES * MAX_NODES];
        scratch.cols.clear();
        scratch.b.clear();
        let full = if self.curved_master || self.slave.faces()[s].is_curved() {
            self.curved_face(s, scratch, out, &mut d, &mut stats)
        } else {
            self.flat_face(s, scratch, out, &mut d, &mut stats)
        };
        stats.area += full.iter().sum::<f64>();
        scratch.merge_columns(n_s);
        let kind = self.slave.faces()[s].kind();
        let measures = FaceMeasures::new(kind, self.transform, &d, &full);
        let dual_fallback =
            apply_multiplier(self.options.multiplier, kind, self.transform, &mut d, &mut scratch.b);
        stats.dual_fallbacks = dual_fallback as u32;
        out.push(&scratch.cols, &scratch.b, &d, n_s, &measures, stats);
    }

    /// The first-order path: returns the full-face integrals ∫_e λ_p |J|.
    fn flat_face(
        &self,
        s: usize,
        scratch: &mut Scratch,
        out: &mut Blocks,
        d: &mut [f64; MAX_NODES * MAX_NODES],
        stats: &mut FaceStats,
    ) -> [f64; MAX_NODES] {
        let sf = self.prepare(s);
        let n_s = sf.element.n_nodes();
        self.flat_candidates(s, scratch);
        stats.candidates = scratch.candidates.len() as u32;
        scratch.straight.clear();
        let mut pair = PairBlock::default();
        for k in 0..scratch.candidates.len() {
            let m = scratch.candidates[k];
            let record = self.options.record_segments.then_some(&mut out.segments);
            if !self.pair(&sf, s, m, stats, record, &mut scratch.straight, &mut pair) {
                continue;
            }
            let nodes = self.master.faces()[m].nodes();
            let pair_d = pair.has_d.then_some(&pair.d);
            scratch.add_pair(d, stats, n_s, nodes, (pair_d, &pair.b), (pair.covered_area, pair.segments));
        }
        // (D4) for D: the face's mass matrix, in closed form, if it is fully
        // covered (the common case), else its covered part, segment by segment
        // (a warped quad always: its rule is calibrated on segments).
        let area: f64 = sf.full.iter().sum();
        let full_mass = match sf.jacobian {
            JacobianField::Affine(j) if (stats.covered_area - area).abs() <= FULL_COVER_RTOL * area => {
                Some(face_mass(sf.element.kind, j))
            }
            _ => None,
        };
        if let Some(mass) = full_mass {
            for p in 0..n_s {
                d[p * MAX_NODES..p * MAX_NODES + n_s].copy_from_slice(&mass[p][..n_s]);
            }
        } else {
            let rule = self.rules.select(&sf, FaceKind::Tri3);
            let mut block = [[0.0; 4]; 4];
            for &(ts, area_ref) in &scratch.straight {
                if sf.element.kind == FaceKind::Tri3 {
                    accumulate_d::<3>(&sf.jacobian, ts, area_ref, &rule, &mut block)
                } else {
                    accumulate_d::<4>(&sf.jacobian, ts, area_ref, &rule, &mut block)
                }
            }
            for p in 0..n_s {
                for q in 0..n_s {
                    d[p * MAX_NODES + q] += block[p.min(q)][p.max(q)];
                }
            }
        }
        std::array::from_fn(|p| if p < 4 { sf.full[p] } else { 0.0 })
    }

    /// (A1) The candidates of first-order slave face `s` (whose swept box is
    /// that of [`Kernel::prepare`]) into `scratch.candidates`, from its group's
    /// query.
    fn flat_candidates(&self, s: usize, scratch: &mut Scratch) {
        if !scratch.group.contains(&s) {
            self.query_group(s, scratch);
        }
        let (lo, hi) = scratch.group_boxes[s - scratch.group.start];
        match scratch.grouped {
            true => self.tree.faces_in_slots_into(&scratch.slots, lo, hi, &mut scratch.candidates),
            false => self.tree.faces_meeting_box_into(lo, hi, &mut scratch.candidates),
        }
    }

    /// The swept boxes of the first-order faces of the group of `s` and, if
    /// they lie close together ([`GROUP_SPREAD`]), the tree slots meeting their
    /// union.
    fn query_group(&self, s: usize, scratch: &mut Scratch) {
        let start = s - s % GROUP;
        scratch.group = start..(start + GROUP).min(self.slave.n_faces());
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let mut largest = 0.0f64;
        let extent = |lo: Point3, hi: Point3| (0..3).map(|k| hi[k] - lo[k]).sum::<f64>();
        for f in scratch.group.clone() {
            if self.slave.faces()[f].is_curved() {
                continue;
            }
            let b = flat_search_box(self.slave, f, self.options);
            scratch.group_boxes[f - start] = b;
            largest = largest.max(extent(b.0, b.1));
            lo = std::array::from_fn(|k| lo[k].min(b.0[k]));
            hi = std::array::from_fn(|k| hi[k].max(b.1[k]));
        }
        scratch.grouped = largest > 0.0 && extent(lo, hi) <= GROUP_SPREAD * largest;
        if scratch.grouped {
            self.tree.slots_meeting_box_into(lo, hi, &mut scratch.slots);
        }
    }

    /// The general path ([`isoparametric`]): any pair with a curved face.
    /// Segmented with whole faces first and, if the coverage ends inside the
    /// slave face, again with [`isoparametric::SUBDIVISION`]² sub-faces.
    fn curved_face(
        &self,
        s: usize,
        scratch: &mut Scratch,
        out: &mut Blocks,
        d: &mut [f64; MAX_NODES * MAX_NODES],
        stats: &mut FaceStats,
    ) -> [f64; MAX_NODES] {
        let face = CurvedFace::of(self.slave, s);
        let gap_tol = curved_gap_tol(&face, self.options);
        let mut cs = CurvedSlave::new(face, 1, gap_tol, AREA_RTOL);
        let (lo, hi) = isoparametric::control_box(&face, cs.normal(), gap_tol);
        self.tree.faces_meeting_box_into(lo, hi, &mut scratch.candidates);
        let recorded = out.segments.len();
        loop {
            let plane_area = self.curved_pairs(s, &cs, scratch, out, d, stats);
            let partly = !scratch.candidates.is_empty() && plane_area < (1.0 - COVER_RTOL) * cs.chord_area;
            if !partly || cs.subdivision == isoparametric::SUBDIVISION {
                break;
            }
            *stats = FaceStats::default();
            d.fill(0.0);
            scratch.cols.clear();
            scratch.b.clear();
            out.segments.truncate(recorded);
            cs = CurvedSlave::new(face, isoparametric::SUBDIVISION, gap_tol, AREA_RTOL);
        }
        isoparametric::face_integrals(&face, &self.rules.curved[0])
    }

    /// (C1)–(D5) of the slave face `cs` against the candidates in `scratch`;
    /// returns the area of the clipped polygons in the plane.
    fn curved_pairs(
        &self,
        s: usize,
        cs: &CurvedSlave,
        scratch: &mut Scratch,
        out: &mut Blocks,
        d: &mut [f64; MAX_NODES * MAX_NODES],
        stats: &mut FaceStats,
    ) -> f64 {
        let n_s = cs.face.kind.n_nodes();
        stats.candidates = scratch.candidates.len() as u32;
        let mut plane_area = 0.0;
        let mut pair = CurvedBlock::ZERO;
        for k in 0..scratch.candidates.len() {
            let m = scratch.candidates[k];
            if !isoparametric::facing_ok(
                self.options.facing,
                cs.normal(),
                self.master_normals[m],
                self.cos_max_angle,
            ) {
                stats.rejected_angle += 1;
                continue;
            }
            let master = CurvedFace::of(self.master, m);
            let record = self.options.record_segments.then_some((&mut out.segments, s, m));
            if !isoparametric::pair(cs, &master, &self.rules.curved, stats, record, &mut pair) {
                continue;
            }
            plane_area += pair.plane_area;
            let nodes = self.master.faces()[m].nodes();
            let covered = (pair.covered_area, pair.segments);
            scratch.add_pair(d, stats, n_s, nodes, (Some(&pair.d), &pair.b), covered);
        }
        plane_area
    }

    fn prepare(&self, s: usize) -> SlaveFace {
        let element = FaceElement::of(self.slave, s);
        let frame = Frame::householder(element.normal(), element.centre());
        let plane = element.project(|x| frame.project(x));
        let polygon = face_polygon(plane.corners());
        let h = element.diameter();
        let clipper = ConvexClipper::new(&polygon);
        let plane_area = polygon_area(&polygon);
        let mut sf = SlaveFace {
            warped_rule: (element.kind == FaceKind::Quad4 && element.warp() >= PLANAR_WARP)
                .then(|| self.rules.fixed_warped.unwrap_or_else(|| rule(warped_quad_degree(&element)))),
            gap_tol: self.options.max_gap.at(h),
            area_tol: AREA_RTOL * plane_area,
            jacobian: element.jacobian_field(),
            heights: element.x.map(|x| frame.height(x)),
            orientation: plane.orientation(),
            full: [0.0; 4],
            area_ratio: None,
            element,
            frame,
            plane,
            clipper,
        };
        sf.full = match sf.jacobian {
            JacobianField::Affine(j) => affine_face_integrals(sf.element.kind, j),
            JacobianField::Norm(_) => {
                face_integrals(&sf.element, self.rules.select(&sf, sf.element.kind).degree)
            }
        };
        if let JacobianField::Affine(_) = sf.jacobian {
            sf.area_ratio = Some(sf.full.iter().sum::<f64>() / plane_area);
        }
        sf
    }

    /// (C1)–(C6) for the pair (slave face, master face `m`) into `block`;
    /// false when the pair is filtered out or does not overlap.
    fn pair(
        &self,
        sf: &SlaveFace,
        s: usize,
        m: usize,
        stats: &mut FaceStats,
        mut record: Option<&mut Vec<Segment>>,
        straight: &mut Vec<([Xi; 3], f64)>,
        block: &mut PairBlock,
    ) -> bool {
        let facing = isoparametric::facing_ok(
            self.options.facing,
            sf.frame.normal(),
            self.master_normals[m],
            self.cos_max_angle,
        );
        if !facing {
            stats.rejected_angle += 1;
            return false;
        }
        // (C3)–(C4)
        let em = FaceElement::of(self.master, m);
        let q = em.x.map(|x| sf.frame.project(x));
        let polygon = sf.clipper.clip(&face_polygon(&q[..em.n_nodes()]));
        if polygon.len() < 3 || polygon_area(&polygon) <= sf.area_tol {
            stats.empty += 1;
            return false;
        }
        // (D1)–(D2): reference coordinates of every polygon vertex on both faces.
        let master_plane = PlaneFace::new(em.kind, q);
        let master_heights = em.x.map(|x| sf.frame.height(x));
        let mut xs = [[0.0; 2]; MAX_POLYGON];
        let mut xm = [[0.0; 2]; MAX_POLYGON];
        let (mut gap, mut overlap) = (0.0f64, 0.0f64);
        for (v, &p) in polygon.iter().enumerate() {
            xs[v] = inverse(&sf.plane, p, stats);
            xm[v] = inverse(&master_plane, p, stats);
            // Height is affine, so n·(x(ξ) − o) = Σ λ_i(ξ) h_i with the corner heights h_i.
            let g = dot4(em.shape(xm[v]), master_heights) - dot4(sf.element.shape(xs[v]), sf.heights);
            if g.abs() > sf.gap_tol {
                stats.rejected_gap += 1;
                return false;
            }
            gap = gap.max(g);
            overlap = overlap.max(-g);
        }
        stats.max_gap = stats.max_gap.max(gap);
        stats.max_overlap = stats.max_overlap.max(overlap);
        let rule = self.rules.select(sf, em.kind);
        *block = PairBlock::default();
        // Both projected faces affine (triangles, parallelograms): ξ_s and ξ_m
        // are affine in the plane point, a segment is a straight triangle in
        // both reference cells and the rule is exact. Otherwise the preimages
        // of straight plane edges are curved: the points are placed in the plane.
        let in_plane = !(sf.plane.is_affine() && master_plane.is_affine());
        block.has_d = in_plane;
        // A rule fixed by the options wins for warped quads.
        let fixed = sf.warped_rule.filter(|_| self.options.warped_quad_degree.is_some());
        let mut record = |ts: [Xi; 3]| {
            if let Some(segments) = record.as_deref_mut() {
                segments.push(Segment { slave: s, master: m, corners: ts.map(|xi| sf.element.map(xi)) });
            }
        };
        if in_plane {
            // The plane's rules are not exact: pieces triangulated stably under noise.
            for [a, b, c] in stable_fan(&polygon, sf.frame.apex_direction()) {
                let plane = [polygon[a], polygon[b], polygon[c]];
                if signed_area(plane) <= 0.0 {
                    continue;
                }
                block.segments += 1;
                let ts = [xs[a], xs[b], xs[c]];
                let mut on = PlaneSegment {
                    slave: sf,
                    master: &master_plane,
                    rules: &self.rules,
                    base: rule,
                    fixed,
                    stats: &mut *stats,
                };
                on.integrate(em.kind, Piece { q: plane, xs: ts, xm: [xm[a], xm[b], xm[c]] }, block);
                record(ts);
            }
        } else {
            // An exact rule takes any triangulation.
            for [a, b, c] in fan_triangles(polygon.len()) {
                let ts = [xs[a], xs[b], xs[c]];
                integrate_segment(sf, em.kind, ts, [xm[a], xm[b], xm[c]], &rule, block, straight);
                record(ts);
            }
        }
        // D (of segments in the plane) is symmetric: only its upper triangle was accumulated.
        if in_plane {
            for p in 0..4 {
                for q in 0..p {
                    block.d[p][q] = block.d[q][p];
                }
            }
        }
        true
    }
}

/// ∫_e λ_p |J| in closed form for an affine |J| = j₀ + j₁ξ + j₂η (triangles and
/// planar quads): on the reference triangle ∫λ_p = 1/6 and ∫λ_p λ_r =
/// (1 + δ_pr)/24 with ξ = λ₁, η = λ₂; on [0,1]² ∫λ_p = 1/4 and ∫λ_p ξ is 1/6
/// for the two corners at ξ = 1, 1/12 for the others (likewise η).
fn affine_face_integrals(kind: FaceKind, [j0, j1, j2]: [f64; 3]) -> [f64; 4] {
    if kind == FaceKind::Tri3 {
        let m = |p: usize, r: usize| if p == r { 2.0 / 24.0 } else { 1.0 / 24.0 };
        std::array::from_fn(|p| if p < 3 { j0 / 6.0 + j1 * m(p, 1) + j2 * m(p, 2) } else { 0.0 })
    } else {
        let m = |at_one: bool| if at_one { 1.0 / 6.0 } else { 1.0 / 12.0 };
        std::array::from_fn(|p| j0 / 4.0 + j1 * m(p == 1 || p == 2) + j2 * m(p == 2 || p == 3))
    }
}

fn inverse(plane: &PlaneFace, p: [f64; 2], stats: &mut FaceStats) -> Xi {
    count_failure(plane.inverse(p), stats)
}

fn inverse_near(plane: &PlaneFace, p: [f64; 2], guess: Xi, stats: &mut FaceStats) -> Xi {
    count_failure(plane.inverse_near(p, guess), stats)
}

/// ξ of an inverse map, counting it in `stats.inverse_failures` when it did
/// not converge.
fn count_failure(r: InverseMap, stats: &mut FaceStats) -> Xi {
    if matches!(r, InverseMap::NotConverged { .. }) {
        stats.inverse_failures += 1;
    }
    r.xi()
}

/// (D3)–(D5) on one intersection triangle of two affine projected faces, with
/// reference images `ts` (slave) and `tm` (master): the quadrature points are
/// placed affinely in the slave's reference triangle, given their master
/// coordinates by the affine map between the two triangles, and weighted by
/// ω'_l = ω_l |J_s(x_l^s)| |T̂s|. Dispatches once to the loop specialised for
/// the two faces' node counts. B and the covered area only: the segment is
/// appended to `straight` for D ([`Kernel::flat_face`]).
#[inline]
fn integrate_segment(
    sf: &SlaveFace,
    master: FaceKind,
    ts: [Xi; 3],
    tm: [Xi; 3],
    rule: &TriangleRule,
    block: &mut PairBlock,
    straight: &mut Vec<([Xi; 3], f64)>,
) {
    // Relative to the orientation of the slave's map.
    let area_ref = sf.orientation * signed_area(ts);
    if area_ref == 0.0 {
        return;
    }
    block.segments += 1;
    straight.push((ts, area_ref));
    let j = &sf.jacobian;
    match (sf.element.kind, master) {
        (FaceKind::Tri3, FaceKind::Tri3) => accumulate::<3, 3>(j, ts, tm, area_ref, rule, block),
        (FaceKind::Tri3, _) => accumulate::<3, 4>(j, ts, tm, area_ref, rule, block),
        (_, FaceKind::Tri3) => accumulate::<4, 3>(j, ts, tm, area_ref, rule, block),
        _ => accumulate::<4, 4>(j, ts, tm, area_ref, rule, block),
    }
}

/// The quadrature loop of [`integrate_segment`] for an `NS`-node slave and an
/// `NM`-node master face (fixed sizes: unrolled, no bounds checks).
#[inline(always)]
fn accumulate<const NS: usize, const NM: usize>(
    jacobian: &JacobianField,
    ts: [Xi; 3],
    tm: [Xi; 3],
    area_ref: f64,
    rule: &TriangleRule,
    block: &mut PairBlock,
) {
    // Sums in locals (registers), added to the block once per segment.
    let (mut b, mut area) = ([[0.0; NS]; NM], 0.0);
    for (pt, &w) in rule.points.iter().zip(rule.weights) {
        let xis = barycentric(ts, *pt);
        let phi: [f64; NS] = shape_of(xis);
        let lam: [f64; NM] = shape_of(barycentric(tm, *pt));
        let wj = w * jacobian.at(xis);
        area += wj;
        add_b(&mut b, wj, &phi, &lam);
    }
    block.covered_area += area_ref * area;
    for q in 0..NM {
        for p in 0..NS {
            block.b[q][p] += area_ref * b[q][p];
        }
    }
}

/// D's share (upper triangle) of a straight segment of an `NS`-node slave face.
fn accumulate_d<const NS: usize>(
    jacobian: &JacobianField,
    ts: [Xi; 3],
    area_ref: f64,
    rule: &TriangleRule,
    d: &mut [[f64; 4]; 4],
) {
    for (pt, &w) in rule.points.iter().zip(rule.weights) {
        let xis = barycentric(ts, *pt);
        let phi: [f64; NS] = shape_of(xis);
        add_d(d, w * area_ref * jacobian.at(xis), &phi);
    }
}

/// The mass matrix ∫_e λ_p λ_q |J| of a first-order face with an affine
/// |J| = j₀ + j₁ξ + j₂η, in closed form: on the reference triangle
/// ∫λ_aλ_bλ_c = a!b!c!/(a+b+c+2)! in the exponents of λ₀, λ₁ = ξ, λ₂ = η; on
/// [0,1]² the integrals factor into ∫f_p f_q (1/3 for equal 1D factors, 1/6
/// otherwise) and ∫f_p f_q ξ (1/4 when both are ξ, 1/12 otherwise).
fn face_mass(kind: FaceKind, [j0, j1, j2]: [f64; 3]) -> [[f64; 4]; 4] {
    let mut m = [[0.0; 4]; 4];
    if kind == FaceKind::Tri3 {
        let factorial = [1.0, 1.0, 2.0, 6.0];
        let moment = |a: usize, b: usize, c: Option<usize>| {
            let mut e = [0usize; 3];
            for i in [Some(a), Some(b), c].into_iter().flatten() {
                e[i] += 1;
            }
            let order = e.iter().sum::<usize>();
            e.iter().map(|&k| factorial[k]).product::<f64>() / if order == 2 { 24.0 } else { 120.0 }
        };
        for p in 0..3 {
            for q in 0..3 {
                m[p][q] = j0 * moment(p, q, None) + j1 * moment(p, q, Some(1)) + j2 * moment(p, q, Some(2));
            }
        }
    } else {
        // λ_p = f_p(ξ) g_p(η): f_p = ξ for p = 1, 2; g_p = η for p = 2, 3.
        let (fx, gy) = (|p: usize| p == 1 || p == 2, |p: usize| p == 2 || p == 3);
        let plain = |a: bool, b: bool| if a == b { 1.0 / 3.0 } else { 1.0 / 6.0 };
        let moment = |a: bool, b: bool| if a && b { 1.0 / 4.0 } else { 1.0 / 12.0 };
        for p in 0..4 {
            for q in 0..4 {
                let (f, g) = ((fx(p), fx(q)), (gy(p), gy(q)));
                m[p][q] = j0 * plain(f.0, f.1) * plain(g.0, g.1)
                    + j1 * moment(f.0, f.1) * plain(g.0, g.1)
                    + j2 * plain(f.0, f.1) * moment(g.0, g.1);
            }
        }
    }
    m
}

/// A segment of a pair with a non-affine projected face, integrated in the
/// projection plane (D3)–(D5): a point q of a plane triangle T gets
/// ξ_s = χ_s⁻¹(q) and ξ_m = χ_m⁻¹(q) by the exact inverses of the two
/// projected maps, and the weight ω'_l = ω_l |T| |J_s(ξ_s)| / |det ∂χ_s/∂ξ(ξ_s)|
/// (the slave's area element per unit plane area, constant on a planar face).
/// The plane polygon is the exact intersection of the projected first-order
/// faces, so the region is exact; the integrand is analytic, and the rule is
/// chosen per triangle from [`PLANE_LADDER`].
struct PlaneSegment<'a> {
    slave: &'a SlaveFace,
    master: &'a PlaneFace,
    rules: &'a Rules,
    /// The polynomial (or warped-quad) rule of the pair: the least degree.
    base: TriangleRule,
    /// A rule fixed by the options: used as is, never cut.
    fixed: Option<TriangleRule>,
    stats: &'a mut FaceStats,
}

impl PlaneSegment<'_> {
    /// Integrates over the plane triangle of `piece`.
    fn integrate(&mut self, master: FaceKind, piece: Piece, block: &mut PairBlock) {
        match (self.slave.element.kind, master) {
            (FaceKind::Tri3, FaceKind::Tri3) => self.adaptive::<3, 3>(piece, 0, block),
            (FaceKind::Tri3, _) => self.adaptive::<3, 4>(piece, 0, block),
            (_, FaceKind::Tri3) => self.adaptive::<4, 3>(piece, 0, block),
            _ => self.adaptive::<4, 4>(piece, 0, block),
        }
    }

    /// The rule of the piece's fold ratio, or four children (summed pairwise,
    /// so that the covered area of many points stays exact to round-off).
    fn adaptive<const NS: usize, const NM: usize>(
        &mut self,
        piece: Piece,
        depth: u32,
        block: &mut PairBlock,
    ) {
        let r = self.slave.plane.fold_ratio(&piece.xs).max(self.master.fold_ratio(&piece.xm));
        let rule = match self.fixed {
            Some(fixed) => Some(fixed),
            None if depth == PLANE_MAX_DEPTH => Some(self.rules.plane[PLANE_LADDER.len() - 1]),
            None => self.rules.plane(r, &self.base),
        };
        if let Some(rule) = rule {
            return self.accumulate::<NS, NM>(piece, &rule, block);
        }
        let m = piece.midpoints();
        let ms = m.map(|p| inverse(&self.slave.plane, p, self.stats));
        let mm = m.map(|p| inverse(self.master, p, self.stats));
        let children = piece.children(ms, mm);
        let mut sum = PairBlock::default();
        for child in children {
            let mut part = PairBlock::default();
            self.adaptive::<NS, NM>(child, depth + 1, &mut part);
            sum.add(&part);
        }
        block.add(&sum);
    }

    #[inline(always)]
    fn accumulate<const NS: usize, const NM: usize>(
        &mut self,
        piece: Piece,
        rule: &TriangleRule,
        block: &mut PairBlock,
    ) {
        let area = signed_area(piece.q);
        let sf = self.slave;
        for (pt, &w) in rule.points.iter().zip(rule.weights) {
            let q = barycentric(piece.q, *pt);
            // Newton from the affine interpolation of the vertices' coordinates.
            let xis = inverse_near(&sf.plane, q, barycentric(piece.xs, *pt), self.stats);
            let xim = inverse_near(self.master, q, barycentric(piece.xm, *pt), self.stats);
            let phi: [f64; NS] = shape_of(xis);
            let lam: [f64; NM] = shape_of(xim);
            let ratio = match sf.area_ratio {
                Some(ratio) => ratio,
                None => sf.jacobian.at(xis) / sf.plane.det(xis).abs(),
            };
            let wj = w * area * ratio;
            block.covered_area += wj;
            add_point(&mut block.d, &mut block.b, wj, &phi, &lam);
        }
    }
}

/// The 3 (Tri3) or 4 (Quad4) shape functions at ξ.
#[inline(always)]
fn shape_of<const N: usize>(xi: Xi) -> [f64; N] {
    let l = crate::catalogue::faces::first_order_values(N == 3, xi);
    std::array::from_fn(|i| l[i])
}

/// Σ a_i b_i over four entries (a triangle's fourth shape value is 0).
#[inline(always)]
fn dot4(a: [f64; 4], b: [f64; 4]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

impl Scratch {
    /// Adds a pair's blocks (n_s × n_s of D, if any, into `d`, n_s × n_m of B
    /// into the face's columns) and counts to the face's.
    fn add_pair<const N: usize>(
        &mut self,
        d: &mut [f64; MAX_NODES * MAX_NODES],
        stats: &mut FaceStats,
        n_s: usize,
        master_nodes: &[usize],
        (pair_d, pair_b): (Option<&[[f64; N]; N]>, &[[f64; N]; N]),
        (covered_area, segments): (f64, u32),
    ) {
        stats.intersecting += 1;
        stats.segments += segments;
        stats.covered_area += covered_area;
        if let Some(pair_d) = pair_d {
            for p in 0..n_s {
                for q in 0..n_s {
                    d[p * MAX_NODES + q] += pair_d[p][q];
                }
            }
        }
        add_columns(&mut self.cols, &mut self.b, n_s, master_nodes, pair_b);
    }
}

/// Appends a pair's n_s × n_m block, by columns `b[q][p]`, to the face's
/// block (columns of `n_s` rows), one column per master point;
/// [`Scratch::merge_columns`] sums the columns of the same point.
fn add_columns<const N: usize>(
    cols: &mut Vec<usize>,
    block: &mut Vec<f64>,
    n_s: usize,
    master_nodes: &[usize],
    b: &[[f64; N]; N],
) {
    for (q, &node) in master_nodes.iter().enumerate() {
        cols.push(node);
        block.extend_from_slice(&b[q][..n_s]);
    }
}

impl Scratch {
    /// Sorts the face block's columns by master point and sums the columns of
    /// the same point in the order the pairs added them (a stable sort), so
    /// that the sums are those of a search-and-add and the rows later merge
    /// sorted runs.
    /// O(c log c) in the c columns: a coarse slave face over a fine master
    /// has thousands.
    fn merge_columns(&mut self, n_s: usize) {
        // Keys (column, position): unique, so an unstable sort keeps the
        // columns of one point in the order they were added.
        self.order.clear();
        self.order.extend(self.cols.iter().enumerate().map(|(j, &c)| (c as u64) << 32 | j as u64));
        self.order.sort_unstable();
        self.merged_cols.clear();
        self.merged_b.clear();
        let cols = &self.cols;
        for j in self.order.iter().map(|&key| (key & u64::from(u32::MAX)) as usize) {
            if self.merged_cols.last() != Some(&cols[j]) {
                self.merged_cols.push(cols[j]);
                self.merged_b.extend(std::iter::repeat_n(0.0, n_s));
            }
            let start = self.merged_b.len() - n_s;
            for p in 0..n_s {
                self.merged_b[start + p] += self.b[j * n_s + p];
            }
        }
        std::mem::swap(&mut self.cols, &mut self.merged_cols);
        std::mem::swap(&mut self.b, &mut self.merged_b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalogue::shape_and_gradients;
    use crate::mortar::pieces::{edge_midpoints, triangle_area};

    /// [∫_T λ_p λ_r (χ⁻¹(q)) dq] and [∫_T λ_p(χ⁻¹(q)) f(q) dq] for f = 1, q_x,
    /// q_y and the shape functions λ of `kind` (Quad4 or Quad9), over plane
    /// triangle `t`, cut into four while `plan` (of the fold ratio and the
    /// depth) gives no rule.
    fn moments(
        face: &PlaneFace,
        kind: FaceKind,
        t: [[f64; 2]; 3],
        plan: &dyn Fn(f64, u32) -> Option<TriangleRule>,
        depth: u32,
    ) -> Vec<f64> {
        let n = kind.n_nodes();
        let xi = t.map(|q| face.inverse(q).xi());
        let mut out = vec![0.0; n * n + 3 * n];
        let Some(rule) = plan(face.fold_ratio(&xi), depth) else {
            let mid = |a: [f64; 2], b: [f64; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
            let (m01, m12, m20) = (mid(t[0], t[1]), mid(t[1], t[2]), mid(t[2], t[0]));
            for child in [[t[0], m01, m20], [m01, t[1], m12], [m20, m12, t[2]], [m12, m20, m01]] {
                let v = moments(face, kind, child, plan, depth + 1);
                out.iter_mut().zip(v).for_each(|(o, v)| *o += v);
            }
            return out;
        };
        let area = signed_area(t);
        for (pt, &w) in rule.points.iter().zip(rule.weights) {
            let q = barycentric(t, *pt);
            let l = shape_and_gradients(kind, face.inverse(q).xi()).0;
            for p in 0..n {
                for r in 0..n {
                    out[n * p + r] += w * area * l[p] * l[r];
                }
                for (k, f) in [1.0, q[0], q[1]].into_iter().enumerate() {
                    out[n * n + 3 * p + k] += w * area * l[p] * f;
                }
            }
        }
        out
    }

    /// On random convex quads of distortion up to 0.95
    /// ([`PlaneFace::distortion`]), over triangles of the quad of every size
    /// from the whole face to 0.15 of it, anywhere in it, `ladder` (with
    /// cutting below `max_depth`) integrates λ_p λ_r(χ⁻¹(q)) and
    /// λ_p(χ⁻¹(q)) f(q), f linear, for the shape functions of `kind`, to 1e-12
    /// of the largest moment (reference: degree 20 on pieces cut down to a
    /// fold ratio of 0.1, and at least twice). Returns the worst error and
    /// the number of triangles cut.
    fn ladder_accuracy(
        kind: FaceKind,
        ladder: &[(f64, usize)],
        max_depth: u32,
        mut seed: u64,
    ) -> (f64, usize) {
        let mut random = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let rules: Vec<TriangleRule> = ladder.iter().map(|&(_, degree)| rule(degree)).collect();
        let (mut worst, mut cut) = (0.0f64, 0usize);
        for i in 0..800 {
            let amplitude = 0.8 * i as f64 / 800.0;
            let mut q = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
            for c in &mut q {
                c[0] += amplitude * (2.0 * random() - 1.0);
                c[1] += amplitude * (2.0 * random() - 1.0);
            }
            let face = PlaneFace::new(FaceKind::Quad4, q);
            if face.distortion() > 0.95 {
                continue;
            }
            let size = [1.0, 0.5, 0.3, 0.15][i % 4];
            let centre = [random(), random()];
            let mut corner = || {
                let at = |c: f64, r: f64| (c + size * (r - 0.5)).clamp(0.0, 1.0);
                face.map([at(centre[0], random()), at(centre[1], random())])
            };
            let mut t = [corner(), corner(), corner()];
            if signed_area(t) < 0.0 {
                t.swap(1, 2);
            }
            if signed_area(t) < 1e-3 * size * size {
                continue;
            }
            let xi = t.map(|p| face.inverse(p).xi());
            cut += (face.fold_ratio(&xi) > ladder[ladder.len() - 1].0) as usize;
            let degree_20 = triangle_rule(20).unwrap();
            let fine = |r: f64, depth: u32| (r <= 0.1 && depth >= 2).then_some(degree_20);
            let exact = moments(&face, kind, t, &fine, 0);
            let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let chosen = |r: f64, depth: u32| match ladder.iter().position(|&(max, _)| r <= max) {
                Some(k) => Some(rules[k]),
                None if depth == max_depth => rules.last().copied(),
                None => None,
            };
            let got = moments(&face, kind, t, &chosen, 0);
            let error = got.iter().zip(&exact).fold(0.0f64, |m, (g, e)| m.max((g - e).abs())) / scale;
            let r = face.fold_ratio(&xi);
            assert!(error < 1e-12, "{kind:?} on quad {q:?}, triangle {t:?}, fold ratio {r}: error {error:e}");
            worst = worst.max(error);
        }
        (worst, cut)
    }

    /// The closed forms for faces with an affine |J| (a triangle, a planar quad
    /// that is no parallelogram) against quadrature: ∫λ_p|J| by the degree-8
    /// rule, ∫λ_pλ_q|J| by the degree-20 rule on each reference triangle cut
    /// into four (so that the reference is no copy of the closed form).
    #[test]
    fn closed_forms_agree_with_quadrature() {
        let faces = [
            FaceElement {
                kind: FaceKind::Tri3,
                x: [[0.1, 0.0, 0.3], [1.3, 0.2, 0.1], [0.4, 0.9, 0.7], [0.0; 3]],
            },
            FaceElement {
                kind: FaceKind::Quad4,
                x: [[0.0, 0.0, 0.0], [2.0, 0.3, 0.0], [1.7, 1.9, 0.0], [-0.2, 1.0, 0.0]],
            },
        ];
        let fine = rule(crate::quadrature::MAX_TRIANGLE_DEGREE);
        for e in faces {
            let jacobian = e.jacobian_field();
            let JacobianField::Affine(j) = jacobian else { panic!("planar face") };
            let (closed, reference) = (affine_face_integrals(e.kind, j), face_integrals(&e, 8));
            for p in 0..4 {
                assert!(
                    (closed[p] - reference[p]).abs() <= 1e-15 * reference[0].abs(),
                    "{p}: {closed:?} {reference:?}"
                );
            }
            let mass = face_mass(e.kind, j);
            let mut reference = [[0.0; 4]; 4];
            for t in e.reference_triangles() {
                let m = edge_midpoints(*t);
                for c in [[t[0], m[0], m[2]], [m[0], t[1], m[1]], [m[2], m[1], t[2]], [m[1], m[2], m[0]]] {
                    if e.kind == FaceKind::Tri3 {
                        accumulate_d::<3>(&jacobian, c, triangle_area(c), &fine, &mut reference)
                    } else {
                        accumulate_d::<4>(&jacobian, c, triangle_area(c), &fine, &mut reference)
                    }
                }
            }
            let n = e.n_nodes();
            for p in 0..n {
                for q in p..n {
                    let tol = 1e-13 * reference[0][0];
                    assert!((mass[p][q] - reference[p][q]).abs() <= tol, "{:?} {p}{q}: {mass:?}", e.kind);
                    assert_eq!(mass[p][q], mass[q][p]);
                }
            }
        }
    }

    /// The justification of [`PLANE_LADDER`] (first-order quads; each rung at
    /// least as fine as the pair's polynomial rule).
    #[test]
    fn plane_ladder_accuracy() {
        let (worst, cut) = ladder_accuracy(FaceKind::Quad4, &PLANE_LADDER, PLANE_MAX_DEPTH, 7);
        assert!(cut >= 10, "some triangles are cut: {cut}");
        eprintln!("plane ladder: worst relative error {worst:e}, {cut} triangles cut");
    }

    /// The justification of [`isoparametric::CURVED_LADDER`] (Quad9 slave
    /// chords; calibrated on another sample, seed 7, by the lowest degree that
    /// met 1e-12 per range of fold ratios).
    #[test]
    fn curved_ladder_accuracy() {
        let (worst, cut) = ladder_accuracy(
            FaceKind::Quad9,
            &isoparametric::CURVED_LADDER,
            isoparametric::CURVED_MAX_DEPTH,
            11,
        );
        assert!(cut >= 10, "some triangles are cut: {cut}");
        eprintln!("curved ladder: worst relative error {worst:e}, {cut} triangles cut");
    }
}
