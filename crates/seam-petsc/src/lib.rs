//! seam's PETSc layer: a sparse symmetric system A x = b solved by a PETSc
//! KSP, by default conjugate gradients preconditioned by smoothed-aggregation
//! algebraic multigrid (GAMG) with block size 3 and the six rigid-body modes
//! of the points as its near-nullspace — what PETSc's own elasticity example
//! (`src/ksp/ksp/tutorials/ex56.c`) does. Any PETSc option reaches it: from
//! the `PETSC_OPTIONS` environment variable, from the string given to
//! [`initialize`], e.g. `-pc_type hypre`, `-pc_type lu
//! -pc_factor_mat_solver_type mumps`, `-ksp_monitor`, `-log_view`.
//!
//! PETSc's API is built on C macros (communicators, error checks), so its
//! calls are written once in C (`src/shim.c`, compiled against the
//! installed headers) and reach Rust through the few functions of the `ffi`
//! module; this crate is the only one of the workspace with `unsafe` code,
//! every block of it in this file with its justification.
//!
//! - PETSc (and MPI) is initialised once per process, on the first
//!   [`initialize`], and finalised at process exit (so `-log_view` prints
//!   its table then).
//! - PETSc is not thread-safe: every call into it holds one process-wide
//!   lock.
//! - Errors are [`PetscError`]: one line, PETSc's own message (a bad option
//!   such as `-pc_type nonsense`, a failed setup); a KSP that stops without
//!   converging is reported by [`Report::converged`] with PETSc's reason.
//!
//! Systems live on `PETSC_COMM_WORLD`: on one process the matrices are
//! sequential. Under `mpirun` with N > 1 ranks, rank 0 [`lead`]s: it calls
//! this layer as one process would, and every call is carried out by all
//! ranks, the others having called [`follow`]; each rank holds a contiguous
//! block of the rows (whole points, balanced by entries) in PETSc's
//! distributed matrices and vectors (MPIAIJ), and the solution comes back
//! whole to rank 0. Between calls the leader may hand each rank a job of
//! the program's own ([`send_jobs`], answered by [`reply`]), e.g. its cells:
//! each rank then [`stage`]s its entries of a matrix, and
//! [`System::staged`] forms the system from them over the ranks without
//! the matrix ever being whole on one of them.

use std::ffi::{c_char, c_int, CStr, CString};
use std::ptr::NonNull;
use std::sync::Mutex;

/// The C functions of `src/shim.c` and the layout of what they share.
mod ffi {
    use std::ffi::{c_char, c_int};

    /// PETSc's `PetscInt` in this build (32-bit indices: `PETSC_SIZEOF_INT
    /// 4`, checked by [`super::initialize`] against the shim's `sizeof`).
    pub type PetscInt = i32;

    /// `seam_petsc_report` of the shim.
    #[repr(C)]
    pub struct RawReport {
        pub iterations: PetscInt,
        pub ksp_residual: f64,
        pub true_residual: f64,
        pub reason: c_int,
        pub reason_name: [c_char; 64],
        pub ksp_type: [c_char; 64],
        pub pc_type: [c_char; 64],
        pub assembly_seconds: f64,
        pub setup_seconds: f64,
        pub solve_seconds: f64,
        pub ranks: c_int,
    }

    /// The shim's opaque `seam_petsc_system` (a Mat and its KSP).
    #[repr(C)]
    pub struct RawSystem {
        _private: [u8; 0],
    }

    extern "C" {
        pub fn seam_petsc_initialize(
            argc: c_int,
            argv: *mut *mut c_char,
            more: *const c_char,
            world_size: *mut c_int,
            err: *mut c_char,
            errlen: usize,
        ) -> c_int;
        pub fn seam_petsc_petscint_size() -> c_int;
        pub fn seam_petsc_finalize();
        pub fn seam_petsc_lead() -> c_int;
        pub fn seam_petsc_follow(
            failed: *mut c_int,
            job: *mut *mut u8,
            job_len: *mut usize,
            err: *mut c_char,
            errlen: usize,
        ) -> c_int;
        pub fn seam_petsc_send_jobs(parts: *const *const u8, lens: *const usize);
        pub fn seam_petsc_reply(bytes: *const u8, len: usize);
        pub fn seam_petsc_receive_reply(rank: c_int, len: *mut usize) -> *mut u8;
        pub fn seam_petsc_release_bytes(bytes: *mut u8);
        pub fn seam_petsc_stage(
            count: usize,
            i: *mut *mut PetscInt,
            j: *mut *mut PetscInt,
            v: *mut *mut f64,
        ) -> c_int;
        pub fn seam_petsc_system_create_staged(
            n: PetscInt,
            n_first: PetscInt,
            bs: PetscInt,
            ranges: *const PetscInt,
            modes: *const f64,
            n_modes: PetscInt,
            symmetric: c_int,
            ksp_type: *const c_char,
            pc_type: *const c_char,
            rtol: f64,
            max_it: PetscInt,
            out: *mut *mut RawSystem,
            err: *mut c_char,
            errlen: usize,
        ) -> c_int;
        pub fn seam_petsc_yield();
        pub fn seam_petsc_system_create(
            n: PetscInt,
            n_first: PetscInt,
            bs: PetscInt,
            rowptr: *const PetscInt,
            cols: *const PetscInt,
            vals: *const f64,
            modes: *const f64,
            n_modes: PetscInt,
            symmetric: c_int,
            ksp_type: *const c_char,
            pc_type: *const c_char,
            rtol: f64,
            max_it: PetscInt,
            out: *mut *mut RawSystem,
            err: *mut c_char,
            errlen: usize,
        ) -> c_int;
        pub fn seam_petsc_system_solve(
            s: *mut RawSystem,
            b: *const f64,
            x: *mut f64,
            nonzero_guess: c_int,
            rtol: f64,
            report: *mut RawReport,
            err: *mut c_char,
            errlen: usize,
        ) -> c_int;
        pub fn seam_petsc_system_set_operator(
            s: *mut RawSystem,
            rowptr: *const PetscInt,
            cols: *const PetscInt,
            vals: *const f64,
            refresh: c_int,
            err: *mut c_char,
            errlen: usize,
        ) -> c_int;
        pub fn seam_petsc_system_values(
            s: *mut RawSystem,
            values: *mut *mut f64,
            count: *mut PetscInt,
            err: *mut c_char,
            errlen: usize,
        ) -> c_int;
        pub fn seam_petsc_system_values_written(s: *mut RawSystem, err: *mut c_char, errlen: usize) -> c_int;
        pub fn seam_petsc_system_destroy(s: *mut RawSystem);
    }
}

use ffi::PetscInt;

/// The one lock around every call into PETSc (not thread-safe).
static PETSC: Mutex<State> = Mutex::new(State { initialised: false, leading: false, ranks: 1 });

/// PETSc in this process.
struct State {
    /// PETSc has been initialised.
    initialised: bool,
    /// This process leads the other MPI ranks ([`lead`]).
    leading: bool,
    /// The ranks it leads, itself included (1 when it does not lead).
    ranks: usize,
}

/// A PETSc failure, as one line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct PetscError(pub String);

/// Length of the shim's error buffers.
const ERR_LEN: usize = 512;

fn error_text(buffer: &[c_char; ERR_LEN], code: c_int) -> PetscError {
    // SAFETY: the shim writes a NUL-terminated string (snprintf) into the
    // zero-initialised buffer, which stays NUL-terminated in any case.
    let text = unsafe { CStr::from_ptr(buffer.as_ptr()) }.to_string_lossy().trim().to_string();
    PetscError(if text.is_empty() { format!("PETSc error code {code}") } else { text })
}

fn c_string(field: &[c_char; 64]) -> String {
    // SAFETY: snprintf in the shim NUL-terminates every 64-byte field.
    unsafe { CStr::from_ptr(field.as_ptr()) }.to_string_lossy().into_owned()
}

fn lock() -> std::sync::MutexGuard<'static, State> {
    // A panic while holding the lock leaves PETSc in a consistent state (the
    // shim has returned): go on with the guard.
    PETSC.lock().unwrap_or_else(|e| e.into_inner())
}

/// Finalises PETSc now, if it was initialised: for a program that
/// initialised MPI itself and finalises it before exiting (PETSc must go
/// first). A leader first releases its followers ([`follow`] returns there).
/// Later PETSc calls fail; the exit handler does nothing.
pub fn finalize() {
    let _guard = lock();
    // SAFETY: no argument; PetscFinalize when PETSc is initialised and not
    // finalised, under the lock that every other PETSc call takes.
    unsafe { ffi::seam_petsc_finalize() }
}

/// Makes this process (rank 0 of an MPI run that the program initialised)
/// the leader of the other ranks, which call [`follow`]: every later call of
/// this layer here runs on all ranks, the systems distributed over them.
/// Returns the number of ranks. [`finalize`] releases the followers.
pub fn lead() -> usize {
    let mut state = lock();
    // SAFETY: no argument; reads MPI's rank and size (MPI is initialised by
    // the caller, or the shim reports one process).
    let size = unsafe { ffi::seam_petsc_lead() };
    state.leading = true;
    state.ranks = size.max(1) as usize;
    state.ranks
}

/// The ranks this process's systems are distributed over: those it
/// [`lead`]s, itself included; 1 when it does not lead.
pub fn ranks() -> usize {
    lock().ranks
}

/// Why [`follow`] returned.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Followed {
    /// The leader finalised: call [`finalize`] and end.
    Released,
    /// The leader [`yield_followers`]: do the leader's other work (the
    /// program's own protocol), then follow again.
    Yielded,
    /// The leader sent this rank a job ([`send_jobs`]): do it, answer it
    /// ([`reply`]), then follow again.
    Job(Vec<u8>),
}

/// A rank other than 0 of an MPI run whose rank 0 [`lead`]s: carries out the
/// leader's calls (PETSc's initialisation, building and solving its systems
/// on this rank's rows) until the leader finalises or yields.
///
/// # Errors
/// On release, when a call failed on this rank (the leader has been told,
/// and has failed with its own message): PETSc's message.
pub fn follow() -> Result<Followed, PetscError> {
    let mut err = [0 as c_char; ERR_LEN];
    let mut failed: c_int = 0;
    let (mut job, mut job_len) = (std::ptr::null_mut(), 0usize);
    // SAFETY: failed is a valid int, job and job_len valid pointers, err has
    // ERR_LEN bytes. The loop returns when the leader releases, yields or
    // sends a job; no other thread of this process calls PETSc meanwhile (a
    // follower does nothing else), so the lock is not taken: the shim's
    // PETSc calls are all on this thread.
    let code =
        unsafe { ffi::seam_petsc_follow(&mut failed, &mut job, &mut job_len, err.as_mut_ptr(), ERR_LEN) };
    match (code, failed) {
        (2, _) => Ok(Followed::Job(take_bytes(job, job_len))),
        (1, _) => Ok(Followed::Yielded),
        (_, 0) => Ok(Followed::Released),
        (_, failed) => Err(error_text(&err, failed)),
    }
}

/// The leader hands its followers back to their program ([`follow`] returns
/// [`Followed::Yielded`]), for work of the program's own between PETSc
/// calls; nothing when this process does not lead.
pub fn yield_followers() {
    let _guard = lock();
    // SAFETY: no argument; a broadcast to the followers when this process
    // leads, under the lock that every other PETSc call takes.
    unsafe { ffi::seam_petsc_yield() }
}

/// Copies a buffer of the shim (`len` bytes, NULL when empty) and releases it.
fn take_bytes(bytes: *mut u8, len: usize) -> Vec<u8> {
    if bytes.is_null() {
        return Vec::new();
    }
    // SAFETY: the shim allocated `bytes` with room for `len` bytes, all
    // received; it is released exactly once, here, after the copy.
    unsafe {
        let copy = std::slice::from_raw_parts(bytes, len).to_vec();
        ffi::seam_petsc_release_bytes(bytes);
        copy
    }
}

/// The leader sends rank r the job `parts[r − 1]` (bytes of the program's
/// own protocol), for every rank it leads: their [`follow`] returns
/// [`Followed::Job`]; their answers come by [`receive_reply`]. Nothing when
/// this process does not lead other ranks.
///
/// # Panics
/// When `parts` has not one entry per other rank.
pub fn send_jobs(parts: &[Vec<u8>]) {
    let state = lock();
    if state.ranks <= 1 {
        return;
    }
    assert_eq!(parts.len(), state.ranks - 1, "one job per other rank");
    let pointers: Vec<*const u8> = parts.iter().map(|p| p.as_ptr()).collect();
    let lens: Vec<usize> = parts.iter().map(Vec::len).collect();
    // SAFETY: one pointer and length per other rank, each valid for its
    // length during the call (the shim sends them before returning); under
    // the lock that every other PETSc call takes.
    unsafe { ffi::seam_petsc_send_jobs(pointers.as_ptr(), lens.as_ptr()) }
}

/// A follower answers the job that [`follow`] returned.
pub fn reply(bytes: &[u8]) {
    let _guard = lock();
    // SAFETY: bytes is valid for its length during the call (sent before
    // the shim returns).
    unsafe { ffi::seam_petsc_reply(bytes.as_ptr(), bytes.len()) }
}

/// The leader: rank `rank`'s answer to its job ([`send_jobs`]), waited for.
pub fn receive_reply(rank: usize) -> Vec<u8> {
    let _guard = lock();
    let mut len = 0usize;
    // SAFETY: len is a valid pointer; the shim returns a buffer of len bytes
    // that take_bytes copies and releases. The leader receives only from
    // ranks it sent a job to, which answer once.
    let bytes = unsafe { ffi::seam_petsc_receive_reply(rank as c_int, &mut len) };
    take_bytes(bytes, len)
}

/// Stages this rank's part of a matrix assembled where its cells are
/// ([`System::staged`]): `count` entries (row, column, value; global
/// indices, any rows, repeated entries summed) that `fill` writes. Replaces
/// what was staged before.
///
/// # Errors
/// Out of memory.
pub fn stage(
    count: usize,
    fill: impl FnOnce(&mut [Index], &mut [Index], &mut [f64]),
) -> Result<(), PetscError> {
    let _guard = lock();
    let (mut i, mut j, mut v) = (std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null_mut());
    // SAFETY: valid out-pointers; on success the shim points them at arrays
    // of count + 1 entries that it owns until the next stage or system.
    if unsafe { ffi::seam_petsc_stage(count, &mut i, &mut j, &mut v) } != 0 {
        return Err(PetscError(format!("out of memory staging {count} matrix entries")));
    }
    // SAFETY: the three arrays were just allocated with room for count
    // entries, are distinct, and nothing else touches them until the shim
    // consumes them in a later call (made under the lock, after this one).
    unsafe {
        fill(
            std::slice::from_raw_parts_mut(i, count),
            std::slice::from_raw_parts_mut(j, count),
            std::slice::from_raw_parts_mut(v, count),
        )
    };
    Ok(())
}

/// Initialises PETSc on the first call (with `options`, a string of PETSc
/// options such as `"-pc_type hypre -ksp_monitor"`, as if given on the
/// command line, after those of `PETSC_OPTIONS`); later calls add `options`
/// to PETSc's options database. PETSc is finalised at process exit.
///
/// # Errors
/// PETSc's initialisation failed, the options do not parse, or the process
/// runs under `mpirun` with more than one rank without leading them
/// ([`lead`]).
pub fn initialize(options: &str) -> Result<(), PetscError> {
    let mut state = lock();
    let options_c = CString::new(options)
        .map_err(|_| PetscError("PETSc options must not contain a NUL character".into()))?;
    let mut err = [0 as c_char; ERR_LEN];
    let mut world = 0;
    let code = if state.initialised {
        // SAFETY: PETSc is initialised; the strings are NUL-terminated and
        // outlive the call; err has ERR_LEN bytes; world is a valid int.
        unsafe {
            ffi::seam_petsc_initialize(
                0,
                std::ptr::null_mut(),
                options_c.as_ptr(),
                &mut world,
                err.as_mut_ptr(),
                ERR_LEN,
            )
        }
    } else {
        // argv as PETSc's command line: the program name, no signal handler
        // of PETSc's (Rust's own stay in place), then the options. PETSc
        // keeps pointers into argv: the strings are leaked on purpose (once
        // per process).
        let words = ["seam", "-no_signal_handler"]
            .into_iter()
            .map(String::from)
            .chain(options.split_whitespace().map(String::from));
        let mut argv: Vec<*mut c_char> =
            words.map(|w| CString::new(w).expect("no NUL: checked above").into_raw()).collect();
        argv.push(std::ptr::null_mut());
        let argv = Box::leak(argv.into_boxed_slice());
        // SAFETY: argv is a NULL-terminated array of argc NUL-terminated
        // strings that live for the rest of the process; err and world as above.
        let code = unsafe {
            ffi::seam_petsc_initialize(
                (argv.len() - 1) as c_int,
                argv.as_mut_ptr(),
                std::ptr::null(),
                &mut world,
                err.as_mut_ptr(),
                ERR_LEN,
            )
        };
        if code == 0 {
            state.initialised = true;
            // SAFETY: a pure function of the shim (returns sizeof(PetscInt)).
            let size = unsafe { ffi::seam_petsc_petscint_size() };
            if size as usize != std::mem::size_of::<PetscInt>() {
                return Err(PetscError(format!(
                    "this PETSc uses {size}-byte indices; seam's layer is built for {}",
                    std::mem::size_of::<PetscInt>()
                )));
            }
        }
        code
    };
    if code != 0 {
        return Err(error_text(&err, code));
    }
    if world > 1 && !state.leading {
        return Err(PetscError(format!(
            "running on {world} MPI ranks, but only rank 0 of `seam solve` built with the mpi feature leads them"
        )));
    }
    Ok(())
}

/// The structure of a system's matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Structure {
    /// Points of `block_size` unknowns each (3 for elasticity).
    Blocks(usize),
    /// A saddle point [A Bᵀ; B 0]: its first `first` unknowns (A's, in
    /// points of `block_size`) and the others (B's rows), split by
    /// PCFIELDSPLIT when the PC is "fieldsplit": Schur complement, upper
    /// triangular factorisation, the complement approximated by
    /// B diag(A)⁻¹ Bᵀ ("selfp"), one GAMG cycle on A and Jacobi on the
    /// approximation unless the options say otherwise
    /// (`-fieldsplit_0_pc_type`, `-fieldsplit_1_ksp_type`, …).
    Saddle {
        /// Unknowns of the first field.
        first: usize,
        /// Its points' size.
        block_size: usize,
    },
}

/// How the KSP is set up before the options database has its say.
#[derive(Clone, Debug, PartialEq)]
pub struct KspConfig {
    /// KSP type (`-ksp_type`), e.g. "cg".
    pub ksp_type: String,
    /// PC type (`-pc_type`), e.g. "gamg".
    pub pc_type: String,
    /// Relative tolerance of the residual (`-ksp_rtol`).
    pub rtol: f64,
    /// Iteration cap (`-ksp_max_it`).
    pub max_iterations: usize,
    /// The matrix is symmetric (told to PETSc).
    pub symmetric: bool,
}

impl Default for KspConfig {
    fn default() -> Self {
        KspConfig {
            ksp_type: "cg".into(),
            pc_type: "gamg".into(),
            rtol: 1e-10,
            max_iterations: 10_000,
            symmetric: true,
        }
    }
}

/// What a solve reports.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// KSP iterations.
    pub iterations: usize,
    /// The residual norm KSP's convergence test used (preconditioned for CG
    /// by default).
    pub ksp_residual: f64,
    /// ‖b − A x‖₂ / ‖b‖₂ at the end.
    pub residual: f64,
    /// PETSc's `KSPConvergedReason` (> 0 converged, < 0 diverged).
    pub reason: i32,
    /// Its name, e.g. "CONVERGED_RTOL", "DIVERGED_ITS".
    pub reason_name: String,
    /// The KSP type used (after the options).
    pub ksp_type: String,
    /// The PC type used.
    pub pc_type: String,
    /// Seconds to build the PETSc matrix.
    pub assembly_seconds: f64,
    /// Seconds of KSPSetUp (the preconditioner), since the last report.
    pub setup_seconds: f64,
    /// Seconds of KSPSolve.
    pub solve_seconds: f64,
    /// The MPI ranks the system was distributed over (1: one process).
    pub ranks: usize,
}

impl Report {
    /// Whether the KSP converged.
    pub fn converged(&self) -> bool {
        self.reason > 0
    }
}

/// A square sparse matrix in PETSc with its KSP, the preconditioner set up:
/// solve with any number of right-hand sides.
pub struct System {
    raw: NonNull<ffi::RawSystem>,
    n: usize,
}

/// A matrix in compressed sparse rows: `rowptr` (n + 1 offsets), sorted
/// 0-based `cols` and `values` of each row.
#[derive(Clone, Copy, Debug)]
pub struct Csr<'a> {
    /// Row offsets.
    pub rowptr: &'a [Index],
    /// Column indices.
    pub cols: &'a [Index],
    /// Values.
    pub values: &'a [f64],
}

/// PETSc's index type (`PetscInt`: 32 bits in Debian's PETSc), in which
/// matrices are passed without a copy of their indices.
pub type Index = PetscInt;

fn index(v: usize, what: &str) -> Result<PetscInt, PetscError> {
    PetscInt::try_from(v).map_err(|_| PetscError(format!("{what} {v} exceeds PETSc's 32-bit indices")))
}

impl System {
    /// Builds the matrix (of `structure`) and its KSP, with the span of
    /// `near_nullspace` (vectors of as many entries as the points' unknowns:
    /// n, or a saddle point's first field; e.g. the rigid-body modes for
    /// elasticity; orthonormalised here, dependent ones dropped) as the
    /// near-nullspace that GAMG's aggregates must represent. Options in
    /// PETSc's database override `config`. [`initialize`] must have been
    /// called.
    ///
    /// # Errors
    /// A PETSc error (an unknown type in the options, a failed setup), or
    /// inconsistent input.
    pub fn new(
        matrix: Csr<'_>,
        structure: Structure,
        near_nullspace: &[Vec<f64>],
        config: &KspConfig,
    ) -> Result<System, PetscError> {
        let n = matrix.rowptr.len().saturating_sub(1);
        let nnz = matrix.rowptr.last().map_or(0, |&v| v.max(0) as usize);
        let (first, block_size) = match structure {
            Structure::Blocks(block_size) => (n, block_size),
            Structure::Saddle { first, block_size } => (first, block_size),
        };
        let consistent = !matrix.rowptr.is_empty()
            && matrix.cols.len() == nnz
            && matrix.values.len() == nnz
            && block_size > 0
            && first <= n
            && first % block_size == 0
            && matrix.cols.iter().all(|&c| c >= 0 && (c as usize) < n)
            && matrix.rowptr.windows(2).all(|w| w[0] <= w[1])
            && near_nullspace.iter().all(|v| v.len() == first);
        if !consistent {
            return Err(PetscError("inconsistent matrix passed to PETSc".into()));
        }
        let Inputs { modes, n_modes, ksp_type, pc_type } = Inputs::new(near_nullspace, first, config)?;
        let guard = initialised()?;
        let mut raw = std::ptr::null_mut();
        let mut err = [0 as c_char; ERR_LEN];
        // SAFETY: the arrays have the lengths the shim reads (n + 1 offsets,
        // nnz columns and values, n entries per near-nullspace vector), checked
        // above; the shim copies them into PETSc objects before returning; the
        // strings are NUL-terminated; raw receives a new system or stays NULL.
        let code = unsafe {
            ffi::seam_petsc_system_create(
                index(n, "size")?,
                index(first, "size")?,
                index(block_size, "block size")?,
                matrix.rowptr.as_ptr(),
                matrix.cols.as_ptr(),
                matrix.values.as_ptr(),
                modes.as_ptr(),
                index(n_modes, "near-nullspace size")?,
                c_int::from(config.symmetric),
                ksp_type.as_ptr(),
                pc_type.as_ptr(),
                config.rtol,
                index(config.max_iterations, "iteration cap")?,
                &mut raw,
                err.as_mut_ptr(),
                ERR_LEN,
            )
        };
        drop(guard);
        System::created(code, raw, n, &err)
    }

    /// The n × n matrix of every rank's staged entries ([`stage`]: summed
    /// where repeated, each sent to the rank that holds its row), never
    /// whole on one rank, and its KSP: rank r holds rows
    /// `ranges[r]..ranges[r + 1]` (ranges has [`ranks`] + 1 entries, n last; whole
    /// points of `structure` below its first field's end). The structure,
    /// near-nullspace (on the first field) and `config` as in
    /// [`System::new`].
    ///
    /// # Errors
    /// As [`System::new`].
    pub fn staged(
        ranges: &[Index],
        structure: Structure,
        near_nullspace: &[Vec<f64>],
        config: &KspConfig,
    ) -> Result<System, PetscError> {
        let n = ranges.last().map_or(0, |&r| r.max(0) as usize);
        let (first, block_size) = match structure {
            Structure::Blocks(block_size) => (n, block_size),
            Structure::Saddle { first, block_size } => (first, block_size),
        };
        let consistent = ranges.len() == ranks() + 1
            && ranges.first() == Some(&0)
            && block_size > 0
            && first <= n
            && first % block_size == 0
            && ranges
                .windows(2)
                .all(|r| r[0] <= r[1] && (r[0] as usize >= first || r[0] as usize % block_size == 0))
            && near_nullspace.iter().all(|v| v.len() == first);
        if !consistent {
            return Err(PetscError("inconsistent rows passed to PETSc".into()));
        }
        let Inputs { modes, n_modes, ksp_type, pc_type } = Inputs::new(near_nullspace, first, config)?;
        let guard = initialised()?;
        let mut raw = std::ptr::null_mut();
        let mut err = [0 as c_char; ERR_LEN];
        // SAFETY: ranges has ranks + 1 entries and modes `first` per vector,
        // checked above (the shim copies the rows each rank needs before
        // returning); the staged entries are the shim's own; the strings are
        // NUL-terminated; raw receives a new system or stays NULL.
        let code = unsafe {
            ffi::seam_petsc_system_create_staged(
                index(n, "size")?,
                index(first, "size")?,
                index(block_size, "block size")?,
                ranges.as_ptr(),
                modes.as_ptr(),
                index(n_modes, "near-nullspace size")?,
                c_int::from(config.symmetric),
                ksp_type.as_ptr(),
                pc_type.as_ptr(),
                config.rtol,
                index(config.max_iterations, "iteration cap")?,
                &mut raw,
                err.as_mut_ptr(),
                ERR_LEN,
            )
        };
        drop(guard);
        System::created(code, raw, n, &err)
    }

    /// Solves A x = b; `x` is the initial guess when `nonzero_guess`.
    ///
    /// # Errors
    /// A PETSc error during the solve (not a KSP that did not converge: see
    /// [`Report::converged`]).
    pub fn solve(&mut self, b: &[f64], x: &mut [f64], nonzero_guess: bool) -> Result<Report, PetscError> {
        self.solve_to(b, x, nonzero_guess, None)
    }

    /// Replaces the operator by `matrix` (n × n, any pattern; e.g. the next
    /// Newton matrix) and keeps the preconditioner set up for the matrix the
    /// system was built with: later solves apply `matrix`, preconditioned as
    /// before, without a new setup.
    ///
    /// # Errors
    /// A PETSc error, or a matrix of another size or inconsistent.
    pub fn set_operator(&mut self, matrix: Csr<'_>) -> Result<(), PetscError> {
        self.replace(matrix, false)
    }

    /// Gives the system's matrix the values of `matrix`, whose entries lie in
    /// the pattern the system was built with (entries of that pattern
    /// missing from it become zeros), and makes it the operator again: the
    /// next solve sets the preconditioner up for it anew, GAMG keeping the
    /// interpolation it built at the first setup (only the coarse
    /// operators PᵀAP and the smoothers are formed again).
    ///
    /// # Errors
    /// A PETSc error (an entry outside the pattern), or a matrix of another
    /// size or inconsistent.
    pub fn refresh(&mut self, matrix: Csr<'_>) -> Result<(), PetscError> {
        self.replace(matrix, true)
    }

    /// [`System::refresh`] in place: `fill` writes the new values into the
    /// system's own array (its compressed rows, columns ascending within a
    /// row, as the matrix it was built with), without a copy of the
    /// matrix (`fill` must not call PETSc). Returns false, without calling
    /// `fill`, where PETSc's matrix is not one array (several ranks, a type
    /// other than AIJ).
    ///
    /// # Errors
    /// A PETSc error.
    pub fn refresh_in_place(&mut self, fill: impl FnOnce(&mut [f64])) -> Result<bool, PetscError> {
        let _guard = lock();
        let mut err = [0 as c_char; ERR_LEN];
        let (mut values, mut count): (*mut f64, PetscInt) = (std::ptr::null_mut(), 0);
        // SAFETY: self.raw is a live system; the shim writes the pointer to
        // its matrix's value array (or NULL) and its length.
        let code = unsafe {
            ffi::seam_petsc_system_values(
                self.raw.as_ptr(),
                &mut values,
                &mut count,
                err.as_mut_ptr(),
                ERR_LEN,
            )
        };
        if code != 0 {
            return Err(error_text(&err, code));
        }
        if values.is_null() {
            return Ok(false);
        }
        // SAFETY: the shim gave the matrix's own array of `count` values,
        // which nothing else touches while self is borrowed mutably (the
        // lock is held; PETSc runs on this thread only) and which lives as
        // long as the matrix; the slice ends with this call.
        fill(unsafe { std::slice::from_raw_parts_mut(values, count.max(0) as usize) });
        // SAFETY: as above; the shim marks the matrix changed.
        let code =
            unsafe { ffi::seam_petsc_system_values_written(self.raw.as_ptr(), err.as_mut_ptr(), ERR_LEN) };
        match code {
            0 => Ok(true),
            code => Err(error_text(&err, code)),
        }
    }

    /// [`System::set_operator`] (`refresh` false) or [`System::refresh`].
    fn replace(&mut self, matrix: Csr<'_>, refresh: bool) -> Result<(), PetscError> {
        let n = self.n;
        let nnz = matrix.rowptr.last().map_or(0, |&v| v.max(0) as usize);
        let consistent = matrix.rowptr.len() == n + 1
            && matrix.rowptr[0] == 0
            && matrix.cols.len() == nnz
            && matrix.values.len() == nnz
            && matrix.cols.iter().all(|&c| c >= 0 && (c as usize) < n)
            && matrix.rowptr.windows(2).all(|w| w[0] <= w[1]);
        if !consistent {
            return Err(PetscError("inconsistent operator passed to PETSc".into()));
        }
        let _guard = lock();
        let mut err = [0 as c_char; ERR_LEN];
        // SAFETY: self.raw is a live system of size n; the arrays have the
        // lengths the shim reads (n + 1 offsets, nnz columns and values),
        // checked above, and are copied into a PETSc matrix before it returns.
        let code = unsafe {
            ffi::seam_petsc_system_set_operator(
                self.raw.as_ptr(),
                matrix.rowptr.as_ptr(),
                matrix.cols.as_ptr(),
                matrix.values.as_ptr(),
                c_int::from(refresh),
                err.as_mut_ptr(),
                ERR_LEN,
            )
        };
        match code {
            0 => Ok(()),
            code => Err(error_text(&err, code)),
        }
    }

    /// [`System::solve`] to the relative tolerance `rtol` for this solve
    /// (None: the system's, after PETSc's options).
    ///
    /// # Errors
    /// As [`System::solve`].
    pub fn solve_to(
        &mut self,
        b: &[f64],
        x: &mut [f64],
        nonzero_guess: bool,
        rtol: Option<f64>,
    ) -> Result<Report, PetscError> {
        if b.len() != self.n || x.len() != self.n {
            return Err(PetscError(format!(
                "right-hand side of {} and solution of {} entries for a system of {}",
                b.len(),
                x.len(),
                self.n
            )));
        }
        let _guard = lock();
        let mut raw = std::mem::MaybeUninit::<ffi::RawReport>::zeroed();
        let mut err = [0 as c_char; ERR_LEN];
        // SAFETY: self.raw is a live system of size n; b and x have n
        // entries and are only used during the call (wrapped, not kept, by
        // PETSc Vecs that the shim destroys before returning); the report is
        // written in full by the shim (memset first).
        let code = unsafe {
            ffi::seam_petsc_system_solve(
                self.raw.as_ptr(),
                b.as_ptr(),
                x.as_mut_ptr(),
                c_int::from(nonzero_guess),
                rtol.unwrap_or(0.0),
                raw.as_mut_ptr(),
                err.as_mut_ptr(),
                ERR_LEN,
            )
        };
        if code != 0 {
            return Err(error_text(&err, code));
        }
        // SAFETY: zero-initialised and filled by the shim: every field valid.
        let raw = unsafe { raw.assume_init() };
        Ok(Report {
            iterations: raw.iterations.max(0) as usize,
            ksp_residual: raw.ksp_residual,
            residual: raw.true_residual,
            reason: raw.reason,
            reason_name: c_string(&raw.reason_name),
            ksp_type: c_string(&raw.ksp_type),
            pc_type: c_string(&raw.pc_type),
            assembly_seconds: raw.assembly_seconds,
            setup_seconds: raw.setup_seconds,
            solve_seconds: raw.solve_seconds,
            ranks: raw.ranks.max(1) as usize,
        })
    }
}

/// What the shim's creation of a system takes besides its matrix: the
/// near-nullspace orthonormalised (`first` entries a vector, one after the
/// other), their count, the KSP and PC types as C strings.
struct Inputs {
    modes: Vec<f64>,
    n_modes: usize,
    ksp_type: CString,
    pc_type: CString,
}

impl Inputs {
    fn new(near_nullspace: &[Vec<f64>], first: usize, config: &KspConfig) -> Result<Inputs, PetscError> {
        let modes = orthonormal(near_nullspace);
        let n_modes = modes.len().checked_div(first).unwrap_or(0);
        let (ksp_type, pc_type) =
            (CString::new(config.ksp_type.as_str()), CString::new(config.pc_type.as_str()));
        let (Ok(ksp_type), Ok(pc_type)) = (ksp_type, pc_type) else {
            return Err(PetscError("KSP and PC types must not contain a NUL character".into()));
        };
        Ok(Inputs { modes, n_modes, ksp_type, pc_type })
    }
}

/// The lock, once PETSc is initialised.
fn initialised() -> Result<std::sync::MutexGuard<'static, State>, PetscError> {
    let guard = lock();
    match guard.initialised {
        true => Ok(guard),
        false => Err(PetscError("PETSc is not initialised".into())),
    }
}

impl System {
    /// The system the shim created (`code` 0, `raw` set), or its error.
    fn created(
        code: c_int,
        raw: *mut ffi::RawSystem,
        n: usize,
        err: &[c_char; ERR_LEN],
    ) -> Result<System, PetscError> {
        match (code, NonNull::new(raw)) {
            (0, Some(raw)) => Ok(System { raw, n }),
            _ => Err(error_text(err, code)),
        }
    }
}

/// An orthonormal basis of the span of `vectors` (modified Gram–Schmidt,
/// twice; vectors whose remainder is below 1e-10 of their norm are dropped),
/// one after the other.
fn orthonormal(vectors: &[Vec<f64>]) -> Vec<f64> {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for v in vectors {
        let norm = dot(v, v).sqrt();
        let mut w = v.clone();
        for _ in 0..2 {
            for q in &basis {
                let c = dot(&w, q);
                w.iter_mut().zip(q).for_each(|(a, b)| *a -= c * b);
            }
        }
        let rest = dot(&w, &w).sqrt();
        if norm > 0.0 && rest > 1e-10 * norm {
            w.iter_mut().for_each(|a| *a /= rest);
            basis.push(w);
        }
    }
    basis.concat()
}

impl Drop for System {
    fn drop(&mut self) {
        let _guard = lock();
        // SAFETY: self.raw came from seam_petsc_system_create and is destroyed
        // exactly once, here.
        unsafe { ffi::seam_petsc_system_destroy(self.raw.as_ptr()) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1D Laplacian (tridiagonal 2, −1) of n unknowns in CSR.
    fn laplacian(n: usize) -> (Vec<Index>, Vec<Index>, Vec<f64>) {
        let (mut rowptr, mut cols, mut values) = (vec![0], Vec::new(), Vec::new());
        for i in 0..n {
            for j in i.saturating_sub(1)..(i + 2).min(n) {
                cols.push(j as Index);
                values.push(if i == j { 2.0 } else { -1.0 });
            }
            rowptr.push(cols.len() as Index);
        }
        (rowptr, cols, values)
    }

    /// A x.
    fn multiply(a: Csr<'_>, x: &[f64]) -> Vec<f64> {
        a.rowptr
            .windows(2)
            .map(|r| (r[0] as usize..r[1] as usize).map(|k| a.values[k] * x[a.cols[k] as usize]).sum())
            .collect()
    }

    #[test]
    fn cg_solves_a_laplacian_and_bad_options_are_one_line_errors() {
        initialize("").unwrap();
        let n = 30;
        let (rowptr, cols, values) = laplacian(n);
        let matrix = Csr { rowptr: &rowptr, cols: &cols, values: &values };
        let config = KspConfig { pc_type: "jacobi".into(), rtol: 1e-12, ..KspConfig::default() };
        let mut system = System::new(matrix, Structure::Blocks(1), &[], &config).unwrap();
        // x = (1, 2, …, n): b = A x.
        let exact: Vec<f64> = (1..=n).map(|i| i as f64).collect();
        let b: Vec<f64> = (0..n)
            .map(|i| {
                (rowptr[i] as usize..rowptr[i + 1] as usize)
                    .map(|k| values[k] * exact[cols[k] as usize])
                    .sum()
            })
            .collect();
        let mut x = vec![0.0; n];
        let report = system.solve(&b, &mut x, false).unwrap();
        assert!(report.converged(), "{report:?}");
        assert_eq!((report.ksp_type.as_str(), report.pc_type.as_str()), ("cg", "jacobi"));
        assert!(report.iterations > 0 && report.iterations <= n, "{report:?}");
        for i in 0..n {
            assert!((x[i] - exact[i]).abs() < 1e-8 * n as f64, "{i}: {} vs {}", x[i], exact[i]);
        }
        // An unknown PC type: PETSc's message, one line.
        let bad = KspConfig { pc_type: "nonsense".into(), ..KspConfig::default() };
        let e = System::new(matrix, Structure::Blocks(1), &[], &bad).err().expect("an unknown PC type fails");
        assert!(e.0.contains("nonsense") && !e.0.contains('\n'), "{e}");
        // An iteration cap of 1: solved without error, reported as diverged.
        let capped = KspConfig { pc_type: "none".into(), max_iterations: 1, ..KspConfig::default() };
        let mut system = System::new(matrix, Structure::Blocks(1), &[], &capped).unwrap();
        let report = system.solve(&b, &mut x, false).unwrap();
        assert!(!report.converged() && report.reason_name == "DIVERGED_ITS", "{report:?}");
    }

    /// A replaced operator is what later solves apply, preconditioned as
    /// before: ILU(0) of the Laplacian, exact for it, preconditions GMRES on
    /// the Laplacian plus a nonsymmetric band (and a row that changes its
    /// pattern); each solve's tolerance as asked.
    #[test]
    fn a_replaced_operator_is_solved_with_the_kept_preconditioner() {
        initialize("").unwrap();
        let n = 30;
        let (rowptr, cols, values) = laplacian(n);
        let config = KspConfig {
            ksp_type: "gmres".into(),
            pc_type: "ilu".into(),
            rtol: 1e-12,
            symmetric: false,
            ..KspConfig::default()
        };
        let matrix = Csr { rowptr: &rowptr, cols: &cols, values: &values };
        let mut system = System::new(matrix, Structure::Blocks(1), &[], &config).unwrap();
        let exact: Vec<f64> = (1..=n).map(|i| (i as f64 * 0.37).sin()).collect();
        let times =
            |rowptr: &[Index], cols: &[Index], values: &[f64]| multiply(Csr { rowptr, cols, values }, &exact);
        let mut x = vec![0.0; n];
        let report = system.solve(&times(&rowptr, &cols, &values), &mut x, false).unwrap();
        assert_eq!(report.iterations, 1, "ILU(0) of a tridiagonal matrix is exact: {report:?}");
        // B = A + 0.3 (superdiagonal) and row 0 = e₀ (a held unknown).
        let (mut rb, mut cb, mut vb) = (vec![0], Vec::new(), Vec::new());
        for i in 0..n {
            if i == 0 {
                cb.push(0);
                vb.push(1.0);
            } else {
                for k in rowptr[i] as usize..rowptr[i + 1] as usize {
                    cb.push(cols[k]);
                    vb.push(values[k] + if cols[k] as usize == i + 1 { 0.3 } else { 0.0 });
                }
            }
            rb.push(cb.len() as Index);
        }
        system.set_operator(Csr { rowptr: &rb, cols: &cb, values: &vb }).unwrap();
        let b = times(&rb, &cb, &vb);
        let mut x = vec![0.0; n];
        let loose = system.solve_to(&b, &mut x, false, Some(1e-2)).unwrap();
        let mut x = vec![0.0; n];
        let tight = system.solve_to(&b, &mut x, false, None).unwrap();
        assert!(
            loose.converged() && tight.converged() && loose.iterations < tight.iterations,
            "{loose:?} {tight:?}"
        );
        assert!(tight.iterations > 1 && tight.residual < 1e-11, "{tight:?}");
        for i in 0..n {
            assert!((x[i] - exact[i]).abs() < 1e-10, "{i}: {} against {}", x[i], exact[i]);
        }
        // Another size: refused.
        let (r, c, v) = laplacian(n + 3);
        assert!(system.set_operator(Csr { rowptr: &r, cols: &c, values: &v }).is_err());
    }

    /// A refreshed matrix is what later solves apply, and the preconditioner
    /// is set up for it: GAMG on a 1D Laplacian of 3 000 unknowns (several
    /// levels), then the same pattern with unknowns held (their rows and
    /// columns zero but for the diagonal), solved as a new system solves it,
    /// then the first values written in place; a value outside the pattern
    /// is refused in one line.
    #[test]
    fn a_refreshed_matrix_is_solved_with_its_own_preconditioner() {
        initialize("").unwrap();
        let n = 3000;
        let (rowptr, cols, values) = laplacian(n);
        let config = KspConfig { pc_type: "gamg".into(), rtol: 1e-12, ..KspConfig::default() };
        let matrix = Csr { rowptr: &rowptr, cols: &cols, values: &values };
        let mut system = System::new(matrix, Structure::Blocks(1), &[], &config).unwrap();
        let exact: Vec<f64> = (0..n).map(|i| (i as f64 * 0.01).sin()).collect();
        let times = |values: &[f64]| multiply(Csr { rowptr: &rowptr, cols: &cols, values }, &exact);
        let mut x = vec![0.0; n];
        assert!(system.solve(&times(&values), &mut x, false).unwrap().converged());
        let held = |i: usize| [0, 700, 701, 1500, 2999].contains(&i);
        let mut refreshed = values.clone();
        for i in 0..n {
            for k in rowptr[i] as usize..rowptr[i + 1] as usize {
                let j = cols[k] as usize;
                if i != j && (held(i) || held(j)) {
                    refreshed[k] = 0.0;
                }
            }
        }
        let b = times(&refreshed);
        system.refresh(Csr { rowptr: &rowptr, cols: &cols, values: &refreshed }).unwrap();
        let mut x = vec![0.0; n];
        let report = system.solve(&b, &mut x, false).unwrap();
        assert!(report.converged() && report.residual < 1e-11, "{report:?}");
        let error = x.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(error < 1e-8, "error {error:e}");
        let fresh = Csr { rowptr: &rowptr, cols: &cols, values: &refreshed };
        let mut new = System::new(fresh, Structure::Blocks(1), &[], &config).unwrap();
        let mut y = vec![0.0; n];
        let anew = new.solve(&b, &mut y, false).unwrap();
        assert!(report.iterations <= anew.iterations + 2, "refreshed {report:?}, new {anew:?}");
        // The first values again, written into PETSc's own array (one
        // process, AIJ): solved as the first system was.
        let written = system.refresh_in_place(|into| into.copy_from_slice(&values)).unwrap();
        assert!(written);
        let mut x = vec![0.0; n];
        let report = system.solve(&times(&values), &mut x, false).unwrap();
        let error = x.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(report.converged() && error < 1e-8, "{report:?}, error {error:e}");
        // An entry outside the pattern: one line.
        let (mut r, mut c, mut v) = (rowptr.clone(), cols.clone(), refreshed.clone());
        c.insert(3, 5);
        v.insert(3, 1.0);
        r.iter_mut().skip(2).for_each(|e| *e += 1);
        let e = system.refresh(Csr { rowptr: &r, cols: &c, values: &v }).unwrap_err();
        assert!(!e.0.contains('\n') && !e.0.is_empty(), "{e}");
    }

    /// A 1D Laplacian staged in halves (as two cells sharing each entry
    /// would): the system of their sums.
    #[test]
    fn a_staged_matrix_is_the_sum_of_its_entries() {
        initialize("").unwrap();
        let n = 30;
        let (rowptr, cols, values) = laplacian(n);
        stage(2 * values.len(), |si, sj, sv| {
            for i in 0..n {
                for k in rowptr[i] as usize..rowptr[i + 1] as usize {
                    for half in 0..2 {
                        (si[2 * k + half], sj[2 * k + half], sv[2 * k + half]) =
                            (i as Index, cols[k], values[k] / 2.0);
                    }
                }
            }
        })
        .unwrap();
        let config = KspConfig { pc_type: "jacobi".into(), rtol: 1e-13, ..KspConfig::default() };
        let mut system = System::staged(&[0, n as Index], Structure::Blocks(1), &[], &config).unwrap();
        let exact: Vec<f64> = (1..=n).map(|i| (i as f64 * 0.37).sin()).collect();
        let b: Vec<f64> = (0..n)
            .map(|i| {
                (rowptr[i] as usize..rowptr[i + 1] as usize)
                    .map(|k| values[k] * exact[cols[k] as usize])
                    .sum()
            })
            .collect();
        let mut x = vec![0.0; n];
        let report = system.solve(&b, &mut x, false).unwrap();
        assert!(report.converged(), "{report:?}");
        for i in 0..n {
            assert!((x[i] - exact[i]).abs() < 1e-10, "{i}: {} against {}", x[i], exact[i]);
        }
        // Rows that do not fit: refused.
        assert!(
            System::staged(&[0, 30, 60], Structure::Blocks(1), &[], &config).is_err(),
            "one rank here, two ranges"
        );
    }
}
