//! The volume elements: seam's cell kinds with their reference nodes, shape
//! functions and gradients, and quadrature rules, all read from the element
//! catalogue ([`seam::catalogue`]).

pub use seam::{gauss_legendre, CellKind, VolumeRule, Xi3, MAX_CELL_NODES};
