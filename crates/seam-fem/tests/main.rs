//! The integration tests of `seam-fem`, one module per subject, in one test
//! binary (one link per crate).

mod backend;
mod cattaneo_mindlin;
mod common;
mod contact;
mod contact_bulging;
mod contact_hertz;
mod contact_hertz_second_order;
mod contact_second_order;
mod convergence;
mod element;
mod finite_contact;
mod finite_convergence;
mod friction;
mod glue;
mod glue_convergence;
mod glue_convergence_second_order;
mod glue_oscillation;
mod glue_supports;
mod hyperelastic;
mod mixed;
mod patch;
#[cfg(feature = "petsc")]
mod petsc;
mod second_order;
mod stiffness;
