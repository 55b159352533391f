//! # seam-examples — the built-in examples, the benchmark and their pictures
//!
//! What `seam example NAME -o DIR` and `seam bench` run, as library code the
//! binary only calls and prints:
//!
//! | example | module | what it does |
//! |---|---|---|
//! | `operator` | [`operator`] | writes two surface meshes, assembles B, D, T as `seam assemble` does, measures the invariants |
//! | `warped-glue` | [`warped_glue`] | two blocks glued at a warped interface (the paper's Fig. 2), with a picture |
//! | `bulging-contact` | [`bulging_contact`] | two blocks with bulging facing sides in contact (Fig. 3), with a picture |
//! | `hertz` | [`hertz`] | an indenter on a block against Hertz's solution: table, CSV and chart |
//! | `cattaneo-mindlin` | [`cattaneo_mindlin`] | the indenter pressed, then pushed sideways with friction, against Cattaneo–Mindlin's partial slip: table, CSV and chart |
//! | `ironing` | [`ironing`] | a hyperelastic indenter pressed into a slab and slid along it, frictionless and with friction: forces over the load steps, table, CSV and picture |
//!
//! The elasticity examples build their [`seam_fem::Problem`] in memory
//! (a scene of `seam_fem::scene`), write it as a case (one mesh per body and
//! `case.toml`, [`seam_case::write`]) for the user to rerun with `seam solve
//! DIR/case.toml --force`, and solve the problem in memory exactly as that
//! case is solved ([`seam_case::solve::solve_problem`]).
//!
//! [`bench`](mod@bench): the assembly benchmark's meshes, measurement and table.
//! [`picture`]: the small software rasteriser of the pictures.
//!
//! Every example returns the lines of its report; failures keep the exit
//! codes of `seam` apart ([`Failure`]).
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod bench;
pub mod bulging_contact;
mod case;
pub mod cattaneo_mindlin;
pub mod hertz;
pub mod ironing;
pub mod operator;
pub mod picture;
pub mod transfer_bench;
pub mod warped_glue;

pub use seam_case::Failure;
use std::path::PathBuf;

/// The options every example takes (sizes for tests and quick runs).
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// The output directory.
    pub output: PathBuf,
    /// Replace files that already exist in it.
    pub force: bool,
    /// warped-glue: h_s/h_m (default [`warped_glue::RATIO`]).
    pub ratio: Option<usize>,
    /// warped-glue, bulging-contact: slave cells across x and y; hertz,
    /// cattaneo-mindlin: slave cells across the uniform zone [0, 1.5a];
    /// ironing: indenter cells across
    /// (defaults: each module's `SLAVE_CELLS` or `FINE_CELLS`).
    pub slave_cells: Option<usize>,
    /// warped-glue: the element order, 1 (Hex8, the default) or 2 (Hex27 at
    /// the same numbers of nodes).
    pub order: Option<usize>,
}

/// A built-in example.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Example {
    /// [`operator`].
    Operator,
    /// [`warped_glue`].
    WarpedGlue,
    /// [`bulging_contact`].
    BulgingContact,
    /// [`hertz`].
    Hertz,
    /// [`cattaneo_mindlin`].
    CattaneoMindlin,
    /// [`ironing`].
    Ironing,
}

/// Runs `example` on the current rayon pool; returns its report, one line
/// each.
///
/// # Errors
/// Bad sizes, an existing file without `force`, an unwritable output
/// ([`Failure::Error`]), or surfaces that do not meet ([`Failure::NoCoupling`]).
pub fn run(example: Example, options: &Options) -> Result<Vec<String>, Failure> {
    match example {
        Example::Operator => operator::run(options),
        Example::WarpedGlue => warped_glue::run(options),
        Example::BulgingContact => bulging_contact::run(options),
        Example::Hertz => hertz::run(options),
        Example::CattaneoMindlin => cattaneo_mindlin::run(options),
        Example::Ironing => ironing::run(options),
    }
}
