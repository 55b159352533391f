//! Fill-reducing orderings for the sparse Cholesky factorisation.
//!
//! An ordering is a permutation `perm` with `perm[new] = old`: the factorisation
//! eliminates vertex `perm[0]` first. Two methods, both on an undirected
//! [`Graph`] (the off-diagonal pattern of a symmetric matrix, or its quotient by
//! the 3 dofs of a point):
//!
//! - [`amd`]: approximate minimum degree (faer's implementation).
//! - [`nested_dissection`]: recursive vertex separators. A graph G = A ∪ S ∪ B
//!   with no edge between A and B is ordered as (order(A), order(B), S), so the
//!   factor has no fill between A and B; A and B are ordered recursively, down to
//!   pieces of at most [`ND_LEAF_SIZE`] vertices, which are ordered by AMD. The
//!   separators come from a multilevel edge bisection (heavy-edge matching,
//!   greedy graph growing on the coarsest graph, Fiduccia–Mattheyses refinement
//!   on every level), whose smaller boundary becomes the separator. For 3D
//!   meshes the factor then has O(n^{4/3}) entries and costs O(n²) flops, against
//!   the larger growth of minimum degree.
//!
//! Both are deterministic: the same graph gives the same permutation whatever
//! the number of threads (the recursion runs the two halves in parallel, but
//! each half's result depends only on its subgraph).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd as faer_amd;
use faer::sparse::SymbolicSparseColMatRef;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Nested dissection stops at pieces of at most this many vertices and orders
/// them by minimum degree.
pub const ND_LEAF_SIZE: usize = 128;

/// An undirected graph in compressed adjacency form: the neighbours of vertex v
/// are `targets[offsets[v]..offsets[v + 1]]`, sorted, without v itself, and the
/// relation is symmetric.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Graph {
    offsets: Vec<usize>,
    targets: Vec<usize>,
}

impl Graph {
    /// The graph of the off-diagonal pattern of a structurally symmetric matrix
    /// given by rows: `row(v)` lists the columns of row v (any order, duplicates
    /// and v itself allowed). The pattern is symmetrised (edge when either
    /// (v, w) or (w, v) is listed).
    ///
    /// # Panics
    /// If a column is ≥ n.
    pub fn from_rows<'a>(n: usize, row: impl Fn(usize) -> &'a [usize]) -> Graph {
        let mut degree = vec![0usize; n + 1];
        for v in 0..n {
            for &w in row(v) {
                assert!(w < n, "column {w} out of range for a graph of {n} vertices");
                if w != v {
                    degree[v] += 1;
                    degree[w] += 1;
                }
            }
        }
        let mut offsets = vec![0usize; n + 1];
        for v in 0..n {
            offsets[v + 1] = offsets[v] + degree[v];
        }
        let mut fill = offsets[..n].to_vec();
        let mut targets = vec![0usize; offsets[n]];
        for v in 0..n {
            for &w in row(v) {
                if w != v {
                    targets[fill[v]] = w;
                    fill[v] += 1;
                    targets[fill[w]] = v;
                    fill[w] += 1;
                }
            }
        }
        Graph::compact(n, offsets, targets)
    }

    /// Sorts and deduplicates every adjacency list.
    fn compact(n: usize, offsets: Vec<usize>, mut targets: Vec<usize>) -> Graph {
        let mut out_offsets = Vec::with_capacity(n + 1);
        out_offsets.push(0);
        let mut len = 0;
        for v in 0..n {
            let list = &mut targets[offsets[v]..offsets[v + 1]];
            list.sort_unstable();
            let mut last = usize::MAX;
            for i in offsets[v]..offsets[v + 1] {
                let w = targets[i];
                if w != last {
                    targets[len] = w;
                    len += 1;
                    last = w;
                }
            }
            out_offsets.push(len);
        }
        targets.truncate(len);
        targets.shrink_to_fit();
        Graph { offsets: out_offsets, targets }
    }

    /// The quotient graph by `group`: vertex v of `self` becomes vertex
    /// `group[v]` (< `n_groups`) of the result; groups are adjacent when two of
    /// their members are.
    ///
    /// # Panics
    /// If `group.len()` is not the number of vertices or a group is out of range.
    pub fn quotient(&self, group: &[usize], n_groups: usize) -> Graph {
        assert_eq!(group.len(), self.n_vertices(), "one group per vertex");
        let mut members = vec![Vec::new(); n_groups];
        for (v, &g) in group.iter().enumerate() {
            members[g].push(v);
        }
        let mut offsets = Vec::with_capacity(n_groups + 1);
        let mut targets = Vec::new();
        offsets.push(0);
        for (g, m) in members.iter().enumerate() {
            let start = targets.len();
            for &v in m {
                targets.extend(self.neighbours(v).iter().map(|&w| group[w]).filter(|&h| h != g));
            }
            let list = &mut targets[start..];
            list.sort_unstable();
            let mut len = start;
            let mut last = usize::MAX;
            for i in start..targets.len() {
                if targets[i] != last {
                    last = targets[i];
                    targets[len] = last;
                    len += 1;
                }
            }
            targets.truncate(len);
            offsets.push(len);
        }
        Graph { offsets, targets }
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Number of (undirected) edges.
    pub fn n_edges(&self) -> usize {
        self.targets.len() / 2
    }

    /// The neighbours of v, sorted.
    pub fn neighbours(&self, v: usize) -> &[usize] {
        &self.targets[self.offsets[v]..self.offsets[v + 1]]
    }
}

/// True when `perm` holds every index 0..perm.len() exactly once.
pub fn is_permutation(perm: &[usize]) -> bool {
    let mut seen = vec![false; perm.len()];
    for &p in perm {
        if p >= perm.len() || seen[p] {
            return false;
        }
        seen[p] = true;
    }
    true
}

/// The inverse permutation: `inverse(perm)[perm[i]] = i`.
pub fn inverse(perm: &[usize]) -> Vec<usize> {
    let mut inv = vec![0; perm.len()];
    for (i, &p) in perm.iter().enumerate() {
        inv[p] = i;
    }
    inv
}

/// Approximate minimum degree ordering of `graph` (`perm[new] = old`).
pub fn amd(graph: &Graph) -> Vec<usize> {
    let n = graph.n_vertices();
    if n <= 2 {
        return (0..n).collect();
    }
    let nnz = graph.targets.len();
    let pattern = SymbolicSparseColMatRef::new_checked(n, n, &graph.offsets, None, &graph.targets);
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let mut mem = MemBuffer::new(faer_amd::order_scratch::<usize>(n, nnz));
    // The graph is sorted and duplicate-free, as `order` requires; it fails only
    // on index overflow, impossible with usize indices of an existing graph.
    match faer_amd::order(
        &mut perm,
        &mut perm_inv,
        pattern,
        faer_amd::Control::default(),
        MemStack::new(&mut mem),
    ) {
        Ok(_) => perm,
        Err(_) => (0..n).collect(),
    }
}

/// Nested dissection ordering of `graph` (module doc; `perm[new] = old`).
pub fn nested_dissection(graph: &Graph) -> Vec<usize> {
    let n = graph.n_vertices();
    let g = WGraph::unit(graph);
    let ids: Vec<usize> = (0..n).collect();
    let mut out = Vec::with_capacity(n);
    dissect(g, ids, &mut out);
    out
}

/// A graph with vertex and edge weights (the coarse graphs of the multilevel
/// bisection).
#[derive(Clone, Debug)]
struct WGraph {
    xadj: Vec<usize>,
    adj: Vec<usize>,
    ewgt: Vec<i64>,
    vwgt: Vec<i64>,
}

impl WGraph {
    fn unit(g: &Graph) -> WGraph {
        WGraph {
            xadj: g.offsets.clone(),
            adj: g.targets.clone(),
            ewgt: vec![1; g.targets.len()],
            vwgt: vec![1; g.n_vertices()],
        }
    }

    fn n(&self) -> usize {
        self.vwgt.len()
    }

    fn range(&self, v: usize) -> std::ops::Range<usize> {
        self.xadj[v]..self.xadj[v + 1]
    }

    fn to_graph(&self) -> Graph {
        Graph { offsets: self.xadj.clone(), targets: self.adj.clone() }
    }

    /// The subgraph induced by the vertices with `part[v] == which`, and its
    /// vertices (old numbers, increasing).
    fn induced(&self, part: &[u8], which: u8) -> (WGraph, Vec<usize>) {
        let mut local = vec![usize::MAX; self.n()];
        let mut verts = Vec::new();
        for v in 0..self.n() {
            if part[v] == which {
                local[v] = verts.len();
                verts.push(v);
            }
        }
        let mut sub = WGraph {
            xadj: Vec::with_capacity(verts.len() + 1),
            adj: Vec::new(),
            ewgt: Vec::new(),
            vwgt: Vec::with_capacity(verts.len()),
        };
        sub.xadj.push(0);
        for &v in &verts {
            for e in self.range(v) {
                let w = self.adj[e];
                if local[w] != usize::MAX {
                    sub.adj.push(local[w]);
                    sub.ewgt.push(self.ewgt[e]);
                }
            }
            sub.xadj.push(sub.adj.len());
            sub.vwgt.push(self.vwgt[v]);
        }
        (sub, verts)
    }
}

/// Appends the nested dissection order of `g` (vertex v is `ids[v]`) to `out`.
fn dissect(g: WGraph, ids: Vec<usize>, out: &mut Vec<usize>) {
    let n = g.n();
    if n <= ND_LEAF_SIZE {
        out.extend(amd(&g.to_graph()).into_iter().map(|v| ids[v]));
        return;
    }
    let part = vertex_separator(&g);
    let count = |p: u8| part.iter().filter(|&&x| x == p).count();
    let (n0, n1) = (count(0), count(1));
    if n0 == 0 || n1 == 0 {
        // No useful separator (e.g. a dense graph): minimum degree on the lot.
        out.extend(amd(&g.to_graph()).into_iter().map(|v| ids[v]));
        return;
    }
    let (g0, v0) = g.induced(&part, 0);
    let (g1, v1) = g.induced(&part, 1);
    let sep: Vec<usize> = (0..n).filter(|&v| part[v] == 2).map(|v| ids[v]).collect();
    let ids0: Vec<usize> = v0.into_iter().map(|v| ids[v]).collect();
    let ids1: Vec<usize> = v1.into_iter().map(|v| ids[v]).collect();
    drop(g);
    if n > 20_000 {
        let (a, b) = rayon::join(
            || {
                let mut a = Vec::with_capacity(ids0.len());
                dissect(g0, ids0, &mut a);
                a
            },
            || {
                let mut b = Vec::with_capacity(ids1.len());
                dissect(g1, ids1, &mut b);
                b
            },
        );
        out.extend(a);
        out.extend(b);
    } else {
        dissect(g0, ids0, out);
        dissect(g1, ids1, out);
    }
    out.extend(sep);
}

/// Coarsening stops at this many vertices.
const COARSEST: usize = 120;
/// Allowed imbalance of the bisection: each side weighs at most
/// (1 + IMBALANCE)/2 of the total (or half the total plus the heaviest vertex).
const IMBALANCE: f64 = 0.1;

/// Labels every vertex 0 or 1 (the two sides) or 2 (the separator); no edge
/// joins sides 0 and 1.
fn vertex_separator(g: &WGraph) -> Vec<u8> {
    // Coarsen.
    let mut levels: Vec<WGraph> = Vec::new();
    let mut maps: Vec<Vec<usize>> = Vec::new();
    {
        let mut current = g;
        while current.n() > COARSEST {
            let (coarse, map) = coarsen(current);
            if coarse.n() as f64 > 0.9 * current.n() as f64 {
                break;
            }
            levels.push(coarse);
            maps.push(map);
            current = levels.last().expect("just pushed");
        }
    }
    let coarsest = levels.last().unwrap_or(g);
    let mut part = initial_bisection(coarsest);
    // Edge bisection refined on every level (measured: fewer factor flops than
    // refining vertex separators on every level), then the vertex separator on
    // the finest graph, refined there.
    for l in (0..levels.len()).rev() {
        let finer = if l == 0 { g } else { &levels[l - 1] };
        let map = &maps[l];
        part = (0..finer.n()).map(|v| part[map[v]]).collect();
        fm_refine(finer, &mut part);
    }
    edge_to_vertex_separator(g, &mut part);
    node_fm_refine(g, &mut part);
    part
}

/// Turns a bisection (labels 0, 1) into a vertex separator (label 2): the
/// lighter of the two boundaries.
fn edge_to_vertex_separator(g: &WGraph, part: &mut [u8]) {
    let boundary = |side: u8| -> Vec<usize> {
        (0..g.n()).filter(|&v| part[v] == side && g.range(v).any(|e| part[g.adj[e]] != side)).collect()
    };
    let (b0, b1) = (boundary(0), boundary(1));
    let weight = |vs: &[usize]| vs.iter().map(|&v| g.vwgt[v]).sum::<i64>();
    let side_weight = |side: u8| (0..g.n()).filter(|&v| part[v] == side).map(|v| g.vwgt[v]).sum::<i64>();
    let (w0, w1) = (weight(&b0), weight(&b1));
    let take = if w0 < w1 || (w0 == w1 && side_weight(0) >= side_weight(1)) { b0 } else { b1 };
    for v in take {
        part[v] = 2;
    }
}

/// Fiduccia–Mattheyses refinement of a vertex separator: a separator vertex v
/// moves to side X and its neighbours on the other side join the separator
/// (gain: w(v) minus their weight). Passes of best-gain-first moves, each
/// vertex moved at most once per pass, within the balance bound; the best
/// prefix of each pass is kept.
fn node_fm_refine(g: &WGraph, part: &mut [u8]) {
    let n = g.n();
    let max_w = max_side_weight(g);
    let mut w = [0i64; 3];
    for v in 0..n {
        w[part[v] as usize] += g.vwgt[v];
    }
    let gain_to = |part: &[u8], v: usize, x: u8| -> i64 {
        g.vwgt[v] - g.range(v).filter(|&e| part[g.adj[e]] == 1 - x).map(|e| g.vwgt[g.adj[e]]).sum::<i64>()
    };
    let mut locked = vec![false; n];
    let limit = 50.max(n / 50);
    for _pass in 0..8 {
        locked.fill(false);
        let mut heaps = [BinaryHeap::new(), BinaryHeap::new()];
        for v in 0..n {
            if part[v] == 2 {
                for x in 0..2u8 {
                    heaps[x as usize].push((gain_to(part, v, x), Reverse(v)));
                }
            }
        }
        let start = (w[2], (w[0] - w[1]).abs());
        let mut best = start;
        let mut best_len = 0;
        // (moved vertex, its side, the vertices it pulled into the separator)
        let mut moves: Vec<(usize, u8, Vec<usize>)> = Vec::new();
        let mut pulled_buf = Vec::new();
        loop {
            // Drop stale entries, then take the better move.
            let mut tops = [None, None];
            for x in 0..2 {
                while let Some(&(gain, Reverse(v))) = heaps[x].peek() {
                    if part[v] != 2 || locked[v] || gain != gain_to(part, v, x as u8) {
                        heaps[x].pop();
                        continue;
                    }
                    if w[x] + g.vwgt[v] > max_w {
                        heaps[x].pop(); // would break the balance (re-queued if it changes)
                        continue;
                    }
                    tops[x] = Some(gain);
                    break;
                }
            }
            let x = match tops {
                [None, None] => break,
                [Some(_), None] => 0,
                [None, Some(_)] => 1,
                [Some(a), Some(b)] => {
                    if a > b || (a == b && w[0] <= w[1]) {
                        0
                    } else {
                        1
                    }
                }
            };
            let (_, Reverse(v)) = heaps[x].pop().expect("peeked");
            let y = 1 - x;
            part[v] = x as u8;
            locked[v] = true;
            w[2] -= g.vwgt[v];
            w[x] += g.vwgt[v];
            pulled_buf.clear();
            for e in g.range(v) {
                let u = g.adj[e];
                if part[u] as usize == y {
                    part[u] = 2;
                    w[y] -= g.vwgt[u];
                    w[2] += g.vwgt[u];
                    pulled_buf.push(u);
                }
            }
            // Re-queue the separator vertices whose gains changed.
            for &c in std::iter::once(&v).chain(pulled_buf.iter()) {
                for e in g.range(c) {
                    let s = g.adj[e];
                    if part[s] == 2 && !locked[s] {
                        for t in 0..2u8 {
                            heaps[t as usize].push((gain_to(part, s, t), Reverse(s)));
                        }
                    }
                }
                if part[c] == 2 && !locked[c] {
                    for t in 0..2u8 {
                        heaps[t as usize].push((gain_to(part, c, t), Reverse(c)));
                    }
                }
            }
            moves.push((v, x as u8, pulled_buf.clone()));
            let state = (w[2], (w[0] - w[1]).abs());
            if state < best {
                best = state;
                best_len = moves.len();
            }
            if moves.len() - best_len > limit {
                break;
            }
        }
        for (v, x, pulled) in moves.drain(best_len..).rev() {
            let (x, y) = (x as usize, 1 - x as usize);
            for &u in &pulled {
                part[u] = y as u8;
                w[2] -= g.vwgt[u];
                w[y] += g.vwgt[u];
            }
            part[v] = 2;
            w[x] -= g.vwgt[v];
            w[2] += g.vwgt[v];
        }
        if best_len == 0 {
            break;
        }
    }
}

/// Heavy-edge matching: returns the coarse graph and the fine → coarse map.
fn coarsen(g: &WGraph) -> (WGraph, Vec<usize>) {
    let n = g.n();
    let mut mate = vec![usize::MAX; n];
    // Visit vertices by increasing degree (ties by number): low-degree vertices
    // (boundary, corners) find partners first.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&v| (g.xadj[v + 1] - g.xadj[v], v));
    let max_vwgt = (g.vwgt.iter().sum::<i64>() / COARSEST as i64).max(1);
    for &v in &order {
        if mate[v] != usize::MAX {
            continue;
        }
        let mut best = v;
        let mut best_key = (i64::MIN, i64::MIN);
        for e in g.range(v) {
            let w = g.adj[e];
            if mate[w] != usize::MAX || g.vwgt[v] + g.vwgt[w] > max_vwgt {
                continue;
            }
            let key = (g.ewgt[e], -g.vwgt[w]);
            if key > best_key {
                best_key = key;
                best = w;
            }
        }
        mate[v] = best;
        mate[best] = v;
    }
    let mut map = vec![usize::MAX; n];
    let mut nc = 0;
    for v in 0..n {
        if map[v] == usize::MAX {
            map[v] = nc;
            map[mate[v]] = nc;
            nc += 1;
        }
    }
    let mut coarse = WGraph {
        xadj: Vec::with_capacity(nc + 1),
        adj: Vec::with_capacity(g.adj.len() / 2),
        ewgt: Vec::with_capacity(g.adj.len() / 2),
        vwgt: vec![0; nc],
    };
    coarse.xadj.push(0);
    let mut slot = vec![usize::MAX; nc];
    for v in 0..n {
        if map[v] != coarse.xadj.len() - 1 {
            continue; // only the first member of each coarse vertex builds it
        }
        let c = map[v];
        let start = coarse.adj.len();
        let members = if mate[v] == v { [v, v] } else { [v, mate[v]] };
        for (k, &u) in members.iter().enumerate() {
            if k == 1 && u == v {
                break;
            }
            coarse.vwgt[c] += g.vwgt[u];
            for e in g.range(u) {
                let cw = map[g.adj[e]];
                if cw == c {
                    continue;
                }
                if slot[cw] == usize::MAX {
                    slot[cw] = coarse.adj.len();
                    coarse.adj.push(cw);
                    coarse.ewgt.push(g.ewgt[e]);
                } else {
                    coarse.ewgt[slot[cw]] += g.ewgt[e];
                }
            }
        }
        for &cw in &coarse.adj[start..] {
            slot[cw] = usize::MAX;
        }
        coarse.xadj.push(coarse.adj.len());
    }
    (coarse, map)
}

/// The largest weight a side may have.
fn max_side_weight(g: &WGraph) -> i64 {
    let total: i64 = g.vwgt.iter().sum();
    let heaviest = g.vwgt.iter().copied().max().unwrap_or(0);
    (((1.0 + IMBALANCE) * total as f64 / 2.0) as i64).max(total / 2 + heaviest)
}

/// Sum of the weights of the edges between the sides.
fn cut(g: &WGraph, part: &[u8]) -> i64 {
    (0..g.n())
        .map(|v| g.range(v).filter(|&e| part[g.adj[e]] != part[v]).map(|e| g.ewgt[e]).sum::<i64>())
        .sum::<i64>()
        / 2
}

/// Greedy graph growing from several seeds, each refined; the smallest cut wins.
fn initial_bisection(g: &WGraph) -> Vec<u8> {
    let n = g.n();
    let total: i64 = g.vwgt.iter().sum();
    let trials = 8.min(n.max(1));
    let mut best: Option<(i64, Vec<u8>)> = None;
    for t in 0..trials {
        let seed = t * n / trials;
        // Grow side 0 from the seed, always taking the vertex of side 1 that
        // lowers the cut most (ties: lowest number).
        let mut part = vec![1u8; n];
        let mut w0 = 0i64;
        let mut gain = vec![0i64; n]; // cut change if moved to side 0, negated
        for v in 0..n {
            gain[v] = -g.range(v).map(|e| g.ewgt[e]).sum::<i64>();
        }
        let mut heap = BinaryHeap::new();
        heap.push((gain[seed], Reverse(seed)));
        let mut scan = 0;
        while w0 < total / 2 {
            let v = match heap.pop() {
                Some((gv, Reverse(v))) => {
                    if part[v] == 0 || gv != gain[v] {
                        continue;
                    }
                    v
                }
                None => {
                    // Side 0 touches nothing more: start a new component.
                    while scan < n && part[scan] == 0 {
                        scan += 1;
                    }
                    if scan == n {
                        break;
                    }
                    scan
                }
            };
            part[v] = 0;
            w0 += g.vwgt[v];
            for e in g.range(v) {
                let u = g.adj[e];
                gain[u] += 2 * g.ewgt[e];
                if part[u] == 1 {
                    heap.push((gain[u], Reverse(u)));
                }
            }
        }
        fm_refine(g, &mut part);
        let c = cut(g, &part);
        if best.as_ref().is_none_or(|(bc, _)| c < *bc) {
            best = Some((c, part));
        }
    }
    best.map(|(_, p)| p).unwrap_or_default()
}

/// Fiduccia–Mattheyses refinement of a bisection: passes of greedy moves (best
/// gain first, each vertex at most once, negative gains allowed) within the
/// balance bound, keeping the best prefix of each pass.
fn fm_refine(g: &WGraph, part: &mut [u8]) {
    let n = g.n();
    let max_w = max_side_weight(g);
    let mut w = [0i64; 2];
    for v in 0..n {
        w[part[v] as usize] += g.vwgt[v];
    }
    let mut gain = vec![0i64; n];
    let mut locked = vec![false; n];
    let limit = 50.max(n / 100);
    for _pass in 0..8 {
        let mut heap = BinaryHeap::new();
        for v in 0..n {
            let mut gv = 0;
            let mut boundary = false;
            for e in g.range(v) {
                if part[g.adj[e]] != part[v] {
                    gv += g.ewgt[e];
                    boundary = true;
                } else {
                    gv -= g.ewgt[e];
                }
            }
            gain[v] = gv;
            locked[v] = false;
            if boundary {
                heap.push((gv, Reverse(v)));
            }
        }
        let imbalance = |w: &[i64; 2]| (w[0] - w[1]).abs();
        let start_imbalance = imbalance(&w);
        let (mut delta, mut best_delta, mut best_len, mut best_imb) = (0i64, 0i64, 0usize, start_imbalance);
        let mut moves: Vec<usize> = Vec::new();
        while let Some((gv, Reverse(v))) = heap.pop() {
            if locked[v] || gv != gain[v] {
                continue;
            }
            let from = part[v] as usize;
            let to = 1 - from;
            // Moves must keep (or restore) the balance bound.
            if w[to] + g.vwgt[v] > max_w && w[to] + g.vwgt[v] > w[from] {
                continue;
            }
            part[v] = to as u8;
            w[from] -= g.vwgt[v];
            w[to] += g.vwgt[v];
            locked[v] = true;
            delta -= gv;
            moves.push(v);
            for e in g.range(v) {
                let u = g.adj[e];
                if part[u] as usize == to {
                    gain[u] -= 2 * g.ewgt[e];
                } else {
                    gain[u] += 2 * g.ewgt[e];
                }
                if !locked[u] {
                    heap.push((gain[u], Reverse(u)));
                }
            }
            let imb = imbalance(&w);
            let feasible = w[0] <= max_w && w[1] <= max_w;
            if feasible && (delta < best_delta || (delta == best_delta && imb < best_imb)) {
                best_delta = delta;
                best_len = moves.len();
                best_imb = imb;
            }
            if moves.len() - best_len > limit {
                break;
            }
        }
        for &v in moves[best_len..].iter().rev() {
            let from = part[v] as usize;
            part[v] = 1 - part[v];
            w[from] -= g.vwgt[v];
            w[1 - from] += g.vwgt[v];
        }
        if best_len == 0 {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 27-point (Hex8 node) graph of an m × m × m grid of points.
    pub(super) fn grid(m: usize) -> Graph {
        let id = |i: usize, j: usize, k: usize| i + m * (j + m * k);
        let mut rows = vec![Vec::new(); m * m * m];
        for k in 0..m {
            for j in 0..m {
                for i in 0..m {
                    for dk in -1i64..=1 {
                        for dj in -1i64..=1 {
                            for di in -1i64..=1 {
                                let (a, b, c) = (i as i64 + di, j as i64 + dj, k as i64 + dk);
                                let r = 0..m as i64;
                                if r.contains(&a) && r.contains(&b) && r.contains(&c) {
                                    rows[id(i, j, k)].push(id(a as usize, b as usize, c as usize));
                                }
                            }
                        }
                    }
                }
            }
        }
        Graph::from_rows(m * m * m, |v| &rows[v])
    }

    #[test]
    fn graph_from_rows_symmetrises() {
        let rows: Vec<Vec<usize>> = vec![vec![0, 1, 1], vec![], vec![0, 2]];
        let g = Graph::from_rows(3, |v| &rows[v]);
        assert_eq!(g.neighbours(0), &[1, 2]);
        assert_eq!(g.neighbours(1), &[0]);
        assert_eq!(g.neighbours(2), &[0]);
        assert_eq!(g.n_edges(), 2);
        let q = g.quotient(&[0, 0, 1], 2);
        assert_eq!(q.neighbours(0), &[1]);
        assert_eq!(q.neighbours(1), &[0]);
    }

    #[test]
    fn orderings_are_permutations_and_deterministic() {
        let g = grid(12);
        for perm in [amd(&g), nested_dissection(&g)] {
            assert_eq!(perm.len(), g.n_vertices());
            assert!(is_permutation(&perm));
        }
        assert_eq!(nested_dissection(&g), nested_dissection(&g));
        // Disconnected pieces and an empty graph.
        let rows: Vec<Vec<usize>> = (0..500).map(|v| if v % 2 == 0 { vec![v + 1] } else { vec![] }).collect();
        let pairs = Graph::from_rows(500, |v| &rows[v]);
        assert!(is_permutation(&nested_dissection(&pairs)));
        assert!(nested_dissection(&Graph::from_rows(0, |_| &[])).is_empty());
    }

    #[test]
    fn separator_of_a_grid_is_a_plane() {
        let m = 12;
        let g = WGraph::unit(&grid(m));
        let part = vertex_separator(&g);
        let sep = part.iter().filter(|&&p| p == 2).count();
        let n0 = part.iter().filter(|&&p| p == 0).count();
        // No edge between the sides, a balanced split, a separator of about m².
        for v in 0..g.n() {
            for e in g.range(v) {
                let w = g.adj[e];
                assert!(!(part[v] == 0 && part[w] == 1), "edge between the sides");
            }
        }
        assert!(sep <= 2 * m * m, "separator of {sep} vertices");
        assert!(n0 as f64 > 0.3 * (m * m * m) as f64 && (n0 as f64) < 0.7 * (m * m * m) as f64);
    }
}
#[cfg(test)]
mod probe_sizes {
    //! Release-mode probes (`cargo test --release -p seam-fem --lib probe_sizes -- --ignored
    //! --nocapture`): separator sizes, and the factor flops of our nested
    //! dissection against AMD and a geometric one (planes through the grid).
    use super::*;
    fn flops(g: &Graph, perm: &[usize]) -> f64 {
        use faer::sparse::linalg::cholesky::*;
        let n = g.n_vertices();
        let inv = inverse(perm);
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &g.offsets, None, &g.targets);
        let sym = factorize_symbolic_cholesky(
            pattern,
            faer::Side::Lower,
            SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(perm, &inv, n)),
            CholeskySymbolicParams::default(),
        )
        .unwrap();
        let SymbolicCholeskyRaw::Supernodal(s) = sym.raw() else { return 0.0 };
        let mut f = 0.0;
        for k in 0..s.n_supernodes() {
            let c = s.supernode_end()[k] - s.supernode_begin()[k];
            let p = s.supernode(k).pattern().len();
            for j in 0..c {
                f += ((c - j + p) as f64).powi(2);
            }
        }
        f
    }
    fn geo(m: usize, lo: [usize; 3], hi: [usize; 3], out: &mut Vec<usize>) {
        let ext = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
        let id = |i: usize, j: usize, k: usize| i + m * (j + m * k);
        if ext[0] * ext[1] * ext[2] <= 128 || ext.iter().any(|&e| e < 3) {
            for k in lo[2]..hi[2] {
                for j in lo[1]..hi[1] {
                    for i in lo[0]..hi[0] {
                        out.push(id(i, j, k));
                    }
                }
            }
            return;
        }
        let d = (0..3).max_by_key(|&d| (ext[d], 3 - d)).unwrap();
        let mid = lo[d] + ext[d] / 2;
        let mut hi0 = hi;
        hi0[d] = mid;
        let mut lo1 = lo;
        lo1[d] = mid + 1;
        geo(m, lo, hi0, out);
        geo(m, lo1, hi, out);
        let mut ls = lo;
        ls[d] = mid;
        let mut hs = hi;
        hs[d] = mid + 1;
        for k in ls[2]..hs[2] {
            for j in ls[1]..hs[1] {
                for i in ls[0]..hs[0] {
                    out.push(id(i, j, k));
                }
            }
        }
    }
    #[test]
    #[ignore]
    fn nd_flops() {
        for m in [31usize, 47] {
            let mut p = Vec::new();
            geo(m, [0; 3], [m; 3], &mut p);
            assert!(is_permutation(&p));
            eprintln!("m={m} geometric: node flops {:.3e}", flops(&super::tests::grid(m), &p));
        }
        for m in [31usize, 47] {
            let g = super::tests::grid(m);
            let t = std::time::Instant::now();
            let p = nested_dissection(&g);
            eprintln!("m={m} ours: node flops {:.3e}, {:.2}s", flops(&g, &p), t.elapsed().as_secs_f64());
            eprintln!("m={m} amd: node flops {:.3e}", flops(&g, &amd(&g)));
        }
    }
    #[test]
    #[ignore]
    fn separator_sizes() {
        for m in [31usize, 47] {
            let g = WGraph::unit(&super::tests::grid(m));
            let t = std::time::Instant::now();
            let part = vertex_separator(&g);
            let c = |p: u8| part.iter().filter(|&&x| x == p).count();
            eprintln!(
                "m={m}: sep {} (plane {}), sides {} {}, {:.2}s",
                c(2),
                m * m,
                c(0),
                c(1),
                t.elapsed().as_secs_f64()
            );
        }
    }
}
