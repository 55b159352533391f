//! The volume elements: seam's cell kinds with their reference nodes, shape
//! functions and gradients, and quadrature rules, all read from the element
//! catalogue ([`seam::catalogue`]); [`ElementKind`] is [`seam::CellKind`] by the
//! name seam-fem has used for it.

pub use seam::{gauss_legendre, CellKind as ElementKind, VolumeRule, Xi3 as Xi, MAX_CELL_NODES as MAX_NODES};
