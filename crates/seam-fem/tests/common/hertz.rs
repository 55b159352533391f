//! The Hertz tests' solve and measurements ([`seam_fem::scene::hertz`]).

use seam_fem::scene::{hertz, Hertz};
use seam_fem::{Problem, Solution, SolveOptions};

/// What one Hertz solve gives, against the analytic values.
pub struct Measured {
    /// The slave element size near the contact.
    pub h: f64,
    /// The pressure at the pole.
    pub p0: f64,
    /// Hertz's p₀.
    pub p0_exact: f64,
    /// The outermost active slave node on the symmetry axes.
    pub a: f64,
    /// Hertz's a.
    pub a_exact: f64,
    /// max |p − p_Hertz| / p₀ over the slave nodes on the axes.
    pub profile: f64,
    /// Displacement unknowns.
    pub dofs: usize,
}

impl Measured {
    /// p₀ / p₀,Hertz − 1.
    pub fn p0_error(&self) -> f64 {
        self.p0 / self.p0_exact - 1.0
    }
}

/// p₀ at the pole, a from the outermost active node on y = 0 and x = 0, and
/// the largest |p − p_Hertz| / p₀ over slave nodes on the axes.
pub fn measure(p: &Hertz, problem: &Problem, s: &Solution) -> Measured {
    let points = problem.bodies[1].mesh.points();
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
        dofs: s.report.dofs,
    }
}

/// Solves the scene `p` (direct solver), asserts the KKT conditions and the
/// balance of the contact force with the load F/4 to 1e-8, prints a line
/// with `label` and returns the measurements.
pub fn solve(label: &str, p: &Hertz) -> Measured {
    let problem = hertz(p).unwrap();
    let s = problem.solve(&SolveOptions::default()).unwrap();
    let (report, contact) = (&s.report, s.report.contact.as_ref().expect("a contact report"));
    let force = -s.interfaces[0].force[2];
    let force_error = (force / (p.force() / 4.0) - 1.0).abs();
    let m = measure(p, &problem, &s);
    let t = &report.seconds;
    println!(
        "{label}: dofs {}, active {}, steps {}, KKT {:.1e}, force error {force_error:.1e}; \
         p0 {:.4} vs {:.4} ({:+.2} %), a {:.4} vs {:.4} ({:+.2} h), profile {:.3}; {:.1} s",
        report.dofs,
        contact.active,
        contact.steps.len(),
        contact.kkt.max(),
        m.p0,
        p.peak_pressure(),
        100.0 * m.p0_error(),
        m.a,
        p.contact_radius,
        (m.a - p.contact_radius) / m.h,
        m.profile,
        t.assembly + t.mortar + t.setup + t.factorization + t.solve,
    );
    assert!(contact.kkt.max() <= 1e-8, "{label}: KKT {:?}", contact.kkt);
    assert!(force_error <= 1e-8, "{label}: contact force {force} against F/4 = {}", p.force() / 4.0);
    m
}
