//! Glue and contact in one problem: base | contact | block | glue | block.
//!
//! A base [0,1]² × [0,1] (E = 2000), a block [0,1]² × [1,1.5] resting on it
//! through a frictionless contact interface (slave: the block's bottom), and a
//! top block [0,1]² × [1.5,2.2] glued to it (slave: the top block's bottom),
//! both blocks E = 1000, ν = 0.3 everywhere. The top is pressed by p = 3
//! (traction −p e_z); every body sits on rollers u_x = 0 at x = 0 and u_y = 0
//! at y = 0 (they touch both interfaces' slave sides), the base also on
//! u_z = 0 at z = 0. The blocks are held in z by the contact alone (force
//! control). The exact solution is uniaxial, σ = −p e_z⊗e_z in every body:
//! u = (ν p x / E, ν p y / E, −p z / E + c) per body with c making u_z
//! continuous across both interfaces; the contact pressure is p at every
//! contact point, every contact point is active, and the glued traction is
//! (0, 0, p) on the top block's bottom (outward normal −e_z).
//!
//! Asserted to 1e-10 relative for lumped and dual contact multipliers; dual
//! glue multipliers with the direct and PCG solvers (glued slave dofs
//! eliminated) and standard ones with both (a saddle point per active-set
//! step, by LDLᵀ or matrix-free PCG); hex and tet meshes, all three meshes
//! non-matching; KKT
//! residuals ≤ 1e-10; the same bits on 1 and 2 threads.
//!
//! Measured (`cargo test -p seam-fem --test mixed -- --nocapture`): errors
//! ≤ 1e-13.
mod common;

use common::{max_abs, Affine, Part};
use seam::{Facing, MortarOptions, Multiplier, Point3};
use seam_fem::generate::{BlockKind, Side};
use seam_fem::pcg::PcgOptions;
use seam_fem::{recover_stresses, traction, Dirichlet, Material, ProblemError, Solver};
use seam_fem::{solve_coupled, Solution, SolveOptions};
use seam_fem::{Body, Coupling, Interface};

const P: f64 = 3.0;
const RTOL: f64 = 1e-10;
/// Zero prescribed values (rollers).
const ZERO: Affine = Affine { a: [[0.0; 3]; 3], c: [0.0; 3] };

struct Stack {
    parts: [Part; 3],
    materials: [Material; 3],
}

impl Stack {
    fn new(kinds: [BlockKind; 3]) -> Stack {
        let parts = [
            Part::new([3, 4, 2], kinds[0], |u, v, w| [u, v, w]),
            Part::new([4, 3, 2], kinds[1], |u, v, w| [u, v, 1.0 + 0.5 * w]),
            Part::new([5, 2, 2], kinds[2], |u, v, w| [u, v, 1.5 + 0.7 * w]),
        ];
        let materials = [2000.0, 1000.0, 1000.0].map(|e| Material::new(e, 0.3).unwrap());
        Stack { parts, materials }
    }

    /// The exact displacement of body `b` at `x`.
    fn exact(&self, b: usize, x: Point3) -> [f64; 3] {
        let strain = |b: usize| P / self.materials[b].young();
        let lateral = 0.3 * strain(b);
        // u_z continuous at z = 1 and z = 1.5.
        let uz = match b {
            0 => -strain(0) * x[2],
            1 => -strain(0) - strain(1) * (x[2] - 1.0),
            _ => -strain(0) - strain(1) * 0.5 - strain(2) * (x[2] - 1.5),
        };
        [lateral * x[0], lateral * x[1], uz]
    }

    fn solve(&self, contact: Multiplier, glue: Multiplier, solver: Solver) -> Result<Solution, ProblemError> {
        let [base, lower, upper] = &self.parts;
        let mut dirichlet = [Dirichlet::new(), Dirichlet::new(), Dirichlet::new()];
        for (part, d) in self.parts.iter().zip(&mut dirichlet) {
            part.fix(d, &ZERO, Side::XMin, [true, false, false]);
            part.fix(d, &ZERO, Side::YMin, [false, true, false]);
        }
        base.fix(&mut dirichlet[0], &ZERO, Side::ZMin, [false, false, true]);
        let mut loads: Vec<Vec<f64>> =
            self.parts.iter().map(|p| vec![0.0; 3 * p.mesh.points().len()]).collect();
        loads[2] = traction(&upper.side(Side::ZMax), |_, _| [0.0, 0.0, -P]);
        let bodies: Vec<Body> = self
            .parts
            .iter()
            .zip(loads)
            .zip(dirichlet)
            .zip(self.materials)
            .map(|(((part, load), dirichlet), material)| Body { mesh: &part.mesh, material, load, dirichlet })
            .collect();
        let surfaces =
            [base.side(Side::ZMax), lower.side(Side::ZMin), lower.side(Side::ZMax), upper.side(Side::ZMin)];
        // Body b's top (master) and body b + 1's bottom (slave).
        let interfaces =
            [(0, contact, Coupling::Contact), (1, glue, Coupling::Glue)].map(|(b, multiplier, kind)| {
                Interface {
                    master: b,
                    master_surface: &surfaces[2 * b],
                    slave: b + 1,
                    slave_surface: &surfaces[2 * b + 1],
                    options: MortarOptions {
                        multiplier,
                        facing: Facing::Opposite,
                        ..MortarOptions::default()
                    },
                    kind,
                }
            });
        solve_coupled(&bodies, &interfaces, &SolveOptions { solver, ..Default::default() })
    }

    /// The largest relative error of displacement, stress, contact pressure and
    /// glued traction; asserts every contact point is active.
    fn error(&self, s: &Solution) -> f64 {
        let u_scale = self
            .parts
            .iter()
            .enumerate()
            .flat_map(|(b, p)| p.mesh.points().iter().map(move |&x| max_abs(&self.exact(b, x))))
            .fold(0.0, f64::max);
        let (mut u_error, mut s_error) = (0.0f64, 0.0f64);
        for (b, part) in self.parts.iter().enumerate() {
            for (p, &x) in part.mesh.points().iter().enumerate() {
                let e = self.exact(b, x);
                let diff: Vec<f64> = (0..3).map(|c| s.displacement[b][3 * p + c] - e[c]).collect();
                u_error = u_error.max(max_abs(&diff) / u_scale);
            }
            let stresses = recover_stresses(&part.mesh, &self.materials[b], &s.displacement[b]).unwrap();
            for cell in &stresses.cell {
                let exact = [0.0, 0.0, -P, 0.0, 0.0, 0.0];
                let diff: Vec<f64> = (0..6).map(|k| cell[k] - exact[k]).collect();
                s_error = s_error.max(max_abs(&diff) / P);
            }
        }
        let contact = s.interfaces[0].contact.as_ref().expect("a contact interface");
        let mut p_error = 0.0f64;
        for p in (0..contact.contact.len()).filter(|&p| contact.contact[p]) {
            assert!(contact.active[p], "contact point {p} is not active");
            p_error = p_error.max((contact.pressure[p] - P).abs() / P);
        }
        assert!(contact.contact.iter().any(|&c| c), "no contact point");
        let glued = &s.interfaces[1];
        let mut t_error = 0.0f64;
        for p in (0..glued.traction.len()).filter(|&p| glued.mortar.covered[p]) {
            let diff: Vec<f64> = (0..3).map(|c| glued.traction[p][c] - [0.0, 0.0, P][c]).collect();
            t_error = t_error.max(max_abs(&diff) / P);
        }
        println!(
            "    u {u_error:.1e}  σ {s_error:.1e}  pressure {p_error:.1e}  glued traction {t_error:.1e}  KKT {:.1e}  \
             steps {}  constraints {}",
            s.report.residual,
            s.report.iterations,
            s.report.constraints
        );
        let kkt = s.report.contact.as_ref().expect("a contact report").kkt;
        assert!(kkt.max() <= RTOL && s.report.residual == kkt.max(), "KKT {kkt:?}");
        u_error.max(s_error).max(p_error).max(t_error)
    }
}

#[test]
fn glue_and_contact_in_one_problem_pass_the_pressure_patch_test() {
    use BlockKind::*;
    let pcg = Solver::Pcg(PcgOptions { rtol: 1e-14, ..PcgOptions::default() });
    for kinds in [[Hex, Tet, Hex], [Tet, Hex, Tet]] {
        let stack = Stack::new(kinds);
        for contact in [Multiplier::Lumped, Multiplier::Dual] {
            for (glue, solver, name) in [
                (Multiplier::Dual, Solver::Direct, "direct"),
                (Multiplier::Dual, pcg, "PCG"),
                (Multiplier::Standard, Solver::Direct, "direct"),
                (Multiplier::Standard, pcg, "PCG"),
            ] {
                println!("  {kinds:?}, contact {contact:?}, glue {glue:?}, {name}");
                let s = stack.solve(contact, glue, solver).unwrap();
                let e = stack.error(&s);
                println!("    {}", s.report.method);
                assert!(e <= RTOL, "{kinds:?} {contact:?} {glue:?} {name}: error {e:.3e}");
            }
        }
    }
}

#[test]
fn glue_and_contact_give_the_same_bits_on_one_and_two_threads() {
    let stack = Stack::new([BlockKind::Hex, BlockKind::Tet, BlockKind::Hex]);
    let solve = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| stack.solve(Multiplier::Lumped, Multiplier::Dual, Solver::Direct).unwrap())
    };
    let (one, two) = (solve(1), solve(2));
    assert_eq!(one.displacement, two.displacement);
    for (a, b) in one.interfaces.iter().zip(&two.interfaces) {
        assert_eq!(a.traction, b.traction);
    }
    let pressure = |s: &Solution| s.interfaces[0].contact.as_ref().unwrap().pressure.clone();
    assert_eq!(pressure(&one), pressure(&two));
}
