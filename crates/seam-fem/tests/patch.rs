//! Patch tests: an affine displacement u = A x + c (constant stress) must be
//! reproduced exactly (to round-off) by every element type on distorted meshes,
//! whether it is imposed by Dirichlet conditions on the whole boundary or by the
//! exact traction σ·n with only the six conditions that remove rigid motions.

use crate::common;

use common::{
    affine, affine_stress, check_affine, distorted, hybrid, kind_name, material, max_abs, tensor, KINDS,
};
use seam::{Point3, SurfaceMesh, VolumeMesh};
use seam_fem::generate::{block, Grid, Side};
use seam_fem::solve::solve;
use seam_fem::{recover_stresses, stiffness, traction, Dirichlet};

const RTOL: f64 = 1e-10;

/// Dirichlet u = A x + c on every boundary point; the interior nodes must follow.
fn displacement_patch(mesh: &VolumeMesh, label: &str) {
    let boundary = mesh.boundary().unwrap();
    let on_boundary = boundary.used_points();
    let interior = on_boundary.iter().filter(|b| !**b).count();
    assert!(interior > 0, "{label}: no interior node");
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

#[test]
fn displacement_patch_test_every_element() {
    for kind in KINDS {
        let (mesh, _) = distorted(kind, 3, 0.25);
        displacement_patch(&mesh, &format!("{kind:?}"));
    }
}

#[test]
fn displacement_patch_test_mixed_gmsh_mesh() {
    let mesh = hybrid();
    let kinds: Vec<&str> = mesh.cells().iter().map(kind_name).collect();
    for k in ["tet", "hex", "pyramid"] {
        assert!(kinds.contains(&k), "the fixture has {k} cells");
    }
    displacement_patch(&mesh, "hybrid_pyramid");
}

/// The point nearest to `target`.
fn nearest(points: &[Point3], target: Point3) -> usize {
    let d = |x: &Point3| (0..3).map(|k| (x[k] - target[k]).powi(2)).sum::<f64>();
    (0..points.len()).min_by(|&a, &b| d(&points[a]).total_cmp(&d(&points[b]))).unwrap()
}

/// The 3-2-1 conditions: all of p0, (y, z) of p1, z of p2, at the exact values of
/// `exact` (p1 − p0 roughly along x, p2 − p0 roughly along y).
fn three_two_one(points: &[Point3], p: [usize; 3], exact: impl Fn(Point3) -> [f64; 3]) -> Dirichlet {
    let mut bc = Dirichlet::new();
    let u = p.map(|p| exact(points[p]));
    bc.fix(p[0], u[0].map(Some));
    bc.fix(p[1], [None, Some(u[1][1]), Some(u[1][2])]);
    bc.fix(p[2], [None, None, Some(u[2][2])]);
    bc
}

/// The exact traction σ·n on the whole (distorted, warped) boundary.
fn traction_patch(mesh: &VolumeMesh, p: [usize; 3], label: &str) {
    let sigma = tensor(&affine_stress(&material()));
    let boundary: SurfaceMesh = mesh.boundary().unwrap();
    let f = traction(&boundary, |_, n| std::array::from_fn(|i| (0..3).map(|j| sigma[i][j] * n[j]).sum()));
    let k = stiffness(mesh, &material()).unwrap();
    let u = solve(&k, &f, &three_two_one(mesh.points(), p, affine)).unwrap();
    check_affine(mesh, &u, label);
}

#[test]
fn traction_patch_test_every_element() {
    for kind in KINDS {
        let (mesh, grid) = distorted(kind, 3, 0.25);
        let p = [grid.point(0, 0, 0), grid.point(3, 0, 0), grid.point(0, 3, 0)];
        traction_patch(&mesh, p, &format!("{kind:?}"));
    }
    let mesh = hybrid();
    let pts = mesh.points();
    let p = [nearest(pts, [0.0; 3]), nearest(pts, [2.0, 0.0, 0.0]), nearest(pts, [0.0, 1.0, 0.0])];
    traction_patch(&mesh, p, "hybrid_pyramid");
}

/// The classic: a unit cube pulled by t = ±σ e_x on its x faces, free elsewhere,
/// gives u = σ/E (x, −ν y, −ν z) exactly.
#[test]
fn uniaxial_tension_on_loaded_faces_only() {
    let m = material();
    let (e, nu, s) = (m.young(), m.poisson(), 7.0);
    let exact = |x: Point3| [s / e * x[0], -nu * s / e * x[1], -nu * s / e * x[2]];
    let grid = Grid::new(3, 2, 4);
    for kind in KINDS {
        let mesh = block(3, 2, 4, |u, v, w| [u, v, w], kind);
        let k = stiffness(&mesh, &m).unwrap();
        let mut f = traction(&grid.side_faces(&mesh, Side::XMax).unwrap(), |_, _| [s, 0.0, 0.0]);
        let f_min = traction(&grid.side_faces(&mesh, Side::XMin).unwrap(), |_, n| [s * n[0], 0.0, 0.0]);
        f.iter_mut().zip(&f_min).for_each(|(a, b)| *a += b);
        let p = [grid.point(0, 0, 0), grid.point(3, 0, 0), grid.point(0, 2, 0)];
        let u = solve(&k, &f, &three_two_one(mesh.points(), p, exact)).unwrap();
        let ex: Vec<f64> = mesh.points().iter().flat_map(|&x| exact(x)).collect();
        let diff: Vec<f64> = u.iter().zip(&ex).map(|(a, b)| a - b).collect();
        let err = max_abs(&diff) / max_abs(&ex);
        assert!(err < RTOL, "{kind:?}: uniaxial error {err:e}");
        let st = recover_stresses(&mesh, &m, &u).unwrap();
        for c in &st.cell {
            assert!(
                (c[0] - s).abs() < RTOL * s && c[1..].iter().all(|v| v.abs() < RTOL * s),
                "{kind:?}: {c:?}"
            );
        }
    }
}

/// Cells raised for the enriched slave space ([`seam_fem::enrich`], the whole
/// boundary as the surface: Tet10 → Tet14, Hex20 → Hex27, the added points
/// off it tied to their cells' interpolants): u = A x + c on the boundary's
/// points, face centres included, is reproduced everywhere through
/// `solve_coupled` with the ties as constraints, to round-off.
#[test]
fn displacement_patch_test_enriched_cells() {
    use seam_fem::generate::{raise_order, BlockKind};
    use seam_fem::{solve_coupled, Body, SolveOptions};
    for kind in [BlockKind::Tet, BlockKind::Hex] {
        let mesh = raise_order(&distorted(kind, 3, 0.25).0, false).unwrap();
        let boundary = mesh.boundary().unwrap();
        let e = seam_fem::enrich(&mesh, &[&boundary]).unwrap().expect("Tri6 or Quad8 faces");
        let raised = e.mesh.cells().iter().filter(|c| c.kind() != mesh.cells()[0].kind()).count();
        assert!(raised > 0 && raised < mesh.cells().len() && !e.ties.is_empty(), "{kind:?}");
        let on_surface = e.surfaces[0].used_points();
        let mut bc = Dirichlet::new();
        for (p, &x) in e.mesh.points().iter().enumerate().filter(|&(p, _)| on_surface[p]) {
            bc.fix(p, affine(x).map(Some));
        }
        let load = vec![0.0; 3 * e.mesh.points().len()];
        let body = Body { mesh: &e.mesh, material: material(), load, dirichlet: bc, ties: e.ties };
        let solution = solve_coupled(&[body], &[], &SolveOptions::default()).unwrap();
        check_affine(&e.mesh, &solution.displacement[0], &format!("enriched {kind:?}"));
        let sigma = affine_stress(&material());
        for cell in recover_stresses(&e.mesh, &material(), &solution.displacement[0]).unwrap().cell {
            let err = (0..6).map(|k| (cell[k] - sigma[k]).abs()).fold(0.0, f64::max);
            assert!(err <= RTOL * max_abs(&sigma), "enriched {kind:?}: stress {cell:?}");
        }
    }
}
