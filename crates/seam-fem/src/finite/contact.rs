//! Frictionless contact in finite deformation: the mortar terms on the
//! current configuration x = X + u, solved with the displacements by a
//! semi-smooth Newton method on the dual (or lumped) multipliers.
//!
//! # The discrete problem
//! At every Newton iteration each contact interface's D and B are assembled
//! on the current slave and master surfaces ((A1)–(D5), [`seam::assemble`]),
//! so that the pairs change as the bodies slide. With n_p the current unit
//! nodal normal of slave point p ([`seam::nodal_normals`]) and
//! N = [`seam::Mortar::nodal_d`] (N_pr = ∫ψ_p λ_r: D, or D Q⁻ᵀ on the
//! transformed second-order slave faces of [`crate::contact`]), the weighted
//! gap of a covered slave point is
//!
//! ```text
//! g̃_p(x) = n_p · (Σ_k B_pk x_m,k − Σ_r N_pr x_s,r)      (> 0 open)
//! ```
//!
//! With the pressures λ_p (the coefficients of the multiplier
//! λ_h = Σ_p λ_p ψ_p, per current area) and ĝ_p = ∂g̃_p/∂x at fixed n, N and
//! B (−N_pr n_p on slave point r, B_pk n_p on master point k), the residual
//! and the complementarity function in force units (Popp, Gitterle, Gee &
//! Wall 2010; Hüeber & Wohlmuth 2005) are
//!
//! ```text
//! R(u, λ) = f_int(u) − f − Σ_p λ_p ĝ_p ,
//! φ_p = d_p λ_p − max(0, d_p λ_p − c g̃_p) ,   c = E_max / h ,
//! ```
//!
//! d_p = D_pp and h the mean slave face diameter. A semi-smooth Newton step
//! solves, on A = {p : d_p λ_p − c g̃_p ≥ 0},
//!
//! ```text
//! [K(u) − Σ_p λ_p ∂ĝ_p/∂u   −ĝ_A] [Δu ]     [R]
//! [∇g̃_A                     0  ] [Δλ_A] = − [g̃_A] ,   Δλ_p = −λ_p off A,
//! ```
//!
//! on the free dofs of u = P y (glue eliminated as in [`super`]), by sparse
//! LU: the matrix is not symmetric. Points that are not covered have no row
//! and λ_p = 0 (they slid off the master). Newton stops when
//! ‖(Pᵀ R)_free, φ‖ ≤ rtol · max(‖f‖, ‖f_int‖) with the prescribed values
//! reached; a step that would invert a cell is halved.
//!
//! # The linearisation
//! n, N and B depend on the positions through the whole geometry kernel
//! (the frames, projection, clipping, inverse maps and quadrature), which
//! stays the one of [`seam::assemble`]. Their derivatives are central
//! differences of that kernel, taken for many points at once by colouring
//! (Curtis, Powell & Reid 1974): a slave point moves the rows of the slave
//! points of its faces, a master point those rows of B that meet its faces;
//! points that move no common row share a colour, and each colour costs six
//! evaluations of the interface (± a step of 10⁻⁶ h per direction). The
//! derivatives are exact to the differences' error (about 10⁻⁹ relative), so
//! Newton converges quadratically down to there.

use super::Bodies;
use crate::constraints::{triple_product, NONE};
use crate::hyperelastic::{FiniteError, NewtonOptions, NewtonReport, Nonlinear};
use crate::multibody::{Interface, ProblemError};
use crate::solution::{ContactFields, InterfaceSolution, Kkt};
use crate::solve::Dirichlet;
use rayon::prelude::*;
use seam::vec3::{dot, norm, sub};
use seam::{BasisTransformation, CsrMatrix, Face, Mortar, MortarError, MortarOptions, Point3, SurfaceMesh};

/// The step of the central differences, relative to the mean slave face
/// diameter.
const DIFFERENCE_STEP: f64 = 1e-6;

/// The smallest step factor when a step would invert a cell.
const MIN_STEP: f64 = 1.0 / 1024.0;

/// One side of a contact interface in its own numbering: the body points its
/// faces use (so that an evaluation copies the surface's points only).
struct Side {
    /// The body point of each local point.
    points: Vec<usize>,
    /// The faces, in local points.
    faces: Vec<Face>,
    /// The body's first dof.
    offset: usize,
}

impl Side {
    fn new(surface: &SurfaceMesh, offset: usize) -> Side {
        let used = surface.used_points();
        let points: Vec<usize> = (0..used.len()).filter(|&p| used[p]).collect();
        let mut local = vec![NONE; used.len()];
        for (l, &p) in points.iter().enumerate() {
            local[p] = l;
        }
        let faces = surface
            .faces()
            .iter()
            .map(|f| Face::from_nodes(&f.nodes().iter().map(|&p| local[p]).collect::<Vec<_>>()))
            .collect();
        Side { points, faces, offset }
    }

    /// x = X + u at the local points (`x0` the body's reference points, `u`
    /// all bodies' dofs).
    fn positions(&self, x0: &[Point3], u: &[f64]) -> Vec<Point3> {
        let u = &u[self.offset..];
        self.points.iter().map(|&p| std::array::from_fn(|c| x0[p][c] + u[3 * p + c])).collect()
    }

    /// The points `x0` of the body at the local points.
    fn at(&self, x0: &[Point3]) -> Vec<Point3> {
        self.points.iter().map(|&p| x0[p]).collect()
    }

    /// The global dof of component `c` of local point `l`.
    fn dof(&self, l: usize, c: usize) -> usize {
        self.offset + 3 * self.points[l] + c
    }
}

/// A contact interface between its two sides.
struct Pair<'a> {
    index: usize,
    slave: Side,
    master: Side,
    options: MortarOptions,
    /// The reference points of the slave and the master body.
    reference: (&'a [Point3], &'a [Point3]),
}

/// A contact interface evaluated on a configuration (local slave points).
struct Current {
    /// D and B; `None` where the surfaces do not overlap.
    mortar: Option<Mortar>,
    /// The unit nodal normals of the slave.
    normals: Vec<Point3>,
    /// N = D, or D Q⁻ᵀ.
    nodal_d: CsrMatrix,
    /// g̃_p (0 where not covered).
    gaps: Vec<f64>,
}

impl Current {
    fn covered(&self, p: usize) -> bool {
        self.mortar.as_ref().is_some_and(|m| m.covered[p])
    }

    fn b(&self) -> &CsrMatrix {
        &self.mortar.as_ref().expect("covered points have a mortar").b
    }

    /// d_p.
    fn d(&self, p: usize) -> f64 {
        self.mortar.as_ref().map_or(0.0, |m| m.d.get(p, p))
    }

    /// Σ_k |B_pk| |x_m,k| + Σ_r |N_pr| |x_s,r| at the current positions of
    /// all bodies' dofs `u` (the size of the terms of g̃_p).
    fn magnitude(&self, p: usize, pair: &Pair, u: &[f64]) -> f64 {
        let size = |side: &Side, x0: &[Point3], l: usize| {
            let q = side.points[l];
            let at = side.offset + 3 * q;
            norm(std::array::from_fn(|c| x0[q][c] + u[at + c]))
        };
        let (cols, vals) = self.nodal_d.row(p);
        let slave: f64 =
            cols.iter().zip(vals).map(|(&r, &v)| v.abs() * size(&pair.slave, pair.reference.0, r)).sum();
        let (cols, vals) = self.b().row(p);
        let master: f64 =
            cols.iter().zip(vals).map(|(&k, &v)| v.abs() * size(&pair.master, pair.reference.1, k)).sum();
        slave + master
    }

    /// ĝ_p as (global dof, value).
    fn gap_gradient(&self, pair: &Pair, p: usize) -> Vec<(usize, f64)> {
        let n = self.normals[p];
        let mut row = Vec::new();
        let (cols, vals) = self.nodal_d.row(p);
        for (&r, &v) in cols.iter().zip(vals) {
            row.extend((0..3).map(|c| (pair.slave.dof(r, c), -v * n[c])));
        }
        let (cols, vals) = self.b().row(p);
        for (&k, &v) in cols.iter().zip(vals) {
            row.extend((0..3).map(|c| (pair.master.dof(k, c), v * n[c])));
        }
        row
    }
}

/// Σ_q a_pq x_q.
fn row_times(a: &CsrMatrix, p: usize, x: &[Point3]) -> Point3 {
    let (cols, vals) = a.row(p);
    std::array::from_fn(|c| cols.iter().zip(vals).map(|(&q, &v)| v * x[q][c]).sum())
}

impl Pair<'_> {
    /// The interface at the local positions `xs`, `xm`.
    fn evaluate(&self, xs: Vec<Point3>, xm: Vec<Point3>) -> Result<Current, ProblemError> {
        let bad = |e: seam::MeshError| ProblemError::Finite {
            what: format!("interface {}: the deformed surfaces: {e}", self.index),
        };
        let slave = SurfaceMesh::new(xs, self.slave.faces.clone()).map_err(bad)?;
        let master = SurfaceMesh::new(xm, self.master.faces.clone()).map_err(bad)?;
        let normals = seam::nodal_normals(&slave);
        let mortar = match seam::assemble(&master, &slave, &self.options) {
            Ok(m) => m,
            Err(MortarError::NoOverlap { .. }) => {
                let gaps = vec![0.0; slave.n_points()];
                return Ok(Current { mortar: None, normals, nodal_d: CsrMatrix::zeros(0, 0), gaps });
            }
            Err(source) => return Err(ProblemError::Mortar { interface: self.index, source }),
        };
        let nodal_d = mortar.nodal_d();
        let gaps = (0..slave.n_points())
            .map(|p| match mortar.covered[p] {
                true => dot(
                    normals[p],
                    sub(row_times(&mortar.b, p, master.points()), row_times(&nodal_d, p, slave.points())),
                ),
                false => 0.0,
            })
            .collect();
        Ok(Current { mortar: Some(mortar), normals, nodal_d, gaps })
    }

    /// The current local positions of both sides.
    fn positions(&self, u: &[f64]) -> (Vec<Point3>, Vec<Point3>) {
        (self.slave.positions(self.reference.0, u), self.master.positions(self.reference.1, u))
    }

    /// Per point of the two sides (slave points first, then master points),
    /// the covered rows it moves: a slave point those of its faces' points, a
    /// master point the rows of B that meet its faces.
    fn influence(&self, base: &Current) -> Vec<Vec<usize>> {
        let ns = self.slave.points.len();
        let mut rows = vec![Vec::new(); ns + self.master.points.len()];
        let Some(m) = &base.mortar else { return rows };
        for f in &self.slave.faces {
            for &a in f.nodes() {
                rows[a].extend_from_slice(f.nodes());
            }
        }
        let bt = m.b.transpose();
        for g in &self.master.faces {
            let meet: Vec<usize> = g.nodes().iter().flat_map(|&k| bt.row(k).0.iter().copied()).collect();
            for &k in g.nodes() {
                rows[ns + k].extend_from_slice(&meet);
            }
        }
        for r in &mut rows {
            r.sort_unstable();
            r.dedup();
            r.retain(|&p| m.covered[p]);
        }
        rows
    }

    /// The contact terms' part of Newton's matrix at `base` (local positions
    /// `xs`, `xm`): −Σ_p λ_p ∂ĝ_p/∂u as triplets into `stiffness`, and ∇g̃_p
    /// for the points `wanted` (module doc: central differences by colour).
    fn linearise(
        &self,
        (xs, xm): (&[Point3], &[Point3]),
        base: &Current,
        (lambda, wanted): (&[f64], &[bool]),
        stiffness: &mut Vec<(usize, usize, f64)>,
    ) -> Result<Vec<Vec<(usize, f64)>>, ProblemError> {
        let ns = xs.len();
        let influence = self.influence(base);
        let h = DIFFERENCE_STEP * mean_diameter(&self.slave.faces, xs);
        let mut gradients = vec![Vec::new(); ns];
        let mut owner = vec![NONE; ns];
        for group in colours(&influence, ns) {
            for &node in &group {
                influence[node].iter().for_each(|&p| owner[p] = node);
            }
            let shifted = |c: usize, s: f64| {
                let (mut a, mut b) = (xs.to_vec(), xm.to_vec());
                for &node in &group {
                    match node < ns {
                        true => a[node][c] += s,
                        false => b[node - ns][c] += s,
                    }
                }
                self.evaluate(a, b)
            };
            let evaluations: Vec<_> =
                (0..3).into_par_iter().map(|c| rayon::join(|| shifted(c, h), || shifted(c, -h))).collect();
            for (c, (plus, minus)) in evaluations.into_iter().enumerate() {
                let (plus, minus) = (plus?, minus?);
                for p in (0..ns).filter(|&p| owner[p] != NONE) {
                    let node = owner[p];
                    let column = match node < ns {
                        true => self.slave.dof(node, c),
                        false => self.master.dof(node - ns, c),
                    };
                    let rows = Difference { base, plus: &plus, minus: &minus, width: 2.0 * h };
                    if wanted[p] {
                        gradients[p].push((column, (plus.gaps[p] - minus.gaps[p]) / rows.width));
                    }
                    if lambda[p] != 0.0 {
                        rows.add_stiffness(self, p, (column, lambda[p]), stiffness);
                    }
                }
            }
            for &node in &group {
                influence[node].iter().for_each(|&p| owner[p] = NONE);
            }
        }
        Ok(gradients)
    }
}

/// Two evaluations of an interface a step apart and the one between.
struct Difference<'a> {
    base: &'a Current,
    plus: &'a Current,
    minus: &'a Current,
    /// The distance between them.
    width: f64,
}

impl Difference<'_> {
    /// Column `column` of −λ_p ∂ĝ_p/∂u: λ_p (∂N_pr n_p + N_pr ∂n_p) at slave
    /// point r, −λ_p (∂B_pk n_p + B_pk ∂n_p) at master point k.
    fn add_stiffness(
        &self,
        pair: &Pair,
        p: usize,
        (column, lambda): (usize, f64),
        stiffness: &mut Vec<(usize, usize, f64)>,
    ) {
        let n = self.base.normals[p];
        let dn: Point3 =
            std::array::from_fn(|c| (self.plus.normals[p][c] - self.minus.normals[p][c]) / self.width);
        let weight = lambda / self.width;
        let mut add = |side: &Side, a: &CsrMatrix, sign: f64, (scale, direction): (f64, Point3)| {
            let (cols, vals) = a.row(p);
            for (&r, &v) in cols.iter().zip(vals) {
                stiffness.extend((0..3).map(|c| (side.dof(r, c), column, sign * scale * v * direction[c])));
            }
        };
        for (a, scale) in [(&self.plus.nodal_d, weight), (&self.minus.nodal_d, -weight)] {
            add(&pair.slave, a, 1.0, (scale, n));
        }
        add(&pair.slave, &self.base.nodal_d, 1.0, (lambda, dn));
        // A side that no longer overlaps has no row.
        for (c, scale) in [(self.plus, weight), (self.minus, -weight)] {
            if c.mortar.is_some() {
                add(&pair.master, c.b(), -1.0, (scale, n));
            }
        }
        add(&pair.master, self.base.b(), -1.0, (lambda, dn));
    }
}

/// The mean diameter of the faces at the positions `x` (the length of the
/// first corner's diagonal, or of the longest side of a triangle).
fn mean_diameter(faces: &[Face], x: &[Point3]) -> f64 {
    let length = |f: &Face| {
        let c = &f.nodes()[..f.n_corners()];
        (1..c.len()).map(|i| norm(sub(x[c[i]], x[c[0]]))).fold(0.0, f64::max)
    };
    faces.iter().map(length).sum::<f64>() / faces.len().max(1) as f64
}

/// Greedy colouring of the points by their `influence` (rows of `n_rows`):
/// no two points of a colour move a common row.
fn colours(influence: &[Vec<usize>], n_rows: usize) -> Vec<Vec<usize>> {
    let mut row_colours: Vec<Vec<u32>> = vec![Vec::new(); n_rows];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut taken = Vec::new();
    for (node, rows) in influence.iter().enumerate().filter(|(_, r)| !r.is_empty()) {
        taken.clear();
        taken.resize(groups.len() + 1, false);
        for &p in rows {
            row_colours[p].iter().for_each(|&c| taken[c as usize] = true);
        }
        let c = taken.iter().position(|&t| !t).expect("one more colour than groups");
        if c == groups.len() {
            groups.push(Vec::new());
        }
        groups[c].push(node);
        for &p in rows {
            row_colours[p].push(c as u32);
        }
    }
    groups
}

/// The contact interfaces of a finite-deformation problem.
pub(super) struct Contact<'a> {
    pairs: Vec<Pair<'a>>,
    /// c of the complementarity function.
    c: f64,
}

/// Per contact interface (in the order of the problem's contact
/// interfaces), the pressure λ_p of each slave body point.
pub(crate) type Pressures = Vec<Vec<f64>>;

/// The problem's state at one iterate.
struct State {
    currents: Vec<Current>,
    /// f_int(u).
    force: Vec<f64>,
    /// R(u, λ) over all dofs.
    residual: Vec<f64>,
    /// Per pair and local slave point: in A.
    active: Vec<Vec<bool>>,
    /// ‖((Pᵀ R)_free, φ)‖ and the force scale.
    norm: f64,
    scale: f64,
    /// The rounding error of φ: g̃_p is a difference of positions, so
    /// c g̃_p is known to about 8 ε c Σ (|B_pk| |x_m,k| + |N_pr| |x_s,r|),
    /// which small displacements far from the origin can make larger than
    /// rtol · scale.
    floor: f64,
}

/// A solved load step of contact in finite deformation.
pub(super) struct Solved {
    /// Newton's residuals and step factors.
    pub(super) report: NewtonReport,
    /// The KKT residuals of the solution.
    pub(super) kkt: Kkt,
    /// f_int(u) − Σ_p λ_p ĝ_p: the forces the bodies' cells and the contact
    /// interfaces exert, over all dofs.
    pub(super) internal: Vec<f64>,
    /// Per contact interface: its evaluation on the final configuration
    /// and its active points (in the local numbering: [`Contact::fields`]).
    currents: Vec<Current>,
    active: Vec<Vec<bool>>,
}

impl<'a> Contact<'a> {
    /// The contact `interfaces` (in problem order) of bodies at `offsets`
    /// with reference points `points[b]`; c from the largest Young's modulus
    /// `young`.
    pub(super) fn new(
        interfaces: &[(usize, &Interface)],
        offsets: &[usize],
        points: &[&'a [Point3]],
        young: f64,
    ) -> Contact<'a> {
        let pairs: Vec<Pair> = interfaces
            .iter()
            .map(|&(index, f)| Pair {
                index,
                slave: Side::new(f.slave_surface, offsets[f.slave]),
                master: Side::new(f.master_surface, offsets[f.master]),
                options: MortarOptions { transformation: BasisTransformation::All, ..f.options },
                reference: (points[f.slave], points[f.master]),
            })
            .collect();
        let h = pairs
            .iter()
            .map(|p| mean_diameter(&p.slave.faces, &p.slave.at(p.reference.0)))
            .fold(0.0, f64::max);
        Contact { pairs, c: young / h }
    }

    /// Whether there is any contact interface.
    pub(super) fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// The state at (u, λ): the interfaces on the current configuration,
    /// f_int, R, the active sets and the residual norm (module doc).
    fn state(&self, system: &Newton, u: &[f64], lambda: &Pressures) -> Result<State, ProblemError> {
        let force = system.bodies.force(u).map_err(|source| ProblemError::Newton { source })?;
        let currents = self
            .pairs
            .par_iter()
            .map(|pair| {
                let (xs, xm) = pair.positions(u);
                pair.evaluate(xs, xm)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut residual: Vec<f64> = force.iter().zip(system.load).map(|(a, b)| a - b).collect();
        let (mut phi2, mut floor2, mut active) = (0.0, 0.0, Vec::new());
        for ((pair, current), lambda) in self.pairs.iter().zip(&currents).zip(lambda) {
            let ns = pair.slave.points.len();
            let mut on = vec![false; ns];
            for p in (0..ns).filter(|&p| current.covered(p)) {
                let l = lambda[pair.slave.points[p]];
                let mu = current.d(p) * l;
                on[p] = mu - self.c * current.gaps[p] >= 0.0;
                let phi = if on[p] { self.c * current.gaps[p] } else { mu };
                phi2 += phi * phi;
                let size = current.magnitude(p, pair, u);
                floor2 += (8.0 * f64::EPSILON * self.c * size).powi(2);
                if l != 0.0 {
                    for (dof, v) in current.gap_gradient(pair, p) {
                        residual[dof] -= l * v;
                    }
                }
            }
            active.push(on);
        }
        let reduced = system.reduce(&residual);
        let r2: f64 = (0..u.len()).filter(|&i| !system.held[i]).map(|i| reduced[i] * reduced[i]).sum();
        let norm2 = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let scale = norm2(system.load).max(norm2(&force));
        Ok(State { currents, force, residual, active, norm: (r2 + phi2).sqrt(), scale, floor: floor2.sqrt() })
    }

    /// Newton's matrix at `state` in all dofs, K(u) − Σ_p λ_p ∂ĝ_p/∂u, and
    /// ∇g̃_p (per pair and local slave point) at the points `wanted`.
    #[allow(clippy::type_complexity)]
    fn jacobian(
        &self,
        system: &Newton,
        (u, lambda): (&[f64], &Pressures),
        state: &State,
        wanted: &[Vec<bool>],
    ) -> Result<(CsrMatrix, Vec<Vec<Vec<(usize, f64)>>>), ProblemError> {
        let mut triplets = Vec::new();
        let mut gradients = Vec::with_capacity(self.pairs.len());
        for ((pair, current), (lambda, wanted)) in
            self.pairs.iter().zip(&state.currents).zip(lambda.iter().zip(wanted))
        {
            let local: Vec<f64> = pair.slave.points.iter().map(|&q| lambda[q]).collect();
            let (xs, xm) = pair.positions(u);
            gradients.push(pair.linearise((&xs, &xm), current, (&local, wanted), &mut triplets)?);
        }
        let k = system.bodies.tangent(u).map_err(|source| ProblemError::Newton { source })?;
        Ok((added(&k, triplets), gradients))
    }

    /// One semi-smooth Newton step at `state`: (Δu, Δλ per pair and local
    /// slave point), the prescribed dofs moved by `remaining`.
    fn step(
        &self,
        system: &Newton,
        (u, lambda): (&[f64], &Pressures),
        state: &State,
        remaining: &[(usize, f64)],
    ) -> Result<(Vec<f64>, Vec<Vec<f64>>), ProblemError> {
        let n = u.len();
        let (k, gradients) = self.jacobian(system, (u, lambda), state, &state.active)?;
        let a = match system.p {
            Some(p) => triple_product(p, &k),
            None => k,
        };
        // The compact unknowns: free dofs, then the active points.
        let mut index = vec![NONE; n];
        let mut free = Vec::new();
        for i in (0..n).filter(|&i| !system.held[i] && a.row(i).0.contains(&i)) {
            index[i] = free.len();
            free.push(i);
        }
        let mut shift = vec![0.0; n];
        for &(dof, v) in remaining {
            shift[dof] = v;
        }
        let reduced = system.reduce(&state.residual);
        let mut rhs: Vec<f64> = free.iter().map(|&i| -reduced[i]).collect();
        let mut rows: Vec<Vec<(usize, f64)>> = free
            .iter()
            .enumerate()
            .map(|(r, &i)| {
                let (cols, vals) = a.row(i);
                let mut row = Vec::with_capacity(cols.len() + 3);
                for (&j, &v) in cols.iter().zip(vals) {
                    match index[j] {
                        NONE => rhs[r] -= v * shift[j],
                        c => row.push((c, v)),
                    }
                }
                row
            })
            .collect();
        let mut points = Vec::new();
        for (q, ((pair, current), (lambda, active))) in
            self.pairs.iter().zip(&state.currents).zip(lambda.iter().zip(&state.active)).enumerate()
        {
            for p in (0..pair.slave.points.len()).filter(|&p| current.covered(p)) {
                let l = lambda[pair.slave.points[p]];
                let column = system.through(&current.gap_gradient(pair, p));
                if !active[p] {
                    // Δλ_p = −λ_p: its column −ĝ_p moves to the right-hand side.
                    for (j, v) in column.into_iter().filter(|e| index[e.0] != NONE) {
                        rhs[index[j]] -= v * l;
                    }
                    continue;
                }
                let c = free.len() + points.len();
                for (j, v) in column.into_iter().filter(|e| index[e.0] != NONE) {
                    rows[index[j]].push((c, -v));
                }
                let mut row = Vec::new();
                let mut value = -current.gaps[p];
                for (j, v) in system.through(&gradients[q][p]) {
                    match index[j] {
                        NONE => value -= v * shift[j],
                        c => row.push((c, v)),
                    }
                }
                rows.push(row);
                rhs.push(value);
                points.push((q, p));
            }
        }
        let mut matrix = CsrMatrix::zeros(0, rows.len());
        for mut row in rows {
            row.sort_unstable_by_key(|e| e.0);
            matrix.indices.extend(row.iter().map(|e| e.0));
            matrix.values.extend(row.iter().map(|e| e.1));
            matrix.indptr.push(matrix.indices.len());
            matrix.nrows += 1;
        }
        let x = crate::backend::sparse_lu(&matrix, &rhs, &Dirichlet::new())
            .map_err(|e| ProblemError::Newton { source: FiniteError::Solve(e) })?;
        let mut dy = shift;
        for (k, &i) in free.iter().enumerate() {
            dy[i] = x[k];
        }
        let du = match system.p {
            Some(p) => p.mul_vec(&dy, 1),
            None => dy,
        };
        // Δλ: −λ everywhere but on A.
        let mut dlambda: Vec<Vec<f64>> = self
            .pairs
            .iter()
            .zip(lambda)
            .map(|(pair, lambda)| pair.slave.points.iter().map(|&q| -lambda[q]).collect())
            .collect();
        for (k, &(q, p)) in points.iter().enumerate() {
            dlambda[q][p] = x[free.len() + k];
        }
        Ok((du, dlambda))
    }
}

impl Contact<'_> {
    /// Newton's method for one load step from (u, λ), which it replaces by
    /// the solution's, with the prescribed values `dirichlet` (module doc).
    ///
    /// # Errors
    /// [`ProblemError::Newton`] for an inverted cell no step avoids, a
    /// singular step or no convergence within the cap;
    /// [`ProblemError::Mortar`] for a failed evaluation of an interface.
    pub(super) fn solve(
        &self,
        system: &Newton,
        dirichlet: &Dirichlet,
        (u, lambda): (&mut Vec<f64>, &mut Pressures),
        options: &NewtonOptions,
    ) -> Result<Solved, ProblemError> {
        let remaining = |u: &[f64]| -> Vec<(usize, f64)> {
            dirichlet.iter().filter(|&(d, v)| u[d] != v).map(|(d, v)| (d, v - u[d])).collect()
        };
        let relative = |s: &State| if s.scale > 0.0 { s.norm / s.scale } else { s.norm };
        let mut state = self.state(system, u, lambda)?;
        let mut report = NewtonReport::default();
        for iteration in 1..=options.max_iterations + 1 {
            let left = remaining(u);
            if left.is_empty() && state.norm <= (options.rtol * state.scale).max(state.floor) {
                let kkt = self.kkt(system, (u, lambda), &state);
                let internal = state.residual.iter().zip(system.load).map(|(r, f)| r + f).collect();
                return Ok(Solved { report, kkt, internal, currents: state.currents, active: state.active });
            }
            if iteration > options.max_iterations {
                break;
            }
            let (du, dlambda) = self.step(system, (u, lambda), &state, &left)?;
            let mut step = 1.0;
            loop {
                let mut trial_u: Vec<f64> = u.iter().zip(&du).map(|(a, d)| a + step * d).collect();
                if step == 1.0 {
                    // Exactly the prescribed values.
                    for &(d, v) in &left {
                        trial_u[d] = u[d] + v;
                    }
                }
                let mut trial_lambda = lambda.clone();
                for ((pair, l), dl) in self.pairs.iter().zip(&mut trial_lambda).zip(&dlambda) {
                    for (p, &q) in pair.slave.points.iter().enumerate() {
                        l[q] = if step == 1.0 && dl[p] == -l[q] { 0.0 } else { l[q] + step * dl[p] };
                    }
                }
                match self.state(system, &trial_u, &trial_lambda) {
                    Ok(next) => {
                        (*u, *lambda, state) = (trial_u, trial_lambda, next);
                        break;
                    }
                    Err(ProblemError::Newton { source }) if source.is_inversion() && step > MIN_STEP => {
                        step *= 0.5
                    }
                    Err(e) => return Err(e),
                }
            }
            report.residuals.push(relative(&state));
            report.line_search.push(step);
        }
        Err(ProblemError::Newton {
            source: FiniteError::NotConverged {
                iterations: options.max_iterations,
                residual: relative(&state),
                rtol: options.rtol,
            },
        })
    }

    /// How far the solution is from the discrete KKT conditions (each as
    /// [`Kkt`] defines it, with R for f − Ku − Cᵀλ and the gaps g̃_p / d_p).
    fn kkt(&self, system: &Newton, (u, lambda): (&[f64], &Pressures), state: &State) -> Kkt {
        let reduced = system.reduce(&state.residual);
        let max = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0, f64::max);
        let equilibrium = max(&mut (0..u.len()).filter(|&i| !system.held[i]).map(|i| reduced[i].abs()));
        let size = max(&mut system.load.iter().chain(&state.force).map(|v| v.abs()));
        let (mut pressures, mut gaps) = (Vec::new(), Vec::new());
        for ((pair, current), lambda) in self.pairs.iter().zip(&state.currents).zip(lambda) {
            for p in (0..pair.slave.points.len()).filter(|&p| current.covered(p)) {
                pressures.push(lambda[pair.slave.points[p]]);
                gaps.push(current.gaps[p] / current.d(p));
            }
        }
        let largest = max(&mut pressures.iter().map(|l| l.abs()));
        let length = max(&mut u.iter().chain(&gaps).map(|v| v.abs()));
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { a };
        Kkt {
            equilibrium: ratio(equilibrium, size),
            pressure: ratio(max(&mut pressures.iter().map(|&l| (-l).max(0.0))), largest),
            penetration: ratio(max(&mut gaps.iter().map(|&g| (-g).max(0.0))), length),
            complementarity: ratio(
                max(&mut pressures.iter().zip(&gaps).map(|(l, g)| (l * g).abs())),
                largest * length,
            ),
        }
    }

    /// The contact fields of the solved step into `out` (per interface of
    /// the problem): pressure, normal, gap g̃_p / d_p (the initial one on the
    /// reference configuration), active set, traction −λ_p n_p and the
    /// resultant −Σ d_p λ_p n_p, on the final configuration.
    pub(super) fn fields(
        &self,
        solved: &Solved,
        lambda: &Pressures,
        out: &mut [InterfaceSolution],
    ) -> Result<(), ProblemError> {
        for (((pair, current), active), lambda) in
            self.pairs.iter().zip(&solved.currents).zip(&solved.active).zip(lambda)
        {
            let initial = pair.evaluate(pair.slave.at(pair.reference.0), pair.master.at(pair.reference.1))?;
            let s = &mut out[pair.index];
            let n_points = s.traction.len();
            let fields = s.contact.get_or_insert_with(|| ContactFields::new(n_points));
            for p in (0..pair.slave.points.len()).filter(|&p| current.covered(p)) {
                let r = pair.slave.points[p];
                let (n, d, pressure) = (current.normals[p], current.d(p), lambda[r]);
                fields.contact[r] = true;
                fields.initial_gap[r] = if initial.covered(p) { initial.gaps[p] / initial.d(p) } else { 0.0 };
                fields.gap[r] = current.gaps[p] / d;
                fields.pressure[r] = pressure;
                fields.active[r] = active[p];
                s.constrained[r] = true;
                s.normal[r] = n;
                s.traction[r] = n.map(|v| -pressure * v);
                for c in 0..3 {
                    s.force[c] -= d * pressure * n[c];
                }
            }
        }
        Ok(())
    }
}

/// What Newton's method with contact works on: the bodies, the load, the
/// glue's P and the prescribed dofs.
pub(super) struct Newton<'a> {
    pub(super) bodies: &'a Bodies<'a>,
    pub(super) load: &'a [f64],
    pub(super) p: Option<&'a CsrMatrix>,
    pub(super) held: Vec<bool>,
}

impl Newton<'_> {
    /// Pᵀ r.
    fn reduce(&self, r: &[f64]) -> Vec<f64> {
        match self.p {
            Some(p) => p.transpose_mul_vec(r, 1),
            None => r.to_vec(),
        }
    }

    /// The sparse vector v through P: (v P)_j = Σ_d v_d P_dj (= (Pᵀ v)_j).
    fn through(&self, v: &[(usize, f64)]) -> Vec<(usize, f64)> {
        let mut out: Vec<(usize, f64)> = match self.p {
            None => v.to_vec(),
            Some(p) => v
                .iter()
                .flat_map(|&(d, a)| {
                    let (cols, vals) = p.row(d);
                    cols.iter().zip(vals).map(move |(&j, &w)| (j, a * w))
                })
                .collect(),
        };
        crate::contact::merged(&mut out)
    }
}

/// k plus the `triplets` (summed where they repeat).
fn added(k: &CsrMatrix, mut triplets: Vec<(usize, usize, f64)>) -> CsrMatrix {
    triplets.sort_by_key(|t| (t.0, t.1));
    let mut out = CsrMatrix::zeros(0, k.ncols);
    let mut t = 0;
    let mut row = Vec::new();
    for i in 0..k.nrows {
        row.clear();
        let (cols, vals) = k.row(i);
        row.extend(cols.iter().copied().zip(vals.iter().copied()));
        while t < triplets.len() && triplets[t].0 == i {
            row.push((triplets[t].1, triplets[t].2));
            t += 1;
        }
        for (j, v) in crate::contact::merged(&mut row) {
            out.indices.push(j);
            out.values.push(v);
        }
        out.indptr.push(out.indices.len());
        out.nrows += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{block, raise_order, BlockKind, Grid, Side as GridSide};
    use crate::hyperelastic::Hyperelastic;
    use crate::material::Material;
    use crate::multibody::Coupling;
    use seam::VolumeMesh;

    /// A small deterministic generator in [0, 1).
    fn random(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Newton's matrix against central differences of the residual, on two
    /// warped, partly overlapping bodies in sliding contact with pressures on
    /// every covered point: the contact part −Σ λ_p ∂ĝ_p/∂u column by column
    /// and ∇g̃_p entry by entry to 1e-6 of their largest entries, first order
    /// (Hex8 | Tet4) and second order (Hex20 | Tet10, transformed Tri6 slave
    /// basis), dual and lumped multipliers.
    #[test]
    fn newton_matrix_is_the_derivative_of_the_residual() {
        let material = Material::new(1000.0, 0.3).unwrap();
        let law = Hyperelastic::neo_hookean(&material);
        let cases = [
            ("Hex8 | Tet4, dual", None, seam::Multiplier::Dual),
            ("Hex20 | Tet10, dual", Some(false), seam::Multiplier::Dual),
            ("Hex8 | Tet4, lumped", None, seam::Multiplier::Lumped),
        ];
        for (label, raise, multiplier) in cases {
            let raised = |m: VolumeMesh| match raise {
                Some(complete) => raise_order(&m, complete).unwrap(),
                None => m,
            };
            let lower =
                raised(block(3, 3, 1, |x, y, z| [x, y, z * (1.0 + 0.1 * x * (1.0 - y))], BlockKind::Hex));
            let upper = raised(block(
                2,
                2,
                1,
                |x, y, z| [0.35 + 0.9 * x, 0.2 + 0.8 * y, 0.97 + 0.1 * x * (1.0 - y) + 0.5 * z],
                BlockKind::Tet,
            ));
            let top = Grid::new(3, 3, 1).side_faces(&lower, GridSide::ZMax).unwrap();
            let bottom = Grid::new(2, 2, 1).side_faces(&upper, GridSide::ZMin).unwrap();
            let interface = Interface {
                master: 0,
                master_surface: &top,
                slave: 1,
                slave_surface: &bottom,
                options: MortarOptions { multiplier, ..Default::default() },
                kind: Coupling::Contact,
                friction: 0.0,
            };
            let offsets = [0, 3 * lower.points().len(), 3 * (lower.points().len() + upper.points().len())];
            let n = offsets[2];
            let laws = [law, law];
            let nonlinear = Bodies { meshes: vec![&lower, &upper], laws: &laws, offsets: &offsets };
            let points = [lower.points(), upper.points()];
            let contact = Contact::new(&[(0, &interface)], &offsets, &points, material.young());
            let load = vec![0.0; n];
            let system = Newton { bodies: &nonlinear, load: &load, p: None, held: vec![false; n] };
            let mut seed = 7;
            let u: Vec<f64> = (0..n).map(|_| 0.02 * (random(&mut seed) - 0.5)).collect();
            let zero: Pressures = vec![vec![0.0; upper.points().len()]];
            let state = contact.state(&system, &u, &zero).unwrap();
            let (pair, current) = (&contact.pairs[0], &state.currents[0]);
            let covered: Vec<bool> = (0..pair.slave.points.len()).map(|p| current.covered(p)).collect();
            assert!(covered.iter().filter(|&&c| c).count() >= 4, "{label}");
            let mut lambda = zero.clone();
            for (_, &q) in pair.slave.points.iter().enumerate().filter(|(p, _)| covered[*p]) {
                lambda[0][q] = 50.0 * (0.5 + random(&mut seed));
            }
            let state = contact.state(&system, &u, &lambda).unwrap();
            let (k, gradients) =
                contact.jacobian(&system, (&u, &lambda), &state, std::slice::from_ref(&covered)).unwrap();
            let k_bodies = nonlinear.tangent(&u).unwrap();
            // The dofs of both surfaces' points.
            let dofs: Vec<usize> = (0..pair.slave.points.len())
                .flat_map(|l| (0..3).map(move |c| (true, l, c)))
                .chain((0..pair.master.points.len()).flat_map(|l| (0..3).map(move |c| (false, l, c))))
                .map(|(slave, l, c)| if slave { pair.slave.dof(l, c) } else { pair.master.dof(l, c) })
                .collect();
            let h = 1e-5 * mean_diameter(&pair.slave.faces, &pair.slave.at(points[1]));
            let (mut largest, mut worst, mut g_largest, mut g_worst) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            for &j in &dofs {
                let at = |s: f64| {
                    let mut v = u.clone();
                    v[j] += s;
                    let state = contact.state(&system, &v, &lambda).unwrap();
                    // R − (f_int − f): the contact terms −Σ λ_p ĝ_p.
                    let terms: Vec<f64> =
                        state.residual.iter().zip(&state.force).map(|(r, f)| r - f).collect();
                    (terms, state.currents[0].gaps.clone())
                };
                let ((tp, gp), (tm, gm)) = (at(h), at(-h));
                for i in 0..n {
                    let exact = k.get(i, j) - k_bodies.get(i, j);
                    let fd = (tp[i] - tm[i]) / (2.0 * h);
                    largest = largest.max(exact.abs());
                    worst = worst.max((exact - fd).abs());
                }
                for p in (0..covered.len()).filter(|&p| covered[p]) {
                    let exact = gradients[0][p].iter().filter(|e| e.0 == j).map(|e| e.1).sum::<f64>();
                    let fd = (gp[p] - gm[p]) / (2.0 * h);
                    g_largest = g_largest.max(exact.abs());
                    g_worst = g_worst.max((exact - fd).abs());
                }
            }
            println!("{label}: contact stiffness {worst:.2e} of {largest:.2e}, gap gradients {g_worst:.2e} of {g_largest:.2e}");
            assert!(largest > 0.0 && worst <= 1e-6 * largest, "{label}: {worst:e} of {largest:e}");
            assert!(g_largest > 0.0 && g_worst <= 1e-6 * g_largest, "{label}: {g_worst:e} of {g_largest:e}");
        }
    }
}
