//! Ironing (after Puso & Laursen 2004, CMAME 193): a hyperelastic indenter
//! with a cylindrical face pressed into a softer hyperelastic slab and slid
//! along it, in finite deformation with large sliding.
//!
//! # Geometry
//! The slab is [0, 6] × [0, 2] × [0, 1] (`cells` hexahedra per unit length);
//! the indenter stands over [0.5, 1.5] × [0.5, 1.5] up to z = 2, its bottom the
//! cylinder z = 1 + R − √(R² − (x − 1)²), R = 1, touching the slab along the
//! line x = 1 and 0.134 above it at its edges (`indenter_cells` across x and
//! y, half as many layers: its bottom, the slave, finer than the slab's top).
//!
//! # Conditions
//! Both neo-Hookean (the slab E = 100, the indenter E = 1000, ν = 0.3). The
//! slab's bottom is clamped; the indenter's top is moved down by
//! [`Ironing::press`] over the first fifth of the pseudo-time, then along x
//! by [`Ironing::slide`] over the rest, y held. Contact with dual
//! multipliers, faces facing each other, every slave point within 0.3 of the
//! slab kept, Coulomb's [`Ironing::friction`].

use super::block_body;
use crate::generate::{block, BlockKind, Grid, Side};
use crate::history::{Amplitude, LoadSteps};
use crate::material::Material;
use crate::multibody::Coupling;
use crate::problem::{Problem, ProblemInterface, Support, SurfaceId};
use crate::Law;
use seam::{Facing, MaxGap, MeshError, MortarOptions, Multiplier};

/// Parameters of [`ironing`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ironing {
    /// Slab hexahedra per unit length (its 6 × 2 × 1 box).
    pub cells: usize,
    /// Indenter hexahedra across x and y (half as many layers).
    pub indenter_cells: usize,
    /// Coulomb's μ.
    pub friction: f64,
    /// How far the indenter's top moves down.
    pub press: f64,
    /// How far it then moves along x.
    pub slide: f64,
    /// Load steps (a fifth of them press).
    pub steps: usize,
}

impl Default for Ironing {
    /// 4 cells per unit in the slab (24 × 8 × 4), 8 across the indenter,
    /// frictionless, pressed by 0.1 and slid by 3 over 20 steps.
    fn default() -> Self {
        Ironing { cells: 4, indenter_cells: 8, friction: 0.0, press: 0.1, slide: 3.0, steps: 20 }
    }
}

/// The problem (module doc).
///
/// # Errors
/// None for sensible sizes (the meshes' faces are found by the grid).
///
/// # Panics
/// If `cells`, `indenter_cells` or `steps` is zero.
pub fn ironing(p: &Ironing) -> Result<Problem, MeshError> {
    let (n, m) = (p.cells, p.indenter_cells);
    let slab = block(6 * n, 2 * n, n, |u, v, w| [6.0 * u, 2.0 * v, w], BlockKind::Hex);
    let layers = (m / 2).max(1);
    let indenter = block(
        m,
        m,
        layers,
        |u, v, w| {
            let x = 0.5 + u;
            let bottom = 2.0 - (1.0 - (x - 1.0).powi(2)).sqrt();
            [x, 0.5 + v, bottom + (2.0 - bottom) * w]
        },
        BlockKind::Hex,
    );
    let sides = [("bottom", Side::ZMin), ("top", Side::ZMax)];
    let with_law = |body: crate::ProblemBody| crate::ProblemBody { law: Law::NeoHookean, ..body };
    let slab_material = Material::new(100.0, 0.3).expect("valid constants");
    let indenter_material = Material::new(1000.0, 0.3).expect("valid constants");
    let bodies = vec![
        with_law(block_body("slab", slab, &Grid::new(6 * n, 2 * n, n), slab_material, &sides)?),
        with_law(block_body("indenter", indenter, &Grid::new(m, m, layers), indenter_material, &sides)?),
    ];
    let (bottom, top) = (0, 1);
    let options = MortarOptions {
        multiplier: Multiplier::Dual,
        facing: Facing::Opposite,
        max_gap: MaxGap::Absolute(0.3),
        ..MortarOptions::default()
    };
    let pressed = 0.2;
    let press = Amplitude::new(vec![[0.0, 0.0], [pressed, 1.0], [1.0, 1.0]]).expect("increasing");
    let slide = Amplitude::new(vec![[0.0, 0.0], [pressed, 0.0], [1.0, 1.0]]).expect("increasing");
    let top_of = |values, amplitude| Support {
        amplitude,
        ..Support::new(SurfaceId { body: 1, surface: top }, values)
    };
    Ok(Problem {
        bodies,
        interfaces: vec![ProblemInterface {
            master: SurfaceId { body: 0, surface: top },
            slave: SurfaceId { body: 1, surface: bottom },
            options,
            kind: Coupling::Contact,
            friction: p.friction,
        }],
        supports: vec![
            Support::new(SurfaceId { body: 0, surface: bottom }, [Some(0.0); 3]),
            top_of([None, Some(0.0), Some(-p.press)], press),
            top_of([Some(p.slide), None, None], slide),
        ],
        steps: LoadSteps::equal(p.steps).expect("at least one step"),
        ..Problem::default()
    })
}
