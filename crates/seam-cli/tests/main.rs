//! The integration tests of `seam-cli`, one module per subject, in one test
//! binary (one link per crate).

mod catalogue;
mod cli;
mod common;
mod contact;
mod examples;
mod exodus;
mod finite;
mod friction;
mod history;
mod inputs;
#[cfg(feature = "mpi")]
mod mpi;
mod output;
#[cfg(feature = "petsc")]
mod petsc;
mod solve;
mod supports;
