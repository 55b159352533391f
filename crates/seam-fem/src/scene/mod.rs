//! Built-in problems that make their own meshes.
//!
//! [`warped_glue`] is the paper's first example (Fig. 2): the unit cube cut by
//! the warped surface z = s(x, y) into two bodies meshed independently with
//! hexahedra, the upper (slave) side `ratio` times coarser than the lower
//! (master) side, glued by mortar; clamped at the bottom, loaded at the top by a
//! traction with a shear part.
//!
//! [`bulging_contact`] is the paper's second example (Fig. 3): two hexahedral
//! blocks whose facing sides bulge towards each other with off-centre bulges of
//! different shapes, touching at one point, meshed independently (the master
//! `ratio` times finer); the lower bottom clamped, the upper top pressed down
//! and sheared by a prescribed displacement; frictionless contact with lumped
//! multipliers.
//!
//! [`hertz`] validates contact: an elastic indenter with a spherical face
//! pressed on an elastic block, against Hertz's contact radius and pressure;
//! [`cattaneo_mindlin`] presses the same indenter (a half model) and pushes it
//! sideways with friction, against Cattaneo and Mindlin's partial slip.
//!
//! [`ironing`] is finite deformation with large sliding: a hyperelastic
//! indenter pressed into a softer slab and slid along it (Puso & Laursen
//! 2004), frictionless or with Coulomb friction.

mod bulging;
mod cattaneo_mindlin;
mod hertz;
mod ironing;
mod polar;
mod warped_glue;

pub use bulging::{bulging_contact, Bulge, BulgingContact};
pub use cattaneo_mindlin::{cattaneo_mindlin, AxisPoint, CattaneoMindlin, PartialSlip};
pub use hertz::{hertz, Hertz, Layout};
pub use ironing::{ironing, Ironing};
pub use warped_glue::{warped_glue, WarpedGlue};

use crate::generate::{Grid, Side};
use crate::material::Material;
use crate::problem::ProblemBody;
use seam::{MeshError, VolumeMesh};

/// A structured block (`mesh` on `grid`) as a body named `name`, without body
/// force, whose boundary surfaces are the named `sides`.
fn block_body(
    name: &str,
    mesh: VolumeMesh,
    grid: &Grid,
    material: Material,
    sides: &[(&str, Side)],
) -> Result<ProblemBody, MeshError> {
    let surfaces = sides
        .iter()
        .map(|&(s, side)| Ok((s.to_string(), grid.side_faces(&mesh, side)?)))
        .collect::<Result<_, MeshError>>()?;
    Ok(ProblemBody::new(name, mesh, material, surfaces))
}

/// The sides "bottom" (z-min) and "top" (z-max).
const BOTTOM_TOP: [(&str, Side); 2] = [("bottom", Side::ZMin), ("top", Side::ZMax)];
