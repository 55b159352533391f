//! How the linear systems of glue and contact are solved: the solver chosen
//! once for a whole solve.

use crate::pcg::PcgOptions;
use crate::petsc::PetscOptions;

/// The linear solver of a glued system, or of each active-set step of
/// contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Solver {
    /// Sparse Cholesky of the reduced system (dual, lumped) or sparse LU of the
    /// saddle point (standard).
    Direct,
    /// Preconditioned conjugate gradients on the reduced system PᵀKP,
    /// matrix-free.
    Pcg(PcgOptions),
    /// A PETSc KSP on the reduced system PᵀKP, assembled (dual and lumped
    /// multipliers: by default CG + GAMG with the rigid-body modes), on the
    /// saddle point (standard multipliers: FGMRES with a Schur-complement
    /// field split), and on each active-set step of contact
    /// ([`crate::petsc`]; cargo feature `petsc`).
    Petsc(PetscOptions),
}
