//! The glued bodies partitioned over MPI ranks (`mpirun -np N seam solve
//! --solver petsc`, the leader/follower model of [`crate::petsc`]): each
//! rank assembles the stiffness of the cells it owns, and PETSc forms the
//! reduced system PᵀKP over the ranks, so that K is never whole on one rank.
//!
//! - **Rows.** The points of all bodies, one after the other, are cut into N
//!   contiguous blocks balanced by their cells (a point weighs one plus the
//!   cells around it, about its rows' entries); rank r holds the rows of its
//!   block in PETSc's distributed matrices.
//! - **Cells.** A cell belongs to the rank that holds its lowest point. Rank
//!   0 (which reads the case) sends each rank its cells — their points'
//!   coordinates and dofs, the body's material — as a job ([`answer`] on
//!   the other ranks); every rank assembles its cells' K (the entries of
//!   rows held elsewhere travel to their owners inside PETSc, summed by
//!   `MatSetValuesCOO`).
//! - **Reduction.** With dual or lumped multipliers u = P_g y (slave dofs
//!   eliminated, module doc of [`crate::glue`]); rank 0 hands PETSc
//!   P_g (its prescribed and eliminated columns dropped), which forms
//!   A = P_gᵀ K P_g (MatPtAP) and b = P_gᵀ(f − K w), w = P_g ȳ the
//!   prescribed values, over the ranks.
//!
//! A cell that cannot be assembled (degenerate) is reported by its rank to
//! rank 0, which fails with the error one process gives.
//!
//! Without the feature `petsc` no process leads other ranks: the jobs are
//! built only by this module's tests.
#![cfg_attr(not(feature = "petsc"), allow(dead_code))]

use crate::element::ElementKind;
use crate::material::Material;
use crate::multibody::{Body, ProblemError};
use crate::AssemblyError;
use seam::VolumeMesh;

/// The tag of a job's bytes (and of its version).
const MAGIC: &[u8; 8] = b"seamK001";

/// The first row of each of `ranks` ranks, then n (in dofs, whole points):
/// contiguous blocks of the bodies' points balanced by 1 + the cells
/// around each point.
pub(crate) fn row_ranges(bodies: &[Body], ranks: usize) -> Vec<usize> {
    let mut weight = Vec::new();
    for body in bodies {
        let base = weight.len();
        weight.resize(base + body.mesh.points().len(), 1usize);
        for cell in body.mesh.cells() {
            for &p in cell.nodes() {
                weight[base + p] += 1;
            }
        }
    }
    let total: usize = weight.iter().sum();
    let mut ranges = vec![0; ranks + 1];
    let (mut sum, mut point) = (0, 0);
    for (r, range) in ranges.iter_mut().enumerate().skip(1) {
        let target = (total as u128 * r as u128 / ranks as u128) as usize;
        while point < weight.len() && sum < target {
            sum += weight[point];
            point += 1;
        }
        *range = 3 * point;
    }
    ranges[ranks] = 3 * weight.len();
    ranges
}

/// The jobs of the ranks: rank r's cells with what assembling them needs
/// (module doc), in the byte layout that [`cell_part`] reads.
pub(crate) fn cell_jobs(bodies: &[Body], ranges: &[usize]) -> Vec<Vec<u8>> {
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
                put(job, (firsts[b] + 3 * p) as u64);
            }
            put(job, cells.len() as u64);
            for &c in &cells {
                let nodes = mesh.cells()[c].nodes();
                put(job, c as u64);
                job.push(nodes.len() as u8);
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

/// One body's cells of a rank: its sub-mesh, its material, the first dof
/// of each of its points, and each cell's index in the body.
struct BodyPart {
    body: usize,
    mesh: VolumeMesh,
    material: Material,
    dofs: Vec<usize>,
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
        let n_points = reader.count(32)?;
        let (mut points, mut dofs) = (Vec::with_capacity(n_points), Vec::with_capacity(n_points));
        for _ in 0..n_points {
            points.push([reader.f64()?, reader.f64()?, reader.f64()?]);
            dofs.push(reader.u64()? as usize);
        }
        let n_cells = reader.count(13)?;
        let (mut cells, mut index) = (Vec::with_capacity(n_cells), Vec::with_capacity(n_cells));
        for _ in 0..n_cells {
            index.push(reader.u64()? as usize);
            let len = reader.byte()? as usize;
            let nodes = (0..len).map(|_| reader.u32().map(|p| p as usize)).collect::<Option<Vec<_>>>()?;
            let kind = kind_with(len)?;
            cells.push(kind.cell(&nodes)?);
        }
        let mesh = VolumeMesh::new(points, cells).ok()?;
        parts.push(BodyPart { body, mesh, material, dofs, cells: index });
    }
    reader.at.is_empty().then_some(parts)
}

/// The element kind of a cell of `nodes` points (every kind has its own
/// count).
fn kind_with(nodes: usize) -> Option<ElementKind> {
    ElementKind::FIRST_ORDER.into_iter().chain(ElementKind::SECOND_ORDER).find(|k| k.n_nodes() == nodes)
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

impl PartError {
    fn to_bytes(&self) -> Vec<u8> {
        match self {
            PartError::Degenerate(body, cell) => {
                let mut bytes = vec![1];
                put(&mut bytes, *body as u64);
                put(&mut bytes, *cell as u64);
                bytes
            }
            PartError::Other(line) => [&[2u8][..], line.as_bytes()].concat(),
        }
    }

    /// An answer's error (empty: none).
    fn from_bytes(bytes: &[u8], rank: usize) -> Option<ProblemError> {
        let mut reader = Reader { at: bytes.get(1..).unwrap_or_default() };
        match bytes.first() {
            None => None,
            Some(1) => match (reader.u64(), reader.u64()) {
                (Some(body), Some(cell)) => Some(ProblemError::Assembly {
                    body: body as usize,
                    source: AssemblyError::DegenerateCell { cell: cell as usize },
                }),
                _ => Some(other(rank, "an unreadable answer")),
            },
            Some(_) => Some(other(rank, &String::from_utf8_lossy(reader.at))),
        }
    }
}

fn other(rank: usize, what: &str) -> ProblemError {
    ProblemError::Solve(crate::solve::SolveError::Petsc(format!(
        "MPI rank {rank} could not assemble its cells: {what}"
    )))
}

/// Assembles a job's cells and stages their entries of K for PETSc
/// (`seam_petsc::stage`).
#[cfg(feature = "petsc")]
fn assemble_part(bytes: &[u8]) -> Result<(), PartError> {
    let parts = cell_part(bytes).ok_or_else(|| PartError::Other("its job's bytes do not read".into()))?;
    let mut blocks = Vec::with_capacity(parts.len());
    for part in &parts {
        let k = crate::stiffness(&part.mesh, &part.material).map_err(
            |AssemblyError::DegenerateCell { cell }| PartError::Degenerate(part.body, part.cells[cell]),
        )?;
        blocks.push(k);
    }
    let count = blocks.iter().map(seam::CsrMatrix::nnz).sum();
    seam_petsc::stage(count, |rows, cols, values| {
        let mut at = 0;
        for (part, k) in parts.iter().zip(&blocks) {
            let dof = |local: usize| (part.dofs[local / 3] + local % 3) as seam_petsc::Index;
            for r in 0..k.nrows {
                let (cs, vs) = k.row(r);
                for (&c, &v) in cs.iter().zip(vs) {
                    (rows[at], cols[at], values[at]) = (dof(r), dof(c), v);
                    at += 1;
                }
            }
        }
    })
    .map_err(|e| PartError::Other(e.0))
}

/// A rank other than 0: does the job that [`crate::petsc::follow_petsc`]
/// returned (assembles its cells' K and stages it for PETSc) and answers
/// rank 0. Then follow again.
#[cfg(feature = "petsc")]
pub fn answer(job: &[u8]) {
    let reply = match assemble_part(job) {
        Ok(()) => Vec::new(),
        Err(e) => e.to_bytes(),
    };
    seam_petsc::reply(&reply);
}

/// Rank 0: hands every rank its cells ([`cell_jobs`]), assembles its own
/// and stages them, and collects the others' answers. `ranges` as
/// [`row_ranges`].
///
/// # Errors
/// The first rank's failure, in rank order: a degenerate cell as one
/// process reports it.
#[cfg(feature = "petsc")]
pub(crate) fn assemble_over_ranks(bodies: &[Body], ranges: &[usize]) -> Result<(), ProblemError> {
    let mut jobs = cell_jobs(bodies, ranges);
    let own = jobs.remove(0);
    seam_petsc::send_jobs(&jobs);
    drop(jobs);
    let mut first = assemble_part(&own)
        .err()
        .map(|e| PartError::from_bytes(&e.to_bytes(), 0).unwrap_or_else(|| other(0, "an unknown failure")));
    for r in 1..ranges.len() - 1 {
        let answer = seam_petsc::receive_reply(r);
        if first.is_none() {
            first = PartError::from_bytes(&answer, r);
        }
    }
    first.map_or(Ok(()), Err)
}

/// The cells' entries of K, point by point: (dof of the row, of the column,
/// value) of every cell of `bodies` in `jobs` read back — what the ranks
/// stage, for tests.
#[cfg(test)]
fn staged_entries(jobs: &[Vec<u8>]) -> Vec<(usize, usize, f64)> {
    let mut all = Vec::new();
    for job in jobs {
        for part in cell_part(job).expect("a job reads back") {
            let k = crate::stiffness(&part.mesh, &part.material).unwrap();
            let dof = |local: usize| part.dofs[local / 3] + local % 3;
            for r in 0..k.nrows {
                let (cs, vs) = k.row(r);
                all.extend(cs.iter().zip(vs).map(|(&c, &v)| (dof(r), dof(c), v)));
            }
        }
    }
    all
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{block, BlockKind};
    use crate::solve::Dirichlet;

    /// Two bodies cut into 1…5 ranks' cells: the rows are balanced whole
    /// points, every cell goes to one rank, and the ranks' entries summed are
    /// diag(K_1, K_2) to round-off.
    #[test]
    fn the_ranks_cells_sum_to_the_bodies_stiffness() {
        let material = Material::new(1000.0, 0.3).unwrap();
        let a = block(3, 2, 2, |u, v, w| [u, v, w], BlockKind::Hex);
        let b = block(2, 2, 3, |u, v, w| [u + 1.0, v, 0.7 * w], BlockKind::Tet);
        let body = |mesh| Body { mesh, material, load: vec![], dirichlet: Dirichlet::new() };
        let bodies = [body(&a), body(&b)];
        let k = crate::multibody::bodies_stiffness(&bodies).unwrap();
        for ranks in 1..=5 {
            let ranges = row_ranges(&bodies, ranks);
            assert_eq!((ranges[0], ranges[ranks]), (0, k.nrows));
            assert!(ranges.windows(2).all(|r| r[0] <= r[1] && r[0] % 3 == 0), "{ranges:?}");
            let jobs = cell_jobs(&bodies, &ranges);
            let cells: usize =
                jobs.iter().flat_map(|j| cell_part(j).unwrap()).map(|p| p.mesh.cells().len()).sum();
            assert_eq!(cells, a.cells().len() + b.cells().len());
            let mut sum = vec![vec![0.0; k.nrows]; k.nrows];
            for (i, j, v) in staged_entries(&jobs) {
                sum[i][j] += v;
            }
            let scale = k.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (i, row) in sum.iter().enumerate() {
                for (j, &v) in row.iter().enumerate() {
                    assert!((v - k.get(i, j)).abs() <= 1e-13 * scale, "{ranks} ranks, ({i}, {j})");
                }
            }
        }
        // Bytes that do not read are refused, not a panic.
        let job = &cell_jobs(&bodies, &row_ranges(&bodies, 2))[1];
        for cut in [0, 8, 16, job.len() / 2, job.len() - 1] {
            assert!(cell_part(&job[..cut]).is_none(), "cut at {cut}");
        }
    }
}

/// Without the feature no process leads other ranks: never called.
#[cfg(not(feature = "petsc"))]
pub(crate) fn assemble_over_ranks(_: &[Body], _: &[usize]) -> Result<(), ProblemError> {
    Err(ProblemError::Solve(crate::solve::SolveError::PetscUnavailable))
}
