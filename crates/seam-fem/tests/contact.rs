//! Frictionless contact of two stacked blocks: the contact patch test,
//! separation, initial overlap, and the KKT conditions of every solve.
//!
//! The lower block [0,1]² × [0, ½] (master, E₁ = 1000, ν₁ = 0.3) and the upper
//! block [0,1]² × [½ + δ, 1 + δ] (slave, E₂ = 300, ν₂ = 0.2) are meshed
//! independently (hexahedra, tetrahedra or prisms, non-matching). Rollers hold
//! the planes x = 0 and y = 0 of both blocks and the bottom of the lower one;
//! the upper block is held only by contact, or by a prescribed u_z on its top.
//! All such problems have a homogeneous uniaxial solution, σ = −p e₃⊗e₃:
//!
//! - pressed by a traction p on top: contact pressure p at every slave point,
//!   u = (ν x, ν y, −z) p/E per body plus the rigid shift of the upper one;
//! - with an initial overlap −δ and the top held: the overlap is pushed out,
//!   p = −δ / (½/E₁ + (½ + δ)/E₂) (springs in series).
//!
//! Measured (`cargo test -p seam-fem --test main contact:: -- --nocapture`): see the
//! printed lines; everything asserted to 1e-8 relative.
use seam::Multiplier;
use seam_fem::generate::BlockKind;
use seam_fem::pcg::PcgOptions;
use seam_fem::scene::{bulging_contact, BulgingContact};
use seam_fem::{Solution, SolveOptions, Solver};

const RTOL: f64 = 1e-8;

use crate::common;
use common::stack::Stack;

fn cases() -> Vec<(&'static str, Stack)> {
    vec![
        ("hex 5 | hex 3", Stack::new(5, BlockKind::Hex, 3, BlockKind::Hex, 0.0)),
        ("tet 4 | hex 7", Stack::new(4, BlockKind::Tet, 7, BlockKind::Hex, 0.0)),
        ("hex 3 | prism 5", Stack::new(3, BlockKind::Hex, 5, BlockKind::Prism, 0.0)),
    ]
}

#[test]
fn contact_patch_test_reproduces_the_uniform_pressure() {
    let p = 2.0;
    for multiplier in [Multiplier::Lumped, Multiplier::Dual] {
        for (name, stack) in cases() {
            let s = stack.solve(p, None, multiplier, Solver::Direct);
            let i = s.interfaces[0].contact.as_ref().expect("a contact interface");
            let points: Vec<usize> = (0..i.contact.len()).filter(|&q| i.contact[q]).collect();
            assert_eq!(points.len(), s.interfaces[0].mortar.covered.iter().filter(|&&c| c).count());
            assert!(points.iter().all(|&q| i.active[q]), "{name}: every slave point is in contact");
            let pressure = points.iter().fold(0.0f64, |m, &q| m.max((i.pressure[q] - p).abs())) / p;
            // The upper body floats: its shift follows from the contact, u_z(top of lower) is continuous.
            let u = stack.displacement_error(&s, p, 0.0);
            let force = (s.interfaces[0].force[2] - p).abs() / p;
            println!(
                "{name} {multiplier:?}: pressure {pressure:.1e}, displacement {u:.1e}, force {force:.1e}"
            );
            assert!(pressure <= RTOL, "{name} {multiplier:?}: pressure error {pressure:e}");
            assert!(u <= RTOL, "{name} {multiplier:?}: displacement error {u:e}");
            assert!(
                force <= RTOL,
                "{name} {multiplier:?}: resultant {:?} against the load {p}",
                s.interfaces[0].force
            );
            assert!(i.gap.iter().all(|g| g.abs() <= 1e-12), "{name}: closed gap");
        }
    }
}

#[test]
fn contact_patch_test_with_pcg() {
    let stack = Stack::new(4, BlockKind::Tet, 7, BlockKind::Hex, 0.0);
    let pcg = Solver::Pcg(PcgOptions { rtol: 1e-13, ..Default::default() });
    let s = stack.solve(2.0, None, Multiplier::Lumped, pcg);
    let u = stack.displacement_error(&s, 2.0, 0.0);
    assert!(u <= RTOL, "displacement error {u:e}");
}

#[test]
fn bodies_apart_stay_apart_without_pressure() {
    let stack = Stack::new(5, BlockKind::Hex, 3, BlockKind::Hex, 0.01);
    let s = stack.solve(0.0, Some(-0.005), Multiplier::Lumped, Solver::Direct);
    let i = s.interfaces[0].contact.as_ref().expect("a contact interface");
    assert_eq!(s.report.contact.as_ref().expect("contact").active, 0);
    assert!(i.pressure.iter().all(|&l| l == 0.0));
    assert!(s.interfaces[0].force == [0.0; 3]);
    // Rigid motion of the upper block: the gap closes by 0.005 everywhere.
    let gap_error = (0..i.contact.len())
        .filter(|&q| i.contact[q])
        .fold(0.0f64, |m, q| m.max((i.gap[q] - 0.005).abs()).max((i.initial_gap[q] - 0.01).abs()));
    assert!(gap_error <= 1e-12, "gap error {gap_error:e}");
}

#[test]
fn pressing_beyond_the_gap_closes_it() {
    let (delta, push) = (0.01, -0.03);
    let stack = Stack::new(5, BlockKind::Hex, 3, BlockKind::Hex, delta);
    let s = stack.solve(0.0, Some(push), Multiplier::Lumped, Solver::Direct);
    // Springs in series: the upper top moves by −0.03, the gap takes 0.01.
    let [e1, e2] = stack.materials.map(|m| m.young());
    let p = (-push - delta) / (0.5 / e1 + 0.5 / e2);
    check_uniform_pressure(&s, &stack, p, delta);
}

#[test]
fn initial_overlaps_are_pushed_out() {
    let delta = -0.01;
    for multiplier in [Multiplier::Lumped, Multiplier::Dual] {
        let stack = Stack::new(4, BlockKind::Tet, 7, BlockKind::Hex, delta);
        let s = stack.solve(0.0, Some(0.0), multiplier, Solver::Direct);
        let [e1, e2] = stack.materials.map(|m| m.young());
        let p = -delta / (0.5 / e1 + 0.5 / e2);
        check_uniform_pressure(&s, &stack, p, delta);
    }
}

/// Every slave point active with pressure p, the initial gap δ closed, and the
/// uniaxial displacement with the upper block shifted by the gap.
fn check_uniform_pressure(s: &Solution, stack: &Stack, p: f64, delta: f64) {
    let i = s.interfaces[0].contact.as_ref().expect("a contact interface");
    let points: Vec<usize> = (0..i.contact.len()).filter(|&q| i.contact[q]).collect();
    assert!(points.iter().all(|&q| i.active[q] && i.gap[q].abs() <= 1e-12));
    assert!(points.iter().all(|&q| (i.initial_gap[q] - delta).abs() <= 1e-12));
    let pressure = points.iter().fold(0.0f64, |m, &q| m.max((i.pressure[q] - p).abs())) / p;
    let u = stack.displacement_error(s, p, -delta);
    println!("p = {p:.4}: pressure error {pressure:.1e}, displacement error {u:.1e}");
    assert!(pressure <= RTOL, "pressure error {pressure:e}");
    assert!(u <= RTOL, "displacement error {u:e}");
}

#[test]
fn the_iteration_cap_stops_with_a_clear_message() {
    // Bulges touching at one point: the contact zone needs several steps.
    let problem =
        bulging_contact(&BulgingContact { cells: 8, layers: 4, ..BulgingContact::default() }).unwrap();
    let capped = SolveOptions { max_active_set_steps: 1, ..Default::default() };
    let error = problem.solve(&capped).unwrap_err().to_string();
    assert!(error.contains("did not settle in 1 steps"), "{error}");
    let solved = problem.solve(&SolveOptions::default()).unwrap();
    assert!(
        solved.report.contact.as_ref().expect("contact").steps.len() >= 2
            && solved.report.contact.as_ref().expect("contact").kkt.max() <= RTOL
    );
    // Direct (condensed on the contact normals) and PCG (full system per step) agree.
    let pcg = Solver::Pcg(PcgOptions { rtol: 1e-13, ..Default::default() });
    let other = problem.solve(&SolveOptions { solver: pcg, ..Default::default() }).unwrap();
    let steps = |s: &seam_fem::Solution| s.report.contact.as_ref().expect("contact").steps.clone();
    let (direct, iterative) = (steps(&solved), steps(&other));
    println!("direct {direct:?}\niterative {iterative:?}");
    // PCG's steps solve to 1e-3 until the active set settles (their path may
    // differ near the verge), the last one then to rtol: the same final set.
    let (d, i) = (direct.last().unwrap(), iterative.last().unwrap());
    assert_eq!((d.active, d.added, d.removed), (i.active, i.added, i.removed), "the same final active set");
    assert!(i.full_tolerance && direct.iter().all(|s| s.full_tolerance));
    assert!(
        iterative.iter().any(|s| !s.full_tolerance) && iterative.len() <= direct.len() + 1,
        "{iterative:?}"
    );
    let (a, b) = (
        &solved.interfaces[0].contact.as_ref().expect("contact").pressure,
        &other.interfaces[0].contact.as_ref().expect("contact").pressure,
    );
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    println!("direct vs PCG pressure: {:.1e} of the peak", diff / scale);
    assert!(diff <= 1e-8 * scale, "direct and PCG pressures differ by {diff:e} (scale {scale:e})");
}

#[test]
fn contact_solutions_are_identical_on_one_and_two_threads() {
    let problem =
        bulging_contact(&BulgingContact { cells: 8, layers: 4, ..BulgingContact::default() }).unwrap();
    let solve = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| problem.solve(&SolveOptions::default()).unwrap())
    };
    let (one, two) = (solve(1), solve(2));
    assert_eq!(one.displacement, two.displacement);
    assert_eq!(
        one.interfaces[0].contact.as_ref().expect("contact").pressure,
        two.interfaces[0].contact.as_ref().expect("contact").pressure
    );
}
