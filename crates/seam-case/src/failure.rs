//! Why a file-level run (`seam assemble`, `transfer`, `check`, a built-in
//! example) failed, sorted as the exit codes of `seam` sort them, with the
//! error chain kept for [`crate::solve::one_line`].

use crate::solve::SolveFailure;
use std::path::Path;

/// A failed run: nothing to couple, or anything else.
#[derive(Debug)]
pub enum Failure {
    /// The run finished but found nothing to couple (`seam` exits with 1).
    NoCoupling(anyhow::Error),
    /// Anything else: bad input, unwritable output, … (`seam` exits with 2).
    Error(anyhow::Error),
    /// A check found incomplete coverage or a violated invariant, and the
    /// caller asked for that to fail (`seam check --strict` exits with 3).
    CheckFailed(anyhow::Error),
}

impl Failure {
    /// An assembly error: no overlap is "ran, found nothing to couple",
    /// naming the two files; anything else an error.
    pub fn from_coupling(e: seam::MortarError, slave: &Path, master: &Path) -> Failure {
        match e {
            e @ seam::MortarError::NoOverlap { .. } => Failure::NoCoupling(
                anyhow::anyhow!(e).context(format!("{} (slave) and {}", slave.display(), master.display())),
            ),
            e @ (seam::MortarError::LumpedSecondOrder { .. }
            | seam::MortarError::LumpedNotPositive { .. }) => {
                Failure::Error(anyhow::anyhow!(e).context(format!("{} (slave)", slave.display())))
            }
            e => Failure::Error(e.into()),
        }
    }

    /// The failure of a solve, with its exit-code class.
    pub fn from_solve(e: SolveFailure) -> Failure {
        match e {
            SolveFailure::NoCoupling(m) => Failure::NoCoupling(anyhow::anyhow!(m)),
            SolveFailure::Error(m) => Failure::Error(anyhow::anyhow!(m)),
        }
    }
}

impl<E: Into<anyhow::Error>> From<E> for Failure {
    fn from(e: E) -> Self {
        Failure::Error(e.into())
    }
}
