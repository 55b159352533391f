//! Dirichlet conditions by elimination and the sparse Cholesky solve.
//!
//! With the dofs split into free F and prescribed D (values ū_D),
//!
//! ```text
//! K_FF u_F = f_F − K_FD ū_D,      u_D = ū_D,
//! ```
//!
//! K_FF is symmetric positive definite when the prescribed dofs remove every
//! rigid-body motion of every connected body; it is factored as P K_FF Pᵀ = LLᵀ:
//!
//! - P is a fill-reducing ordering ([`FillOrdering`], [`crate::ordering`]); by
//!   default nested dissection on the graph of the points (the 3 dofs of a
//!   point stay together), whose factor costs O(n²) flops on 3D meshes against
//!   the faster growth of minimum degree.
//! - The symbolic and numeric factorisations (supernodal) and the triangular
//!   solves are faer's, run as a fixed number of tasks (8) on the current
//!   rayon pool: the same bits on any number of threads.
//!
//! For large problems where the factor does not fit, [`crate::pcg`] offers
//! preconditioned conjugate gradients.
//!
//! # Singularity
//! K_FF is singular (or numerically so) when a body can move without deforming.
//! In floating point the factorisation may then still succeed with a tiny pivot,
//! so the solve also checks itself: with the same factors it solves K_FF x = K_FF z
//! for a fixed vector z and requires ‖x − z‖_∞ ≤ [`SINGULAR_PROBE_RTOL`] ‖z‖_∞.
//! Along a null direction the error is O(‖z‖), elsewhere O(κ ε), so this
//! detects singular systems and rejects only those with a condition number
//! beyond ~10¹⁰.

use crate::ordering::{self, Graph};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal::SupernodalLltRef, CholeskySymbolicParams, LltRef,
    SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Accum, Conj, Mat, Par, Side};
use rayon::prelude::*;
use seam::CsrMatrix;
use std::collections::BTreeMap;
use std::time::Instant;

/// Largest relative error of the self-check solve (module doc) before the system
/// counts as singular.
pub const SINGULAR_PROBE_RTOL: f64 = 1e-6;

/// Why a solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// K is singular on the free dofs.
    #[error("the problem is singular: the body can move without deforming; add Dirichlet conditions")]
    Singular,
    /// The factorisation succeeded but iterative refinement stalls above its
    /// tolerance: the system is too ill-conditioned for the solver, for
    /// example a nearly incompressible material (ν close to 0.5).
    #[error("the system is too ill-conditioned to solve accurately: iterative refinement stalls at relative residual {residual:.1e}")]
    IllConditioned {
        /// ‖b − M x‖_∞ / ‖b‖_∞ where refinement stalled.
        residual: f64,
    },

    /// K is not square, or f does not have one entry per row of K.
    #[error("dimension mismatch: K is {nrows}×{ncols} and f has {f_len} entries")]
    Dimension {
        /// Rows of K.
        nrows: usize,
        /// Columns of K.
        ncols: usize,
        /// Entries of f.
        f_len: usize,
    },
    /// A Dirichlet condition refers to a dof that does not exist.
    #[error("Dirichlet condition on dof {dof} (point {}, component {}), but there are only {n_dofs} dofs", dof / 3, dof % 3)]
    DofOutOfRange {
        /// The dof.
        dof: usize,
        /// The number of dofs.
        n_dofs: usize,
    },
    /// A prescribed value is NaN or infinite.
    #[error("Dirichlet value of dof {dof} (point {}, component {}) is not finite", dof / 3, dof % 3)]
    NonFiniteValue {
        /// The dof.
        dof: usize,
    },
    /// A solve with a [`CholeskyAnalysis`] got another pattern of K, or left
    /// an analysed prescribed dof free.
    #[error("the matrix or the prescribed dofs do not match the analysed pattern")]
    PatternChanged,
    /// The Cholesky factor (or its workspace) could not be allocated.
    #[error("out of memory for the sparse Cholesky factor")]
    OutOfMemory,
    /// The sparse product CᵀC of a saddle point's constraints (PETSc's
    /// augmented system) could not be allocated, or its size overflows.
    #[error("out of memory for the product CᵀC of the constraints ({rows} rows, {entries} entries)")]
    ProductOutOfMemory {
        /// Rows of C.
        rows: usize,
        /// Entries of C.
        entries: usize,
    },
    /// The conjugate gradient iteration reached its iteration cap with
    /// ‖r‖ > rtol ‖b‖.
    #[error("conjugate gradients did not converge: relative residual {relative_residual:.1e} after {iterations} iterations")]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// ‖r‖ / ‖b‖ at the end.
        relative_residual: f64,
    },
    /// The iteration stagnated above its relative tolerance: round-off in
    /// double precision holds the residual there.
    #[error("the relative tolerance {rtol:.1e} is below what double precision reaches on this system: round-off holds the relative residual at {reached:.1e}; ask for a larger tolerance")]
    ToleranceUnreachable {
        /// The tolerance asked for.
        rtol: f64,
        /// The smallest relative residual reached.
        reached: f64,
    },
    /// A system that is not symmetric (the semismooth Newton step of
    /// frictional contact) was given to conjugate gradients.
    #[error("conjugate gradients (solver `pcg`) solve symmetric systems only, and this one is not symmetric: use solver `direct` or `petsc`")]
    NotSymmetric,
    /// The PETSc solver was asked for, but this build has no PETSc.
    #[error(
        "this seam was built without PETSc: build it with `cargo build --release -p seam-cli --features petsc` \
         (needs PETSc, e.g. `apt-get install petsc-dev pkg-config`)"
    )]
    PetscUnavailable,
    /// PETSc reported an error (PETSc's own message): an unknown option
    /// value, a failed setup.
    #[error("PETSc: {0}")]
    Petsc(String),
    /// The PETSc KSP stopped without converging.
    #[error("the PETSc solve did not converge: {reason} after {iterations} iterations, relative residual {residual:.1e}")]
    PetscNotConverged {
        /// PETSc's converged reason, e.g. "DIVERGED_ITS".
        reason: String,
        /// Iterations done.
        iterations: usize,
        /// ‖b − A x‖ / ‖b‖ at the end.
        residual: f64,
    },
}

/// Prescribed displacements: a value per fixed dof (`dof = 3·point + component`).
/// Fixing a dof again replaces its value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Dirichlet {
    values: BTreeMap<usize, f64>,
}

impl Dirichlet {
    /// No conditions.
    pub fn new() -> Dirichlet {
        Dirichlet::default()
    }

    /// Prescribes the components of `point` given as `Some(value)`:
    /// `fix(p, [Some(0.0), None, None])` fixes u_x only.
    pub fn fix(&mut self, point: usize, values: [Option<f64>; 3]) -> &mut Self {
        for (c, v) in values.iter().enumerate() {
            if let Some(v) = *v {
                self.values.insert(3 * point + c, v);
            }
        }
        self
    }

    /// Prescribes the same components and values on every point of `points`.
    pub fn fix_all(
        &mut self,
        points: impl IntoIterator<Item = usize>,
        values: [Option<f64>; 3],
    ) -> &mut Self {
        for p in points {
            self.fix(p, values);
        }
        self
    }

    /// Clamps the points: u = 0 in all three components.
    pub fn clamp(&mut self, points: impl IntoIterator<Item = usize>) -> &mut Self {
        self.fix_all(points, [Some(0.0); 3])
    }

    /// Prescribes one dof.
    pub fn fix_dof(&mut self, dof: usize, value: f64) -> &mut Self {
        self.values.insert(dof, value);
        self
    }

    /// The prescribed value of `dof`, if any.
    pub fn value(&self, dof: usize) -> Option<f64> {
        self.values.get(&dof).copied()
    }

    /// (dof, value) in increasing dof order.
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.values.iter().map(|(&d, &v)| (d, v))
    }

    /// Number of prescribed dofs.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// True when nothing is prescribed.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}

/// Solves K u = f with the Dirichlet conditions by elimination (module doc);
/// returns the full vector u (prescribed values included).
///
/// K must be symmetric (not checked; the factorisation reads the entries K_ij,
/// j ≥ i, of the free rows). Dofs whose
/// row of K has no stored entry (points that no cell uses) are not unknowns:
/// they get u = 0, or their prescribed value.
///
/// Uses [`DirectOptions::default`]; see [`solve_direct`].
///
/// # Errors
/// [`SolveError::Singular`] when K is (numerically) singular on the free dofs;
/// [`SolveError::Dimension`], [`SolveError::DofOutOfRange`],
/// [`SolveError::NonFiniteValue`] for inconsistent input;
/// [`SolveError::OutOfMemory`] when the factor does not fit.
pub fn solve(k: &CsrMatrix, f: &[f64], dirichlet: &Dirichlet) -> Result<Vec<f64>, SolveError> {
    solve_direct(k, f, dirichlet, &DirectOptions::default()).map(|(u, _)| u)
}

/// The fill-reducing ordering of the direct solver ([`crate::ordering`]).
///
/// The point variants order the graph of the points (the dof graph compressed
/// by the triples `dof = 3·point + component`) and number the free dofs of each
/// point consecutively; they are used when K has that 3 × 3 block pattern
/// (every point's three rows have the same columns, in whole triples), and
/// fall back to the dof graph otherwise.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FillOrdering {
    /// faer's approximate minimum degree on the dof graph.
    DofAmd,
    /// Approximate minimum degree on the point graph.
    PointAmd,
    /// Nested dissection on the point graph.
    #[default]
    NestedDissection,
}

/// Options of [`solve_direct`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DirectOptions {
    /// The fill-reducing ordering.
    pub ordering: FillOrdering,
}

/// What [`solve_direct`] did, and how long it took.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DirectReport {
    /// Number of unknowns (free dofs with a stored row).
    pub n_free: usize,
    /// True when the ordering ran on the point graph (3 × 3 blocks detected).
    pub point_blocks: bool,
    /// Seconds spent in the fill-reducing ordering (0 for
    /// [`FillOrdering::DofAmd`], which runs inside the symbolic phase).
    pub ordering_seconds: f64,
    /// Seconds of the symbolic factorisation (elimination tree, column counts,
    /// supernodes).
    pub symbolic_seconds: f64,
    /// Seconds of the numeric factorisation K_FF = L Lᵀ.
    pub numeric_seconds: f64,
    /// Seconds of the two triangular solves (right-hand side and probe).
    pub solve_seconds: f64,
    /// Stored entries of L.
    pub nnz_l: usize,
    /// True when faer chose its supernodal (blocked, BLAS-3) factorisation.
    pub supernodal: bool,
    /// Floating-point operations of the factorisation, Σ_j c_j² over the
    /// column counts c_j of L (diagonal included).
    pub flops: f64,
    /// Columns of the largest supernode (1 when simplicial).
    pub largest_supernode: usize,
}

/// The Dirichlet elimination: u holds the prescribed values, `free` the
/// unknown dofs in increasing order, `local[dof]` their reduced number.
struct Reduced {
    u: Vec<f64>,
    fixed: Vec<bool>,
    free: Vec<usize>,
    local: Vec<usize>,
}

impl Reduced {
    fn new(k: &CsrMatrix, f: &[f64], dirichlet: &Dirichlet) -> Result<Reduced, SolveError> {
        let n = k.nrows;
        if k.ncols != n || f.len() != n {
            return Err(SolveError::Dimension { nrows: k.nrows, ncols: k.ncols, f_len: f.len() });
        }
        let mut u = vec![0.0; n];
        let mut fixed = vec![false; n];
        for (dof, v) in dirichlet.iter() {
            if dof >= n {
                return Err(SolveError::DofOutOfRange { dof, n_dofs: n });
            }
            if !v.is_finite() {
                return Err(SolveError::NonFiniteValue { dof });
            }
            u[dof] = v;
            fixed[dof] = true;
        }
        let mut local = vec![usize::MAX; n];
        let mut free = Vec::new();
        for i in 0..n {
            if !fixed[i] && k.indptr[i + 1] > k.indptr[i] {
                local[i] = free.len();
                free.push(i);
            }
        }
        Ok(Reduced { u, fixed, free, local })
    }

    /// r_F = f_F − K_FD ū_D, by reduced number.
    fn rhs(&self, k: &CsrMatrix, f: &[f64]) -> Vec<f64> {
        self.free
            .iter()
            .map(|&i| {
                let (cols, values) = k.row(i);
                let mut b = f[i];
                for (&j, &v) in cols.iter().zip(values) {
                    if self.fixed[j] {
                        b -= v * self.u[j];
                    }
                }
                b
            })
            .collect()
    }
}

/// True when K is made of 3 × 3 blocks: every point's three rows have the same
/// columns, which come in whole triples (3q, 3q+1, 3q+2).
fn has_point_blocks(k: &CsrMatrix) -> bool {
    if k.nrows % 3 != 0 || k.ncols != k.nrows {
        return false;
    }
    (0..k.nrows / 3).all(|p| {
        let cols = k.row(3 * p).0;
        cols.len() % 3 == 0
            && k.row(3 * p + 1).0 == cols
            && k.row(3 * p + 2).0 == cols
            && cols.chunks_exact(3).all(|t| t[0] % 3 == 0 && t[1] == t[0] + 1 && t[2] == t[0] + 2)
    })
}

/// The fill-reducing permutation of the reduced system (`perm[new] = old`, by
/// reduced number), and whether it was computed on points.
fn reduced_ordering(k: &CsrMatrix, red: &Reduced, method: FillOrdering) -> (Vec<usize>, bool) {
    let m = red.free.len();
    let blocks = has_point_blocks(k);
    // Groups of consecutive reduced dofs: the free dofs of a point, or single dofs.
    let mut group = Vec::with_capacity(m);
    let mut starts = Vec::new();
    for (r, &i) in red.free.iter().enumerate() {
        if r == 0 || !blocks || red.free[r - 1] / 3 != i / 3 {
            starts.push(r);
        }
        group.push(starts.len() - 1);
    }
    let n_groups = starts.len();
    starts.push(m);
    let rows: Vec<Vec<usize>> = (0..n_groups)
        .into_par_iter()
        .map(|g| {
            let mut row: Vec<usize> = (starts[g]..starts[g + 1])
                .flat_map(|r| k.row(red.free[r]).0.iter())
                .map(|&j| red.local[j])
                .filter(|&l| l != usize::MAX)
                .map(|l| group[l])
                .collect();
            row.sort_unstable();
            row.dedup();
            row
        })
        .collect();
    let graph = Graph::from_rows(n_groups, |g| &rows[g]);
    drop(rows);
    let group_perm = match method {
        FillOrdering::NestedDissection => ordering::nested_dissection(&graph),
        _ => ordering::amd(&graph),
    };
    let perm = group_perm.iter().flat_map(|&g| starts[g]..starts[g + 1]).collect();
    (perm, blocks)
}

/// [`solve`] with a choice of ordering, reporting the phases (module doc).
///
/// The numeric factorisation and the solves run on the current rayon pool
/// (faer's `Par::rayon`); the ordering is deterministic, so the factor has the
/// same pattern whatever the number of threads.
///
/// # Errors
/// As [`solve`].
pub fn solve_direct(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    options: &DirectOptions,
) -> Result<(Vec<f64>, DirectReport), SolveError> {
    if k.ncols != k.nrows || f.len() != k.nrows {
        return Err(SolveError::Dimension { nrows: k.nrows, ncols: k.ncols, f_len: f.len() });
    }
    CholeskyAnalysis::new(k, dirichlet, options)?.solve(k, f, dirichlet)
}

/// The ordering and symbolic factorisation of K_FF for one sparsity pattern of
/// K and one set of prescribed dofs D, reusable for a sequence of solves with
/// other values on that pattern and more prescribed dofs E ⊇ D (an active set):
/// a dof of E \ D keeps its place in the pattern with an identity row and
/// column (u_i = ū_i), so only the numeric factorisation is repeated.
pub struct CholeskyAnalysis {
    /// Rows of K.
    n: usize,
    /// Stored entries of K (the pattern must not change).
    nnz: usize,
    /// D.
    fixed: Vec<bool>,
    /// F = the dofs not in D with a stored row, ascending, and their reduced numbers.
    free: Vec<usize>,
    local: Vec<usize>,
    /// Lower triangle of K_FF in CSC.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    sym: SymbolicCholesky<usize>,
    report: DirectReport,
}

impl CholeskyAnalysis {
    /// Orders and analyses K_FF for the prescribed dofs of `dirichlet` (D).
    ///
    /// # Errors
    /// [`SolveError::DofOutOfRange`], [`SolveError::NonFiniteValue`] for bad
    /// conditions, [`SolveError::OutOfMemory`].
    pub fn new(k: &CsrMatrix, dirichlet: &Dirichlet, options: &DirectOptions) -> Result<Self, SolveError> {
        Self::analyse(k, Reduced::new(k, &vec![0.0; k.nrows], dirichlet)?, options.ordering, None)
    }

    /// Orders (by `method`, or `order` of the reduced numbers when given)
    /// and analyses K_FF for the split of `red`.
    fn analyse(
        k: &CsrMatrix,
        red: Reduced,
        method: FillOrdering,
        order: Option<Vec<usize>>,
    ) -> Result<Self, SolveError> {
        let m = red.free.len();
        let mut col_ptr = Vec::with_capacity(m + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0usize);
        for (r, &i) in red.free.iter().enumerate() {
            let (cols, _) = k.row(i);
            row_idx.extend(cols.iter().map(|&j| red.local[j]).filter(|&l| l != usize::MAX && l >= r));
            col_ptr.push(row_idx.len());
        }
        let mut report = DirectReport { n_free: m, ..DirectReport::default() };
        let clock = Instant::now();
        let custom = match (order, method) {
            (Some(perm), _) => Some(perm),
            (None, FillOrdering::DofAmd) => None,
            (None, method) if m > 0 => {
                let (perm, blocks) = reduced_ordering(k, &red, method);
                report.point_blocks = blocks;
                Some(perm)
            }
            _ => None,
        }
        .map(|perm| {
            let inv = ordering::inverse(&perm);
            (perm, inv)
        });
        report.ordering_seconds = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let ord = match &custom {
            None => SymmetricOrdering::Amd,
            Some((fwd, inv)) => SymmetricOrdering::Custom(PermRef::new_checked(fwd, inv, m)),
        };
        let symbolic = SymbolicSparseColMatRef::new_checked(m, m, &col_ptr, None, &row_idx);
        let sym = factorize_symbolic_cholesky(symbolic, Side::Lower, ord, CholeskySymbolicParams::default())
            .map_err(|_| SolveError::OutOfMemory)?;
        drop(custom);
        report.symbolic_seconds = clock.elapsed().as_secs_f64();
        report.nnz_l = sym.len_val();
        (report.flops, report.largest_supernode) = factor_flops(&sym);
        report.supernodal = matches!(sym.raw(), SymbolicCholeskyRaw::Supernodal(_));
        let Reduced { fixed, free, local, .. } = red;
        Ok(CholeskyAnalysis { n: k.nrows, nnz: k.nnz(), fixed, free, local, col_ptr, row_idx, sym, report })
    }

    /// The Schur complement on the prescribed dofs `w` (each of D, with a
    /// stored row) of K with D \ W prescribed, O = F the others:
    ///
    /// ```text
    /// S = K_WW − K_WO K_OO⁻¹ K_OW .
    /// ```
    ///
    /// Formed without solves: K_{O∪W} + Σ, Σ = diag(K_WW), is factored with
    /// W last (O in this analysis's order), so that its trailing block gives
    /// L_WW L_WWᵀ = S + Σ. (The shift makes the matrix definite when S is
    /// only semidefinite: a body held by W alone.) S is symmetric; rows and
    /// columns in the order of `w`.
    ///
    /// # Errors
    /// [`SolveError::PatternChanged`] for another pattern of K or a dof of
    /// `w` that is free or has no stored row; [`SolveError::Singular`] when
    /// K_OO is singular or a diagonal entry of K_WW is not positive;
    /// [`SolveError::OutOfMemory`].
    pub fn schur_complement(&self, k: &CsrMatrix, w: &[usize]) -> Result<Mat<f64>, SolveError> {
        let (m, nw) = (self.free.len(), w.len());
        if k.nrows != self.n || k.nnz() != self.nnz || w.iter().any(|&d| d >= self.n || !self.fixed[d]) {
            return Err(SolveError::PatternChanged);
        }
        // F' = F ∪ W, numbered in ascending dofs; ordered as F, then W.
        let mut fixed = self.fixed.clone();
        for &d in w {
            if self.local[d] != usize::MAX
                || k.row(d).0.is_empty()
                || !std::mem::replace(&mut fixed[d], false)
            {
                return Err(SolveError::PatternChanged);
            }
        }
        let mut local = vec![usize::MAX; self.n];
        let mut free = Vec::with_capacity(m + nw);
        for i in (0..self.n).filter(|&i| !fixed[i] && k.indptr[i + 1] > k.indptr[i]) {
            local[i] = free.len();
            free.push(i);
        }
        let fwd = match self.sym.perm() {
            Some(perm) => perm.arrays().0.to_vec(),
            None => (0..m).collect(),
        };
        let order = fwd.iter().map(|&r| local[self.free[r]]).chain(w.iter().map(|&d| local[d])).collect();
        let red = Reduced { u: Vec::new(), fixed, free, local };
        let analysis = Self::analyse(k, red, FillOrdering::DofAmd, Some(order))?;
        let mut vals = analysis.lower_values(k, |_| false);
        let mut shift = vec![0.0; nw];
        for (sigma, &d) in shift.iter_mut().zip(w) {
            let c = analysis.local[d];
            let diagonal = (analysis.col_ptr[c]..analysis.col_ptr[c + 1]).find(|&p| analysis.row_idx[p] == c);
            match diagonal {
                Some(p) if vals[p] > 0.0 => {
                    *sigma = vals[p];
                    vals[p] *= 2.0;
                }
                _ => return Err(SolveError::Singular),
            }
        }
        let factor = analysis.factor_values(&vals)?;
        // L_WW: the factor's entries in rows and columns m.. (W in order).
        let mut l = Mat::<f64>::zeros(nw, nw);
        match analysis.sym.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                let llt = SupernodalLltRef::new(s, &factor.l_values);
                for sn in 0..s.n_supernodes() {
                    let (begin, end) = (s.supernode_begin()[sn], s.supernode_end()[sn]);
                    if end <= m {
                        continue;
                    }
                    let node = llt.supernode(sn);
                    let rows: Vec<usize> = (begin..end).chain(node.pattern().iter().copied()).collect();
                    for c in begin.max(m)..end {
                        for (ri, &r) in rows.iter().enumerate().skip(c - begin) {
                            l[(r - m, c - m)] = node.val()[(ri, c - begin)];
                        }
                    }
                }
            }
            SymbolicCholeskyRaw::Simplicial(s) => {
                let lf = s.factor();
                for c in m..m + nw {
                    for p in lf.col_ptr()[c]..lf.col_ptr()[c + 1] {
                        l[(lf.row_idx()[p] - m, c - m)] = factor.l_values[p];
                    }
                }
            }
        }
        let mut schur = Mat::<f64>::zeros(nw, nw);
        matmul(schur.as_mut(), Accum::Replace, l.as_ref(), l.transpose(), 1.0, parallelism());
        for (j, sigma) in shift.iter().enumerate() {
            schur[(j, j)] -= sigma;
        }
        // Exactly symmetric (the product's two halves may round apart).
        for i in 0..nw {
            for j in 0..i {
                schur[(j, i)] = schur[(i, j)];
            }
        }
        Ok(schur)
    }

    /// The unknowns F (ascending): reduced number r is dof `free()[r]`.
    pub fn free(&self) -> &[usize] {
        &self.free
    }

    /// The reduced number of each dof (`usize::MAX` for the dofs of D).
    pub fn local(&self) -> &[usize] {
        &self.local
    }

    /// Factors K_FF (D as analysed).
    ///
    /// # Errors
    /// [`SolveError::PatternChanged`] for another pattern of K;
    /// [`SolveError::Singular`]; [`SolveError::OutOfMemory`].
    pub fn factor(&self, k: &CsrMatrix) -> Result<CholeskyFactor<'_>, SolveError> {
        if k.nrows != self.n || k.nnz() != self.nnz {
            return Err(SolveError::PatternChanged);
        }
        self.factor_values(&self.lower_values(k, |_| false))
    }

    /// Solves K u = f with the prescribed dofs of `dirichlet` (E ⊇ D), K with
    /// the analysed pattern; the report includes the analysis phases.
    ///
    /// # Errors
    /// [`SolveError::PatternChanged`] when K does not have the analysed pattern,
    /// or a dof of D is not prescribed; otherwise as [`solve`].
    pub fn solve(
        &self,
        k: &CsrMatrix,
        f: &[f64],
        dirichlet: &Dirichlet,
    ) -> Result<(Vec<f64>, DirectReport), SolveError> {
        let red = Reduced::new(k, f, dirichlet)?;
        if k.nrows != self.n || k.nnz() != self.nnz || (0..self.n).any(|i| self.fixed[i] && !red.fixed[i]) {
            return Err(SolveError::PatternChanged);
        }
        let mut report = self.report.clone();
        let m = self.free.len();
        if m == 0 {
            return Ok((red.u, report));
        }
        // Extra prescribed dofs (E \ D) get identity rows and columns.
        let factor = self.factor_values(&self.lower_values(k, |i| red.fixed[i]))?;
        report.numeric_seconds = factor.numeric_seconds;
        let b = red.rhs(k, f);
        let mut rhs = Mat::<f64>::from_fn(m, 1, |r, _| {
            let i = self.free[r];
            if red.fixed[i] {
                red.u[i]
            } else {
                b[red.local[i]]
            }
        });
        let clock = Instant::now();
        factor.solve_in_place(rhs.as_mut());
        report.solve_seconds = clock.elapsed().as_secs_f64();
        let mut u = red.u;
        for (r, &i) in self.free.iter().enumerate() {
            u[i] = rhs[(r, 0)];
        }
        if u.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::Singular);
        }
        Ok((u, report))
    }

    /// The lower triangle of K_FF on the analysed pattern, with identity rows
    /// and columns for the dofs where `extra` holds.
    fn lower_values(&self, k: &CsrMatrix, extra: impl Fn(usize) -> bool) -> Vec<f64> {
        let mut vals = Vec::with_capacity(self.row_idx.len());
        for (r, &i) in self.free.iter().enumerate() {
            let (cols, values) = k.row(i);
            for (&j, &v) in cols.iter().zip(values) {
                if self.local[j] != usize::MAX && self.local[j] >= r {
                    vals.push(match (extra(i), extra(j)) {
                        (false, false) => v,
                        _ if i == j => 1.0,
                        _ => 0.0,
                    });
                }
            }
        }
        debug_assert_eq!(vals.len(), self.row_idx.len());
        vals
    }

    /// The numeric factorisation of the matrix with lower triangle `vals`,
    /// checked by the probe solve (module doc).
    fn factor_values(&self, vals: &[f64]) -> Result<CholeskyFactor<'_>, SolveError> {
        let m = self.free.len();
        let symbolic = SymbolicSparseColMatRef::new_checked(m, m, &self.col_ptr, None, &self.row_idx);
        let kff = SparseColMatRef::new(symbolic, vals);
        let clock = Instant::now();
        let par = parallelism();
        let sym = &self.sym;
        let mut l_values = Vec::new();
        l_values.try_reserve_exact(sym.len_val()).map_err(|_| SolveError::OutOfMemory)?;
        l_values.resize(sym.len_val(), 0.0f64);
        let scratch = sym.factorize_numeric_llt_scratch::<f64>(par, Default::default());
        let mut mem = MemBuffer::try_new(scratch).map_err(|_| SolveError::OutOfMemory)?;
        sym.factorize_numeric_llt(
            &mut l_values,
            kff,
            Side::Lower,
            Default::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(|_| SolveError::Singular)?;
        let factor =
            CholeskyFactor { analysis: self, l_values, numeric_seconds: clock.elapsed().as_secs_f64() };
        // The probe: solve A x = A z and compare with z.
        let z: Vec<f64> = (0..m).map(probe).collect();
        let mut az = Mat::<f64>::zeros(m, 1);
        for c in 0..m {
            for p in self.col_ptr[c]..self.col_ptr[c + 1] {
                let (r, v) = (self.row_idx[p], vals[p]);
                az[(r, 0)] += v * z[c];
                if r != c {
                    az[(c, 0)] += v * z[r];
                }
            }
        }
        factor.solve_in_place(az.as_mut());
        let (mut err, mut size) = (0.0f64, 0.0f64);
        for r in 0..m {
            err = err.max((az[(r, 0)] - z[r]).abs());
            size = size.max(z[r].abs());
        }
        // NaN (a failed factorisation) counts as singular too.
        if err.is_nan() || err > SINGULAR_PROBE_RTOL * size {
            return Err(SolveError::Singular);
        }
        Ok(factor)
    }
}

/// The numeric Cholesky factor of K_FF from a [`CholeskyAnalysis`].
pub struct CholeskyFactor<'a> {
    analysis: &'a CholeskyAnalysis,
    l_values: Vec<f64>,
    /// Seconds of the numeric factorisation.
    pub numeric_seconds: f64,
}

impl<'a> CholeskyFactor<'a> {
    /// The analysis it was factored with.
    pub fn analysis(&self) -> &'a CholeskyAnalysis {
        self.analysis
    }

    /// The factor's values, for [`CholeskyFactor::again`] (a factor kept
    /// without the borrow of its analysis).
    pub fn into_values(self) -> Vec<f64> {
        self.l_values
    }

    /// The factor of `analysis` with `l_values` from
    /// [`CholeskyFactor::into_values`] of a factor of it.
    ///
    /// # Panics
    /// If `l_values` does not have the analysed length.
    pub fn again(analysis: &'a CholeskyAnalysis, l_values: Vec<f64>) -> Self {
        assert_eq!(l_values.len(), analysis.sym.len_val(), "values of a factor of this analysis");
        CholeskyFactor { analysis, l_values, numeric_seconds: 0.0 }
    }

    /// X ← K_FF⁻¹ X for the columns of `rhs`, rows in reduced numbering
    /// ([`CholeskyAnalysis::free`]).
    ///
    /// # Panics
    /// If `rhs` does not have one row per unknown.
    pub fn solve_in_place(&self, rhs: faer::MatMut<'_, f64>) {
        let sym = &self.analysis.sym;
        assert_eq!(rhs.nrows(), self.analysis.free.len(), "one row per unknown");
        let par = parallelism();
        let llt = LltRef::new(sym, &self.l_values);
        let scratch = sym.solve_in_place_scratch::<f64>(rhs.ncols(), par);
        let mut mem = MemBuffer::new(scratch);
        llt.solve_in_place_with_conj(Conj::No, rhs, par, MemStack::new(&mut mem));
    }
}

/// faer's parallelism: a fixed number of tasks on the current rayon pool, so
/// that the factorisation's arithmetic, and hence its bits, do not depend on
/// the number of threads.
pub(crate) fn parallelism() -> Par {
    Par::rayon(FACTOR_TASKS)
}

/// Tasks of faer's parallel factorisations and solves (module doc).
const FACTOR_TASKS: usize = 8;

/// Σ_j c_j² over the column counts of L, and the widest supernode.
fn factor_flops(sym: &SymbolicCholesky<usize>) -> (f64, usize) {
    match sym.raw() {
        SymbolicCholeskyRaw::Supernodal(s) => {
            let mut flops = 0.0;
            let mut widest = 0;
            for k in 0..s.n_supernodes() {
                let cols = s.supernode_end()[k] - s.supernode_begin()[k];
                let below = s.supernode(k).pattern().len();
                widest = widest.max(cols);
                for j in 0..cols {
                    flops += ((cols - j + below) as f64).powi(2);
                }
            }
            (flops, widest)
        }
        SymbolicCholeskyRaw::Simplicial(s) => {
            (s.col_ptr().windows(2).map(|w| ((w[1] - w[0]) as f64).powi(2)).sum(), 1)
        }
    }
}

/// A fixed pseudo-random entry in \[1, 2) (SplitMix64 of the index).
fn probe(r: usize) -> f64 {
    let mut x = (r as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^= x >> 31;
    1.0 + (x >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 1D Laplacian chain of `n` nodes, springs of stiffness 1.
    fn chain(n: usize) -> CsrMatrix {
        let rows: Vec<(Vec<usize>, Vec<f64>)> = (0..n)
            .map(|i| {
                let mut c = Vec::new();
                let mut v = Vec::new();
                if i > 0 {
                    c.push(i - 1);
                    v.push(-1.0);
                }
                c.push(i);
                v.push(if i == 0 || i == n - 1 { 1.0 } else { 2.0 });
                if i + 1 < n {
                    c.push(i + 1);
                    v.push(-1.0);
                }
                (c, v)
            })
            .collect();
        CsrMatrix::from_rows(n, rows.iter().map(|(c, v)| (c.as_slice(), v.as_slice())))
    }

    #[test]
    fn chain_with_both_ends_prescribed_is_linear() {
        let k = chain(6);
        let mut d = Dirichlet::new();
        d.fix_dof(0, 1.0).fix_dof(5, 6.0);
        let u = solve(&k, &[0.0; 6], &d).unwrap();
        for (i, v) in u.iter().enumerate() {
            assert!((v - (1.0 + i as f64)).abs() < 1e-13, "{u:?}");
        }
    }

    #[test]
    fn floating_chain_is_singular() {
        let k = chain(6);
        assert_eq!(solve(&k, &[0.0; 6], &Dirichlet::new()), Err(SolveError::Singular));
        let mut d = Dirichlet::new();
        d.fix_dof(6, 0.0);
        assert_eq!(solve(&k, &[0.0; 6], &d), Err(SolveError::DofOutOfRange { dof: 6, n_dofs: 6 }));
        assert!(matches!(solve(&k, &[0.0; 5], &d), Err(SolveError::Dimension { .. })));
    }

    /// S = K_WW − K_WO K_OO⁻¹ K_OW by the partial factorisation against the
    /// dense formula: a clamped block with W on its loaded side, and a free
    /// block held by W alone (S semidefinite: its rigid motions live in W).
    #[test]
    fn schur_complement_is_the_dense_one() {
        use crate::generate::{block, BlockKind, Grid, Side};
        use faer::linalg::solvers::Solve;
        let n = 3;
        let mesh = block(n, n + 1, n, |u, v, w| [u, v + 0.1 * u * u, w], BlockKind::Hex);
        let grid = Grid::new(n, n + 1, n);
        let k = crate::stiffness(&mesh, &crate::Material::new(1000.0, 0.3).unwrap()).unwrap();
        let dofs = |side| -> Vec<usize> {
            let mut d: Vec<usize> =
                grid.side_points(side).into_iter().flat_map(|p| 3 * p..3 * p + 3).collect();
            d.reverse();
            d
        };
        let mut clamped = Dirichlet::new();
        clamped.clamp(grid.side_points(Side::XMin));
        for (held, w) in [(clamped, dofs(Side::XMax)), (Dirichlet::new(), dofs(Side::XMin))] {
            let mut tied = held.clone();
            for &d in &w {
                tied.fix_dof(d, 0.0);
            }
            let analysis = CholeskyAnalysis::new(&k, &tied, &DirectOptions::default()).unwrap();
            let s = analysis.schur_complement(&k, &w).unwrap();
            // Dense: the free dofs O, then S = K_WW − K_WO K_OO⁻¹ K_OW.
            let o = analysis.free();
            let entry = |i: usize, j: usize| {
                let (c, v) = k.row(i);
                c.iter().position(|&q| q == j).map_or(0.0, |p| v[p])
            };
            let k_oo = Mat::<f64>::from_fn(o.len(), o.len(), |a, b| entry(o[a], o[b]));
            let k_ow = Mat::<f64>::from_fn(o.len(), w.len(), |a, b| entry(o[a], w[b]));
            let z = k_oo.llt(faer::Side::Lower).unwrap().solve(&k_ow);
            let dense =
                Mat::<f64>::from_fn(w.len(), w.len(), |a, b| entry(w[a], w[b])) - k_ow.transpose() * &z;
            let scale = (0..w.len()).map(|j| dense[(j, j)]).fold(0.0f64, f64::max);
            let miss = (0..w.len())
                .flat_map(|i| (0..w.len()).map(move |j| (i, j)))
                .map(|(i, j)| (s[(i, j)] - dense[(i, j)]).abs())
                .fold(0.0f64, f64::max);
            assert!(miss <= 1e-12 * scale, "S off by {miss:e} of {scale:e}");
        }
        // W must be held by the analysis.
        let analysis = CholeskyAnalysis::new(&k, &Dirichlet::new(), &DirectOptions::default()).unwrap();
        assert!(matches!(analysis.schur_complement(&k, &[0]), Err(SolveError::PatternChanged)));
    }

    /// A clamped Hex8 block with a load, and a few single prescribed components.
    fn block_problem(n: usize) -> (CsrMatrix, Vec<f64>, Dirichlet) {
        use crate::generate::{block, BlockKind, Grid, Side};
        let mesh = block(n, n + 1, n, |u, v, w| [u, v + 0.1 * u * u, w], BlockKind::Hex);
        let grid = Grid::new(n, n + 1, n);
        let k = crate::stiffness(&mesh, &crate::Material::new(1000.0, 0.3).unwrap()).unwrap();
        let f = crate::traction(&grid.side_faces(&mesh, Side::XMax).unwrap(), |_, _| [1.0, 0.5, -0.2]);
        let mut bc = Dirichlet::new();
        bc.clamp(grid.side_points(Side::XMin));
        bc.fix(grid.point(n, 0, 0), [None, Some(0.01), None]);
        bc.fix(grid.point(n, n + 1, n), [Some(-0.02), None, Some(0.0)]);
        (k, f, bc)
    }

    #[test]
    fn one_analysis_serves_more_prescribed_dofs_and_new_values() {
        let (mut k, f, bc) = block_problem(5);
        let analysis = CholeskyAnalysis::new(&k, &bc, &DirectOptions::default()).unwrap();
        let mut more = bc.clone();
        more.fix(40, [Some(0.003), None, Some(-0.001)]).fix(77, [None, Some(0.002), None]);
        for v in k.values.iter_mut() {
            *v *= 1.5;
        }
        let (u, _) = analysis.solve(&k, &f, &more).unwrap();
        let reference = solve(&k, &f, &more).unwrap();
        let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = u.iter().zip(&reference).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(err <= 1e-12 * scale, "{err:e} vs {scale:e}");
        // A dof of the analysed set must stay prescribed.
        let fewer = Dirichlet::new();
        assert_eq!(analysis.solve(&k, &f, &fewer).unwrap_err(), SolveError::PatternChanged);
    }

    #[test]
    fn orderings_give_the_same_solution() {
        let (k, f, bc) = block_problem(7);
        let solve_with = |ordering| solve_direct(&k, &f, &bc, &DirectOptions { ordering }).unwrap();
        let (reference, r0) = solve_with(FillOrdering::DofAmd);
        assert!(!r0.point_blocks);
        let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for ordering in [FillOrdering::PointAmd, FillOrdering::NestedDissection] {
            let (u, report) = solve_with(ordering);
            assert!(report.point_blocks && report.supernodal, "{report:?}");
            assert!(report.nnz_l > 0 && report.flops > 0.0, "{report:?}");
            let err = u.iter().zip(&reference).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(err <= 1e-12 * scale, "{ordering:?}: {err:e} vs {scale:e}");
        }
        // The default is nested dissection, and the prescribed values are kept.
        let u = solve(&k, &f, &bc).unwrap();
        for (dof, v) in bc.iter() {
            assert_eq!(u[dof], v);
        }
    }

    #[test]
    fn point_blocks_are_detected() {
        let (k, _, _) = block_problem(2);
        assert!(has_point_blocks(&k));
        assert!(!has_point_blocks(&chain(6)));
        // A pattern with a lone entry in one row of a point is not blocked, and
        // still solves (dof-level ordering).
        let base = chain(6);
        let mut rows: Vec<(Vec<usize>, Vec<f64>)> = (0..6)
            .map(|i| {
                let (c, v) = base.row(i);
                (c.to_vec(), v.to_vec())
            })
            .collect();
        rows[0].1[0] += 1.0;
        let k = CsrMatrix::from_rows(6, rows.iter().map(|(c, v)| (c.as_slice(), v.as_slice())));
        assert!(!has_point_blocks(&k));
        let (u, report) = solve_direct(&k, &[1.0; 6], &Dirichlet::new(), &DirectOptions::default()).unwrap();
        assert!(!report.point_blocks);
        let ku = k.mul_vec(&u, 1);
        assert!(ku.iter().all(|v| (v - 1.0).abs() < 1e-12), "{ku:?}");
    }

    #[test]
    fn dirichlet_builder() {
        let mut d = Dirichlet::new();
        d.fix(2, [Some(1.0), None, Some(3.0)]).clamp([0]);
        d.fix(2, [Some(5.0), None, None]);
        let all: Vec<_> = d.iter().collect();
        assert_eq!(all, vec![(0, 0.0), (1, 0.0), (2, 0.0), (6, 5.0), (8, 3.0)]);
        assert_eq!(d.value(7), None);
        assert_eq!(d.len(), 5);
    }
}
