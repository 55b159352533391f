//! The glued constraints C u = g on the multi-body system and the solvers of
//! the constrained system, shared by gluing ([`crate::glue`]) and contact
//! ([`crate::contact`]).
//!
//! - [`Constraints::new`]: one row (D̃ u_s − B̃ u_m)_{q,c} per slave dof that
//!   is neither prescribed nor claimed by an earlier interface, in Wohlmuth's
//!   modified multiplier basis (the multipliers of prescribed and crosspoint
//!   dofs moved to their neighbours), so C has full row rank and constant
//!   tractions stay in the multiplier space.
//! - Elimination: each row eliminates its own slave dof, C = [C_S C_R],
//!   u = P u_R with P = [I; −C_S⁻¹C_R] ([`prolongation`] when C_S is
//!   diagonal, [`triple_product`] for PᵀKP, row by row).
//! - [`saddle_point`]: [K Cᵀ; C 0] by sparse LDLᵀ with iterative refinement.
//! - [`matrix_free`]: PCG on PᵀKP for any C_S, one sparse LU of C_S.

use crate::assembly::split_mut;
use crate::multibody::{Body, Coupling, Interface, ProblemError, Timings};
use crate::pcg::{par_mul, pcg, BlockJacobi, PcgOptions};
use crate::saddle::solve_saddle;
use crate::solve::{Dirichlet, SolveError};
use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Mat, Par};
use rayon::prelude::*;
use seam::{CsrMatrix, Mortar, SurfaceMesh};
use std::time::Instant;

/// One row of C: the slave dof it constrains (and eliminates).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Row {
    pub(crate) dof: usize,
    pub(crate) interface: usize,
    pub(crate) point: usize,
    pub(crate) component: usize,
}

/// The constraint matrix C of all interfaces (module doc).
#[derive(Clone)]
pub(crate) struct Constraints {
    /// rows × dofs.
    pub(crate) c: CsrMatrix,
    pub(crate) rows: Vec<Row>,
    /// Per row: the mortar rows it combines, (slave point, weight); its own
    /// point first with weight 1 (see [`Constraints::new`]).
    pub(crate) parts: Vec<Vec<(usize, f64)>>,
    /// Per dof: the row that eliminates it, or `NONE`.
    pub(crate) row_of: Vec<usize>,
    /// The right-hand side of each row (C u = g): zero for glue, the gap for
    /// an active contact row ([`crate::contact`]).
    pub(crate) g: Vec<f64>,
}

pub(crate) const NONE: usize = usize::MAX;

/// [`Row::interface`] of a body's tie ([`crate::enrichment::Tie`]).
pub(crate) const TIE: usize = usize::MAX;

impl Constraints {
    /// Rows (D̃ u_s − B̃ u_m)_{q,c} for covered slave points q, in interface,
    /// point, component order, one per slave dof that is neither prescribed nor
    /// constrained by an earlier interface (a crosspoint or crossline).
    ///
    /// The multipliers of those other covered dofs ("removed") are not dropped:
    /// as in Wohlmuth's modified basis at Dirichlet and crosspoint nodes, the
    /// basis function ψ_p of a removed point p is added to the kept points Q_p
    /// nearest to it on the slave surface (through removed points), ψ̃_q = ψ_q +
    /// Σ_p ψ_p / |Q_p|, so row q of C is row q of [D −B] plus 1/|Q_p| times
    /// row p. The modified basis still sums to one, so a constant traction
    /// is in the multiplier space and patch tests stay exact with supports or
    /// other interfaces touching the slave side. A removed point with no kept
    /// point connected to it (the whole interface prescribed in that
    /// component) keeps no multiplier.
    pub(crate) fn new(
        (interfaces, bodies): (&[Interface], &[Body]),
        mortars: &[Mortar],
        offsets: &[usize],
        dirichlet: &Dirichlet,
    ) -> Self {
        let n = *offsets.last().unwrap();
        let mut row_of = vec![NONE; n];
        let mut rows = Vec::new();
        let mut parts = Vec::new();
        let mut entries: Vec<(usize, f64)> = Vec::new();
        let mut c = CsrMatrix::zeros(0, n);
        let glued = interfaces.iter().zip(mortars).enumerate().filter(|(_, (f, _))| f.kind == Coupling::Glue);
        for (i, (f, m)) in glued {
            let (os, om) = (offsets[f.slave], offsets[f.master]);
            // ∫ψ_p λ_r for nodal slave dofs (D itself unless dual multipliers
            // on second-order faces work in a transformed basis).
            let d = m.nodal_d();
            let covered: Vec<usize> = (0..m.covered.len()).filter(|&p| m.covered[p]).collect();
            let removed: [Vec<bool>; 3] = std::array::from_fn(|comp| {
                let mut removed = vec![false; m.covered.len()];
                for &p in &covered {
                    let dof = os + 3 * p + comp;
                    removed[p] = row_of[dof] != NONE || dirichlet.value(dof).is_some();
                }
                removed
            });
            let shares = removed.each_ref().map(|r| shares_of_removed(f.slave_surface, &covered, r));
            for &p in &covered {
                for comp in (0..3).filter(|&comp| !removed[comp][p]) {
                    let dof = os + 3 * p + comp;
                    row_of[dof] = rows.len();
                    rows.push(Row { dof, interface: i, point: p, component: comp });
                    let part: Vec<(usize, f64)> =
                        std::iter::once((p, 1.0)).chain(shares[comp][p].iter().copied()).collect();
                    entries.clear();
                    for &(q, w) in &part {
                        let (dq, dv) = d.row(q);
                        entries.extend(dq.iter().zip(dv).map(|(&k, &v)| (os + 3 * k + comp, w * v)));
                        let (bq, bv) = m.b.row(q);
                        entries.extend(bq.iter().zip(bv).map(|(&k, &v)| (om + 3 * k + comp, -w * v)));
                    }
                    entries.sort_unstable_by_key(|e| e.0);
                    for (k, &(j, v)) in entries.iter().enumerate() {
                        if k > 0 && entries[k - 1].0 == j {
                            *c.values.last_mut().expect("a previous entry") += v;
                        } else {
                            c.indices.push(j);
                            c.values.push(v);
                        }
                    }
                    c.indptr.push(c.indices.len());
                    c.nrows += 1;
                    parts.push(part);
                }
            }
        }
        // The bodies' ties, u_t − Σ w_q u_q = 0, eliminating u_t.
        for (b, body) in bodies.iter().enumerate() {
            for tie in &body.ties {
                for comp in 0..3 {
                    let dof = offsets[b] + 3 * tie.point + comp;
                    row_of[dof] = rows.len();
                    rows.push(Row { dof, interface: TIE, point: tie.point, component: comp });
                    entries.clear();
                    entries.push((dof, 1.0));
                    entries.extend(tie.to.iter().map(|&(q, w)| (offsets[b] + 3 * q + comp, -w)));
                    entries.sort_unstable_by_key(|e| e.0);
                    c.indices.extend(entries.iter().map(|e| e.0));
                    c.values.extend(entries.iter().map(|e| e.1));
                    c.indptr.push(c.indices.len());
                    c.nrows += 1;
                    parts.push(Vec::new());
                }
            }
        }
        let g = vec![0.0; rows.len()];
        Constraints { c, rows, parts, row_of, g }
    }

    /// True when eliminating u_S = T u_R would fill PᵀKP in:
    /// Σ_rows nnz(T row)² (the entries of TᵀK_SST from the diagonal of K_SS)
    /// exceeds nnz(K)/16. This happens when the slave side is coarser than the
    /// master side (a slave node then couples (2 h_s/h_m + 1)² master nodes);
    /// the saddle point is then the cheaper factorisation. Measured on the
    /// warped-glue problem (`examples/glue_bench.rs`), 110k dofs,
    /// h_s/h_m = 4 (fill ≈ nnz(K)/4): reduced Cholesky 50 s, LDLᵀ 10 s;
    /// 116k dofs, h_s/h_m = 8: 82 s against 3 s.
    pub(crate) fn elimination_fills_in(&self, k: &CsrMatrix) -> bool {
        let fill: usize = (0..self.rows.len()).map(|r| (self.c.row(r).0.len() - 1).pow(2)).sum();
        16 * fill > k.nnz()
    }

    /// True when each row touches no eliminated dof but its own: C_S is diagonal.
    pub(crate) fn eliminated_block_is_diagonal(&self) -> bool {
        self.rows.iter().enumerate().all(|(r, row)| {
            let (cols, _) = self.c.row(r);
            cols.iter().all(|&j| j == row.dof || self.row_of[j] == NONE)
        })
    }
}

/// Per slave point q: the removed points p whose multiplier goes to q, with
/// the weight 1/|Q_p| (see [`Constraints::new`]). Q_p are the kept covered
/// points at the smallest distance from p in the face graph of `surface`,
/// walking through removed covered points only.
pub(crate) fn shares_of_removed(
    surface: &SurfaceMesh,
    covered: &[usize],
    removed: &[bool],
) -> Vec<Vec<(usize, f64)>> {
    let n = removed.len();
    let mut shares = vec![Vec::new(); n];
    if !covered.iter().any(|&p| removed[p]) {
        return shares;
    }
    let is_covered = {
        let mut c = vec![false; n];
        covered.iter().for_each(|&p| c[p] = true);
        c
    };
    // Faces of each point (CSR).
    let faces = surface.faces();
    let mut start = vec![0usize; n + 1];
    for face in faces {
        face.nodes().iter().for_each(|&p| start[p + 1] += 1);
    }
    for p in 0..n {
        start[p + 1] += start[p];
    }
    let mut fill = start.clone();
    let mut face_of = vec![0usize; start[n]];
    for (k, face) in faces.iter().enumerate() {
        for &p in face.nodes() {
            face_of[fill[p]] = k;
            fill[p] += 1;
        }
    }
    let mut seen = vec![usize::MAX; n];
    let (mut layer, mut next, mut found) = (Vec::new(), Vec::new(), Vec::new());
    for &p in covered.iter().filter(|&&p| removed[p]) {
        layer.clear();
        layer.push(p);
        seen[p] = p;
        found.clear();
        while found.is_empty() && !layer.is_empty() {
            next.clear();
            for &a in &layer {
                for &k in &face_of[start[a]..start[a + 1]] {
                    for &b in faces[k].nodes() {
                        if seen[b] == p || !is_covered[b] {
                            continue;
                        }
                        seen[b] = p;
                        if removed[b] {
                            next.push(b);
                        } else {
                            found.push(b);
                        }
                    }
                }
            }
            std::mem::swap(&mut layer, &mut next);
        }
        let w = 1.0 / found.len() as f64;
        for &q in &found {
            shares[q].push((p, w));
        }
    }
    shares
}

/// (u, λ, method, iterations) of a solver.
pub(crate) type Solved = (Vec<f64>, Vec<f64>, &'static str, usize);

/// The index in R of each retained dof (`NONE` for eliminated ones), and n_R.
pub(crate) fn retained_numbering(constraints: &Constraints) -> (Vec<usize>, usize) {
    let mut retained = vec![NONE; constraints.row_of.len()];
    let mut n_r = 0;
    for (r, &row) in retained.iter_mut().zip(&constraints.row_of) {
        if row == NONE {
            *r = n_r;
            n_r += 1;
        }
    }
    (retained, n_r)
}

/// P = [I; −C_S⁻¹C_R] (n × n_R) for diagonal C_S, and the index in R of each
/// retained dof (`NONE` for eliminated ones).
pub(crate) fn prolongation(constraints: &Constraints) -> (CsrMatrix, Vec<usize>) {
    let n = constraints.row_of.len();
    let (retained, n_r) = retained_numbering(constraints);
    let mut p = CsrMatrix::zeros(0, n_r);
    for dof in 0..n {
        match constraints.row_of[dof] {
            NONE => {
                p.indices.push(retained[dof]);
                p.values.push(1.0);
            }
            r => {
                let (cols, vals) = constraints.c.row(r);
                let pivot = constraints.c.get(r, dof);
                for (&j, &v) in cols.iter().zip(vals) {
                    if j != dof {
                        p.indices.push(retained[j]);
                        p.values.push(-v / pivot);
                    }
                }
            }
        }
        p.indptr.push(p.indices.len());
        p.nrows += 1;
    }
    (p, retained)
}

/// A CSR matrix read as the CSC matrix of its transpose (no copy).
pub(crate) fn transposed_view(a: &CsrMatrix) -> SparseColMatRef<'_, usize, f64> {
    let symbolic = SymbolicSparseColMatRef::new_checked(a.ncols, a.nrows, &a.indptr, None, &a.indices);
    SparseColMatRef::new(symbolic, &a.values)
}

/// The CSR matrix whose transpose is the CSC matrix `x` (no copy).
pub(crate) fn from_transposed(x: SparseColMat<usize, f64>) -> CsrMatrix {
    let (symbolic, values) = x.into_parts();
    let (nrows, ncols, indptr, _, indices) = symbolic.into_parts();
    CsrMatrix { nrows: ncols, ncols: nrows, indptr, indices, values }
}

/// CᵀC, by a sparse product (faer, sorted output).
///
/// # Errors
/// [`SolveError::ProductOutOfMemory`] when the product cannot be allocated.
pub(crate) fn gram(c: &CsrMatrix) -> Result<CsrMatrix, SolveError> {
    // As CSC: view(C) = Cᵀ and view(Cᵀ) = C, so their product is CᵀC, whose
    // CSR is its (symmetric) transpose's CSC.
    let ct = c.transpose();
    let a = faer::sparse::linalg::matmul::sparse_sparse_matmul(
        transposed_view(c),
        transposed_view(&ct),
        1.0,
        Par::rayon(0),
    )
    .map_err(|_| SolveError::ProductOutOfMemory { rows: c.nrows, entries: c.nnz() })?;
    Ok(from_transposed(a))
}

/// PᵀKP row by row (Gustavson): row i is Σ_k P_ki Σ_l K_kl P_l·, summed in a
/// dense accumulator, its columns then sorted. No intermediate KP is formed,
/// so the product needs K, P and the result only. Each row is summed by one
/// thread in a fixed order, so the result does not depend on the threads.
pub(crate) fn triple_product(p: &CsrMatrix, k: &CsrMatrix) -> CsrMatrix {
    let (pt, n) = (p.transpose(), p.ncols);
    // Row blocks, a few per thread, each with its own accumulator of n entries.
    let blocks = 4 * rayon::current_num_threads();
    let ranges: Vec<_> = (0..blocks).map(|b| b * n / blocks..(b + 1) * n / blocks).collect();
    // Row i's columns, each once, in `cols` (`seen[j]` = i marks j).
    let pattern = |i: usize, seen: &mut [usize], cols: &mut Vec<usize>| {
        cols.clear();
        for &r in pt.row(i).0 {
            for &l in k.row(r).0 {
                for &j in p.row(l).0 {
                    if seen[j] != i {
                        seen[j] = i;
                        cols.push(j);
                    }
                }
            }
        }
    };
    let counts: Vec<Vec<usize>> = ranges
        .par_iter()
        .map(|rows| {
            let (mut seen, mut cols) = (vec![usize::MAX; n], Vec::new());
            rows.clone()
                .map(|i| {
                    pattern(i, &mut seen, &mut cols);
                    cols.len()
                })
                .collect()
        })
        .collect();
    let mut indptr = Vec::with_capacity(n + 1);
    indptr.push(0);
    for c in counts.iter().flatten() {
        indptr.push(indptr.last().copied().unwrap_or(0) + c);
    }
    drop(counts);
    let nnz = indptr[n];
    let (mut indices, mut values) = (vec![0; nnz], vec![0.0; nnz]);
    // Each block's slice of the result.
    let at: Vec<usize> = ranges.iter().map(|r| indptr[r.start]).chain([nnz]).collect();
    let parts: Vec<_> =
        ranges.into_iter().zip(split_mut(&mut indices, &at)).zip(split_mut(&mut values, &at)).collect();
    parts.into_par_iter().for_each(|((rows, out_i), out_v)| {
        let (mut seen, mut cols, mut sum) = (vec![usize::MAX; n], Vec::new(), vec![0.0; n]);
        let base = indptr[rows.start];
        for i in rows {
            pattern(i, &mut seen, &mut cols);
            cols.sort_unstable();
            let (pc, pv) = pt.row(i);
            for (&r, &pri) in pc.iter().zip(pv) {
                let (kc, kv) = k.row(r);
                for (&l, &krl) in kc.iter().zip(kv) {
                    let (jc, jv) = p.row(l);
                    let a = pri * krl;
                    for (&j, &plj) in jc.iter().zip(jv) {
                        sum[j] += a * plj;
                    }
                }
            }
            let at = indptr[i] - base;
            for (q, &j) in cols.iter().enumerate() {
                out_i[at + q] = j;
                out_v[at + q] = std::mem::take(&mut sum[j]);
            }
        }
    });
    CsrMatrix { nrows: n, ncols: n, indptr, indices, values }
}

/// The saddle point over the free dofs F (standard multipliers, or dual and
/// lumped ones whose elimination fills in),
/// [K_FF C_Fᵀ; C_F 0] [u_F; λ] = [f_F − K_FD ū; g − C_D ū], by sparse LDLᵀ
/// with each multiplier ordered after its slave point ([`solve_saddle`]).
pub(crate) fn saddle_point(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    constraints: &Constraints,
    seconds: &mut Timings,
) -> Result<Solved, ProblemError> {
    let clock = Instant::now();
    let n = k.nrows;
    let mut u = vec![0.0; n];
    let mut local = vec![NONE; n];
    let mut free = Vec::new();
    for (dof, v) in dirichlet.iter() {
        u[dof] = v;
    }
    for (i, _) in free_dofs(k, dirichlet).iter().enumerate().filter(|(_, &is_free)| is_free) {
        local[i] = free.len();
        free.push(i);
    }
    let (m, nc) = (free.len(), constraints.rows.len());
    let ct = constraints.c.transpose();
    let mut a = CsrMatrix::zeros(0, m + nc);
    let mut rhs = vec![0.0; m + nc];
    let push = |a: &mut CsrMatrix, cols: &[usize], vals: &[f64], b: &mut f64| {
        for (&j, &v) in cols.iter().zip(vals) {
            if local[j] != NONE {
                a.indices.push(local[j]);
                a.values.push(v);
            } else {
                *b -= v * u[j];
            }
        }
    };
    for (r, &i) in free.iter().enumerate() {
        let mut b = f[i];
        let (cols, vals) = k.row(i);
        push(&mut a, cols, vals, &mut b);
        let (rows, vals) = ct.row(i);
        a.indices.extend(rows.iter().map(|&l| m + l));
        a.values.extend_from_slice(vals);
        a.indptr.push(a.indices.len());
        a.nrows += 1;
        rhs[r] = b;
    }
    for r in 0..nc {
        let (cols, vals) = constraints.c.row(r);
        let mut b = constraints.g[r];
        push(&mut a, cols, vals, &mut b);
        a.indptr.push(a.indices.len());
        a.nrows += 1;
        rhs[m + r] = b;
    }
    // Ordering groups: the points, each multiplier with the slave point it constrains.
    let mut group_of_point = vec![NONE; n / 3 + 1];
    let mut n_groups = 0;
    let mut group = |dof: usize| {
        let g = &mut group_of_point[dof / 3];
        if *g == NONE {
            *g = n_groups;
            n_groups += 1;
        }
        *g
    };
    let dofs: Vec<usize> = free.iter().copied().chain(constraints.rows.iter().map(|row| row.dof)).collect();
    let groups: Vec<usize> = dofs.into_iter().map(&mut group).collect();
    let signs: Vec<i8> = (0..m + nc).map(|i| if i < m { 1 } else { -1 }).collect();
    seconds.setup += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let (x, report) = solve_saddle(&a, &rhs, &signs, &groups)?;
    seconds.factorization += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    for (r, &i) in free.iter().enumerate() {
        u[i] = x[r];
    }
    let lambda = x[m..].to_vec();
    seconds.solve += clock.elapsed().as_secs_f64();
    Ok((u, lambda, "saddle-point LDLᵀ", report.refinements))
}

/// Per dof: an unknown, i.e. not prescribed and used by some cell.
pub(crate) fn free_dofs(k: &CsrMatrix, dirichlet: &Dirichlet) -> Vec<bool> {
    let mut free: Vec<bool> = (0..k.nrows).map(|i| k.indptr[i + 1] > k.indptr[i]).collect();
    for (dof, _) in dirichlet.iter() {
        free[dof] = false;
    }
    free
}

/// PCG on PᵀKP, matrix-free (any multiplier): P x = [x; −C_S⁻¹C_R x] and
/// Pᵀy = y_R − C_Rᵀ C_S⁻ᵀ y_S with one sparse LU of C_S (interface-sized);
/// for C u = g (contact rows) u = P x + u_g with (u_g)_S = C_S⁻¹ g. The
/// Dirichlet dofs are eliminated as in [`solve_pcg`] (identity rows, zero
/// right-hand side), the preconditioner is K's point-block Jacobi.
pub(crate) fn matrix_free(
    k: &CsrMatrix,
    f: &[f64],
    dirichlet: &Dirichlet,
    constraints: &Constraints,
    options: &PcgOptions,
    seconds: &mut Timings,
) -> Result<Solved, ProblemError> {
    let clock = Instant::now();
    let n = k.nrows;
    let (retained, n_r) = retained_numbering(constraints);
    let reduction = Reduction::new(constraints, &retained, n_r)?;
    let mut active_r = vec![true; n_r];
    let mut lift = vec![0.0; n_r];
    for (dof, v) in dirichlet.iter() {
        active_r[retained[dof]] = false;
        lift[retained[dof]] = v;
    }
    let active = free_dofs(k, dirichlet);
    let mut u_g = vec![0.0; n];
    if constraints.g.iter().any(|&g| g != 0.0) {
        for (row, v) in constraints.rows.iter().zip(reduction.solve_cs(&constraints.g, false)) {
            u_g[row.dof] = v;
        }
    }
    // b = Pᵀ(f − K (P ū + u_g)) on the free retained dofs.
    let mut ku = vec![0.0; n];
    let lifted: Vec<f64> = reduction.apply_p(&lift).iter().zip(&u_g).map(|(a, b)| a + b).collect();
    par_mul(k, &lifted, &mut ku);
    let residual: Vec<f64> = f.iter().zip(&ku).map(|(a, b)| a - b).collect();
    let mut b = reduction.apply_pt(&residual);
    for (bi, &a) in b.iter_mut().zip(&active_r) {
        if !a {
            *bi = 0.0;
        }
    }
    let jacobi = BlockJacobi::new(k, &active, if n % 3 == 0 { 3 } else { 1 });
    seconds.setup += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let apply_a = |x: &[f64], y: &mut [f64]| {
        let mut kx = vec![0.0; n];
        par_mul(k, &reduction.apply_p(x), &mut kx);
        y.copy_from_slice(&reduction.apply_pt(&kx));
        for ((yi, xi), &a) in y.iter_mut().zip(x).zip(&active_r) {
            if !a {
                *yi = *xi;
            }
        }
    };
    let apply_m = |r: &[f64], z: &mut [f64]| {
        let mut full = vec![0.0; n];
        for (dof, &i) in retained.iter().enumerate() {
            if i != NONE {
                full[dof] = r[i];
            }
        }
        let mut out = vec![0.0; n];
        jacobi.apply(&full, &mut out);
        for (dof, &i) in retained.iter().enumerate() {
            if i != NONE {
                z[i] = out[dof];
            }
        }
    };
    let mut x = vec![0.0; n_r];
    let report = pcg(apply_a, apply_m, &b, &mut x, options.rtol, options.max_iter);
    if let Some(e) = report.error(options.rtol) {
        return Err(e.into());
    }
    seconds.factorization += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    for ((xi, l), &a) in x.iter_mut().zip(&lift).zip(&active_r) {
        if !a {
            *xi = *l;
        }
    }
    let u: Vec<f64> = reduction.apply_p(&x).iter().zip(&u_g).map(|(a, b)| a + b).collect();
    let mut ku = vec![0.0; n];
    par_mul(k, &u, &mut ku);
    let rest: Vec<f64> = constraints.rows.iter().map(|row| f[row.dof] - ku[row.dof]).collect();
    let lambda = reduction.solve_cs(&rest, true);
    seconds.solve += clock.elapsed().as_secs_f64();
    Ok((u, lambda, "reduced PCG, matrix-free (u_s = T u_m)", report.iterations))
}

/// C = [C_S C_R] split by eliminated (S) and retained (R) dofs, C_S factored.
struct Reduction<'a> {
    constraints: &'a Constraints,
    retained: &'a [usize],
    c_r: CsrMatrix,
    c_r_t: CsrMatrix,
    lu: faer::sparse::linalg::solvers::Lu<usize, f64>,
}

impl<'a> Reduction<'a> {
    fn new(constraints: &'a Constraints, retained: &'a [usize], n_r: usize) -> Result<Self, ProblemError> {
        let nc = constraints.rows.len();
        let mut c_s = CsrMatrix::zeros(0, nc);
        let mut c_r = CsrMatrix::zeros(0, n_r);
        for r in 0..nc {
            let (cols, vals) = constraints.c.row(r);
            for (&j, &v) in cols.iter().zip(vals) {
                match constraints.row_of[j] {
                    NONE => {
                        c_r.indices.push(retained[j]);
                        c_r.values.push(v);
                    }
                    l => {
                        c_s.indices.push(l);
                        c_s.values.push(v);
                    }
                }
            }
            for m in [&mut c_s, &mut c_r] {
                m.indptr.push(m.indices.len());
                m.nrows += 1;
            }
        }
        // Columns of C_S follow the row order of their eliminated dofs, which
        // increases with the dof within an interface; sort to be safe.
        for i in 0..c_s.nrows {
            let range = c_s.indptr[i]..c_s.indptr[i + 1];
            let mut pairs: Vec<(usize, f64)> = c_s.indices[range.clone()]
                .iter()
                .copied()
                .zip(c_s.values[range.clone()].iter().copied())
                .collect();
            pairs.sort_unstable_by_key(|p| p.0);
            for (k, (j, v)) in range.zip(pairs) {
                c_s.indices[k] = j;
                c_s.values[k] = v;
            }
        }
        let c_s_t = c_s.transpose();
        let lu = transposed_view(&c_s_t).sp_lu().map_err(|_| SolveError::Singular)?;
        let c_r_t = c_r.transpose();
        Ok(Reduction { constraints, retained, c_r, c_r_t, lu })
    }

    /// C_S⁻¹ w, or C_S⁻ᵀ w.
    fn solve_cs(&self, w: &[f64], transpose: bool) -> Vec<f64> {
        let mut x = Mat::<f64>::from_fn(w.len(), 1, |i, _| w[i]);
        if transpose {
            self.lu.solve_transpose_in_place(x.as_mut());
        } else {
            self.lu.solve_in_place(x.as_mut());
        }
        (0..w.len()).map(|i| x[(i, 0)]).collect()
    }

    /// u = P x.
    fn apply_p(&self, x: &[f64]) -> Vec<f64> {
        let mut u = vec![0.0; self.retained.len()];
        for (ui, &i) in u.iter_mut().zip(self.retained) {
            if i != NONE {
                *ui = x[i];
            }
        }
        let s = self.solve_cs(&self.c_r.mul_vec(x, 1), false);
        for (row, si) in self.constraints.rows.iter().zip(s) {
            u[row.dof] = -si;
        }
        u
    }

    /// z = Pᵀ y.
    fn apply_pt(&self, y: &[f64]) -> Vec<f64> {
        let y_s: Vec<f64> = self.constraints.rows.iter().map(|row| y[row.dof]).collect();
        let t = self.solve_cs(&y_s, true);
        let correction = self.c_r_t.mul_vec(&t, 1);
        let mut z = vec![0.0; self.c_r.ncols];
        for (&i, &yi) in self.retained.iter().zip(y) {
            if i != NONE {
                z[i] = yi;
            }
        }
        for (zi, c) in z.iter_mut().zip(correction) {
            *zi -= c;
        }
        z
    }
}

/// The glued interfaces eliminated (dual or lumped multipliers, module doc
/// of [`crate::glue`]): u = P_g y with y the unknowns of all dofs, eliminated
/// ones left out (empty rows and columns), so the contact points keep their
/// numbering.
pub(crate) struct Elimination {
    /// P_g, n × n.
    pub(crate) p: CsrMatrix,
    /// P_gᵀ K P_g.
    pub(crate) k: CsrMatrix,
    /// P_gᵀ f.
    pub(crate) f: Vec<f64>,
    /// Per dof: [`NONE`] if eliminated.
    pub(crate) retained: Vec<usize>,
}

impl Elimination {
    pub(crate) fn new(
        constraints: &Constraints,
        k: &CsrMatrix,
        f: &[f64],
    ) -> Result<Elimination, ProblemError> {
        if !constraints.eliminated_block_is_diagonal() {
            let interface = constraints.rows[0].interface;
            let what = "with the PCG and PETSc solvers, glued interfaces that constrain each other's slave \
                        points (crosspoints) next to contact interfaces are not supported (use the direct solver)"
                .into();
            return Err(ProblemError::BadInterface { interface, what });
        }
        let (p, retained) = full_prolongation(constraints);
        Ok(Elimination { k: triple_product(&p, k), f: p.transpose_mul_vec(f, 1), p, retained })
    }
}

/// P_g of [`Elimination`] (n × n: u = P_g y, y in the numbering of all
/// dofs, its eliminated entries unused) and, per dof, its retained index or
/// [`NONE`] if eliminated. C_S must be diagonal.
pub(crate) fn full_prolongation(constraints: &Constraints) -> (CsrMatrix, Vec<usize>) {
    let (p, retained) = prolongation(constraints);
    let mut dof_of = vec![0; p.ncols];
    for (dof, &r) in retained.iter().enumerate().filter(|(_, &r)| r != NONE) {
        dof_of[r] = dof;
    }
    let n = p.nrows;
    let indices = p.indices.iter().map(|&r| dof_of[r]).collect();
    (CsrMatrix { nrows: n, ncols: n, indptr: p.indptr, indices, values: p.values }, retained)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sparse n × m matrix with about `fill` of its entries set (a fixed
    /// pseudo-random pattern and values).
    fn sparse(n: usize, m: usize, fill: f64, seed: u64) -> CsrMatrix {
        let mut state = seed;
        let mut next = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut a = CsrMatrix::zeros(0, m);
        for _ in 0..n {
            for j in 0..m {
                if next() < fill {
                    a.indices.push(j);
                    a.values.push(next() - 0.5);
                }
            }
            a.indptr.push(a.indices.len());
            a.nrows += 1;
        }
        a
    }

    fn dense(a: &CsrMatrix) -> Vec<Vec<f64>> {
        let mut d = vec![vec![0.0; a.ncols]; a.nrows];
        for (i, row) in d.iter_mut().enumerate() {
            let (cols, vals) = a.row(i);
            cols.iter().zip(vals).for_each(|(&j, &v)| row[j] = v);
        }
        d
    }

    /// PᵀKP row by row against the dense product, for a square and a
    /// rectangular P with empty rows and columns; sorted rows, and the same
    /// bits on one thread as on several.
    #[test]
    fn triple_product_is_pt_k_p() {
        for (n, m, seed) in [(40, 40, 1), (37, 23, 2), (5, 9, 3)] {
            let (k, p) = (sparse(n, n, 0.2, seed), sparse(n, m, 0.08, seed + 10));
            let a = triple_product(&p, &k);
            let (dk, dp) = (dense(&k), dense(&p));
            assert_eq!((a.nrows, a.ncols), (m, m));
            for (i, row) in dense(&a).iter().enumerate() {
                let cols = a.row(i).0;
                assert!(cols.windows(2).all(|w| w[0] < w[1]), "row {i} sorted, each column once");
                for (j, &v) in row.iter().enumerate() {
                    let exact: f64 = (0..n)
                        .flat_map(|r| (0..n).map(move |l| (r, l)))
                        .map(|(r, l)| dp[r][i] * dk[r][l] * dp[l][j])
                        .sum();
                    assert!((v - exact).abs() < 1e-13, "({i}, {j}): {v} against {exact}");
                }
            }
            let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
            let serial = one.install(|| triple_product(&p, &k));
            assert_eq!((serial.indptr, serial.indices), (a.indptr, a.indices));
            assert!(serial.values.iter().zip(&a.values).all(|(x, y)| x.to_bits() == y.to_bits()));
        }
    }
}
