//! Cattaneo–Mindlin: the Hertz indenter pressed by P, then pushed sideways
//! by Q < μP, against the analytic partial-slip solution.

use super::hertz::{bodies, contact, id, Hertz, Layout, TOP};
use crate::history::{Amplitude, LoadSteps, Value};
use crate::material::Material;
use crate::problem::{Load, Problem, Support};
use crate::solution::Solution;
use seam::{MeshError, Multiplier};
use std::sync::Arc;

/// Parameters of [`cattaneo_mindlin`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CattaneoMindlin {
    /// The indenter, the block and their meshes as for [`super::hertz`]
    /// (the materials equal, so that the normal and tangential problems
    /// decouple; the force P is Hertz's [`Hertz::force`]).
    pub hertz: Hertz,
    /// Coulomb's μ.
    pub friction: f64,
    /// Q / (μP), in [0, 1).
    pub shear_ratio: f64,
    /// Load steps of the shear, after the one step that presses.
    pub shear_steps: usize,
}

impl Default for CattaneoMindlin {
    /// [`Hertz::default`] with both bodies E = 1000, ν = 0.3, a = 0.04 R
    /// (the indenter 12.5a wide and 15a tall, nearer Cattaneo–Mindlin's half
    /// spaces: at a = 0.08 R pressing left a radial traction of 3–5 % of q
    /// locked in the stick zone), meshed on rings ([`Layout::Rings`]) whose
    /// band [0.55a, 1.1a] holds the rim and the stick–slip circle, the cells
    /// growing 1.4× outside it, dual multipliers (lumped ones make the
    /// traction oscillate where the rings' spacing changes: 8.5 % in L2 at
    /// the example's mesh, against 2–3 %), pairs kept up to the gap a/4 (6×
    /// the approach a²/R); μ = 0.3, Q = 0.5 μP in 10 steps.
    fn default() -> Self {
        let material = Material::new(1000.0, 0.3).expect("valid constants");
        let hertz = Hertz {
            contact_radius: 0.04,
            fine_zone: 1.1,
            grading: 1.4,
            max_gap: 0.25,
            multiplier: Multiplier::Dual,
            layout: Layout::Rings,
            indenter: material,
            block: material,
            ..Hertz::default()
        };
        CattaneoMindlin { hertz, friction: 0.3, shear_ratio: 0.5, shear_steps: 10 }
    }
}

impl CattaneoMindlin {
    /// Q = (Q/μP) μ P on the whole indenter (the half model carries Q/2).
    pub fn shear_force(&self) -> f64 {
        self.shear_ratio * self.friction * self.hertz.force()
    }

    /// The stick radius c = a (1 − Q/μP)^{1/3}.
    pub fn stick_radius(&self) -> f64 {
        self.hertz.contact_radius * (1.0 - self.shear_ratio).cbrt()
    }

    /// The magnitude of the tangential traction (along Q):
    /// q(r) = μp₀/a √(a² − r²) in the slip annulus c ≤ r ≤ a, and
    /// μp₀/a [√(a² − r²) − √(c² − r²)] inside c.
    pub fn traction(&self, r: f64) -> f64 {
        let (a, c) = (self.hertz.contact_radius, self.stick_radius());
        let root = |s: f64| (s * s - r * r).max(0.0).sqrt();
        self.friction * self.hertz.peak_pressure() / a * (root(a) - root(c))
    }

    /// The pseudo-time at which P is reached and the shear starts.
    pub fn pressed(&self) -> f64 {
        1.0 / (self.shear_steps + 1) as f64
    }
}

/// Cattaneo and Mindlin's quantities read off a solution of
/// [`cattaneo_mindlin`] ([`CattaneoMindlin::measure`]).
#[derive(Clone, Debug, PartialEq)]
pub struct PartialSlip {
    /// The radius of the half disc whose area is that of the sticking
    /// points, √(2 Σ_stick d_p / π), d_p = D_pp the weight of slave point p.
    pub stick_radius: f64,
    /// The same of the active points.
    pub contact_radius: f64,
    /// ‖t_x − q‖ / ‖q‖ in the discrete L2 norm Σ_p d_p v_p² over the contact
    /// points, t_x the traction along Q and q [`CattaneoMindlin::traction`].
    pub traction_error: f64,
    /// Points in contact and sticking.
    pub stick: usize,
    /// Points in contact and slipping.
    pub slip: usize,
    /// The slave points on the symmetry line y = 0 inside r < 2a, by x.
    pub axis: Vec<AxisPoint>,
}

/// A slave point on the line y = 0 of the block's top.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisPoint {
    /// Its x.
    pub x: f64,
    /// The contact pressure.
    pub pressure: f64,
    /// The traction along Q.
    pub traction: f64,
    /// Cattaneo–Mindlin's q(|x|).
    pub analytic: f64,
    /// In contact and sticking.
    pub stick: bool,
}

impl CattaneoMindlin {
    /// Reads the stick radius, the contact radius and the error of the
    /// tangential traction off `solution` of `problem` (the slave the
    /// block's flat top, [`Hertz::curved_slave`] unset).
    ///
    /// # Panics
    /// If the solution's first interface is not a contact interface.
    pub fn measure(&self, problem: &Problem, solution: &Solution) -> PartialSlip {
        let f = &solution.interfaces[0];
        let c = f.contact.as_ref().expect("a contact interface");
        let points = problem.bodies[problem.interfaces[0].slave.body].mesh.points();
        let weight = |p: usize| f.mortar.d.get(p, p);
        let area = |on: &dyn Fn(usize) -> bool| (0..points.len()).filter(|&p| on(p)).map(weight).sum::<f64>();
        let radius = |area: f64| (2.0 * area / std::f64::consts::PI).sqrt();
        let r = |p: usize| points[p][0].hypot(points[p][1]);
        let (mut miss, mut norm) = (0.0, 0.0);
        for p in (0..points.len()).filter(|&p| c.contact[p]) {
            let q = self.traction(r(p));
            miss += weight(p) * (f.tangential_traction[p][0] - q).powi(2);
            norm += weight(p) * q * q;
        }
        let mut axis: Vec<AxisPoint> = (0..points.len())
            .filter(|&p| c.contact[p] && points[p][1] == 0.0 && r(p) < 2.0 * self.hertz.contact_radius)
            .map(|p| AxisPoint {
                x: points[p][0],
                pressure: c.pressure[p],
                traction: f.tangential_traction[p][0],
                analytic: self.traction(r(p)),
                stick: c.active[p] && c.stick[p],
            })
            .collect();
        axis.sort_by(|a, b| a.x.total_cmp(&b.x));
        let count = |stick: bool| (0..points.len()).filter(|&p| c.active[p] && c.stick[p] == stick).count();
        PartialSlip {
            stick_radius: radius(area(&|p| c.active[p] && c.stick[p])),
            contact_radius: radius(area(&|p| c.active[p])),
            traction_error: (miss / norm).sqrt(),
            stick: count(true),
            slip: count(false),
            axis,
        }
    }
}

/// The Cattaneo–Mindlin problem, a half model of [`super::hertz`]'s
/// indenter and block (symmetry plane y = 0; x from −L to L, −W to W):
///
/// - bodies "indenter" (master, surfaces "bottom" = the sphere, "top",
///   "y0") and "block" (slave, "top", "bottom", "y0"), the block's bottom
///   clamped, y = 0 a symmetry plane of both;
/// - the indenter's top pressed by the uniform traction of P/2 over the
///   first of 1 + `shear_steps` equal load steps, then pushed along x by
///   the uniform traction of Q/2, rising linearly over the remaining steps,
///   with the linear normal traction k x (k = 3HQ/(4L⁴), H the top's
///   height) whose moment balances Q's about the contact, as a rigid holder
///   would: the indenter is held along x by friction only;
/// - frictional contact with μ = `friction`.
///
/// # Errors
/// [`MeshError`] only for degenerate parameters.
pub fn cattaneo_mindlin(p: &CattaneoMindlin) -> Result<Problem, MeshError> {
    let bodies = bodies(&p.hertz, true)?;
    let (bottom, y0) = (0, 2);
    let (indenter, slab) = (0, 1);
    let supports = vec![
        Support::new(id(slab, bottom), [Some(0.0); 3]),
        Support::new(id(indenter, y0), [None, Some(0.0), None]),
        Support::new(id(slab, y0), [None, Some(0.0), None]),
    ];
    let (l, h) = p.hertz.indenter_size();
    let area = 2.0 * l * l;
    let t1 = p.pressed();
    let press = Load {
        amplitude: Amplitude::new(vec![[0.0, 0.0], [t1, 1.0]]).expect("increasing"),
        ..Load::new(id(indenter, TOP), [0.0, 0.0, -0.5 * p.hertz.force() / area])
    };
    let q = 0.5 * p.shear_force();
    let k = 3.0 * h * p.shear_force() / (4.0 * l.powi(4));
    let couple = Value::Function(format!("{k:?}*x"), Arc::new(move |x, _| Ok(k * x[0])));
    let shear = Load {
        boundary: id(indenter, TOP),
        t: [Value::Number(q / area), Value::Number(0.0), couple],
        amplitude: Amplitude::new(vec![[0.0, 0.0], [t1, 0.0], [1.0, 1.0]]).expect("increasing"),
    };
    let mut interface = contact(&p.hertz);
    interface.friction = p.friction;
    Ok(Problem {
        bodies,
        interfaces: vec![interface],
        supports,
        loads: vec![press, shear],
        steps: LoadSteps::equal(p.shear_steps + 1).expect("at least one step"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tractions_carry_q_and_the_loads_have_no_moment_about_the_contact() {
        let p = CattaneoMindlin::default();
        // ∫ q dA over the contact disc = Q.
        let (a, n) = (p.hertz.contact_radius, 20000);
        let dr = a / n as f64;
        let total: f64 = (0..n)
            .map(|i| (i as f64 + 0.5) * dr)
            .map(|r| p.traction(r) * 2.0 * std::f64::consts::PI * r * dr)
            .sum();
        assert!((total / p.shear_force() - 1.0).abs() < 1e-6, "{total}");
        // At the stick edge the traction is μ p.
        let c = p.stick_radius();
        assert!((p.traction(c) - p.friction * p.hertz.pressure(c)).abs() < 1e-12 * p.hertz.peak_pressure());

        let problem = cattaneo_mindlin(&p).unwrap();
        let top = problem.bodies[0].surfaces[TOP].1.clone();
        let mesh = problem.bodies[0].mesh.clone();
        let [_, shear] = problem.loads.as_slice() else { panic!("two loads") };
        // The shear's nodal forces: their resultant Q/2 along x and their moment about y through the origin zero.
        let body = problem.loads_and_supports(1.0).unwrap().swap_remove(0).0;
        let press = problem.loads_and_supports(p.pressed()).unwrap().swap_remove(0).0;
        let (mut f, mut m) = ([0.0; 3], 0.0);
        for (i, x) in mesh.points().iter().enumerate() {
            let g: [f64; 3] = std::array::from_fn(|k| body[3 * i + k] - press[3 * i + k]);
            for k in 0..3 {
                f[k] += g[k];
            }
            m += x[2] * g[0] - x[0] * g[2];
        }
        assert!(top.n_faces() > 0 && shear.amplitude.at(p.pressed()) == 0.0);
        let q = 0.5 * p.shear_force();
        assert!((f[0] - q).abs() < 1e-12 * q && f[1].abs() < 1e-12 * q && f[2].abs() < 1e-12 * q, "{f:?}");
        assert!(m.abs() < 1e-12 * q, "{m}");
    }
}
