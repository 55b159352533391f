//! Hyperelastic bodies in finite deformation ([`seam_fem::hyperelastic`]):
//! the laws against closed forms and their own derivatives, the cells'
//! tangents against finite differences of their forces, and Newton's method
//! reproducing homogeneous large deformations on every cell kind.

use crate::common;

use common::{distorted, material, Rng, KINDS};
use seam::{CellKind, Point3, VolumeMesh};
use seam_fem::generate::{block, raise_order, BlockKind, Grid, Side};
use seam_fem::hyperelastic::{
    cauchy_stresses, cell_deformation_gradient, det, internal_force, solve_newton, tangent, FiniteError,
    Hyperelastic, Mat3, NewtonOptions,
};
use seam_fem::{stiffness, Dirichlet, Law, Material, ProblemBody};

const VOIGT: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

fn laws(m: &Material) -> [(&'static str, Hyperelastic); 2] {
    [
        ("neo-Hookean", Hyperelastic::neo_hookean(m)),
        ("Saint Venant-Kirchhoff", Hyperelastic::saint_venant_kirchhoff(m)),
    ]
}

fn identity() -> Mat3 {
    std::array::from_fn(|a| std::array::from_fn(|b| if a == b { 1.0 } else { 0.0 }))
}

fn mul(x: &Mat3, y: &Mat3) -> Mat3 {
    std::array::from_fn(|a| std::array::from_fn(|b| (0..3).map(|k| x[a][k] * y[k][b]).sum()))
}

fn transpose(m: &Mat3) -> Mat3 {
    std::array::from_fn(|a| std::array::from_fn(|b| m[b][a]))
}

fn largest(m: &Mat3) -> f64 {
    m.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()))
}

fn difference(x: &Mat3, y: &Mat3) -> f64 {
    largest(&std::array::from_fn(|a| std::array::from_fn(|b| x[a][b] - y[a][b])))
}

/// A general deformation gradient: I plus 0.3 × random, J > 0.
fn general(seed: u64) -> Mat3 {
    let mut rng = Rng(seed);
    let f: Mat3 = std::array::from_fn(|a| {
        std::array::from_fn(|b| if a == b { 1.0 } else { 0.0 } + 0.3 * rng.symmetric())
    });
    assert!(det(&f) > 0.2);
    f
}

/// The 50 % stretch along x and the simple shear γ = 0.5 in the x–y plane.
fn deformations() -> [(&'static str, Mat3); 2] {
    [
        ("stretch 1.5", [[1.5, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        ("simple shear 0.5", [[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
    ]
}

/// The closed-form Cauchy stress: neo-Hookean σ = [μ (B − I) + λ ln J I] / J,
/// B = F Fᵀ; Saint Venant–Kirchhoff σ = F (λ tr E I + 2μ E) Fᵀ / J.
pub(crate) fn analytic_cauchy(law: &Hyperelastic, f: &Mat3) -> Mat3 {
    let j = det(f);
    let i = identity();
    match *law {
        Hyperelastic::NeoHookean { lambda, mu } => {
            let b = mul(f, &transpose(f));
            std::array::from_fn(|p| {
                std::array::from_fn(|q| (mu * (b[p][q] - i[p][q]) + lambda * j.ln() * i[p][q]) / j)
            })
        }
        Hyperelastic::SaintVenantKirchhoff { lambda, mu } => {
            let c = mul(&transpose(f), f);
            let e: Mat3 = std::array::from_fn(|p| std::array::from_fn(|q| 0.5 * (c[p][q] - i[p][q])));
            let tr = e[0][0] + e[1][1] + e[2][2];
            let s: Mat3 =
                std::array::from_fn(|p| std::array::from_fn(|q| lambda * tr * i[p][q] + 2.0 * mu * e[p][q]));
            let sigma = mul(&mul(f, &s), &transpose(f));
            sigma.map(|row| row.map(|v| v / j))
        }
    }
}

/// Both laws at F = I: no stress, the small-strain C; and their tangent of
/// a whole mesh at u = 0 is the linear stiffness K.
#[test]
fn both_laws_linearise_to_the_small_strain_body() {
    let m = material();
    let c = m.c();
    for (name, law) in laws(&m) {
        let (s, tangent_at_rest) = law.stress(&identity()).unwrap();
        assert!(largest(&s) == 0.0, "{name}: S(I) = {s:?}");
        for v in 0..6 {
            for w in 0..6 {
                assert!((tangent_at_rest[v][w] - c[v][w]).abs() <= 1e-12 * m.young(), "{name}: C[{v}][{w}]");
            }
        }
    }
    let (mesh, _) = distorted(KINDS[0], 2, 0.25);
    let k = stiffness(&mesh, &m).unwrap();
    for (name, law) in laws(&m) {
        let t = tangent(&mesh, &law, &vec![0.0; k.nrows]).unwrap();
        assert_eq!((&t.indptr, &t.indices), (&k.indptr, &k.indices), "{name}: the pattern of K");
        let scale = k.values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let worst = t.values.iter().zip(&k.values).fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(worst <= 1e-12 * scale, "{name}: tangent at rest differs from K by {worst:e}");
        assert!(internal_force(&mesh, &law, &vec![0.0; k.nrows]).unwrap().iter().all(|&f| f == 0.0));
    }
}

/// ℂ is the derivative of S: S(F + εG) − S(F − εG) = 2ε ℂ : δE with
/// δE = sym(Fᵀ G), at general F and G.
#[test]
fn the_material_tangent_is_the_derivative_of_the_stress() {
    let m = material();
    for (name, law) in laws(&m) {
        for seed in 1..6 {
            let f = general(seed);
            let mut rng = Rng(100 + seed);
            let g: Mat3 = std::array::from_fn(|_| std::array::from_fn(|_| rng.symmetric()));
            let eps = 1e-6;
            let at = |t: f64| {
                law.stress(&std::array::from_fn(|a| std::array::from_fn(|b| f[a][b] + t * g[a][b])))
                    .unwrap()
                    .0
            };
            let (s_plus, s_minus) = (at(eps), at(-eps));
            let (_, c) = law.stress(&f).unwrap();
            let fg = mul(&transpose(&f), &g);
            // δE in Voigt order, engineering shears.
            let de: [f64; 6] = std::array::from_fn(|v| {
                let (p, q) = VOIGT[v];
                if p == q {
                    fg[p][p]
                } else {
                    fg[p][q] + fg[q][p]
                }
            });
            let scale = largest(&law.stress(&f).unwrap().0).max(m.young());
            for (v, &(p, q)) in VOIGT.iter().enumerate() {
                let fd = (s_plus[p][q] - s_minus[p][q]) / (2.0 * eps);
                let exact: f64 = (0..6).map(|w| c[v][w] * de[w]).sum();
                assert!(
                    (fd - exact).abs() <= 1e-6 * scale,
                    "{name}, seed {seed}, S_{p}{q}: {fd} against {exact}"
                );
            }
        }
    }
}

/// The Cauchy stress of the 50 % stretch and of simple shear γ = 0.5 equals
/// the closed forms (and, for the stretch, the hand-reduced components);
/// rotating the deformation rotates it (frame indifference).
#[test]
fn the_cauchy_stress_of_known_deformations() {
    let m = material();
    let (lambda, mu) = m.lame();
    for (name, law) in laws(&m) {
        for (label, f) in deformations() {
            let sigma = law.cauchy(&f).unwrap();
            let exact = analytic_cauchy(&law, &f);
            assert!(difference(&sigma, &exact) <= 1e-12 * largest(&exact), "{name}, {label}");
            // A rotation Q: σ(QF) = Q σ(F) Qᵀ.
            let (c, s) = (0.6f64, 0.8f64);
            let q = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
            let rotated = law.cauchy(&mul(&q, &f)).unwrap();
            let expected = mul(&mul(&q, &sigma), &transpose(&q));
            assert!(difference(&rotated, &expected) <= 1e-12 * largest(&sigma), "{name}, {label}: frame");
        }
    }
    // The stretch s = 1.5 by hand: neo-Hookean σ_xx = [μ (s² − 1) + λ ln s]/s,
    // σ_yy = λ ln s / s; Saint Venant–Kirchhoff with e = (s² − 1)/2:
    // σ_xx = s (λ + 2μ) e, σ_yy = λ e / s.
    let s = 1.5f64;
    let e = 0.5 * (s * s - 1.0);
    let hand = [
        ((mu * (s * s - 1.0) + lambda * s.ln()) / s, lambda * s.ln() / s),
        (s * (lambda + 2.0 * mu) * e, lambda * e / s),
    ];
    for ((name, law), (xx, yy)) in laws(&m).into_iter().zip(hand) {
        let sigma = law.cauchy(&deformations()[0].1).unwrap();
        assert!(
            (sigma[0][0] - xx).abs() <= 1e-12 * xx.abs() && (sigma[1][1] - yy).abs() <= 1e-12 * xx.abs(),
            "{name}"
        );
        assert!(sigma[2][2] == sigma[1][1] && sigma[0][1] == 0.0, "{name}: {sigma:?}");
    }
}

/// Every cell kind: the first-order blocks and both raisings (complete and
/// serendipity), each kind once, on distorted cells.
fn meshes(n: usize) -> Vec<(CellKind, VolumeMesh)> {
    every_kind(|kind| distorted(kind, n, 0.25).0)
}

/// [`meshes`] of the blocks `first` gives.
fn every_kind(first: impl Fn(BlockKind) -> VolumeMesh) -> Vec<(CellKind, VolumeMesh)> {
    let mut out: Vec<(CellKind, VolumeMesh)> = Vec::new();
    for kind in KINDS {
        let first = first(kind);
        let raised = [true, false].map(|complete| raise_order(&first, complete).unwrap());
        for mesh in [first.clone()].into_iter().chain(raised) {
            let cell = CellKind::of(&mesh.cells()[0]);
            if !out.iter().any(|(k, _)| *k == cell) {
                out.push((cell, mesh));
            }
        }
    }
    out
}

/// K(u) v = (f(u + εv) − f(u − εv)) / 2ε at a large random u, on one or
/// two cells of every kind, both laws.
#[test]
fn the_tangent_is_the_derivative_of_the_internal_force() {
    let m = material();
    let kinds = meshes(1);
    assert!(kinds.len() >= 10, "{} cell kinds", kinds.len());
    for (kind, mesh) in &kinds {
        let n = 3 * mesh.points().len();
        let mut rng = Rng(*kind as u64 + 7);
        let u: Vec<f64> = (0..n).map(|_| 0.03 * rng.symmetric()).collect();
        let v: Vec<f64> = (0..n).map(|_| rng.symmetric()).collect();
        for (name, law) in laws(&m) {
            let k = tangent(mesh, &law, &u).unwrap();
            let kv = k.mul_vec(&v, 1);
            let eps = 1e-6;
            let at = |t: f64| {
                let w: Vec<f64> = u.iter().zip(&v).map(|(a, b)| a + t * b).collect();
                internal_force(mesh, &law, &w).unwrap()
            };
            let (plus, minus) = (at(eps), at(-eps));
            let scale = kv.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            for i in 0..n {
                let fd = (plus[i] - minus[i]) / (2.0 * eps);
                assert!(
                    (fd - kv[i]).abs() <= 1e-6 * scale,
                    "{kind:?}, {name}, dof {i}: {fd} against {}",
                    kv[i]
                );
            }
            // The tangent of a hyperelastic body is symmetric.
            for r in 0..n {
                let (cols, vals) = k.row(r);
                for (&c, &x) in cols.iter().zip(vals) {
                    assert!(
                        (x - k.get(c, r)).abs() <= 1e-12 * scale,
                        "{kind:?}, {name}: K not symmetric at ({r}, {c})"
                    );
                }
            }
        }
    }
}

/// One body, homogeneous large deformation: u = (F − I) X prescribed on the
/// boundary of a distorted block of every cell kind (the interior nodes
/// free, starting at rest), F the 50 % stretch or simple shear γ = 0.5,
/// both laws. The solve reproduces u inside to 1e-10 and the Cauchy stress
/// at every quadrature point, and as recovered per cell and per point,
/// equals the closed form to 1e-10 (the
/// predictor's linearised step reaches the affine field, which is in
/// equilibrium: Newton has nothing left).
#[test]
fn homogeneous_large_deformations_on_every_cell_kind() {
    let m = material();
    for (kind, mesh) in meshes(2) {
        let boundary = mesh.boundary().unwrap().used_points();
        assert!(boundary.iter().any(|b| !b), "{kind:?}: an interior node");
        for (label, f) in deformations() {
            let exact = |x: Point3| -> [f64; 3] {
                std::array::from_fn(|a| (0..3).map(|b| f[a][b] * x[b]).sum::<f64>() - x[a])
            };
            let mut bc = Dirichlet::new();
            for (p, &x) in mesh.points().iter().enumerate().filter(|(p, _)| boundary[*p]) {
                bc.fix(p, exact(x).map(Some));
            }
            let n = 3 * mesh.points().len();
            for (name, law) in laws(&m) {
                let (u, report) =
                    solve_newton(&mesh, &law, (&vec![0.0; n], &bc), &vec![0.0; n], &NewtonOptions::default())
                        .unwrap_or_else(|e| panic!("{kind:?}, {label}, {name}: {e}"));
                let r = &report.residuals;
                assert!(r.len() <= 2 && r.iter().all(|&x| x <= 1e-10), "{kind:?}, {label}, {name}: {r:?}");
                let scale = 0.5;
                for (p, &x) in mesh.points().iter().enumerate() {
                    let e = exact(x);
                    for a in 0..3 {
                        assert!(
                            (u[3 * p + a] - e[a]).abs() <= 1e-10 * scale,
                            "{kind:?}, {label}, {name}: point {p}"
                        );
                    }
                }
                let sigma_exact = analytic_cauchy(&law, &f);
                // The recovered stresses (cells and points), Voigt order.
                let recovered = cauchy_stresses(&mesh, &law, &u).unwrap();
                let voigt = VOIGT.map(|(a, b)| sigma_exact[a][b]);
                for s in recovered.cell.iter().chain(&recovered.nodal) {
                    for k in 0..6 {
                        assert!(
                            (s[k] - voigt[k]).abs() <= 1e-10 * largest(&sigma_exact),
                            "{kind:?}, {label}, {name}: {s:?}"
                        );
                    }
                }
                for (c, cell) in mesh.cells().iter().enumerate() {
                    let x: Vec<Point3> = cell.nodes().iter().map(|&p| mesh.points()[p]).collect();
                    let ue: Vec<[f64; 3]> =
                        cell.nodes().iter().map(|&p| [u[3 * p], u[3 * p + 1], u[3 * p + 2]]).collect();
                    for &xi in &kind.stiffness_rule().points {
                        let fh = cell_deformation_gradient(kind, &x, &ue, xi).unwrap();
                        let sigma = law.cauchy(&fh).unwrap();
                        assert!(
                            difference(&sigma, &sigma_exact) <= 1e-10 * largest(&sigma_exact),
                            "{kind:?}, {label}, {name}: cell {c}"
                        );
                    }
                }
            }
        }
    }
}

/// Newton's convergence where the deformation is not homogeneous: a
/// distorted block of every cell kind clamped at z = 0, its top z = 1
/// turned by 30° about the vertical axis through the block's centre and
/// lifted by 20 %, both laws, from rest. At most 12 iterations, and
/// quadratic at the end: over the residuals above round-off (1e-13), the
/// last contraction below the one before and below 1e-2.
#[test]
fn newton_converges_quadratically_on_a_twisted_block() {
    let m = material();
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    // A sheared 2 × 2 × 2 block, its bottom at z = 0 and its top at z = 1.
    for (kind, mesh) in
        every_kind(|kind| block(2, 2, 2, |u, v, w| [1.2 * u + 0.2 * v, 0.9 * v + 0.1 * w, w], kind))
    {
        let n = 3 * mesh.points().len();
        let mut bc = Dirichlet::new();
        for (p, x) in mesh.points().iter().enumerate() {
            if x[2] == 0.0 {
                bc.fix(p, [Some(0.0); 3]);
            }
            if x[2] == 1.0 {
                let (dx, dy) = (x[0] - 0.6, x[1] - 0.5);
                bc.fix(p, [Some(c * dx - s * dy - dx), Some(s * dx + c * dy - dy), Some(0.2 * x[2])]);
            }
        }
        for (name, law) in laws(&m) {
            let (_, report) =
                solve_newton(&mesh, &law, (&vec![0.0; n], &bc), &vec![0.0; n], &NewtonOptions::default())
                    .unwrap_or_else(|e| panic!("{kind:?}, {name}: {e}"));
            let r = &report.residuals;
            println!(
                "{kind:?}, {name}: {} iterations, residuals {r:?}, steps {:?}",
                r.len(),
                report.line_search
            );
            assert!(r.len() <= 12 && r.last().is_some_and(|&x| x <= 1e-10), "{kind:?}, {name}: {r:?}");
            // The contractions above round-off (1e-13).
            let above: Vec<f64> = r.iter().copied().filter(|&x| x > 1e-13).collect();
            let rates: Vec<f64> = above.windows(2).map(|w| w[1] / w[0]).collect();
            if let [.., before, last] = rates.as_slice() {
                assert!(last < before && *last < 1e-2, "{kind:?}, {name}: {r:?}");
            }
        }
    }
}

/// A prescribed deformation that turns cells inside out stops with a line
/// naming a cell.
#[test]
fn an_inverting_deformation_is_refused_with_the_cell() {
    let m = material();
    let (mesh, _) = distorted(KINDS[0], 2, 0.25);
    let boundary = mesh.boundary().unwrap().used_points();
    let mut bc = Dirichlet::new();
    for (p, &x) in mesh.points().iter().enumerate().filter(|(p, _)| boundary[*p]) {
        bc.fix(p, [Some(-1.5 * x[0]), Some(0.0), Some(0.0)]);
    }
    let n = 3 * mesh.points().len();
    let law = Hyperelastic::neo_hookean(&m);
    let error = solve_newton(&mesh, &law, (&vec![0.0; n], &bc), &vec![0.0; n], &NewtonOptions::default())
        .unwrap_err();
    assert!(matches!(error, FiniteError::Inverted { .. }), "{error:?}");
    assert!(
        error.to_string().starts_with("cell ")
            && error.to_string().ends_with("is inverted by the displacements (J ≤ 0)"),
        "{error}"
    );
}

/// The lateral stretch s of uniaxial stress at the axial stretch `axial`:
/// σ_yy(diag(axial, s, s)) = 0, by Newton on s (closed forms above).
pub(crate) fn lateral_stretch(law: &Hyperelastic, axial: f64) -> f64 {
    let sigma = |s: f64| analytic_cauchy(law, &[[axial, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]])[1][1];
    let mut s = 1.0;
    for _ in 0..50 {
        let h = 1e-7;
        let step = sigma(s) / ((sigma(s + h) - sigma(s - h)) / (2.0 * h));
        s -= step;
        if step.abs() < 1e-15 {
            break;
        }
    }
    assert!(
        sigma(s).abs()
            < 1e-9 * analytic_cauchy(law, &[[axial, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]])[0][0].abs()
    );
    s
}

/// A `kind` block [0, 1]² × [z0, z0 + 1] of n × n × nz cells (raised to
/// second order with `raise`: complete or not) with the surfaces XMin,
/// YMin, ZMin, ZMax.
pub(crate) fn slab(
    name: &str,
    (n, nz): (usize, usize),
    z0: f64,
    kind: BlockKind,
    raise: Option<bool>,
    law: Law,
) -> ProblemBody {
    let cube = block(n, n, nz, |x, y, z| [x, y, z0 + z], kind);
    let mesh = match raise {
        Some(complete) => raise_order(&cube, complete).unwrap(),
        None => cube,
    };
    let grid = Grid::new(n, n, nz);
    let surfaces = [Side::XMin, Side::YMin, Side::ZMin, Side::ZMax]
        .map(|side| (format!("{side:?}"), grid.side_faces(&mesh, side).unwrap()))
        .to_vec();
    ProblemBody { law, ..ProblemBody::new(name, mesh, material(), surfaces) }
}

/// Uniaxial stress to the stretch 1.5 along z over four load steps, in one
/// body and across a non-matching glued interface (dual multipliers: Hex8
/// under a coarser and a finer Tet4, the glue as a saddle point and
/// eliminated; Hex27 under Tet10 with its Tri6 slave faces raised), rollers
/// on x = 0, y = 0 and the bottom, the top pulled up: the homogeneous state
/// diag(s, s, 1.5), s from σ_xx = 0, reproduced to 1e-10 in displacement,
/// Cauchy stress and interface traction (σ_zz per reference area, s² σ_zz),
/// for both laws; Newton reports each step.
#[test]
fn uniaxial_stress_over_load_steps_in_one_body_and_across_glue() {
    uniaxial_stress_with(&seam_fem::SolveOptions::default());
}

/// [`uniaxial_stress_over_load_steps_in_one_body_and_across_glue`] by the
/// solver of `options` (PETSc: every case by FGMRES with GAMG on the glue
/// eliminated).
pub(crate) fn uniaxial_stress_with(options: &seam_fem::SolveOptions) {
    use seam_fem::{solve_steps, Coupling, LoadSteps, Problem, ProblemInterface, Support, SurfaceId};
    let id = |body, surface| SurfaceId { body, surface };
    let roller =
        |b, s, k: usize, v: f64| Support::new(id(b, s), std::array::from_fn(|c| (c == k).then_some(v)));
    let stretch = 1.5;
    for (law_name, law) in
        [("neo-Hookean", Law::NeoHookean), ("Saint Venant-Kirchhoff", Law::SaintVenantKirchhoff)]
    {
        let hyper = law.hyperelastic(&material()).unwrap();
        let s = lateral_stretch(&hyper, stretch);
        let f = [[s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, stretch]];
        let sigma = analytic_cauchy(&hyper, &[[stretch, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]]);
        let sigma_zz = sigma[0][0];
        let one = Problem {
            bodies: vec![slab("one", (2, 2), 0.0, BlockKind::Tet, Some(false), law)],
            supports: vec![
                roller(0, 0, 0, 0.0),
                roller(0, 1, 1, 0.0),
                roller(0, 2, 2, 0.0),
                roller(0, 3, 2, 0.5),
            ],
            steps: LoadSteps::equal(4).unwrap(),
            ..Problem::default()
        };
        let glued = |lower: (BlockKind, Option<bool>, usize),
                     upper: (BlockKind, Option<bool>, usize, usize)| Problem {
            bodies: vec![
                slab("lower", (lower.2, 2), 0.0, lower.0, lower.1, law),
                slab("upper", (upper.2, upper.3), 1.0, upper.0, upper.1, law),
            ],
            interfaces: vec![ProblemInterface {
                master: id(0, 3),
                slave: id(1, 2),
                options: seam::MortarOptions { multiplier: seam::Multiplier::Dual, ..Default::default() },
                kind: Coupling::Glue,
                friction: 0.0,
            }],
            supports: vec![
                roller(0, 2, 2, 0.0),
                roller(0, 0, 0, 0.0),
                roller(0, 1, 1, 0.0),
                roller(1, 0, 0, 0.0),
                roller(1, 1, 1, 0.0),
                roller(1, 3, 2, 1.0),
            ],
            steps: LoadSteps::equal(4).unwrap(),
            ..Problem::default()
        };
        // The glue eliminated (a finer slave) or as a saddle point (a coarser
        // slave, where the elimination fills in).
        let (eliminated, saddle) = match options.solver {
            seam_fem::Solver::Petsc(_) => ("PETSc", "PETSc"),
            _ => ("sparse Cholesky", "saddle-point LDLᵀ"),
        };
        let cases = [
            ("one Tet10 body", one, eliminated),
            ("Hex8 | Tet4", glued((BlockKind::Hex, None, 3), (BlockKind::Tet, None, 2, 2)), saddle),
            (
                "Hex8 | finer Hex8",
                glued((BlockKind::Hex, None, 2), (BlockKind::Hex, None, 4, 10)),
                eliminated,
            ),
            (
                "Hex27 | Tet10",
                glued((BlockKind::Hex, Some(true), 3), (BlockKind::Tet, Some(false), 2, 2)),
                saddle,
            ),
        ];
        for (label, problem, method) in cases {
            let steps: Vec<_> = solve_steps(&problem, options)
                .collect::<Result<_, _>>()
                .unwrap_or_else(|e| panic!("{law_name}, {label}: {e}"));
            assert_eq!(steps.len(), 4);
            for (t, step) in &steps {
                let newton = step.report.newton.as_ref().expect("a Newton report");
                println!("{law_name}, {label}, t = {t}: residuals {:?}", newton.residuals);
                assert!(
                    newton.residuals.last().is_none_or(|&r| r <= 1e-10),
                    "{law_name}, {label}: {newton:?}"
                );
            }
            let solution = &steps[3].1;
            assert!(solution.report.method.contains(method), "{label}: {}", solution.report.method);
            // `solve` follows the same load path (finite deformation depends on it).
            let at_once = seam_fem::solve(&problem, options).unwrap();
            assert_eq!(at_once.displacement, solution.displacement, "{law_name}, {label}");
            let voigt = VOIGT.map(|(a, b)| if a == b && a == 2 { sigma_zz } else { 0.0 });
            for (b, body) in problem.bodies.iter().enumerate() {
                let u = &solution.displacement[b];
                for (p, x) in body.mesh.points().iter().enumerate() {
                    for a in 0..3 {
                        let exact = (0..3).map(|k| f[a][k] * x[k]).sum::<f64>() - x[a];
                        assert!(
                            (u[3 * p + a] - exact).abs() <= 1e-10,
                            "{law_name}, {label}: body {b}, point {p}"
                        );
                    }
                }
                for s in solution.stresses[b].cell.iter().chain(&solution.stresses[b].nodal) {
                    for k in 0..6 {
                        assert!(
                            (s[k] - voigt[k]).abs() <= 1e-10 * sigma_zz,
                            "{law_name}, {label}: body {b}: {s:?}"
                        );
                    }
                }
            }
            // The traction on the slave (its bottom, normal −z): −P_zz per reference area, P_zz = s² σ_zz.
            if let Some(i) = solution.interfaces.first() {
                let nominal = s * s * sigma_zz;
                for (p, t) in i.traction.iter().enumerate().filter(|(p, _)| i.constrained[*p]) {
                    assert!(
                        (t[2] + nominal).abs() <= 1e-8 * nominal && t[0].abs() + t[1].abs() <= 1e-8 * nominal,
                        "{law_name}, {label}: traction {t:?} at {p}, expected (0, 0, {})",
                        -nominal
                    );
                }
            }
        }
    }
}

/// A linear and a hyperelastic body in one problem: one line naming both.
#[test]
fn linear_and_hyperelastic_bodies_are_not_mixed() {
    use seam_fem::{solve_steps, Problem, SolveOptions};
    let problem = Problem {
        bodies: vec![
            slab("soft", (1, 1), 0.0, BlockKind::Hex, None, Law::NeoHookean),
            slab("steel", (1, 1), 1.0, BlockKind::Hex, None, Law::Linear),
        ],
        ..Problem::default()
    };
    let error = solve_steps(&problem, &SolveOptions::default()).next().unwrap().unwrap_err().to_string();
    assert!(error.starts_with("body \"steel\" is linear and body \"soft\" hyperelastic"), "{error}");
}
