//! What a solve of a multi-body problem gives: per body its displacement and
//! stresses, per interface its traction (with normal and tangential parts),
//! resultant force and, for contact, pressure, gaps and active set; and the
//! report of how it was solved. The solve itself: [`crate::coupled`].

use crate::backend::Solver;
use crate::multibody::{Coupling, Operators, Timings};
use crate::stress::Stresses;
use seam::{Mortar, Point3};

/// How a problem is solved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// The linear solver of the glued system, or of each active-set step.
    pub solver: Solver,
    /// Contact: the cap on active-set steps.
    pub max_active_set_steps: usize,
    /// How the interfaces' operators are assembled.
    pub operators: Operators,
    /// Finite deformation: Newton's tolerance and iteration cap.
    pub newton: crate::hyperelastic::NewtonOptions,
}

impl Default for SolveOptions {
    /// Direct solves, at most 50 active-set steps, operators assembled
    /// here, Newton to 1e-10 in at most 25 iterations.
    fn default() -> Self {
        SolveOptions {
            solver: Solver::Direct,
            max_active_set_steps: 50,
            operators: Operators::Here,
            newton: Default::default(),
        }
    }
}

/// The solution of a multi-body problem.
#[derive(Clone, Debug)]
pub struct Solution {
    /// Per body: displacements, 3 per mesh point.
    pub displacement: Vec<Vec<f64>>,
    /// Per body: cell and nodal stresses, von Mises.
    pub stresses: Vec<Stresses>,
    /// Per interface, in input order.
    pub interfaces: Vec<InterfaceSolution>,
    /// Sizes, method, residuals and timings.
    pub report: Report,
}

/// The solution on one interface, per point of the slave body (zero, or
/// false, off the slave surface).
#[derive(Clone, Debug)]
pub struct InterfaceSolution {
    /// Glue or contact.
    pub kind: Coupling,
    /// The mortar operator of the interface.
    pub mortar: Mortar,
    /// The traction (force per area) the master exerts on the slave: −λ for
    /// glue (at prescribed and crosspoint dofs the value of the modified
    /// multiplier there), −λ_p n_p for contact.
    pub traction: Vec<[f64; 3]>,
    /// The slave's outward unit normal: the contact constraint's at contact
    /// points, else the nodal normal.
    pub normal: Vec<Point3>,
    /// t·n: negative is compression.
    pub normal_traction: Vec<f64>,
    /// t − (t·n) n.
    pub tangential_traction: Vec<[f64; 3]>,
    /// The interface constrains the point (glue: some component; contact: a
    /// contact point).
    pub constrained: Vec<bool>,
    /// Resultant force of the master on the slave, −Σ_p (D λ)_p.
    pub force: [f64; 3],
    /// Contact interfaces: pressure, gaps and active set.
    pub contact: Option<ContactFields>,
    /// The slave body was raised for the enriched slave space of dual
    /// multipliers ([`crate::enrichment`]): the mortar operator is that of
    /// its Tri7 and Quad9 faces, with rows for their centres after the
    /// body's points.
    pub enriched: bool,
}

impl InterfaceSolution {
    /// An interface with no traction yet, on a slave body of `n` points.
    pub(crate) fn new(kind: Coupling, mortar: Mortar, n: usize) -> InterfaceSolution {
        InterfaceSolution {
            kind,
            mortar,
            traction: vec![[0.0; 3]; n],
            normal: vec![[0.0; 3]; n],
            normal_traction: vec![0.0; n],
            tangential_traction: vec![[0.0; 3]; n],
            constrained: vec![false; n],
            force: [0.0; 3],
            contact: (kind == Coupling::Contact).then(|| ContactFields::new(n)),
            enriched: false,
        }
    }

    /// Keeps the first `n` points of the slave body (those of its mesh when
    /// it was raised for the enriched slave space, [`crate::enrichment`]).
    pub(crate) fn truncate(&mut self, n: usize) {
        self.traction.truncate(n);
        self.normal.truncate(n);
        self.normal_traction.truncate(n);
        self.tangential_traction.truncate(n);
        self.constrained.truncate(n);
        if let Some(c) = &mut self.contact {
            for v in [&mut c.initial_gap, &mut c.gap, &mut c.pressure] {
                v.truncate(n);
            }
            c.contact.truncate(n);
            c.active.truncate(n);
            c.stick.truncate(n);
            c.slip.truncate(n);
            c.slip_increment.truncate(n);
            c.friction_bound.truncate(n);
        }
    }

    /// The number of points the interface constrains.
    pub fn constrained_points(&self) -> usize {
        self.constrained.iter().filter(|&&c| c).count()
    }
}

/// A contact interface's fields per slave body point (zero, or false, off the
/// contact points). With dual multipliers on second-order slave faces they
/// belong to the transformed unknowns of Popp et al. (2012) at each node
/// (module doc of [`crate::contact`]): the pressure is the coefficient λ_p of
/// the dual function ψ_p (a weighted mean of the pressure around p, not a
/// nodal value), the gaps are those of ũ_p.
#[derive(Clone, Debug)]
pub struct ContactFields {
    /// Has a contact constraint (a contact point).
    pub contact: Vec<bool>,
    /// The initial weighted gap g_p.
    pub initial_gap: Vec<f64>,
    /// The gap after deformation, g_p − w_p (≥ 0).
    pub gap: Vec<f64>,
    /// The contact pressure λ_p (≥ 0, force per area).
    pub pressure: Vec<f64>,
    /// In the final active set.
    pub active: Vec<bool>,
    /// The Coulomb coefficient μ of the interface (0: frictionless).
    pub friction: f64,
    /// In contact and sticking (with friction).
    pub stick: Vec<bool>,
    /// The accumulated tangential slip of the slave against the master
    /// (over the load steps so far).
    pub slip: Vec<Point3>,
    /// The tangential slip of the last load step.
    pub slip_increment: Vec<Point3>,
    /// μ λ_n: the largest frictional traction the point can carry.
    pub friction_bound: Vec<f64>,
}

impl ContactFields {
    /// No contact point yet on a slave body of `n` points.
    pub(crate) fn new(n: usize) -> ContactFields {
        ContactFields {
            contact: vec![false; n],
            initial_gap: vec![0.0; n],
            gap: vec![0.0; n],
            pressure: vec![0.0; n],
            active: vec![false; n],
            friction: 0.0,
            stick: vec![false; n],
            slip: vec![[0.0; 3]; n],
            slip_increment: vec![[0.0; 3]; n],
            friction_bound: vec![0.0; n],
        }
    }
}

/// What the solve did.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Displacement unknowns, 3 per point of all bodies that some cell uses.
    pub dofs: usize,
    /// Rows of the glued interfaces' constraints.
    pub constraints: usize,
    /// The method used, e.g. "saddle-point LDLᵀ".
    pub method: &'static str,
    /// Glue only: PCG iterations, or refinement steps of a direct solve;
    /// with contact: active-set steps.
    pub iterations: usize,
    /// Glue only: ‖f − K u − Cᵀλ‖ / ‖f‖ over the free dofs and ‖C u‖
    /// relative to ‖C‖‖u‖, the larger; with contact: the largest KKT residual.
    pub residual: f64,
    /// With contact: active-set steps and KKT residuals.
    pub contact: Option<ContactReport>,
    /// With [`crate::Solver::Petsc`]: the KSP and PC, each solve's
    /// iterations and residual, PETSc's own seconds.
    pub petsc: Option<crate::petsc::PetscSummary>,
    /// Finite deformation: Newton's residuals and line-search steps.
    pub newton: Option<crate::hyperelastic::NewtonReport>,
    /// Seconds per phase.
    pub seconds: Timings,
}

/// The contact part of a [`Report`].
#[derive(Clone, Debug, PartialEq)]
pub struct ContactReport {
    /// Contact points (slave points with a constraint), all interfaces.
    pub contact_points: usize,
    /// Active points at the solution, all interfaces.
    pub active: usize,
    /// The active-set steps.
    pub steps: Vec<ActiveSetStep>,
    /// KKT residuals of the solution.
    pub kkt: Kkt,
}

/// One active-set step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ActiveSetStep {
    /// Active points during the step's solve.
    pub active: usize,
    /// Points that become active after it.
    pub added: usize,
    /// Points that become inactive after it.
    pub removed: usize,
    /// PCG iterations of the step (0 for a direct solve).
    pub linear_iterations: usize,
    /// Solved to the requested tolerance: every direct step; of an iterative
    /// solver's, those from the first whose solution to 10⁻³ leaves the active
    /// set unchanged, which then goes on to the full tolerance (the earlier
    /// ones stop at 10⁻³, `active_set_method`).
    pub full_tolerance: bool,
    /// How far the step's iterate is from the contact conditions, relative:
    /// negative pressure on active points and penetration at inactive ones
    /// (0 up to the linear solve once the active set is right).
    pub residual: f64,
}

/// How well the solution meets the discrete KKT conditions, each relative.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kkt {
    /// ‖(f − Ku − Cᵀλ)_F‖∞ over the free dofs F, relative to the size of the
    /// terms, max(‖f_F‖∞, max_i Σ_j |K_ij u_j|).
    pub equilibrium: f64,
    /// max_p (−λ_p)⁺ / max_p |λ_p|: negative pressure.
    pub pressure: f64,
    /// max_p (w_p − g_p)⁺ / max(‖u‖∞, max |g|): penetration.
    pub penetration: f64,
    /// max_p |λ_p (g_p − w_p)| / (max |λ| · max(‖u‖∞, max |g|)).
    pub complementarity: f64,
}

impl Kkt {
    /// The largest of the four.
    pub fn max(&self) -> f64 {
        self.equilibrium.max(self.pressure).max(self.penetration).max(self.complementarity)
    }
}
