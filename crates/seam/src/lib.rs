//! # seam — mortar coupling between non-matching warped surface meshes
//!
//! For a slave surface Γs and a master surface Γm, seam assembles
//!
//! ```text
//! D_pq = ∫Γs ψ_p λ^s_q ,   B_pq = ∫Γs ψ_p (λ^m_q ∘ Φ) ,   T = D⁻¹B
//! ```
//!
//! following Dickopf & Krause, *Weak information transfer between non-matching
//! warped interfaces* (steps A1–D5). The pipeline, one module per stage:
//!
//! | stage | module | paper |
//! |---|---|---|
//! | the element catalogue: [`FaceKind`], [`CellKind`] and their descriptions | [`catalogue`] | |
//! | plain data: [`SurfaceMesh`], [`VolumeMesh`] | `mesh` | |
//! | reference elements, inverse projection | `element` | D1–D2 |
//! | second-order (curved) faces: Tri6, Quad8, Quad9 maps, control nets, inverse projection | [`curved`] | D1–D2 |
//! | triangle quadrature rules; volume rules: [`volume_rule`] | `quadrature` | D3 |
//! | proximity search: [`FaceTree`] | `search` | A1 |
//! | Householder frame, projection, polygon clipping | `clip` | C2–C4 |
//! | assembly of B, D; multipliers; transfer: [`assemble`], [`Mortar`], [`Transfer`] | `mortar` | A2–D5 |
//! | the result matrices: [`CsrMatrix`] | `sparse` | |
//! | patches on parametric surfaces (examples, tests, benchmarks) | [`generate`] | |
//!
//! The crate does no I/O; `seam-io` reads and writes files.
//!
//! ```
//! use seam::generate::{flat, patch, Pattern};
//! use seam::{assemble, MortarOptions, Multiplier};
//!
//! // Unit square: 4×4 quads (slave) against 5×3 cells of triangles (master).
//! let slave = patch(4, 4, Pattern::Quads, flat(1.0, 1.0));
//! let master = patch(5, 3, Pattern::Triangles, flat(1.0, 1.0));
//! let options = MortarOptions { multiplier: Multiplier::Dual, ..Default::default() };
//! let mortar = assemble(&master, &slave, &options)?;
//! assert!((mortar.summary.covered_area - 1.0).abs() < 1e-14);
//! assert!(mortar.d.is_diagonal());
//! // T = D⁻¹B maps a linear field on the master exactly onto the slave (I4).
//! let x: Vec<f64> = master.points().iter().map(|p| p[0]).collect();
//! let tx = mortar.transfer()?.apply(&x, 1);
//! for (p, point) in slave.points().iter().enumerate() {
//!     assert!((tx[p] - point[0]).abs() < 1e-13);
//! }
//! # Ok::<(), seam::MortarError>(())
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod catalogue;
pub mod clip;
pub mod curved;
mod element;
/// Small 3-vector operations on [`Point3`].
pub mod vec3 {
    pub use crate::element::{cross, dot, norm, sub};
}
pub mod generate;
mod mesh;
mod mortar;
mod named;
mod quadrature;
mod search;
mod sparse;
mod wire;

pub use catalogue::{
    Cell, CellKind, CellType, Face, FaceKind, FaceType, LocalFace, Shape, Xi, Xi3, MAX_CELL_NODES,
    MAX_FACE_NODES,
};
pub use clip::{
    clip_polygon_polygon, convex_hull, face_polygon, fan_triangles, make_strictly_convex, orient,
    polygon_area, stable_fan, ConvexClipper, Frame, Point2, Polygon, MAX_POLYGON, NEAR_COLLINEAR,
};
pub use element::{FaceElement, InverseMap, JacobianField, PlaneFace, PLANAR_WARP};
pub use mesh::{
    area_vector, is_proper_face, FaceOwner, MeshError, Point3, SurfaceMesh, VolumeMesh, MAX_MAGNITUDE,
    MIN_FACE_SIZE, ZERO_AREA_RTOL,
};
pub use mortar::{
    assemble, assemble_keeping, assemble_with_tree, face_integrals, face_quality, master_side, nodal_areas,
    nodal_normals, normal_gaps, normal_gaps_from, orientation_conflicts, reassemble, slave_faces_near,
    warped_quad_degree, BasisTransformation, FaceBlocks, FaceQuality, FaceStats, Facing, MasterSide, MaxGap,
    Mortar, MortarError, MortarOptions, MortarSummary, Multiplier, Segment, Transfer, BASIS_ALPHA,
    COVERED_FRACTION, TRI6_ALPHA, WARPED_RTOL,
};
pub use named::{Named, UnknownName};
pub use quadrature::{
    gauss_legendre, triangle_rule, volume_rule, TriangleRule, VolumeRule, MAX_TRIANGLE_DEGREE,
};
pub use search::{face_box, swept_box, FaceTree};
pub use sparse::CsrMatrix;
pub use wire::WireError;
/// The operator in parts, for distributed memory (MPI ranks).
pub mod parts {
    pub use crate::mortar::parts::*;
}
