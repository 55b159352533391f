//! Linear elasticity for seam (being written).
#![forbid(unsafe_code)]
#![deny(missing_docs)]
