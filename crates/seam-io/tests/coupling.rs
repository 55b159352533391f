//! The mortar operator on meshes really made by Gmsh (unstructured triangles,
//! mixed triangles and quads): invariants I1, I2, I4 and I7 of docs/verification.md (invariants).

use seam::{assemble, MortarOptions, Multiplier, SurfaceMesh};
use std::path::PathBuf;

fn fixture(name: &str, group: Option<&str>) -> SurfaceMesh {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name);
    seam_io::read_surface_file(&path, group).unwrap()
}

#[test]
fn gmsh_unstructured_triangles_and_mixed_mesh_couple_exactly() {
    let tris = fixture("square_tri.v41.bin.msh", Some("interface"));
    let mixed = fixture("square_mixed.v22.ascii.msh", Some("interface"));
    let linear = |p: &[f64; 3]| 1.0 - 0.7 * p[0] + 2.5 * p[1];
    for (master, slave) in [(&tris, &mixed), (&mixed, &tris)] {
        for multiplier in [Multiplier::Standard, Multiplier::Dual, Multiplier::Lumped] {
            let o = MortarOptions { multiplier, ..Default::default() };
            let m = assemble(master, slave, &o).unwrap();
            // I2: the unit square is covered exactly.
            assert!((m.summary.covered_area - 1.0).abs() < 1e-13);
            assert!((m.d.sum() - 1.0).abs() < 1e-13 && (m.b.sum() - 1.0).abs() < 1e-13);
            // I1: rows of D and B agree.
            for (d, b) in m.d.row_sums().iter().zip(m.b.row_sums()) {
                assert!((d - b).abs() < 1e-15, "{d} vs {b}");
            }
            // I4: linear fields are reproduced (not with lumping).
            let t = m.transfer().unwrap();
            let fm: Vec<f64> = master.points().iter().map(linear).collect();
            let tf = t.apply(&fm, 1);
            let err = slave
                .points()
                .iter()
                .enumerate()
                .filter(|&(p, _)| m.on_surface[p])
                .map(|(p, x)| (tf[p] - linear(x)).abs())
                .fold(0.0, f64::max);
            if multiplier == Multiplier::Lumped {
                assert!(err > 1e-6, "lumping does not reproduce linear fields");
            } else {
                assert!(err < 1e-12, "{multiplier:?}: linear field error {err:e}");
            }
            // I7: one thread gives the same bits.
            let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
            let single = pool.install(|| assemble(master, slave, &o).unwrap());
            assert!(single.b == m.b && single.d == m.d);
        }
    }
}
