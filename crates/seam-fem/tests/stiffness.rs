//! The global stiffness: rigid-body modes, symmetry, determinism, errors.

use crate::common;

use common::{distorted, hybrid, max_abs, KINDS};
use seam::{Cell, CsrMatrix, VolumeMesh};
use seam_fem::generate::{block, raise_order, BlockKind, Grid, Side};
use seam_fem::solve::solve;
use seam_fem::{
    body_force, rigid_body_modes, stiffness, stiffness_times, AssemblyError, Dirichlet, Material,
    MaterialError, SolveError,
};

fn check_rigid_modes(mesh: &VolumeMesh, label: &str) {
    let k = stiffness(mesh, &Material::new(210e3, 0.3).unwrap()).unwrap();
    let knorm = k.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (m, r) in rigid_body_modes(mesh.points()).iter().enumerate() {
        let kr = k.mul_vec(r, 1);
        let rel = max_abs(&kr) / (knorm * max_abs(r));
        assert!(rel < 1e-12, "{label}: |K r_{m}| / (|K| |r|) = {rel:e}");
    }
}

#[test]
fn rigid_body_modes_are_in_the_kernel() {
    for kind in KINDS {
        let (mesh, _) = distorted(kind, 3, 0.2);
        check_rigid_modes(&mesh, &format!("{kind:?}"));
    }
    check_rigid_modes(&hybrid(), "hybrid_pyramid");
}

fn is_symmetric(k: &CsrMatrix) -> bool {
    (0..k.nrows).all(|i| {
        let (c, v) = k.row(i);
        c.iter().zip(v).all(|(&j, &x)| k.get(j, i).to_bits() == x.to_bits())
    })
}

#[test]
fn stiffness_is_symmetric_with_sorted_rows() {
    let (mesh, _) = distorted(BlockKind::Prism, 3, 0.2);
    let k = stiffness(&mesh, &Material::new(1.0, 0.3).unwrap()).unwrap();
    assert_eq!(k.nrows, 3 * mesh.points().len());
    assert!(is_symmetric(&k));
    for i in 0..k.nrows {
        let (c, _) = k.row(i);
        assert!(c.windows(2).all(|w| w[0] < w[1]));
        assert!(c.binary_search(&i).is_ok(), "row {i} has no diagonal");
    }
}

#[test]
fn assembly_is_identical_on_one_and_two_threads() {
    let m = Material::new(1.0, 0.3).unwrap();
    let run = |threads: usize, mesh: &VolumeMesh| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            (stiffness(mesh, &m).unwrap(), body_force(mesh, |x| [x[1], x[0] * x[2], 1.0]).unwrap())
        })
    };
    for mesh in [distorted(BlockKind::Tet, 5, 0.2).0, hybrid()] {
        let (k1, f1) = run(1, &mesh);
        let (k2, f2) = run(2, &mesh);
        assert_eq!(k1.indptr, k2.indptr);
        assert_eq!(k1.indices, k2.indices);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&k1.values), bits(&k2.values));
        assert_eq!(bits(&f1), bits(&f2));
    }
}

#[test]
fn bad_material_is_an_error() {
    assert_eq!(Material::new(-2.0, 0.3), Err(MaterialError::Young(-2.0)));
    assert_eq!(
        Material::new(1.0, 0.5).unwrap_err().to_string(),
        "Poisson's ratio ν = 0.5 must lie in (-1, 0.5)"
    );
}

#[test]
fn singular_systems_are_errors() {
    let mesh = block(2, 2, 2, |u, v, w| [u, v, w], BlockKind::Hex);
    let grid = Grid::new(2, 2, 2);
    let k = stiffness(&mesh, &Material::new(1.0, 0.3).unwrap()).unwrap();
    let f = vec![0.0; k.nrows];
    // No conditions at all.
    let e = solve(&k, &f, &Dirichlet::new()).unwrap_err();
    assert_eq!(e, SolveError::Singular);
    assert_eq!(
        e.to_string(),
        "the problem is singular: the body can move without deforming; add Dirichlet conditions"
    );
    // Only u_x fixed on a face: the body still slides in y and z.
    let mut bc = Dirichlet::new();
    bc.fix_all(grid.side_points(Side::XMin), [Some(0.0), None, None]);
    assert_eq!(solve(&k, &f, &bc), Err(SolveError::Singular));
    // All three translations fixed at one point, but rotations free.
    let mut bc = Dirichlet::new();
    bc.clamp([0]);
    assert_eq!(solve(&k, &f, &bc), Err(SolveError::Singular));
    // Two points clamped: rotation about the line through them is free.
    bc.clamp([grid.point(2, 2, 2)]);
    assert_eq!(solve(&k, &f, &bc), Err(SolveError::Singular));
    // 3-2-1: well posed.
    bc.fix(grid.point(2, 0, 0), [None, Some(0.0), None]);
    assert!(solve(&k, &f, &bc).is_ok());
}

#[test]
fn degenerate_cells_are_named() {
    let mut mesh = block(2, 1, 1, |u, v, w| [u, v, w], BlockKind::Tet);
    let mut cells = mesh.cells().to_vec();
    // A flat tet (four coplanar points) as cell 7.
    cells[7] = Cell::Tet4([0, 1, 3, 4]);
    mesh = VolumeMesh::new(mesh.points().to_vec(), cells).unwrap();
    let m = Material::new(1.0, 0.3).unwrap();
    assert_eq!(stiffness(&mesh, &m), Err(AssemblyError::DegenerateCell { cell: 7 }));
    // A hex folded onto itself (top face below the bottom face on one side).
    let p = vec![
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., -0.5],
        [1., 1., -0.5],
        [0., 1., 1.],
    ];
    let folded = VolumeMesh::new(p, vec![Cell::Hex8([0, 1, 2, 3, 4, 5, 6, 7])]).unwrap();
    assert_eq!(stiffness(&folded, &m), Err(AssemblyError::DegenerateCell { cell: 0 }));
}

/// K u formed cell by cell (what a PETSc solve uses once K has gone) is K's
/// product to round-off, on every cell kind, first and second order, and the
/// same bits on one and two threads.
#[test]
fn stiffness_times_is_k_times_u() {
    let m = Material::new(210e3, 0.3).unwrap();
    let mut meshes: Vec<(String, VolumeMesh)> =
        KINDS.iter().map(|&kind| (format!("{kind:?}"), distorted(kind, 3, 0.2).0)).collect();
    meshes.push(("hybrid_pyramid".into(), hybrid()));
    for (label, complete) in [("Hex20", false), ("Hex27", true)] {
        let (mesh, _) = distorted(BlockKind::Hex, 2, 0.2);
        meshes.push((label.into(), raise_order(&mesh, complete).unwrap()));
    }
    for (label, mesh) in &meshes {
        let u: Vec<f64> =
            (0..3 * mesh.points().len()).map(|i| ((i * 7919) % 101) as f64 / 50.0 - 1.0).collect();
        let k = stiffness(mesh, &m).unwrap();
        let expected = k.mul_vec(&u, 1);
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| stiffness_times(mesh, &m, &u).unwrap())
        };
        let ku = run(2);
        let scale = max_abs(&k.values) * max_abs(&u);
        let diff: Vec<f64> = ku.iter().zip(&expected).map(|(a, b)| a - b).collect();
        assert!(max_abs(&diff) < 1e-14 * scale, "{label}: |Ku − K·u| = {:e} of {scale:e}", max_abs(&diff));
        assert!(ku.iter().zip(run(1)).all(|(a, b)| a.to_bits() == b.to_bits()), "{label}: threads");
    }
    let mut cells = meshes[0].1.cells().to_vec();
    cells.truncate(1);
    let p = meshes[0].1.points().to_vec();
    let n = p.len();
    let flat = VolumeMesh::new(p.iter().map(|x| [x[0], x[1], 0.0]).collect(), cells).unwrap();
    assert_eq!(stiffness_times(&flat, &m, &vec![0.0; 3 * n]), Err(AssemblyError::DegenerateCell { cell: 0 }));
}
