//! Second-order elements (their shape functions are checked against Gmsh in
//! `seam::catalogue`): completeness, face traces, element stiffness kernels, the order raising
//! generator, patch tests on every second-order cell, and convergence rates of
//! Tet10 and Hex27 on a manufactured solution.

use crate::common;

use common::manufactured::{exact, gradient, load};
use common::{
    affine, affine_stress, check_affine, distorted, error_sums, fitted_rate, hybrid, material, max_abs,
    tensor, warp, Rng, KINDS,
};
use faer::{Mat, Side as EigSide};
use seam::Xi3;
use seam::{Cell, Point3, VolumeMesh};
use seam_fem::assembly::element_stiffness;
use seam_fem::generate::{block, node_supports, raise_order, BlockKind, Grid, RaiseError};
use seam_fem::solve::solve;
use seam_fem::{
    body_force, cell_volumes, rigid_body_modes, stiffness, traction, CellKind, Dirichlet, Material,
};

/// Points strictly inside the reference cell of `kind`.
fn samples(kind: CellKind) -> Vec<Xi3> {
    match kind.family() {
        CellKind::Tet4 => vec![[0.1, 0.2, 0.3], [0.25, 0.25, 0.25], [0.6, 0.1, 0.05]],
        CellKind::Hex8 => vec![[0.1, -0.7, 0.3], [0.0; 3], [0.9, 0.8, -0.95]],
        CellKind::Prism6 => vec![[0.1, 0.2, 0.3], [0.5, 0.3, -0.9], [0.2, 0.7, 0.6]],
        _ => vec![[0.1, -0.2, 0.3], [0.5, 0.3, 0.1], [-0.05, 0.02, 0.9], [0.0, 0.0, 0.5]],
    }
}

/// A random polynomial of total degree ≤ `degree` (1 or 2) and its gradient.
fn polynomial(rng: &mut Rng, degree: usize) -> impl Fn(Xi3) -> (f64, [f64; 3]) {
    let c: [f64; 10] = std::array::from_fn(|_| rng.symmetric());
    let q = if degree >= 2 { 1.0 } else { 0.0 };
    move |[x, y, z]: Xi3| {
        let v = c[0]
            + c[1] * x
            + c[2] * y
            + c[3] * z
            + q * (c[4] * x * x + c[5] * y * y + c[6] * z * z + c[7] * x * y + c[8] * y * z + c[9] * x * z);
        let g = [
            c[1] + q * (2.0 * c[4] * x + c[7] * y + c[9] * z),
            c[2] + q * (2.0 * c[5] * y + c[7] * x + c[8] * z),
            c[3] + q * (2.0 * c[6] * z + c[8] * y + c[9] * x),
        ];
        (v, g)
    }
}

/// Σ p(node_i) N_i = p and Σ p(node_i) ∇N_i = ∇p for quadratic p: every
/// second-order space, the pyramids' rational ones included, contains P₂.
#[test]
fn quadratic_fields_are_reproduced() {
    let mut rng = Rng(7);
    for kind in CellKind::SECOND_ORDER {
        for degree in [1, 2] {
            let p = polynomial(&mut rng, degree);
            let values: Vec<f64> = kind.reference_nodes().iter().map(|&x| p(x).0).collect();
            for xi in samples(kind) {
                let (n, g) = (kind.shape(xi), kind.gradients(xi));
                let v: f64 = values.iter().zip(&n).map(|(a, b)| a * b).sum();
                let (pv, pg) = p(xi);
                assert!((v - pv).abs() < 1e-12, "{kind:?} degree {degree}: {v} vs {pv}");
                for k in 0..3 {
                    let d: f64 = values.iter().zip(&g).map(|(a, b)| a * b[k]).sum();
                    assert!((d - pg[k]).abs() < 1e-11, "{kind:?} degree {degree} ∂_{k}: {d} vs {}", pg[k]);
                }
            }
        }
    }
}

/// Conformity: on each face of the reference cell, the shape functions of the
/// nodes off the face vanish, so the trace is spanned by the face's own nodes
/// (a Tri6, Quad8 or Quad9 trace) and neighbours match.
#[test]
fn traces_on_faces_depend_on_face_nodes_only() {
    let mut rng = Rng(11);
    for kind in CellKind::SECOND_ORDER {
        let nodes = kind.reference_nodes();
        let probe = kind.cell(&(0..kind.n_nodes()).collect::<Vec<_>>()).unwrap();
        for face in probe.faces() {
            let on: Vec<usize> = face.nodes().to_vec();
            let corners: Vec<Xi3> = face.corner_nodes().iter().map(|&c| nodes[c]).collect();
            for _ in 0..5 {
                // A random convex combination of the face's corners.
                let w: Vec<f64> = corners.iter().map(|_| 0.5 * (rng.symmetric() + 1.0) + 0.05).collect();
                let s: f64 = w.iter().sum();
                let xi: Xi3 =
                    std::array::from_fn(|k| corners.iter().zip(&w).map(|(c, w)| c[k] * w).sum::<f64>() / s);
                let n = kind.shape(xi);
                for i in (0..kind.n_nodes()).filter(|i| !on.contains(i)) {
                    assert!(n[i].abs() < 1e-13, "{kind:?}: N_{i} = {} on face {:?} at {xi:?}", n[i], face);
                }
            }
        }
    }
}

/// The element stiffness of every reference cell, and of a distorted cell of
/// each kind, has exactly the six rigid-body zero eigenvalues.
#[test]
fn element_stiffness_has_exactly_six_zero_modes() {
    let mut cells: Vec<(CellKind, Vec<Point3>)> =
        CellKind::SECOND_ORDER.iter().map(|&k| (k, k.reference_nodes().to_vec())).collect();
    // And a distorted cell of each kind, touching a moved interior point.
    for (kind, mesh, grid) in patch_meshes() {
        let inner = grid.point(1, 1, 1);
        let cell = mesh.cells().iter().find(|c| c.nodes().contains(&inner)).unwrap();
        cells.push((kind, cell.nodes().iter().map(|&p| mesh.points()[p]).collect()));
    }
    let m = Material::new(1.0, 0.3).unwrap();
    for (kind, x) in cells {
        let k = element_stiffness(kind, &x, &m).unwrap();
        let n = 3 * kind.n_nodes();
        let eig = Mat::from_fn(n, n, |i, j| k[i * n + j]).self_adjoint_eigenvalues(EigSide::Lower).unwrap();
        let top = eig[n - 1];
        let zero = eig.iter().filter(|&&e| e.abs() < 1e-10 * top).count();
        assert_eq!(zero, 6, "{kind:?}: eigenvalues {eig:?}");
        assert!(eig[6] > 1e-4 * top, "{kind:?}: smallest deformation mode {} vs {top}", eig[6]);
        assert!(eig[0] > -1e-12 * top, "{kind:?}: negative eigenvalue {}", eig[0]);
    }
}

fn raised_kinds(kind: BlockKind) -> [bool; 2] {
    // Tets have a single second-order kind.
    if kind == BlockKind::Tet {
        [true; 2]
    } else {
        [false, true]
    }
}

#[test]
fn raise_order_shares_nodes_and_keeps_the_geometry() {
    for kind in KINDS {
        let (mesh, _) = distorted(kind, 3, 0.25);
        for complete in raised_kinds(kind) {
            let high = raise_order(&mesh, complete).unwrap();
            assert_eq!(&high.points()[..mesh.points().len()], mesh.points(), "{kind:?}: old points kept");
            for (lo, hi) in mesh.cells().iter().zip(high.cells()) {
                assert_eq!(lo.nodes(), hi.corner_nodes(), "{kind:?}: corners kept");
                assert!(hi.is_second_order());
            }
            // A conforming raise shares mid-edge and face nodes: the boundary has
            // as many faces as before, every one of second order.
            let (b0, b1) = (mesh.boundary().unwrap(), high.boundary().unwrap());
            assert_eq!(b0.n_faces(), b1.n_faces(), "{kind:?} complete {complete}");
            // Straight-sided raise: the same cell volumes.
            let (v0, v1) = (cell_volumes(&mesh).unwrap(), cell_volumes(&high).unwrap());
            for (a, b) in v0.iter().zip(&v1) {
                assert!((a - b).abs() < 1e-13 * a, "{kind:?}: volume {a} vs {b}");
            }
            // Rigid motions are in the kernel of K.
            let k = stiffness(&high, &Material::new(210e3, 0.3).unwrap()).unwrap();
            let knorm = k.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for r in rigid_body_modes(high.points()) {
                let rel = max_abs(&k.mul_vec(&r, 1)) / (knorm * max_abs(&r));
                assert!(rel < 1e-12, "{kind:?}: |K r| / (|K| |r|) = {rel:e}");
            }
        }
    }
    // Every node of a tet mesh n³: corners + one per edge.
    let tets = raise_order(&block(2, 2, 2, |u, v, w| [u, v, w], BlockKind::Tet), false).unwrap();
    // 27 grid points; edges of the Kuhn split of a 2³ grid: 12·... counted by Euler:
    // V − E + F − C = 1 with C = 48 tets, F = (4·48 + boundary 48) / 2 = 120.
    assert_eq!(tets.points().len(), 27 + (27 + 120 - 48 - 1));
    assert!(matches!(raise_order(&tets, true), Err(RaiseError::SecondOrder { cell: 0 })));
    assert_eq!(node_supports(CellKind::Hex27)[26], (0..8).collect::<Vec<_>>());
}

/// The second-order meshes of the patch tests: distorted 3³ blocks raised,
/// (kind, mesh, grid) for all seven second-order kinds.
fn patch_meshes() -> Vec<(CellKind, VolumeMesh, Grid)> {
    let mut out = Vec::new();
    for kind in KINDS {
        let (mesh, grid) = distorted(kind, 3, 0.25);
        for complete in if kind == BlockKind::Tet { vec![false] } else { vec![false, true] } {
            let high = raise_order(&mesh, complete).unwrap();
            out.push((CellKind::of(&high.cells()[0]), high, grid));
        }
    }
    let kinds: Vec<CellKind> = out.iter().map(|m| m.0).collect();
    for k in CellKind::SECOND_ORDER {
        assert!(kinds.contains(&k), "{k:?} has a patch mesh");
    }
    out
}

/// Dirichlet u = A x + c on every boundary node of `mesh`; the interior nodes
/// must follow and the stresses be constant.
fn displacement_patch(mesh: &VolumeMesh, label: &str) {
    let on_boundary = mesh.boundary().unwrap().used_points();
    assert!(on_boundary.iter().any(|b| !b), "{label}: no interior node");
    let mut bc = Dirichlet::new();
    for (p, &x) in mesh.points().iter().enumerate() {
        if on_boundary[p] {
            bc.fix(p, affine(x).map(Some));
        }
    }
    let k = stiffness(mesh, &material()).unwrap();
    let u = solve(&k, &vec![0.0; k.nrows], &bc).unwrap();
    check_affine(mesh, &u, label);
}

/// The identity block of `kind` raised, then every point (mid-edge and centre
/// nodes included) moved by the smooth warp: curved isoparametric cells.
fn curved_block(n: usize, kind: BlockKind, complete: bool) -> VolumeMesh {
    let straight = raise_order(&block(n, n, n, |u, v, w| [u, v, w], kind), complete).unwrap();
    let points = straight.points().iter().map(|x| warp(x[0], x[1], x[2])).collect();
    VolumeMesh::new(points, straight.cells().to_vec()).unwrap()
}

#[test]
fn displacement_patch_test_every_second_order_element() {
    for (kind, mesh, _) in patch_meshes() {
        displacement_patch(&mesh, &format!("{kind:?} displacement patch"));
    }
}

/// The mixed Gmsh mesh (tets, hexes, pyramids) raised both ways: conforming
/// across tet–pyramid and hex–pyramid faces, and it passes the patch test.
#[test]
fn raised_mixed_mesh_conforms_and_passes_the_patch_test() {
    let mesh = hybrid();
    for complete in [false, true] {
        let high = raise_order(&mesh, complete).unwrap();
        assert_eq!(high.boundary().unwrap().n_faces(), mesh.boundary().unwrap().n_faces());
        displacement_patch(&high, &format!("hybrid_pyramid raised (complete {complete})"));
    }
}

/// Curved hexes and prisms pass the patch test too: for their isoparametric
/// maps cof(J)ᵀ∇_ξN_i has degree ≤ 5 in each hex variable (≤ 4 in (ξ, η) and
/// ≤ 5 in ζ for prisms), which the stiffness rules integrate exactly, so
/// Σ_e ∫_e ∇N_i dV = 0 holds discretely at interior nodes. (Curved Tet10s need a
/// degree-3 rule for that and are not claimed.)
#[test]
fn displacement_patch_test_on_curved_hexes_and_prisms() {
    for kind in [BlockKind::Hex, BlockKind::Prism] {
        for complete in [false, true] {
            let mesh = curved_block(3, kind, complete);
            let label = format!("curved {:?}", CellKind::of(&mesh.cells()[0]));
            displacement_patch(&mesh, &label);
        }
    }
}

/// The exact traction σ·n on the whole boundary of second-order faces (Tri6,
/// Quad8, Quad9), 3-2-1 supports: the traction load on second-order faces is
/// consistent.
#[test]
fn traction_patch_test_every_second_order_element() {
    let sigma = tensor(&affine_stress(&material()));
    for (kind, mesh, grid) in patch_meshes() {
        let f = traction(&mesh.boundary().unwrap(), |_, n| {
            std::array::from_fn(|i| (0..3).map(|j| sigma[i][j] * n[j]).sum())
        });
        let p = [grid.point(0, 0, 0), grid.point(3, 0, 0), grid.point(0, 3, 0)];
        let mut bc = Dirichlet::new();
        let u = p.map(|p| affine(mesh.points()[p]));
        bc.fix(p[0], u[0].map(Some));
        bc.fix(p[1], [None, Some(u[1][1]), Some(u[1][2])]);
        bc.fix(p[2], [None, None, Some(u[2][2])]);
        let k = stiffness(&mesh, &material()).unwrap();
        let sol = solve(&k, &f, &bc).unwrap();
        check_affine(&mesh, &sol, &format!("{kind:?} traction patch"));
    }
}

/// Manufactured solution on the warped cube with curved isoparametric cells
/// (the identity block raised, then every point, mid-edge nodes included, moved
/// by the warp), n = 2, 4, 8: fitted rates of the relative L2 and H1 errors.
fn rates(kind: BlockKind, complete: bool) -> (f64, f64) {
    let m = Material::new(100.0, 0.3).unwrap();
    let (mut h, mut l2, mut h1) = (Vec::new(), Vec::new(), Vec::new());
    for n in [2, 4, 8] {
        let mesh = curved_block(n, kind, complete);
        let boundary = mesh.boundary().unwrap().used_points();
        let mut bc = Dirichlet::new();
        for (p, &x) in mesh.points().iter().enumerate() {
            if boundary[p] {
                bc.fix(p, exact(x).map(Some));
            }
        }
        let k = stiffness(&mesh, &m).unwrap();
        let f = body_force(&mesh, load(&m)).unwrap();
        let u = solve(&k, &f, &bc).unwrap();
        let e = error_sums(&mesh, &m, &u, exact, gradient).relative();
        println!("{kind:?} n = {n}: relative L2 {:.3e}, H1 {:.3e}", e.l2, e.h1);
        h.push(1.0 / n as f64);
        l2.push(e.l2);
        h1.push(e.h1);
    }
    (fitted_rate(&h, &l2), fitted_rate(&h, &h1))
}

#[test]
fn tet10_converges_at_third_and_second_order() {
    let (l2, h1) = rates(BlockKind::Tet, false);
    println!("Tet10 fitted rates: L2 {l2:.3}, H1 {h1:.3}");
    assert!(l2 >= 2.9, "Tet10 L2 rate {l2:.3} < 2.9");
    assert!(h1 >= 1.9, "Tet10 H1 rate {h1:.3} < 1.9");
}

#[test]
fn hex27_converges_at_third_and_second_order() {
    let (l2, h1) = rates(BlockKind::Hex, true);
    println!("Hex27 fitted rates: L2 {l2:.3}, H1 {h1:.3}");
    assert!(l2 >= 2.9, "Hex27 L2 rate {l2:.3} < 2.9");
    assert!(h1 >= 1.9, "Hex27 H1 rate {h1:.3} < 1.9");
}

/// Curved cells: the faces of the mesh are curved Tri6/Quad9 patches; the
/// traction of a constant stress summed over a closed curved surface is
/// ∮ σ n dA = 0 and ⅓∮ x·n dA is the volume ∫ dV (quadrature of the cells).
#[test]
fn curved_face_loads_close_and_give_the_volume() {
    for (kind, complete) in KINDS.into_iter().flat_map(|k| raised_kinds(k).map(|c| (k, c))) {
        let mesh = curved_block(2, kind, complete);
        let boundary = mesh.boundary().unwrap();
        // ⅓ Σ_p x_p·f_p with t = n/3: ∫ N_i (x·n)/3 summed = ⅓∮ x·n dA when x = Σ N_i x_i.
        let f = traction(&boundary, |_, n| n);
        let (mut total, mut xn) = ([0.0; 3], 0.0);
        for (p, x) in mesh.points().iter().enumerate() {
            for c in 0..3 {
                total[c] += f[3 * p + c];
                xn += x[c] * f[3 * p + c] / 3.0;
            }
        }
        let volume: f64 = cell_volumes(&mesh).unwrap().iter().sum();
        assert!(max_abs(&total) < 1e-10, "{kind:?}: ∮ n dA = {total:?}");
        assert!((xn - volume).abs() < 1e-4 * volume, "{kind:?}: ⅓∮ x·n dA = {xn} vs volume {volume}");
        assert!(mesh.cells().iter().all(Cell::is_second_order));
    }
}
