//! The integration tests of `seam-io`, one module per subject, in one test
//! binary (one link per crate).

mod abaqus;
mod coupling;
mod exodus;
mod fuzz_regressions;
mod large_blocks;
mod msh;
mod msh_write;
mod vtu;
