//! Rust errors → Python exceptions, all in one place.
//!
//! | Rust | Python |
//! |---|---|
//! | `seam::MeshError`, a negative face index | `seam.MeshError` (a `ValueError`) |
//! | `seam_io::MshError`, I/O kinds | `FileNotFoundError`, `PermissionError`, `IsADirectoryError`, `NotADirectoryError`, else `OSError` |
//! | `seam_io::MshError`, other kinds | `seam.MshError` (a `ValueError`) |
//! | `MortarError::InvalidOption` | `seam.InvalidOptionError` (a `seam.MortarError`, a `ValueError`) |
//! | `MortarError::NoOverlap` | `seam.NoOverlapError` (idem) |
//! | `MortarError::Factorization` | `seam.FactorizationError` (idem) |
//! | `MortarError::NonFinite` | `seam.MortarError` |
//! | `seam_case::CheckError` | as its `MortarError` |
//! | `seam_case::Failure::Case` | `seam.CaseError` (a `seam.SolveError`) |
//! | `seam_case::Failure::NoCoupling` | `seam.NoCouplingError` (a `seam.SolveError`) |
//! | `seam_case::Failure::Convergence` | `seam.ConvergenceError` (a `seam.SolveError`) |
//! | `seam_case::Failure`, other classes | `seam.SolveError` (a `ValueError`) |
//! | a panic (a bug) in the library | the entry point's class ([`Entry`]) |
//!
//! Messages are the Rust `Display` text, unchanged. Every call into the
//! library goes through [`detach`] or [`guard`], so that a panic reaches Python
//! as an exception `except Exception` catches, not as pyo3's
//! `PanicException` (a `BaseException`). The notices of output directories
//! (`seam_case::output`: waiting for another run writing there, what was
//! recovered from an interrupted one) are `seam.OutputWarning`s
//! ([`warn_notice`]).

use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyIsADirectoryError, PyNotADirectoryError, PyOSError, PyPermissionError,
    PyUserWarning, PyValueError,
};
use pyo3::{PyErr, PyResult, Python};
use seam::MortarError as CoreMortarError;
use seam_io::MshErrorKind;
use std::any::Any;
use std::io::ErrorKind;
use std::panic::{catch_unwind, AssertUnwindSafe};

create_exception!(
    seam,
    MeshError,
    PyValueError,
    "The points and faces do not form a valid surface mesh (non-finite coordinate, \
     node index out of range, repeated corner, zero-area face, no faces)."
);
create_exception!(
    seam,
    MshError,
    PyValueError,
    "A Gmsh MSH file could not be interpreted (the message gives the file and line)."
);
create_exception!(seam, MortarError, PyValueError, "The mortar assembly produced no operator.");
create_exception!(seam, InvalidOptionError, MortarError, "An option of `assemble` is out of range.");
create_exception!(
    seam,
    NoOverlapError,
    MortarError,
    "No master face meets a slave face within the gap and angle limits."
);
create_exception!(
    seam,
    FactorizationError,
    MortarError,
    "D restricted to the covered slave nodes is not positive definite."
);

create_exception!(
    seam,
    SolveError,
    PyValueError,
    "`seam.solve` could not solve the case or write its results (the one-line message of `seam solve`)."
);

create_exception!(
    seam,
    CaseError,
    SolveError,
    "The case (file or dict), an option of `seam.solve` or an input file is wrong."
);
create_exception!(
    seam,
    NoCouplingError,
    SolveError,
    "An interface whose surfaces do not meet: nothing to couple (`seam solve` exits with 1)."
);
create_exception!(
    seam,
    ConvergenceError,
    SolveError,
    "An iteration did not converge: PCG, PETSc's Krylov solver, or the contact active set."
);

/// The exception of a failed solve, by its class.
pub fn failure_error(e: seam_case::Failure) -> PyErr {
    use seam_case::Failure;
    match e {
        Failure::Case(m) => CaseError::new_err(m),
        Failure::NoCoupling(m) => NoCouplingError::new_err(m),
        Failure::Convergence(m) => ConvergenceError::new_err(m),
        Failure::Error(m) | Failure::CheckFailed(m) => SolveError::new_err(m),
    }
}

create_exception!(
    seam,
    OutputWarning,
    PyUserWarning,
    "A notice about an output directory: `write` waits for another run writing into it, or \
     recovered what an interrupted run left there (the one line `seam` prints on stderr)."
);

/// Issues a notice of an output directory as a `seam.OutputWarning` (a
/// warning that the filters turn into an error cannot interrupt the write:
/// it is dropped).
pub fn warn_notice(line: &str) {
    Python::attach(|py| {
        let message = std::ffi::CString::new(line.replace('\0', "")).unwrap_or_default();
        let _ = PyErr::warn(py, &py.get_type::<OutputWarning>(), &message, 1);
    });
}

/// `seam.MeshError` with the message of `e`.
pub fn mesh_error(e: seam::MeshError) -> PyErr {
    MeshError::new_err(e.to_string())
}

/// `seam.MortarError` subclasses by kind.
pub fn mortar_error(e: CoreMortarError) -> PyErr {
    mortar_error_saying(&e, e.to_string())
}

/// The class of `check`'s mortar error, with the message of `e` (which names
/// the stage that failed).
pub fn check_error(e: seam_case::CheckError) -> PyErr {
    mortar_error_saying(e.mortar_error(), e.to_string())
}

/// The `seam.MortarError` subclass of `e`'s kind with `message`.
fn mortar_error_saying(e: &CoreMortarError, message: String) -> PyErr {
    match e {
        CoreMortarError::InvalidOption(_) => InvalidOptionError::new_err(message),
        CoreMortarError::NoOverlap { .. } => NoOverlapError::new_err(message),
        CoreMortarError::Factorization(_) => FactorizationError::new_err(message),
        CoreMortarError::NonFinite { .. } => MortarError::new_err(message),
        // A multiplier the slave faces do not admit: an invalid option for them.
        CoreMortarError::LumpedSecondOrder { .. } | CoreMortarError::LumpedNotPositive { .. } => {
            InvalidOptionError::new_err(message)
        }
    }
}

/// I/O failures become the `OSError` subclass of their kind, built like Python
/// builds them, `(errno, strerror, filename)`: `strerror` is the message without
/// the path (the path is `filename`). Everything else is `seam.MshError`.
pub fn msh_error(e: seam_io::MshError) -> PyErr {
    let MshErrorKind::Io(io) = e.kind() else {
        return MshError::new_err(e.to_string());
    };
    let strerror = e.kind().to_string();
    let filename = e.path().map(|p| p.to_string_lossy().into_owned());
    macro_rules! os_error {
        ($class:ty) => {
            match (io.raw_os_error(), filename) {
                (Some(errno), Some(filename)) => <$class>::new_err((errno, strerror, filename)),
                (Some(errno), None) => <$class>::new_err((errno, strerror)),
                (None, _) => <$class>::new_err(e.to_string()),
            }
        };
    }
    match io.kind() {
        ErrorKind::NotFound => os_error!(PyFileNotFoundError),
        ErrorKind::PermissionDenied => os_error!(PyPermissionError),
        ErrorKind::IsADirectory => os_error!(PyIsADirectoryError),
        ErrorKind::NotADirectory => os_error!(PyNotADirectoryError),
        _ => os_error!(PyOSError),
    }
}

/// Which kind of call into the library: the class a panic in it becomes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Entry {
    /// Building a mesh (`seam.Mesh`, tuples): `seam.MeshError`.
    Mesh,
    /// Reading an MSH file: `seam.MshError`.
    ReadMesh,
    /// Assembling, checking or applying an operator: `seam.MortarError`.
    Mortar,
    /// Solving a case or writing its results: `seam.SolveError`.
    Solve,
}

impl Entry {
    /// The entry named `name` ("mesh", "read_mesh", "mortar", "solve").
    pub fn named(name: &str) -> Option<Entry> {
        [
            ("mesh", Entry::Mesh),
            ("read_mesh", Entry::ReadMesh),
            ("mortar", Entry::Mortar),
            ("solve", Entry::Solve),
        ]
        .into_iter()
        .find_map(|(n, e)| (n == name).then_some(e))
    }

    /// The exception of a panic with `payload` in this entry.
    pub fn panic_error(self, payload: &(dyn Any + Send)) -> PyErr {
        let message = panic_message(payload);
        match self {
            Entry::Mesh => MeshError::new_err(message),
            Entry::ReadMesh => MshError::new_err(message),
            Entry::Mortar => MortarError::new_err(message),
            Entry::Solve => SolveError::new_err(message),
        }
    }
}

/// The one-line message of a panic: what it said (a `&str` or `String`
/// payload), marked as seam's bug.
pub fn panic_message(payload: &(dyn Any + Send)) -> String {
    let said = payload
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("(no message)");
    let first = said.lines().next().unwrap_or_default();
    format!("internal error in seam (a bug; please report it with the input): {first}")
}

/// `_seam._panic_in(entry)`, for the tests: panics inside [`detach`] as a
/// call into the library of `entry` ("mesh", "read_mesh", "mortar",
/// "solve") would, and raises what that call raises then.
#[pyo3::pyfunction]
pub fn _panic_in(py: Python<'_>, entry: &str) -> PyResult<()> {
    let entry = Entry::named(entry).ok_or_else(|| PyValueError::new_err(format!("no entry {entry:?}")))?;
    detach(py, entry, || -> () { panic!("a panic forced by a test\nsecond line") })
}

/// `f()` with the GIL released, a panic in it turned into `entry`'s exception.
pub fn detach<T: Send>(py: Python<'_>, entry: Entry, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    py.detach(|| catch_unwind(AssertUnwindSafe(f))).map_err(|payload| entry.panic_error(&*payload))
}
