//! From per-face blocks to CSR rows.
//!
//! Each slave face e leaves a dense block: its n_s × |cols_e| part of B (the
//! master points it touched) and its n_s × n_s part of D. Row p of the global
//! matrices is the sum over the faces around p, taken in increasing face order,
//! of the block rows for p — so the result does not depend on how faces were
//! spread over threads (I7).

use super::{FaceStats, Mortar, MortarSummary, Multiplier, Segment, COVERED_FRACTION};
use crate::mesh::SurfaceMesh;
use crate::sparse::CsrMatrix;
use rayon::prelude::*;

/// Per-face blocks of a range of slave faces, in face order.
#[derive(Default)]
pub(super) struct Blocks {
    /// `col_ptr[f]..col_ptr[f + 1]` indexes face f's columns in `cols`.
    col_ptr: Vec<usize>,
    /// Master point indices (u32: half the memory; checked in `assemble_with_tree`).
    cols: Vec<u32>,
    /// Column-major 4-row blocks: `b[j * 4 + p]` for column j of `cols`.
    b: Vec<f64>,
    /// Row-major 4×4 blocks of D.
    d: Vec<[f64; 16]>,
    /// ∫_e λ_p |J| over the whole face.
    full: Vec<[f64; 4]>,
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
            d: Vec::with_capacity(faces),
            full: Vec::with_capacity(faces),
            faces: Vec::with_capacity(faces),
            segments: Vec::new(),
        };
        b.col_ptr.push(0);
        b
    }

    pub(super) fn push(&mut self, cols: &[usize], b: &[f64], d: [f64; 16], full: [f64; 4], stats: FaceStats) {
        self.cols.extend(cols.iter().map(|&c| c as u32));
        self.b.extend_from_slice(b);
        self.col_ptr.push(self.cols.len());
        self.d.push(d);
        self.full.push(full);
        self.faces.push(stats);
    }

    fn cols(&self, f: usize) -> std::ops::Range<usize> {
        self.col_ptr[f]..self.col_ptr[f + 1]
    }
}

/// The blocks of all slave faces, as the chunks that computed them (face f is
/// entry f % chunk of chunk f / chunk): no copy into one array.
pub(super) struct ChunkedBlocks {
    pub(super) chunks: Vec<Blocks>,
    pub(super) chunk: usize,
}

impl ChunkedBlocks {
    fn at(&self, f: usize) -> (&Blocks, usize) {
        (&self.chunks[f / self.chunk], f % self.chunk)
    }

    /// Per-face statistics, in face order.
    pub(super) fn stats(&self) -> impl Iterator<Item = &FaceStats> {
        self.chunks.iter().flat_map(|c| c.faces.iter())
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
    multiplier: Multiplier,
    mut summary: MortarSummary,
) -> Mortar {
    let around = PointFaces::new(slave);
    let n = slave.n_points();
    let b = sum_rows(n, master.n_points(), &around, |f, l, out| {
        let (c, k) = blocks.at(f);
        for j in c.cols(k) {
            out.push((c.cols[j] as usize, c.b[j * 4 + l]));
        }
    });
    // The B blocks are done with: free them before D is built (peak memory).
    for c in &mut blocks.chunks {
        c.cols = Vec::new();
        c.b = Vec::new();
        c.col_ptr = Vec::new();
    }
    let d = sum_rows(n, n, &around, |f, l, out| {
        let (c, k) = blocks.at(f);
        for (q, &node) in slave.faces()[f].nodes().iter().enumerate() {
            out.push((node, c.d[k][l * 4 + q]));
        }
    });
    let node_coverage: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|p| {
            let (mut covered, mut full) = (0.0, 0.0);
            for &(f, l) in around.around(p) {
                let (c, k) = blocks.at(f);
                // Row sums of a face's D block are ∫_{e,cov} λ_l for every multiplier.
                covered += c.d[k][l * 4..l * 4 + 4].iter().sum::<f64>();
                full += c.full[k][l];
            }
            if full > 0.0 {
                covered / full
            } else {
                0.0
            }
        })
        .collect();
    let on_surface = slave.used_points();
    let covered: Vec<bool> = node_coverage.iter().map(|&c| c > COVERED_FRACTION).collect();
    summary.uncovered_slave_nodes = (0..n).filter(|&p| on_surface[p] && !covered[p]).count();
    let faces = blocks.chunks.iter_mut().flat_map(|c| std::mem::take(&mut c.faces)).collect();
    let segments = blocks.chunks.iter_mut().flat_map(|c| std::mem::take(&mut c.segments)).collect();
    Mortar { b, d, multiplier, faces, node_coverage, covered, on_surface, segments, summary }
}

/// Builds an nrows × ncols CSR matrix whose row p collects, for each face around
/// p in order, the (column, value) entries `entries(face, local)` pushes;
/// duplicates are summed in that order and exact zeros dropped.
fn sum_rows(
    nrows: usize,
    ncols: usize,
    around: &PointFaces,
    entries: impl Fn(usize, usize, &mut Vec<(usize, f64)>) + Sync,
) -> CsrMatrix {
    const CHUNK: usize = 4096;
    let parts: Vec<(Vec<usize>, Vec<usize>, Vec<f64>)> = (0..nrows.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let rows = c * CHUNK..((c + 1) * CHUNK).min(nrows);
            let mut lens = Vec::with_capacity(rows.len());
            let guess = 16 * rows.len();
            let (mut cols, mut vals) = (Vec::with_capacity(guess), Vec::with_capacity(guess));
            let mut buf: Vec<(usize, f64)> = Vec::new();
            for p in rows {
                buf.clear();
                for &(f, l) in around.around(p) {
                    entries(f, l, &mut buf);
                }
                sort_by_column(&mut buf); // stable: equal columns keep face order
                let start = cols.len();
                for &(j, v) in &buf {
                    if cols.len() > start && cols[cols.len() - 1] == j {
                        *vals.last_mut().unwrap() += v;
                    } else {
                        cols.push(j);
                        vals.push(v);
                    }
                }
                // Drop exact zeros (e.g. off-diagonal entries of a dual D).
                let mut keep = start;
                for k in start..cols.len() {
                    if vals[k] != 0.0 {
                        cols[keep] = cols[k];
                        vals[keep] = vals[k];
                        keep += 1;
                    }
                }
                cols.truncate(keep);
                vals.truncate(keep);
                lens.push(keep - start);
            }
            (lens, cols, vals)
        })
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
        ti.copy_from_slice(cols);
        tv.copy_from_slice(vals);
    });
    CsrMatrix { nrows, ncols, indptr, indices, values }
}

/// Stable insertion sort by column: rows hold a few dozen entries, mostly in
/// runs already sorted, and this allocates nothing (unlike `sort_by_key`).
fn sort_by_column(v: &mut [(usize, f64)]) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j - 1].0 > v[j].0 {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}
