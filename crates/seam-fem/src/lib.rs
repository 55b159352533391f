//! # seam-fem — linear elasticity on volume meshes
//!
//! Small-strain isotropic linear elasticity on every cell kind of seam's
//! catalogue, first and second order, possibly mixed, on a
//! [`seam::VolumeMesh`]: find u with
//!
//! ```text
//! −div σ(u) = b in Ω,   σ = C ε(u),   u = ū on Γ_D,   σ n = t on Γ_N,
//! ```
//!
//! discretised as K u = f, 3 dofs per point, `dof = 3·point + component`.
//!
//! | stage | module |
//! |---|---|
//! | reference cells: shape functions, quadrature | [`element`] |
//! | E, ν → λ, μ, C | [`material`] |
//! | K, body-force and traction loads (parallel, deterministic) | [`assembly`] |
//! | Dirichlet conditions, sparse Cholesky solve | [`solve`](mod@solve) |
//! | bodies, interfaces, one dof numbering, the assembled system | [`multibody`] |
//! | gluing (paper's first application) | [`glue`] |
//! | glued bodies over MPI ranks: K where its cells are | [`partition`] |
//! | frictionless contact, mixed with glue (second application) | [`contact`] |
//! | how the linear systems are solved: [`Solver`] | [`backend`] |
//! | one solve for any mix of glue and contact, and its solution | [`coupled`], [`solution`], [`problem`] |
//! | load steps in pseudo-time, amplitudes, values varying in space and time | [`history`] |
//! | cell, nodal and von Mises stresses | [`stress`] |
//! | structured blocks for tests and examples | [`generate`] |
//!
//! ```
//! use seam_fem::generate::{block, BlockKind, Grid, Side};
//! use seam_fem::solve::solve;
//! use seam_fem::{recover_stresses, stiffness, traction, Dirichlet, Material};
//!
//! // A unit cube clamped at x = 0 and pulled by a traction of 1 in x at x = 1.
//! let (n, material) = (3, Material::new(1000.0, 0.3)?);
//! let mesh = block(n, n, n, |u, v, w| [u, v, w], BlockKind::Hex);
//! let grid = Grid::new(n, n, n);
//! let k = stiffness(&mesh, &material)?;
//! let f = traction(&grid.side_faces(&mesh, Side::XMax)?, |_, _| [1.0, 0.0, 0.0]);
//! let mut bc = Dirichlet::new();
//! bc.clamp(grid.side_points(Side::XMin));
//! let u = solve(&k, &f, &bc)?;
//! let s = recover_stresses(&mesh, &material, &u)?;
//! // The total force is carried through every section: mean σ_xx = 1.
//! let mean: f64 = s.cell.iter().map(|c| c[0]).sum::<f64>() / s.cell.len() as f64;
//! assert!((mean - 1.0).abs() < 0.05);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod assembly;
pub mod backend;
mod constraints;
pub mod contact;
pub mod coupled;
pub mod element;
pub mod enrichment;
pub mod finite;
pub mod generate;
pub mod glue;
pub mod history;
pub mod hyperelastic;
pub mod material;
pub mod multibody;
pub mod partition;
pub mod problem;
pub mod saddle;
pub mod scene;
pub mod solution;
pub mod solve;
pub mod stress;

pub use assembly::{
    body_force, cell_volumes, rigid_body_modes, stiffness, stiffness_times, traction, AssemblyError,
};
pub use backend::Solver;
pub use coupled::solve_coupled;
pub use element::{CellKind, VolumeRule};
pub use enrichment::{enrich, Enriched, Tie};
pub use history::{Amplitude, HistoryError, LoadSteps, Value};
pub use hyperelastic::Law;
pub use material::{Material, MaterialError};
pub use multibody::{Body, Coupling, Interface, OperatorAssembler, Operators, ProblemError, Timings};
pub use problem::{
    solve, solve_steps, Load, Problem, ProblemBody, ProblemInterface, Steps, Support, SurfaceId, MAX_CUTS,
};
pub use solution::{
    ActiveSetStep, ContactFields, ContactReport, InterfaceSolution, Kkt, Report, Solution, SolveOptions,
};
pub use solve::{Dirichlet, SolveError};
pub use stress::{recover_stresses, von_mises, Stresses};
pub mod ordering;
pub mod pcg;
pub mod petsc;

/// FNV-1a over 64-bit words: a fingerprint to know a matrix (its pattern,
/// its values, the dofs it holds) again.
pub(crate) struct Fnv(pub(crate) u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    #[inline]
    pub(crate) fn add(&mut self, word: u64) {
        self.0 = (self.0 ^ word).wrapping_mul(0x0100_0000_01b3);
    }

    /// The fingerprint of `words`.
    pub(crate) fn of(words: impl Iterator<Item = u64>) -> u64 {
        let mut h = Fnv::default();
        words.for_each(|w| h.add(w));
        h.0
    }
}
