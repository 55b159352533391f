//! The integration tests of `seam-examples`, one module per subject, in one test
//! binary (one link per crate).

mod rerun;
