//! Mortar gluing of two bodies: patch tests (standard and dual multipliers reproduce
//! an affine displacement across non-matching, rotated meshes), equilibrium.
mod common;

use common::{affine, affine_stress, max_abs, tensor};
use seam::{Facing, MortarOptions, Multiplier, Point3, SurfaceMesh, VolumeMesh};
use seam_fem::generate::{block, BlockKind, Grid, Side};
use seam_fem::glue::{solve_glued, Body, Interface, Solver};
use seam_fem::{recover_stresses, traction, Dirichlet, Material};

/// A rotation about the axis (1, 2, 3) by 0.4 rad.
fn rotate(x: Point3) -> Point3 {
    let a: [f64; 3] = [1.0, 2.0, 3.0];
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let k = [a[0] / l, a[1] / l, a[2] / l];
    let (s, c) = 0.4f64.sin_cos();
    let kx = [k[1] * x[2] - k[2] * x[1], k[2] * x[0] - k[0] * x[2], k[0] * x[1] - k[1] * x[0]];
    let kdx = k[0] * x[0] + k[1] * x[1] + k[2] * x[2];
    std::array::from_fn(|i| x[i] * c + kx[i] * s + k[i] * kdx * (1.0 - c))
}

struct Block {
    mesh: VolumeMesh,
    grid: Grid,
}

fn make(n: [usize; 3], z: [f64; 2], kind: BlockKind, rotated: bool) -> Block {
    let mesh = block(
        n[0],
        n[1],
        n[2],
        |u, v, w| {
            let x = [u, v, z[0] + (z[1] - z[0]) * w];
            if rotated {
                rotate(x)
            } else {
                x
            }
        },
        kind,
    );
    Block { mesh, grid: Grid::new(n[0], n[1], n[2]) }
}

/// Loads σn of the affine field on every side but `skip`.
fn affine_load(b: &Block, material: &Material, skip: &[Side]) -> Vec<f64> {
    let s = tensor(&affine_stress(material));
    let mut f = vec![0.0; 3 * b.mesh.points().len()];
    for side in Side::ALL.into_iter().filter(|s| !skip.contains(s)) {
        let faces = b.grid.side_faces(&b.mesh, side).unwrap();
        let t = traction(&faces, |_, n| {
            std::array::from_fn(|i| s[i][0] * n[0] + s[i][1] * n[1] + s[i][2] * n[2])
        });
        for (a, b) in f.iter_mut().zip(t) {
            *a += b;
        }
    }
    f
}

fn patch(lower: Block, upper: Block, multiplier: Multiplier) -> f64 {
    let material = Material::new(1000.0, 0.3).unwrap();
    let mut fixed = Dirichlet::new();
    for p in lower.grid.side_points(Side::ZMin) {
        fixed.fix(p, affine(lower.mesh.points()[p]).map(Some));
    }
    let bodies = [
        Body {
            mesh: &lower.mesh,
            material,
            load: affine_load(&lower, &material, &[Side::ZMin, Side::ZMax]),
            dirichlet: fixed,
        },
        Body {
            mesh: &upper.mesh,
            material,
            load: affine_load(&upper, &material, &[Side::ZMin]),
            dirichlet: Dirichlet::new(),
        },
    ];
    let master: SurfaceMesh = lower.grid.side_faces(&lower.mesh, Side::ZMax).unwrap();
    let slave: SurfaceMesh = upper.grid.side_faces(&upper.mesh, Side::ZMin).unwrap();
    let options = MortarOptions { multiplier, facing: Facing::Opposite, ..MortarOptions::default() };
    let interfaces =
        [Interface { master: 0, master_surface: &master, slave: 1, slave_surface: &slave, options }];
    let sol = solve_glued(&bodies, &interfaces, Solver::Direct).unwrap();
    println!("{multiplier:?}: {:?}", sol.report);
    let mut err = 0.0f64;
    let scale = 2e-3;
    for (b, body) in bodies.iter().enumerate() {
        for (p, x) in body.mesh.points().iter().enumerate() {
            let exact = affine(*x);
            for c in 0..3 {
                err = err.max((sol.displacement[b][3 * p + c] - exact[c]).abs() / scale);
            }
        }
        let s = recover_stresses(body.mesh, &material, &sol.displacement[b]).unwrap();
        let exact = affine_stress(&material);
        let smax = max_abs(&exact);
        for cell in &s.cell {
            for k in 0..6 {
                err = err.max((cell[k] - exact[k]).abs() / smax);
            }
        }
    }
    err
}

#[test]
fn patch_test_non_matching_blocks() {
    for multiplier in [Multiplier::Standard, Multiplier::Dual, Multiplier::Lumped] {
        for rotated in [false, true] {
            let lower = make([5, 4, 3], [0.0, 1.0], BlockKind::Hex, rotated);
            let upper = make([3, 2, 2], [1.0, 1.7], BlockKind::Tet, rotated);
            let err = patch(lower, upper, multiplier);
            println!("{multiplier:?} rotated {rotated}: {err:.2e}");
        }
    }
}
