//! The multi-body core that gluing ([`crate::glue`]) and contact
//! ([`crate::contact`]) build on: bodies and interfaces, one dof numbering
//! over all bodies (`dof = offset_b + 3·point + component`), and the
//! assembled system diag(K_1, …, K_N) with the interfaces' mortar operators.
//! On it, the crate's private `constraints` module builds the glued
//! constraints C u = g (Wohlmuth's modified multiplier basis where slave dofs
//! are prescribed or shared at crosspoints) and solves the constrained system:
//! elimination u = P y, the saddle point [K Cᵀ; C 0] by sparse LDLᵀ, or PCG on
//! PᵀKP matrix-free.

use crate::enrichment::Tie;
use crate::material::Material;
use crate::solve::{Dirichlet, SolveError};
use crate::{stiffness, AssemblyError};
use seam::{BasisTransformation, CsrMatrix, Mortar, MortarError, MortarOptions, SurfaceMesh, VolumeMesh};
use std::time::Instant;

/// An assembler of an interface's operator (B, D; A1–D5) from the master
/// surface, the slave surface and the options, as [`seam::assemble`].
pub type OperatorAssembler =
    dyn Fn(&SurfaceMesh, &SurfaceMesh, &MortarOptions) -> Result<Mortar, MortarError> + Send + Sync;

/// How a solve assembles its interfaces' operators.
#[derive(Clone, Copy, Default)]
pub enum Operators {
    /// By [`seam::assemble`] in this process.
    #[default]
    Here,
    /// By this assembler, with the same B and D bit for bit (the binary under
    /// MPI: over the ranks). Interfaces are assembled one after the other,
    /// never concurrently.
    By(&'static OperatorAssembler),
}

impl Operators {
    /// An interface's operator.
    fn assemble(
        self,
        master: &SurfaceMesh,
        slave: &SurfaceMesh,
        options: &MortarOptions,
    ) -> Result<Mortar, MortarError> {
        match self {
            Operators::Here => seam::assemble(master, slave, options),
            Operators::By(assemble) => assemble(master, slave, options),
        }
    }
}

impl std::fmt::Debug for Operators {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Operators::Here => "Here",
            Operators::By(_) => "By(assembler)",
        })
    }
}

impl PartialEq for Operators {
    /// The same way: both here, or the same assembler.
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Operators::Here, Operators::Here) => true,
            (Operators::By(a), Operators::By(b)) => std::ptr::addr_eq(*a, *b),
            _ => false,
        }
    }
}

/// One linear-elastic body.
#[derive(Clone, Debug)]
pub struct Body<'a> {
    /// Its cells.
    pub mesh: &'a VolumeMesh,
    /// Its material.
    pub material: Material,
    /// Its load vector f (body forces and tractions), 3 entries per mesh point.
    pub load: Vec<f64>,
    /// Its prescribed displacements (dofs `3·point + component` of this body).
    pub dirichlet: Dirichlet,
    /// Points that follow others of the body ([`crate::enrichment`]): one
    /// constraint row each, in every component, after the interfaces' rows.
    pub ties: Vec<Tie>,
}

/// How an interface couples its two bodies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Coupling {
    /// Glued: (D u_s − B u_m) = 0 in every component (this module).
    #[default]
    Glue,
    /// Frictionless contact: a normal inequality per slave point
    /// ([`crate::contact`]).
    Contact,
}

/// An interface between a master and a slave surface of two bodies, glued or
/// in contact. The surfaces index their body's mesh points.
#[derive(Clone, Debug)]
pub struct Interface<'a> {
    /// Index of the master body.
    pub master: usize,
    /// The master surface.
    pub master_surface: &'a SurfaceMesh,
    /// Index of the slave body.
    pub slave: usize,
    /// The slave surface (where the multiplier lives).
    pub slave_surface: &'a SurfaceMesh,
    /// Mortar options (multiplier, gap and angle limits).
    pub options: MortarOptions,
    /// Glue or contact.
    pub kind: Coupling,
    /// Contact: the Coulomb friction coefficient μ ≥ 0 (0: frictionless).
    pub friction: f64,
}

/// Why a multi-body problem (glued, in contact, or both) could not be solved.
#[derive(Debug, thiserror::Error)]
pub enum ProblemError {
    /// An interface refers to a body that does not exist, or to one body twice.
    #[error("interface {interface}: {what}")]
    BadInterface {
        /// Interface index.
        interface: usize,
        /// What is wrong.
        what: String,
    },
    /// A body's load or surface does not match its mesh.
    #[error("body {body}: {what}")]
    BadBody {
        /// Body index.
        body: usize,
        /// What is wrong.
        what: String,
    },
    /// A body's stiffness could not be assembled.
    #[error("body {body}: {source}")]
    Assembly {
        /// Body index.
        body: usize,
        /// The cause.
        source: AssemblyError,
    },
    /// An interface's mortar operator could not be assembled.
    #[error("interface {interface}: {source}")]
    Mortar {
        /// Interface index.
        interface: usize,
        /// The cause.
        source: MortarError,
    },
    /// A slave point of a glued interface is also a slave point of a contact
    /// interface.
    #[error(
        "interface {glue}: slave point {point} at ({}, {}, {}) is also a slave point of contact interface \
         {contact}: a point cannot be glued and in contact at once (split the surfaces so that they share no point)",
        at[0], at[1], at[2]
    )]
    SharedSlavePoint {
        /// The glued interface.
        glue: usize,
        /// The contact interface.
        contact: usize,
        /// The point, in the slave body's mesh.
        point: usize,
        /// Its coordinates.
        at: seam::Point3,
    },
    /// A load or support has no finite value somewhere (a function of
    /// position and time, [`crate::history::Value`]).
    #[error("{what}: {message}")]
    Value {
        /// The load or support, named by its boundary and component.
        what: String,
        /// Why.
        message: String,
    },
    /// The linear solve failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// An active-set step's system is singular: some body is held neither by
    /// its supports nor by the contact points active in that step.
    #[error(
        "contact: active-set step {step}: the system is singular with {active} active contact points; every \
         body must be held by its supports, or touch (gap ≤ 0) another body from the start"
    )]
    SingularStep {
        /// The step, from 1.
        step: usize,
        /// Its active contact points.
        active: usize,
    },
    /// The system is singular even with every contact point closed: a body
    /// can move without deforming (contact holds only the normal direction).
    #[error(
        "contact: the system is singular even with all {points} contact points closed: a body can move \
         without deforming (frictionless contact holds only the normal direction; add supports)"
    )]
    Unsupported {
        /// The contact points.
        points: usize,
    },
    /// The active set still changed after the iteration cap.
    #[error(
        "contact: the active set did not settle in {steps} steps (last step: {added} points added, {removed} \
         removed); raise the iteration cap or check the load and the supports"
    )]
    ActiveSetNotSettled {
        /// Steps taken (the cap).
        steps: usize,
        /// Points added by the last step.
        added: usize,
        /// Points removed by the last step.
        removed: usize,
    },
    /// The semismooth Newton iteration of frictional contact did not
    /// converge within the iteration cap.
    #[error(
        "frictional contact: semismooth Newton did not converge in {steps} steps (last step: {changed} points \
         changed between inactive, stick and slip; relative update {update:.1e}); raise the iteration cap or \
         use more load steps"
    )]
    FrictionNotConverged {
        /// Steps taken (the cap).
        steps: usize,
        /// Points whose status (inactive, stick, slip) the last step changed.
        changed: usize,
        /// The last step's relative update.
        update: f64,
    },
    /// Linear and hyperelastic bodies in one problem.
    #[error("body \"{linear}\" is linear and body \"{hyperelastic}\" hyperelastic: a problem is solved either in small strain or in finite deformation, so give every body a hyperelastic material or none")]
    MixedLaws {
        /// A linear body's name.
        linear: String,
        /// A hyperelastic body's name.
        hyperelastic: String,
    },
    /// What finite deformation does not solve (yet).
    #[error("{what}")]
    Finite {
        /// What and why.
        what: String,
    },
    /// Newton's method in finite deformation failed.
    #[error("finite deformation: {source}")]
    Newton {
        /// Why.
        source: crate::hyperelastic::FiniteError,
    },
    /// A displacement of the solution is NaN or infinite: an overflow (nothing
    /// non-finite passes as a result).
    #[error("body {body}: the solution is not finite at point {} (component {}): an overflow; check the magnitudes of loads, prescribed values and moduli", dof / 3, dof % 3)]
    NonFiniteSolution {
        /// Body index.
        body: usize,
        /// The first such dof of the body (`3·point + component`).
        dof: usize,
    },
}

/// Wall-clock seconds per phase.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Timings {
    /// Stiffness assembly of all bodies.
    pub assembly: f64,
    /// Mortar operators (search and assembly) of all interfaces.
    pub mortar: f64,
    /// Forming the system to solve (constraints, reduction PᵀKP).
    pub setup: f64,
    /// Factorisation, or the PCG iterations.
    pub factorization: f64,
    /// Triangular solves, refinement and recovery of u and λ.
    pub solve: f64,
    /// Stresses and the interfaces' tractions.
    pub stresses: f64,
}

impl std::ops::AddAssign for Timings {
    /// Adds the seconds of another solve (a load step) phase by phase.
    fn add_assign(&mut self, other: Timings) {
        let Timings { assembly, mortar, setup, factorization, solve, stresses } = other;
        self.assembly += assembly;
        self.mortar += mortar;
        self.setup += setup;
        self.factorization += factorization;
        self.solve += solve;
        self.stresses += stresses;
    }
}

/// The bodies' stiffness and loads as one system, and the interfaces' mortar
/// operators.
pub(crate) struct System {
    /// diag(K_1, …, K_N).
    pub k: CsrMatrix,
    /// The loads, one after the other.
    pub f: Vec<f64>,
    /// All prescribed dofs, in global numbering.
    pub dirichlet: Dirichlet,
    /// offsets[b] = first dof of body b; the last entry is the number of dofs.
    pub offsets: Vec<usize>,
    /// Per interface.
    pub mortars: Vec<Mortar>,
    /// The points of all bodies, one after the other (point i carries dofs
    /// 3i, 3i + 1, 3i + 2).
    pub points: Vec<seam::Point3>,
}

/// Assembles K_b per body (timed as `assembly`; `stiffness` false: K is
/// left empty, 0 × 0, for MPI ranks to assemble, [`crate::partition`]), the
/// mortar operator per interface by `operators` (`mortar`), and joins them
/// into one [`System`] (`setup`).
pub(crate) fn assemble_system(
    bodies: &[Body],
    interfaces: &[Interface],
    (stiffness, operators): (bool, Operators),
    seconds: &mut Timings,
) -> Result<System, ProblemError> {
    let clock = Instant::now();
    let k = match stiffness {
        true => bodies_stiffness(bodies)?,
        false => CsrMatrix::zeros(0, 0),
    };
    seconds.assembly = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let mortars = interfaces
        .iter()
        .enumerate()
        .map(|(i, f)| {
            // Contact weights its gaps and pressures by the transformed basis
            // on every second-order slave face (module doc of `contact`).
            let options = match f.kind {
                Coupling::Contact => MortarOptions { transformation: BasisTransformation::All, ..f.options },
                Coupling::Glue => f.options,
            };
            operators
                .assemble(f.master_surface, f.slave_surface, &options)
                .map_err(|source| ProblemError::Mortar { interface: i, source })
        })
        .collect::<Result<Vec<_>, _>>()?;
    seconds.mortar = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let offsets = dof_offsets(bodies);
    let n = *offsets.last().expect("at least the leading zero");
    let mut f = vec![0.0; n];
    let mut dirichlet = Dirichlet::new();
    for (b, body) in bodies.iter().enumerate() {
        f[offsets[b]..offsets[b + 1]].copy_from_slice(&body.load);
        for (dof, v) in body.dirichlet.iter() {
            dirichlet.fix_dof(offsets[b] + dof, v);
        }
    }
    let points = bodies.iter().flat_map(|b| b.mesh.points().iter().copied()).collect();
    seconds.setup = clock.elapsed().as_secs_f64();
    Ok(System { k, f, dirichlet, offsets, mortars, points })
}

pub(crate) fn check_input(bodies: &[Body], interfaces: &[Interface]) -> Result<(), ProblemError> {
    for (b, body) in bodies.iter().enumerate() {
        let n = 3 * body.mesh.points().len();
        if body.load.len() != n {
            let what = format!("the load has {} entries, the mesh {} dofs", body.load.len(), n);
            return Err(ProblemError::BadBody { body: b, what });
        }
        if let Some((dof, _)) = body.dirichlet.iter().find(|&(d, _)| d >= n) {
            let what = format!("Dirichlet condition on dof {dof}, but the mesh has {n} dofs");
            return Err(ProblemError::BadBody { body: b, what });
        }
        for tie in &body.ties {
            let points = std::iter::once(tie.point).chain(tie.to.iter().map(|e| e.0));
            if let Some(p) = points.clone().find(|&p| 3 * p >= n) {
                let what =
                    format!("point {} is tied to point {p}, but the mesh has {} points", tie.point, n / 3);
                return Err(ProblemError::BadBody { body: b, what });
            }
            if tie.to.iter().any(|e| !e.1.is_finite())
                || (0..3).any(|c| body.dirichlet.value(3 * tie.point + c).is_some())
            {
                let what = format!("point {} is tied with a non-finite weight or also prescribed", tie.point);
                return Err(ProblemError::BadBody { body: b, what });
            }
        }
    }
    for (i, f) in interfaces.iter().enumerate() {
        let bad = |what: String| ProblemError::BadInterface { interface: i, what };
        for (side, body, surface) in
            [("master", f.master, f.master_surface), ("slave", f.slave, f.slave_surface)]
        {
            let Some(b) = bodies.get(body) else {
                return Err(bad(format!("{side} body {body} does not exist ({} bodies)", bodies.len())));
            };
            if surface.n_points() != b.mesh.points().len() {
                return Err(bad(format!(
                    "the {side} surface has {} points, its body's mesh {}: surfaces must index the body's points",
                    surface.n_points(),
                    b.mesh.points().len()
                )));
            }
        }
        if f.master == f.slave {
            return Err(bad(format!("master and slave are the same body {}", f.master)));
        }
    }
    Ok(())
}

/// Per dof of all bodies: whether it is free, neither prescribed nor of a
/// point that no cell uses (an empty row of K).
pub(crate) fn free_dofs_of(bodies: &[Body], dirichlet: &Dirichlet) -> Vec<bool> {
    let mut free = Vec::new();
    for body in bodies {
        free.extend(body.mesh.used_points().into_iter().flat_map(|used| [used; 3]));
    }
    for (dof, _) in dirichlet.iter() {
        free[dof] = false;
    }
    free
}

/// offsets[b] = first dof of body b; the last entry is the number of dofs.
pub(crate) fn dof_offsets(bodies: &[Body]) -> Vec<usize> {
    let mut offsets = vec![0];
    for body in bodies {
        offsets.push(offsets.last().unwrap() + 3 * body.mesh.points().len());
    }
    offsets
}

/// diag(K_1, …, K_N), the bodies' stiffness matrices as one matrix in the
/// numbering of [`dof_offsets`] (what [`System::k`] holds; a solve that gives
/// K up while it runs forms it again by this).
///
/// # Errors
/// [`ProblemError::Assembly`] for a body with a degenerate cell.
pub(crate) fn bodies_stiffness(bodies: &[Body]) -> Result<CsrMatrix, ProblemError> {
    let stiffnesses = bodies
        .iter()
        .enumerate()
        .map(|(b, body)| {
            stiffness(body.mesh, &body.material).map_err(|source| ProblemError::Assembly { body: b, source })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let n = *dof_offsets(bodies).last().expect("at least the leading zero");
    Ok(block_diagonal(&stiffnesses, n))
}

/// diag(K_1, …, K_N) as one n × n matrix.
pub(crate) fn block_diagonal(blocks: &[CsrMatrix], n: usize) -> CsrMatrix {
    let nnz = blocks.iter().map(CsrMatrix::nnz).sum();
    let mut k = CsrMatrix {
        nrows: n,
        ncols: n,
        indptr: Vec::with_capacity(n + 1),
        indices: Vec::with_capacity(nnz),
        values: Vec::with_capacity(nnz),
    };
    k.indptr.push(0);
    let mut offset = 0;
    for block in blocks {
        let base = k.indices.len();
        k.indices.extend(block.indices.iter().map(|&j| j + offset));
        k.values.extend_from_slice(&block.values);
        k.indptr.extend(block.indptr[1..].iter().map(|&p| base + p));
        offset += block.nrows;
    }
    k
}
