//! The stacked blocks of the contact tests (`tests/contact.rs`): the lower
//! block [0,1]² × [0, ½] (master, E₁ = 1000, ν₁ = 0.3) under the upper block
//! [0,1]² × [½ + δ, 1 + δ] (slave, E₂ = 300, ν₂ = 0.2), rollers on x = 0 and
//! y = 0, the lower bottom on u_z = 0; uniaxial exact solutions.

use seam::{Multiplier, Point3, SurfaceMesh, VolumeMesh};
use seam_fem::generate::{block, BlockKind, Grid, Side};
use seam_fem::{solve_coupled, Solution, SolveOptions};
use seam_fem::{traction, Dirichlet, Material};
use seam_fem::{Body, Coupling, Interface, Solver};

/// KKT residuals every solve must meet.
const RTOL: f64 = 1e-8;

pub struct Stack {
    pub lower: (VolumeMesh, Grid),
    pub upper: (VolumeMesh, Grid),
    pub delta: f64,
    pub materials: [Material; 2],
}

impl Stack {
    /// Lower `nl` cells across of `kl`, upper `nu` of `ku`; upper block shifted up by δ.
    pub fn new(nl: usize, kl: BlockKind, nu: usize, ku: BlockKind, delta: f64) -> Stack {
        let lower = block(nl, nl, 2, |u, v, w| [u, v, 0.5 * w], kl);
        let upper = block(nu, nu, 3, |u, v, w| [u, v, 0.5 + delta + 0.5 * w], ku);
        let materials = [Material::new(1000.0, 0.3).unwrap(), Material::new(300.0, 0.2).unwrap()];
        Stack { lower: (lower, Grid::new(nl, nl, 2)), upper: (upper, Grid::new(nu, nu, 3)), delta, materials }
    }

    pub fn surfaces(&self) -> (SurfaceMesh, SurfaceMesh) {
        let top = self.lower.1.side_faces(&self.lower.0, Side::ZMax).unwrap();
        let bottom = self.upper.1.side_faces(&self.upper.0, Side::ZMin).unwrap();
        (top, bottom)
    }

    /// Rollers on x = 0 and y = 0; the lower bottom on u_z = 0; the upper top
    /// loaded by −p e₃, or held at u_z = `top` when given.
    pub fn solve(&self, p: f64, top: Option<f64>, multiplier: Multiplier, solver: Solver) -> Solution {
        let rollers = |grid: &Grid, d: &mut Dirichlet| {
            for q in grid.side_points(Side::XMin) {
                d.fix(q, [Some(0.0), None, None]);
            }
            for q in grid.side_points(Side::YMin) {
                d.fix(q, [None, Some(0.0), None]);
            }
        };
        let mut dl = Dirichlet::new();
        rollers(&self.lower.1, &mut dl);
        for q in self.lower.1.side_points(Side::ZMin) {
            dl.fix(q, [None, None, Some(0.0)]);
        }
        let mut du = Dirichlet::new();
        rollers(&self.upper.1, &mut du);
        if let Some(v) = top {
            for q in self.upper.1.side_points(Side::ZMax) {
                du.fix(q, [None, None, Some(v)]);
            }
        }
        let load =
            traction(&self.upper.1.side_faces(&self.upper.0, Side::ZMax).unwrap(), |_, _| [0.0, 0.0, -p]);
        let (master, slave) = self.surfaces();
        let bodies = [
            Body {
                mesh: &self.lower.0,
                material: self.materials[0],
                load: vec![0.0; 3 * self.lower.0.points().len()],
                dirichlet: dl,
                ties: Vec::new(),
            },
            Body { mesh: &self.upper.0, material: self.materials[1], load, dirichlet: du, ties: Vec::new() },
        ];
        let options =
            seam::MortarOptions { multiplier, facing: seam::Facing::Opposite, ..Default::default() };
        let interfaces = [Interface {
            master: 0,
            master_surface: &master,
            slave: 1,
            slave_surface: &slave,
            options,
            kind: Coupling::Contact,
            friction: 0.0,
        }];
        let solution =
            solve_coupled(&bodies, &interfaces, &SolveOptions { solver, ..Default::default() }).unwrap();
        let kkt = solution.report.contact.as_ref().expect("contact").kkt;
        println!("    KKT {kkt:?}, steps {:?}", solution.report.contact.as_ref().expect("contact").steps);
        assert!(kkt.max() <= RTOL, "KKT conditions violated: {kkt:?}");
        solution
    }

    /// max |u − u_exact| / max |u_exact| for the uniaxial solution with
    /// pressure p, the upper body shifted rigidly by `shift` in z.
    pub fn displacement_error(&self, s: &Solution, p: f64, shift: f64) -> f64 {
        let exact = |x: Point3, m: &Material, base: f64| -> Point3 {
            let (e, nu) = (m.young(), m.poisson());
            [nu * p / e * x[0], nu * p / e * x[1], -p / e * (x[2] - base)]
        };
        let mut err = 0.0f64;
        let mut size = 0.0f64;
        let lower_top = -0.5 * p / self.materials[0].young();
        let bodies = [(&self.lower.0, 0.0, 0.0), (&self.upper.0, 0.5 + self.delta, lower_top + shift)];
        for (b, (mesh, base, offset)) in bodies.iter().enumerate() {
            for (q, x) in mesh.points().iter().enumerate() {
                let mut e = exact(*x, &self.materials[b], *base);
                e[2] += offset;
                for c in 0..3 {
                    err = err.max((s.displacement[b][3 * q + c] - e[c]).abs());
                    size = size.max(e[c].abs());
                }
            }
        }
        err / size
    }
}
