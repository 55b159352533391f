//! Patch tests with supports and other interfaces touching the slave side.
//!
//! Where slave interface dofs are prescribed (a symmetry roller on a face that
//! meets the interface) or constrained by an earlier interface (a crossline),
//! their multipliers move to their neighbours (Wohlmuth's modified basis) so
//! that a constant traction stays in the multiplier space. Every case below is
//! an affine displacement u = a x + c that the discretisation reproduces: the
//! solution must equal it at every node, the stress in every cell, and the
//! traction −λ must be σ n_s at every covered slave point, all to 1e-10
//! relative, for standard and dual multipliers, direct and PCG solvers.
//!
//! - Rollers: a master block under a slave block on the plane z = 1 + s x
//!   (s = 0 and s = 0.2), both bodies on a roller u_x = 0 at x = 0, the master
//!   clamped to the exact field at z = 0, every other outer face loaded by σ n,
//!   with σ_xx, σ_yy, σ_zz and σ_yz nonzero (the tilted interface carries shear
//!   and normal traction). Hex|tet and tet|hex, non-matching.
//! - Crossline: blocks A = [0,1]×[0,1]², B = [1,2]×[0,1]² and C = [0,2]×[0,1]×
//!   [1,1.6] glued A|B (x = 1), A|C and B|C (z = 1; C's bottom split at x = 1),
//!   C slave of both upper interfaces, so C's points on the line x = 1, z = 1
//!   are slave points of two interfaces and B's points on it are slave of A|B
//!   and master of B|C. The patch field, A clamped at z = 0, all other outer
//!   faces loaded.
//!
//! Measured (`cargo test -p seam-fem --test glue_supports -- --nocapture`):
//! every error ≤ 3e-14.
mod common;

use common::{max_abs, stress_vector, Affine, Part};
use seam::{nodal_normals, Facing, MortarOptions, Multiplier, SurfaceMesh};
use seam_fem::generate::{BlockKind, Side};
use seam_fem::pcg::PcgOptions;
use seam_fem::{recover_stresses, Dirichlet, Material, Solver};
use seam_fem::{solve_coupled, Body, Coupling, Interface, SolveOptions};

const RTOL: f64 = 1e-10;

/// (master body, master surface, slave body, slave surface).
type Glue = (usize, SurfaceMesh, usize, SurfaceMesh);

/// Solves and returns the largest relative error of displacement, cell stress
/// and slave traction, and the method that solved.
fn error(
    label: &str,
    parts: &[&Part],
    loads: Vec<Vec<f64>>,
    dirichlet: Vec<Dirichlet>,
    glues: &[Glue],
    field: &Affine,
    (multiplier, solver): (Multiplier, Solver),
) -> (f64, &'static str) {
    let material = Material::new(1000.0, 0.3).unwrap();
    let sigma = field.stress(&material);
    let bodies: Vec<Body> = parts
        .iter()
        .zip(loads)
        .zip(dirichlet)
        .map(|((part, load), dirichlet)| Body { mesh: &part.mesh, material, load, dirichlet })
        .collect();
    let options = MortarOptions { multiplier, facing: Facing::Opposite, ..MortarOptions::default() };
    let interfaces: Vec<Interface> = glues
        .iter()
        .map(|(master, master_surface, slave, slave_surface)| Interface {
            master: *master,
            master_surface,
            slave: *slave,
            slave_surface,
            options,
            kind: Coupling::Glue,
        })
        .collect();
    let sol = solve_coupled(&bodies, &interfaces, &SolveOptions { solver, ..Default::default() }).unwrap();

    let (mut u_error, mut s_error, mut t_error) = (0.0f64, 0.0f64, 0.0f64);
    let u_scale =
        parts.iter().flat_map(|p| p.mesh.points().iter().map(|&x| max_abs(&field.at(x)))).fold(0.0, f64::max);
    let s_scale = max_abs(&sigma);
    for (b, part) in parts.iter().enumerate() {
        for (p, &x) in part.mesh.points().iter().enumerate() {
            let e = field.at(x);
            let diff: Vec<f64> = (0..3).map(|c| sol.displacement[b][3 * p + c] - e[c]).collect();
            u_error = u_error.max(max_abs(&diff) / u_scale);
        }
        let s = recover_stresses(&part.mesh, &material, &sol.displacement[b]).unwrap();
        for cell in &s.cell {
            let diff: Vec<f64> = (0..6).map(|k| cell[k] - sigma[k]).collect();
            s_error = s_error.max(max_abs(&diff) / s_scale);
        }
    }
    for ((_, _, _, slave_surface), glued) in glues.iter().zip(&sol.interfaces) {
        let normals = nodal_normals(slave_surface);
        for p in (0..normals.len()).filter(|&p| glued.mortar.covered[p]) {
            let t = stress_vector(&sigma, normals[p]);
            let diff: Vec<f64> = (0..3).map(|c| glued.traction[p][c] - t[c]).collect();
            t_error = t_error.max(max_abs(&diff) / s_scale);
        }
    }
    let solver_name = if matches!(solver, Solver::Direct) { "direct" } else { "PCG" };
    println!(
        "  {label:<34} {:<9} {solver_name:<7} u {u_error:.1e}  σ {s_error:.1e}  t {t_error:.1e}  ({})",
        format!("{multiplier:?}"),
        sol.report.method
    );
    (u_error.max(s_error).max(t_error), sol.report.method)
}

/// Standard and dual, direct and PCG.
fn variants() -> [(Multiplier, Solver); 4] {
    let pcg = Solver::Pcg(PcgOptions { rtol: 1e-14, ..PcgOptions::default() });
    [
        (Multiplier::Standard, Solver::Direct),
        (Multiplier::Dual, Solver::Direct),
        (Multiplier::Standard, pcg),
        (Multiplier::Dual, pcg),
    ]
}

#[test]
fn patch_test_rollers_on_both_bodies_touching_the_interface() {
    use BlockKind::*;
    // u_x = 0 on x = 0, no shear there: a roller; biaxial with σ_yz.
    let field =
        Affine { a: [[1e-3, 0.0, 0.0], [0.0, -5e-4, 4e-4], [0.0, 1e-4, 7e-4]], c: [0.0, -2e-3, 5e-4] };
    let sigma = field.stress(&Material::new(1000.0, 0.3).unwrap());
    let mut methods = std::collections::BTreeSet::new();
    for slope in [0.0, 0.2] {
        // The last pair (a thick slave over a coarse master) is solved by
        // elimination (reduced Cholesky) for dual multipliers.
        for (m, s) in [
            (([4, 3, 2], Hex), ([3, 5, 2], Tet)),
            (([3, 4, 2], Tet), ([5, 3, 2], Hex)),
            (([2, 2, 1], Hex), ([6, 6, 6], Hex)),
        ] {
            let interface = move |x: f64| 1.0 + slope * x;
            let master = Part::new(m.0, m.1, |u, v, w| [u, v, w * interface(u)]);
            let slave = Part::new(s.0, s.1, |u, v, w| [u, v, interface(u) + w * (1.7 - interface(u))]);
            let mut fixed = [Dirichlet::new(), Dirichlet::new()];
            master.fix(&mut fixed[0], &field, Side::ZMin, [true; 3]);
            for (part, d) in [&master, &slave].into_iter().zip(&mut fixed) {
                part.fix(d, &field, Side::XMin, [true, false, false]);
            }
            use Side::*;
            let loads =
                vec![master.load(&sigma, &[XMax, YMin, YMax]), slave.load(&sigma, &[XMax, YMin, YMax, ZMax])];
            let glues = [(0, master.side(ZMax), 1, slave.side(ZMin))];
            let label = format!("{:?}|{:?} slope {slope}", m.1, s.1);
            for variant in variants() {
                let (e, method) =
                    error(&label, &[&master, &slave], loads.clone(), fixed.to_vec(), &glues, &field, variant);
                assert!(e <= RTOL, "{label} {variant:?}: error {e:.3e}");
                methods.insert(method);
            }
        }
    }
    assert_eq!(methods.len(), 3, "every glue solver ran: {methods:?}");
}

#[test]
fn patch_test_three_blocks_meeting_along_a_crossline() {
    use BlockKind::*;
    use Side::*;
    let field = Affine::PATCH;
    let sigma = field.stress(&Material::new(1000.0, 0.3).unwrap());
    for kinds in [[Hex, Tet, Hex], [Tet, Hex, Tet]] {
        let a = Part::new([3, 3, 3], kinds[0], |u, v, w| [u, v, w]);
        let b = Part::new([2, 4, 3], kinds[1], |u, v, w| [1.0 + u, v, w]);
        let c = Part::new([4, 5, 2], kinds[2], |u, v, w| [2.0 * u, v, 1.0 + 0.6 * w]);
        let mut fixed = [Dirichlet::new(), Dirichlet::new(), Dirichlet::new()];
        a.fix(&mut fixed[0], &field, ZMin, [true; 3]);
        let loads = vec![
            a.load(&sigma, &[XMin, YMin, YMax]),
            b.load(&sigma, &[XMax, YMin, YMax, ZMin]),
            c.load(&sigma, &[XMin, XMax, YMin, YMax, ZMax]),
        ];
        let glues = [
            (0, a.side(XMax), 1, b.side(XMin)),
            (0, a.side(ZMax), 2, c.side_where(ZMin, |[i, _, _]| i <= 2)),
            (1, b.side(ZMax), 2, c.side_where(ZMin, |[i, _, _]| i >= 2)),
        ];
        let label = format!("crossline {kinds:?}");
        for variant in variants() {
            let (e, _) = error(&label, &[&a, &b, &c], loads.clone(), fixed.to_vec(), &glues, &field, variant);
            assert!(e <= RTOL, "{label} {variant:?}: error {e:.3e}");
        }
    }
}
