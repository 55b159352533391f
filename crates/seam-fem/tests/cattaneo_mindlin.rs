//! Cattaneo–Mindlin ([`seam_fem::scene::cattaneo_mindlin`]): the Hertz
//! indenter pressed by P, then pushed sideways by Q = 0.5 μP (μ = 0.3,
//! equal materials), against c = a (1 − Q/μP)^{1/3} and q(r).

use seam_fem::scene::{cattaneo_mindlin, CattaneoMindlin, Hertz, PartialSlip};
use seam_fem::{solve_steps, SolveOptions};

/// What a run gives: the reading at the end, the semismooth Newton
/// residuals of every load step and the unknowns. (Larger meshes: `cargo
/// run --release -p seam-fem --example friction_bench`.)
struct Run {
    slip: PartialSlip,
    residuals: Vec<Vec<f64>>,
    dofs: usize,
}

fn run(p: &CattaneoMindlin) -> Run {
    let problem = cattaneo_mindlin(p).unwrap();
    let mut residuals = Vec::new();
    let mut last = None;
    for step in solve_steps(&problem, &SolveOptions::default()) {
        let (t, s) = step.unwrap();
        let r: Vec<f64> = s.report.contact.as_ref().unwrap().steps.iter().map(|s| s.residual).collect();
        println!(
            "  t = {t:.3}: {} iterations {:?}",
            r.len(),
            r.iter().map(|x| format!("{x:.1e}")).collect::<Vec<_>>()
        );
        residuals.push(r);
        last = Some(s);
    }
    let s = last.unwrap();
    let slip = p.measure(&problem, &s);
    println!(
        "n = {}: {} dofs; stick {} slip {}; c {:+.2} %, a {:+.2} %, q L2 {:.2} %",
        p.hertz.fine_cells,
        s.report.dofs,
        slip.stick,
        slip.slip,
        100.0 * (slip.stick_radius / p.stick_radius() - 1.0),
        100.0 * (slip.contact_radius / p.hertz.contact_radius - 1.0),
        100.0 * slip.traction_error
    );
    Run { slip, residuals, dofs: s.report.dofs }
}

fn at(fine_cells: usize, shear_steps: usize) -> CattaneoMindlin {
    let p = CattaneoMindlin::default();
    CattaneoMindlin { hertz: Hertz { fine_cells, ..p.hertz }, shear_steps, ..p }
}

/// Superlinear convergence: over the residuals above round-off (1e-10),
/// the last contraction factor below 0.05 and below the one before; or
/// exact at the first step (no set changed: one linear solve).
fn superlinear(r: &[f64]) -> bool {
    if let [_, last] = r {
        return *last <= 1e-10;
    }
    let r: Vec<f64> = r.iter().copied().filter(|&r| r > 1e-10).collect();
    let rate: Vec<f64> = r.windows(2).map(|w| w[1] / w[0]).collect();
    matches!(rate.as_slice(), [.., before, last] if last < before && *last < 0.05)
}

/// A coarse mesh (rings 0.18a apart): a stick zone inside a slip annulus,
/// the traction within Coulomb's cone and equal to μp where it slips, the
/// stick radius near Cattaneo–Mindlin's, Newton superlinear in every step.
#[test]
fn a_stick_zone_inside_a_slip_annulus() {
    let p = at(3, 2);
    let run = run(&p);
    let s = &run.slip;
    assert!(s.stick > 0 && s.slip > 0, "stick {} slip {}", s.stick, s.slip);
    let a = p.hertz.contact_radius;
    for x in &s.axis {
        let bound = p.friction * x.pressure;
        assert!(x.traction.abs() <= bound * (1.0 + 1e-9) + 1e-12, "{x:?}");
        // Slipping along Q, at the cone (t_y, zero in the limit by symmetry, is not shown).
        if !x.stick && x.pressure > 0.0 {
            assert!(x.traction >= 0.99 * bound, "slipping against Q: {x:?}");
        }
        // The centre sticks, the rim slips.
        if x.x.abs() < 0.5 * a {
            assert!(x.stick, "{x:?}");
        }
    }
    let c = s.stick_radius / p.stick_radius() - 1.0;
    assert!(c.abs() < 0.08, "stick radius {:+.2} %", 100.0 * c);
    // Pressing finds its active set in finitely many steps (the last
    // residual at round-off); the shear steps converge superlinearly.
    assert!(run.residuals[0].last().is_some_and(|&r| r < 1e-10), "{:?}", run.residuals[0]);
    for r in &run.residuals[1..] {
        assert!(superlinear(r), "{r:?}");
    }
    assert!(run.dofs > 0);
}

/// The accuracy under refinement (about 50 s): at the example's mesh (n = 8,
/// the rings 0.069a apart) the stick radius within 3 % and the tangential
/// traction within 5 % in L2 of Cattaneo–Mindlin's, and both errors falling
/// under refinement (n = 4, 6, 8, four shear steps as the example).
#[test]
fn the_partial_slip_converges_to_cattaneo_mindlin() {
    let errors: Vec<(f64, f64)> = [4, 6, 8]
        .into_iter()
        .map(|n| {
            let p = at(n, 4);
            let s = run(&p).slip;
            ((s.stick_radius / p.stick_radius() - 1.0).abs(), s.traction_error)
        })
        .collect();
    for w in errors.windows(2) {
        assert!(w[1].0 < w[0].0 && w[1].1 < w[0].1, "the errors (|c|, q) do not fall: {errors:?}");
    }
    let (c, q) = errors[2];
    assert!(c < 0.03 && q < 0.05, "at the example's mesh: c {:.2} %, q {:.2} %", 100.0 * c, 100.0 * q);
}

/// The iteration cap stops frictional contact with a line that says what
/// still changed.
#[test]
fn the_iteration_cap_stops_friction_with_a_clear_message() {
    let problem = cattaneo_mindlin(&at(3, 1)).unwrap();
    let capped = SolveOptions { max_active_set_steps: 2, ..SolveOptions::default() };
    let error = solve_steps(&problem, &capped).find_map(Result::err).expect("capped").to_string();
    assert!(
        error.starts_with("frictional contact: semismooth Newton did not converge in 2 steps (last step: ")
            && error.contains("relative update"),
        "{error}"
    );
}
