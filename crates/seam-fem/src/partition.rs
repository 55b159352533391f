//! The glued bodies partitioned over MPI ranks (`mpirun -np N seam solve
//! --solver petsc`, the leader/follower model of [`crate::petsc`]): each
//! rank assembles and reduces the cells it owns, so that neither K nor the
//! reduced system is ever whole on one rank.
//!
//! With dual or lumped multipliers u = Q y + w ([`crate::glue`]: Q = P_g,
//! the slave dofs eliminated, without the columns of prescribed, eliminated
//! and unused dofs; w = P_g ȳ the prescribed values), and the system is
//! A y = b with
//!
//! ```text
//! A = QᵀKQ = Σ_e Q_eᵀ K_e Q_e,    b = Qᵀ f − Σ_e Q_eᵀ K_e w_e,
//! ```
//!
//! e the cells, Q_e and w_e their dofs' rows of Q and values of w (the
//! identity on the left-out rows of A, zero in b).
//!
//! - **Rows.** The points of all bodies, one after the other, are cut into N
//!   contiguous blocks balanced by the lengths of their rows in A, counted
//!   by points (`row_ranges`); rank r holds the rows of its block in
//!   PETSc's distributed matrices.
//! - **Cells.** A cell belongs to the rank that holds its lowest point. Rank
//!   0 (which reads the case) sends each rank its cells — their points'
//!   coordinates, rows of Q and values of w, the body's material — as a job
//!   (`answer` on the other ranks); every rank forms its cells' K, their
//!   Σ_e Q_eᵀ K_e Q_e (by the triple product of one process, in the columns
//!   its rows of Q meet) and Σ_e Q_eᵀ K_e w_e, and stages the former for
//!   the PETSc layer (`seam_petsc::stage`), which sends the entries of rows
//!   held elsewhere to their ranks;
//!   the latter come back to rank 0 with the answers.
//!
//! A cell that cannot be assembled (degenerate) is reported by its rank to
//! rank 0, which fails with the error one process gives.
//!
//! Without the feature `petsc` no process leads other ranks: the jobs are
//! built only by this module's tests.
#![cfg_attr(not(feature = "petsc"), allow(dead_code))]

use crate::material::Material;
use crate::multibody::{Body, ProblemError};
use crate::AssemblyError;
use seam::CellKind;
use seam::{CsrMatrix, VolumeMesh};

/// The tag of a job's bytes (and of its version).
const MAGIC: &[u8; 8] = b"seamK002";

/// The first row of each of `ranks` ranks, then n (in dofs, whole points):
/// contiguous blocks of the bodies' points balanced by their rows' lengths
/// in A = QᵀKQ, counted in points (one plus the points that row p of A
/// meets: ∪ supp Q_l over the points l of the cells around every k with
/// Q_kp ≠ 0), plus `extra(p)` (rows added to A's, in the same unit), the
/// last block also holding rows of weight `tail` after the points'. The
/// master points of an interface, coupled through the eliminated slave
/// points, have rows several times as long as K's; the counts are exact at
/// the level of points and cost a fraction of forming A.
pub(crate) fn row_ranges(
    bodies: &[Body],
    q: &CsrMatrix,
    (extra, tail): (&dyn Fn(usize) -> usize, usize),
    ranks: usize,
) -> Vec<usize> {
    let n = q.nrows / 3;
    // The cells of all bodies in the numbering of all points, and the cells
    // around each point.
    let (mut first, mut nodes) = (vec![0], Vec::new());
    let mut base = 0;
    for body in bodies {
        for cell in body.mesh.cells() {
            nodes.extend(cell.nodes().iter().map(|&p| base + p));
            first.push(nodes.len());
        }
        base += body.mesh.points().len();
    }
    let around = transpose(n, (0..first.len() - 1).map(|c| &nodes[first[c]..first[c + 1]]));
    // Q and Qᵀ by points.
    let q_points: Vec<Vec<usize>> = (0..n)
        .map(|k| {
            let mut cols: Vec<usize> =
                (3 * k..3 * k + 3).flat_map(|r| q.row(r).0.iter().map(|&j| j / 3)).collect();
            cols.sort_unstable();
            cols.dedup();
            cols
        })
        .collect();
    let q_t = transpose(n, q_points.iter().map(Vec::as_slice));
    let mut stamp = vec![usize::MAX; n];
    let weight: Vec<usize> = (0..n)
        .map(|p| {
            let mut count = 1 + extra(p);
            for &k in q_t.row(p) {
                for &c in around.row(k) {
                    for &l in &nodes[first[c]..first[c + 1]] {
                        for &j in &q_points[l] {
                            if stamp[j] != p {
                                stamp[j] = p;
                                count += 1;
                            }
                        }
                    }
                }
            }
            count
        })
        .collect();
    let total: usize = weight.iter().sum::<usize>() + tail;
    let mut ranges = vec![0; ranks + 1];
    let (mut sum, mut point) = (0, 0);
    for (r, range) in ranges.iter_mut().enumerate().skip(1) {
        let target = (total as u128 * r as u128 / ranks as u128) as usize;
        while point < n && sum < target {
            sum += weight[point];
            point += 1;
        }
        *range = 3 * point;
    }
    ranges[ranks] = 3 * n;
    ranges
}

/// K's diagonal at the `wanted` dofs of all bodies (0 elsewhere), from the
/// cells that touch them, each dof's entries summed in increasing cell order
/// as [`crate::stiffness`] sums them.
///
/// # Errors
/// [`ProblemError::Assembly`] for a degenerate cell among them.
pub(crate) fn stiffness_diagonal(bodies: &[Body], wanted: &[bool]) -> Result<Vec<f64>, ProblemError> {
    let mut diagonal = vec![0.0; wanted.len()];
    let mut base = 0;
    for (b, body) in bodies.iter().enumerate() {
        for (c, cell) in body.mesh.cells().iter().enumerate() {
            let dofs = |p: usize| base + 3 * p..base + 3 * p + 3;
            if !cell.nodes().iter().any(|&p| dofs(p).any(|d| wanted[d])) {
                continue;
            }
            let (x, kind) = crate::assembly::corners(body.mesh, c);
            let k = crate::assembly::element_stiffness(kind, &x[..kind.n_nodes()], &body.material).ok_or(
                ProblemError::Assembly { body: b, source: AssemblyError::DegenerateCell { cell: c } },
            )?;
            let nd = 3 * kind.n_nodes();
            for (l, &p) in cell.nodes().iter().enumerate() {
                for (a, d) in dofs(p).enumerate() {
                    diagonal[d] += k[(3 * l + a) * nd + 3 * l + a];
                }
            }
        }
        base += 3 * body.mesh.points().len();
    }
    Ok(diagonal)
}

/// Lists of indices below `n`, one per row, as CSR rows of their transpose
/// (each row's entries in increasing order of the rows that hold them).
fn transpose<'a>(n: usize, rows: impl Iterator<Item = &'a [usize]> + Clone) -> Lists {
    let mut start = vec![0usize; n + 1];
    for row in rows.clone() {
        for &j in row {
            start[j + 1] += 1;
        }
    }
    for j in 0..n {
        start[j + 1] += start[j];
    }
    let mut fill = start.clone();
    let mut items = vec![0; start[n]];
    for (i, row) in rows.enumerate() {
        for &j in row {
            items[fill[j]] = i;
            fill[j] += 1;
        }
    }
    Lists { start, items }
}

/// Lists of indices, CSR-like.
struct Lists {
    start: Vec<usize>,
    items: Vec<usize>,
}

impl Lists {
    fn row(&self, i: usize) -> &[usize] {
        &self.items[self.start[i]..self.start[i + 1]]
    }
}

/// The jobs of the ranks: rank r's cells with what assembling them and
/// reducing them by u = Q y + w needs (module doc): their points'
/// coordinates and dofs, those dofs' rows of Q and values of w, the body's
/// material; in the byte layout that [`cell_part`] reads.
pub(crate) fn cell_jobs(bodies: &[Body], ranges: &[usize], q: &CsrMatrix, w: &[f64]) -> Vec<Vec<u8>> {
    let ranks = ranges.len() - 1;
    let owner = |dof: usize| ranges.partition_point(|&r| r <= dof) - 1;
    let mut jobs: Vec<Vec<u8>> = (0..ranks).map(|_| MAGIC.to_vec()).collect();
    let mut parts: Vec<Vec<(usize, &Body, Vec<usize>)>> = vec![Vec::new(); ranks];
    let mut offset = 0;
    for (b, body) in bodies.iter().enumerate() {
        let mut cells: Vec<Vec<usize>> = vec![Vec::new(); ranks];
        for (c, cell) in body.mesh.cells().iter().enumerate() {
            let lowest = cell.nodes().iter().copied().min().unwrap_or(0);
            cells[owner(offset + 3 * lowest)].push(c);
        }
        for (r, cells) in cells.into_iter().enumerate().filter(|(_, c)| !c.is_empty()) {
            parts[r].push((b, body, cells));
        }
        offset += 3 * body.mesh.points().len();
    }
    let firsts = body_offsets(bodies);
    for (job, part) in jobs.iter_mut().zip(parts) {
        put(job, part.len() as u64);
        for (b, body, cells) in part {
            // The points of these cells, numbered in order of first use.
            let mesh = body.mesh;
            let mut local = vec![u32::MAX; mesh.points().len()];
            let mut points = Vec::new();
            for &c in &cells {
                for &p in mesh.cells()[c].nodes() {
                    if local[p] == u32::MAX {
                        local[p] = points.len() as u32;
                        points.push(p);
                    }
                }
            }
            put(job, b as u64);
            job.extend_from_slice(&body.material.young().to_le_bytes());
            job.extend_from_slice(&body.material.poisson().to_le_bytes());
            put(job, points.len() as u64);
            for &p in &points {
                for x in mesh.points()[p] {
                    job.extend_from_slice(&x.to_le_bytes());
                }
                let dof = firsts[b] + 3 * p;
                for d in dof..dof + 3 {
                    let (cols, vals) = q.row(d);
                    job.extend_from_slice(&w[d].to_le_bytes());
                    job.extend_from_slice(&(cols.len() as u32).to_le_bytes());
                    for (&j, &v) in cols.iter().zip(vals) {
                        job.extend_from_slice(&(j as u32).to_le_bytes());
                        job.extend_from_slice(&v.to_le_bytes());
                    }
                }
            }
            put(job, cells.len() as u64);
            for &c in &cells {
                let (kind, nodes) = (mesh.cells()[c].kind(), mesh.cells()[c].nodes());
                put(job, c as u64);
                job.push(kind as u8);
                for &p in nodes {
                    job.extend_from_slice(&local[p].to_le_bytes());
                }
            }
        }
    }
    jobs
}

fn body_offsets(bodies: &[Body]) -> Vec<usize> {
    crate::multibody::dof_offsets(bodies)
}

fn put(job: &mut Vec<u8>, v: u64) {
    job.extend_from_slice(&v.to_le_bytes());
}

/// One body's cells of a rank: its sub-mesh, its material, each local
/// dof's row of Q and value of w, and each cell's index in the body.
struct BodyPart {
    body: usize,
    mesh: VolumeMesh,
    material: Material,
    q: Vec<Vec<(usize, f64)>>,
    w: Vec<f64>,
    cells: Vec<usize>,
}

/// Reads a job's bytes ([`cell_jobs`]).
fn cell_part(bytes: &[u8]) -> Option<Vec<BodyPart>> {
    let mut reader = Reader { at: bytes.strip_prefix(MAGIC.as_slice())? };
    let n_parts = reader.count(1)?;
    let mut parts = Vec::with_capacity(n_parts);
    for _ in 0..n_parts {
        let body = reader.u64()? as usize;
        let material = Material::new(reader.f64()?, reader.f64()?).ok()?;
        let n_points = reader.count(60)?;
        let mut points = Vec::with_capacity(n_points);
        let (mut q, mut w) = (Vec::with_capacity(3 * n_points), Vec::with_capacity(3 * n_points));
        for _ in 0..n_points {
            points.push([reader.f64()?, reader.f64()?, reader.f64()?]);
            for _ in 0..3 {
                w.push(reader.f64()?);
                let len = reader.u32()? as usize;
                if len.checked_mul(12)? > reader.at.len() {
                    return None;
                }
                q.push(
                    (0..len).map(|_| Some((reader.u32()? as usize, reader.f64()?))).collect::<Option<_>>()?,
                );
            }
        }
        let n_cells = reader.count(13)?;
        let (mut cells, mut index) = (Vec::with_capacity(n_cells), Vec::with_capacity(n_cells));
        for _ in 0..n_cells {
            index.push(reader.u64()? as usize);
            let kind = *CellKind::ALL.get(reader.byte()? as usize)?;
            let nodes =
                (0..kind.n_nodes()).map(|_| reader.u32().map(|p| p as usize)).collect::<Option<Vec<_>>>()?;
            cells.push(kind.cell(&nodes)?);
        }
        let mesh = VolumeMesh::new(points, cells).ok()?;
        parts.push(BodyPart { body, mesh, material, q, w, cells: index });
    }
    reader.at.is_empty().then_some(parts)
}

/// Little-endian fields, none read past the end.
struct Reader<'a> {
    at: &'a [u8],
}

impl Reader<'_> {
    fn bytes<const N: usize>(&mut self) -> Option<[u8; N]> {
        let head = self.at.get(..N)?.try_into().ok()?;
        self.at = &self.at[N..];
        Some(head)
    }
    fn u64(&mut self) -> Option<u64> {
        self.bytes().map(u64::from_le_bytes)
    }
    fn u32(&mut self) -> Option<u32> {
        self.bytes().map(u32::from_le_bytes)
    }
    fn f64(&mut self) -> Option<f64> {
        self.bytes().map(f64::from_le_bytes)
    }
    fn byte(&mut self) -> Option<u8> {
        self.bytes::<1>().map(|[b]| b)
    }
    /// A count of items of at least `size` bytes each, bounded by the bytes
    /// left (so that a bad count cannot reserve unbounded memory).
    fn count(&mut self, size: usize) -> Option<usize> {
        let n = usize::try_from(self.u64()?).ok()?;
        (n.checked_mul(size)? <= self.at.len()).then_some(n)
    }
}

/// Why a rank's cells could not be assembled.
enum PartError {
    /// A degenerate cell: the body and the cell's index in it.
    Degenerate(usize, usize),
    /// Anything else, as a line.
    Other(String),
}

/// A rank's contributions to Qᵀ K w: (index, value), by increasing index.
type Contributions = Vec<(usize, f64)>;

/// A rank's answer as bytes: 0 and its contributions, 1 and a degenerate
/// cell (body, cell), or 2 and a line.
fn answer_bytes(answer: &Result<Contributions, PartError>) -> Vec<u8> {
    let mut bytes = Vec::new();
    match answer {
        Ok(contributions) => {
            bytes.push(0);
            put(&mut bytes, contributions.len() as u64);
            for &(i, v) in contributions {
                put(&mut bytes, i as u64);
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        Err(PartError::Degenerate(body, cell)) => {
            bytes.push(1);
            put(&mut bytes, *body as u64);
            put(&mut bytes, *cell as u64);
        }
        Err(PartError::Other(line)) => {
            bytes.push(2);
            bytes.extend_from_slice(line.as_bytes());
        }
    }
    bytes
}

/// Reads rank `rank`'s answer ([`answer_bytes`]).
fn read_answer(bytes: &[u8], rank: usize) -> Result<Contributions, ProblemError> {
    let mut reader = Reader { at: bytes.get(1..).unwrap_or_default() };
    match bytes.first() {
        Some(0) => {
            let read = |reader: &mut Reader| -> Option<Contributions> {
                let n = reader.count(16)?;
                (0..n).map(|_| Some((reader.u64()? as usize, reader.f64()?))).collect()
            };
            read(&mut reader).ok_or_else(|| other(rank, "an unreadable answer"))
        }
        Some(1) => match (reader.u64(), reader.u64()) {
            (Some(body), Some(cell)) => Err(ProblemError::Assembly {
                body: body as usize,
                source: AssemblyError::DegenerateCell { cell: cell as usize },
            }),
            _ => Err(other(rank, "an unreadable answer")),
        },
        Some(_) => Err(other(rank, &String::from_utf8_lossy(reader.at))),
        None => Err(other(rank, "no answer")),
    }
}

fn other(rank: usize, what: &str) -> ProblemError {
    ProblemError::Solve(crate::solve::SolveError::Petsc(format!(
        "MPI rank {rank} could not assemble its cells: {what}"
    )))
}

/// A body part's columns of Q (sorted) and Q_eᵀ K_e Q_e in them.
type Reduced = (Vec<usize>, CsrMatrix);

/// A job's cells reduced: per body part, the columns its rows of Q meet
/// (sorted) and Q_eᵀ K_e Q_e in them (K_e the part's stiffness, Q_e its
/// rows of Q), and the contributions Q_eᵀ K_e w_e to Qᵀ K w.
fn reduce_part(bytes: &[u8]) -> Result<(Vec<Reduced>, Contributions), PartError> {
    let parts = cell_part(bytes).ok_or_else(|| PartError::Other("its job's bytes do not read".into()))?;
    let (mut products, mut contributions) = (Vec::with_capacity(parts.len()), Vec::new());
    for part in &parts {
        let k = crate::stiffness(&part.mesh, &part.material).map_err(
            |AssemblyError::DegenerateCell { cell }| PartError::Degenerate(part.body, part.cells[cell]),
        )?;
        let mut cols: Vec<usize> = part.q.iter().flatten().map(|&(j, _)| j).collect();
        cols.sort_unstable();
        cols.dedup();
        let mut q = CsrMatrix::zeros(0, cols.len());
        for row in &part.q {
            for &(j, v) in row {
                q.indices.push(cols.binary_search(&j).expect("a column of the rows"));
                q.values.push(v);
            }
            q.indptr.push(q.indices.len());
            q.nrows += 1;
        }
        let qtkw = q.transpose_mul_vec(&k.mul_vec(&part.w, 1), 1);
        contributions.extend(qtkw.iter().zip(&cols).filter(|(&v, _)| v != 0.0).map(|(&v, &j)| (j, v)));
        products.push((cols, crate::constraints::triple_product(&q, &k)));
    }
    // Sorted by index, each index's values in part order (deterministic).
    contributions.sort_by_key(|&(j, _)| j);
    Ok((products, contributions))
}

/// Reduces a job's cells ([`reduce_part`]) and stages their entries of
/// QᵀKQ and `extra` entries for PETSc (`seam_petsc::stage`).
#[cfg(feature = "petsc")]
fn stage_part(bytes: &[u8], extra: &[(usize, usize, f64)]) -> Result<Contributions, PartError> {
    let (products, contributions) = reduce_part(bytes)?;
    let count = products.iter().map(|(_, a)| a.nnz()).sum::<usize>() + extra.len();
    seam_petsc::stage(count, |rows, cols, values| {
        let mut at = 0;
        let mut push = |i: usize, j: usize, v: f64| {
            (rows[at], cols[at], values[at]) = (i as seam_petsc::Index, j as seam_petsc::Index, v);
            at += 1;
        };
        for (global, a) in &products {
            for r in 0..a.nrows {
                let (cs, vs) = a.row(r);
                for (&c, &v) in cs.iter().zip(vs) {
                    push(global[r], global[c], v);
                }
            }
        }
        for &(i, j, v) in extra {
            push(i, j, v);
        }
    })
    .map_err(|e| PartError::Other(e.0))?;
    Ok(contributions)
}

/// A rank other than 0: does the job that [`crate::petsc::follow_petsc`]
/// returned — reduces its cells and stages their entries of QᵀKQ for PETSc —
/// and answers rank 0 with its contributions to Qᵀ K w. Then follow again.
#[cfg(feature = "petsc")]
pub fn answer(job: &[u8]) {
    seam_petsc::reply(&answer_bytes(&stage_part(job, &[])));
}

/// Rank 0: hands every rank its cells ([`cell_jobs`]), reduces its own and
/// stages them with the `extra` entries (the identity on rows left out, the
/// constraints of a saddle point), and collects the others' answers;
/// returns Qᵀ K w, summed in rank order. `ranges` as [`row_ranges`];
/// u = Q y + w.
///
/// # Errors
/// The first rank's failure, in rank order: a degenerate cell as one
/// process reports it.
#[cfg(feature = "petsc")]
pub(crate) fn assemble_over_ranks(
    bodies: &[Body],
    ranges: &[usize],
    (q, w): (&CsrMatrix, &[f64]),
    extra: &[(usize, usize, f64)],
) -> Result<Vec<f64>, ProblemError> {
    let mut jobs = cell_jobs(bodies, ranges, q, w);
    let own = jobs.remove(0);
    seam_petsc::send_jobs(&jobs);
    drop(jobs);
    let own = read_answer(&answer_bytes(&stage_part(&own, extra)), 0);
    let answers: Vec<_> =
        (1..ranges.len() - 1).map(|r| read_answer(&seam_petsc::receive_reply(r), r)).collect();
    let mut qtkw = vec![0.0; q.nrows];
    for contributions in std::iter::once(own).chain(answers) {
        for (i, v) in contributions? {
            qtkw[i] += v;
        }
    }
    Ok(qtkw)
}

/// Without the feature no process leads other ranks: never called.
#[cfg(not(feature = "petsc"))]
pub(crate) fn assemble_over_ranks(
    _: &[Body],
    _: &[usize],
    _: (&CsrMatrix, &[f64]),
    _: &[(usize, usize, f64)],
) -> Result<Vec<f64>, ProblemError> {
    Err(ProblemError::Solve(crate::solve::SolveError::PetscUnavailable))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{block, BlockKind};
    use crate::solve::Dirichlet;

    /// Two bodies cut into 1…5 ranks' cells, reduced by a Q that ties some
    /// dofs of the second body to the first's (as eliminated slave dofs are)
    /// and drops others: the rows are whole points, every cell goes to one
    /// rank, and the ranks' entries and contributions summed are QᵀKQ and
    /// QᵀKw of the whole bodies to round-off.
    #[test]
    fn the_ranks_cells_sum_to_the_reduced_system() {
        let material = Material::new(1000.0, 0.3).unwrap();
        let a = block(3, 2, 2, |u, v, w| [u, v, w], BlockKind::Hex);
        let b = block(2, 2, 3, |u, v, w| [u + 1.0, v, 0.7 * w], BlockKind::Tet);
        let body =
            |mesh| Body { mesh, material, load: vec![], dirichlet: Dirichlet::new(), ties: Vec::new() };
        let bodies = [body(&a), body(&b)];
        let k = crate::multibody::bodies_stiffness(&bodies).unwrap();
        let n = k.nrows;
        let n_a = 3 * a.points().len();
        // Q: the identity, but the first 12 dofs of b are eliminated (their
        // rows the mean of two dofs of a, their columns empty) and dof 5 is
        // dropped (an empty row and column).
        let mut q = CsrMatrix::zeros(0, n);
        for d in 0..n {
            match d {
                5 => {}
                d if (n_a..n_a + 12).contains(&d) => {
                    let m = (d - n_a) % n_a;
                    q.indices.extend([m + 6, m + 9]);
                    q.values.extend([0.5, 0.5]);
                }
                d => {
                    q.indices.push(d);
                    q.values.push(1.0);
                }
            }
            q.indptr.push(q.indices.len());
            q.nrows += 1;
        }
        let w: Vec<f64> = (0..n).map(|d| if d % 7 == 0 { (d as f64).sin() } else { 0.0 }).collect();
        let reduced = crate::constraints::triple_product(&q, &k);
        let qtkw = q.transpose_mul_vec(&k.mul_vec(&w, 1), 1);
        let scale = k.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for ranks in 1..=5 {
            let ranges = row_ranges(&bodies, &q, (&|_| 0, 0), ranks);
            assert_eq!((ranges[0], ranges[ranks]), (0, n));
            assert!(ranges.windows(2).all(|r| r[0] <= r[1] && r[0] % 3 == 0), "{ranges:?}");
            let jobs = cell_jobs(&bodies, &ranges, &q, &w);
            let cells: usize =
                jobs.iter().flat_map(|j| cell_part(j).unwrap()).map(|p| p.mesh.cells().len()).sum();
            assert_eq!(cells, a.cells().len() + b.cells().len());
            let (mut sum, mut contributions) = (vec![vec![0.0; n]; n], vec![0.0; n]);
            for job in &jobs {
                let (products, part) = reduce_part(job).ok().unwrap();
                for (global, a) in products {
                    for r in 0..a.nrows {
                        let (cs, vs) = a.row(r);
                        cs.iter().zip(vs).for_each(|(&c, &v)| sum[global[r]][global[c]] += v);
                    }
                }
                part.iter().for_each(|&(i, v)| contributions[i] += v);
            }
            for (i, row) in sum.iter().enumerate() {
                for (j, &v) in row.iter().enumerate() {
                    assert!((v - reduced.get(i, j)).abs() <= 1e-13 * scale, "{ranks} ranks, ({i}, {j})");
                }
                assert!((contributions[i] - qtkw[i]).abs() <= 1e-13 * scale, "{ranks} ranks, QᵀKw at {i}");
            }
        }
        // A rank's failure comes back as one process reports it.
        let degenerate = read_answer(&answer_bytes(&Err(PartError::Degenerate(1, 7))), 1);
        assert!(
            matches!(
                degenerate,
                Err(ProblemError::Assembly { body: 1, source: AssemblyError::DegenerateCell { cell: 7 } })
            ),
            "{degenerate:?}"
        );
        let text = read_answer(&answer_bytes(&Err(PartError::Other("out of memory".into()))), 2).unwrap_err();
        assert_eq!(text.to_string(), "PETSc: MPI rank 2 could not assemble its cells: out of memory");
        let done = read_answer(&answer_bytes(&Ok(vec![(3, 0.5), (9, -1.0)])), 1).unwrap();
        assert_eq!(done, vec![(3, 0.5), (9, -1.0)]);
        assert!(read_answer(&[], 1).is_err(), "no answer");
        // Bytes that do not read are refused, not a panic.
        let job = &cell_jobs(&bodies, &row_ranges(&bodies, &q, (&|_| 0, 0), 2), &q, &w)[1];
        for cut in [0, 8, 16, job.len() / 2, job.len() - 1] {
            assert!(cell_part(&job[..cut]).is_none(), "cut at {cut}");
        }
    }
}
