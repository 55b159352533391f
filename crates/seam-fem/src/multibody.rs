//! The multi-body core that gluing ([`crate::glue`]) and contact
//! ([`crate::contact`]) build on: bodies and interfaces, one dof numbering
//! over all bodies (`dof = offset_b + 3·point + component`), the assembled
//! system diag(K_1, …, K_N) with the interfaces' mortar operators, and the
//! glued constraints C u = g with Wohlmuth's modified multiplier basis where
//! slave dofs are prescribed or shared (crosspoints), their elimination
//! u = P y, and the saddle point [K Cᵀ; C 0] solved by sparse LDLᵀ.

use crate::material::Material;
use crate::pcg::PcgOptions;
use crate::saddle::solve_saddle;
use crate::solve::{Dirichlet, SolveError};
use crate::{stiffness, AssemblyError};
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMatRef};
use faer::Par;
use seam::{CsrMatrix, Mortar, MortarError, MortarOptions, SurfaceMesh, VolumeMesh};
use std::time::Instant;

/// One linear-elastic body.
#[derive(Clone, Debug)]
pub struct Body<'a> {
    /// Its cells.
    pub mesh: &'a VolumeMesh,
    /// Its material.
    pub material: Material,
    /// Its load vector f (body forces and tractions), 3 entries per mesh point.
    pub load: Vec<f64>,
    /// Its prescribed displacements (dofs `3·point + component` of this body).
    pub dirichlet: Dirichlet,
}

/// How an interface couples its two bodies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Coupling {
    /// Glued: (D u_s − B u_m) = 0 in every component (this module).
    #[default]
    Glue,
    /// Frictionless contact: a normal inequality per slave point
    /// ([`crate::contact`]).
    Contact,
}

/// An interface between a master and a slave surface of two bodies, glued or
/// in contact. The surfaces index their body's mesh points.
#[derive(Clone, Debug)]
pub struct Interface<'a> {
    /// Index of the master body.
    pub master: usize,
    /// The master surface.
    pub master_surface: &'a SurfaceMesh,
    /// Index of the slave body.
    pub slave: usize,
    /// The slave surface (where the multiplier lives).
    pub slave_surface: &'a SurfaceMesh,
    /// Mortar options (multiplier, gap and angle limits).
    pub options: MortarOptions,
    /// Glue or contact.
    pub kind: Coupling,
}

/// How the glued system is solved (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Solver {
    /// Sparse Cholesky of the reduced system (dual, lumped) or sparse LU of the
    /// saddle point (standard).
    Direct,
    /// Preconditioned conjugate gradients on the reduced system PᵀKP (explicit
    /// for dual and lumped multipliers, matrix-free for standard ones).
    Pcg(PcgOptions),
}

/// Why a multi-body problem (glued, in contact, or both) could not be solved.
#[derive(Debug, thiserror::Error)]
pub enum ProblemError {
    /// An interface refers to a body that does not exist, or to one body twice.
    #[error("interface {interface}: {what}")]
    BadInterface {
        /// Interface index.
        interface: usize,
        /// What is wrong.
        what: String,
    },
    /// A body's load or surface does not match its mesh.
    #[error("body {body}: {what}")]
    BadBody {
        /// Body index.
        body: usize,
        /// What is wrong.
        what: String,
    },
    /// A body's stiffness could not be assembled.
    #[error("body {body}: {source}")]
    Assembly {
        /// Body index.
        body: usize,
        /// The cause.
        source: AssemblyError,
    },
    /// An interface's mortar operator could not be assembled.
    #[error("interface {interface}: {source}")]
    Mortar {
        /// Interface index.
        interface: usize,
        /// The cause.
        source: MortarError,
    },
    /// A slave point of a glued interface is also a slave point of a contact
    /// interface.
    #[error(
        "interface {glue}: slave point {point} at ({}, {}, {}) is also a slave point of contact interface \
         {contact}: a point cannot be glued and in contact at once (split the surfaces so that they share no point)",
        at[0], at[1], at[2]
    )]
    SharedSlavePoint {
        /// The glued interface.
        glue: usize,
        /// The contact interface.
        contact: usize,
        /// The point, in the slave body's mesh.
        point: usize,
        /// Its coordinates.
        at: seam::Point3,
    },
    /// The linear solve failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// An active-set step's system is singular: some body is held neither by
    /// its supports nor by the contact points active in that step.
    #[error(
        "contact: active-set step {step}: the system is singular with {active} active contact points; every \
         body must be held by its supports, or touch (gap ≤ 0) another body from the start"
    )]
    SingularStep {
        /// The step, from 1.
        step: usize,
        /// Its active contact points.
        active: usize,
    },
    /// The system is singular even with every contact point closed: a body
    /// can move without deforming (contact holds only the normal direction).
    #[error(
        "contact: the system is singular even with all {points} contact points closed: a body can move \
         without deforming (frictionless contact holds only the normal direction; add supports)"
    )]
    Unsupported {
        /// The contact points.
        points: usize,
    },
    /// The active set still changed after the iteration cap.
    #[error(
        "contact: the active set did not settle in {steps} steps (last step: {added} points added, {removed} \
         removed); raise the iteration cap or check the load and the supports"
    )]
    ActiveSetNotSettled {
        /// Steps taken (the cap).
        steps: usize,
        /// Points added by the last step.
        added: usize,
        /// Points removed by the last step.
        removed: usize,
    },
    /// A displacement of the solution is NaN or infinite: an overflow (nothing
    /// non-finite passes as a result).
    #[error("body {body}: the solution is not finite at point {} (component {}): an overflow; check the magnitudes of loads, prescribed values and moduli", dof / 3, dof % 3)]
    NonFiniteSolution {
        /// Body index.
        body: usize,
        /// The first such dof of the body (`3·point + component`).
        dof: usize,
    },
}

/// Wall-clock seconds per phase.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// Stiffness assembly of all bodies.
    pub assembly: f64,
    /// Mortar operators (search and assembly) of all interfaces.
    pub mortar: f64,
    /// Forming the system to solve (constraints, reduction PᵀKP).
    pub setup: f64,
    /// Factorisation, or the PCG iterations.
    pub factorization: f64,
    /// Triangular solves, refinement and recovery of u and λ.
    pub solve: f64,
    /// Stresses and the interfaces' tractions.
    pub stresses: f64,
}

/// The bodies' stiffness and loads as one system, and the interfaces' mortar
/// operators.
pub(crate) struct System {
    /// diag(K_1, …, K_N).
    pub k: CsrMatrix,
    /// The loads, one after the other.
    pub f: Vec<f64>,
    /// All prescribed dofs, in global numbering.
    pub dirichlet: Dirichlet,
    /// offsets[b] = first dof of body b; the last entry is the number of dofs.
    pub offsets: Vec<usize>,
    /// Per interface.
    pub mortars: Vec<Mortar>,
}

/// Assembles K_b per body (timed as `assembly`), the mortar operator per
/// interface (`mortar`), and joins them into one [`System`] (`setup`).
pub(crate) fn assemble_system(
    bodies: &[Body],
    interfaces: &[Interface],
    seconds: &mut Timings,
) -> Result<System, ProblemError> {
    let clock = Instant::now();
    let stiffnesses = bodies
        .iter()
        .enumerate()
        .map(|(b, body)| {
            stiffness(body.mesh, &body.material).map_err(|source| ProblemError::Assembly { body: b, source })
        })
        .collect::<Result<Vec<_>, _>>()?;
    seconds.assembly = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let mortars = interfaces
        .iter()
        .enumerate()
        .map(|(i, f)| {
            seam::assemble(f.master_surface, f.slave_surface, &f.options)
                .map_err(|source| ProblemError::Mortar { interface: i, source })
        })
        .collect::<Result<Vec<_>, _>>()?;
    seconds.mortar = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let offsets = dof_offsets(bodies);
    let n = *offsets.last().expect("at least the leading zero");
    let k = block_diagonal(&stiffnesses, n);
    drop(stiffnesses);
    let mut f = vec![0.0; n];
    let mut dirichlet = Dirichlet::new();
    for (b, body) in bodies.iter().enumerate() {
        f[offsets[b]..offsets[b + 1]].copy_from_slice(&body.load);
        for (dof, v) in body.dirichlet.iter() {
            dirichlet.fix_dof(offsets[b] + dof, v);
        }
    }
    seconds.setup = clock.elapsed().as_secs_f64();
    Ok(System { k, f, dirichlet, offsets, mortars })
}

pub(crate) fn check_input(bodies: &[Body], interfaces: &[Interface]) -> Result<(), ProblemError> {
    for (b, body) in bodies.iter().enumerate() {
        let n = 3 * body.mesh.points().len();
        if body.load.len() != n {
            let what = format!("the load has {} entries, the mesh {} dofs", body.load.len(), n);
            return Err(ProblemError::BadBody { body: b, what });
        }
        if let Some((dof, _)) = body.dirichlet.iter().find(|&(d, _)| d >= n) {
            let what = format!("Dirichlet condition on dof {dof}, but the mesh has {n} dofs");
            return Err(ProblemError::BadBody { body: b, what });
        }
    }
    for (i, f) in interfaces.iter().enumerate() {
        let bad = |what: String| ProblemError::BadInterface { interface: i, what };
        for (side, body, surface) in
            [("master", f.master, f.master_surface), ("slave", f.slave, f.slave_surface)]
        {
            let Some(b) = bodies.get(body) else {
                return Err(bad(format!("{side} body {body} does not exist ({} bodies)", bodies.len())));
            };
            if surface.n_points() != b.mesh.points().len() {
                return Err(bad(format!(
                    "the {side} surface has {} points, its body's mesh {}: surfaces must index the body's points",
                    surface.n_points(),
                    b.mesh.points().len()
                )));
            }
        }
        if f.master == f.slave {
            return Err(bad(format!("master and slave are the same body {}", f.master)));
        }
    }
    Ok(())
}

/// offsets[b] = first dof of body b; the last entry is the number of dofs.
pub(crate) fn dof_offsets(bodies: &[Body]) -> Vec<usize> {
    let mut offsets = vec![0];
    for body in bodies {
        offsets.push(offsets.last().unwrap() + 3 * body.mesh.points().len());
    }
    offsets
}

/// diag(K_1, …, K_N) as one n × n matrix.
pub(crate) fn block_diagonal(blocks: &[CsrMatrix], n: usize) -> CsrMatrix {
    let nnz = blocks.iter().map(CsrMatrix::nnz).sum();
    let mut k = CsrMatrix {
        nrows: n,
        ncols: n,
        indptr: Vec::with_capacity(n + 1),
        indices: Vec::with_capacity(nnz),
        values: Vec::with_capacity(nnz),
    };
    k.indptr.push(0);
    let mut offset = 0;
    for block in blocks {
        let base = k.indices.len();
        k.indices.extend(block.indices.iter().map(|&j| j + offset));
        k.values.extend_from_slice(&block.values);
        k.indptr.extend(block.indptr[1..].iter().map(|&p| base + p));
        offset += block.nrows;
    }
    k
}

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
        interfaces: &[Interface],
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
                        let (dq, dv) = m.d.row(q);
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

/// PᵀKP for a symmetric K, by two sparse products (faer, sorted output).
pub(crate) fn triple_product(p: &CsrMatrix, k: &CsrMatrix) -> CsrMatrix {
    let par = Par::rayon(0);
    // As CSC: view(P) = Pᵀ, view(K) = K, so Pᵀ·K is (KP)ᵀ, i.e. KP in CSR.
    let kp =
        faer::sparse::linalg::matmul::sparse_sparse_matmul(transposed_view(p), transposed_view(k), 1.0, par)
            .expect("sparse product fits in memory");
    let kp = from_transposed(kp);
    // (KP)ᵀ P as CSC is PᵀKP in CSR: view(KP) = (KP)ᵀ = PᵀK; P as CSC needs a transpose.
    let pt = p.transpose();
    let a = faer::sparse::linalg::matmul::sparse_sparse_matmul(
        transposed_view(&kp),
        transposed_view(&pt),
        1.0,
        par,
    )
    .expect("sparse product fits in memory");
    from_transposed(a)
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
