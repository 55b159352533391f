//! Contact in finite deformation (`seam_fem::finite`): the mortar terms on
//! the current configuration, Newton with their linearisation.

use crate::common::material;
use crate::hyperelastic::{analytic_cauchy, lateral_stretch, slab};
use seam_fem::generate::BlockKind;
use seam_fem::{
    solve_steps, Coupling, Law, LoadSteps, Problem, ProblemInterface, Solution, SolveOptions, Support,
    SurfaceId,
};

fn id(body: usize, surface: usize) -> SurfaceId {
    SurfaceId { body, surface }
}

/// Component `k` of `surface` prescribed to `v`.
fn roller(body: usize, surface: usize, k: usize, v: f64) -> Support {
    Support::new(id(body, surface), std::array::from_fn(|c| (c == k).then_some(v)))
}

/// Two blocks [0, 1]² × [0, 1] (master, `lower` cells across) and
/// [0, 1]² × [1, 2] (slave, `upper`) in frictionless contact, rollers on
/// x = 0, y = 0 and the bottom, the top moved down by `press` over `steps`
/// load steps.
fn stack(
    law: Law,
    lower: (BlockKind, usize),
    upper: (BlockKind, usize),
    press: f64,
    steps: usize,
) -> Problem {
    Problem {
        bodies: vec![
            slab("lower", (lower.1, 2), 0.0, lower.0, None, law),
            slab("upper", (upper.1, 2), 1.0, upper.0, None, law),
        ],
        interfaces: vec![ProblemInterface {
            master: id(0, 3),
            slave: id(1, 2),
            options: seam::MortarOptions { multiplier: seam::Multiplier::Dual, ..Default::default() },
            kind: Coupling::Contact,
            friction: 0.0,
        }],
        supports: vec![
            roller(0, 2, 2, 0.0),
            roller(0, 0, 0, 0.0),
            roller(0, 1, 1, 0.0),
            roller(1, 0, 0, 0.0),
            roller(1, 1, 1, 0.0),
            roller(1, 3, 2, -press),
        ],
        steps: LoadSteps::equal(steps).unwrap(),
        ..Problem::default()
    }
}

fn solve_all(problem: &Problem) -> Vec<(f64, Solution)> {
    solve_steps(problem, &SolveOptions::default()).collect::<Result<_, _>>().unwrap_or_else(|e| panic!("{e}"))
}

/// The contact patch test under 20 % compression: two non-matching blocks
/// of one material pressed together by 0.4 over four steps are each in
/// uniaxial stress with the stretch 0.8; every contact point carries the
/// pressure −σ_zz of that state (per current area) to 1e-8, the points move
/// as the homogeneous deformation to 1e-10, for both laws and hex | tet.
#[test]
fn contact_patch_test_under_20_percent_compression() {
    for (law_name, law) in
        [("neo-Hookean", Law::NeoHookean), ("Saint Venant-Kirchhoff", Law::SaintVenantKirchhoff)]
    {
        let hyper = law.hyperelastic(&material()).unwrap();
        let s = lateral_stretch(&hyper, 0.8);
        let pressure = -analytic_cauchy(&hyper, &[[0.8, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]])[0][0];
        assert!(pressure > 0.0);
        for (label, lower, upper) in [
            ("Hex8 | Hex8", (BlockKind::Hex, 3), (BlockKind::Hex, 4)),
            ("Hex8 | Tet4", (BlockKind::Hex, 3), (BlockKind::Tet, 2)),
        ] {
            let problem = stack(law, lower, upper, 0.4, 4);
            let steps = solve_all(&problem);
            for (t, step) in &steps {
                let newton = step.report.newton.as_ref().unwrap();
                println!("{law_name}, {label}, t = {t}: residuals {:?}", newton.residuals);
            }
            let solution = &steps.last().unwrap().1;
            let i = &solution.interfaces[0];
            let c = i.contact.as_ref().unwrap();
            let points: Vec<usize> = (0..c.contact.len()).filter(|&p| c.contact[p]).collect();
            assert!(!points.is_empty());
            for &p in &points {
                assert!(c.active[p], "{label}: point {p} inactive");
                assert!(
                    (c.pressure[p] - pressure).abs() <= 1e-8 * pressure,
                    "{law_name}, {label}: pressure {} at {p}, expected {pressure}",
                    c.pressure[p]
                );
            }
            for (b, body) in problem.bodies.iter().enumerate() {
                let u = &solution.displacement[b];
                for (p, x) in body.mesh.points().iter().enumerate() {
                    let z0 = b as f64;
                    let exact = [(s - 1.0) * x[0], (s - 1.0) * x[1], -0.2 * (x[2] - z0) - 0.2 * z0];
                    for a in 0..3 {
                        assert!(
                            (u[3 * p + a] - exact[a]).abs() <= 1e-10,
                            "{law_name}, {label}: body {b}, point {p}: {:?} against {exact:?}",
                            &u[3 * p..3 * p + 3]
                        );
                    }
                }
            }
        }
    }
}
