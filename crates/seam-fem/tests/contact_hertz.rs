//! Hertz contact against the analytic solution: a³ = 3FR/(4E*),
//! p₀ = 3F/(2πa²), p(r) = p₀ √(1 − r²/a²), with a/R = 0.08 and the block
//! 12.5a wide and deep ([`seam_fem::scene::hertz`], a quarter model).
//!
//! Per mesh (slave element size h = 1.5a / n near the contact):
//! - the total contact force equals the applied force F/4 to 1e-8;
//! - the KKT conditions hold to 1e-8;
//! - the peak pressure (at the pole) is within 5 % of p₀, and the contact
//!   radius (the outermost active slave node on the symmetry axes) within one
//!   slave element of a;
//! - under refinement the error of p₀ decreases.
//!
//! Measured (`cargo test --release -p seam-fem --test contact_hertz -- --nocapture`),
//! h = 1.5a/n:
//!
//! | n | dofs | steps | active | p₀ error | a − a_Hertz | max \|p − p_Hertz\| / p₀ on the axes |
//! |---|---|---|---|---|---|---|
//! | 4 | 18 945 | 8 | 8 | +1.87 % | −0.67 h | 0.028 |
//! | 6 | 39 045 | 10 | 19 | +0.73 % | 0 | 0.124 (the node at r = a) |
//! | 8 | 61 050 | 10 | 30 | +0.17 % | −0.33 h | 0.057 |
//!
//! KKT residuals ≤ 3e-16, force errors ≤ 3e-13.
use seam_fem::scene::{hertz, Hertz};
use seam_fem::{Solution, SolveOptions};

struct Measured {
    h: f64,
    p0: f64,
    p0_exact: f64,
    a: f64,
    a_exact: f64,
    profile: f64,
}

/// p₀ at the pole, a from the outermost active node on y = 0 and x = 0, and
/// the largest |p − p_Hertz| / p₀ over slave nodes on the axes.
fn measure(p: &Hertz, s: &Solution, points: &[seam::Point3]) -> Measured {
    let i = s.interfaces[0].contact.as_ref().expect("a contact interface");
    let on_axis = |q: usize| points[q][2].abs() < 1e-12 && (points[q][0] == 0.0 || points[q][1] == 0.0);
    let r = |q: usize| points[q][0].hypot(points[q][1]);
    let pole = (0..points.len()).find(|&q| on_axis(q) && r(q) == 0.0).expect("a node at the pole");
    let a = (0..points.len()).filter(|&q| on_axis(q) && i.active[q]).map(r).fold(0.0, f64::max);
    let profile = (0..points.len())
        .filter(|&q| on_axis(q) && i.contact[q])
        .map(|q| (i.pressure[q] - p.pressure(r(q))).abs())
        .fold(0.0, f64::max)
        / p.peak_pressure();
    Measured {
        h: p.slave_size(),
        p0: i.pressure[pole],
        p0_exact: p.peak_pressure(),
        a,
        a_exact: p.contact_radius,
        profile,
    }
}

#[test]
fn hertz_contact_radius_and_peak_pressure() {
    let mut levels = Vec::new();
    for n in [4, 6, 8] {
        let p = Hertz { fine_cells: n, ..Hertz::default() };
        let problem = hertz(&p).unwrap();
        let s = problem.solve(&SolveOptions::default()).unwrap();
        let (report, contact) = (&s.report, s.report.contact.as_ref().expect("a contact report"));
        let force = -s.interfaces[0].force[2];
        let force_error = (force / (p.force() / 4.0) - 1.0).abs();
        let m = measure(&p, &s, problem.bodies[1].mesh.points());
        println!(
            "n = {n}: dofs {}, active {}, steps {}, KKT {:.1e}, force error {force_error:.1e}; \
             p0 {:.4} vs {:.4} ({:+.2} %), a {:.4} vs {:.4} ({:+.2} h), profile {:.3}; {:.1} s",
            report.dofs,
            contact.active,
            contact.steps.len(),
            contact.kkt.max(),
            m.p0,
            p.peak_pressure(),
            100.0 * (m.p0 / p.peak_pressure() - 1.0),
            m.a,
            p.contact_radius,
            (m.a - p.contact_radius) / m.h,
            m.profile,
            report.seconds.factorization + report.seconds.setup + report.seconds.assembly,
        );
        assert!(contact.kkt.max() <= 1e-8, "KKT {:?}", contact.kkt);
        assert!(force_error <= 1e-8, "contact force {force} against F/4 = {}", p.force() / 4.0);
        levels.push(m);
    }
    for m in &levels {
        let (e_p0, e_a) = (m.p0 / m.p0_exact - 1.0, (m.a - m.a_exact).abs());
        assert!(e_p0.abs() <= 0.05, "p0 {} against {} ({:+.2} %)", m.p0, m.p0_exact, 100.0 * e_p0);
        assert!(
            e_a <= m.h * (1.0 + 1e-9),
            "a {} against {}: more than one slave element h = {}",
            m.a,
            m.a_exact,
            m.h
        );
    }
    for pair in levels.windows(2) {
        let error = |m: &Measured| (m.p0 / m.p0_exact - 1.0).abs();
        assert!(
            error(&pair[1]) < error(&pair[0]),
            "the p0 error does not decrease: h {} → {}",
            pair[0].h,
            pair[1].h
        );
    }
}
