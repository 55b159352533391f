//! I8: on curved interfaces meshed independently, with gaps and overlaps of size
//! O(h²), the L2(Γs) error of T f for a smooth f decays as O(h²): fitted rate ≥ 1.9
//! over four refinements (16 to 128 cells across), for standard and dual multipliers, triangle and quad
//! slaves.
//!
//! The error of a refinement is ‖e‖ = (eᵀ M e)^½ with e = T f_m − f_s (nodal
//! values of f on each side) and M the slave mass matrix (the standard D of a
//! fully covered slave), on the slave nodes whose support is fully covered.

use seam::generate::{cylinder, patch, Pattern};
use seam::{assemble, MaxGap, MortarOptions, Multiplier, Point3, SurfaceMesh};

/// A smooth field in 3D.
fn f(p: Point3) -> f64 {
    (1.3 * p[0]).sin() * p[1] + (0.7 * p[2]).cos() + p[0] * p[2]
}

/// A sphere patch of radius `r`: polar angle θ ∈ [0.4, 1.4], azimuth φ ∈ [0, 1.2].
/// Its bilinear quads are warped.
fn sphere(r: f64) -> impl Fn(f64, f64) -> Point3 {
    move |u, v| {
        let (theta, phi) = (0.4 + 1.0 * u, 1.2 * v);
        [r * theta.sin() * phi.cos(), r * theta.sin() * phi.sin(), r * theta.cos()]
    }
}

#[derive(Clone, Copy)]
enum Surface {
    Cylinder,
    Sphere,
}

/// Slave and master meshes at refinement `n` (slave n × n cells, master with
/// about 1.3 n cells of the other type, radius 1 + 0.3 h² for the master: a gap
/// of O(h²), or an overlap with `sign` = −1).
fn meshes(surface: Surface, n: usize, slave_quads: bool, sign: f64) -> (SurfaceMesh, SurfaceMesh) {
    let h = 1.0 / n as f64;
    let r = 1.0 + sign * 0.3 * h * h;
    let m = (1.3 * n as f64).round() as usize;
    let jitter = |seed| Pattern::JitteredTriangles { amplitude: 0.2, seed };
    let (slave_pattern, master_pattern) =
        if slave_quads { (Pattern::Quads, jitter(n as u64)) } else { (jitter(n as u64), Pattern::Quads) };
    match surface {
        Surface::Cylinder => (
            patch(m, m, master_pattern, cylinder(r, 1.2, 1.0)),
            patch(n, n, slave_pattern, cylinder(1.0, 1.2, 1.0)),
        ),
        Surface::Sphere => (patch(m, m, master_pattern, sphere(r)), patch(n, n, slave_pattern, sphere(1.0))),
    }
}

/// ‖T f_m − f_s‖ in the slave mass-matrix norm, on fully covered slave nodes.
fn error(master: &SurfaceMesh, slave: &SurfaceMesh, multiplier: Multiplier) -> f64 {
    let o = MortarOptions { multiplier, max_gap: MaxGap::Relative(0.5), ..Default::default() };
    let m = assemble(master, slave, &o).unwrap();
    let mass = assemble(master, slave, &MortarOptions::default()).unwrap().d;
    let fm: Vec<f64> = master.points().iter().map(|&p| f(p)).collect();
    let tf = m.transfer().unwrap().apply(&fm, 1);
    let e: Vec<f64> = (0..slave.n_points())
        .map(|p| if m.node_coverage[p] > 1.0 - 1e-9 { tf[p] - f(slave.points()[p]) } else { 0.0 })
        .collect();
    let me = mass.mul_vec(&e, 1);
    e.iter().zip(&me).map(|(a, b)| a * b).sum::<f64>().sqrt()
}

/// Least-squares slope of log(error) against log(h).
fn fitted_rate(hs: &[f64], errors: &[f64]) -> f64 {
    let x: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let y: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let (mx, my) = (x.iter().sum::<f64>() / x.len() as f64, y.iter().sum::<f64>() / y.len() as f64);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

fn check_rate(surface: Surface, slave_quads: bool, multiplier: Multiplier, sign: f64) {
    // 8 cells across a 1.2-rad patch is still pre-asymptotic: start at 16.
    let levels = [16, 32, 64, 128];
    let mut hs = Vec::new();
    let mut errors = Vec::new();
    for n in levels {
        let (master, slave) = meshes(surface, n, slave_quads, sign);
        hs.push(1.0 / n as f64);
        errors.push(error(&master, &slave, multiplier));
    }
    let rate = fitted_rate(&hs, &errors);
    let label = format!(
        "{} {} slave, {multiplier:?}, {}",
        match surface {
            Surface::Cylinder => "cylinder",
            Surface::Sphere => "sphere",
        },
        if slave_quads { "quad" } else { "triangle" },
        if sign > 0.0 { "gap" } else { "overlap" }
    );
    let shown: Vec<String> = errors.iter().map(|e| format!("{e:.2e}")).collect();
    eprintln!("{label}: errors {}, rate {rate:.3}", shown.join(" "));
    assert!(rate >= 1.9, "{label}: L2 rate {rate:.3} < 1.9 (errors {errors:?})");
}

#[test]
fn cylinder_transfer_converges_at_second_order() {
    for multiplier in [Multiplier::Standard, Multiplier::Dual] {
        for slave_quads in [true, false] {
            check_rate(Surface::Cylinder, slave_quads, multiplier, 1.0);
        }
    }
    check_rate(Surface::Cylinder, true, Multiplier::Standard, -1.0);
}

#[test]
fn sphere_transfer_converges_at_second_order() {
    for multiplier in [Multiplier::Standard, Multiplier::Dual] {
        for slave_quads in [true, false] {
            check_rate(Surface::Sphere, slave_quads, multiplier, 1.0);
        }
    }
    check_rate(Surface::Sphere, false, Multiplier::Dual, -1.0);
}
