//! Contact in finite deformation, frictionless and with Coulomb friction:
//! the mortar terms on the current configuration x = X + u, solved with the
//! displacements by a semi-smooth Newton method on the dual (or lumped)
//! multipliers.
//!
//! # The discrete problem
//! At every Newton iteration each contact interface's D and B are assembled
//! on the current slave and master surfaces ((A1)–(D5), [`seam::assemble`]),
//! so that the pairs change as the bodies slide. With N =
//! [`seam::Mortar::nodal_d`] (N_pr = ∫ψ_p λ_r: D, or D Q⁻ᵀ on the transformed
//! second-order slave faces of [`crate::contact`]), a covered slave point p
//! has the weighted relative position r_p = Σ_k B_pk x_m,k − Σ_r N_pr x_s,r,
//! the frame (n, τ₁, τ₂) of its current nodal normal ([`seam::nodal_normals`];
//! τ₁ from the last step's normal, [`frame`]), the weighted gap g̃_p = n·r_p
//! (> 0 open) and the weighted slip increment since the last load step,
//! frame-indifferent (Gitterle, Popp, Gee & Wall 2010):
//!
//! ```text
//! w_α = τ_α · ((B − Bⁿ) x_m − (N − Nⁿ) x_s)_p ,
//! ```
//!
//! Bⁿ, Nⁿ the last step's matrices (the reference configuration's before the
//! first step; a point not covered then carries no friction in this step).
//! The multiplier λ_p is a Cartesian vector (the master exerts −λ_p per
//! current area on the slave), so the residual is
//!
//! ```text
//! R(u, λ) = f_int(u) − f + Σ_p (N_p· ⊗ λ_p on the slave, −B_p· ⊗ λ_p on the master)
//! ```
//!
//! and Coulomb's law is the complementarity functions of
//! [`crate::contact::friction`] in force units, with λ_n = n·λ_p,
//! λ_τ = τ·λ_p, ξ = d_p λ_n − c_n g̃_p, v = d_p λ_τ + c_t w, c_n = E_max / h
//! (h the mean slave face diameter), c_t = c_n / 10: F_p = d_p λ_p where
//! ξ < 0 (inactive), else c_n g̃_p and per tangent c_t w_α in stick
//! (‖v‖ ≤ μ ξ) or d_p λ_τα − μ ξ v_α / ‖v‖ in slip; a tangent with μ = 0, along
//! a prescribed axis or without a slip history carries no friction,
//! d_p λ_τα = 0. Each semi-smooth Newton step takes the statuses from the
//! iterate and solves
//!
//! ```text
//! [∂R/∂u   ∂R/∂λ ] [Δu]     [R]
//! [∂F/∂u   ∂F/∂λ ] [Δλ] = − [F]
//! ```
//!
//! on the free dofs of u = P y (glue eliminated as in [`super`]) and three
//! unknowns per covered point, by sparse LU: the matrix is not symmetric.
//! Points that are not covered have no unknowns and λ_p = 0 (they slid off
//! the master). Newton stops when ‖((Pᵀ R)_free, F)‖ ≤ rtol · max(‖f‖,
//! ‖f_int‖) with the prescribed values reached, or at the rounding error of
//! F (below); a step that would invert a cell is halved.
//!
//! # The linearisation
//! n, τ, N and B depend on the positions through the whole geometry kernel
//! (the frames, projection, clipping, inverse maps and quadrature), which
//! stays the one of [`seam::assemble`]. Their derivatives are central
//! differences of that kernel, taken for many points at once by colouring
//! (Curtis, Powell & Reid 1974): a slave point moves the rows of the slave
//! points of its faces, a master point those rows of B that meet its faces;
//! points that move no common row share a colour, and each colour costs six
//! evaluations of the interface (± a step of 10⁻⁶ h per direction), each of
//! them (A1)–(D5) on the slave faces its points can change only, the other
//! faces' blocks kept from the base ([`seam::reassemble`]). ∂F/∂λ is
//! in closed form ([`Law::jacobian`]). The derivatives are exact to the
//! differences' error (about 10⁻⁹ relative), so Newton converges
//! quadratically down to there. r_p is summed about x_s,p, so that its
//! rounding error, and that of g̃_p and w, is that of lengths between nearby
//! points: 8 ε Σ (|B_pk| |x_m,k − x_s,p| + |N_pr| |x_s,r − x_s,p|) + …
//! ([`Current::magnitude`]), the floor of the residual.

use super::Bodies;
use crate::constraints::{triple_product, NONE};
use crate::hyperelastic::{FiniteError, Linear, NewtonOptions, NewtonReport, Nonlinear};
use crate::multibody::{Interface, ProblemError};
use crate::solution::{ContactFields, InterfaceSolution, Kkt};
use crate::solve::Dirichlet;
use crate::solve::SolveError;
use crate::Solver;
use rayon::prelude::*;
use seam::vec3::{dot, norm, sub};
use seam::{BasisTransformation, CsrMatrix, Face, Mortar, MortarError, MortarOptions, Point3, SurfaceMesh};

/// The step of the central differences, relative to the mean slave face
/// diameter.
const DIFFERENCE_STEP: f64 = 1e-6;

/// Newton gives up once its residual exceeds this many times the smallest
/// it has reached (after four iterations).
const DIVERGED: f64 = 1e3;

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
    /// Coulomb's μ.
    friction: f64,
}

/// A contact interface evaluated at positions (local numbering).
#[derive(Clone, Debug)]
pub(crate) struct Current {
    /// D and B; `None` where the surfaces do not overlap.
    mortar: Option<Mortar>,
    /// The unit nodal normals of the slave.
    normals: Vec<Point3>,
    /// N = D, or D Q⁻ᵀ.
    nodal_d: CsrMatrix,
    /// The positions of the slave and the master points.
    xs: Vec<Point3>,
    xm: Vec<Point3>,
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

    /// Σ_k B_pk x_m,k − Σ_r N_pr x_s,r with these matrices at the positions
    /// of `at` (the weighted position of the master relative to the slave),
    /// summed about o = x_s,p: Σ_k B_pk (x_m,k − o) − Σ_r N_pr (x_s,r − o) +
    /// (Σ_k B_pk − Σ_r N_pr) o, whose last term vanishes where p is covered,
    /// so that the rounding is that of the lengths between nearby points, not
    /// of the coordinates.
    fn relative(&self, p: usize, at: &Current) -> Point3 {
        let o = at.xs[p];
        let about = |a: &CsrMatrix, x: &[Point3]| -> (Point3, f64) {
            let (cols, vals) = a.row(p);
            let sum =
                std::array::from_fn(|c| cols.iter().zip(vals).map(|(&q, &v)| v * (x[q][c] - o[c])).sum());
            (sum, vals.iter().sum())
        };
        let ((m, bm), (s, ns)) = (about(self.b(), &at.xm), about(&self.nodal_d, &at.xs));
        std::array::from_fn(|c| m[c] - s[c] + (bm - ns) * o[c])
    }

    /// The size of the terms of [`Current::relative`] (at its own
    /// positions): Σ_k |B_pk| |x_m,k − o| + Σ_r |N_pr| |x_s,r − o| +
    /// |Σ_k B_pk − Σ_r N_pr| |o|.
    fn magnitude(&self, p: usize, at: &Current) -> f64 {
        let o = at.xs[p];
        let size = |a: &CsrMatrix, x: &[Point3]| {
            let (cols, vals) = a.row(p);
            let terms = cols.iter().zip(vals).map(|(&q, &v)| v.abs() * norm(sub(x[q], o))).sum::<f64>();
            (terms, vals.iter().sum::<f64>())
        };
        let ((m, bm), (s, ns)) = (size(self.b(), &at.xm), size(&self.nodal_d, &at.xs));
        m + s + (bm - ns).abs() * norm(o)
    }
}

/// The nodal frame (n, τ₁, τ₂) at the normal `n`: [`crate::contact::frame`]
/// where a component is prescribed; otherwise τ₁ is the axis most
/// orthogonal to `guide` (the last step's normal) made orthogonal to n, a
/// smooth function of n within a step (the axis most orthogonal to n itself
/// jumps where two components of n tie, as on a flat surface).
fn frame(n: Point3, fixed: [bool; 3], guide: Point3) -> Option<[Point3; 3]> {
    if fixed.iter().any(|&f| f) {
        return crate::contact::frame(n, fixed);
    }
    let length = norm(n);
    if length < 0.5 || length.is_nan() {
        return None;
    }
    let n = n.map(|v| v / length);
    let c = (0..3).min_by(|&i, &j| guide[i].abs().total_cmp(&guide[j].abs())).expect("three axes");
    let t = std::array::from_fn(|i| if i == c { 1.0 } else { 0.0 });
    let t = sub(t, n.map(|v| v * n[c]));
    let t1 = t.map(|v| v / norm(t));
    Some([n, t1, seam::vec3::cross(n, t1)])
}

/// Where a contact point is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Status {
    /// ξ < 0: λ = 0.
    Inactive,
    /// In contact, ‖v‖ ≤ μ ξ: no slip.
    Stick,
    /// In contact and slipping (or frictionless).
    Slip,
}

/// A covered slave point's geometry on a configuration.
struct Point {
    /// (n, τ₁, τ₂) ([`frame`]).
    frame: [Point3; 3],
    d: f64,
    /// g̃_p = n · (B x_m − N x_s).
    gap: f64,
    /// The weighted slip increment since the last load step,
    /// w_α = τ_α · ((B − Bⁿ) x_m − (N − Nⁿ) x_s) (Gitterle et al. 2010:
    /// frame-indifferent), if the point was covered then.
    slip: Option<[f64; 2]>,
    /// The rounding error of g̃_p and w (module doc).
    rounding: f64,
}

/// The complementarity functions of one point with λ and c_n, c_t.
struct Law {
    mu: f64,
    /// Tangents τ_α that carry friction (not held at the slave point).
    axes: [bool; 2],
    c_n: f64,
    c_t: f64,
}

impl Law {
    /// (ξ, v) with λ_n = n·λ, λ_τ = τ·λ: ξ = d λ_n − c_n g̃, v = d λ_τ + c_t w
    /// (force units).
    fn xi_v(&self, g: &Point, lambda: Point3) -> (f64, [f64; 2]) {
        let xi = g.d * dot(g.frame[0], lambda) - self.c_n * g.gap;
        let w = g.slip.unwrap_or([0.0; 2]);
        (xi, std::array::from_fn(|a| g.d * dot(g.frame[1 + a], lambda) + self.c_t * w[a]))
    }

    /// Whether axis α carries friction at `g`.
    fn frictional(&self, g: &Point, a: usize) -> bool {
        self.mu > 0.0 && self.axes[a] && g.slip.is_some()
    }

    /// The status the iterate λ gives the point.
    fn status(&self, g: &Point, lambda: Point3) -> Status {
        let (xi, v) = self.xi_v(g, lambda);
        let norm_v = (0..2).filter(|&a| self.frictional(g, a)).map(|a| v[a] * v[a]).sum::<f64>().sqrt();
        match () {
            _ if xi < 0.0 => Status::Inactive,
            _ if (0..2).any(|a| self.frictional(g, a)) && norm_v <= self.mu * xi => Status::Stick,
            _ => Status::Slip,
        }
    }

    /// F_p (force units) for the status `s`: d λ when inactive; else c_n g̃
    /// and per tangent d λ_τα where it carries no friction, c_t w_α in
    /// stick, d λ_τα − μ ξ v_α / ‖v‖ in slip (Coulomb's
    /// C_τ = max(μξ, ‖v‖) λ_τ − μ max(0, ξ) v over ‖v‖, friction module doc).
    fn rows(&self, g: &Point, lambda: Point3, s: Status) -> [f64; 3] {
        if s == Status::Inactive {
            return lambda.map(|l| g.d * l);
        }
        let (xi, v) = self.xi_v(g, lambda);
        let norm_v = (0..2).filter(|&a| self.frictional(g, a)).map(|a| v[a] * v[a]).sum::<f64>().sqrt();
        let w = g.slip.unwrap_or([0.0; 2]);
        let mut out = [self.c_n * g.gap, 0.0, 0.0];
        for a in 0..2 {
            let lt = g.d * dot(g.frame[1 + a], lambda);
            out[1 + a] = match (self.frictional(g, a), s) {
                (false, _) => lt,
                (true, Status::Stick) => self.c_t * w[a],
                (true, _) => lt - self.mu * xi * v[a] / norm_v,
            };
        }
        out
    }

    /// ∂F/∂λ of [`Law::rows`] (rows of F, columns of the Cartesian λ): d I
    /// when inactive; else 0 for the normal row and per tangent d τ_αᵀ where
    /// it carries no friction, 0 in stick, and in slip
    /// d τ_αᵀ − μ (v̂_α d nᵀ + ξ Σ_β (δ_αβ − v̂_α v̂_β) d τ_βᵀ / ‖v‖), v̂ = v / ‖v‖
    /// over the axes that carry friction.
    fn jacobian(&self, g: &Point, lambda: Point3, s: Status) -> [[f64; 3]; 3] {
        let mut out = [[0.0; 3]; 3];
        if s == Status::Inactive {
            (0..3).for_each(|k| out[k][k] = g.d);
            return out;
        }
        let (xi, v) = self.xi_v(g, lambda);
        let axes: Vec<usize> = (0..2).filter(|&a| self.frictional(g, a)).collect();
        let norm_v = axes.iter().map(|&a| v[a] * v[a]).sum::<f64>().sqrt();
        for a in 0..2 {
            let row = &mut out[1 + a];
            match (self.frictional(g, a), s) {
                (false, _) => *row = g.frame[1 + a].map(|t| g.d * t),
                (true, Status::Stick) => {}
                (true, _) => {
                    let hat = |b: usize| v[b] / norm_v;
                    for c in 0..3 {
                        let mut sum = g.d * g.frame[1 + a][c] - self.mu * hat(a) * g.d * g.frame[0][c];
                        for &b in &axes {
                            let delta = if a == b { 1.0 } else { 0.0 };
                            sum -=
                                self.mu * xi * (delta - hat(a) * hat(b)) * g.d * g.frame[1 + b][c] / norm_v;
                        }
                        row[c] = sum;
                    }
                }
            }
        }
        out
    }
}

impl Pair<'_> {
    /// The interface at the local positions `xs`, `xm`.
    fn evaluate(&self, xs: Vec<Point3>, xm: Vec<Point3>) -> Result<Current, ProblemError> {
        let whole = |m: &SurfaceMesh, s: &SurfaceMesh| seam::assemble(m, s, &self.options).map(|m| (m, ()));
        Ok(self.evaluate_with(xs, (xm, &self.master.faces), whole)?.0)
    }

    /// [`Pair::evaluate`] against the master faces `faces` only, the operator
    /// from `assemble` (master, slave) with what else it returns (`None`
    /// without overlap).
    fn evaluate_with<T>(
        &self,
        xs: Vec<Point3>,
        (xm, faces): (Vec<Point3>, &[Face]),
        assemble: impl FnOnce(&SurfaceMesh, &SurfaceMesh) -> Result<(Mortar, T), MortarError>,
    ) -> Result<(Current, Option<T>), ProblemError> {
        let bad = |e: seam::MeshError| ProblemError::Finite {
            what: format!("interface {}: the deformed surfaces: {e}", self.index),
        };
        let slave = SurfaceMesh::new(xs, self.slave.faces.clone()).map_err(bad)?;
        let master = SurfaceMesh::new(xm, faces.to_vec()).map_err(bad)?;
        let normals = seam::nodal_normals(&slave);
        let (mortar, extra) = match assemble(&master, &slave) {
            Ok((m, extra)) => (Some(m), Some(extra)),
            Err(MortarError::NoOverlap { .. }) => (None, None),
            Err(source) => return Err(ProblemError::Mortar { interface: self.index, source }),
        };
        let nodal_d = mortar.as_ref().map_or(CsrMatrix::zeros(0, 0), |m| m.nodal_d());
        let (xs, xm) = (slave.into_parts().0, master.into_parts().0);
        Ok((Current { mortar, normals, nodal_d, xs, xm }, extra))
    }

    /// The current local positions of both sides.
    fn positions(&self, u: &[f64]) -> (Vec<Point3>, Vec<Point3>) {
        (self.slave.positions(self.reference.0, u), self.master.positions(self.reference.1, u))
    }

    /// The interface on the reference configuration.
    fn reference(&self) -> Result<Current, ProblemError> {
        self.evaluate(self.slave.at(self.reference.0), self.master.at(self.reference.1))
    }

    /// Covered point p's geometry at `current`, `old` the last load step's
    /// evaluation, `held` the prescribed dofs; `None` when its normal is
    /// prescribed.
    fn point(&self, current: &Current, old: &Current, p: usize, held: &[bool]) -> Option<Point> {
        let fixed: [bool; 3] = std::array::from_fn(|c| held[self.slave.dof(p, c)]);
        let guide = if old.covered(p) { old.normals[p] } else { current.normals[p] };
        let frame = frame(current.normals[p], fixed, guide)?;
        let relative = current.relative(p, current);
        let slip = old.covered(p).then(|| {
            let w = sub(relative, old.relative(p, current));
            [dot(frame[1], w), dot(frame[2], w)]
        });
        let rounding =
            current.magnitude(p, current) + if old.covered(p) { old.magnitude(p, current) } else { 0.0 };
        Some(Point {
            frame,
            d: current.d(p),
            gap: dot(frame[0], relative),
            slip,
            rounding: 8.0 * f64::EPSILON * rounding,
        })
    }

    /// Per point of the two sides (slave points first, then master points),
    /// the covered rows it moves: a slave point those of its faces' points, a
    /// master point the rows of B (and of the last step's Bⁿ, through the
    /// slip) that meet its faces.
    fn influence(&self, base: &Current, old: &Current) -> Vec<Vec<usize>> {
        let ns = self.slave.points.len();
        let mut rows = vec![Vec::new(); ns + self.master.points.len()];
        let Some(m) = &base.mortar else { return rows };
        for f in &self.slave.faces {
            for &a in f.nodes() {
                rows[a].extend_from_slice(f.nodes());
            }
        }
        let bt = m.b.transpose();
        let old_bt = old.mortar.as_ref().map(|m| m.b.transpose());
        for g in &self.master.faces {
            let mut meet: Vec<usize> = g.nodes().iter().flat_map(|&k| bt.row(k).0.iter().copied()).collect();
            if let Some(old_bt) = &old_bt {
                meet.extend(g.nodes().iter().flat_map(|&k| old_bt.row(k).0.iter().copied()));
            }
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
}

/// One contact interface at an iterate: its evaluation and, per local slave
/// point, its multiplier, geometry and status (covered points with a free
/// normal only).
struct Iterate {
    current: Current,
    points: Vec<Option<(Point, Status)>>,
}

/// The contact interfaces of a finite-deformation problem.
pub(super) struct Contact<'a> {
    pairs: Vec<Pair<'a>>,
    /// c_n of the complementarity functions, E_max / h; c_t = [`C_T`] c_n.
    c: f64,
}

/// c_t / c_n, as in small strain ([`crate::contact::friction`]).
const C_T: f64 = 0.1;

/// What contact carries from one load step to the next, per contact
/// interface (in the problem's order of contact interfaces).
#[derive(Clone, Debug, Default)]
pub(crate) struct History {
    /// λ_p (Cartesian: the master exerts −λ_p per current area on the
    /// slave) per slave body point.
    lambda: Vec<Vec<Point3>>,
    /// The evaluation at the end of the last step (the reference
    /// configuration before the first).
    previous: Vec<Current>,
    /// The accumulated slip of the slave against the master per slave body
    /// point, and that of the last step.
    slip: Vec<Vec<(Point3, Point3)>>,
}

/// The problem's state at one iterate.
struct State {
    iterates: Vec<Iterate>,
    /// f_int(u).
    force: Vec<f64>,
    /// R(u, λ) over all dofs.
    residual: Vec<f64>,
    /// ‖((Pᵀ R)_free, F)‖ and the force scale.
    norm: f64,
    scale: f64,
    /// The rounding error of F: g̃_p and w are differences of positions,
    /// known to about 8 ε Σ (|B_pk| |x_m,k| + |N_pr| |x_s,r|) each, which
    /// small displacements far from the origin can make larger than
    /// rtol · scale.
    floor: f64,
}

/// A solved load step of contact in finite deformation.
pub(super) struct Solved {
    /// Newton's residuals and step factors.
    pub(super) report: NewtonReport,
    /// The KKT residuals of the solution.
    pub(super) kkt: Kkt,
    /// f_int(u) + the contact forces on the bodies' dofs (the forces the
    /// cells and the contact interfaces exert), over all dofs.
    pub(super) internal: Vec<f64>,
    /// Per contact interface at the solution.
    iterates: Vec<Iterate>,
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
                friction: f.friction,
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

    /// A history at rest: no multipliers, no slip, the interfaces on the
    /// reference configuration; `history` itself if it fits.
    pub(super) fn history(&self, history: History) -> Result<History, ProblemError> {
        if history.previous.len() == self.pairs.len() {
            return Ok(history);
        }
        let sizes = |p: &Pair| p.reference.0.len();
        Ok(History {
            lambda: self.pairs.iter().map(|p| vec![[0.0; 3]; sizes(p)]).collect(),
            previous: self.pairs.iter().map(Pair::reference).collect::<Result<_, _>>()?,
            slip: self.pairs.iter().map(|p| vec![([0.0; 3], [0.0; 3]); sizes(p)]).collect(),
        })
    }

    fn law(&self, pair: &Pair, p: usize, held: &[bool], g: &Point) -> Law {
        let axes = std::array::from_fn(|a| {
            // A tangent along a prescribed axis carries no friction (its reaction does).
            let t = g.frame[1 + a];
            !(0..3).any(|c| held[pair.slave.dof(p, c)] && t[c].abs() == 1.0)
        });
        Law { mu: pair.friction, axes, c_n: self.c, c_t: C_T * self.c }
    }

    /// The state at (u, λ): the interfaces on the current configuration, each
    /// point's status (from the iterate, or `statuses` when given), f_int, R
    /// and the residual norm (module doc).
    fn state(
        &self,
        system: &Newton,
        (u, history): (&[f64], &History),
        statuses: Option<&[Vec<Option<Status>>]>,
    ) -> Result<State, ProblemError> {
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
        let (mut f2, mut floor2, mut iterates) = (0.0, 0.0, Vec::new());
        for (q, (pair, current)) in self.pairs.iter().zip(currents).enumerate() {
            let ns = pair.slave.points.len();
            let mut points = Vec::with_capacity(ns);
            for p in 0..ns {
                let point = current
                    .covered(p)
                    .then(|| pair.point(&current, &history.previous[q], p, &system.held))
                    .flatten();
                let Some(g) = point else {
                    points.push(None);
                    continue;
                };
                let lambda = history.lambda[q][pair.slave.points[p]];
                let law = self.law(pair, p, &system.held, &g);
                let status = match statuses {
                    Some(s) => s[q][p].expect("the same points"),
                    None => law.status(&g, lambda),
                };
                let rows = law.rows(&g, lambda, status);
                f2 += rows.iter().map(|v| v * v).sum::<f64>();
                floor2 += ((law.c_n + 2.0 * law.c_t) * g.rounding).powi(2);
                // The master exerts −λ_p on the slave: +N λ on the slave's dofs, −B λ on the master's.
                let (cols, vals) = current.nodal_d.row(p);
                for (&r, &v) in cols.iter().zip(vals) {
                    (0..3).for_each(|c| residual[pair.slave.dof(r, c)] += v * lambda[c]);
                }
                let (cols, vals) = current.b().row(p);
                for (&k, &v) in cols.iter().zip(vals) {
                    (0..3).for_each(|c| residual[pair.master.dof(k, c)] -= v * lambda[c]);
                }
                points.push(Some((g, status)));
            }
            iterates.push(Iterate { current, points });
        }
        let reduced = system.reduce(&residual);
        let r2: f64 = (0..u.len()).filter(|&i| !system.held[i]).map(|i| reduced[i] * reduced[i]).sum();
        let norm2 = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let scale = norm2(system.load).max(norm2(&force));
        Ok(State { iterates, force, residual, norm: (r2 + f2).sqrt(), scale, floor: floor2.sqrt() })
    }

    /// Newton's matrix at `state` over all dofs and the points' multipliers:
    /// ∂R/∂u (K(u) + ∂(N λ, −B λ)/∂u) as a matrix, and per pair and covered
    /// point ∂F_p/∂u (three sparse rows) and ∂F_p/∂λ_p (module doc: central
    /// differences, by colour in u).
    #[allow(clippy::type_complexity)]
    fn jacobian(
        &self,
        system: &Newton,
        (u, history): (&[f64], &History),
        state: &State,
    ) -> Result<(CsrMatrix, Vec<Vec<PointRows>>), ProblemError> {
        let mut triplets = Vec::new();
        let mut rows = Vec::with_capacity(self.pairs.len());
        for (q, (pair, iterate)) in self.pairs.iter().zip(&state.iterates).enumerate() {
            rows.push(self.linearise(pair, (q, iterate), (history, &system.held), &mut triplets)?);
        }
        let k = system.bodies.tangent(u).map_err(|source| ProblemError::Newton { source })?;
        Ok((added(&k, triplets), rows))
    }

    /// [`Contact::jacobian`] of one pair: the force terms' derivatives as
    /// triplets into `stiffness`, the points' rows returned.
    fn linearise(
        &self,
        pair: &Pair,
        (q, base): (usize, &Iterate),
        (history, held): (&History, &[bool]),
        stiffness: &mut Vec<(usize, usize, f64)>,
    ) -> Result<Vec<PointRows>, ProblemError> {
        let (xs, xm) = (&base.current.xs, &base.current.xm);
        let ns = xs.len();
        let lambda = |p: usize| history.lambda[q][pair.slave.points[p]];
        let old = &history.previous[q];
        let mut out: Vec<PointRows> = (0..ns).map(|_| PointRows::default()).collect();
        // ∂F_p/∂λ_p in closed form ([`Law::jacobian`]).
        for (p, point) in base.points.iter().enumerate() {
            let Some((g, status)) = point else { continue };
            out[p].lambda = self.law(pair, p, held, g).jacobian(g, lambda(p), *status);
        }
        // ∂/∂u by colour, against the master faces that meet the slave (a
        // step of 10⁻⁶ h makes no new pair but where a corner crosses an edge),
        // for the rows that have one: an inactive point with λ_p = 0 has
        // F_p = d_p λ_p and no force terms, both constant in u there.
        let mut influence = pair.influence(&base.current, old);
        let moving: Vec<bool> = (0..ns)
            .map(|p| {
                base.points[p].as_ref().is_some_and(|(_, s)| *s != Status::Inactive || lambda(p) != [0.0; 3])
            })
            .collect();
        influence.iter_mut().for_each(|rows| rows.retain(|&p| moving[p]));
        let near: Vec<Face> = pair
            .master
            .faces
            .iter()
            .filter(|f| f.nodes().iter().any(|&k| !influence[ns + k].is_empty()))
            .copied()
            .collect();
        let h = DIFFERENCE_STEP * mean_diameter(&pair.slave.faces, xs);
        if influence.iter().all(Vec::is_empty) {
            return Ok(out);
        }
        // The face blocks at the base, kept: a colour's evaluations compute
        // only the slave faces its points can change ([`seam::reassemble`]).
        let keep = |m: &SurfaceMesh, s: &SurfaceMesh| {
            let (mortar, kept) = seam::assemble_keeping(m, s, &pair.options)?;
            Ok((mortar, (kept, seam::slave_faces_near(m, s, &pair.options, 2.0 * h))))
        };
        let Some((kept, slave_faces_near)) = pair.evaluate_with(xs.clone(), (xm.clone(), &near), keep)?.1
        else {
            return Ok(out);
        };
        let faces_of = |faces: &[Face], n: usize| {
            let mut of = vec![Vec::new(); n];
            for (f, face) in faces.iter().enumerate() {
                face.nodes().iter().for_each(|&a| of[a].push(f));
            }
            of
        };
        let (slave_faces_of, master_faces_of) = (faces_of(&pair.slave.faces, ns), faces_of(&near, xm.len()));
        let mut owner = vec![NONE; ns];
        for group in colours(&influence, ns) {
            for &node in &group {
                influence[node].iter().for_each(|&p| owner[p] = node);
            }
            let mut moved: Vec<usize> = Vec::new();
            for &node in &group {
                match node < ns {
                    true => moved.extend(&slave_faces_of[node]),
                    false => {
                        master_faces_of[node - ns].iter().for_each(|&g| moved.extend(&slave_faces_near[g]))
                    }
                }
            }
            moved.sort_unstable();
            moved.dedup();
            let shifted = |c: usize, s: f64| {
                let (mut a, mut b) = (xs.clone(), xm.clone());
                for &node in &group {
                    match node < ns {
                        true => a[node][c] += s,
                        false => b[node - ns][c] += s,
                    }
                }
                let again = |m: &SurfaceMesh, s: &SurfaceMesh| {
                    seam::reassemble(m, s, &pair.options, &kept, &moved).map(|m| (m, ()))
                };
                Ok::<_, ProblemError>(pair.evaluate_with(a, (b, &near), again)?.0)
            };
            let evaluations: Vec<_> =
                (0..3).into_par_iter().map(|c| rayon::join(|| shifted(c, h), || shifted(c, -h))).collect();
            for (c, (plus, minus)) in evaluations.into_iter().enumerate() {
                let (plus, minus) = (plus?, minus?);
                for p in (0..ns).filter(|&p| owner[p] != NONE) {
                    let Some((g, status)) = &base.points[p] else { continue };
                    let node = owner[p];
                    let column = match node < ns {
                        true => pair.slave.dof(node, c),
                        false => pair.master.dof(node - ns, c),
                    };
                    let l = lambda(p);
                    let law = self.law(pair, p, held, g);
                    let rows = |e: &Current| match e.covered(p) {
                        true => pair.point(e, old, p, held).map(|g| law.rows(&g, l, *status)),
                        false => None,
                    };
                    if let (Some(a), Some(b)) = (rows(&plus), rows(&minus)) {
                        for k in 0..3 {
                            out[p].u[k].push((column, (a[k] - b[k]) / (2.0 * h)));
                        }
                    }
                    if l != [0.0; 3] {
                        let weight = 1.0 / (2.0 * h);
                        for (e, sign) in [(&plus, weight), (&minus, -weight)] {
                            add_force_terms(pair, e, p, (column, l.map(|v| sign * v)), stiffness);
                        }
                    }
                }
            }
            for &node in &group {
                influence[node].iter().for_each(|&p| owner[p] = NONE);
            }
        }
        Ok(out)
    }
}

/// The derivatives of one point's F_p: per row, the sparse ∂/∂u (global
/// dofs, summed where they repeat) and ∂/∂λ_p.
#[derive(Default)]
struct PointRows {
    u: [Vec<(usize, f64)>; 3],
    lambda: [[f64; 3]; 3],
}

/// Column `column` of the force terms (N_pr λ at slave point r, −B_pk λ at
/// master point k) of point p at the evaluation `e`, times the weighted λ.
fn add_force_terms(
    pair: &Pair,
    e: &Current,
    p: usize,
    (column, lambda): (usize, Point3),
    stiffness: &mut Vec<(usize, usize, f64)>,
) {
    if !e.covered(p) {
        return;
    }
    let (cols, vals) = e.nodal_d.row(p);
    for (&r, &v) in cols.iter().zip(vals) {
        stiffness.extend((0..3).map(|c| (pair.slave.dof(r, c), column, v * lambda[c])));
    }
    let (cols, vals) = e.b().row(p);
    for (&k, &v) in cols.iter().zip(vals) {
        stiffness.extend((0..3).map(|c| (pair.master.dof(k, c), column, -v * lambda[c])));
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

impl Contact<'_> {
    /// One semi-smooth Newton step at `state`: Δu and Δλ (per pair and
    /// local slave point), the prescribed dofs moved by `remaining`.
    #[allow(clippy::type_complexity)]
    fn step(
        &self,
        system: &Newton,
        (u, history): (&[f64], &History),
        state: &State,
        remaining: &[(usize, f64)],
        linear: &mut Linear,
    ) -> Result<(Vec<f64>, Vec<Vec<Point3>>), ProblemError> {
        let n = u.len();
        let (k, rows) = self.jacobian(system, (u, history), state)?;
        let a = match system.p {
            Some(p) => triple_product(p, &k),
            None => k,
        };
        // The compact unknowns: free dofs, then three per point.
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
        let mut matrix_rows: Vec<Vec<(usize, f64)>> = free
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
        let mut frames = Vec::new();
        for (q, ((pair, iterate), rows)) in self.pairs.iter().zip(&state.iterates).zip(&rows).enumerate() {
            for (p, point) in iterate.points.iter().enumerate() {
                let Some((g, status)) = point else { continue };
                let first = free.len() + 3 * points.len();
                // λ_p's columns in the force rows: N_pr on slave point r, −B_pk on master point k.
                let current = &iterate.current;
                let (cols, vals) = current.nodal_d.row(p);
                let slave = cols.iter().zip(vals).map(|(&r, &v)| (r, v, &pair.slave));
                let (cols, vals) = current.b().row(p);
                let master = cols.iter().zip(vals).map(|(&k, &v)| (k, -v, &pair.master));
                for (point, v, side) in slave.chain(master) {
                    for c in 0..3 {
                        for (j, w) in system.through(&[(side.dof(point, c), v)]) {
                            if index[j] != NONE {
                                matrix_rows[index[j]].push((first + c, w));
                            }
                        }
                    }
                }
                // F_p's rows.
                let law = self.law(pair, p, &system.held, g);
                let value = law.rows(g, history.lambda[q][pair.slave.points[p]], *status);
                for k in 0..3 {
                    let mut row: Vec<(usize, f64)> =
                        (0..3).map(|c| (first + c, rows[p].lambda[k][c])).collect();
                    let mut b = -value[k];
                    for (j, v) in system.through(&rows[p].u[k]) {
                        match index[j] {
                            NONE => b -= v * shift[j],
                            c => row.push((c, v)),
                        }
                    }
                    matrix_rows.push(row);
                    rhs.push(b);
                }
                points.push((q, p));
                frames.push((g.frame, *status == Status::Inactive));
            }
        }
        let mut matrix = CsrMatrix::zeros(0, matrix_rows.len());
        for row in matrix_rows {
            let row = crate::contact::merged(&mut row.clone());
            matrix.indices.extend(row.iter().map(|e| e.0));
            matrix.values.extend(row.iter().map(|e| e.1));
            matrix.indptr.push(matrix.indices.len());
            matrix.nrows += 1;
        }
        let x = match linear.solver {
            Solver::Petsc(o) => bordered(&matrix, &rhs, (&free, n, &frames), &a, (&o, linear)),
            _ => crate::backend::sparse_lu(&matrix, &rhs, &Dirichlet::new()),
        }
        .map_err(|e| ProblemError::Newton { source: FiniteError::Solve(e) })?;
        let mut dy = shift;
        for (k, &i) in free.iter().enumerate() {
            dy[i] = x[k];
        }
        let du = match system.p {
            Some(p) => p.mul_vec(&dy, 1),
            None => dy,
        };
        // Δλ: −λ off the covered points.
        let mut dlambda: Vec<Vec<Point3>> = self
            .pairs
            .iter()
            .zip(&history.lambda)
            .map(|(pair, lambda)| pair.slave.points.iter().map(|&r| lambda[r].map(|v| -v)).collect())
            .collect();
        for (k, &(q, p)) in points.iter().enumerate() {
            let first = free.len() + 3 * k;
            dlambda[q][p] = [x[first], x[first + 1], x[first + 2]];
        }
        Ok((du, dlambda))
    }

    /// Newton's method for one load step from (u, history), which it
    /// replaces by the solution's (module doc): the multipliers, and at the
    /// end the accumulated slip and this step's evaluation. With a `guess`
    /// (the last steps extrapolated) the iteration starts there, unless a
    /// cell is inverted at it.
    ///
    /// # Errors
    /// [`ProblemError::Newton`] for an inverted cell no step avoids, a
    /// singular step or no convergence within the cap;
    /// [`ProblemError::Mortar`] for a failed evaluation of an interface.
    pub(super) fn solve(
        &self,
        system: &Newton,
        dirichlet: &Dirichlet,
        (u, history): (&mut Vec<f64>, &mut History),
        (options, guess): (&NewtonOptions, Option<Vec<f64>>),
        linear: &mut Linear,
    ) -> Result<Solved, ProblemError> {
        let remaining = |u: &[f64]| -> Vec<(usize, f64)> {
            dirichlet.iter().filter(|&(d, v)| u[d] != v).map(|(d, v)| (d, v - u[d])).collect()
        };
        let relative = |s: &State| if s.scale > 0.0 { s.norm / s.scale } else { s.norm };
        let mut state = self.state(system, (u, history), None)?;
        // The extrapolated start, unless it turns a cell inside out.
        if let Some(Ok(start)) = guess.as_ref().map(|g| self.state(system, (g, history), None)) {
            *u = guess.expect("evaluated");
            state = start;
        }
        let mut report = NewtonReport::default();
        for iteration in 1..=options.max_iterations + 1 {
            let left = remaining(u);
            if left.is_empty() && state.norm <= (options.rtol * state.scale).max(state.floor) {
                let kkt = self.kkt(system, (u, history), &state);
                self.end_step(history, &state);
                let internal = state.residual.iter().zip(system.load).map(|(r, f)| r + f).collect();
                return Ok(Solved { report, kkt, internal, iterates: state.iterates });
            }
            if iteration > options.max_iterations {
                break;
            }
            let (du, dlambda) = self.step(system, (u, history), &state, &left, linear)?;
            let mut step = 1.0;
            loop {
                let mut trial_u: Vec<f64> = u.iter().zip(&du).map(|(a, d)| a + step * d).collect();
                if step == 1.0 {
                    // Exactly the prescribed values.
                    for &(d, v) in &left {
                        trial_u[d] = u[d] + v;
                    }
                }
                let mut trial = history.clone();
                for ((pair, l), dl) in self.pairs.iter().zip(&mut trial.lambda).zip(&dlambda) {
                    for (p, &r) in pair.slave.points.iter().enumerate() {
                        l[r] = std::array::from_fn(|c| {
                            if step == 1.0 && dl[p][c] == -l[r][c] {
                                0.0
                            } else {
                                l[r][c] + step * dl[p][c]
                            }
                        });
                    }
                }
                match self.state(system, (&trial_u, &trial), None) {
                    Ok(next) => {
                        (*u, *history, state) = (trial_u, trial, next);
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
            // Diverging (the statuses cycling far from the solution): give up
            // early, so that the load step can be cut ([`crate::MAX_CUTS`]).
            let best = report.residuals.iter().copied().fold(f64::INFINITY, f64::min);
            if report.residuals.len() >= 4 && relative(&state) > DIVERGED * best {
                break;
            }
        }
        Err(ProblemError::Newton {
            source: FiniteError::NotConverged {
                iterations: report.residuals.len(),
                residual: relative(&state),
                rtol: options.rtol,
            },
        })
    }

    /// The end of a load step: the slip of each point in contact, s = Σ_α
    /// τ_α w_α / d_p, added to its accumulated slip; the evaluation kept for
    /// the next step's slip increments.
    fn end_step(&self, history: &mut History, state: &State) {
        for (q, (pair, iterate)) in self.pairs.iter().zip(&state.iterates).enumerate() {
            for (p, &r) in pair.slave.points.iter().enumerate() {
                let increment = match &iterate.points[p] {
                    Some((g, status)) if *status != Status::Inactive => {
                        let w = g.slip.unwrap_or([0.0; 2]);
                        std::array::from_fn(|c| (w[0] * g.frame[1][c] + w[1] * g.frame[2][c]) / g.d)
                    }
                    _ => [0.0; 3],
                };
                let (total, last) = &mut history.slip[q][r];
                *last = increment;
                (0..3).for_each(|c| total[c] += increment[c]);
            }
            history.previous[q] = iterate.current.clone();
        }
    }

    /// How far the solution is from the discrete KKT conditions (each as
    /// [`Kkt`] defines it, with R for f − Ku − Cᵀλ, the pressures n·λ_p and
    /// the gaps g̃_p / d_p).
    fn kkt(&self, system: &Newton, (u, history): (&[f64], &History), state: &State) -> Kkt {
        let reduced = system.reduce(&state.residual);
        let max = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0, f64::max);
        let equilibrium = max(&mut (0..u.len()).filter(|&i| !system.held[i]).map(|i| reduced[i].abs()));
        let size = max(&mut system.load.iter().chain(&state.force).map(|v| v.abs()));
        let (mut pressures, mut gaps) = (Vec::new(), Vec::new());
        for (q, (pair, iterate)) in self.pairs.iter().zip(&state.iterates).enumerate() {
            for (p, point) in iterate.points.iter().enumerate() {
                if let Some((g, _)) = point {
                    pressures.push(dot(g.frame[0], history.lambda[q][pair.slave.points[p]]));
                    gaps.push(g.gap / g.d);
                }
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
}
impl Contact<'_> {
    /// The contact fields of the solved step into `out` (per interface of
    /// the problem), on the final configuration: pressure n·λ_p, normal, gap
    /// g̃_p / d_p (the initial one on the reference configuration), status,
    /// slip, the friction bound μ n·λ_p, traction −λ_p and the resultant
    /// −Σ d_p λ_p.
    pub(super) fn fields(
        &self,
        solved: &Solved,
        history: &History,
        out: &mut [InterfaceSolution],
    ) -> Result<(), ProblemError> {
        for (q, (pair, iterate)) in self.pairs.iter().zip(&solved.iterates).enumerate() {
            let initial = pair.reference()?;
            let s = &mut out[pair.index];
            let n_points = s.traction.len();
            let fields = s.contact.get_or_insert_with(|| ContactFields::new(n_points));
            fields.friction = pair.friction;
            for (p, point) in iterate.points.iter().enumerate() {
                let Some((g, status)) = point else { continue };
                let r = pair.slave.points[p];
                let (lambda, n) = (history.lambda[q][r], g.frame[0]);
                let pressure = dot(n, lambda);
                fields.contact[r] = true;
                if initial.covered(p) {
                    fields.initial_gap[r] =
                        dot(initial.normals[p], initial.relative(p, &initial)) / initial.d(p);
                }
                fields.gap[r] = g.gap / g.d;
                fields.pressure[r] = pressure;
                fields.active[r] = *status != Status::Inactive;
                fields.stick[r] = *status == Status::Stick;
                (fields.slip[r], fields.slip_increment[r]) = history.slip[q][r];
                fields.friction_bound[r] = pair.friction * pressure;
                s.constrained[r] = true;
                s.normal[r] = n;
                s.traction[r] = lambda.map(|v| -v);
                for c in 0..3 {
                    s.force[c] -= g.d * lambda[c];
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

/// A covered point's frame (n, τ₁, τ₂) and whether it is inactive.
type PointFrame = ([Point3; 3], bool);

/// x of the compact Newton system `matrix` x = `rhs` (the `free` dofs of
/// the n, then three per covered point) by PETSc, with the field split and
/// GAMG on the displacements. The system is padded to all n dofs (identity
/// rows elsewhere), so that the displacements are points of 3, and each
/// point's multiplier is taken into its frame, λ_p = R_pᵀ μ_p (`frames`:
/// R_p = (n, τ₁, τ₂), and whether the point is inactive, whose rows
/// d λ_p = … become R_p's: d μ_p = …), so that the Schur complement's
/// diagonal that Jacobi takes is not the zero of a Cartesian axis across
/// the normal. `a` is the reduced tangent, whose empty rows mark the
/// eliminated dofs of the rigid-body modes.
fn bordered(
    matrix: &CsrMatrix,
    rhs: &[f64],
    (free, n, frames): (&[usize], usize, &[PointFrame]),
    a: &CsrMatrix,
    (options, linear): (&crate::petsc::PetscOptions, &mut Linear),
) -> Result<Vec<f64>, SolveError> {
    let m = free.len();
    let to_padded = |c: usize| if c < m { free[c] } else { n + c - m };
    let mut compact_row = vec![NONE; n];
    free.iter().enumerate().for_each(|(k, &i)| compact_row[i] = k);
    // A compact row with its multipliers' columns in the frames (μ).
    let in_frames = |r: usize| -> Vec<(usize, f64)> {
        let (cols, vals) = matrix.row(r);
        let mut out: Vec<(usize, f64)> = Vec::with_capacity(cols.len());
        let mut blocks: Vec<(usize, Point3)> = Vec::new();
        for (&c, &v) in cols.iter().zip(vals) {
            match c < m {
                true => out.push((to_padded(c), v)),
                false => match blocks.iter_mut().find(|b| b.0 == (c - m) / 3) {
                    Some(b) => b.1[(c - m) % 3] += v,
                    None => blocks
                        .push(((c - m) / 3, std::array::from_fn(|j| if j == (c - m) % 3 { v } else { 0.0 }))),
                },
            }
        }
        for (k, l) in blocks {
            out.extend((0..3).map(|c| (n + 3 * k + c, dot(l, frames[k].0[c]))));
        }
        out
    };
    let size = n + matrix.nrows - m;
    let mut padded = CsrMatrix::zeros(0, size);
    let mut b = vec![0.0; size];
    for i in 0..size {
        let mut row: Vec<(usize, f64)> = match i < n {
            true => match compact_row[i] {
                NONE => vec![(i, 1.0)],
                r => {
                    b[i] = rhs[r];
                    in_frames(r)
                }
            },
            false => {
                let (k, c) = ((i - n) / 3, (i - n) % 3);
                let (frame, inactive) = &frames[k];
                let first = m + 3 * k;
                match inactive {
                    false => {
                        b[i] = rhs[first + c];
                        in_frames(first + c)
                    }
                    // Row c of R_p times the point's three rows.
                    true => {
                        b[i] = (0..3).map(|j| frame[c][j] * rhs[first + j]).sum();
                        let mut sum: Vec<(usize, f64)> = (0..3)
                            .flat_map(|j| {
                                in_frames(first + j).into_iter().map(move |(col, v)| (col, frame[c][j] * v))
                            })
                            .collect();
                        crate::contact::merged(&mut sum)
                    }
                }
            }
        };
        let row = crate::contact::merged(&mut row);
        padded.indices.extend(row.iter().map(|e| e.0));
        padded.values.extend(row.iter().map(|e| e.1));
        padded.indptr.push(padded.indices.len());
        padded.nrows += 1;
    }
    let modes = linear.modes_of(a, n);
    let x = crate::petsc::solve_petsc_bordered(&padded, &b, (n, &modes), options, linear.summary)?;
    // Back to the compact unknowns, λ_p = R_pᵀ μ_p.
    let mut out: Vec<f64> = free.iter().map(|&i| x[i]).collect();
    for (k, (frame, _)) in frames.iter().enumerate() {
        let mu = &x[n + 3 * k..n + 3 * k + 3];
        out.extend((0..3).map(|j| (0..3).map(|c| frame[c][j] * mu[c]).sum::<f64>()));
    }
    Ok(out)
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
    /// warped, partly overlapping bodies in sliding contact with multipliers
    /// on every covered point (normal and tangential) and a slip history
    /// (the last step at another configuration), the points' statuses held:
    /// the force terms ∂(N λ, −B λ)/∂u column by column and each point's
    /// ∂F_p/∂u entry by entry (and its tangential rows alone) to 1e-6 of
    /// their largest entries, ∂F_p/∂λ_p to 1e-7; first order
    /// (Hex8 | Tet4) and second order (Hex20 | Tet10, transformed Tri6 slave
    /// basis), dual and lumped multipliers, frictionless and μ = 0.3 (with
    /// points in stick and in slip).
    #[test]
    fn newton_matrix_is_the_derivative_of_the_residual() {
        let material = Material::new(1000.0, 0.3).unwrap();
        let law = Hyperelastic::neo_hookean(&material);
        let cases = [
            ("Hex8 | Tet4, dual", None, seam::Multiplier::Dual, 0.0),
            ("Hex8 | Tet4, dual, μ = 0.3", None, seam::Multiplier::Dual, 0.3),
            ("Hex20 | Tet10, dual, μ = 0.3", Some(false), seam::Multiplier::Dual, 0.3),
            ("Hex8 | Tet4, lumped, μ = 0.3", None, seam::Multiplier::Lumped, 0.3),
        ];
        let mut sticking = 0;
        for (label, raise, multiplier, friction) in cases {
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
                friction,
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
            let mut history = contact.history(History::default()).unwrap();
            // The last step: the slave 0.2 to the side (over half a master face:
            // the slip reaches master points B no longer does).
            let old: Vec<f64> =
                (0..n).map(|i| if i >= offsets[1] && i % 3 == 0 { -0.2 } else { 0.0 }).collect();
            let (xs, xm) = contact.pairs[0].positions(&old);
            history.previous[0] = contact.pairs[0].evaluate(xs, xm).unwrap();
            let u: Vec<f64> = (0..n).map(|_| 0.02 * (random(&mut seed) - 0.5)).collect();
            let state = contact.state(&system, (&u, &history), None).unwrap();
            let pair = &contact.pairs[0];
            let covered: Vec<usize> =
                (0..pair.slave.points.len()).filter(|&p| state.iterates[0].points[p].is_some()).collect();
            assert!(covered.len() >= 4, "{label}");
            for &p in &covered {
                // n·λ about 50, tangential parts up to ±75: some points stick, some slip.
                let g = &state.iterates[0].points[p].as_ref().unwrap().0;
                let (a, b, c) = (
                    50.0 * (0.5 + random(&mut seed)),
                    150.0 * (random(&mut seed) - 0.5),
                    150.0 * (random(&mut seed) - 0.5),
                );
                history.lambda[0][pair.slave.points[p]] =
                    std::array::from_fn(|k| a * g.frame[0][k] + b * g.frame[1][k] + c * g.frame[2][k]);
            }
            let state = contact.state(&system, (&u, &history), None).unwrap();
            let statuses: Vec<Vec<Option<Status>>> =
                vec![state.iterates[0].points.iter().map(|p| p.as_ref().map(|e| e.1)).collect()];
            let count = |s: Status| statuses[0].iter().filter(|&&e| e == Some(s)).count();
            println!(
                "{label}: {} stick, {} slip, {} inactive",
                count(Status::Stick),
                count(Status::Slip),
                count(Status::Inactive)
            );
            if friction > 0.0 {
                assert!(count(Status::Slip) > 0, "{label}");
                sticking += count(Status::Stick);
            }
            let (k, rows) = contact.jacobian(&system, (&u, &history), &state).unwrap();
            // ∂F/∂λ (closed form) against central differences in λ.
            let (mut l_largest, mut l_worst) = (0.0f64, 0.0f64);
            for &p in &covered {
                let (g, status) = state.iterates[0].points[p].as_ref().unwrap();
                let law = contact.law(pair, p, &system.held, g);
                let l = history.lambda[0][pair.slave.points[p]];
                let step = 1e-6 * norm(l);
                for c in 0..3 {
                    let at = |s: f64| {
                        let mut m = l;
                        m[c] += s;
                        law.rows(g, m, *status)
                    };
                    let (plus, minus) = (at(step), at(-step));
                    for r in 0..3 {
                        let fd = (plus[r] - minus[r]) / (2.0 * step);
                        l_largest = l_largest.max(rows[0][p].lambda[r][c].abs());
                        l_worst = l_worst.max((rows[0][p].lambda[r][c] - fd).abs());
                    }
                }
            }
            assert!(
                l_largest > 0.0 && l_worst <= 1e-7 * l_largest,
                "{label}: ∂F/∂λ {l_worst:e} of {l_largest:e}"
            );
            let k_bodies = nonlinear.tangent(&u).unwrap();
            let values = |state: &State| -> Vec<Option<[f64; 3]>> {
                state.iterates[0]
                    .points
                    .iter()
                    .enumerate()
                    .map(|(p, e)| {
                        e.as_ref().map(|(g, s)| {
                            let lambda = history.lambda[0][pair.slave.points[p]];
                            contact.law(pair, p, &system.held, g).rows(g, lambda, *s)
                        })
                    })
                    .collect()
            };
            let dofs: Vec<usize> = (0..pair.slave.points.len())
                .flat_map(|l| (0..3).map(move |c| (true, l, c)))
                .chain((0..pair.master.points.len()).flat_map(|l| (0..3).map(move |c| (false, l, c))))
                .map(|(slave, l, c)| if slave { pair.slave.dof(l, c) } else { pair.master.dof(l, c) })
                .collect();
            let h = 1e-5 * mean_diameter(&pair.slave.faces, &pair.slave.at(points[1]));
            let (mut largest, mut worst, mut f_largest, mut f_worst) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            let (mut t_largest, mut t_worst) = (0.0f64, 0.0f64);
            for &j in &dofs {
                let at = |s: f64| {
                    let mut v = u.clone();
                    v[j] += s;
                    let state = contact.state(&system, (&v, &history), Some(&statuses)).unwrap();
                    // R − (f_int − f): the force terms.
                    let terms: Vec<f64> =
                        state.residual.iter().zip(&state.force).map(|(r, f)| r - f).collect();
                    (terms, values(&state))
                };
                let ((tp, fp), (tm, fm)) = (at(h), at(-h));
                for i in 0..n {
                    let exact = k.get(i, j) - k_bodies.get(i, j);
                    let fd = (tp[i] - tm[i]) / (2.0 * h);
                    largest = largest.max(exact.abs());
                    worst = worst.max((exact - fd).abs());
                }
                for &p in &covered {
                    let (Some(a), Some(b)) = (fp[p], fm[p]) else { panic!("{label}: point {p} uncovered") };
                    for r in 0..3 {
                        let exact = rows[0][p].u[r].iter().filter(|e| e.0 == j).map(|e| e.1).sum::<f64>();
                        let fd = (a[r] - b[r]) / (2.0 * h);
                        f_largest = f_largest.max(exact.abs());
                        f_worst = f_worst.max((exact - fd).abs());
                        if r > 0 {
                            t_largest = t_largest.max(exact.abs());
                            t_worst = t_worst.max((exact - fd).abs());
                        }
                    }
                }
            }
            println!("{label}: force terms {worst:.2e} of {largest:.2e}, point rows {f_worst:.2e} of {f_largest:.2e}, tangential {t_worst:.2e} of {t_largest:.2e}");
            assert!(largest > 0.0 && worst <= 1e-6 * largest, "{label}: {worst:e} of {largest:e}");
            assert!(f_largest > 0.0 && f_worst <= 1e-6 * f_largest, "{label}: {f_worst:e} of {f_largest:e}");
            assert!(t_largest > 0.0 && t_worst <= 1e-6 * t_largest, "{label}: {t_worst:e} of {t_largest:e}");
        }
        assert!(sticking > 0, "some points stick");
    }
}
