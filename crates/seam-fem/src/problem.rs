//! A glued multi-body problem with named bodies and boundaries: what a case file
//! (`seam solve CASE.toml`) or a built-in example describes, in memory.
//!
//! Boundaries are named surfaces of a body ("body:surface"); Dirichlet
//! conditions, tractions and interfaces refer to them. [`solve`] builds
//! the loads f = ∫_Ω N b + ∫_Γ N t and the prescribed dofs of each body, and
//! hands them to [`solve_coupled`].

use crate::assembly::{body_force, traction};
use crate::coupled::solve_coupled;
use crate::material::Material;
use crate::multibody::{Body, Coupling, Interface, ProblemError};
use crate::solution::{Solution, SolveOptions};
use crate::solve::Dirichlet;
use seam::{MortarOptions, SurfaceMesh, VolumeMesh};

/// A body with its named boundary surfaces.
#[derive(Clone, Debug)]
pub struct ProblemBody {
    /// Its name (unique in the problem).
    pub name: String,
    /// Its cells.
    pub mesh: VolumeMesh,
    /// Its material.
    pub material: Material,
    /// Force per volume.
    pub body_force: [f64; 3],
    /// Named boundary surfaces, outward, indexing the mesh's points.
    pub surfaces: Vec<(String, SurfaceMesh)>,
}

/// A surface of a body: indices into [`Problem::bodies`] and its `surfaces`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SurfaceId {
    /// The body.
    pub body: usize,
    /// The surface of that body.
    pub surface: usize,
}

/// An interface, glued or in contact.
#[derive(Clone, Debug)]
pub struct ProblemInterface {
    /// The master surface.
    pub master: SurfaceId,
    /// The slave surface, where the multiplier lives.
    pub slave: SurfaceId,
    /// Multiplier, gap and angle limits.
    pub options: MortarOptions,
    /// Glue or contact.
    pub kind: Coupling,
}

/// Prescribed displacement components on a boundary.
#[derive(Clone, Copy, Debug)]
pub struct Support {
    /// The boundary.
    pub boundary: SurfaceId,
    /// u_x, u_y, u_z, each prescribed or free.
    pub values: [Option<f64>; 3],
}

/// A uniform traction (force per area) on a boundary.
#[derive(Clone, Copy, Debug)]
pub struct Load {
    /// The boundary.
    pub boundary: SurfaceId,
    /// The traction vector.
    pub t: [f64; 3],
}

/// Bodies, interfaces, supports and loads.
#[derive(Clone, Debug, Default)]
pub struct Problem {
    /// The bodies.
    pub bodies: Vec<ProblemBody>,
    /// The interfaces, glued and contact (frictionless, [`crate::contact`]).
    pub interfaces: Vec<ProblemInterface>,
    /// Dirichlet conditions, applied in order (a later one overrides an earlier
    /// one on shared points).
    pub supports: Vec<Support>,
    /// Tractions.
    pub loads: Vec<Load>,
}

impl Problem {
    /// The surface `id`.
    ///
    /// # Panics
    /// If `id` is out of range.
    pub fn surface(&self, id: SurfaceId) -> &SurfaceMesh {
        &self.bodies[id.body].surfaces[id.surface].1
    }

    /// "body:surface" of `id`.
    pub fn surface_name(&self, id: SurfaceId) -> String {
        let body = &self.bodies[id.body];
        format!("{}:{}", body.name, body.surfaces[id.surface].0)
    }

    /// The id of the surface named "body:surface", if any.
    pub fn find_surface(&self, name: &str) -> Option<SurfaceId> {
        let (b, s) = name.split_once(':')?;
        let body = self.bodies.iter().position(|x| x.name == b)?;
        let surface = self.bodies[body].surfaces.iter().position(|x| x.0 == s)?;
        Some(SurfaceId { body, surface })
    }

    /// Displacement unknowns, 3 per point of every body.
    pub fn dofs(&self) -> usize {
        self.bodies.iter().map(|b| 3 * b.mesh.points().len()).sum()
    }

    /// Per body: the load vector (body force and tractions) and the prescribed dofs.
    ///
    /// # Errors
    /// [`ProblemError::Assembly`] for a degenerate cell.
    pub fn loads_and_supports(&self) -> Result<Vec<(Vec<f64>, Dirichlet)>, ProblemError> {
        self.bodies
            .iter()
            .enumerate()
            .map(|(b, body)| {
                let mut f = if body.body_force == [0.0; 3] {
                    vec![0.0; 3 * body.mesh.points().len()]
                } else {
                    body_force(&body.mesh, |_| body.body_force)
                        .map_err(|source| ProblemError::Assembly { body: b, source })?
                };
                for load in self.loads.iter().filter(|l| l.boundary.body == b) {
                    let t = traction(self.surface(load.boundary), |_, _| load.t);
                    for (a, v) in f.iter_mut().zip(t) {
                        *a += v;
                    }
                }
                let mut dirichlet = Dirichlet::new();
                for support in self.supports.iter().filter(|s| s.boundary.body == b) {
                    let surface = self.surface(support.boundary);
                    let used = surface.used_points();
                    dirichlet.fix_all((0..used.len()).filter(|&p| used[p]), support.values);
                }
                Ok((f, dirichlet))
            })
            .collect()
    }

    /// True when some interface is a contact interface.
    pub fn has_contact(&self) -> bool {
        self.interfaces.iter().any(|f| f.kind == Coupling::Contact)
    }

    /// Solves the problem ([`solve`]).
    ///
    /// # Errors
    /// As [`solve_coupled`].
    pub fn solve(&self, options: &SolveOptions) -> Result<Solution, ProblemError> {
        solve(self, options)
    }

    /// The solver's view of the bodies with their loads and supports.
    pub(crate) fn solver_bodies(&self, prepared: &[(Vec<f64>, Dirichlet)]) -> Vec<Body<'_>> {
        self.bodies
            .iter()
            .zip(prepared)
            .map(|(b, (load, dirichlet))| Body {
                mesh: &b.mesh,
                material: b.material,
                load: load.clone(),
                dirichlet: dirichlet.clone(),
                ties: Vec::new(),
            })
            .collect()
    }

    /// The solver's view of the interfaces.
    pub(crate) fn coupled(&self) -> Vec<Interface<'_>> {
        self.interfaces
            .iter()
            .map(|f| Interface {
                master: f.master.body,
                master_surface: self.surface(f.master),
                slave: f.slave.body,
                slave_surface: self.surface(f.slave),
                options: f.options,
                kind: f.kind,
            })
            .collect()
    }
}

/// Assembles and solves `problem`, glued and contact interfaces in any mix:
/// the loads and supports of each body, then [`solve_coupled`].
///
/// ```
/// use seam_fem::scene::{warped_glue, WarpedGlue};
/// use seam_fem::{solve, SolveOptions};
///
/// // Two blocks glued at a warped interface, the upper one pulled by
/// // t = (0.2, 0, −1) on its unit top and held by the interface alone.
/// let params = WarpedGlue { slave_cells: 2, ratio: 2, slave_layers: 2, master_layers: 2, ..Default::default() };
/// let solution = solve(&warped_glue(&params)?, &SolveOptions::default())?;
/// // The master holds the slave with the opposite of the load.
/// let force = solution.interfaces[0].force;
/// assert!((force[0] + 0.2).abs() < 1e-9 && force[1].abs() < 1e-9 && (force[2] - 1.0).abs() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// As [`solve_coupled`]; [`ProblemError::Assembly`] for a degenerate cell
/// under a body force.
pub fn solve(problem: &Problem, options: &SolveOptions) -> Result<Solution, ProblemError> {
    let Some((raised, ties)) = problem.enriched() else {
        let prepared = problem.loads_and_supports()?;
        return solve_coupled(&problem.solver_bodies(&prepared), &problem.coupled(), options);
    };
    let prepared = raised.loads_and_supports()?;
    let mut bodies = raised.solver_bodies(&prepared);
    for (body, ties) in bodies.iter_mut().zip(ties) {
        body.ties = ties;
    }
    let mut solution = solve_coupled(&bodies, &raised.coupled(), options)?;
    // Back to the original points (the raised meshes append theirs).
    for (b, body) in problem.bodies.iter().enumerate() {
        let n = body.mesh.points().len();
        solution.displacement[b].truncate(3 * n);
        solution.stresses[b].nodal.truncate(n);
        solution.stresses[b].nodal_von_mises.truncate(n);
    }
    for (s, f) in solution.interfaces.iter_mut().zip(&problem.interfaces) {
        s.truncate(problem.bodies[f.slave.body].mesh.points().len());
        let kinds = |p: &Problem| p.surface(f.slave).faces().iter().map(|f| f.kind()).collect::<Vec<_>>();
        s.enriched = kinds(&raised) != kinds(problem);
    }
    Ok(solution)
}

impl Problem {
    /// With dual multipliers on a glued slave surface with Tri6 or Quad8
    /// faces: the problem on the enriched slave space ([`crate::enrichment`]),
    /// its slave bodies raised, their surfaces indexing the raised points
    /// (the slave surfaces with Tri7 and Quad9 faces), and per body its ties;
    /// `None` when no interface needs it. A body with such a slave face on a
    /// Prism15 or Pyramid13 cell (no enriched kind) is not raised: its
    /// interfaces keep Popp's transformed basis ([`seam::BASIS_ALPHA`]).
    pub fn enriched(&self) -> Option<(Problem, Vec<Vec<crate::Tie>>)> {
        let needs = |f: &ProblemInterface| {
            f.kind == Coupling::Glue
                && f.options.multiplier == seam::Multiplier::Dual
                && self.surface(f.slave).faces().iter().any(|face| face.kind().info().enriched.is_some())
        };
        if !self.interfaces.iter().any(needs) {
            return None; // the common case: no copy of the problem
        }
        let mut raised = self.clone();
        let mut ties = vec![Vec::new(); self.bodies.len()];
        let mut any = false;
        for (b, body) in self.bodies.iter().enumerate() {
            let slaves: Vec<usize> = self
                .interfaces
                .iter()
                .filter(|f| f.slave.body == b && needs(f))
                .map(|f| f.slave.surface)
                .collect();
            let surfaces: Vec<&SurfaceMesh> = slaves.iter().map(|&s| &body.surfaces[s].1).collect();
            let Ok(Some(e)) = crate::enrich(&body.mesh, &surfaces) else { continue };
            let target = &mut raised.bodies[b];
            for (_, surface) in target.surfaces.iter_mut() {
                *surface = SurfaceMesh::new(e.mesh.points().to_vec(), surface.faces().to_vec())
                    .expect("the same faces over the same first points");
            }
            for (&s, surface) in slaves.iter().zip(e.surfaces) {
                target.surfaces[s].1 = surface;
            }
            target.mesh = e.mesh;
            ties[b] = e.ties;
            any = true;
        }
        any.then_some((raised, ties))
    }
}
