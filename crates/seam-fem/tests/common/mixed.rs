//! The stack of `tests/mixed.rs`: base | contact | block | glue | block,
//! pressed on top; the exact solution is uniaxial (that file's doc).

use super::{max_abs, Affine, Part};
use seam::{Facing, MortarOptions, Multiplier, Point3};
use seam_fem::generate::{BlockKind, Side};
use seam_fem::{recover_stresses, traction, Dirichlet, Material, ProblemError, Solver};
use seam_fem::{solve_coupled, Solution, SolveOptions};
use seam_fem::{Body, Coupling, Interface};

/// The pressure on top.
pub const P: f64 = 3.0;
/// Errors and KKT residuals asserted.
pub const RTOL: f64 = 1e-10;
/// Zero prescribed values (rollers).
const ZERO: Affine = Affine { a: [[0.0; 3]; 3], c: [0.0; 3] };

pub struct Stack {
    pub parts: [Part; 3],
    pub materials: [Material; 3],
}

impl Stack {
    pub fn new(kinds: [BlockKind; 3]) -> Stack {
        let parts = [
            Part::new([3, 4, 2], kinds[0], |u, v, w| [u, v, w]),
            Part::new([4, 3, 2], kinds[1], |u, v, w| [u, v, 1.0 + 0.5 * w]),
            Part::new([5, 2, 2], kinds[2], |u, v, w| [u, v, 1.5 + 0.7 * w]),
        ];
        let materials = [2000.0, 1000.0, 1000.0].map(|e| Material::new(e, 0.3).unwrap());
        Stack { parts, materials }
    }

    /// The exact displacement of body `b` at `x`.
    pub fn exact(&self, b: usize, x: Point3) -> [f64; 3] {
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

    pub fn solve(
        &self,
        contact: Multiplier,
        glue: Multiplier,
        solver: Solver,
    ) -> Result<Solution, ProblemError> {
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
            .map(|(((part, load), dirichlet), material)| Body {
                mesh: &part.mesh,
                material,
                load,
                dirichlet,
                ties: Vec::new(),
            })
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
                    friction: 0.0,
                }
            });
        solve_coupled(&bodies, &interfaces, &SolveOptions { solver, ..Default::default() })
    }

    /// The largest relative error of displacement, stress, contact pressure and
    /// glued traction; asserts every contact point is active.
    pub fn error(&self, s: &Solution) -> f64 {
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
