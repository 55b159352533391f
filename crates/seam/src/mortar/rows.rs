//! From per-face blocks to CSR rows.
//!
//! Each slave face e leaves a dense block: its n_s × |cols_e| part of B (the
//! master points it touched) and its n_s × n_s part of D. Row p of the global
//! matrices is the sum over the faces around p, taken in increasing face order,
//! of the block rows for p — so the result does not depend on how faces were
//! spread over threads (I7).

use super::isoparametric::MAX_NODES;
use super::multiplier::{transformation_row, transformation_weight, FaceMeasures};
use super::BasisTransformation;
use super::{FaceStats, Mortar, MortarSummary, Multiplier, Segment, COVERED_FRACTION};

use crate::mesh::SurfaceMesh;
use crate::sparse::CsrMatrix;
use crate::wire::{Reader, WireError, Writer};
use rayon::prelude::*;
use std::borrow::Cow;

/// Per-face blocks of a range of slave faces, in face order, each stored
/// with its own node count n_s (3 to 9).
#[derive(Clone, Default)]
pub(super) struct Blocks {
    /// `col_ptr[f]..col_ptr[f + 1]` indexes face f's columns in `cols`.
    col_ptr: Vec<usize>,
    /// Master point indices (u32: half the memory; checked in `assemble_with_tree`).
    cols: Vec<u32>,
    /// Column-major n_s-row blocks: `b[b_ptr[f] + j * n_s + p]` for column j of face f.
    b: Vec<f64>,
    b_ptr: Vec<usize>,
    /// Row-major n_s × n_s blocks of D, from `node_ptr[f]²`-free offsets `d_ptr[f]`.
    d: Vec<f64>,
    d_ptr: Vec<usize>,
    /// Per local node: the covered and full measures of the face
    /// (`multiplier::FaceMeasures`), from `node_ptr[f]`.
    covered: Vec<f64>,
    full: Vec<f64>,
    node_ptr: Vec<usize>,
    pub(super) faces: Vec<FaceStats>,
    /// Intersection triangles, when recorded.
    pub(super) segments: Vec<Segment>,
}

impl Blocks {
    pub(super) fn with_capacity(faces: usize) -> Blocks {
        let mut b = Blocks {
            col_ptr: Vec::with_capacity(faces + 1),
            cols: Vec::with_capacity(faces * 12),
            b: Vec::with_capacity(faces * 48),
            b_ptr: Vec::with_capacity(faces + 1),
            d: Vec::with_capacity(faces * 16),
            d_ptr: Vec::with_capacity(faces + 1),
            covered: Vec::with_capacity(faces * 4),
            full: Vec::with_capacity(faces * 4),
            node_ptr: Vec::with_capacity(faces + 1),
            faces: Vec::with_capacity(faces),
            segments: Vec::new(),
        };
        b.col_ptr.push(0);
        b.b_ptr.push(0);
        b.d_ptr.push(0);
        b.node_ptr.push(0);
        b
    }

    /// Appends a face's blocks: `b` column-major with `n_s` rows, `d` row-major
    /// with stride [`MAX_NODES`].
    pub(super) fn push(
        &mut self,
        cols: &[usize],
        b: &[f64],
        d: &[f64; MAX_NODES * MAX_NODES],
        n_s: usize,
        measures: &FaceMeasures,
        stats: FaceStats,
    ) {
        self.cols.extend(cols.iter().map(|&c| c as u32));
        self.b.extend_from_slice(b);
        self.col_ptr.push(self.cols.len());
        self.b_ptr.push(self.b.len());
        for p in 0..n_s {
            self.d.extend_from_slice(&d[p * MAX_NODES..p * MAX_NODES + n_s]);
        }
        self.d_ptr.push(self.d.len());
        self.covered.extend_from_slice(&measures.covered[..n_s]);
        self.full.extend_from_slice(&measures.full[..n_s]);
        self.node_ptr.push(self.full.len());
        self.faces.push(stats);
    }

    /// Number of faces held.
    pub(super) fn len(&self) -> usize {
        self.faces.len()
    }

    /// Whether every column is below `n`.
    pub(super) fn columns_below(&self, n: usize) -> bool {
        self.cols.iter().all(|&c| (c as usize) < n)
    }

    /// Renumbers the columns (master points) by `global` and the segments'
    /// faces by `slave_faces` and `master_faces` (a part's local numbering to
    /// the whole surfaces').
    pub(super) fn renumber(&mut self, global: &[usize], slave_faces: &[usize], master_faces: &[usize]) {
        for c in &mut self.cols {
            *c = global[*c as usize] as u32;
        }
        for s in &mut self.segments {
            (s.slave, s.master) = (slave_faces[s.slave], master_faces[s.master]);
        }
    }

    /// Appends the blocks to `w` ([`crate::wire`]).
    pub(super) fn encode(&self, w: &mut Writer) {
        w.usizes(&self.col_ptr);
        w.u32s(&self.cols);
        w.f64s(&self.b);
        w.usizes(&self.b_ptr);
        w.f64s(&self.d);
        w.usizes(&self.d_ptr);
        w.f64s(&self.covered);
        w.f64s(&self.full);
        w.usizes(&self.node_ptr);
        w.usize(self.faces.len());
        for f in &self.faces {
            for v in [f.area, f.covered_area, f.max_gap, f.max_overlap] {
                w.f64(v);
            }
            let counts = [f.candidates, f.rejected_angle, f.rejected_gap, f.empty, f.intersecting];
            for v in counts.into_iter().chain([f.segments, f.inverse_failures, f.dual_fallbacks]) {
                w.u64(u64::from(v));
            }
        }
        w.usize(self.segments.len());
        for s in &self.segments {
            w.usize(s.slave);
            w.usize(s.master);
            s.corners.iter().flatten().for_each(|&x| w.f64(x));
        }
    }

    /// Reads what [`Blocks::encode`] wrote, checking that the offsets are
    /// consistent with the arrays.
    pub(super) fn decode(r: &mut Reader) -> Result<Blocks, WireError> {
        let mut b = Blocks {
            col_ptr: r.usizes()?,
            cols: r.u32s()?,
            b: r.f64s()?,
            b_ptr: r.usizes()?,
            d: r.f64s()?,
            d_ptr: r.usizes()?,
            covered: r.f64s()?,
            full: r.f64s()?,
            node_ptr: r.usizes()?,
            ..Blocks::default()
        };
        let n = r.usize()?;
        for _ in 0..n.min(r.0.len() / 96) {
            let [area, covered_area, max_gap, max_overlap] = [r.f64()?, r.f64()?, r.f64()?, r.f64()?];
            let mut count = || r.u64().and_then(|v| u32::try_from(v).map_err(|_| WireError));
            b.faces.push(FaceStats {
                area,
                covered_area,
                max_gap,
                max_overlap,
                candidates: count()?,
                rejected_angle: count()?,
                rejected_gap: count()?,
                empty: count()?,
                intersecting: count()?,
                segments: count()?,
                inverse_failures: count()?,
                dual_fallbacks: count()?,
            });
        }
        let segments = r.usize()?;
        for _ in 0..segments.min(r.0.len() / 88) {
            let (slave, master) = (r.usize()?, r.usize()?);
            let mut corners = [[0.0; 3]; 3];
            for x in corners.iter_mut().flatten() {
                *x = r.f64()?;
            }
            b.segments.push(Segment { slave, master, corners });
        }
        let consistent = |ptr: &[usize], len: usize| {
            ptr.len() == n + 1 && ptr[0] == 0 && ptr[n] == len && ptr.windows(2).all(|w| w[0] <= w[1])
        };
        let ok = b.faces.len() == n
            && b.segments.len() == segments
            && consistent(&b.col_ptr, b.cols.len())
            && consistent(&b.b_ptr, b.b.len())
            && consistent(&b.d_ptr, b.d.len())
            && consistent(&b.node_ptr, b.full.len())
            && b.covered.len() == b.full.len()
            && (0..n).all(|f| {
                let n_s = b.node_ptr[f + 1] - b.node_ptr[f];
                (1..=MAX_NODES).contains(&n_s)
                    && b.d_ptr[f + 1] - b.d_ptr[f] == n_s * n_s
                    && b.b_ptr[f + 1] - b.b_ptr[f] == n_s * (b.col_ptr[f + 1] - b.col_ptr[f])
            });
        match ok {
            true => Ok(b),
            false => Err(WireError),
        }
    }

    fn n_s(&self, f: usize) -> usize {
        self.node_ptr[f + 1] - self.node_ptr[f]
    }

    /// Row `l` of face f's B block as (master point, value) pairs.
    fn b_row(&self, f: usize, l: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let n_s = self.n_s(f);
        let cols = &self.cols[self.col_ptr[f]..self.col_ptr[f + 1]];
        let b = &self.b[self.b_ptr[f]..self.b_ptr[f + 1]];
        cols.iter().zip(b.chunks_exact(n_s)).map(move |(&c, column)| (c as usize, column[l]))
    }

    /// Row `l` of face f's D block.
    fn d_row(&self, f: usize, l: usize) -> &[f64] {
        let n_s = self.n_s(f);
        &self.d[self.d_ptr[f] + l * n_s..self.d_ptr[f] + (l + 1) * n_s]
    }
}

/// The blocks of all slave faces, as the chunks that computed them: face f
/// is entry f % chunk of chunk f / chunk, or, for blocks gathered from parts
/// ([`super::parts`]) or partly kept from an earlier assembly
/// ([`super::reassemble`]), the (chunk, entry) of `index[f]`; no copy into one
/// array.
pub(super) struct ChunkedBlocks<'a> {
    pub(super) chunks: Vec<Cow<'a, Blocks>>,
    pub(super) chunk: usize,
    pub(super) index: Option<Vec<(u32, u32)>>,
}

impl ChunkedBlocks<'_> {
    /// The chunks of [`CHUNK`](super::CHUNK) faces of a whole assembly.
    pub(super) fn owned(chunks: Vec<Blocks>) -> ChunkedBlocks<'static> {
        ChunkedBlocks {
            chunks: chunks.into_iter().map(Cow::Owned).collect(),
            chunk: super::CHUNK,
            index: None,
        }
    }

    fn at(&self, f: usize) -> (&Blocks, usize) {
        match &self.index {
            Some(index) => (&self.chunks[index[f].0 as usize], index[f].1 as usize),
            None => (&self.chunks[f / self.chunk], f % self.chunk),
        }
    }

    /// The number of faces (chunks kept from an earlier assembly may hold
    /// more blocks than `index` uses).
    fn len(&self) -> usize {
        match &self.index {
            Some(index) => index.len(),
            None => self.chunks.iter().map(|c| c.len()).sum(),
        }
    }

    /// Per-face statistics, in face order.
    pub(super) fn stats(&self) -> impl Iterator<Item = &FaceStats> {
        (0..self.len()).map(|f| {
            let (c, k) = self.at(f);
            &c.faces[k]
        })
    }
}

/// For every point, the (face, local corner) pairs around it, faces ascending.
struct PointFaces {
    ptr: Vec<usize>,
    entries: Vec<(usize, usize)>,
}

impl PointFaces {
    fn new(mesh: &SurfaceMesh) -> PointFaces {
        let mut ptr = vec![0usize; mesh.n_points() + 1];
        for face in mesh.faces() {
            for &n in face.nodes() {
                ptr[n + 1] += 1;
            }
        }
        for i in 0..mesh.n_points() {
            ptr[i + 1] += ptr[i];
        }
        let mut next = ptr.clone();
        let mut entries = vec![(0, 0); ptr[mesh.n_points()]];
        for (f, face) in mesh.faces().iter().enumerate() {
            for (l, &n) in face.nodes().iter().enumerate() {
                entries[next[n]] = (f, l);
                next[n] += 1;
            }
        }
        PointFaces { ptr, entries }
    }

    fn around(&self, p: usize) -> &[(usize, usize)] {
        &self.entries[self.ptr[p]..self.ptr[p + 1]]
    }
}

/// Sums the face blocks into B and D and measures the coverage of each point.
pub(super) fn into_mortar(
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    mut blocks: ChunkedBlocks,
    (multiplier, transformation): (Multiplier, BasisTransformation),
    mut summary: MortarSummary,
) -> Mortar {
    let around = PointFaces::new(slave);
    let n = slave.n_points();
    let b = sum_rows(n, master.n_points(), &around, |f, l, row| {
        let (c, k) = blocks.at(f);
        row.add(c.b_row(k, l));
    });
    // The B blocks are done with: free them before D is built (peak memory).
    for c in blocks.chunks.iter_mut().filter_map(|c| match c {
        Cow::Owned(c) => Some(c),
        Cow::Borrowed(_) => None,
    }) {
        c.cols = Vec::new();
        c.b = Vec::new();
        c.col_ptr = Vec::new();
        c.b_ptr = Vec::new();
    }
    let d = sum_rows(n, n, &around, |f, l, row| {
        let (c, k) = blocks.at(f);
        row.add(slave.faces()[f].nodes().iter().copied().zip(c.d_row(k, l).iter().copied()));
    });
    let node_coverage = node_coverage(slave, &blocks);
    let on_surface = slave.used_points();
    let mut covered: Vec<bool> = node_coverage.iter().map(|&c| c > COVERED_FRACTION).collect();
    let basis = transformation_weight(slave, transformation)
        .filter(|_| multiplier == Multiplier::Dual)
        .map(|alpha| basis_transformation(slave, alpha));
    if let Some(q) = &basis {
        // T = Qᵀ D⁻¹ B mixes the rows of the λ̃ around a node: it is covered
        // only when all of them are.
        let qt = q.transpose();
        covered = (0..n).map(|r| covered[r] && qt.row(r).0.iter().all(|&p| covered[p])).collect();
    }
    summary.uncovered_slave_nodes = (0..n).filter(|&p| on_surface[p] && !covered[p]).count();
    let faces = blocks.stats().copied().collect();
    // Each face's segments from the chunk that holds its block (kept chunks
    // of a reassembly also hold the replaced faces').
    let index = blocks.index.take();
    let mut segments: Vec<Segment> = blocks
        .chunks
        .iter_mut()
        .enumerate()
        .flat_map(|(k, c)| {
            let segments = match c {
                Cow::Owned(c) => std::mem::take(&mut c.segments),
                Cow::Borrowed(c) => c.segments.clone(),
            };
            let index = index.as_deref();
            segments.into_iter().filter(move |s| index.is_none_or(|i| i[s.slave].0 as usize == k))
        })
        .collect();
    if index.is_some() {
        segments.sort_by_key(|s| s.slave); // stable: each face's own order
    }
    Mortar { b, d, multiplier, basis, faces, node_coverage, covered, on_surface, segments, summary }
}

/// Per point: the covered over the full measure of the faces around it (0 when
/// the full measure is), each summed in increasing face order like the rows.
/// One pass over the faces, scattering into the points.
fn node_coverage(slave: &SurfaceMesh, blocks: &ChunkedBlocks) -> Vec<f64> {
    let n = slave.n_points();
    let (mut covered, mut full) = (vec![0.0; n], vec![0.0; n]);
    for (f, face) in slave.faces().iter().enumerate() {
        let (c, k) = blocks.at(f);
        let r = c.node_ptr[k]..c.node_ptr[k + 1];
        for ((&p, &a), &b) in face.nodes().iter().zip(&c.covered[r.clone()]).zip(&c.full[r]) {
            covered[p] += a;
            full[p] += b;
        }
    }
    covered.iter().zip(&full).map(|(&c, &f)| if f > 0.0 { c / f } else { 0.0 }).collect()
}

/// The global basis transformation λ̃ = Q λ of weight `alpha` of a surface's
/// second-order faces (`multiplier::BASIS_ALPHA`): rows are the transformed
/// functions, the union of the faces' Q_e (which agree on shared nodes).
pub(super) fn basis_transformation(slave: &SurfaceMesh, alpha: f64) -> CsrMatrix {
    let n = slave.n_points();
    let mut entries: Vec<(usize, usize, f64)> = Vec::new();
    for face in slave.faces() {
        let kind = face.kind();
        let nodes = face.nodes();
        for p in 0..nodes.len() {
            entries.extend(transformation_row(kind, Some(alpha), p).map(|(c, v)| (nodes[p], nodes[c], v)));
        }
    }
    entries.sort_by_key(|e| (e.0, e.1));
    entries.dedup_by(|a, b| a.0 == b.0 && a.1 == b.1);
    let used = slave.used_points();
    let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for (r, c, v) in entries {
        rows[r].push((c, v));
    }
    for (p, row) in rows.iter_mut().enumerate() {
        if !used[p] {
            row.push((p, 1.0));
        }
    }
    let split: Vec<(Vec<usize>, Vec<f64>)> = rows.into_iter().map(|r| r.into_iter().unzip()).collect();
    CsrMatrix::from_rows(n, split.iter().map(|(c, v)| (c.as_slice(), v.as_slice())))
}

/// Builds an nrows × ncols CSR matrix whose row p collects, for each face around
/// p in order, the (column, value) entries `entries(face, local)` adds;
/// duplicates are summed in that order and exact zeros dropped.
fn sum_rows(
    nrows: usize,
    ncols: usize,
    around: &PointFaces,
    entries: impl Fn(usize, usize, &mut RowSum) + Sync,
) -> CsrMatrix {
    const CHUNK: usize = 4096;
    assert!(ncols <= u32::MAX as usize, "{ncols} columns: at most {} are supported", u32::MAX);
    let parts: Vec<(Vec<usize>, Vec<u32>, Vec<f64>)> = (0..nrows.div_ceil(CHUNK))
        .into_par_iter()
        .map_init(
            || RowSum::new(ncols),
            |sum, c| {
                let rows = c * CHUNK..((c + 1) * CHUNK).min(nrows);
                sum.begin(rows.len());
                for p in rows {
                    for &(f, l) in around.around(p) {
                        entries(f, l, sum);
                    }
                    sum.end_row();
                }
                sum.take()
            },
        )
        .collect();
    // Exact sizes up front; the parts are copied into disjoint slices in parallel
    // (zeroed allocations are mapped lazily, so the pages are first touched there).
    let nnz: usize = parts.iter().map(|(_, cols, _)| cols.len()).sum();
    let mut indptr = Vec::with_capacity(nrows + 1);
    indptr.push(0);
    for (lens, _, _) in &parts {
        for &len in lens {
            indptr.push(indptr[indptr.len() - 1] + len);
        }
    }
    let mut indices = vec![0usize; nnz];
    let mut values = vec![0.0f64; nnz];
    let mut targets = Vec::with_capacity(parts.len());
    let (mut rest_i, mut rest_v) = (indices.as_mut_slice(), values.as_mut_slice());
    for (_, cols, _) in &parts {
        let (head_i, tail_i) = rest_i.split_at_mut(cols.len());
        let (head_v, tail_v) = rest_v.split_at_mut(cols.len());
        targets.push((head_i, head_v));
        (rest_i, rest_v) = (tail_i, tail_v);
    }
    targets.into_par_iter().zip(parts.par_iter()).for_each(|((ti, tv), (_, cols, vals))| {
        for (t, &c) in ti.iter_mut().zip(cols) {
            *t = c as usize;
        }
        tv.copy_from_slice(vals);
    });
    CsrMatrix { nrows, ncols, indptr, indices, values }
}

/// Sums the rows of a chunk of consecutive rows, one at a time. A dense
/// marker over all columns (4 bytes a column, one per worker) gives each
/// column its slot in the current row, so a duplicate is added on the spot,
/// in the order the entries come (face order: the same sums as a stable sort
/// by column and a left-to-right merge), and only the row's unique columns
/// are sorted: O(entries + unique · log unique) per row, however many columns
/// the row has.
struct RowSum {
    /// Per column: its slot in `row`, or [`RowSum::NONE`]. Every row leaves it clear.
    slot: Vec<u32>,
    /// The current row's sums, by slot.
    row: Vec<f64>,
    /// The finished rows' lengths, columns and values; the current row's
    /// columns follow in `cols` (u32: half the memory and copying).
    lens: Vec<usize>,
    cols: Vec<u32>,
    vals: Vec<f64>,
}

impl RowSum {
    const NONE: u32 = u32::MAX;

    fn new(ncols: usize) -> RowSum {
        let slot = vec![RowSum::NONE; ncols];
        RowSum { slot, row: Vec::new(), lens: Vec::new(), cols: Vec::new(), vals: Vec::new() }
    }

    /// Starts a chunk of `rows` rows.
    fn begin(&mut self, rows: usize) {
        let guess = 16 * rows;
        self.lens = Vec::with_capacity(rows);
        self.cols = Vec::with_capacity(guess);
        self.vals = Vec::with_capacity(guess);
    }

    /// Adds (column, value) entries to the current row.
    #[inline]
    fn add(&mut self, entries: impl Iterator<Item = (usize, f64)>) {
        let RowSum { slot, row, cols, .. } = self;
        for (c, v) in entries {
            let k = &mut slot[c];
            if *k == RowSum::NONE {
                *k = row.len() as u32;
                row.push(v);
                cols.push(c as u32);
            } else {
                row[*k as usize] += v;
            }
        }
    }

    /// Ends the current row: sorts its columns and drops exact zeros (e.g.
    /// off-diagonal entries of a dual D).
    fn end_row(&mut self) {
        let RowSum { slot, row, lens, cols, vals } = self;
        let start = vals.len(); // finished rows have as many values as columns
        cols[start..].sort_unstable(); // unique columns: stability is moot
        vals.extend(
            cols[start..]
                .iter()
                .map(|&c| row[std::mem::replace(&mut slot[c as usize], RowSum::NONE) as usize]),
        );
        row.clear();
        if vals[start..].contains(&0.0) {
            let mut keep = start;
            for k in start..vals.len() {
                if vals[k] != 0.0 {
                    (cols[keep], vals[keep]) = (cols[k], vals[k]);
                    keep += 1;
                }
            }
            cols.truncate(keep);
            vals.truncate(keep);
        }
        lens.push(vals.len() - start);
    }

    /// The chunk's rows: lengths, columns, values.
    fn take(&mut self) -> (Vec<usize>, Vec<u32>, Vec<f64>) {
        (std::mem::take(&mut self.lens), std::mem::take(&mut self.cols), std::mem::take(&mut self.vals))
    }
}
