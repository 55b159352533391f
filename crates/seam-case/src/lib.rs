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
//! Errors display as one line naming the file (or the expression) and the item
//! at fault.
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod case;
pub mod expression;
pub mod threads;

pub use case::{
    Body, Case, CaseError, CaseMultiplier, ContactSettings, Dirichlet, Interface, InterfaceKind, Output,
    SurfaceRef, Traction,
};
pub use expression::{Expression, ExpressionError};
