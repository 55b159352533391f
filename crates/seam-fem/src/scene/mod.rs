//! Built-in problems that make their own meshes.
//!
//! [`warped_glue`] is the paper's first example (Fig. 2): the unit cube cut by
//! the warped surface z = s(x, y) into two bodies meshed independently with
//! hexahedra, the upper (slave) side `ratio` times coarser than the lower
//! (master) side, glued by mortar; clamped at the bottom, loaded at the top by a
//! traction with a shear part.

mod warped_glue;

pub use warped_glue::{warped_glue, WarpedGlue};
