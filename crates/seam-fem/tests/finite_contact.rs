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
pub(crate) fn stack(
    law: Law,
    lower: (BlockKind, usize),
    upper: (BlockKind, usize),
    press: f64,
    steps: usize,
) -> Problem {
    stacked(Coupling::Contact, law, (lower, upper), press, steps)
}

/// [`stack`] with the blocks coupled by `kind`.
fn stacked(
    kind: Coupling,
    law: Law,
    (lower, upper): ((BlockKind, usize), (BlockKind, usize)),
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
            kind,
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
    solve_with(problem, &SolveOptions::default())
}

pub(crate) fn solve_with(problem: &Problem, options: &SolveOptions) -> Vec<(f64, Solution)> {
    solve_steps(problem, options).collect::<Result<_, _>>().unwrap_or_else(|e| panic!("{e}"))
}

/// Newton from each step's start, not from the last steps' extrapolation
/// (which leaves the later steps of these monotone loadings one or two
/// iterations, too few to measure an order).
fn unextrapolated() -> SolveOptions {
    let mut options = SolveOptions::default();
    options.newton.extrapolate = false;
    options
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
            assert_compressed(&format!("{law_name}, {label}"), &problem, solution, (0, 1), law);
        }
    }
}

/// The stretch s across and the contact pressure −σ_zz of uniaxial stress
/// at the stretch 0.8 along z for `law`.
fn compressed(law: Law) -> (f64, f64) {
    let hyper = law.hyperelastic(&material()).unwrap();
    let s = lateral_stretch(&hyper, 0.8);
    let pressure = -analytic_cauchy(&hyper, &[[0.8, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]])[0][0];
    assert!(pressure > 0.0);
    (s, pressure)
}

/// Every body of `problem` in the uniaxial state `compressed(law)` (z = 0
/// held): displacements ((s − 1) x, (s − 1) y, −0.2 z) to 1e-10; at least
/// `points` contact points on contact interface `i`, each active with the
/// pressure to 1e-8.
pub(crate) fn assert_compressed(
    label: &str,
    problem: &Problem,
    solution: &Solution,
    (i, points): (usize, usize),
    law: Law,
) {
    let (s, pressure) = compressed(law);
    let c = solution.interfaces[i].contact.as_ref().unwrap();
    let contact: Vec<usize> = (0..c.contact.len()).filter(|&p| c.contact[p]).collect();
    assert!(contact.len() >= points, "{label}: {} contact points", contact.len());
    for &p in &contact {
        assert!(
            c.active[p] && (c.pressure[p] - pressure).abs() <= 1e-8 * pressure,
            "{label}: pressure {} at {p} (active {}), expected {pressure}",
            c.pressure[p],
            c.active[p]
        );
    }
    for (b, body) in problem.bodies.iter().enumerate() {
        let u = &solution.displacement[b];
        for (p, x) in body.mesh.points().iter().enumerate() {
            let exact = [(s - 1.0) * x[0], (s - 1.0) * x[1], -0.2 * x[2]];
            for a in 0..3 {
                assert!(
                    (u[3 * p + a] - exact[a]).abs() <= 1e-10,
                    "{label}: body {b}, point {p}: {:?} against {exact:?}",
                    &u[3 * p..3 * p + 3]
                );
            }
        }
    }
}

/// Large sliding: a Tet4 block (1 × 1 × 0.5, 4 × 4 × 2 cells) pressed by
/// 0.05 onto a rigid Hex8 base (4 × 1.5 × 0.5, 16 × 6 × 2 cells, every point
/// held, so that its surface stays flat) over the first 10 % of the
/// pseudo-time, then dragged along it by twice its length (its top held),
/// with Coulomb's `friction`; the pairs change at every one of 21 load
/// steps. Returns the solution of each step.
fn dragged_block(friction: f64) -> Vec<(f64, Solution)> {
    use seam::MortarOptions;
    use seam_fem::generate::{block, Grid, Side};
    use seam_fem::{Amplitude, ProblemBody};
    let surfaces = |mesh: &seam::VolumeMesh, grid: Grid| {
        [Side::ZMin, Side::ZMax]
            .map(|side| (format!("{side:?}"), grid.side_faces(mesh, side).unwrap()))
            .to_vec()
    };
    let base = block(16, 6, 2, |x, y, z| [4.0 * x - 0.5, 1.5 * y - 0.25, 0.5 * z], BlockKind::Hex);
    let slider = block(4, 4, 2, |x, y, z| [x, y, 0.5 + 0.5 * z], BlockKind::Tet);
    let law = Law::NeoHookean;
    let bodies = vec![
        ProblemBody {
            law,
            ..ProblemBody::new("base", base.clone(), material(), surfaces(&base, Grid::new(16, 6, 2)))
        },
        ProblemBody {
            law,
            ..ProblemBody::new("slider", slider.clone(), material(), surfaces(&slider, Grid::new(4, 4, 2)))
        },
    ];
    let press = Amplitude::new(vec![[0.0, 0.0], [0.1, 1.0], [1.0, 1.0]]).unwrap();
    let drag = Amplitude::new(vec![[0.0, 0.0], [0.1, 0.0], [1.0, 1.0]]).unwrap();
    let top = |values, amplitude| Support { amplitude, ..Support::new(id(1, 1), values) };
    let problem = Problem {
        bodies,
        interfaces: vec![ProblemInterface {
            master: id(0, 1),
            slave: id(1, 0),
            options: MortarOptions { multiplier: seam::Multiplier::Dual, ..Default::default() },
            kind: Coupling::Contact,
            friction,
        }],
        supports: vec![
            Support::new(id(0, 0), [Some(0.0); 3]),
            Support::new(id(0, 1), [Some(0.0); 3]),
            top([None, None, Some(-0.05)], press),
            top([Some(2.0), Some(0.0), None], drag),
        ],
        steps: LoadSteps::equal(21).unwrap(),
        ..Problem::default()
    };
    let steps = solve_all(&problem);
    let mut iterations = 0;
    for (t, step) in &steps {
        let i = &step.interfaces[0];
        let c = i.contact.as_ref().unwrap();
        let newton = step.report.newton.as_ref().unwrap();
        iterations += newton.residuals.len();
        let count = |s: &[bool]| s.iter().filter(|&&b| b).count();
        println!(
            "μ = {friction}, t = {t:.3}: F = {:?}, {} active, {} stick, residuals {:?}",
            i.force,
            count(&c.active),
            count(&c.stick),
            newton.residuals
        );
        assert!(i.force[2] > 0.0, "t = {t}: the master pushes the slave up: {:?}", i.force);
        // At convergence no point is between active and inactive: active
        // points have zero gap and positive pressure, the others zero
        // pressure and an open gap.
        for p in (0..c.contact.len()).filter(|&p| c.contact[p]) {
            match c.active[p] {
                true => assert!(c.pressure[p] > 0.0 && c.gap[p].abs() <= 1e-9, "t = {t}, point {p}"),
                false => assert!(c.pressure[p] == 0.0 && c.gap[p] >= -1e-9, "t = {t}, point {p}"),
            }
        }
    }
    // The block's bottom reached x + 2, less its shear under friction.
    let u = &steps.last().unwrap().1.displacement[1];
    assert!((u[0] - 2.0).abs() < 0.1, "{}", u[0]);
    println!("μ = {friction}: {iterations} Newton iterations over {} steps", steps.len());
    steps
}

/// The dragged block ([`dragged_block`]) without friction: the contact
/// force is normal, F_x = F_y = 0 to 1e-8 of F_z at every step.
#[test]
fn a_block_dragged_twice_its_length_slides_without_tangential_force() {
    for (t, step) in dragged_block(0.0) {
        let f = step.interfaces[0].force;
        assert!(f[0].abs() <= 1e-8 * f[2] && f[1].abs() <= 1e-8 * f[2], "t = {t}: {f:?}");
    }
}

/// The dragged block ([`dragged_block`]) with μ = 0.3: while it slides (from
/// the fourth step, every point slipping) the master resists with
/// F_x = −μ F_z to 0.5 % (F_y, left by the sticking of the press phase,
/// relaxes below 1 % of F_z), and each slave point's slip increment is along
/// +x; the accumulated slip at the end is the drag less the block's elastic
/// shear, within 5 % of 2. Newton's order in slip is at least 1.8.
#[test]
fn a_block_dragged_with_friction_carries_mu_times_its_press() {
    let mu = 0.3;
    let steps = dragged_block(mu);
    // Every point slips: Newton's order with the statuses settled, the slope
    // of log r_{k+1} against log r_k over all steps' iterations with
    // 10⁻¹³ < r_{k+1} < r_k ≤ 10⁻³ (a step cut in halves lists both parts'
    // iterations). From the extrapolated starts (the default) steady sliding
    // takes one or two iterations and the slope, 2.10, comes from the three
    // iterations of the steps where the slip sets in; without extrapolation
    // (`NewtonOptions::extrapolate`) it is 1.76 over 28 (docs/defects.md).
    let mut pairs = Vec::new();
    for (t, step) in steps.iter().skip(3) {
        let i = &step.interfaces[0];
        let (f, c) = (i.force, i.contact.as_ref().unwrap());
        assert!((f[0] + mu * f[2]).abs() <= 0.005 * mu * f[2], "t = {t}: F_x / F_z = {}", f[0] / f[2]);
        assert!(f[1].abs() <= 0.01 * f[2], "t = {t}: {f:?}");
        for p in (0..c.active.len()).filter(|&p| c.active[p]) {
            assert!(
                !c.stick[p] && c.slip_increment[p][0] > 0.0,
                "t = {t}, point {p}: {:?}",
                c.slip_increment[p]
            );
        }
        let r = &step.report.newton.as_ref().unwrap().residuals;
        pairs.extend(
            r.windows(2)
                .filter(|w| w[0] <= 1e-3 && w[1] > 1e-13 && w[1] < w[0])
                .map(|w| (w[0].ln(), w[1].ln())),
        );
    }
    let n = pairs.len() as f64;
    let (mx, my) = (pairs.iter().map(|p| p.0).sum::<f64>() / n, pairs.iter().map(|p| p.1).sum::<f64>() / n);
    let slope = pairs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
        / pairs.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>();
    println!("order {slope:.2} from {} iterations", pairs.len());
    assert!(pairs.len() >= 3 && slope >= 1.8, "order {slope} from {} iterations", pairs.len());
    let c = steps.last().unwrap().1.interfaces[0].contact.clone().unwrap();
    let slip =
        (0..c.active.len()).filter(|&p| c.active[p]).map(|p| c.slip[p][0]).fold(f64::INFINITY, f64::min);
    assert!((slip - 2.0).abs() < 0.1, "accumulated slip {slip}");
}

/// The order of convergence log(r₃/r₂) / log(r₂/r₁) from the last three
/// residuals above round-off (10⁻¹³) of which the first is at most 0.02
/// (the asymptotic range); `None` without three such.
fn order(residuals: &[f64]) -> Option<f64> {
    let above: Vec<f64> = residuals.iter().copied().filter(|&r| r > 1e-13).collect();
    let &[r1, r2, r3] = above.get(above.len().checked_sub(3)?..)? else { unreachable!() };
    (r1 <= 0.02).then(|| (r3 / r2).ln() / (r2 / r1).ln())
}

/// Newton's last iterations converge at order ≥ 1.8 (measured from the
/// residuals of every step that takes three or more) in glue and in
/// frictionless contact with its active set settled (the steps after the
/// first, where the whole interface is already in contact): the
/// linearisation is consistent.
#[test]
fn newton_converges_quadratically_in_glue_and_contact() {
    // Glue in one step of 40 % (Newton's predictor leaves smaller steps two
    // iterations above round-off), contact in four of 5 %, the first of
    // which settles the active set (with friction: every point sticks, the
    // blocks of one material expanding alike).
    let cases = [
        ("glue", Coupling::Glue, 0.0, 0.8, 1, 0),
        ("contact", Coupling::Contact, 0.0, 0.4, 4, 1),
        ("contact, μ = 0.3", Coupling::Contact, 0.3, 0.4, 4, 1),
    ];
    for (label, kind, friction, press, n, skip) in cases {
        let mut problem =
            stacked(kind, Law::NeoHookean, ((BlockKind::Hex, 3), (BlockKind::Tet, 2)), press, n);
        problem.interfaces[0].friction = friction;
        let steps = solve_with(&problem, &unextrapolated());
        let mut measured = 0;
        for (t, step) in steps.iter().skip(skip) {
            let residuals = &step.report.newton.as_ref().unwrap().residuals;
            println!("{label}, t = {t}: {residuals:?}");
            if let Some(q) = order(residuals) {
                println!("{label}, t = {t}: order {q:.2}");
                assert!(q >= 1.8, "{label}, t = {t}: order {q} from {residuals:?}");
                measured += 1;
            }
        }
        assert_eq!(measured, n - skip, "{label}: a step took too few iterations in the asymptotic range");
    }
}

/// Small loads: a Tet4 punch (0.6 × 0.6 × 0.5, its top clamped and pressed
/// by 10⁻⁶) on a deformable Hex8 base, a non-homogeneous contact, gives the
/// small-strain contact's displacements (`Law::Linear`, the reference
/// configuration's gaps and normals) to 1e-5 of the largest, for both
/// laws: the finite-deformation contact linearises to today's.
#[test]
fn a_small_load_gives_the_small_strain_contact() {
    use seam_fem::generate::{block, Grid, Side};
    use seam_fem::ProblemBody;
    let surfaces = |mesh: &seam::VolumeMesh, grid: Grid| {
        [Side::ZMin, Side::ZMax]
            .map(|side| (format!("{side:?}"), grid.side_faces(mesh, side).unwrap()))
            .to_vec()
    };
    let base = block(4, 4, 2, |x, y, z| [x, y, 0.5 * z], BlockKind::Hex);
    let punch = block(3, 3, 2, |x, y, z| [0.2 + 0.6 * x, 0.2 + 0.6 * y, 0.5 + 0.5 * z], BlockKind::Tet);
    let problem = |law| Problem {
        bodies: vec![
            ProblemBody {
                law,
                ..ProblemBody::new("base", base.clone(), material(), surfaces(&base, Grid::new(4, 4, 2)))
            },
            ProblemBody {
                law,
                ..ProblemBody::new("punch", punch.clone(), material(), surfaces(&punch, Grid::new(3, 3, 2)))
            },
        ],
        interfaces: vec![ProblemInterface {
            master: id(0, 1),
            slave: id(1, 0),
            options: seam::MortarOptions { multiplier: seam::Multiplier::Dual, ..Default::default() },
            kind: Coupling::Contact,
            friction: 0.0,
        }],
        supports: vec![
            Support::new(id(0, 0), [Some(0.0); 3]),
            Support::new(id(1, 1), [Some(0.0), Some(0.0), Some(-1e-6)]),
        ],
        ..Problem::default()
    };
    let linear = seam_fem::solve(&problem(Law::Linear), &SolveOptions::default()).unwrap();
    for law in [Law::NeoHookean, Law::SaintVenantKirchhoff] {
        let finite = seam_fem::solve(&problem(law), &SolveOptions::default()).unwrap();
        let largest = linear.displacement.iter().flatten().fold(0.0f64, |a, &b| a.max(b.abs()));
        let worst = linear
            .displacement
            .iter()
            .flatten()
            .zip(finite.displacement.iter().flatten())
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        println!("{law:?}: {worst:.2e} of {largest:.2e}");
        assert!(worst <= 1e-5 * largest, "{law:?}: {worst:e} of {largest:e}");
        let (l, f) = (
            &linear.interfaces[0].contact.as_ref().unwrap(),
            &finite.interfaces[0].contact.as_ref().unwrap(),
        );
        let active = |c: &seam_fem::ContactFields| c.active.clone();
        assert_eq!(active(l), active(f), "{law:?}: the same active set");
    }
}

/// The ironing scene ([`seam_fem::scene::ironing`], coarse: 10 steps) with
/// μ = 0.3: pressed and slid three times its width. Coulomb's law holds point
/// by point at every step: the tangential traction equals μ p at slipping
/// points and is at most μ p at sticking ones (to 1e-8 of the largest p),
/// inactive points carry nothing; once the indenter slides, the contact force
/// opposes the slide (F_x < 0).
#[test]
fn ironing_presses_and_slides_a_hyperelastic_indenter() {
    use seam_fem::scene::{ironing, Ironing};
    for mu in [0.3] {
        let params = Ironing { cells: 2, indenter_cells: 4, friction: mu, steps: 10, ..Ironing::default() };
        let problem = ironing(&params).unwrap();
        let steps = solve_all(&problem);
        for (t, step) in &steps {
            let i = &step.interfaces[0];
            let c = i.contact.as_ref().unwrap();
            let active = c.active.iter().filter(|&&a| a).count();
            let newton = step.report.newton.as_ref().unwrap();
            println!(
                "μ = {mu}, t = {t:.2}: F = {:?}, {active} active, {} iterations in {} parts",
                i.force,
                newton.residuals.len(),
                newton.substeps
            );
            assert!(active > 0 && i.force[2] > 0.0, "t = {t}");
            let largest = c.pressure.iter().fold(0.0f64, |a, &b| a.max(b));
            for p in (0..c.active.len()).filter(|&p| c.contact[p]) {
                let tangential = seam::vec3::norm(i.tangential_traction[p]);
                let bound = mu * c.pressure[p];
                let tol = 1e-8 * largest;
                match (c.active[p], c.stick[p]) {
                    (false, _) => assert!(
                        tangential <= tol && c.pressure[p].abs() <= tol,
                        "t = {t}, point {p}: {tangential}, {}, gap {}",
                        c.pressure[p],
                        c.gap[p]
                    ),
                    (true, true) => {
                        assert!(tangential <= bound + tol, "t = {t}, point {p}: {tangential} > {bound}")
                    }
                    (true, false) => assert!(
                        (tangential - bound).abs() <= tol,
                        "t = {t}, point {p}: {tangential} against {bound}"
                    ),
                }
            }
            if mu > 0.0 && *t > 0.25 {
                assert!(i.force[0] < 0.0, "t = {t}: {:?}", i.force);
            }
        }
    }
}

/// A load step too large for Newton's iteration cap (a Tet10 block
/// stretched to 1.5 in one step, at most 2 iterations) is cut in halves
/// until each part converges: the report counts the parts and lists the
/// iterations of all of them, and the state is the homogeneous stretch to
/// 1e-10; with no cut left (`MAX_CUTS`) the failure is Newton's.
#[test]
fn a_load_step_newton_cannot_take_is_cut_in_halves() {
    use crate::hyperelastic::slab;
    let roller = |s, k: usize, v: f64| Support::new(id(0, s), std::array::from_fn(|c| (c == k).then_some(v)));
    let problem = Problem {
        bodies: vec![slab("one", (2, 2), 0.0, BlockKind::Tet, Some(false), Law::NeoHookean)],
        supports: vec![roller(0, 0, 0.0), roller(1, 1, 0.0), roller(2, 2, 0.0), roller(3, 2, 0.5)],
        ..Problem::default()
    };
    let mut options = SolveOptions::default();
    options.newton.max_iterations = 2;
    let solution = seam_fem::solve(&problem, &options).unwrap();
    let newton = solution.report.newton.as_ref().unwrap();
    println!("{} parts, residuals {:?}", newton.substeps, newton.residuals);
    assert!(newton.substeps >= 2 && newton.residuals.len() > 2, "{newton:?}");
    assert_eq!(solution.report.iterations, newton.residuals.len());
    let hyper = Law::NeoHookean.hyperelastic(&material()).unwrap();
    let s = lateral_stretch(&hyper, 1.5);
    for (p, x) in problem.bodies[0].mesh.points().iter().enumerate() {
        let exact = [(s - 1.0) * x[0], (s - 1.0) * x[1], 0.5 * x[2]];
        for a in 0..3 {
            assert!((solution.displacement[0][3 * p + a] - exact[a]).abs() <= 1e-10, "point {p}");
        }
    }
    options.newton.max_iterations = 1;
    let error = seam_fem::solve(&problem, &options).unwrap_err().to_string();
    assert!(error.contains("Newton did not converge"), "{error}");
}

/// Glue and contact in one finite-deformation problem: three neo-Hookean
/// blocks stacked ([0, 1]² × [0, 3]), the lowest (Hex8, 3 across) glued to
/// the middle one (Tet4, 2 across; dual multipliers, eliminated), which
/// touches the top one (Hex8, 4 across) in frictionless contact; rollers on
/// x = 0, y = 0 and the bottom, the top pressed down by 0.6 (20 %) over four
/// steps. Every block is in the uniaxial state of stretch 0.8: displacements
/// to 1e-10, the contact pressure −σ_zz at every contact point to 1e-8.
#[test]
fn glue_and_contact_in_one_finite_deformation_problem() {
    glue_and_contact_with(&SolveOptions::default());
}

/// [`glue_and_contact_in_one_finite_deformation_problem`] by the solver of
/// `options`; returns the Newton iterations of each step.
pub(crate) fn glue_and_contact_with(options: &SolveOptions) -> Vec<usize> {
    let law = Law::NeoHookean;
    let (s, pressure) = compressed(law);
    let interface = |master: usize, kind| ProblemInterface {
        master: id(master, 3),
        slave: id(master + 1, 2),
        options: seam::MortarOptions { multiplier: seam::Multiplier::Dual, ..Default::default() },
        kind,
        friction: 0.0,
    };
    let mut supports = vec![roller(0, 2, 2, 0.0), roller(2, 3, 2, -0.6)];
    for b in 0..3 {
        supports.extend([roller(b, 0, 0, 0.0), roller(b, 1, 1, 0.0)]);
    }
    let problem = Problem {
        bodies: vec![
            slab("bottom", (3, 2), 0.0, BlockKind::Hex, None, law),
            slab("middle", (2, 2), 1.0, BlockKind::Tet, None, law),
            slab("top", (4, 2), 2.0, BlockKind::Hex, None, law),
        ],
        interfaces: vec![interface(0, Coupling::Glue), interface(1, Coupling::Contact)],
        supports,
        steps: LoadSteps::equal(4).unwrap(),
        ..Problem::default()
    };
    let steps = solve_with(&problem, options);
    let solution = &steps.last().unwrap().1;
    assert_compressed("glue and contact", &problem, solution, (1, 1), law);
    // The glue's traction per reference area: s² σ_zz.
    let glue = &solution.interfaces[0];
    for (p, t) in glue.traction.iter().enumerate().filter(|(p, _)| glue.constrained[*p]) {
        assert!((t[2] - s * s * pressure).abs() <= 1e-8 * pressure, "glue point {p}: {t:?}");
    }
    steps.iter().map(|(_, s)| s.report.newton.as_ref().unwrap().residuals.len()).collect()
}

/// The contact patch test of second-order cells: Hex27 (2 across) under
/// Tet10 (2 across; Tri6 slave faces, dual multipliers in Popp's
/// transformed basis), neo-Hookean, 20 % over four steps: the pressure
/// −σ_zz at every contact point to 1e-8, the displacements to 1e-10.
#[test]
fn second_order_contact_patch_test_under_20_percent_compression() {
    let law = Law::NeoHookean;
    let mut problem = stack(law, (BlockKind::Hex, 2), (BlockKind::Tet, 2), 0.4, 4);
    problem.bodies = vec![
        slab("lower", (2, 2), 0.0, BlockKind::Hex, Some(true), law),
        slab("upper", (2, 2), 1.0, BlockKind::Tet, Some(false), law),
    ];
    let steps = solve_all(&problem);
    assert_compressed("Hex27 | Tet10", &problem, &steps.last().unwrap().1, (0, 25), law);
}
