//! The paper's second example (Fig. 3): two bodies with bulging interfaces in
//! frictionless contact.
//!
//! # Geometry
//! Two hexahedral blocks over the square \[0,1\]², meshed independently:
//!
//! ```text
//! lower (master):  0 ≤ z ≤ t(x, y),   t(x, y) = 1/2 + b_m(x, y)
//! upper (slave):   s(x, y) ≤ z ≤ 1,   s(x, y) = 1/2 + δ − b_s(x, y)
//! ```
//!
//! with Gaussian bulges, the lower top bulging up, the upper bottom bulging
//! down,
//!
//! ```text
//! b(x, y) = a · exp(−(x − c_x)²/r_x² − (y − c_y)²/r_y²)
//! ```
//!
//! (a [`Bulge`] each; by default a round bulge b_m of height 0.08 and radius
//! 0.35 at (0.4, 0.45) below an elongated one b_s of height 0.06 and radii
//! (0.4, 0.25) at (0.58, 0.52), so the problem has no symmetry; slopes up to
//! about 0.2 each) and the lift
//!
//! ```text
//! δ = max_{[0,1]²} (b_m + b_s) + clearance ,
//! ```
//!
//! so that the initial gap s − t = δ − b_m − b_s is positive except at one
//! touching point ([`BulgingContact::touching_point`], (0.4635, 0.4908) by
//! default), where it is the clearance (0 by default). Far from the bulges the
//! gap is about δ = 0.1307 (default). Cells are uniform in z; the master is
//! `ratio` times finer than the slave in every direction.
//!
//! # Conditions
//! The lower body's bottom is clamped; the upper body's top is moved by the
//! uniform displacement [`BulgingContact::press`], by default (0.02, −0.01,
//! −0.08): down by more than the gap near the touching point but less than
//! the gap far from the bulges (a partial contact zone around the touching
//! point), with a shear. E = 1000, ν = 0.3 in both bodies. The interface
//! "lower:top" (master) – "upper:bottom" (slave) is a contact interface with
//! lumped standard multipliers ([`Multiplier::Lumped`], as in the paper), faces
//! facing each other ([`Facing::Opposite`]), and a gap limit
//! ([`MaxGap::Absolute`]) of 1/2, the block height, well above δ, so that
//! every initially open slave point gets its constraint.

use super::{block_body, BOTTOM_TOP};
use crate::generate::{block, BlockKind, Grid};
use crate::material::Material;
use crate::multibody::Coupling;
use crate::problem::{Problem, ProblemInterface, Support, SurfaceId};
use seam::{Facing, MaxGap, MeshError, MortarOptions, Multiplier, Point3};

/// A Gaussian bulge a · exp(−(x − c_x)²/r_x² − (y − c_y)²/r_y²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bulge {
    /// Its height a.
    pub height: f64,
    /// Its centre (c_x, c_y).
    pub centre: [f64; 2],
    /// Its radii (r_x, r_y).
    pub radius: [f64; 2],
}

impl Bulge {
    /// b(x, y).
    pub fn at(&self, x: f64, y: f64) -> f64 {
        let dx = (x - self.centre[0]) / self.radius[0];
        let dy = (y - self.centre[1]) / self.radius[1];
        self.height * (-dx * dx - dy * dy).exp()
    }
}

/// Parameters of [`bulging_contact`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BulgingContact {
    /// Slave (upper) cells across x and y.
    pub cells: usize,
    /// h_s / h_m: master cells across = round(`ratio` · `cells`), master layers
    /// = round(`ratio` · `layers`).
    pub ratio: f64,
    /// Slave cell layers (uniform in z).
    pub layers: usize,
    /// The bulge b_m of the lower body's top (up).
    pub master_bulge: Bulge,
    /// The bulge b_s of the upper body's bottom (down).
    pub slave_bulge: Bulge,
    /// The smallest initial gap (0: the bodies touch at one point).
    pub clearance: f64,
    /// The displacement prescribed on the upper body's top.
    pub press: [f64; 3],
    /// The multiplier (lumped or dual).
    pub multiplier: Multiplier,
}

impl Default for BulgingContact {
    /// 12 × 12 × 6 slave cells, 18 × 18 × 9 master cells; the bulges of the
    /// module doc, touching; pressed by (0.02, −0.01, −0.08); lumped
    /// multipliers. About 30 of the 169 slave points end up in contact.
    fn default() -> Self {
        BulgingContact {
            cells: 12,
            ratio: 1.5,
            layers: 6,
            master_bulge: Bulge { height: 0.08, centre: [0.4, 0.45], radius: [0.35, 0.35] },
            slave_bulge: Bulge { height: 0.06, centre: [0.58, 0.52], radius: [0.4, 0.25] },
            clearance: 0.0,
            press: [0.02, -0.01, -0.08],
            multiplier: Multiplier::Lumped,
        }
    }
}

impl BulgingContact {
    /// The point of \[0,1\]² where b_m + b_s is largest: where the bodies touch
    /// (clearance 0). Found by a grid search refined to round-off.
    pub fn touching_point(&self) -> [f64; 2] {
        let f = |x: f64, y: f64| self.master_bulge.at(x, y) + self.slave_bulge.at(x, y);
        let (mut best, mut value) = ([0.5, 0.5], f64::NEG_INFINITY);
        // 65 × 65 points on the square, then 17 × 17 around the best, each
        // round 4 times finer.
        let (mut step, mut half_width) = (1.0 / 64.0, 32);
        while step > 1e-12 {
            let around = best;
            for i in -half_width..=half_width {
                for j in -half_width..=half_width {
                    let x = (around[0] + f64::from(i) * step).clamp(0.0, 1.0);
                    let y = (around[1] + f64::from(j) * step).clamp(0.0, 1.0);
                    let v = f(x, y);
                    if v > value {
                        (best, value) = ([x, y], v);
                    }
                }
            }
            (step, half_width) = (step / 4.0, 8);
        }
        best
    }

    /// The lift δ = max (b_m + b_s) over \[0,1\]² plus the clearance (module
    /// doc), the maximum at [`Self::touching_point`].
    pub fn lift(&self) -> f64 {
        let [x, y] = self.touching_point();
        self.master_bulge.at(x, y) + self.slave_bulge.at(x, y) + self.clearance
    }

    /// The lower body's top t(x, y) = 1/2 + b_m(x, y).
    pub fn master_surface(&self, x: f64, y: f64) -> f64 {
        0.5 + self.master_bulge.at(x, y)
    }

    /// The upper body's bottom s(x, y) = 1/2 + δ − b_s(x, y), with δ =
    /// [`Self::lift`] (searched anew at each call).
    pub fn slave_surface(&self, x: f64, y: f64) -> f64 {
        self.slave_surface_lifted(x, y, self.lift())
    }

    /// The initial gap s(x, y) − t(x, y), vertical (searches δ anew at each call).
    pub fn initial_gap(&self, x: f64, y: f64) -> f64 {
        self.slave_surface(x, y) - self.master_surface(x, y)
    }

    /// Master cells across.
    pub fn master_cells(&self) -> usize {
        scaled(self.cells, self.ratio)
    }

    /// Master cell layers.
    pub fn master_layers(&self) -> usize {
        scaled(self.layers, self.ratio)
    }

    fn slave_surface_lifted(&self, x: f64, y: f64, lift: f64) -> f64 {
        0.5 + lift - self.slave_bulge.at(x, y)
    }
}

/// round(n · ratio), at least 1.
fn scaled(n: usize, ratio: f64) -> usize {
    ((n as f64 * ratio).round() as usize).max(1)
}

/// The bulging-contact problem (module doc): bodies "lower" (master, surfaces
/// "bottom", "top") and "upper" (slave, "bottom", "top"), E = 1000, ν = 0.3
/// both; "lower:bottom" clamped, "upper:top" moved by `p.press`; one contact
/// interface "lower:top" – "upper:bottom". Solve it with
/// [`Problem::solve`].
///
/// # Errors
/// [`MeshError`] from the boundary extraction, only for degenerate parameters.
/// The upper body must keep a positive thickness, 1/2 + δ − b_s < 1, else
/// the solve reports inverted cells.
///
/// # Panics
/// If a cell count is zero.
pub fn bulging_contact(p: &BulgingContact) -> Result<Problem, MeshError> {
    let material = Material::new(1000.0, 0.3).expect("valid constants");
    let lift = p.lift();
    let (nm, lm) = (p.master_cells(), p.master_layers());
    let lower = block(nm, nm, lm, |u, v, w| [u, v, p.master_surface(u, v) * w], BlockKind::Hex);
    let (ns, ls) = (p.cells, p.layers);
    let upper_map = |u: f64, v: f64, w: f64| -> Point3 {
        let s = p.slave_surface_lifted(u, v, lift);
        [u, v, s + (1.0 - s) * w]
    };
    let upper = block(ns, ns, ls, upper_map, BlockKind::Hex);
    let bodies = vec![
        block_body("lower", lower, &Grid::new(nm, nm, lm), material, &BOTTOM_TOP)?,
        block_body("upper", upper, &Grid::new(ns, ns, ls), material, &BOTTOM_TOP)?,
    ];
    let (bottom, top) = (0, 1);
    let options = MortarOptions {
        multiplier: p.multiplier,
        facing: Facing::Opposite,
        max_gap: MaxGap::Absolute(0.5),
        ..MortarOptions::default()
    };
    Ok(Problem {
        bodies,
        interfaces: vec![ProblemInterface {
            master: SurfaceId { body: 0, surface: top },
            slave: SurfaceId { body: 1, surface: bottom },
            options,
            kind: Coupling::Contact,
            friction: 0.0,
        }],
        supports: vec![
            Support::new(SurfaceId { body: 0, surface: bottom }, [Some(0.0); 3]),
            Support::new(SurfaceId { body: 1, surface: top }, p.press.map(Some)),
        ],
        loads: vec![],
        ..Problem::default()
    })
}
