//! The PETSc solver (`Solver::Petsc`, cargo feature `petsc`; `cargo test -p
//! seam-fem --features petsc --test main petsc::`): the glued and contact patch
//! tests, the glued convergence study and Hertz give the direct solver's
//! answers to the solver tolerance, and multigrid keeps the iterations
//! bounded under refinement.
//!
//! Tolerances: the KSP stops at rtol = 1e-12 (1e-13 for the patch tests) in
//! its preconditioned norm; the solutions then agree with the direct ones to
//! 1e-9 relative (measured: see the printed lines).
use crate::common;

use common::hertz::solve_scene_with;
use common::shell::{level, Sides};
use common::stack::Stack;
use common::{crossline_patch_error, rollers_patch_error};
use seam::Multiplier;
use seam_fem::generate::BlockKind;
use seam_fem::petsc::{initialize_petsc, PetscOptions};
use seam_fem::scene::Hertz;
use seam_fem::{SolveOptions, Solver};

fn petsc(rtol: f64) -> Solver {
    initialize_petsc("").expect("PETSc starts");
    Solver::Petsc(PetscOptions { rtol, ..PetscOptions::default() })
}

/// The rollers and crossline cases of `glue_supports.rs`: dual multipliers
/// (the reduced system, or the saddle point at the crossline) and standard
/// ones (the saddle point; lumped multipliers do not pass patch tests, I4):
/// the affine field to 1e-10.
#[test]
fn glued_patch_tests() {
    use BlockKind::*;
    for multiplier in [Multiplier::Dual, Multiplier::Standard] {
        let variant = (multiplier, petsc(1e-14));
        for (m, s) in [(([4, 3, 2], Hex), ([3, 5, 2], Tet)), (([3, 4, 2], Tet), ([5, 3, 2], Hex))] {
            let (e, method, label) = rollers_patch_error(m, s, 0.2, variant);
            assert!(e <= 1e-10, "{label} {multiplier:?}: error {e:.3e}");
            assert!(method.contains("PETSc"), "{method}");
        }
        let (e, method, label) = crossline_patch_error([Hex, Tet, Hex], variant);
        assert!(e <= 1e-10, "{label} {multiplier:?}: error {e:.3e}");
        assert!(method.contains("saddle point"), "{method}");
    }
}

/// Dual multipliers on a Tet10 slave in the enriched slave space (the ties
/// as eliminated rows of the reduced system): uniaxial tension exact.
#[test]
fn glued_enriched_slave_space() {
    let (problem, exact) = crate::glue::enriched_tension();
    let options = SolveOptions { solver: petsc(1e-14), ..SolveOptions::default() };
    let solution = problem.solve(&options).unwrap();
    let e = crate::glue::enriched_tension_error(&problem, &solution, exact);
    println!("{}: error {e:.1e}", solution.report.method);
    assert!(e < 1e-10, "error {e:e}");
    assert!(solution.report.method.contains("PETSc"), "{}", solution.report.method);
}

/// Glue and contact in one problem (`mixed.rs`): contact on the rotated
/// system after eliminating dual glue, or a saddle point per active-set step
/// with standard glue; the uniaxial solution to 1e-10.
#[test]
fn glue_and_contact_in_one_problem() {
    let stack = common::mixed::Stack::new([BlockKind::Hex, BlockKind::Tet, BlockKind::Hex]);
    for glue in [Multiplier::Dual, Multiplier::Standard] {
        let s = stack.solve(Multiplier::Lumped, glue, petsc(1e-13)).unwrap();
        let e = stack.error(&s);
        println!("glue {glue:?}: {} — error {e:.1e}", s.report.method);
        assert!(e <= 1e-10, "glue {glue:?}: error {e:.3e}");
        assert!(s.report.petsc.as_ref().is_some_and(|p| !p.solves.is_empty()));
    }
}

/// The contact patch test of `contact.rs`: the uniform pressure and the
/// uniaxial displacement to 1e-8, each active-set step a warm-started KSP
/// (the settling one two: to 1e-3, then to rtol).
#[test]
fn contact_patch_test() {
    for multiplier in [Multiplier::Lumped, Multiplier::Dual] {
        let stack = Stack::new(4, BlockKind::Tet, 7, BlockKind::Hex, 0.0);
        let s = stack.solve(2.0, None, multiplier, petsc(1e-13));
        let u = stack.displacement_error(&s, 2.0, 0.0);
        assert!(u <= 1e-8, "{multiplier:?}: displacement error {u:e}");
        let report = s.report.petsc.as_ref().expect("a PETSc report");
        // One KSP solve per active-set step, and one more: the step whose solve
        // to 1e-3 left the active set as it was goes on to rtol.
        let steps = &s.report.contact.as_ref().expect("contact").steps;
        assert_eq!(report.solves.len(), steps.len() + 1, "one KSP solve per active-set step, one to refine");
        let linear: usize = steps.iter().map(|s| s.linear_iterations).sum();
        assert_eq!(linear, report.solves.iter().map(|k| k.iterations).sum::<usize>());
        assert!(report.solves.iter().all(|k| k.reason.starts_with("CONVERGED")), "{report:?}");
        assert_eq!((report.ksp_type.as_str(), report.pc_type.as_str()), ("cg", "gamg"));
    }
}

/// The glued convergence study (`glue_convergence.rs`, dual, h_s/h_m = 4):
/// the errors against the manufactured solution equal the direct solver's
/// to 1e-6 of their size at every level (so the rates are the same).
#[test]
fn glue_convergence_case_gives_the_direct_errors() {
    for n in [3, 4, 6] {
        let (direct, _) = level(n, 4 * n, Multiplier::Dual, Sides::Loaded, Solver::Direct);
        let (iterative, _) = level(n, 4 * n, Multiplier::Dual, Sides::Loaded, petsc(1e-12));
        for (name, a, b) in [
            ("L2", direct.l2, iterative.l2),
            ("H1", direct.h1, iterative.h1),
            ("energy", direct.energy, iterative.energy),
        ] {
            println!("n = {n}: {name} error {a:.6e} (direct) {b:.6e} (PETSc)");
            assert!((a - b).abs() <= 1e-6 * a, "n = {n}: {name} error {b:e} against {a:e}");
        }
    }
}

/// Hertz (first-order hexahedra, n = 4, dual): PETSc's solution is the
/// direct one to 1e-9 relative, so p₀ and a are the same.
#[test]
fn hertz_gives_the_direct_answer() {
    let p = Hertz { fine_cells: 4, multiplier: Multiplier::Dual, ..Hertz::default() };
    let (direct, _, d) = solve_scene_with("Hertz n = 4, direct", &p, &SolveOptions::default());
    let options = SolveOptions { solver: petsc(1e-12), ..SolveOptions::default() };
    let (iterative, _, s) = solve_scene_with("Hertz n = 4, PETSc", &p, &options);
    let scale = d.displacement.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let difference = d
        .displacement
        .iter()
        .flatten()
        .zip(s.displacement.iter().flatten())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    println!("Hertz: max |u_petsc − u_direct| / max |u| = {:.1e}", difference / scale);
    assert!(difference <= 1e-9 * scale, "{:e}", difference / scale);
    assert!((direct.p0 - iterative.p0).abs() <= 1e-8 * direct.p0.abs(), "{} vs {}", iterative.p0, direct.p0);
    assert_eq!(direct.a, iterative.a);
}

/// Multigrid works: the warped-glue problem (dual multipliers, h_s/h_m = 2)
/// at three refinements, h halved each time (7 620, 53 466 and 399 822
/// unknowns), needs at most 1.3 times the iterations of the level before
/// with PETSc's default GAMG: measured 42, 53, 66 (1.26×, 1.25×). Smaller
/// levels are pre-asymptotic (n = 4, 8, 16: 34, 47, 58, 1.38× then 1.23×);
/// point-block Jacobi PCG about doubles per level.
#[test]
fn multigrid_iterations_stay_bounded_under_refinement() {
    use seam_fem::scene::{warped_glue, WarpedGlue};
    let mut iterations = Vec::new();
    for n in [6, 12, 24] {
        let scene = WarpedGlue {
            slave_cells: n,
            ratio: 2,
            slave_layers: n,
            master_layers: 2 * n,
            multiplier: Multiplier::Dual,
            ..WarpedGlue::default()
        };
        let problem = warped_glue(&scene).unwrap();
        let options = SolveOptions { solver: petsc(1e-10), ..SolveOptions::default() };
        let s = problem.solve(&options).unwrap();
        let report = s.report.petsc.as_ref().expect("a PETSc report");
        println!("warped glue n = {n}: {} dofs, {} iterations", s.report.dofs, report.solves[0].iterations);
        iterations.push(report.solves[0].iterations);
    }
    for k in 1..iterations.len() {
        let growth = iterations[k] as f64 / iterations[k - 1] as f64;
        assert!(growth <= 1.3, "iterations {iterations:?}: growth {growth:.2} at level {k}");
    }
}

/// Frictional contact with PETSc (each semismooth Newton step on the
/// displacements alone, FGMRES + GAMG): the patch tests of `friction.rs` —
/// held by friction alone (hex|tet, rotated, and Tri6 slave faces in the
/// transformed basis), then driven into slip — as exact as with the direct
/// solver.
#[test]
fn frictional_patch_tests() {
    use crate::friction::{block_on_base_as, traction_miss, Layout, TopX, E, P};
    let options = SolveOptions { solver: petsc(1e-13), ..SolveOptions::default() };
    let (c, s) = ((0.6f64).cos(), (0.6f64).sin());
    let rotated = [[c, 0.0, s], [s * s, c, -s * c], [-s * c, s, c * c]];
    let tri6 = Layout { second_order: true, tri6_slave: true, ..Layout::default() };
    let tau = 0.5;
    for (name, layout) in [
        ("hex|tet", Layout::default()),
        ("hex|tet rotated", Layout { rotation: rotated, ..Layout::default() }),
        ("hex27|tet10 dual", tri6),
    ] {
        let problem = block_on_base_as(0.3, tau, TopX::Traction(tau), layout);
        let s = problem.solve(&options).unwrap();
        assert!(s.report.method.contains("PETSc"), "{}", s.report.method);
        let c = s.interfaces[0].contact.as_ref().unwrap();
        assert!((0..c.contact.len()).filter(|&p| c.contact[p]).all(|p| c.active[p] && c.stick[p]), "{name}");
        let miss = traction_miss(&s, layout.rotate([-tau, 0.0, P]));
        let steps = &s.report.contact.as_ref().unwrap().steps;
        println!("{name} (stick): traction off by {miss:.1e}, {} Newton steps", steps.len());
        assert!(miss < 1e-10, "{name}: traction off by {miss:e}");
    }
    let mu = 0.3;
    for (name, layout) in [("hex|tet", Layout::default()), ("hex27|tet10 dual", tri6)] {
        let mut problem = block_on_base_as(mu, mu * P, TopX::Displacement(0.05), layout);
        problem.steps = seam_fem::LoadSteps::equal(10).unwrap();
        let s = problem.solve(&options).unwrap();
        let c = s.interfaces[0].contact.as_ref().unwrap();
        let points: Vec<usize> = (0..c.contact.len()).filter(|&p| c.contact[p]).collect();
        assert!(points.iter().all(|&p| c.active[p] && !c.stick[p]), "{name}: all slip");
        let miss = traction_miss(&s, [-mu * P, 0.0, P]);
        let expected = 0.05 - 2.0 * mu * P * 0.5 / (E / 2.0);
        let slip = points.iter().map(|&p| (c.slip[p][0] - expected).abs()).fold(0.0, f64::max);
        let steps = &s.report.contact.as_ref().unwrap().steps;
        println!(
            "{name} (slip): traction off by {miss:.1e}, slip by {slip:.1e}, {} Newton steps",
            steps.len()
        );
        assert!(miss < 1e-10 && slip < 1e-10, "{name}: traction off by {miss:e}, slip by {slip:e}");
    }
}

/// Cattaneo–Mindlin (coarse, 2 shear steps) with PETSc: every load step ends
/// in the direct solver's stick, slip and inactive sets with its
/// displacements to 1e-8, and Newton ends at round-off with the inexact
/// (loose, then tight) Krylov solves.
#[test]
fn cattaneo_mindlin_as_the_direct_solver() {
    use seam_fem::scene::{cattaneo_mindlin, CattaneoMindlin};
    let p = CattaneoMindlin::default();
    let p = CattaneoMindlin { hertz: Hertz { fine_cells: 2, ..p.hertz }, shear_steps: 2, ..p };
    let problem = cattaneo_mindlin(&p).unwrap();
    let direct = seam_fem::solve_steps(&problem, &SolveOptions::default());
    let options = SolveOptions { solver: petsc(1e-12), ..SolveOptions::default() };
    let iterative = seam_fem::solve_steps(&problem, &options);
    for (k, (d, i)) in direct.zip(iterative).enumerate() {
        let ((t, d), (_, i)) = (d.unwrap(), i.unwrap());
        let (cd, ci) = (d.interfaces[0].contact.as_ref().unwrap(), i.interfaces[0].contact.as_ref().unwrap());
        assert_eq!((&cd.active, &cd.stick), (&ci.active, &ci.stick), "t = {t}");
        let scale = d.displacement.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let difference = d
            .displacement
            .iter()
            .flatten()
            .zip(i.displacement.iter().flatten())
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        let steps = &i.report.contact.as_ref().unwrap().steps;
        let r: Vec<String> = steps.iter().map(|s| format!("{:.1e}", s.residual)).collect();
        let krylov: Vec<usize> = steps.iter().map(|s| s.linear_iterations).collect();
        println!("t = {t:.2}: u off by {:.1e}; Newton {r:?}, KSP {krylov:?}", difference / scale);
        assert!(difference <= 1e-8 * scale, "t = {t}: {:e}", difference / scale);
        // Every load step ends at round-off, brought there in the shear
        // steps by an update that contracts by 10⁻³ at least: the last one,
        // or the one before it when that already reached 1e-9 and the last
        // only polishes to the Krylov tolerance (inexact Newton: a loose
        // step's update may be followed by a larger one, so the direct
        // solver's test of superlinear contraction does not apply to the
        // whole sequence).
        let r: Vec<f64> = steps.iter().map(|s| s.residual).collect();
        let fast = |w: &[f64]| w[1] < 1e-3 * w[0];
        let terminal = match r.as_slice() {
            [.., a, b, c] => *c < 1e-10 && (fast(&[*b, *c]) || (*b < 1e-9 && fast(&[*a, *b]))),
            [b, c] => *c < 1e-10 && fast(&[*b, *c]),
            _ => false,
        };
        assert!(if k == 0 { r.last().is_some_and(|&r| r < 1e-10) } else { terminal }, "t = {t}: {r:?}");
    }
}

/// Friction next to glue with PETSc: a cap glued on the block with dual
/// multipliers (eliminated node by node) keeps the stick patch test exact;
/// with standard ones (not eliminated) the solve is refused in one line.
#[test]
fn frictional_patch_test_with_a_glued_cap() {
    use crate::friction::{capped_block_on_base, traction_miss, TopX, P};
    let options = SolveOptions { solver: petsc(1e-13), ..SolveOptions::default() };
    let tau = 0.5;
    let problem = capped_block_on_base(0.3, tau, TopX::Traction(tau), Multiplier::Dual);
    let s = problem.solve(&options).unwrap();
    assert!(s.report.method.contains("PETSc"), "{}", s.report.method);
    let miss = traction_miss(&s, [-tau, 0.0, P]);
    println!("glued cap (dual), stick: traction off by {miss:.1e}");
    assert!(miss < 1e-10, "traction off by {miss:e}");
    let problem = capped_block_on_base(0.3, tau, TopX::Traction(tau), Multiplier::Standard);
    let e = problem.solve(&options).expect_err("refused").to_string();
    assert!(e.contains("eliminated node by node") && !e.contains('\n'), "{e}");
}

/// Finite deformation by PETSc (`Solver::Petsc` for hyperelastic bodies):
/// uniaxial stress in one body and across glue (`hyperelastic.rs`), glue
/// and contact in one problem (three blocks, 20 % compression) and
/// the contact patch test (Hex8 | Tet4, both laws) pass to the direct
/// solver's tolerances (displacements 1e-10, pressures 1e-8) in as many
/// Newton iterations per step (±1), the contact steps by FGMRES with the
/// field split, the glued tangent by FGMRES with GAMG.
#[test]
fn finite_deformation_glue_and_contact() {
    use crate::finite_contact::{assert_compressed, glue_and_contact_with, solve_with, stack};
    use seam_fem::Law;
    let options = SolveOptions { solver: petsc(1e-13), ..SolveOptions::default() };
    crate::hyperelastic::uniaxial_stress_with(&options);
    let direct = glue_and_contact_with(&SolveOptions::default());
    let by_petsc = glue_and_contact_with(&options);
    println!("glue and contact: Newton iterations {direct:?} (direct), {by_petsc:?} (PETSc)");
    assert!(direct.iter().zip(&by_petsc).all(|(a, b)| a.abs_diff(*b) <= 1), "{direct:?} {by_petsc:?}");
    for law in [Law::NeoHookean, Law::SaintVenantKirchhoff] {
        let problem = stack(law, (BlockKind::Hex, 3), (BlockKind::Tet, 2), 0.4, 4);
        let steps = solve_with(&problem, &options);
        let solution = &steps.last().unwrap().1;
        assert!(solution.report.method.contains("PETSc"), "{}", solution.report.method);
        let petsc = solution.report.petsc.as_ref().expect("PETSc's record");
        println!("{law:?}: {} KSP solves, {:?}", petsc.solves.len(), petsc.solves.last());
        assert_compressed(&format!("{law:?}, PETSc"), &problem, solution, (0, 1), law);
    }
}
