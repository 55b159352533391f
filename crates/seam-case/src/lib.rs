//! # seam-case — the application layer shared by the `seam` binary and Python
//!
//! What a user writes, checked before any heavy work:
//!
//! | input | module | checked |
//! |---|---|---|
//! | case files of `seam solve` (TOML) | [`case`] | syntax, names and references, materials, the coupling graph (no surface coupled twice, no cycle), that every body is held, that the mesh files are regular files |
//! | expressions in x, y, z of `seam transfer --expr` | [`expression`] | syntax, variables, size and nesting; every value finite |
//! | worker threads (`--threads`, `threads=`) | [`threads`] | at least 1, at most a few per core |
//!
//! And the pipeline of `seam solve` and `seam.solve`: [`solve`] reads the
//! meshes of a checked case, solves it and writes its results all-or-nothing,
//! one run at a time per directory and recovered after a kill
//! ([`output::Staged`]). The file-level pipelines of `seam assemble`
//! ([`assemble`]) and `seam transfer` ([`transfer`]), on surfaces read with
//! their fields ([`input`]).
//!
//! Errors display as one line naming the file (or the expression) and the item
//! at fault.
//!
//! The other direction, a [`seam_fem::Problem`] in memory written as a case
//! (meshes and `case.toml`): [`write`](mod@write). The human report of a solved case:
//! [`report`]. Failures sorted by exit code: [`Failure`].
//!
//! And what both front ends report: [`check()`], how two surfaces meet
//! (`seam check`, `seam.check`). With the feature `mpi`: the protocol of a
//! run over MPI ranks (`ranks`).
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod assemble;
pub mod case;
pub mod check;
pub mod expression;
mod failure;
pub mod input;
pub mod output;
pub mod process;
#[cfg(feature = "mpi")]
pub mod ranks;
pub mod report;
pub mod solve;
pub mod threads;
pub mod transfer;
pub mod write;

pub use case::{
    Body, Case, CaseError, ContactSettings, Dirichlet, Interface, InterfaceKind, Output, SurfaceRef, Traction,
};
pub use check::{check, Check, CheckError, CheckReport, GapBin, Invariant, Quality};
pub use expression::{Expression, ExpressionError};
pub use failure::{in_context, one_line, Failure};
