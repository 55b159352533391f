//! The integration tests of `seam`, one module per subject, in one test
//! binary (one link per crate).

mod convergence;
mod curved;
mod exact_segments;
mod moved;
mod noise;
mod operator;
mod parts;
