//! A glued multi-body problem with named bodies and boundaries: what a case file
//! (`seam solve CASE.toml`) or a built-in example describes, in memory.
//!
//! Boundaries are named surfaces of a body ("body:surface"); Dirichlet
//! conditions, tractions and interfaces refer to them. [`solve`] builds
//! the loads f = ∫_Ω N b + ∫_Γ N t and the prescribed dofs of each body, and
//! hands them to [`crate::solve_coupled`].

use crate::assembly::{body_force, traction};
use crate::coupled::solve_coupled_from;
use crate::history::{Amplitude, LoadSteps, Value};
use crate::hyperelastic::FiniteError;
use crate::material::Material;
use crate::multibody::{Body, Coupling, Interface, ProblemError};
use crate::solution::{Solution, SolveOptions};
use crate::solve::Dirichlet;
use seam::{MortarOptions, Point3, SurfaceMesh, VolumeMesh};

/// A body with its named boundary surfaces.
#[derive(Clone, Debug)]
pub struct ProblemBody {
    /// Its name (unique in the problem).
    pub name: String,
    /// Its cells.
    pub mesh: VolumeMesh,
    /// Its material.
    pub material: Material,
    /// Its law: linear (small strain) or hyperelastic (finite deformation)
    /// with the material's constants.
    pub law: crate::Law,
    /// Force per volume (at the amplitude's factor 1).
    pub body_force: [f64; 3],
    /// How the body force follows the pseudo-time.
    pub body_force_amplitude: Amplitude,
    /// Named boundary surfaces, outward, indexing the mesh's points.
    pub surfaces: Vec<(String, SurfaceMesh)>,
}

impl ProblemBody {
    /// A linear body without body force.
    pub fn new(
        name: impl Into<String>,
        mesh: VolumeMesh,
        material: Material,
        surfaces: Vec<(String, SurfaceMesh)>,
    ) -> ProblemBody {
        ProblemBody {
            name: name.into(),
            mesh,
            material,
            law: crate::Law::Linear,
            body_force: [0.0; 3],
            body_force_amplitude: Amplitude::ramp(),
            surfaces,
        }
    }
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
    /// Contact: the Coulomb friction coefficient μ ≥ 0 (0: frictionless).
    pub friction: f64,
}

/// Prescribed displacement components on a boundary: a(t) · v(x, t) for the
/// amplitude a and the values v ([`crate::history`]).
#[derive(Clone, Debug)]
pub struct Support {
    /// The boundary.
    pub boundary: SurfaceId,
    /// u_x, u_y, u_z, each prescribed or free.
    pub values: [Option<Value>; 3],
    /// How the values follow the pseudo-time.
    pub amplitude: Amplitude,
}

impl Support {
    /// Components fixed at numbers, reached by the default ramp.
    pub fn new(boundary: SurfaceId, values: [Option<f64>; 3]) -> Support {
        Support { boundary, values: values.map(|v| v.map(Value::Number)), amplitude: Amplitude::ramp() }
    }
}

/// A traction (force per area) on a boundary: a(t) · t(x, t) for the
/// amplitude a and the components t ([`crate::history`]).
#[derive(Clone, Debug)]
pub struct Load {
    /// The boundary.
    pub boundary: SurfaceId,
    /// The traction vector's components.
    pub t: [Value; 3],
    /// How the traction follows the pseudo-time.
    pub amplitude: Amplitude,
}

impl Load {
    /// A uniform traction, reached by the default ramp.
    pub fn new(boundary: SurfaceId, t: [f64; 3]) -> Load {
        Load { boundary, t: t.map(Value::Number), amplitude: Amplitude::ramp() }
    }
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
    /// The pseudo-times the problem is solved at (default: t = 1 alone).
    pub steps: LoadSteps,
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

    /// Per body at pseudo-time `t`: the load vector (body force and
    /// tractions) and the prescribed dofs ([`crate::history`]).
    ///
    /// # Errors
    /// [`ProblemError::Assembly`] for a degenerate cell;
    /// [`ProblemError::Value`] for a value with no finite value at some point.
    pub fn loads_and_supports(&self, t: f64) -> Result<Vec<(Vec<f64>, Dirichlet)>, ProblemError> {
        self.bodies
            .iter()
            .enumerate()
            .map(|(b, body)| {
                let force = body.body_force.map(|v| v * body.body_force_amplitude.at(t));
                let mut f = if force == [0.0; 3] {
                    vec![0.0; 3 * body.mesh.points().len()]
                } else {
                    body_force(&body.mesh, |_| force)
                        .map_err(|source| ProblemError::Assembly { body: b, source })?
                };
                for load in self.loads.iter().filter(|l| l.boundary.body == b) {
                    for (a, v) in f.iter_mut().zip(self.traction_at(load, t)?) {
                        *a += v;
                    }
                }
                let mut dirichlet = Dirichlet::new();
                for support in self.supports.iter().filter(|s| s.boundary.body == b) {
                    self.fix(&mut dirichlet, support, t)?;
                }
                Ok((f, dirichlet))
            })
            .collect()
    }

    /// The consistent nodal forces of `load` at time `t`. A function is
    /// evaluated at the quadrature points; of the points where it has no
    /// finite value the lexicographically smallest is named (the same one
    /// for any thread count).
    fn traction_at(&self, load: &Load, t: f64) -> Result<Vec<f64>, ProblemError> {
        let a = load.amplitude.at(t);
        let surface = self.surface(load.boundary);
        if let [Some(x), Some(y), Some(z)] = load.t.each_ref().map(Value::number) {
            let value = [x * a, y * a, z * a];
            return Ok(traction(surface, |_, _| value));
        }
        let failed = std::sync::Mutex::new(None::<(Point3, usize, String)>);
        let f = traction(surface, |x, _| {
            std::array::from_fn(|k| match load.t[k].at(x, t) {
                Ok(v) => v * a,
                Err(why) => {
                    let mut first = failed.lock().unwrap_or_else(|e| e.into_inner());
                    if first
                        .as_ref()
                        .is_none_or(|(p, _, _)| x.partial_cmp(p) == Some(std::cmp::Ordering::Less))
                    {
                        *first = Some((x, k, why));
                    }
                    0.0
                }
            })
        });
        match failed.into_inner().unwrap_or_else(|e| e.into_inner()) {
            None => Ok(f),
            Some((_, k, why)) => Err(ProblemError::Value {
                what: format!("traction on {}, component {}", self.surface_name(load.boundary), k + 1),
                message: why,
            }),
        }
    }

    /// Prescribes `support` at time `t` on the points of its boundary.
    fn fix(&self, dirichlet: &mut Dirichlet, support: &Support, t: f64) -> Result<(), ProblemError> {
        let a = support.amplitude.at(t);
        let surface = self.surface(support.boundary);
        let used = surface.used_points();
        let points = (0..used.len()).filter(|&p| used[p]);
        if support.values.iter().flatten().all(|v| v.number().is_some()) {
            let values = support.values.each_ref().map(|v| v.as_ref().and_then(Value::number).map(|v| v * a));
            dirichlet.fix_all(points, values);
            return Ok(());
        }
        for p in points {
            let x = surface.points()[p];
            let mut values = [None; 3];
            for (k, v) in support.values.iter().enumerate() {
                if let Some(v) = v {
                    values[k] = Some(
                        v.at(x, t).map_err(|why| ProblemError::Value {
                            what: format!(
                                "dirichlet on {}, u{}",
                                self.surface_name(support.boundary),
                                ["x", "y", "z"][k]
                            ),
                            message: why,
                        })? * a,
                    );
                }
            }
            dirichlet.fix(p, values);
        }
        Ok(())
    }

    /// True when some contact interface has friction (μ > 0).
    pub fn has_friction(&self) -> bool {
        self.interfaces.iter().any(|f| f.kind == Coupling::Contact && f.friction > 0.0)
    }

    /// True when some interface is a contact interface.
    pub fn has_contact(&self) -> bool {
        self.interfaces.iter().any(|f| f.kind == Coupling::Contact)
    }

    /// Solves the problem ([`solve`]).
    ///
    /// # Errors
    /// As [`crate::solve_coupled`].
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

    /// The bodies' hyperelastic laws when every body has one, `None` when
    /// none has.
    ///
    /// # Errors
    /// [`ProblemError::MixedLaws`] naming a linear and a hyperelastic body.
    pub fn hyperelastic_laws(&self) -> Result<Option<Vec<crate::hyperelastic::Hyperelastic>>, ProblemError> {
        let laws: Vec<_> = self.bodies.iter().map(|b| b.law.hyperelastic(&b.material)).collect();
        let linear = self.bodies.iter().zip(&laws).find(|(_, l)| l.is_none());
        let hyperelastic = self.bodies.iter().zip(&laws).find(|(_, l)| l.is_some());
        match (linear, hyperelastic) {
            (Some((l, _)), Some((h, _))) => {
                Err(ProblemError::MixedLaws { linear: l.name.clone(), hyperelastic: h.name.clone() })
            }
            (_, Some(_)) => Ok(Some(laws.into_iter().flatten().collect())),
            _ => Ok(None),
        }
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
                friction: f.friction,
            })
            .collect()
    }
}

/// Assembles and solves `problem` at t = 1, glued and contact interfaces in
/// any mix: the loads and supports of each body, then [`crate::solve_coupled`]
/// (glue and frictionless contact do not depend on the load path, so the
/// earlier steps of [`Problem::steps`] are not needed; with friction or
/// hyperelastic bodies every step is solved in turn; [`solve_steps`] gives
/// each).
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
/// As [`crate::solve_coupled`]; [`ProblemError::Assembly`] for a degenerate cell
/// under a body force; [`ProblemError::Value`] for a load or support with no
/// finite value somewhere.
pub fn solve(problem: &Problem, options: &SolveOptions) -> Result<Solution, ProblemError> {
    let mut steps = Steps::new(problem, *options);
    if !problem.has_friction() && problem.hyperelastic_laws()?.is_none() {
        return steps.solve_at(1.0);
    }
    // Friction depends on the path: every step, the last one kept.
    let mut last = None;
    for step in steps {
        last = Some(step?.1);
    }
    Ok(last.expect("at least one load step"))
}

/// The solutions at the times of [`Problem::steps`], in order (an iterator:
/// each step is solved when asked for, and the caller keeps what it needs).
///
/// # Errors
/// Each item as [`solve`].
pub fn solve_steps<'a>(problem: &'a Problem, options: &SolveOptions) -> Steps<'a> {
    Steps::new(problem, *options)
}

/// The most halvings of a load step whose Newton iteration fails in finite
/// deformation ([`Steps`]).
pub const MAX_CUTS: usize = 5;

/// The iterator of [`solve_steps`]: (t, solution at t).
pub struct Steps<'a> {
    problem: &'a Problem,
    /// The problem on the enriched slave space, when it needs one ([`Problem::enriched`]).
    raised: Option<(Problem, Vec<Vec<crate::Tie>>)>,
    options: SolveOptions,
    next: usize,
    /// What friction carries from one step to the next.
    state: crate::contact::friction::FrictionState,
    /// Finite deformation: the last step's displacements and pressures.
    finite: crate::finite::FiniteState,
}

impl<'a> Steps<'a> {
    fn new(problem: &'a Problem, options: SolveOptions) -> Steps<'a> {
        Steps {
            problem,
            raised: problem.enriched(),
            options,
            next: 0,
            state: Default::default(),
            finite: Default::default(),
        }
    }

    /// The solution at pseudo-time `t`, from the state at `before`: in finite
    /// deformation, where Newton fails, the state is restored and the
    /// interval is cut in halves, solved one after the other, down to
    /// 2⁻[`MAX_CUTS`] of it; the report's Newton iterations are those of all
    /// its parts ([`crate::hyperelastic::NewtonReport::substeps`]).
    fn solve_through(&mut self, before: f64, t: f64, cuts: usize) -> Result<Solution, ProblemError> {
        let saved =
            (self.problem.hyperelastic_laws()?.is_some() && cuts < MAX_CUTS).then(|| self.finite.clone());
        match (self.solve_at(t), saved) {
            (Err(ProblemError::Newton { source }), Some(saved))
                if !matches!(source, FiniteError::Assembly(_)) =>
            {
                self.finite = saved;
                let middle = 0.5 * (before + t);
                let first = self.solve_through(before, middle, cuts + 1)?;
                let mut second = self.solve_through(middle, t, cuts + 1)?;
                if let (Some(a), Some(b)) = (&first.report.newton, &mut second.report.newton) {
                    b.residuals.splice(0..0, a.residuals.iter().copied());
                    b.line_search.splice(0..0, a.line_search.iter().copied());
                    b.substeps += a.substeps;
                    second.report.iterations = b.residuals.len();
                }
                Ok(second)
            }
            (solved, _) => solved,
        }
    }

    /// The solution at pseudo-time `t`: in small strain, or in finite
    /// deformation ([`crate::finite`]) when the bodies are hyperelastic.
    fn solve_at(&mut self, t: f64) -> Result<Solution, ProblemError> {
        let problem = self.problem;
        let laws = problem.hyperelastic_laws()?;
        let (options, state, finite) = (&self.options, &mut self.state, &mut self.finite);
        let mut solve = |bodies: &[Body], interfaces: &[Interface]| match &laws {
            Some(laws) => crate::finite::solve_finite_from(bodies, laws, interfaces, options, (t, finite)),
            None => solve_coupled_from(bodies, interfaces, options, state),
        };
        let Some((raised, ties)) = &self.raised else {
            let prepared = problem.loads_and_supports(t)?;
            let bodies = problem.solver_bodies(&prepared);
            return solve(&bodies, &problem.coupled());
        };
        let prepared = raised.loads_and_supports(t)?;
        let mut bodies = raised.solver_bodies(&prepared);
        for (body, ties) in bodies.iter_mut().zip(ties) {
            body.ties.clone_from(ties);
        }
        let mut solution = solve(&bodies, &raised.coupled())?;
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
            s.enriched = kinds(raised) != kinds(problem);
        }
        Ok(solution)
    }
}

impl Iterator for Steps<'_> {
    type Item = Result<(f64, Solution), ProblemError>;

    fn next(&mut self) -> Option<Self::Item> {
        let times = self.problem.steps.times();
        let t = *times.get(self.next)?;
        let before = if self.next == 0 { 0.0 } else { times[self.next - 1] };
        self.next += 1;
        Some(self.solve_through(before, t, 0).map(|s| (t, s)))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = self.problem.steps.len() - self.next;
        (left, Some(left))
    }
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
