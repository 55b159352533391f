//! The operator again after a few points move (`seam::reassemble`): with the
//! slave faces the move can change computed afresh and every other face's
//! block kept, it is the whole assembly on the moved surfaces bit for bit.

use seam::generate::{cylinder, flat, patch, quadratic_patch, Pattern};
use seam::{
    assemble, assemble_keeping, reassemble, slave_faces_near, CsrMatrix, FaceKind, MortarOptions, Multiplier,
    Point3, SurfaceMesh,
};

fn same_bits(a: &CsrMatrix, b: &CsrMatrix, what: &str) {
    assert_eq!(
        (a.nrows, a.ncols, &a.indptr, &a.indices),
        (b.nrows, b.ncols, &b.indptr, &b.indices),
        "{what}"
    );
    let bits = |m: &CsrMatrix| m.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert!(bits(a) == bits(b), "{what}: values differ");
}

/// `mesh` with point `p` moved by `delta`.
fn moved(mesh: &SurfaceMesh, p: usize, delta: Point3) -> SurfaceMesh {
    let mut points = mesh.points().to_vec();
    (0..3).for_each(|k| points[p][k] += delta[k]);
    SurfaceMesh::new(points, mesh.faces().to_vec()).unwrap()
}

/// Moves slave point `s` and master point `m` by `delta` and reassembles the
/// faces the move touches.
fn check(
    name: &str,
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    options: &MortarOptions,
    (s, m): (usize, usize),
) {
    let (first, kept) = assemble_keeping(master, slave, options).unwrap();
    let whole = assemble(master, slave, options).unwrap();
    same_bits(&first.b, &whole.b, &format!("{name}: kept B"));
    let h = 1e-4;
    let near = slave_faces_near(master, slave, options, 2.0 * h);
    let (master2, slave2) = (moved(master, m, [h, -h, h]), moved(slave, s, [-h, h, h]));
    let mut faces: Vec<usize> =
        (0..slave.n_faces()).filter(|&f| slave.faces()[f].nodes().contains(&s)).collect();
    for g in (0..master.n_faces()).filter(|&g| master.faces()[g].nodes().contains(&m)) {
        faces.extend(&near[g]);
    }
    faces.sort_unstable();
    faces.dedup();
    assert!(faces.len() < slave.n_faces() / 2, "{name}: {} of {} faces moved", faces.len(), slave.n_faces());
    let again = reassemble(&master2, &slave2, options, &kept, &faces).unwrap();
    let whole = assemble(&master2, &slave2, options).unwrap();
    same_bits(&again.b, &whole.b, &format!("{name}: B"));
    same_bits(&again.d, &whole.d, &format!("{name}: D"));
    assert_eq!(again.summary, whole.summary, "{name}: totals");
    assert_eq!(again.faces, whole.faces, "{name}: face statistics");
    assert_eq!(again.segments, whole.segments, "{name}: segments");
    assert_eq!(again.covered, whole.covered, "{name}: covered");
    assert_eq!(again.basis.is_some(), whole.basis.is_some(), "{name}: Q");
    // The move changed B: the kept blocks alone would be wrong.
    assert!(again.b.values != first.b.values, "{name}: the move changed nothing");
}

#[test]
fn reassembly_after_a_move_is_the_whole_assembly() {
    let options = |multiplier| MortarOptions { multiplier, record_segments: true, ..Default::default() };
    let slave = patch(13, 11, Pattern::Quads, flat(1.0, 1.0));
    let master = patch(9, 10, Pattern::JitteredTriangles { amplitude: 0.25, seed: 7 }, flat(1.0, 1.0));
    for m in [Multiplier::Standard, Multiplier::Dual, Multiplier::Lumped] {
        check(&format!("flat {m:?}"), &master, &slave, &options(m), (60, 45));
    }
    let slave = patch(12, 9, Pattern::Quads, cylinder(1.0, std::f64::consts::FRAC_PI_2, 1.0));
    let master = patch(10, 7, Pattern::Triangles, cylinder(1.01, std::f64::consts::FRAC_PI_2, 1.0));
    check("cylinder", &master, &slave, &options(Multiplier::Dual), (50, 40));
    let x = cylinder(1.0, std::f64::consts::FRAC_PI_2, 1.0);
    let slave = quadratic_patch(6, 5, FaceKind::Quad8, None, &x);
    let master = quadratic_patch(
        5,
        4,
        FaceKind::Tri6,
        Some((0.2, 3)),
        cylinder(1.002, std::f64::consts::FRAC_PI_2, 1.0),
    );
    check("second order, transformed", &master, &slave, &options(Multiplier::Dual), (40, 30));
}

#[test]
fn reassembly_refuses_kept_blocks_of_another_surface() {
    let slave = patch(4, 4, Pattern::Quads, flat(1.0, 1.0));
    let master = patch(3, 3, Pattern::Triangles, flat(1.0, 1.0));
    let options = MortarOptions::default();
    let (_, kept) = assemble_keeping(&master, &slave, &options).unwrap();
    let other = patch(5, 4, Pattern::Quads, flat(1.0, 1.0));
    assert!(reassemble(&master, &other, &options, &kept, &[0]).is_err());
    assert!(reassemble(&master, &slave, &options, &kept, &[3, 1]).is_err());
    assert!(reassemble(&master, &slave, &options, &kept, &[16]).is_err());
}
