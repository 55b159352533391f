//! Hyperelastic bodies in finite deformation, total Lagrangian: the laws, the
//! cells' internal forces and consistent tangents, and Newton's method with a
//! backtracking line search for one body under prescribed displacements and
//! dead loads.
//!
//! With F = I + ∇_X u, C = FᵀF, J = det F, the second Piola–Kirchhoff stress
//! S = 2 ∂W/∂C and the material tangent ℂ = 2 ∂S/∂C of
//!
//! ```text
//! neo-Hookean (compressible):  W = μ/2 (I₁ − 3) − μ ln J + λ/2 (ln J)²
//!     S = μ (I − C⁻¹) + λ ln J C⁻¹
//!     ℂ = λ C⁻¹ ⊗ C⁻¹ + (μ − λ ln J) (C⁻¹_IK C⁻¹_JL + C⁻¹_IL C⁻¹_JK)
//! Saint Venant–Kirchhoff:      W = λ/2 (tr E)² + μ E:E,  E = ½ (C − I)
//!     S = λ tr E I + 2μ E,     ℂ = the small-strain C
//! ```
//!
//! (λ, μ from Young's modulus and Poisson's ratio, [`Material::lame`]; both
//! laws linearise at F = I to the small-strain body.) A cell's internal force
//! and tangent, with g_i = ∇_X N_i in the reference configuration,
//!
//! ```text
//! f_{3i+a}      = ∫ F_aI S_IJ g_iJ dV
//! K_{3i+a,3j+b} = ∫ (g_i·S g_j) δ_ab + (B_i)ᵀ ℂ B_j dV ,   B_i[v][a] = δE_v / δu_ia
//! ```
//!
//! in Voigt order xx yy zz yz xz xy with engineering shears (as
//! [`crate::material`]), by the cell's stiffness rule; K is formed as
//! g_iJ A_aJbL g_jL with A = ∂P/∂F (its major symmetry: the blocks j ≥ i,
//! mirrored). The Cauchy stress is
//! σ = F S Fᵀ / J.

use crate::assembly::{cell_matrix, cell_vector, geometry, geometry_at_rule, AssemblyError};
use crate::material::Material;
use crate::petsc::PetscSummary;
use crate::solve::{CholeskyAnalysis, DirectOptions, Dirichlet, SolveError};
use crate::stress::Stresses;
use crate::Solver;
use rayon::prelude::*;
use seam::{CellKind, CsrMatrix, Point3, VolumeMesh, Xi3, MAX_CELL_NODES};

/// A 3 × 3 matrix, row-major: m[row][column].
pub type Mat3 = [[f64; 3]; 3];

/// The index pairs of the Voigt order xx yy zz yz xz xy.
const VOIGT: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

/// A body's constitutive law: small-strain linear elasticity (the
/// default), or a hyperelastic law solved in finite deformation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Law {
    /// Linear elasticity, small strain.
    #[default]
    Linear,
    /// [`Hyperelastic::NeoHookean`].
    NeoHookean,
    /// [`Hyperelastic::SaintVenantKirchhoff`].
    SaintVenantKirchhoff,
}

impl Law {
    /// The hyperelastic law of `material`'s constants, `None` for
    /// [`Law::Linear`].
    pub fn hyperelastic(self, material: &Material) -> Option<Hyperelastic> {
        match self {
            Law::Linear => None,
            Law::NeoHookean => Some(Hyperelastic::neo_hookean(material)),
            Law::SaintVenantKirchhoff => Some(Hyperelastic::saint_venant_kirchhoff(material)),
        }
    }

    /// Its name in a case file: "linear", "neo-hookean",
    /// "saint-venant-kirchhoff".
    pub fn name(self) -> &'static str {
        match self {
            Law::Linear => "linear",
            Law::NeoHookean => "neo-hookean",
            Law::SaintVenantKirchhoff => "saint-venant-kirchhoff",
        }
    }
}

/// A hyperelastic law (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Hyperelastic {
    /// Compressible neo-Hookean, W = μ/2 (I₁ − 3) − μ ln J + λ/2 (ln J)².
    NeoHookean {
        /// Lamé's λ.
        lambda: f64,
        /// The shear modulus μ.
        mu: f64,
    },
    /// Saint Venant–Kirchhoff, W = λ/2 (tr E)² + μ E:E.
    SaintVenantKirchhoff {
        /// Lamé's λ.
        lambda: f64,
        /// The shear modulus μ.
        mu: f64,
    },
}

impl Hyperelastic {
    /// The neo-Hookean law with λ and μ of `material`.
    pub fn neo_hookean(material: &Material) -> Hyperelastic {
        let (lambda, mu) = material.lame();
        Hyperelastic::NeoHookean { lambda, mu }
    }

    /// The Saint Venant–Kirchhoff law with λ and μ of `material`.
    pub fn saint_venant_kirchhoff(material: &Material) -> Hyperelastic {
        let (lambda, mu) = material.lame();
        Hyperelastic::SaintVenantKirchhoff { lambda, mu }
    }

    /// S and ℂ (Voigt, module doc) at the deformation gradient `f`; `None`
    /// where the law is undefined (neo-Hookean: J ≤ 0).
    pub fn stress(&self, f: &Mat3) -> Option<(Mat3, [[f64; 6]; 6])> {
        let c = mul(&transpose(f), f);
        let mut s = [[0.0; 3]; 3];
        let mut tangent = [[0.0; 6]; 6];
        match *self {
            Hyperelastic::NeoHookean { lambda, mu } => {
                let j = det(f);
                if j.is_nan() || j <= 0.0 {
                    return None;
                }
                let ci = inverse(&c)?;
                let ln_j = j.ln();
                for (a, row) in s.iter_mut().enumerate() {
                    for (b, v) in row.iter_mut().enumerate() {
                        *v = mu * (delta(a, b) - ci[a][b]) + lambda * ln_j * ci[a][b];
                    }
                }
                let m = mu - lambda * ln_j;
                for (v, &(i, j)) in VOIGT.iter().enumerate() {
                    for (w, &(k, l)) in VOIGT.iter().enumerate() {
                        tangent[v][w] =
                            lambda * ci[i][j] * ci[k][l] + m * (ci[i][k] * ci[j][l] + ci[i][l] * ci[j][k]);
                    }
                }
            }
            Hyperelastic::SaintVenantKirchhoff { lambda, mu } => {
                let e: Mat3 = std::array::from_fn(|a| std::array::from_fn(|b| 0.5 * (c[a][b] - delta(a, b))));
                let trace = e[0][0] + e[1][1] + e[2][2];
                for (a, row) in s.iter_mut().enumerate() {
                    for (b, v) in row.iter_mut().enumerate() {
                        *v = lambda * trace * delta(a, b) + 2.0 * mu * e[a][b];
                    }
                }
                for (v, &(i, j)) in VOIGT.iter().enumerate() {
                    for (w, &(k, l)) in VOIGT.iter().enumerate() {
                        tangent[v][w] = lambda * delta(i, j) * delta(k, l)
                            + mu * (delta(i, k) * delta(j, l) + delta(i, l) * delta(j, k));
                    }
                }
            }
        }
        Some((s, tangent))
    }

    /// The Cauchy stress σ = F S Fᵀ / J at `f`; `None` where J ≤ 0.
    pub fn cauchy(&self, f: &Mat3) -> Option<Mat3> {
        let j = det(f);
        if j.is_nan() || j <= 0.0 {
            return None;
        }
        let (s, _) = self.stress(f)?;
        let sigma = mul(&mul(f, &s), &transpose(f));
        Some(sigma.map(|row| row.map(|v| v / j)))
    }
}

/// The deformation gradient F = I + Σ_i u_i ⊗ g_i of a cell's nodal
/// displacements `u` and reference gradients `grads`.
fn deformation_gradient(u: &[[f64; 3]], grads: &[[f64; 3]]) -> Mat3 {
    let mut f: Mat3 = std::array::from_fn(|a| std::array::from_fn(|b| delta(a, b)));
    for (ui, gi) in u.iter().zip(grads) {
        for a in 0..3 {
            for b in 0..3 {
                f[a][b] += ui[a] * gi[b];
            }
        }
    }
    f
}

/// F at the reference point `xi` of a cell of `kind` with reference nodes
/// `x` and nodal displacements `u`; `None` for a degenerate cell.
pub fn cell_deformation_gradient(kind: CellKind, x: &[Point3], u: &[[f64; 3]], xi: Xi3) -> Option<Mat3> {
    let g = geometry(kind, x, xi)?;
    Some(deformation_gradient(u, &g.grads[..x.len()]))
}

/// A cell's internal force (3n) and, with `tangent`, its consistent tangent
/// ((3n)², row-major) at the nodal displacements `u` (module doc); false
/// where the cell is degenerate or the law undefined.
fn element(
    kind: CellKind,
    x: &[Point3],
    u: &[[f64; 3]],
    law: &Hyperelastic,
    force: &mut [f64],
    tangent: Option<&mut [f64]>,
) -> bool {
    let rule = kind.stiffness_rule();
    let Some(geo) = geometry_at_rule(kind, x, rule) else { return false };
    let n = x.len();
    let nd = 3 * n;
    force.fill(0.0);
    let mut tangent = tangent;
    if let Some(k) = tangent.as_deref_mut() {
        k.fill(0.0);
    }
    for (g, w) in geo.iter().zip(&rule.weights) {
        let grads = &g.grads[..n];
        let f = deformation_gradient(u, grads);
        let Some((s, c)) = law.stress(&f) else { return false };
        let wd = w * g.det.abs();
        // P = F S: f_{3i+a} = ∫ P_aJ g_iJ.
        let p = mul(&f, &s);
        for (i, gi) in grads.iter().enumerate() {
            for a in 0..3 {
                force[3 * i + a] += wd * (p[a][0] * gi[0] + p[a][1] * gi[1] + p[a][2] * gi[2]);
            }
        }
        let Some(k) = tangent.as_deref_mut() else { continue };
        // K_ij[a][b] += t_i[a][b][L] g_jL, t_i[a][b][L] = g_iJ A_aJbL, for
        // j ≥ i (A has the major symmetry A_aJbL = A_bLaJ): mirrored below.
        let a4 = first_elasticity(&f, &s, &c);
        for (i, gi) in grads.iter().enumerate() {
            let t: [[[f64; 3]; 3]; 3] = std::array::from_fn(|a| {
                std::array::from_fn(|b| {
                    std::array::from_fn(|l| {
                        wd * (gi[0] * a4[a][0][b][l] + gi[1] * a4[a][1][b][l] + gi[2] * a4[a][2][b][l])
                    })
                })
            });
            for (j, gj) in grads.iter().enumerate().skip(i) {
                for (a, ta) in t.iter().enumerate() {
                    let row = &mut k[(3 * i + a) * nd + 3 * j..][..3];
                    for (v, tab) in row.iter_mut().zip(ta) {
                        *v += tab[0] * gj[0] + tab[1] * gj[1] + tab[2] * gj[2];
                    }
                }
            }
        }
    }
    if let Some(k) = tangent {
        for r in 0..nd {
            for col in (3 * (r / 3 + 1))..nd {
                k[col * nd + r] = k[r * nd + col];
            }
        }
    }
    true
}

/// The Cauchy stresses of the displacements `u` of `mesh` ([`Stresses`]:
/// per cell at its reference centroid, Voigt order xx yy zz yz xz xy; per
/// point the volume-weighted average over its cells in the reference
/// configuration; von Mises of both).
///
/// # Errors
/// As [`internal_force`].
pub fn cauchy_stresses(mesh: &VolumeMesh, law: &Hyperelastic, u: &[f64]) -> Result<Stresses, FiniteError> {
    assert_eq!(u.len(), 3 * mesh.points().len(), "u has 3 entries per point");
    let cell: Vec<Option<[f64; 6]>> = (0..mesh.cells().len())
        .into_par_iter()
        .map(|c| {
            let (x, kind) = crate::assembly::corners(mesh, c);
            let x = &x[..kind.n_nodes()];
            let f = cell_deformation_gradient(
                kind,
                x,
                &cell_displacements(mesh, c, u)[..x.len()],
                kind.centroid(),
            )?;
            let sigma = law.cauchy(&f)?;
            Some(VOIGT.map(|(a, b)| sigma[a][b]))
        })
        .collect();
    if let Some(c) = cell.iter().position(Option::is_none) {
        return Err(failure(mesh, AssemblyError::DegenerateCell { cell: c }));
    }
    Ok(Stresses::of_cells(mesh, cell.into_iter().flatten().collect())?)
}

/// The displacements of cell `c`'s nodes out of the global `u` (entries
/// past its node count 0).
fn cell_displacements(mesh: &VolumeMesh, c: usize, u: &[f64]) -> [[f64; 3]; MAX_CELL_NODES] {
    let mut out = [[0.0; 3]; MAX_CELL_NODES];
    for (o, &p) in out.iter_mut().zip(mesh.cells()[c].nodes()) {
        *o = [u[3 * p], u[3 * p + 1], u[3 * p + 2]];
    }
    out
}

/// What stops a finite-deformation evaluation or solve.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FiniteError {
    /// A cell is degenerate in the reference configuration.
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// A cell is inverted (J ≤ 0 at one of its quadrature points) by the
    /// displacements.
    #[error("cell {cell} is inverted by the displacements (J ≤ 0)")]
    Inverted {
        /// The cell index.
        cell: usize,
    },
    /// A body's cell failed.
    #[error("body {body}: {source}")]
    Body {
        /// The body index.
        body: usize,
        /// What failed in it.
        source: Box<FiniteError>,
    },
    /// A linear solve failed.
    #[error("Newton's linear solve: {0}")]
    Solve(#[from] SolveError),
    /// Newton's method did not reach the tolerance.
    #[error(
        "Newton did not converge in {iterations} iterations (relative residual {residual:.3e}, asked {rtol:.0e})"
    )]
    NotConverged {
        /// The iterations taken.
        iterations: usize,
        /// The last relative residual.
        residual: f64,
        /// The tolerance asked.
        rtol: f64,
    },
    /// The line search found no step that lowers the residual.
    #[error("Newton's line search found no step that lowers the residual at iteration {iteration} (relative residual {residual:.3e})")]
    LineSearch {
        /// The iteration (from 1).
        iteration: usize,
        /// The relative residual it stopped at.
        residual: f64,
    },
}

impl FiniteError {
    /// Whether this is an inverted cell (of some body).
    pub fn is_inversion(&self) -> bool {
        match self {
            FiniteError::Inverted { .. } => true,
            FiniteError::Body { source, .. } => source.is_inversion(),
            _ => false,
        }
    }
}

/// A failed cell evaluation: [`FiniteError::Inverted`] if the cell is sound
/// in the reference configuration, else the assembly error.
fn failure(mesh: &VolumeMesh, e: AssemblyError) -> FiniteError {
    let AssemblyError::DegenerateCell { cell } = e;
    let (x, kind) = crate::assembly::corners(mesh, cell);
    match geometry_at_rule(kind, &x[..kind.n_nodes()], kind.stiffness_rule()) {
        Some(_) => FiniteError::Inverted { cell },
        None => FiniteError::Assembly(e),
    }
}

/// The internal force f_int(u) of `mesh` (3·n_points; module doc).
///
/// # Errors
/// [`FiniteError::Inverted`] or [`FiniteError::Assembly`] for the first
/// failing cell.
pub fn internal_force(mesh: &VolumeMesh, law: &Hyperelastic, u: &[f64]) -> Result<Vec<f64>, FiniteError> {
    assert_eq!(u.len(), 3 * mesh.points().len(), "u has 3 entries per point");
    cell_vector(mesh, |kind, x, c, out| {
        element(kind, x, &cell_displacements(mesh, c, u)[..x.len()], law, out, None)
    })
    .map_err(|e| failure(mesh, e))
}

/// The consistent tangent K(u) = ∂f_int/∂u of `mesh` (the pattern of
/// [`crate::stiffness`]; symmetric).
///
/// # Errors
/// As [`internal_force`].
pub fn tangent(mesh: &VolumeMesh, law: &Hyperelastic, u: &[f64]) -> Result<CsrMatrix, FiniteError> {
    assert_eq!(u.len(), 3 * mesh.points().len(), "u has 3 entries per point");
    cell_matrix(mesh, |kind, x, c, out| {
        let mut force = [0.0; 3 * MAX_CELL_NODES];
        element(
            kind,
            x,
            &cell_displacements(mesh, c, u)[..x.len()],
            law,
            &mut force[..3 * x.len()],
            Some(out),
        )
    })
    .map_err(|e| failure(mesh, e))
}

/// Newton's tolerance and iteration cap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonOptions {
    /// Converged when ‖R‖ ≤ rtol · the force scale on the free dofs
    /// ([`solve_newton`]).
    pub rtol: f64,
    /// The most iterations.
    pub max_iterations: usize,
    /// Contact: start each load step from the extrapolation of the last
    /// one, u + (t − tⁿ) Δu/Δt (where no cell is inverted there), rather
    /// than from u.
    pub extrapolate: bool,
}

impl Default for NewtonOptions {
    /// rtol 1e-10, 25 iterations, extrapolated starts.
    fn default() -> Self {
        NewtonOptions { rtol: 1e-10, max_iterations: 25, extrapolate: true }
    }
}

/// How Newton's method went.
#[derive(Clone, Debug, PartialEq)]
pub struct NewtonReport {
    /// The relative residual after each iteration.
    pub residuals: Vec<f64>,
    /// The line search's step factor of each iteration (1 for a full step).
    pub line_search: Vec<f64>,
    /// The parts the load step was solved in: 1, or more where Newton
    /// failed and the step was cut in halves ([`crate::MAX_CUTS`]).
    pub substeps: usize,
}

impl Default for NewtonReport {
    /// No iterations, one part.
    fn default() -> Self {
        NewtonReport { residuals: Vec::new(), line_search: Vec::new(), substeps: 1 }
    }
}

/// The smallest step factor of the line search (halving from 1).
const MIN_STEP: f64 = 1.0 / 1024.0;

/// What Newton's method solves: f_int(u) = load for u of `len` entries.
pub(crate) trait Nonlinear {
    /// The number of unknowns.
    fn len(&self) -> usize;
    /// f_int(u).
    fn force(&self, u: &[f64]) -> Result<Vec<f64>, FiniteError>;
    /// K(u) = ∂f_int/∂u.
    fn tangent(&self, u: &[f64]) -> Result<CsrMatrix, FiniteError>;
}

/// One body of one law.
struct OneBody<'a>(&'a VolumeMesh, &'a Hyperelastic);

impl Nonlinear for OneBody<'_> {
    fn len(&self) -> usize {
        3 * self.0.points().len()
    }
    fn force(&self, u: &[f64]) -> Result<Vec<f64>, FiniteError> {
        internal_force(self.0, self.1, u)
    }
    fn tangent(&self, u: &[f64]) -> Result<CsrMatrix, FiniteError> {
        tangent(self.0, self.1, u)
    }
}

/// How Newton's linear steps meet linear constraints C u = 0 on u (glue).
#[derive(Clone, Copy)]
pub(crate) enum Constrained<'a> {
    /// No constraints.
    Free,
    /// Eliminated, u = P y (P in the numbering of all dofs, eliminated ones
    /// with empty rows and columns): each step on Pᵀ K P.
    Eliminated(&'a CsrMatrix),
    /// Each step the saddle point [K Cᵀ; C 0] by sparse LDLᵀ, where Pᵀ K P
    /// would fill in (a slave coarser than its master); P still reduces the
    /// residual.
    Saddle(&'a CsrMatrix, &'a crate::constraints::Constraints),
}

impl Constrained<'_> {
    /// P, if any.
    fn prolongation(&self) -> Option<&CsrMatrix> {
        match *self {
            Constrained::Free => None,
            Constrained::Eliminated(p) | Constrained::Saddle(p, _) => Some(p),
        }
    }
}

/// How Newton's linear steps are solved: the solver (direct or PETSc), the
/// rigid-body modes of the points in the unknowns' numbering (PETSc's
/// GAMG), and PETSc's record of its solves.
pub(crate) struct Linear<'a> {
    /// The solver.
    pub solver: Solver,
    /// The six rigid-body modes (empty for the direct solver).
    pub modes: Vec<Vec<f64>>,
    /// PETSc's solves.
    pub summary: &'a mut PetscSummary,
}

impl Linear<'_> {
    /// The rigid-body modes zero at the dofs without a diagonal entry in
    /// `a` (eliminated by glue), the first `n` entries of each.
    pub(crate) fn modes_of(&self, a: &CsrMatrix, n: usize) -> Vec<Vec<f64>> {
        let kept: Vec<bool> = (0..n).map(|i| a.row(i).0.contains(&i)).collect();
        let keep = |m: &Vec<f64>| m.iter().zip(&kept).map(|(&v, &k)| if k { v } else { 0.0 }).collect();
        self.modes.iter().map(keep).collect()
    }
}

/// The step Δu of K Δu = r under the constraints `how` and the Dirichlet
/// values `increments` (r = load − f_int, `reduced` = Pᵀ r): by sparse
/// Cholesky of Pᵀ K P, its ordering and symbolic factorisation kept in
/// `analysis` over the iterations (the pattern and the held dofs do not
/// change), sparse LU where that matrix is not positive definite (far from
/// equilibrium), or by the saddle point (falling back to the elimination if
/// its LDLᵀ fails); with PETSc by FGMRES and GAMG on Pᵀ K P.
fn newton_step(
    k: CsrMatrix,
    (r, reduced): (&[f64], &[f64]),
    increments: &Dirichlet,
    (how, analysis): (Constrained, &mut Option<CholeskyAnalysis>),
    linear: &mut Linear,
) -> Result<Vec<f64>, FiniteError> {
    if let (Constrained::Saddle(_, constraints), Solver::Direct) = (how, linear.solver) {
        let mut seconds = crate::multibody::Timings::default();
        if let Ok((du, ..)) = crate::constraints::saddle_point(&k, r, increments, constraints, &mut seconds) {
            return Ok(du);
        }
    }
    let elimination = how.prolongation();
    let k = match elimination {
        Some(p) => crate::constraints::triple_product(p, &k),
        None => k,
    };
    let dy = match linear.solver {
        Solver::Petsc(o) => {
            let modes = linear.modes_of(&k, k.nrows);
            crate::petsc::solve_petsc_tangent(k, reduced, increments, &modes, &o, linear.summary)?
        }
        Solver::Direct | Solver::Pcg(_) => {
            if analysis.is_none() {
                *analysis = Some(CholeskyAnalysis::new(&k, increments, &DirectOptions::default())?);
            }
            match analysis.as_ref().expect("analysed").solve(&k, reduced, increments) {
                Ok((dy, _)) => dy,
                Err(SolveError::Singular) => crate::backend::sparse_lu(&k, reduced, increments)?,
                Err(e) => return Err(e.into()),
            }
        }
    };
    Ok(match elimination {
        Some(p) => p.mul_vec(&dy, 1),
        None => dy,
    })
}

/// Solves f_int(u) = `load` (dead loads) for `mesh` of `law` with the
/// displacements `dirichlet` prescribed, from `start`:
///
/// 1. the predictor: the prescribed values are reached through the
///    linearised response, K(u) Δu = load − f_int(u) with Δu = (prescribed
///    − u) on the prescribed dofs, the step halved while a cell would
///    invert (then again from there);
/// 2. Newton's method on the free dofs with a backtracking line search on
///    the residual norm (halving from the full step until ‖R‖ falls by the
///    factor 1 − 10⁻⁴ α, or a cell inverts), until ‖R‖ ≤ rtol · s, s the
///    larger of ‖load‖ and ‖f_int‖ over all dofs after the predictor (the
///    body's force level, reactions included).
///
/// Each step by sparse Cholesky of the tangent, or sparse LU where it is not
/// positive definite.
///
/// # Errors
/// [`FiniteError`]: an inverted cell that no predictor step avoids, a
/// singular tangent, no convergence within the cap, or a line search that
/// found no lower residual.
pub fn solve_newton(
    mesh: &VolumeMesh,
    law: &Hyperelastic,
    (load, dirichlet): (&[f64], &Dirichlet),
    start: &[f64],
    options: &NewtonOptions,
) -> Result<(Vec<f64>, NewtonReport), FiniteError> {
    let mut summary = PetscSummary::default();
    let mut linear = Linear { solver: Solver::Direct, modes: Vec::new(), summary: &mut summary };
    newton(&OneBody(mesh, law), Constrained::Free, (load, dirichlet), start, (options, &mut linear))
}

/// [`solve_newton`] for any [`Nonlinear`] system, with the linear
/// constraints `how` (glue: u = P y, P = [I; −C_S⁻¹C_R] in the numbering
/// of all dofs, `start` satisfying them, no prescribed dof eliminated): the
/// residual is Pᵀ (load − f_int(u)), and each step meets C Δu = 0; the
/// steps solved by `linear`.
pub(crate) fn newton(
    system: &impl Nonlinear,
    how: Constrained,
    (load, dirichlet): (&[f64], &Dirichlet),
    start: &[f64],
    (options, linear): (&NewtonOptions, &mut Linear),
) -> Result<(Vec<f64>, NewtonReport), FiniteError> {
    let n = system.len();
    assert!(load.len() == n && start.len() == n, "3 entries per point");
    let mut u = start.to_vec();
    let mut held = vec![false; n];
    let mut zero = Dirichlet::new();
    for (dof, _) in dirichlet.iter() {
        held[dof] = true;
        zero.fix_dof(dof, 0.0);
    }
    // The residual load − f_int, reduced to the free (retained) dofs, and
    // the reduced one's norm.
    let free_residual = |f: &[f64]| -> (Vec<f64>, Vec<f64>, f64) {
        let r: Vec<f64> = (0..n).map(|i| load[i] - f[i]).collect();
        let mut reduced = match how.prolongation() {
            Some(p) => p.transpose_mul_vec(&r, 1),
            None => r.clone(),
        };
        (0..n).filter(|&i| held[i]).for_each(|i| reduced[i] = 0.0);
        let norm = reduced.iter().map(|v| v * v).sum::<f64>().sqrt();
        (r, reduced, norm)
    };
    let norm2 = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut analysis = None;
    // 1. The predictor.
    let mut f = system.force(&u)?;
    while dirichlet.iter().any(|(dof, v)| u[dof] != v) {
        let mut remaining = Dirichlet::new();
        for (dof, v) in dirichlet.iter() {
            remaining.fix_dof(dof, v - u[dof]);
        }
        let (r, reduced, _) = free_residual(&f);
        let du = newton_step(system.tangent(&u)?, (&r, &reduced), &remaining, (how, &mut analysis), linear)?;
        let mut step = 1.0;
        loop {
            let trial: Vec<f64> = u.iter().zip(&du).map(|(a, d)| a + step * d).collect();
            match system.force(&trial) {
                Ok(next) => {
                    (u, f) = (trial, next);
                    break;
                }
                Err(e) if e.is_inversion() && step > MIN_STEP => step *= 0.5,
                Err(e) => return Err(e),
            }
        }
        if step == 1.0 {
            // Exactly the prescribed values (the step added v − u).
            for (dof, v) in dirichlet.iter() {
                u[dof] = v;
            }
            f = system.force(&u)?;
        }
    }
    // 2. Newton.
    let scale = norm2(load).max(norm2(&f));
    let (mut r, mut reduced, mut norm) = free_residual(&f);
    let mut report = NewtonReport::default();
    if norm <= options.rtol * scale {
        return Ok((u, report));
    }
    for iteration in 1..=options.max_iterations {
        let du = newton_step(system.tangent(&u)?, (&r, &reduced), &zero, (how, &mut analysis), linear)?;
        let mut step = 1.0;
        loop {
            let trial: Vec<f64> = u.iter().zip(&du).map(|(a, d)| a + step * d).collect();
            match system.force(&trial).map(|f| free_residual(&f)) {
                Ok((r_trial, reduced_trial, n_trial)) if n_trial <= (1.0 - 1e-4 * step) * norm => {
                    (u, r, reduced, norm) = (trial, r_trial, reduced_trial, n_trial);
                    break;
                }
                Ok(_) if step > MIN_STEP => step *= 0.5,
                Err(e) if e.is_inversion() && step > MIN_STEP => step *= 0.5,
                Ok(_) => return Err(FiniteError::LineSearch { iteration, residual: norm / scale }),
                Err(e) if e.is_inversion() => {
                    return Err(FiniteError::LineSearch { iteration, residual: norm / scale });
                }
                Err(e) => return Err(e),
            }
        }
        report.residuals.push(norm / scale);
        report.line_search.push(step);
        if norm <= options.rtol * scale {
            return Ok((u, report));
        }
    }
    Err(FiniteError::NotConverged {
        iterations: options.max_iterations,
        residual: norm / scale,
        rtol: options.rtol,
    })
}

fn delta(a: usize, b: usize) -> f64 {
    if a == b {
        1.0
    } else {
        0.0
    }
}

/// The first elasticity tensor A = ∂P/∂F at F with S and ℂ (Voigt) of the
/// law: A_aJbL = δ_ab S_JL + F_aI ℂ_IJKL F_bK, indexed [a][J][b][L].
fn first_elasticity(f: &Mat3, s: &Mat3, c: &[[f64; 6]; 6]) -> [[[[f64; 3]; 3]; 3]; 3] {
    /// The Voigt index of (I, J).
    const V: [[usize; 3]; 3] = [[0, 5, 4], [5, 1, 3], [4, 3, 2]];
    // m[a][J][K][L] = F_aI ℂ_IJKL.
    let m: [[[[f64; 3]; 3]; 3]; 3] = std::array::from_fn(|a| {
        std::array::from_fn(|jj| {
            std::array::from_fn(|kk| {
                std::array::from_fn(|l| (0..3).map(|i| f[a][i] * c[V[i][jj]][V[kk][l]]).sum())
            })
        })
    });
    std::array::from_fn(|a| {
        std::array::from_fn(|jj| {
            std::array::from_fn(|b| {
                std::array::from_fn(|l| {
                    delta(a, b) * s[jj][l] + (0..3).map(|kk| m[a][jj][kk][l] * f[b][kk]).sum::<f64>()
                })
            })
        })
    })
}

fn transpose(m: &Mat3) -> Mat3 {
    std::array::from_fn(|a| std::array::from_fn(|b| m[b][a]))
}

fn mul(x: &Mat3, y: &Mat3) -> Mat3 {
    std::array::from_fn(|a| std::array::from_fn(|b| (0..3).map(|k| x[a][k] * y[k][b]).sum()))
}

/// det m.
pub fn det(m: &Mat3) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

fn inverse(m: &Mat3) -> Option<Mat3> {
    let d = det(m);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let cof = |r: usize, c: usize| {
        let (r1, r2, c1, c2) = ((r + 1) % 3, (r + 2) % 3, (c + 1) % 3, (c + 2) % 3);
        m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]
    };
    // (m⁻¹)_ab = cof(b, a) / det.
    Some(std::array::from_fn(|a| std::array::from_fn(|b| cof(b, a) / d)))
}
