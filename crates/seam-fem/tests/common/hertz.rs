//! The Hertz tests' solve and measurements ([`seam_fem::scene::hertz`]).

use seam::{MortarOptions, Multiplier};
use seam_fem::scene::{hertz, Hertz};
use seam_fem::{Dirichlet, Problem, Solution, SolveOptions};

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
    let points = slave_points(problem);
    let i = s.interfaces[0].contact.as_ref().expect("a contact interface");
    let on_axis = |q: usize| {
        let surface = if p.curved_slave { p.sphere(points[q][0], points[q][1]) } else { 0.0 };
        (points[q][2] - surface).abs() < 1e-12 && (points[q][0] == 0.0 || points[q][1] == 0.0)
    };
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

/// The points of the contact's slave body.
fn slave_points(problem: &Problem) -> &[seam::Point3] {
    problem.bodies[problem.interfaces[0].slave.body].mesh.points()
}

/// Two other readings at the pole of a dual-multiplier solve, relative to
/// Hertz's p₀ (p₀ / p₀,Hertz − 1).
pub struct PoleReadings {
    /// What the reported pressure would read if the multiplier were exact:
    /// the weighted mean of Hertz's pressure that the pole's coefficient is,
    /// ∫ λ̃_pole p_H / ∫ λ̃_pole = (D⁻¹ Q M I_h p_H)_pole (module doc of
    /// `seam_fem::contact`; Q = I and λ̃ = λ without a basis transformation),
    /// with I_h p_H the interpolant of p_H on the slave's Lagrange space and
    /// M_pq = ∫ λ_p λ_q over the covered slave surface.
    pub exact_mean: f64,
    /// The L2 projection of the multiplier λ_h = Σ_p λ_p ψ_p onto the slave's
    /// Lagrange space of the covered surface, M⁻¹ z with
    /// z_r = ∫ λ_r λ_h = Σ_p λ_p ∫ ψ_p λ_r (`Mortar::nodal_d`); None when
    /// M is numerically singular (a node whose support is covered only in a
    /// sliver).
    pub projection: Option<f64>,
}

/// The [`PoleReadings`] of a solve of the scene `p` with dual multipliers:
/// M is D of the interface assembled once more with standard multipliers.
pub fn pole_readings(p: &Hertz, problem: &Problem, s: &Solution) -> PoleReadings {
    let f = &problem.interfaces[0];
    let options = MortarOptions { multiplier: Multiplier::Standard, ..f.options };
    let m = seam::assemble(problem.surface(f.master), problem.surface(f.slave), &options).unwrap().d;
    let dual = &s.interfaces[0].mortar;
    assert_eq!(dual.multiplier, Multiplier::Dual);
    let i = s.interfaces[0].contact.as_ref().expect("a contact interface");
    let points = slave_points(problem);
    let r = |q: usize| points[q][0].hypot(points[q][1]);
    let pole = (0..points.len()).find(|&q| dual.on_surface[q] && r(q) == 0.0).expect("a node at the pole");
    let relative = |v: f64| v / p.peak_pressure() - 1.0;
    // Σ_r Q_pr (M v)_r / D_pp at the pole.
    let mean = |v: &[f64]| {
        let mv = m.mul_vec(v, 1);
        let qmv = match &dual.basis {
            Some(q) => q.mul_vec(&mv, 1),
            None => mv,
        };
        qmv[pole] / dual.d.get(pole, pole)
    };
    let ones: Vec<f64> = dual.on_surface.iter().map(|&on| if on { 1.0 } else { 0.0 }).collect();
    assert!((mean(&ones) - 1.0).abs() < 1e-12, "the weights at the pole have mean {}", mean(&ones));
    let interpolant: Vec<f64> =
        (0..points.len()).map(|q| if dual.on_surface[q] { p.pressure(r(q)) } else { 0.0 }).collect();
    let z = dual.nodal_d().transpose_mul_vec(&i.pressure, 1);
    let projected = seam_fem::solve::solve(&m, &z, &Dirichlet::new()).ok();
    PoleReadings {
        exact_mean: relative(mean(&interpolant)),
        projection: projected.map(|v| relative(v[pole])),
    }
}

/// Solves the scene `p` (direct solver), asserts the KKT conditions and the
/// balance of the contact force with the load F/4 to 1e-8, prints a line
/// with `label` and returns the measurements.
pub fn solve(label: &str, p: &Hertz) -> Measured {
    solve_scene(label, p).0
}

/// [`solve`], also returning the problem and its solution.
pub fn solve_scene(label: &str, p: &Hertz) -> (Measured, Problem, Solution) {
    solve_scene_with(label, p, &SolveOptions::default())
}

/// [`solve_scene`] with `options`.
pub fn solve_scene_with(label: &str, p: &Hertz, options: &SolveOptions) -> (Measured, Problem, Solution) {
    let problem = hertz(p).unwrap();
    let s = problem.solve(options).unwrap();
    let (report, contact) = (&s.report, s.report.contact.as_ref().expect("a contact report"));
    // The master's force on the slave: down on the block, up on the indenter.
    let force = if p.curved_slave { 1.0 } else { -1.0 } * s.interfaces[0].force[2];
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
    (m, problem, s)
}
