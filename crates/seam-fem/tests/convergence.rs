//! Convergence to a manufactured smooth solution
//!
//! ```text
//! u = s (sin x, z cos y, x y z),   b = −div σ(u) = −s [μ Δu + (λ+μ) ∇(div u)]
//! div u = s (cos x − z sin y + x y),   Δu = s (−sin x, −z cos y, 0)
//! ```
//!
//! on a warped cube, Dirichlet u on the whole boundary, meshes of 4, 8, 16 cells
//! per side. Linear elements: ‖u − u_h‖_L2 = O(h²), |u − u_h|_H1 and the energy
//! error O(h). The test prints the measured rates.

use crate::common;

use common::manufactured::{exact, gradient, load};
use common::{error_sums, warp};
use seam_fem::generate::{block, BlockKind};
use seam_fem::solve::solve;
use seam_fem::{body_force, stiffness, Dirichlet, Material};

fn run(kind: BlockKind) {
    let m = Material::new(100.0, 0.3).unwrap();
    let mut results = Vec::new();
    for n in [4, 8, 16] {
        let mesh = block(n, n, n, warp, kind);
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
        results.push((n, error_sums(&mesh, &m, &u, exact, gradient).relative()));
    }
    println!("{kind:?}: n, relative errors L2 / H1 / energy, rates");
    for (i, (n, e)) in results.iter().enumerate() {
        if i == 0 {
            println!("  {n:>2}  {:.3e} {:.3e} {:.3e}", e.l2, e.h1, e.energy);
            continue;
        }
        let p = &results[i - 1].1;
        let rate = |a: f64, b: f64| (a / b).log2();
        let (r0, r1, re) = (rate(p.l2, e.l2), rate(p.h1, e.h1), rate(p.energy, e.energy));
        println!(
            "  {n:>2}  {:.3e} {:.3e} {:.3e}   rates L2 {r0:.3}  H1 {r1:.3}  energy {re:.3}",
            e.l2, e.h1, e.energy
        );
        assert!(r0 >= 1.8, "{kind:?}: L2 rate {r0:.3} < 1.8 at n = {n}");
        assert!(r1 >= 0.9 && re >= 0.9, "{kind:?}: H1 / energy rates {r1:.3} / {re:.3} < 0.9 at n = {n}");
    }
}

#[test]
fn hex_converges() {
    run(BlockKind::Hex);
}

#[test]
fn tet_converges() {
    run(BlockKind::Tet);
}
