//! Coulomb friction: patch tests of a block on a base (non-matching hex|tet)
//! in stick and in slip, exact for first-order elements. (μ = 0 against
//! frictionless contact: the unit tests of `contact::friction`.)

use seam::{Multiplier, Point3};
use seam_fem::generate::{block, BlockKind, Grid, Side};
use seam_fem::{
    solve, Coupling, Load, Material, Problem, ProblemBody, ProblemInterface, SolveOptions, Support, SurfaceId,
};

pub(crate) const E: f64 = 100.0;
pub(crate) const P: f64 = 2.0;

/// The base [0,1]² × [0, ½] (hexahedra 3×3×2, clamped at the bottom) and the
/// block [0,1]² × [½, 1] (tetrahedra 2×2×2) on it in contact with friction
/// μ, ν = 0 in both. The block's top is pressed by P; its sides x = 0, 1 of
/// both bodies carry the complementary shear ∓τ_s in z of a uniform σ_xz =
/// τ_s; `top_x` is either a traction τ on the top or a prescribed u_x.
fn block_on_base(mu: f64, tau_side: f64, top_x: TopX) -> Problem {
    block_on_base_as(mu, tau_side, top_x, Layout::default())
}

/// How [`block_on_base_as`] builds the bodies: rotated by `rotation` (points
/// and loads), and second order (a Tet10 base, a Hex27 block; with
/// `tri6_slave` a Hex27 base and a Tet10 block, dual multipliers in Popp's
/// transformed basis).
#[derive(Clone, Copy)]
pub(crate) struct Layout {
    pub(crate) rotation: [[f64; 3]; 3],
    pub(crate) second_order: bool,
    pub(crate) tri6_slave: bool,
}

impl Default for Layout {
    fn default() -> Self {
        let rotation = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        Layout { rotation, second_order: false, tri6_slave: false }
    }
}

impl Layout {
    pub(crate) fn rotate(&self, v: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|j| self.rotation[i][j] * v[j]).sum())
    }

    pub(crate) fn back(&self, v: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|j| self.rotation[j][i] * v[j]).sum())
    }
}

/// [`block_on_base`] with `layout` (a prescribed u_x needs no rotation).
pub(crate) fn block_on_base_as(mu: f64, tau_side: f64, top_x: TopX, layout: Layout) -> Problem {
    let material = Material::new(E, 0.0).unwrap();
    let sides = [("bottom", Side::ZMin), ("top", Side::ZMax), ("xmin", Side::XMin), ("xmax", Side::XMax)];
    let body = |name: &str, n: [usize; 3], z0: f64, kind| {
        let mut b =
            block_body(name, (n, kind, material), |x, y, z| layout.rotate([x, y, z0 + 0.5 * z]), &sides);
        if layout.second_order {
            let complete = kind == BlockKind::Hex;
            let mesh = seam_fem::generate::raise_order(&b.mesh, complete).unwrap();
            let grid = Grid::new(n[0], n[1], n[2]);
            for (surface, &(_, side)) in b.surfaces.iter_mut().zip(&sides) {
                surface.1 = grid.side_faces(&mesh, side).unwrap();
            }
            b.mesh = mesh;
        }
        b
    };
    let id = |body, surface| SurfaceId { body, surface };
    let mut loads = Vec::new();
    for b in 0..2 {
        loads.push(Load::new(id(b, 2), layout.rotate([0.0, 0.0, -tau_side])));
        loads.push(Load::new(id(b, 3), layout.rotate([0.0, 0.0, tau_side])));
    }
    let mut supports = vec![Support::new(id(0, 0), [Some(0.0); 3])];
    match top_x {
        TopX::Traction(tau) => loads.push(Load::new(id(1, 1), layout.rotate([tau, 0.0, -P]))),
        TopX::Displacement(ux) => {
            loads.push(Load::new(id(1, 1), [0.0, 0.0, -P]));
            supports.push(Support::new(id(1, 1), [Some(ux), None, None]));
        }
    }
    let (base_kind, block_kind) = match layout {
        Layout { second_order: true, tri6_slave: false, .. } => (BlockKind::Tet, BlockKind::Hex),
        _ => (BlockKind::Hex, BlockKind::Tet),
    };
    let bodies = [body("base", [3, 3, 2], 0.0, base_kind), body("block", [2, 2, 2], 0.5, block_kind)];
    let mut problem = Problem { supports, loads, ..on_base(bodies, mu) };
    if layout.tri6_slave {
        problem.interfaces[0].options.multiplier = Multiplier::Dual;
    }
    problem
}

/// An n[0] × n[1] × n[2] block of `kind` cells mapped by `map` from the
/// unit cube, with the named sides.
fn block_body(
    name: &str,
    (n, kind, material): ([usize; 3], BlockKind, Material),
    map: impl Fn(f64, f64, f64) -> [f64; 3],
    sides: &[(&str, Side)],
) -> ProblemBody {
    let mesh = block(n[0], n[1], n[2], map, kind);
    let grid = Grid::new(n[0], n[1], n[2]);
    let surfaces =
        sides.iter().map(|&(s, side)| (s.to_string(), grid.side_faces(&mesh, side).unwrap())).collect();
    ProblemBody::new(name, mesh, material, surfaces)
}

/// The bodies [base, block] in contact, the block's surface 0 (slave) on
/// the base's surface 1 (master), lumped multipliers, friction μ.
fn on_base(bodies: [ProblemBody; 2], mu: f64) -> Problem {
    let id = |body, surface| SurfaceId { body, surface };
    let options = seam::MortarOptions {
        multiplier: Multiplier::Lumped,
        facing: seam::Facing::Opposite,
        ..Default::default()
    };
    Problem {
        bodies: bodies.to_vec(),
        interfaces: vec![ProblemInterface {
            master: id(0, 1),
            slave: id(1, 0),
            options,
            kind: Coupling::Contact,
            friction: mu,
        }],
        ..Problem::default()
    }
}

#[derive(Clone, Copy)]
pub(crate) enum TopX {
    Traction(f64),
    Displacement(f64),
}

/// The largest |t − expected| over the contact points of the solution's interface.
pub(crate) fn traction_miss(s: &seam_fem::Solution, expected: Point3) -> f64 {
    let f = &s.interfaces[0];
    let c = f.contact.as_ref().unwrap();
    (0..c.contact.len())
        .filter(|&p| c.contact[p])
        .flat_map(|p| (0..3).map(move |k| (f.traction[p][k] - expected[k]).abs()))
        .fold(0.0, f64::max)
}

#[test]
fn below_the_friction_bound_every_point_sticks_and_the_traction_is_exact() {
    // τ = 0.5 < μ P = 0.6: the block is held by friction alone. Hex8 base |
    // Tet4 block, then rotated, then a Tet10 base | Hex27 block (Quad9 slave
    // faces), then a Hex27 base | Tet10 block (Tri6 slave faces, dual
    // multipliers in the transformed basis).
    let tau = 0.5;
    let (c, s) = ((0.6f64).cos(), (0.6f64).sin());
    let rotated = [[c, 0.0, s], [s * s, c, -s * c], [-s * c, s, c * c]];
    let layouts = [
        ("hex|tet", Layout::default()),
        ("hex|tet rotated", Layout { rotation: rotated, ..Layout::default() }),
        ("tet10|hex27", Layout { second_order: true, ..Layout::default() }),
        ("hex27|tet10 dual", Layout { second_order: true, tri6_slave: true, ..Layout::default() }),
    ];
    for (name, layout) in layouts {
        let problem = block_on_base_as(0.3, tau, TopX::Traction(tau), layout);
        let s = solve(&problem, &SolveOptions::default()).unwrap();
        let c = s.interfaces[0].contact.as_ref().unwrap();
        let points: Vec<usize> = (0..c.contact.len()).filter(|&p| c.contact[p]).collect();
        assert!(!points.is_empty() && points.iter().all(|&p| c.active[p] && c.stick[p]), "{name}: all stick");
        // The master holds the slave (outward normal −z) with σ·(−e_z) = (−τ, 0, P).
        let miss = traction_miss(&s, layout.rotate([-tau, 0.0, P]));
        assert!(miss < 1e-10, "{name}: traction off by {miss:e}");
        assert!(points.iter().all(|&p| c.slip[p].iter().all(|v| v.abs() < 1e-14)), "{name}: no slip");
        // The exact field: u_x = τ z / G (G = E/2 with ν = 0), u_z = −P z / E.
        let g = E / 2.0;
        for (body, u) in problem.bodies.iter().zip(&s.displacement) {
            for (&x, u) in body.mesh.points().iter().zip(u.chunks(3)) {
                let z = layout.back(x)[2];
                let exact = layout.rotate([tau * z / g, 0.0, -P * z / E]);
                assert!((0..3).all(|k| (u[k] - exact[k]).abs() < 1e-12), "{name} {x:?}: {u:?} vs {exact:?}");
            }
        }
        let steps = &s.report.contact.as_ref().unwrap().steps;
        assert!(steps.len() <= 3, "{name}: {steps:?}");
    }
}

#[test]
fn driven_past_the_friction_bound_every_point_slips_at_mu_p_along_the_drive() {
    // The top pushed 0.05 along x: the shear needed to stick, τ = G · 0.05 / ½
    // = 5, is beyond μ P = 0.6, so the block slides with ‖t_τ‖ = μ P. Hex8 |
    // Tet4, and Hex27 | Tet10 (Tri6 slave faces, dual multipliers in the
    // transformed basis).
    let mu = 0.3;
    let tau = mu * P;
    let tri6 = Layout { second_order: true, tri6_slave: true, ..Layout::default() };
    for (name, layout) in [("hex|tet", Layout::default()), ("hex27|tet10 dual", tri6)] {
        let mut problem = block_on_base_as(mu, tau, TopX::Displacement(0.05), layout);
        problem.steps = seam_fem::LoadSteps::equal(10).unwrap();
        let s = solve(&problem, &SolveOptions::default()).unwrap();
        let f = &s.interfaces[0];
        let c = f.contact.as_ref().unwrap();
        let points: Vec<usize> = (0..c.contact.len()).filter(|&p| c.contact[p]).collect();
        assert!(points.iter().all(|&p| c.active[p] && !c.stick[p]), "{name}: all slip");
        let miss = traction_miss(&s, [-tau, 0.0, P]);
        assert!(miss < 1e-10, "{name}: traction off by {miss:e}");
        for &p in &points {
            let bound = c.friction_bound[p];
            assert!((bound - mu * P).abs() < 1e-10, "{name}: {bound}");
            let t = f.tangential_traction[p];
            assert!(((t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt() - bound).abs() < 1e-10, "{name}");
            // Slip along the drive: the drive less the shear of the block and the base, each τ ½ / G.
            let slip = c.slip[p];
            let expected = 0.05 - 2.0 * tau * 0.5 / (E / 2.0);
            assert!(
                (slip[0] - expected).abs() < 1e-12 && slip[1].abs() < 1e-12 && slip[2].abs() < 1e-12,
                "{name}: {slip:?}"
            );
        }
        let steps = &s.report.contact.as_ref().unwrap().steps;
        let r: Vec<f64> = steps.iter().map(|s| s.residual).collect();
        println!("{name}: Newton updates of the last load step: {r:?}");
        assert!(steps.len() <= 8, "{name}: {steps:?}");
        // Superlinear: the ratio of successive updates falls over the last ones (to round-off).
        let k = r.iter().position(|&x| x < 1e-8).expect("converged");
        assert!(
            k >= 3 && r[k] / r[k - 1] < r[k - 1] / r[k - 2] && r[k - 1] / r[k - 2] < r[k - 2] / r[k - 3],
            "{name}: {r:?}"
        );
    }
}

/// A block (1 × 1 × ½, tetrahedra) of weight W on a base inclined by α
/// (tan α = 0.1; hexahedra, clamped), μ = 0.3, its top pushed horizontally
/// (u_x prescribed) uphill until it slides: the push is W (tan α + μ) /
/// (1 − μ tan α) (NAFEMS-type sliding block).
#[test]
fn a_block_pushed_up_an_incline_slides_at_the_coulomb_force() {
    let (tan, mu, weight) = (0.1f64, 0.3, 1.0);
    let (sin, cos) = (tan / (1.0 + tan * tan).sqrt(), 1.0 / (1.0 + tan * tan).sqrt());
    let incline = move |p: [f64; 3]| [p[0] * cos - p[2] * sin, p[1], p[0] * sin + p[2] * cos];
    let material = Material::new(E, 0.3).unwrap();
    let body = |name: &str, n: [usize; 3], corner: [f64; 3], size: [f64; 3], kind| {
        let map =
            |x, y, z| incline([corner[0] + size[0] * x, corner[1] + size[1] * y, corner[2] + size[2] * z]);
        block_body(name, (n, kind, material), map, &[("bottom", Side::ZMin), ("top", Side::ZMax)])
    };
    let base = body("base", [6, 3, 2], [-0.5, 0.0, -0.5], [2.0, 1.0, 0.5], BlockKind::Hex);
    let mut slider = body("block", [3, 3, 2], [0.0, 0.0, 0.0], [1.0, 1.0, 0.5], BlockKind::Tet);
    slider.body_force = [0.0, 0.0, -weight / 0.5];
    let id = |body, surface| SurfaceId { body, surface };
    let problem = Problem {
        supports: vec![
            Support::new(id(0, 0), [Some(0.0); 3]),
            Support::new(id(1, 1), [Some(0.02), None, None]),
        ],
        steps: seam_fem::LoadSteps::equal(4).unwrap(),
        ..on_base([base, slider], mu)
    };
    let s = solve(&problem, &SolveOptions::default()).unwrap();
    let c = s.interfaces[0].contact.as_ref().unwrap();
    let slipping = (0..c.contact.len()).filter(|&p| c.active[p] && !c.stick[p]).count();
    assert_eq!(slipping, (0..c.contact.len()).filter(|&p| c.active[p]).count(), "every active point slips");
    let force = s.interfaces[0].force;
    assert!((force[2] - weight).abs() < 1e-10, "the base carries the weight: {force:?}");
    let push = -force[0] / weight;
    let exact = (tan + mu) / (1.0 - mu * tan);
    println!("push / weight {push:.6} (exact {exact:.6})");
    assert!((push - exact).abs() < 1e-3 * exact, "{push} vs {exact}");
}

/// Hertz (quarter model, the symmetry planes prescribed at contact points)
/// with friction μ = 0.3 between equal materials, where the normal and the
/// tangential problems decouple (Cattaneo–Mindlin's premise): the pressure is
/// the frictionless one and the frictional tractions nearly vanish.
#[test]
fn hertz_between_equal_materials_is_frictionless_with_friction() {
    use seam_fem::scene::{hertz, Hertz};
    let material = Material::new(1000.0, 0.3).unwrap();
    let params = Hertz { fine_cells: 4, indenter: material, block: material, ..Hertz::default() };
    let frictionless = hertz(&params).unwrap();
    let mut frictional = frictionless.clone();
    frictional.interfaces[0].friction = 0.3;
    frictional.steps = seam_fem::LoadSteps::equal(2).unwrap();
    let clock = std::time::Instant::now();
    let a = solve(&frictionless, &SolveOptions::default()).unwrap();
    let t0 = clock.elapsed().as_secs_f64();
    let b = solve(&frictional, &SolveOptions::default()).unwrap();
    let t1 = clock.elapsed().as_secs_f64() - t0;
    let (ca, cb) = (a.interfaces[0].contact.as_ref().unwrap(), b.interfaces[0].contact.as_ref().unwrap());
    let p0 = params.peak_pressure();
    let max = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |m, x| m.max(x.abs()));
    let dp = max(&mut ca.pressure.iter().zip(&cb.pressure).map(|(x, y)| x - y));
    let tt = max(&mut b.interfaces[0]
        .tangential_traction
        .iter()
        .map(|t| (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt()));
    println!(
        "dofs {}: frictionless {t0:.2} s, frictional {t1:.2} s ({:?} Newton iterations in the last step); pressure change {:.2e} p0, largest frictional traction {:.2e} p0",
        a.report.dofs,
        b.report.contact.as_ref().unwrap().steps.len(),
        dp / p0,
        tt / p0
    );
    assert_eq!(ca.active, cb.active);
    // Measured 3.9e-4 and 2.1e-2 (finite bodies and non-matching meshes do not decouple exactly).
    assert!(dp < 1e-3 * p0 && tt < 3e-2 * p0, "{:e} {:e}", dp / p0, tt / p0);
    assert!(cb.stick.iter().zip(&cb.active).all(|(s, a)| s == a), "every active point sticks");
}

/// History: the block on the base pressed by P and pushed sideways by a
/// traction τ = 0.9 μP on its top (no side loads: the pressure is not uniform,
/// so the edges slip first), then unloaded sideways. At the peak some points
/// slip and some stick; after unloading the slip stays and the locked-in
/// frictional tractions balance each other (their resultant vanishes to
/// round-off).
#[test]
fn slip_stays_and_locked_in_tractions_balance_after_unloading() {
    let mu = 0.3;
    let mut problem = block_on_base(mu, 0.0, TopX::Traction(0.0));
    // P from the start (its amplitude 1 throughout), τ up and down again.
    let press = problem.loads.last_mut().unwrap();
    press.amplitude = seam_fem::Amplitude::new(vec![[0.0, 1.0]]).unwrap();
    let sideways = Load {
        amplitude: seam_fem::Amplitude::new(vec![[0.0, 0.0], [0.5, 1.0], [1.0, 0.0]]).unwrap(),
        ..Load::new(SurfaceId { body: 1, surface: 1 }, [0.9 * mu * P, 0.0, 0.0])
    };
    problem.loads.push(sideways);
    problem.steps = seam_fem::LoadSteps::equal(6).unwrap();
    let steps: Vec<_> =
        seam_fem::solve_steps(&problem, &SolveOptions::default()).map(Result::unwrap).collect();
    let (_, peak) = &steps[2];
    let c = peak.interfaces[0].contact.as_ref().unwrap();
    let stick = (0..c.contact.len()).filter(|&p| c.active[p] && c.stick[p]).count();
    let slip = (0..c.contact.len()).filter(|&p| c.active[p] && !c.stick[p]).count();
    println!("at the peak: {stick} points stick, {slip} slip");
    assert!(stick > 0 && slip > 0, "partial slip at the peak");
    let (time, last) = steps.last().unwrap();
    assert_eq!(*time, 1.0);
    let f = &last.interfaces[0];
    let c = f.contact.as_ref().unwrap();
    let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let slip_left = c.slip.iter().map(|&s| norm(s)).fold(0.0, f64::max);
    let locked = f.tangential_traction.iter().map(|&t| norm(t)).fold(0.0, f64::max);
    // The resultant: the sideways load is gone, the weight of P stays.
    let force = f.force;
    println!("after unloading: slip {slip_left:e}, locked-in traction {locked:e}, resultant {force:?}");
    assert!(slip_left > 1e-6, "the slip stays");
    assert!(locked > 1e-3 * mu * P, "tractions are locked in");
    assert!(force[0].abs() < 1e-12 * P && force[1].abs() < 1e-12 * P, "{force:?}");
}

/// [`block_on_base`] with a cap [0,1]² × [1, 3/2] (hexahedra 3×3×1) glued on
/// the block's top (the cap's bottom the slave, with `multiplier`): the
/// block's top loads and supports move to the cap's top, the cap's sides
/// carry the same complementary shear.
pub(crate) fn capped_block_on_base(mu: f64, tau_side: f64, top_x: TopX, multiplier: Multiplier) -> Problem {
    let mut problem = block_on_base(mu, tau_side, top_x);
    let material = Material::new(E, 0.0).unwrap();
    let sides = [("bottom", Side::ZMin), ("top", Side::ZMax), ("xmin", Side::XMin), ("xmax", Side::XMax)];
    let cap =
        block_body("cap", ([3, 3, 1], BlockKind::Hex, material), |x, y, z| [x, y, 1.0 + 0.5 * z], &sides);
    problem.bodies.push(cap);
    let id = |body, surface| SurfaceId { body, surface };
    let to_cap = |b: &mut SurfaceId| {
        if *b == id(1, 1) {
            *b = id(2, 1);
        }
    };
    problem.loads.iter_mut().for_each(|l| to_cap(&mut l.boundary));
    problem.supports.iter_mut().for_each(|s| to_cap(&mut s.boundary));
    problem.loads.push(Load::new(id(2, 2), [0.0, 0.0, -tau_side]));
    problem.loads.push(Load::new(id(2, 3), [0.0, 0.0, tau_side]));
    let options = seam::MortarOptions { multiplier, facing: seam::Facing::Opposite, ..Default::default() };
    let glue =
        ProblemInterface { master: id(1, 1), slave: id(2, 0), options, kind: Coupling::Glue, friction: 0.0 };
    problem.interfaces.push(glue);
    problem
}

#[test]
fn a_glued_cap_keeps_the_patch_tests_exact() {
    // Stick (τ = 0.5 < μP) and slip (the cap's top driven 0.05 along x); the
    // glue with dual multipliers eliminated node by node (the Newton steps
    // condensed on the contact jumps), or standard ones (the whole system).
    let mu = 0.3;
    let cases = [("stick", 0.5, TopX::Traction(0.5)), ("slip", mu * P, TopX::Displacement(0.05))];
    let methods = [
        (Multiplier::Dual, "sparse Cholesky, semismooth Newton on the condensed contact unknowns"),
        (Multiplier::Standard, "sparse LDLᵀ and GMRES per semismooth Newton step"),
    ];
    for ((name, tau, top_x), (multiplier, method)) in cases.into_iter().flat_map(|c| methods.map(|m| (c, m)))
    {
        let mut problem = capped_block_on_base(mu, tau, top_x, multiplier);
        if name == "slip" {
            problem.steps = seam_fem::LoadSteps::equal(10).unwrap();
        }
        let s = solve(&problem, &SolveOptions::default()).unwrap();
        assert_eq!(s.report.method, method);
        let c = s.interfaces[0].contact.as_ref().unwrap();
        let points: Vec<usize> = (0..c.contact.len()).filter(|&p| c.contact[p]).collect();
        let stick = name == "stick";
        assert!(!points.is_empty() && points.iter().all(|&p| c.active[p] && c.stick[p] == stick), "{name}");
        let miss = traction_miss(&s, [-tau, 0.0, P]);
        assert!(miss < 1e-10, "{name}: contact traction off by {miss:e}");
        // The glue carries the same uniform stress: (τ, 0, −P) on the cap's bottom (normal −z).
        let glue = &s.interfaces[1];
        let on = (0..glue.traction.len()).filter(|&p| glue.constrained[p]);
        let glue_miss =
            on.map(|p| glue.traction[p]).map(|t| (t[0] + tau).abs().max(t[1].abs()).max((t[2] - P).abs()));
        let glue_miss = glue_miss.fold(0.0, f64::max);
        assert!(
            glue.constrained.iter().any(|&c| c) && glue_miss < 1e-9,
            "{name}: glue traction off by {glue_miss:e}"
        );
        if stick {
            // The exact field: u_x = τ z / G (G = E/2 with ν = 0), u_z = −P z / E.
            for (body, u) in problem.bodies.iter().zip(&s.displacement) {
                for (&x, u) in body.mesh.points().iter().zip(u.chunks(3)) {
                    let exact = [tau * x[2] / (E / 2.0), 0.0, -P * x[2] / E];
                    assert!((0..3).all(|k| (u[k] - exact[k]).abs() < 1e-12), "{x:?}: {u:?} vs {exact:?}");
                }
            }
        } else {
            // Slip along the drive: the drive less the shear of the block, the cap and the base.
            let expected = 0.05 - 3.0 * tau * 0.5 / (E / 2.0);
            assert!(
                points.iter().all(|&p| (c.slip[p][0] - expected).abs() < 1e-12),
                "{:?}",
                c.slip[points[0]]
            );
        }
    }
}
