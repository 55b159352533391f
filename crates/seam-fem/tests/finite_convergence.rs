//! Convergence of glued hyperelastic bodies in finite deformation: a
//! manufactured solution u* = s (sin(x + z), z cos y, x y z), s = 0.1
//! (strains up to about 20 %), on the unit cube cut at z = 1/2 into two
//! neo-Hookean blocks meshed independently (the master below 1.5× finer than
//! the slave above), glued with dual multipliers in the reference
//! configuration; the body force b = −Div P(F(u*)) (P = F S, its divergence
//! by central differences of the law's stress, step 10⁻⁴), u* prescribed on
//! every outer face. Relative L2 errors over both bodies by volume rules of
//! degree 5, fitted rates over three refinements: ≥ 1.9 with Hex8, ≥ 2.8 with
//! Hex27 (`-- --nocapture` prints the tables). Measured:
//!
//! | cells | slave n (master ⌈1.5 n⌉) | relative L2 errors | fitted rate |
//! |---|---|---|---|
//! | Hex8 | 2, 4, 8 | 3.46e-2, 8.00e-3, 1.99e-3 | 2.06 |
//! | Hex27 | 2, 4, 6 | 1.79e-3, 2.61e-4, 7.92e-5 | 2.83 (2.77 then 2.94) |
//!
//! (Hex27 from n = 1, 2, 4 fits 2.63: n = 1, one cell across, is not yet
//! asymptotic.)

use crate::common::{error_sums, fitted_rate, material};
use seam::{Multiplier, Point3, SurfaceMesh, VolumeMesh};
use seam_fem::generate::{block, raise_order, BlockKind};
use seam_fem::hyperelastic::Hyperelastic;
use seam_fem::{body_force, Body, Coupling, Dirichlet, Interface, SolveOptions};

const S: f64 = 0.1;

fn exact(x: Point3) -> [f64; 3] {
    [S * (x[0] + x[2]).sin(), S * x[2] * x[1].cos(), S * x[0] * x[1] * x[2]]
}

fn gradient(x: Point3) -> [[f64; 3]; 3] {
    let c = (x[0] + x[2]).cos();
    [
        [S * c, 0.0, S * c],
        [0.0, -S * x[2] * x[1].sin(), S * x[1].cos()],
        [S * x[1] * x[2], S * x[0] * x[2], S * x[0] * x[1]],
    ]
}

/// The first Piola–Kirchhoff stress P = F S at x.
fn piola(law: &Hyperelastic, x: Point3) -> [[f64; 3]; 3] {
    let g = gradient(x);
    let f: [[f64; 3]; 3] = std::array::from_fn(|a| std::array::from_fn(|k| g[a][k] + f64::from(a == k)));
    let (s, _) = law.stress(&f).expect("F is invertible");
    std::array::from_fn(|a| std::array::from_fn(|k| (0..3).map(|j| f[a][j] * s[j][k]).sum()))
}

/// b = −Div P by central differences.
fn load(law: &Hyperelastic, x: Point3) -> [f64; 3] {
    let h = 1e-4;
    let mut b = [0.0; 3];
    for k in 0..3 {
        let shifted = |d: f64| {
            let mut y = x;
            y[k] += d;
            piola(law, y)
        };
        let (p, m) = (shifted(h), shifted(-h));
        for a in 0..3 {
            b[a] -= (p[a][k] - m[a][k]) / (2.0 * h);
        }
    }
    b
}

/// A block [0, 1]² × [z0, z0 + 1/2] of n × n × max(n/2, 1) cells, raised to
/// Hex27 with `second`; its face on z = 1/2 and u* on every other face.
fn part(n: usize, z0: f64, second: bool) -> (VolumeMesh, SurfaceMesh, Dirichlet) {
    let hex = block(n, n, (n / 2).max(1), |u, v, w| [u, v, z0 + 0.5 * w], BlockKind::Hex);
    let mesh = if second { raise_order(&hex, true).unwrap() } else { hex };
    let boundary = mesh.boundary().unwrap();
    let on_interface =
        |f: &seam::Face| f.nodes().iter().all(|&p| (boundary.points()[p][2] - 0.5).abs() < 1e-12);
    let faces: Vec<seam::Face> = boundary.faces().iter().copied().filter(|f| on_interface(f)).collect();
    let interface = SurfaceMesh::new(mesh.points().to_vec(), faces).unwrap();
    let mut dirichlet = Dirichlet::new();
    for face in boundary.faces().iter().filter(|f| !on_interface(f)) {
        for &p in face.nodes() {
            let u = exact(mesh.points()[p]);
            for c in 0..3 {
                dirichlet.fix_dof(3 * p + c, u[c]);
            }
        }
    }
    (mesh, interface, dirichlet)
}

/// The relative L2 error over both bodies at slave cells `n` (master 1.5 n,
/// rounded up).
fn level(n: usize, second: bool) -> f64 {
    let m = material();
    let law = Hyperelastic::neo_hookean(&m);
    let (lower, top, fix_lower) = part((3 * n).div_ceil(2), 0.0, second);
    let (upper, bottom, fix_upper) = part(n, 0.5, second);
    let body = |mesh, dirichlet| Body {
        mesh,
        material: m,
        load: body_force(mesh, |x| load(&law, x)).unwrap(),
        dirichlet,
        ties: Vec::new(),
    };
    let bodies = [body(&lower, fix_lower), body(&upper, fix_upper)];
    let interfaces = [Interface {
        master: 0,
        master_surface: &top,
        slave: 1,
        slave_surface: &bottom,
        options: seam::MortarOptions { multiplier: Multiplier::Dual, ..Default::default() },
        kind: Coupling::Glue,
        friction: 0.0,
    }];
    let solution =
        seam_fem::finite::solve_finite(&bodies, &[law, law], &interfaces, &SolveOptions::default()).unwrap();
    let sums = error_sums(&lower, &m, &solution.displacement[0], exact, gradient).plus(error_sums(
        &upper,
        &m,
        &solution.displacement[1],
        exact,
        gradient,
    ));
    sums.relative().l2
}

#[test]
fn manufactured_finite_strain_solution_on_glued_non_matching_blocks() {
    for (label, second, levels, bound) in [("Hex8", false, [2, 4, 8], 1.9), ("Hex27", true, [2, 4, 6], 2.8)] {
        let (mut hs, mut errors) = (Vec::new(), Vec::new());
        for n in levels {
            let e = level(n, second);
            println!("{label}: n_s = {n}, L2 {e:.3e}");
            hs.push(1.0 / n as f64);
            errors.push(e);
        }
        let rate = fitted_rate(&hs, &errors);
        println!("{label}: fitted L2 rate {rate:.2}");
        assert!(rate >= bound, "{label}: rate {rate} from {errors:?}");
    }
}
