//! The integration tests of `seam-case`, one module per subject, in one test
//! binary (one link per crate).

mod fuzz_regressions;
