//! (A2)–(D5): assembly of the mortar matrices
//!
//! ```text
//! D_pq = ∫Γs ψ_p λ^s_q ,   B_pq = ∫Γs ψ_p (λ^m_q ∘ Φ) ,   T = D⁻¹B
//! ```
//!
//! over all slave faces in parallel, the multiplier spaces (standard, dual,
//! lumped) and the transfer operator.
//!
//! Rows are slave points and columns master points, numbered as in the meshes
//! (so as in the files they came from); points off the interface have empty rows
//! and columns.
//!
//! # Determinism (I7)
//! Slave faces are cut into fixed chunks whatever the thread count; each face's
//! contribution is computed alone, in a fixed order (candidates sorted by master
//! face); rows are then summed face by face in increasing face order. B, D and T
//! are therefore bit-for-bit the same for any number of threads.

mod diagnostics;
mod isoparametric;
mod kernel;
mod moved;
mod multiplier;
pub mod parts;
mod pieces;
mod rows;
mod transfer;

pub use diagnostics::{
    face_quality, master_side, nodal_areas, nodal_normals, normal_gaps, normal_gaps_from,
    orientation_conflicts, FaceQuality, MasterSide,
};
pub use moved::{assemble_keeping, reassemble, slave_faces_near, FaceBlocks};
pub use multiplier::{BASIS_ALPHA, TRI6_ALPHA};
pub use transfer::Transfer;

use crate::element::FaceElement;
use crate::mesh::{Point3, SurfaceMesh};
use crate::quadrature::{triangle_rule, MAX_TRIANGLE_DEGREE};
use crate::search::FaceTree;
use crate::sparse::CsrMatrix;
use kernel::{Kernel, Scratch};
use rayon::prelude::*;
use rows::{Blocks, ChunkedBlocks};

/// The Lagrange multiplier basis ψ_p.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Deserialize), serde(rename_all = "lowercase"))]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Multiplier {
    /// ψ_p = λ_p: D is the slave mass matrix of the covered part (SPD).
    #[default]
    Standard,
    /// Biorthogonal ψ_p = Σ_q a_pq λ_q, built per slave face on its covered part so
    /// that ∫_e ψ_p λ_q = δ_pq ∫_e λ_q: D is diagonal.
    Dual,
    /// ψ_p = λ_p with D replaced by its row sums (diagonal).
    Lumped,
}

/// Which normal orientations may be paired.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Deserialize), serde(rename_all = "lowercase"))]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Facing {
    /// |n_s·n_m| ≥ cos(max angle): either orientation (a surface mesh's normals may
    /// point either way).
    #[default]
    Any,
    /// −n_s·n_m ≥ cos(max angle): the faces face each other (two bodies, outward
    /// normals).
    Opposite,
}

crate::named!(Multiplier, "multiplier", { Standard => "standard", Dual => "dual", Lumped => "lumped" });
crate::named!(Facing, "facing", { Any => "any", Opposite => "opposite" });

/// The largest normal distance |(x_m − x_s)·n_s| allowed between paired points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MaxGap {
    /// A fraction of each slave face's diameter.
    Relative(f64),
    /// A length.
    Absolute(f64),
}

impl MaxGap {
    /// The default: half the local slave face diameter. Gaps and overlaps from
    /// independent meshing of a curved interface are O(h²/R), far below that,
    /// while the opposite side of a thin body is usually farther away.
    pub const DEFAULT: MaxGap = MaxGap::Relative(0.5);

    /// The tolerance for a slave face of diameter `h`.
    pub fn at(&self, h: f64) -> f64 {
        match *self {
            MaxGap::Relative(f) => f * h,
            MaxGap::Absolute(g) => g,
        }
    }
}

impl Default for MaxGap {
    fn default() -> Self {
        MaxGap::DEFAULT
    }
}

/// Candidate degrees for warped slave quads, tried in order.
const WARPED_LADDER: [usize; 8] = [6, 8, 10, 12, 14, 16, 18, MAX_TRIANGLE_DEGREE];

/// Relative agreement with the degree-20 rule required of a warped quad's face
/// integrals.
pub const WARPED_RTOL: f64 = 1e-13;

/// The triangle-rule degree for segments of a warped quad (whose surface
/// Jacobian is not a polynomial): the lowest degree of a ladder 6, 8, …, 20 whose
/// face integrals ∫_e λ_p |J| agree with the degree-20 rule to [`WARPED_RTOL`].
/// Segments are sub-triangles of the face, on which a rule is at least as
/// accurate. Chosen once per face; test `warped_quad_rule_accuracy` shows the
/// face integrals within 1e-12 relative of a subdivided degree-20 reference for
/// quads with one corner lifted by up to about a face size.
pub fn warped_quad_degree(e: &FaceElement) -> usize {
    let reference = face_integrals(e, MAX_TRIANGLE_DEGREE);
    let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    WARPED_LADDER
        .into_iter()
        .find(|&d| {
            let a = face_integrals(e, d);
            (0..e.n_nodes()).all(|p| (a[p] - reference[p]).abs() <= WARPED_RTOL * scale)
        })
        .unwrap_or(MAX_TRIANGLE_DEGREE)
}

/// ∫_e λ_p |J| over the whole face with the triangle rule of `degree`.
pub fn face_integrals(e: &FaceElement, degree: usize) -> [f64; 4] {
    let rule = triangle_rule(degree).expect("degree within the tabulated range");
    let jacobian = e.jacobian_field();
    let mut full = [0.0; 4];
    for t in e.reference_triangles() {
        let area_ref = pieces::triangle_area(*t);
        for (pt, &w) in rule.points.iter().zip(rule.weights) {
            let xi = pieces::barycentric(*t, *pt);
            let wj = w * area_ref * jacobian.at(xi);
            let phi = e.shape(xi);
            for p in 0..4 {
                full[p] += wj * phi[p];
            }
        }
    }
    full
}

/// Options of the assembly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MortarOptions {
    /// Multiplier basis.
    pub multiplier: Multiplier,
    /// Admissible normal orientations.
    pub facing: Facing,
    /// Largest normal distance between paired points.
    pub max_gap: MaxGap,
    /// Largest angle between the slave and master normals, in degrees.
    pub max_angle_degrees: f64,
    /// Triangle-rule degree on segments of warped slave quads; `None` chooses it
    /// per face ([`warped_quad_degree`]). Polynomial integrands —
    /// triangles, planar quads — always get an exact rule.
    pub warped_quad_degree: Option<usize>,
    /// Keep the intersection triangles ([`Mortar::segments`]), for inspection.
    pub record_segments: bool,
    /// Which second-order slave surfaces get the basis transformation of dual
    /// multipliers.
    pub transformation: BasisTransformation,
}

/// Which second-order slave surfaces get the basis transformation of dual
/// multipliers ([`BASIS_ALPHA`]; [`TRI6_ALPHA`] on surfaces of Tri6 faces).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BasisTransformation {
    /// Surfaces with Tri6 or Quad8 faces, whose corner functions have no
    /// positive integral; a surface of Quad9 faces keeps the plain dual basis,
    /// which contains the linear functions (optimal glued convergence).
    #[default]
    Needed,
    /// Every surface with second-order faces, Quad9 included: the multipliers
    /// are then weighted by the transformed functions, whose weights sit on
    /// their nodes, as contact's weighted gaps and nodal pressures want (Popp
    /// et al. 2012; Hertz on Hex27: p₀ −0.30 % against +7.3 % with the plain
    /// Quad9 dual basis).
    All,
}

impl Default for MortarOptions {
    fn default() -> Self {
        MortarOptions {
            multiplier: Multiplier::Standard,
            facing: Facing::Any,
            max_gap: MaxGap::DEFAULT,
            max_angle_degrees: 45.0,
            warped_quad_degree: None,
            record_segments: false,
            transformation: BasisTransformation::Needed,
        }
    }
}

/// Why an assembly produced no operator.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MortarError {
    /// The options are out of range.
    #[error("invalid option: {0}")]
    InvalidOption(String),
    /// No master face overlaps any slave face.
    #[error(
        "the meshes do not overlap: no master face meets a slave face within the gap and angle limits \
         ({candidates} candidate pairs from the search; {rejected_angle} rejected by the normal angle, \
         {rejected_gap} by the gap limit, {empty} with no overlap in projection){}",
        nearest_distance.map_or(String::new(), |d| format!(
            "; the master surface is {d:.3e} away from the nearest slave face centre (box distance)"
        ))
    )]
    NoOverlap {
        /// Candidate pairs from the search.
        candidates: usize,
        /// Pairs whose normals differ too much.
        rejected_angle: usize,
        /// Pairs too far apart along the normal.
        rejected_gap: usize,
        /// Pairs whose projections do not overlap.
        empty: usize,
        /// The distance from the slave face centres to the nearest master face
        /// box (a lower bound of the distance between the surfaces).
        nearest_distance: Option<f64>,
    },
    /// Lumped multipliers with a row sum of D that is not positive: on
    /// second-order faces ∫ λ_p vanishes (Tri6 corners) or is negative
    /// (Quad8 corners).
    #[error(
        "lumped multipliers need positive row sums of D, but slave node {row} (0-based) has ∫λ = {value:.3e}: \
         the corner functions of second-order faces (Tri6, Quad8) do not have positive integrals; use dual multipliers"
    )]
    LumpedNotPositive {
        /// The row (slave point index).
        row: usize,
        /// Its row sum.
        value: f64,
    },
    /// Lumped multipliers on a slave surface with Tri6 or Quad8 faces, whose
    /// corner functions have ∫λ = 0 (Tri6) or < 0 (Quad8) on flat faces and
    /// only by the face's curvature otherwise.
    #[error(
        "lumped multipliers are refused on {kind} slave faces (face {face}, 0-based): their corner functions \
         have no positive integral, so D would not be positive; use dual multipliers"
    )]
    LumpedSecondOrder {
        /// The first such face.
        face: usize,
        /// "Tri6" or "Quad8".
        kind: &'static str,
    },
    /// D restricted to the covered slave nodes could not be factorised.
    #[error("the slave mass matrix D is not positive definite on the covered nodes ({0})")]
    Factorization(String),
    /// An entry of B or D is NaN or infinite (an overflow in the geometry of
    /// the faces of that row; nothing non-finite is returned).
    #[error("the operator is not finite in the row of slave node {row} (0-based): an overflow in the geometry of its faces")]
    NonFinite {
        /// The row (slave point index).
        row: usize,
    },
}

/// What one slave face received.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FaceStats {
    /// Area of the face, ∫_e |J|.
    pub area: f64,
    /// Covered area, Σ over its segments of ∫ |J|.
    pub covered_area: f64,
    /// Master faces the search returned.
    pub candidates: u32,
    /// Pairs rejected by the normal angle.
    pub rejected_angle: u32,
    /// Pairs rejected by the gap limit.
    pub rejected_gap: u32,
    /// Pairs with no overlap in projection.
    pub empty: u32,
    /// Pairs that contributed.
    pub intersecting: u32,
    /// Intersection triangles.
    pub segments: u32,
    /// Largest gap (x_m − x_s)·n_s > 0 seen at polygon vertices (0 if none).
    pub max_gap: f64,
    /// Largest overlap −(x_m − x_s)·n_s > 0 seen (0 if none).
    pub max_overlap: f64,
    /// Inverse projections that did not converge (the best iterate was used).
    pub inverse_failures: u32,
    /// Dual multipliers replaced by lumped ones because the covered part's mass
    /// matrix was singular.
    pub dual_fallbacks: u32,
}

/// Totals over the interface.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct MortarSummary {
    /// Slave points used by some slave face.
    pub slave_nodes: usize,
    /// Master points used by some master face.
    pub master_nodes: usize,
    /// Slave faces.
    pub slave_faces: usize,
    /// Master faces.
    pub master_faces: usize,
    /// Pairs returned by the search.
    pub candidate_pairs: usize,
    /// Pairs that contributed.
    pub intersecting_pairs: usize,
    /// Intersection triangles.
    pub segments: usize,
    /// ∫Γs 1.
    pub slave_area: f64,
    /// 1ᵀD1 (standard multipliers): the covered part of Γs.
    pub covered_area: f64,
    /// Slave points on the surface whose support is (numerically) not covered
    /// (listed by [`Mortar::uncovered_nodes`]).
    pub uncovered_slave_nodes: usize,
    /// Largest gap seen.
    pub max_gap: f64,
    /// Largest overlap seen.
    pub max_overlap: f64,
    /// Inverse projections that did not converge.
    pub inverse_failures: usize,
    /// Faces whose dual basis fell back to lumping.
    pub dual_fallbacks: usize,
}

impl Mortar {
    /// D in the nodal (Lagrange) slave basis, N_pr = ∫ ψ_p λ_r: the slave
    /// block of the constraints ∫ ψ_p (u_s − u_m) = 0 for nodal u_s. Without a
    /// basis transformation it is D; with one it is D Q⁻ᵀ, as sparse as Q:
    /// Q has unit rows at corners (plus α towards their edge nodes) and
    /// 1 − 2α on edge nodes, so (Q⁻¹)_pp = 1/Q_pp and (Q⁻¹)_rp = −Q_rp/(Q_rr Q_pp).
    pub fn nodal_d(&self) -> CsrMatrix {
        let Some(q) = &self.basis else { return self.d.clone() };
        let qt = q.transpose();
        let diag_q = q.diagonal();
        let d = self.d.diagonal();
        let rows: Vec<(Vec<usize>, Vec<f64>)> = (0..d.len())
            .map(|p| {
                let (rs, vs) = qt.row(p);
                let vals = rs
                    .iter()
                    .zip(vs)
                    .map(|(&r, &v)| if r == p { d[p] / v } else { -d[p] * v / (diag_q[r] * diag_q[p]) })
                    .collect();
                (rs.to_vec(), vals)
            })
            .collect();
        CsrMatrix::from_rows(self.d.ncols, rows.iter().map(|(c, v)| (c.as_slice(), v.as_slice())))
    }

    /// The slave points on the surface whose support is not covered, ascending.
    pub fn uncovered_nodes(&self) -> Vec<usize> {
        (0..self.covered.len()).filter(|&p| self.on_surface[p] && !self.covered[p]).collect()
    }
}

/// One intersection triangle (a mortar segment) on the slave surface: the
/// images x_s(ξ_s) of its corners, and the faces whose overlap it is part of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Slave face index.
    pub slave: usize,
    /// Master face index.
    pub master: usize,
    /// Corners on the slave surface.
    pub corners: [Point3; 3],
}

/// A node counts as covered when the covered part of its support carries more
/// than this fraction of ∫ λ_p.
pub const COVERED_FRACTION: f64 = 1e-10;

/// The assembled mortar operator.
#[derive(Clone, Debug)]
pub struct Mortar {
    /// B, slave points × master points.
    pub b: CsrMatrix,
    /// D, slave points × slave points (diagonal for dual and lumped).
    pub d: CsrMatrix,
    /// The multiplier the matrices were built with.
    pub multiplier: Multiplier,
    /// For dual multipliers on a slave surface with Tri6 or Quad8 faces: the
    /// basis transformation Q (slave points × slave points, rows the
    /// transformed functions λ̃ = Q λ, see [`BASIS_ALPHA`]) in which D is
    /// diagonal and positive; B and D are then written in the λ̃ basis and the
    /// nodal transfer is T = Qᵀ D⁻¹ B. `None` otherwise (T = D⁻¹ B).
    pub basis: Option<CsrMatrix>,
    /// Per slave face.
    pub faces: Vec<FaceStats>,
    /// Per slave point: covered fraction of ∫ λ_p (0 off the surface).
    pub node_coverage: Vec<f64>,
    /// Per slave point: covered (see [`COVERED_FRACTION`]).
    pub covered: Vec<bool>,
    /// Per slave point: used by some slave face.
    pub on_surface: Vec<bool>,
    /// The intersection triangles, in slave face order, when
    /// [`MortarOptions::record_segments`] was set (empty otherwise).
    pub segments: Vec<Segment>,
    /// Totals.
    pub summary: MortarSummary,
}

/// Assembles B and D between `master` and `slave` (search included).
///
/// # Errors
/// [`MortarError::NoOverlap`] when no pair contributes; invalid options.
pub fn assemble(
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    options: &MortarOptions,
) -> Result<Mortar, MortarError> {
    assemble_with_tree(master, &FaceTree::new(master), slave, options, &|_| {})
}

/// Assembles B and D with a prebuilt search tree over `master`; `progress` is
/// called with the number of slave faces finished since its last call.
///
/// Runs on the current rayon thread pool (choose the thread count with
/// `rayon::ThreadPool::install`).
///
/// # Errors
/// See [`assemble`].
pub fn assemble_with_tree(
    master: &SurfaceMesh,
    tree: &FaceTree,
    slave: &SurfaceMesh,
    options: &MortarOptions,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Mortar, MortarError> {
    check_inputs(master, slave, options)?;
    let transform = multiplier::transformation_weight(slave, options.transformation);
    let chunks = face_blocks(master, tree, slave, options, transform, progress);
    into_operator(master, tree, slave, options, ChunkedBlocks::owned(chunks))
}

/// Faces per chunk of the assembly (fixed, whatever the thread count: I7).
const CHUNK: usize = 256;

/// (A1)–(D5) for every face of `slave`: the per-face blocks, in chunks of
/// [`CHUNK`] faces.
fn face_blocks(
    master: &SurfaceMesh,
    tree: &FaceTree,
    slave: &SurfaceMesh,
    options: &MortarOptions,
    transform: Option<f64>,
    progress: &(dyn Fn(usize) + Sync),
) -> Vec<Blocks> {
    let kernel = Kernel::new(master, tree, slave, options, transform);
    let n = slave.n_faces();
    let chunks: Vec<Blocks> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let range = c * CHUNK..((c + 1) * CHUNK).min(n);
            let mut scratch = Scratch::default();
            let mut blocks = Blocks::with_capacity(range.len());
            for s in range.clone() {
                kernel.face(s, &mut scratch, &mut blocks);
            }
            progress(range.len());
            blocks
        })
        .collect();
    chunks
}

/// (A1)–(D5) for the slave faces `faces` (ascending) of `slave`: their
/// blocks, in chunks of [`CHUNK`] of them.
fn face_blocks_of(
    master: &SurfaceMesh,
    tree: &FaceTree,
    slave: &SurfaceMesh,
    options: &MortarOptions,
    transform: Option<f64>,
    faces: &[usize],
) -> Vec<Blocks> {
    let kernel = Kernel::new(master, tree, slave, options, transform);
    faces
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut scratch = Scratch::default();
            let mut blocks = Blocks::with_capacity(chunk.len());
            for &s in chunk {
                kernel.face(s, &mut scratch, &mut blocks);
            }
            blocks
        })
        .collect()
}

/// The operator from the blocks of all slave faces, in face order: the
/// totals, the rows summed face by face (I7), and the checks of the result.
fn into_operator(
    master: &SurfaceMesh,
    tree: &FaceTree,
    slave: &SurfaceMesh,
    options: &MortarOptions,
    blocks: ChunkedBlocks,
) -> Result<Mortar, MortarError> {
    let n = slave.n_faces();
    let summary = summarize(master, slave, blocks.stats());
    if summary.intersecting_pairs == 0 {
        let sum = |f: fn(&FaceStats) -> u32| blocks.stats().map(|s| f(s) as usize).sum();
        return Err(MortarError::NoOverlap {
            candidates: summary.candidate_pairs,
            rejected_angle: sum(|s| s.rejected_angle),
            rejected_gap: sum(|s| s.rejected_gap),
            empty: sum(|s| s.empty),
            nearest_distance: (0..n)
                .into_par_iter()
                .map(|s| tree.distance_to(crate::element::FaceElement::of(slave, s).centre()))
                .reduce_with(f64::min),
        });
    }
    let mortar =
        rows::into_mortar(master, slave, blocks, (options.multiplier, options.transformation), summary);
    if let Some(row) = mortar.b.first_non_finite_row().or_else(|| mortar.d.first_non_finite_row()) {
        return Err(MortarError::NonFinite { row });
    }
    if options.multiplier == Multiplier::Lumped {
        let diagonal = mortar.d.diagonal();
        // Relative to the largest: a row sum that is round-off of zero counts.
        let scale = diagonal.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if let Some(row) = (0..diagonal.len()).find(|&p| mortar.covered[p] && diagonal[p] <= 1e-12 * scale) {
            return Err(MortarError::LumpedNotPositive { row, value: diagonal[row] });
        }
    }
    Ok(mortar)
}

/// The options, lumped multipliers on a slave surface that refuses them, and
/// the point counts (columns are kept as u32).
fn check_inputs(
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    options: &MortarOptions,
) -> Result<(), MortarError> {
    check_options(options)?;
    if options.multiplier == Multiplier::Lumped {
        // Lumping needs ∫ λ_p > 0 for every shape function.
        let refused =
            slave.faces().iter().enumerate().find_map(|(f, face)| {
                (!face.kind().info().positive_integrals).then(|| (f, face.kind().name()))
            });
        if let Some((face, kind)) = refused {
            return Err(MortarError::LumpedSecondOrder { face, kind });
        }
    }
    // Columns of B (master points) and of D (slave points) are kept as u32.
    for (side, mesh) in [("master", master), ("slave", slave)] {
        if mesh.n_points() > u32::MAX as usize {
            return Err(MortarError::InvalidOption(format!(
                "the {side} mesh has {} points; at most {} are supported",
                mesh.n_points(),
                u32::MAX
            )));
        }
    }
    Ok(())
}

fn check_options(o: &MortarOptions) -> Result<(), MortarError> {
    let bad = |m: String| Err(MortarError::InvalidOption(m));
    let gap = match o.max_gap {
        MaxGap::Relative(v) | MaxGap::Absolute(v) => v,
    };
    if !(gap.is_finite() && gap >= 0.0) {
        return bad(format!("the max gap must be a finite non-negative number, got {gap}"));
    }
    if !(o.max_angle_degrees > 0.0 && o.max_angle_degrees < 90.0) {
        return bad(format!("the max angle must lie in (0, 90) degrees, got {}", o.max_angle_degrees));
    }
    if let Some(degree) = o.warped_quad_degree {
        if degree == 0 || degree > MAX_TRIANGLE_DEGREE {
            return bad(format!("the quadrature degree must lie in 1..={MAX_TRIANGLE_DEGREE}, got {degree}"));
        }
    }
    Ok(())
}

fn summarize<'a>(
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    faces: impl Iterator<Item = &'a FaceStats>,
) -> MortarSummary {
    let count = |m: &SurfaceMesh| m.used_points().iter().filter(|&&u| u).count();
    let mut s = MortarSummary {
        slave_nodes: count(slave),
        master_nodes: count(master),
        slave_faces: slave.n_faces(),
        master_faces: master.n_faces(),
        ..Default::default()
    };
    for f in faces {
        s.candidate_pairs += f.candidates as usize;
        s.intersecting_pairs += f.intersecting as usize;
        s.segments += f.segments as usize;
        s.slave_area += f.area;
        s.covered_area += f.covered_area;
        s.max_gap = s.max_gap.max(f.max_gap);
        s.max_overlap = s.max_overlap.max(f.max_overlap);
        s.inverse_failures += f.inverse_failures as usize;
        s.dual_fallbacks += f.dual_fallbacks as usize;
    }
    s
}
