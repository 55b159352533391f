//! Why a run failed (`seam solve`, `assemble`, `transfer`, `check`, a
//! built-in example; `seam.solve` in Python), sorted by what the user must
//! change, and by the exit codes of `seam`.

use std::path::Path;

/// A failed run: its class and its message, one line naming the file and the
/// item at fault.
///
/// | class | what went wrong | `seam` exits with | Python raises |
/// |---|---|---|---|
/// | [`Case`](Failure::Case) | the case (file or dict), an option or an input file is wrong | 2 | `seam.CaseError` |
/// | [`NoCoupling`](Failure::NoCoupling) | the run finished but found nothing to couple | 1 | `seam.NoCouplingError` |
/// | [`Convergence`](Failure::Convergence) | an iteration did not converge (PCG, PETSc, the active set) | 2 | `seam.ConvergenceError` |
/// | [`Error`](Failure::Error) | anything else: a singular system, an unwritable output, … | 2 | `seam.SolveError` |
/// | [`CheckFailed`](Failure::CheckFailed) | `check --strict` found incomplete coverage or a violated invariant | 3 | — |
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Failure {
    /// The case, an option or an input file is wrong.
    #[error("{0}")]
    Case(String),
    /// The run finished but found nothing to couple.
    #[error("{0}")]
    NoCoupling(String),
    /// An iterative solve or the active-set iteration did not converge.
    #[error("{0}")]
    Convergence(String),
    /// Anything else.
    #[error("{0}")]
    Error(String),
    /// A check found incomplete coverage or a violated invariant, and the
    /// caller asked for that to fail.
    #[error("{0}")]
    CheckFailed(String),
}

impl Failure {
    /// The one-line message.
    pub fn message(&self) -> &str {
        match self {
            Failure::Case(m)
            | Failure::NoCoupling(m)
            | Failure::Convergence(m)
            | Failure::Error(m)
            | Failure::CheckFailed(m) => m,
        }
    }

    /// The exit code of `seam` for this failure (1, 2 or 3).
    pub fn exit_code(&self) -> u8 {
        match self {
            Failure::NoCoupling(_) => 1,
            Failure::CheckFailed(_) => 3,
            Failure::Case(_) | Failure::Convergence(_) | Failure::Error(_) => 2,
        }
    }

    /// An error and its causes as [`Failure::Error`] ([`one_line`]).
    pub fn error(e: &(dyn std::error::Error + 'static)) -> Failure {
        Failure::Error(one_line(e))
    }

    /// An error and its causes as [`Failure::Case`] ([`one_line`]).
    pub fn case(e: &(dyn std::error::Error + 'static)) -> Failure {
        Failure::Case(one_line(e))
    }

    /// An assembly error: no overlap is "ran, found nothing to couple",
    /// naming the two files; anything else an error.
    pub fn from_coupling(e: seam::MortarError, slave: &Path, master: &Path) -> Failure {
        match e {
            e @ seam::MortarError::NoOverlap { .. } => Failure::NoCoupling(in_context(
                format!("{} (slave) and {}", slave.display(), master.display()),
                &e,
            )),
            e @ (seam::MortarError::LumpedSecondOrder { .. }
            | seam::MortarError::LumpedNotPositive { .. }) => {
                Failure::Error(in_context(format!("{} (slave)", slave.display()), &e))
            }
            e => Failure::error(&e),
        }
    }
}

/// An error of a pipeline written with anyhow's context: [`Failure::Error`]
/// with the context and the causes on one line ([`one_line`]).
impl From<anyhow::Error> for Failure {
    fn from(e: anyhow::Error) -> Self {
        Failure::Error(one_line(e.as_ref()))
    }
}

/// The error and its causes on one line, "context: cause: cause", leaving out a
/// cause whose text the line already holds (many errors quote their source).
pub fn one_line(e: &(dyn std::error::Error + 'static)) -> String {
    in_context(String::new(), e)
}

/// `context`, then the error and its causes as [`one_line`] puts them.
pub fn in_context(context: String, e: &(dyn std::error::Error + 'static)) -> String {
    let mut line = context;
    let mut cause = Some(e);
    while let Some(e) = cause {
        let text = e.to_string();
        if !line.contains(&text) {
            if !line.is_empty() {
                line.push_str(": ");
            }
            line.push_str(&text);
        }
        cause = e.source();
    }
    line.replace('\n', " ")
}
