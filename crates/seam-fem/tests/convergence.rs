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

mod common;

use common::warp;
use seam::{Point3, VolumeMesh};
use seam_fem::assembly::{geometry, map_point};
use seam_fem::generate::{block, BlockKind};
use seam_fem::{body_force, solve, stiffness, Dirichlet, ElementKind, Material};

const S: f64 = 1e-2;

fn exact(x: Point3) -> [f64; 3] {
    [S * x[0].sin(), S * x[2] * x[1].cos(), S * x[0] * x[1] * x[2]]
}

/// ∇u: g[a][k] = ∂u_a/∂x_k.
fn exact_gradient(x: Point3) -> [[f64; 3]; 3] {
    let [a, b, c] = x;
    [[S * a.cos(), 0.0, 0.0], [0.0, -S * c * b.sin(), S * b.cos()], [S * b * c, S * a * c, S * a * b]]
}

fn load(m: &Material) -> impl Fn(Point3) -> [f64; 3] + Sync {
    let (l, mu) = m.lame();
    move |x| {
        let [a, b, c] = x;
        let grad_div = [-a.sin() + b, -c * b.cos() + a, -b.sin()];
        let lap = [-a.sin(), -c * b.cos(), 0.0];
        std::array::from_fn(|i| -S * (mu * lap[i] + (l + mu) * grad_div[i]))
    }
}

struct Errors {
    l2: f64,
    h1: f64,
    energy: f64,
}

/// Relative L2, H1-seminorm and energy errors of u_h (quadrature of degree 5).
fn errors(mesh: &VolumeMesh, m: &Material, u: &[f64]) -> Errors {
    let (l, mu) = m.lame();
    let rules = ElementKind::ALL.map(|k| k.rule(5));
    let (mut e0, mut n0, mut e1, mut n1, mut ee, mut ne) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let energy = |g: &[[f64; 3]; 3]| {
        let eps: [[f64; 3]; 3] = std::array::from_fn(|a| std::array::from_fn(|k| 0.5 * (g[a][k] + g[k][a])));
        let tr = eps[0][0] + eps[1][1] + eps[2][2];
        let dd: f64 =
            (0..3).flat_map(|a| (0..3).map(move |k| (a, k))).map(|(a, k)| eps[a][k] * eps[a][k]).sum();
        l * tr * tr + 2.0 * mu * dd
    };
    for cell in mesh.cells() {
        let kind = ElementKind::of(cell);
        let x: Vec<Point3> = cell.nodes().iter().map(|&p| mesh.points()[p]).collect();
        let rule = &rules[kind as usize];
        for (xi, w) in rule.iter() {
            let geo = geometry(kind, &x, xi).unwrap();
            let wd = w * geo.det.abs();
            let n = kind.shape(xi);
            let y = map_point(kind, &x, xi);
            let (ue, ge) = (exact(y), exact_gradient(y));
            let mut uh = [0.0; 3];
            let mut gh = [[0.0; 3]; 3];
            for (i, &p) in cell.nodes().iter().enumerate() {
                for a in 0..3 {
                    uh[a] += n[i] * u[3 * p + a];
                    for k in 0..3 {
                        gh[a][k] += geo.grads[i][k] * u[3 * p + a];
                    }
                }
            }
            let ge_minus: [[f64; 3]; 3] =
                std::array::from_fn(|a| std::array::from_fn(|k| ge[a][k] - gh[a][k]));
            for a in 0..3 {
                e0 += wd * (ue[a] - uh[a]).powi(2);
                n0 += wd * ue[a].powi(2);
                for k in 0..3 {
                    e1 += wd * ge_minus[a][k].powi(2);
                    n1 += wd * ge[a][k].powi(2);
                }
            }
            ee += wd * energy(&ge_minus);
            ne += wd * energy(&ge);
        }
    }
    Errors { l2: (e0 / n0).sqrt(), h1: (e1 / n1).sqrt(), energy: (ee / ne).sqrt() }
}

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
        results.push((n, errors(&mesh, &m, &u)));
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
