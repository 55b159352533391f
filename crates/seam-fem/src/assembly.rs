//! Global assembly: the stiffness matrix K, body-force and traction loads.
//!
//! Degrees of freedom: 3 per mesh point, `dof = 3·point + component`
//! (component 0, 1, 2 = x, y, z). For a cell e with nodes i, j and physical
//! shape gradients g_i = ∇_x N_i = J⁻ᵀ∇_ξ N_i (J = ∂x/∂ξ = Σ_i x_i ⊗ ∇_ξ N_i),
//!
//! ```text
//! K^e_{3i+a, 3j+b} = Σ_q w_q |det J| (λ g_ia g_jb + μ g_ib g_ja + μ δ_ab g_i·g_j)   (= ∫_e B_iᵀ C B_j)
//! f_{3i+a}         = ∫_Ω N_i b_a dV + ∫_Γ N_i t_a dA
//! ```
//!
//! # Determinism
//! Cell blocks are computed in parallel (rayon), each by a fixed sequence of
//! operations. K is then built row by row (in parallel over points): a row sums
//! the blocks of the cells around its point in increasing cell order, so every
//! entry is the same sum in the same order whatever the number of threads. Loads
//! are scattered in cell (face) order. The results are bitwise reproducible.

use crate::material::Material;
use rayon::prelude::*;
use seam::curved::CurvedFace;
use seam::{triangle_rule, CsrMatrix, FaceElement, Point3, SurfaceMesh, VolumeMesh};
use seam::{CellKind, VolumeRule, Xi3, MAX_CELL_NODES};

/// Quadrature degree of body-force loads on first-order cells
/// ([`CellKind::rule`]): exact for N_i·b with b affine on affine cells.
pub const BODY_FORCE_DEGREE: usize = 2;

/// The body-force quadrature degree of `kind`: order + 1 (2 on first-order,
/// 3 on second-order cells), exact for N_i·b with b affine on affine cells.
pub fn body_force_degree(kind: CellKind) -> usize {
    BODY_FORCE_DEGREE + kind.order() - 1
}

/// Triangle-rule degree of traction loads on each reference triangle of a face:
/// exact for N_i t |J| with t affine on triangles and planar quads (and for
/// N_i σ·(∂x/∂ξ × ∂x/∂η) with σ constant on warped quads).
pub const TRACTION_DEGREE: usize = 4;

/// Triangle-rule degree of traction loads on second-order faces (Tri6, Quad8,
/// Quad9): exact for N_i t |J| with t affine on flat straight-sided faces
/// (degree ≤ 5 on each half of a quad) and for N_i σ·(∂x/∂ξ × ∂x/∂η) with σ
/// constant on curved Tri6 faces (degree 4).
pub const CURVED_TRACTION_DEGREE: usize = 6;

/// A cell is degenerate when |det J| ≤ `DEGENERATE_RTOL` · |J e_1| |J e_2| |J e_3|
/// at a quadrature point (a volume vanishing relative to its edge lengths).
pub const DEGENERATE_RTOL: f64 = 1e-12;

/// Why an assembly failed.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum AssemblyError {
    /// A cell's Jacobian determinant vanishes or changes sign.
    #[error("cell {cell} is degenerate or tangled: its Jacobian determinant vanishes or changes sign")]
    DegenerateCell {
        /// The cell index.
        cell: usize,
    },
}

/// The physical view of a cell at one reference point.
#[derive(Clone, Copy, Debug)]
pub struct PointGeometry {
    /// det J, J = ∂x/∂ξ (negative for a cell of negative orientation).
    pub det: f64,
    /// Physical gradients ∇_x N_i = J⁻ᵀ ∇_ξ N_i; entries past the node count are 0.
    pub grads: [[f64; 3]; MAX_CELL_NODES],
}

/// The map x(ξ) = Σ_i N_i(ξ) x_i of a cell with nodes `x` (Gmsh order).
pub fn map_point(kind: CellKind, x: &[Point3], xi: Xi3) -> Point3 {
    let n = kind.shape(xi);
    let mut p = [0.0; 3];
    for (i, xi) in x.iter().enumerate() {
        for k in 0..3 {
            p[k] += n[i] * xi[k];
        }
    }
    p
}

/// det J and the physical gradients at ξ; `None` when the cell is degenerate
/// there (|det J| ≤ [`DEGENERATE_RTOL`] · Π_l |J e_l|, or not finite).
pub fn geometry(kind: CellKind, x: &[Point3], xi: Xi3) -> Option<PointGeometry> {
    debug_assert_eq!(x.len(), kind.n_nodes());
    let g = kind.gradients(xi);
    // J[k][l] = ∂x_k/∂ξ_l
    let mut j = [[0.0; 3]; 3];
    for (i, xi) in x.iter().enumerate() {
        for k in 0..3 {
            for l in 0..3 {
                j[k][l] += xi[k] * g[i][l];
            }
        }
    }
    let cof = [
        [
            j[1][1] * j[2][2] - j[1][2] * j[2][1],
            j[1][2] * j[2][0] - j[1][0] * j[2][2],
            j[1][0] * j[2][1] - j[1][1] * j[2][0],
        ],
        [
            j[0][2] * j[2][1] - j[0][1] * j[2][2],
            j[0][0] * j[2][2] - j[0][2] * j[2][0],
            j[0][1] * j[2][0] - j[0][0] * j[2][1],
        ],
        [
            j[0][1] * j[1][2] - j[0][2] * j[1][1],
            j[0][2] * j[1][0] - j[0][0] * j[1][2],
            j[0][0] * j[1][1] - j[0][1] * j[1][0],
        ],
    ];
    let det = j[0][0] * cof[0][0] + j[0][1] * cof[0][1] + j[0][2] * cof[0][2];
    let col = |l: usize| (j[0][l] * j[0][l] + j[1][l] * j[1][l] + j[2][l] * j[2][l]).sqrt();
    let scale = col(0) * col(1) * col(2);
    if !det.is_finite() || det.abs() <= DEGENERATE_RTOL * scale {
        return None;
    }
    // J⁻¹ = cof(J)ᵀ / det, so ∇_x N = J⁻ᵀ ∇_ξ N = cof(J) ∇_ξ N / det.
    let mut grads = [[0.0; 3]; MAX_CELL_NODES];
    for i in 0..x.len() {
        for k in 0..3 {
            grads[i][k] = (cof[k][0] * g[i][0] + cof[k][1] * g[i][1] + cof[k][2] * g[i][2]) / det;
        }
    }
    Some(PointGeometry { det, grads })
}

/// The geometry at every point of `rule`, or `None` if the cell is degenerate at
/// one of them or det J changes sign between them.
pub(crate) fn geometry_at_rule(
    kind: CellKind,
    x: &[Point3],
    rule: &VolumeRule,
) -> Option<Vec<PointGeometry>> {
    let geo: Vec<PointGeometry> =
        rule.points.iter().map(|&xi| geometry(kind, x, xi)).collect::<Option<_>>()?;
    let positive = geo[0].det > 0.0;
    geo.iter().all(|g| (g.det > 0.0) == positive).then_some(geo)
}

/// Element stiffness ∫_e Bᵀ C B dV with [`CellKind::stiffness_rule`], as a dense
/// row-major (3n)×(3n) matrix in local dofs 3i + a. Cells of either orientation
/// are accepted (|det J|). `None` for a degenerate or tangled cell.
pub fn element_stiffness(kind: CellKind, x: &[Point3], material: &Material) -> Option<Vec<f64>> {
    let rule = kind.stiffness_rule();
    let geo = geometry_at_rule(kind, x, rule)?;
    let (lambda, mu) = material.lame();
    let n = kind.n_nodes();
    let nd = 3 * n;
    let mut k = vec![0.0; nd * nd];
    for (g, w) in geo.iter().zip(&rule.weights) {
        let wd = w * g.det.abs();
        let (wl, wm) = (wd * lambda, wd * mu);
        for i in 0..n {
            let gi = g.grads[i];
            for j in i..n {
                let gj = g.grads[j];
                let dot = gi[0] * gj[0] + gi[1] * gj[1] + gi[2] * gj[2];
                for a in 0..3 {
                    for b in 0..3 {
                        let mut v = wl * gi[a] * gj[b] + wm * gi[b] * gj[a];
                        if a == b {
                            v += wm * dot;
                        }
                        k[(3 * i + a) * nd + 3 * j + b] += v;
                    }
                }
            }
        }
    }
    // Mirror the upper blocks: K^e is exactly symmetric.
    for r in 0..nd {
        for c in 0..r {
            k[r * nd + c] = k[c * nd + r];
        }
    }
    Some(k)
}

/// The node coordinates of cell `c` (entries past its node count are 0) and its kind.
pub(crate) fn corners(mesh: &VolumeMesh, c: usize) -> ([Point3; MAX_CELL_NODES], CellKind) {
    let cell = &mesh.cells()[c];
    let mut x = [[0.0; 3]; MAX_CELL_NODES];
    for (i, &p) in cell.nodes().iter().enumerate() {
        x[i] = mesh.points()[p];
    }
    (x, CellKind::of(cell))
}

/// Runs `f` on every cell (its kind and node coordinates) in parallel; the first
/// (lowest) failing cell is the error.
fn per_cell<T: Send>(
    mesh: &VolumeMesh,
    f: impl Fn(CellKind, &[Point3]) -> Option<T> + Sync,
) -> Result<Vec<T>, AssemblyError> {
    let out: Vec<Option<T>> = (0..mesh.cells().len())
        .into_par_iter()
        .map(|c| {
            let (x, kind) = corners(mesh, c);
            f(kind, &x[..kind.n_nodes()])
        })
        .collect();
    if let Some(cell) = out.iter().position(Option::is_none) {
        return Err(AssemblyError::DegenerateCell { cell });
    }
    Ok(out.into_iter().flatten().collect())
}

/// The cells around each point, in increasing cell order, with the point's local
/// index in the cell: (offsets, (cell, local)), CSR-like.
pub(crate) fn point_cells(mesh: &VolumeMesh) -> (Vec<usize>, Vec<(usize, usize)>) {
    let n = mesh.points().len();
    let mut offsets = vec![0usize; n + 1];
    for cell in mesh.cells() {
        for &p in cell.nodes() {
            offsets[p + 1] += 1;
        }
    }
    for p in 0..n {
        offsets[p + 1] += offsets[p];
    }
    let mut fill = offsets.clone();
    let mut entries = vec![(0, 0); offsets[n]];
    for (c, cell) in mesh.cells().iter().enumerate() {
        for (l, &p) in cell.nodes().iter().enumerate() {
            entries[fill[p]] = (c, l);
            fill[p] += 1;
        }
    }
    (offsets, entries)
}

/// The global stiffness matrix K (3·n_points square, symmetric, sorted CSR).
/// Points that no cell uses get empty rows.
///
/// # Errors
/// [`AssemblyError::DegenerateCell`] for the first degenerate or tangled cell.
///
/// # Performance
/// Parallel over cells, then over points; deterministic (module doc).
pub fn stiffness(mesh: &VolumeMesh, material: &Material) -> Result<CsrMatrix, AssemblyError> {
    cell_matrix(mesh, |kind, x, _, out| {
        element_stiffness(kind, x, material).map(|k| out.copy_from_slice(&k)).is_some()
    })
}

/// The global matrix Σ_e A^e (3·n_points square, sorted CSR, the pattern
/// of [`stiffness`]) of the dense row-major (3n)×(3n) cell blocks that
/// `fill(kind, nodes' coordinates, cell, block)` writes (false for a
/// degenerate cell), summed per point over its cells in increasing cell
/// order.
///
/// # Errors
/// [`AssemblyError::DegenerateCell`] for the first failing cell.
pub(crate) fn cell_matrix(
    mesh: &VolumeMesh,
    fill: impl Fn(CellKind, &[Point3], usize, &mut [f64]) -> bool + Sync,
) -> Result<CsrMatrix, AssemblyError> {
    let cells = mesh.cells();
    let (start, blocks) = cell_blocks(mesh, |nodes| (3 * nodes).pow(2), fill)?;
    let (offsets, around) = point_cells(mesh);
    let n = mesh.points().len();
    // The neighbouring points of p (sorted, each once) in `nb`.
    let neighbours = |p: usize, nb: &mut Vec<usize>| {
        nb.clear();
        nb.extend(
            around[offsets[p]..offsets[p + 1]].iter().flat_map(|&(c, _)| cells[c].nodes().iter().copied()),
        );
        nb.sort_unstable();
        nb.dedup();
    };
    let widths: Vec<usize> = (0..n)
        .into_par_iter()
        .map_init(Vec::new, |nb, p| {
            neighbours(p, nb);
            3 * nb.len()
        })
        .collect();
    // Point p's three rows, each `widths[p]` long, are consecutive.
    let mut indptr = Vec::with_capacity(3 * n + 1);
    indptr.push(0);
    for w in widths {
        for _ in 0..3 {
            indptr.push(indptr[indptr.len() - 1] + w);
        }
    }
    let nnz = indptr[3 * n];
    let (mut indices, mut values) = (vec![0; nnz], vec![0.0; nnz]);
    let point_start: Vec<usize> = indptr.iter().step_by(3).copied().collect();
    split_mut(&mut indices, &point_start)
        .into_par_iter()
        .zip(split_mut(&mut values, &point_start))
        .enumerate()
        .for_each_init(Vec::new, |nb, (p, (cols, vals))| {
            neighbours(p, nb);
            let width = 3 * nb.len();
            if width == 0 {
                return; // a point that no cell uses: three empty rows
            }
            for row in cols.chunks_mut(width) {
                for (q, &j) in nb.iter().enumerate() {
                    row[3 * q..3 * q + 3].copy_from_slice(&[3 * j, 3 * j + 1, 3 * j + 2]);
                }
            }
            for &(c, li) in &around[offsets[p]..offsets[p + 1]] {
                let nodes = cells[c].nodes();
                let nd = 3 * nodes.len();
                let block = &blocks[start[c]..start[c + 1]];
                for (lj, q) in nodes.iter().enumerate() {
                    let col = 3 * nb.binary_search(q).expect("a cell's nodes are neighbours");
                    for a in 0..3 {
                        let src = &block[(3 * li + a) * nd + 3 * lj..][..3];
                        let dst = &mut vals[a * width + col..][..3];
                        for b in 0..3 {
                            dst[b] += src[b];
                        }
                    }
                }
            }
        });
    Ok(CsrMatrix { nrows: 3 * n, ncols: 3 * n, indptr, indices, values })
}

/// K u without K: Σ_e K^e u_e, each cell's product formed on its own (in
/// parallel), each point's entries summed over its cells in increasing cell
/// order (deterministic, module doc). What a solve needs of K after K has
/// gone to make room for the solver (the residual, the multipliers).
///
/// # Errors
/// [`AssemblyError::DegenerateCell`] for the first degenerate or tangled cell.
pub fn stiffness_times(mesh: &VolumeMesh, material: &Material, u: &[f64]) -> Result<Vec<f64>, AssemblyError> {
    let cells = mesh.cells();
    assert_eq!(u.len(), 3 * mesh.points().len(), "u has 3 entries per point");
    cell_vector(mesh, |kind, x, c, out| {
        let Some(k) = element_stiffness(kind, x, material) else { return false };
        let nodes = cells[c].nodes();
        for (row, y) in k.chunks_exact(out.len()).zip(out.iter_mut()) {
            *y = nodes
                .iter()
                .enumerate()
                .map(|(j, &q)| (0..3).map(|b| row[3 * j + b] * u[3 * q + b]).sum::<f64>())
                .sum();
        }
        true
    })
}

/// The global vector Σ_e v^e (3·n_points) of the cell vectors (3n, local
/// dofs 3i + a) that `fill(kind, nodes' coordinates, cell, block)` writes
/// (false for a degenerate cell), each point's entries summed over its
/// cells in increasing cell order (deterministic).
///
/// # Errors
/// [`AssemblyError::DegenerateCell`] for the first failing cell.
pub(crate) fn cell_vector(
    mesh: &VolumeMesh,
    fill: impl Fn(CellKind, &[Point3], usize, &mut [f64]) -> bool + Sync,
) -> Result<Vec<f64>, AssemblyError> {
    let n = mesh.points().len();
    let (start, products) = cell_blocks(mesh, |nodes| 3 * nodes, fill)?;
    let (offsets, around) = point_cells(mesh);
    let mut ku = vec![0.0; 3 * n];
    ku.par_chunks_mut(3).enumerate().for_each(|(p, out)| {
        for &(c, l) in &around[offsets[p]..offsets[p + 1]] {
            for a in 0..3 {
                out[a] += products[start[c] + 3 * l + a];
            }
        }
    });
    Ok(ku)
}

/// One block of `len(n_nodes)` entries per cell in one buffer (cell c's from
/// start[c]), filled in parallel by `fill(kind, nodes' coordinates, cell,
/// block)`, which returns false for a degenerate cell: a few large
/// allocations, which go back to the system when freed, where one per cell
/// would stay with the allocator.
///
/// # Errors
/// [`AssemblyError::DegenerateCell`] for the first (lowest) failing cell.
fn cell_blocks(
    mesh: &VolumeMesh,
    len: impl Fn(usize) -> usize,
    fill: impl Fn(CellKind, &[Point3], usize, &mut [f64]) -> bool + Sync,
) -> Result<(Vec<usize>, Vec<f64>), AssemblyError> {
    let cells = mesh.cells();
    let mut start = Vec::with_capacity(cells.len() + 1);
    start.push(0);
    for cell in cells {
        start.push(start[start.len() - 1] + len(cell.nodes().len()));
    }
    let mut blocks = vec![0.0; start[cells.len()]];
    let ok: Vec<bool> = split_mut(&mut blocks, &start)
        .into_par_iter()
        .enumerate()
        .map(|(c, out)| {
            let (x, kind) = corners(mesh, c);
            fill(kind, &x[..kind.n_nodes()], c, out)
        })
        .collect();
    match ok.iter().position(|&ok| !ok) {
        Some(cell) => Err(AssemblyError::DegenerateCell { cell }),
        None => Ok((start, blocks)),
    }
}

/// `data` cut at the offsets `at` (increasing, from 0 to at most its length):
/// piece i is data[at[i]..at[i + 1]].
pub(crate) fn split_mut<'a, T>(mut data: &'a mut [T], at: &[usize]) -> Vec<&'a mut [T]> {
    at.windows(2)
        .map(|w| {
            let (piece, rest) = std::mem::take(&mut data).split_at_mut(w[1] - w[0]);
            data = rest;
            piece
        })
        .collect()
}

/// Body-force load f_{3i+a} = ∫_Ω N_i b_a(x) dV, with [`CellKind::rule`] of
/// degree [`body_force_degree`]; length 3·n_points.
///
/// # Errors
/// [`AssemblyError::DegenerateCell`] for the first degenerate or tangled cell.
pub fn body_force(
    mesh: &VolumeMesh,
    b: impl Fn(Point3) -> [f64; 3] + Sync,
) -> Result<Vec<f64>, AssemblyError> {
    let rules = CellKind::ALL.map(|k| k.rule(body_force_degree(k)));
    let local = per_cell(mesh, |kind, x| {
        let rule = &rules[kind as usize];
        let geo = geometry_at_rule(kind, x, rule)?;
        let mut f = [[0.0; 3]; MAX_CELL_NODES];
        for ((&xi, w), g) in rule.points.iter().zip(&rule.weights).zip(&geo) {
            let n = kind.shape(xi);
            let bx = b(map_point(kind, x, xi));
            let wd = w * g.det.abs();
            for i in 0..x.len() {
                for a in 0..3 {
                    f[i][a] += wd * n[i] * bx[a];
                }
            }
        }
        Some(f)
    })?;
    let mut f = vec![0.0; 3 * mesh.points().len()];
    for (cell, fl) in mesh.cells().iter().zip(&local) {
        for (i, &p) in cell.nodes().iter().enumerate() {
            for a in 0..3 {
                f[3 * p + a] += fl[i][a];
            }
        }
    }
    Ok(f)
}

/// A face of a surface as the traction integrates it: first-order faces through
/// [`FaceElement`], second-order ones through [`CurvedFace`] (quads on \[0,1\]²).
enum LoadFace {
    Flat(FaceElement),
    Curved(CurvedFace),
}

impl LoadFace {
    fn of(surface: &SurfaceMesh, f: usize) -> LoadFace {
        let face = &surface.faces()[f];
        if !face.is_curved() {
            return LoadFace::Flat(FaceElement::of(surface, f));
        }
        let mut x = [[0.0; 3]; 9];
        for (xi, &p) in x.iter_mut().zip(face.nodes()) {
            *xi = surface.points()[p];
        }
        LoadFace::Curved(CurvedFace::new(face.kind(), &x))
    }

    /// The reference triangles covering the reference face, and the rule degree.
    fn triangles(&self) -> (&'static [[[f64; 2]; 3]], usize) {
        match self {
            LoadFace::Flat(e) => (e.reference_triangles(), TRACTION_DEGREE),
            LoadFace::Curved(c) => (c.kind.reference_triangles(), CURVED_TRACTION_DEGREE),
        }
    }

    /// x(ξ), ∂x/∂ξ × ∂x/∂η and the shape functions at ξ.
    fn at(&self, xi: [f64; 2]) -> (Point3, Point3, [f64; 9]) {
        let (x, a, b, n) = match self {
            LoadFace::Flat(e) => {
                let (a, b) = e.tangents(xi);
                let mut n = [0.0; 9];
                n[..4].copy_from_slice(&e.shape(xi));
                (e.map(xi), a, b, n)
            }
            LoadFace::Curved(c) => {
                let (x, a, b) = c.map_and_tangents(xi);
                (x, a, b, c.kind.shape_and_gradients(xi).0)
            }
        };
        (x, [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]], n)
    }
}

/// Traction load f_{3i+a} = ∫_Γ N_i t_a(x, n) dA over the faces of `surface`,
/// whose points must be the volume mesh's points (as from
/// [`VolumeMesh::boundary`], [`VolumeMesh::orient_outward`] or `seam_io`); length
/// 3·n_points.
///
/// `t(x, n)` is the traction at x, n the unit normal ∂x/∂ξ × ∂x/∂η / |…| of the
/// face there (outward for outward-oriented faces): a pressure p is
/// `|_, n| [-p * n[0], -p * n[1], -p * n[2]]`. Quads are integrated as two
/// reference triangles with [`seam::triangle_rule`] of degree [`TRACTION_DEGREE`]
/// (as `seam::face_integrals` does), triangles as one. Second-order faces (Tri6,
/// Quad8, Quad9) use their quadratic shape functions and the true curved map
/// x(ξ) = Σ N_i(ξ) x_i of [`seam::curved`] (quads on \[0,1\]², the two halves of
/// the square), with the rule of degree [`CURVED_TRACTION_DEGREE`]; dA = |∂x/∂ξ ×
/// ∂x/∂η| dξ.
pub fn traction(surface: &SurfaceMesh, t: impl Fn(Point3, Point3) -> [f64; 3] + Sync) -> Vec<f64> {
    let rules =
        [TRACTION_DEGREE, CURVED_TRACTION_DEGREE].map(|d| triangle_rule(d).expect("tabulated degree"));
    let local: Vec<[[f64; 3]; 9]> = (0..surface.n_faces())
        .into_par_iter()
        .map(|f| {
            let e = LoadFace::of(surface, f);
            let n_nodes = surface.faces()[f].len();
            let (triangles, degree) = e.triangles();
            let rule = &rules[(degree == CURVED_TRACTION_DEGREE) as usize];
            let mut out = [[0.0; 3]; 9];
            for tri in triangles {
                let (u, v) = (
                    [tri[1][0] - tri[0][0], tri[1][1] - tri[0][1]],
                    [tri[2][0] - tri[0][0], tri[2][1] - tri[0][1]],
                );
                let area = 0.5 * (u[0] * v[1] - u[1] * v[0]).abs();
                for (p, &w) in rule.points.iter().zip(rule.weights) {
                    let xi = [tri[0][0] + p[0] * u[0] + p[1] * v[0], tri[0][1] + p[0] * u[1] + p[1] * v[1]];
                    let (x, nv, n) = e.at(xi);
                    let jac = (nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]).sqrt();
                    let tx = t(x, [nv[0] / jac, nv[1] / jac, nv[2] / jac]);
                    let wj = w * area * jac;
                    for i in 0..n_nodes {
                        for c in 0..3 {
                            out[i][c] += wj * n[i] * tx[c];
                        }
                    }
                }
            }
            out
        })
        .collect();
    let mut f = vec![0.0; 3 * surface.n_points()];
    for (face, fl) in surface.faces().iter().zip(&local) {
        for (i, &p) in face.nodes().iter().enumerate() {
            for c in 0..3 {
                f[3 * p + c] += fl[i][c];
            }
        }
    }
    f
}

/// Cell volumes ∫_e dV = Σ_q w_q |det J| with the stiffness rule (exact for
/// every first-order cell, trilinear hexes included, and for second-order
/// cells whose map is of the first-order family's form, e.g. straight-sided).
///
/// # Errors
/// [`AssemblyError::DegenerateCell`] for the first degenerate or tangled cell.
pub fn cell_volumes(mesh: &VolumeMesh) -> Result<Vec<f64>, AssemblyError> {
    per_cell(mesh, |kind, x| {
        let rule = kind.stiffness_rule();
        let geo = geometry_at_rule(kind, x, rule)?;
        Some(geo.iter().zip(&rule.weights).map(|(g, w)| w * g.det.abs()).sum())
    })
}

/// The six rigid-body motions of the points, as dof vectors (length 3·n):
/// translations e_x, e_y, e_z, then rotations e_k × x about the origin.
pub fn rigid_body_modes(points: &[Point3]) -> [Vec<f64>; 6] {
    std::array::from_fn(|m| {
        points
            .iter()
            .flat_map(|x| match m {
                0..=2 => {
                    let mut v = [0.0; 3];
                    v[m] = 1.0;
                    v
                }
                3 => [0.0, -x[2], x[1]],
                4 => [x[2], 0.0, -x[0]],
                _ => [-x[1], x[0], 0.0],
            })
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use seam::{Face, FaceKind};

    #[test]
    fn unit_tet_stiffness_row_sums_vanish() {
        let x = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
        let m = Material::new(1.0, 0.25).unwrap();
        let k = element_stiffness(CellKind::Tet4, &x, &m).unwrap();
        for r in 0..12 {
            for a in 0..3 {
                let s: f64 = (0..4).map(|j| k[r * 12 + 3 * j + a]).sum();
                assert!(s.abs() < 1e-15);
            }
        }
        // Flat tet: degenerate.
        let flat = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]];
        assert!(element_stiffness(CellKind::Tet4, &flat, &m).is_none());
    }

    /// Points that no cell uses (a file's other volumes) get empty rows, and
    /// the used ones the same rows as without them.
    #[test]
    fn unused_points_get_empty_rows() {
        let m = Material::new(1.0, 0.25).unwrap();
        let x = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
        let alone =
            stiffness(&VolumeMesh::new(x.to_vec(), vec![seam::Cell::Tet4([0, 1, 2, 3])]).unwrap(), &m);
        let points = vec![[5.0; 3], x[0], x[1], [6.0; 3], x[2], x[3], [7.0; 3]];
        let mesh = VolumeMesh::new(points, vec![seam::Cell::Tet4([1, 2, 4, 5])]).unwrap();
        let (k, alone) = (stiffness(&mesh, &m).unwrap(), alone.unwrap());
        assert_eq!(k.nrows, 21);
        let row = |k: &CsrMatrix, r: usize| k.indptr[r + 1] - k.indptr[r];
        for p in [0, 3, 6] {
            assert!((0..3).all(|a| row(&k, 3 * p + a) == 0), "point {p}");
        }
        assert_eq!(k.nnz(), alone.nnz());
        assert_eq!(row(&k, 3 * 5 + 2), 12);
        assert_eq!(
            k.values[k.indptr[3 * 5 + 2]..k.indptr[3 * 5 + 3]],
            alone.values[alone.indptr[11]..alone.indptr[12]]
        );
    }

    /// A unit pressure on a flat unit face: the classic consistent loads,
    /// Quad8 −1/12 at corners and 1/3 at mid-edges, Quad9 1/36, 1/9, 4/9,
    /// Tri6 (area ½) 0 at corners and 1/6 at mid-edges.
    #[test]
    fn second_order_face_loads_are_the_consistent_ones() {
        for (kind, face, expected) in [
            (FaceKind::Quad8, Face::Quad8(std::array::from_fn(|i| i)), vec![-1.0 / 12.0, 1.0 / 3.0]),
            (
                FaceKind::Quad9,
                Face::Quad9(std::array::from_fn(|i| i)),
                vec![1.0 / 36.0, 1.0 / 9.0, 4.0 / 9.0],
            ),
            (FaceKind::Tri6, Face::Tri6(std::array::from_fn(|i| i)), vec![0.0, 1.0 / 6.0]),
        ] {
            let points: Vec<Point3> = kind.nodes().iter().map(|x| [x[0], x[1], 0.0]).collect();
            let surface = SurfaceMesh::new(points, vec![face]).unwrap();
            let f = traction(&surface, |_, n| n);
            let corners = kind.n_corners();
            for i in 0..kind.n_nodes() {
                let e = expected[if i < corners {
                    0
                } else if i < 2 * corners {
                    1
                } else {
                    2
                }];
                assert!((f[3 * i + 2] - e).abs() < 1e-14, "{kind:?} node {i}: {} vs {e}", f[3 * i + 2]);
                assert!(f[3 * i].abs() < 1e-15 && f[3 * i + 1].abs() < 1e-15);
            }
        }
    }
}
