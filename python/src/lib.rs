//! Python bindings of seam: conversions only (NumPy/SciPy ↔ `seam`, `seam-io`).
//!
//! | Python | Rust |
//! |---|---|
//! | `seam.Mesh` | [`seam::SurfaceMesh`] ([`mesh::PyMesh`]) |
//! | `seam.read_mesh` | [`seam_io::read_tagged_surface_file`] (MSH, or `.inp` by extension) |
//! | `seam.assemble` | [`seam::assemble`] on a rayon pool, GIL released |
//! | `seam.check` | [`seam_case::check()`], its report through `json.loads` |
//! | `seam.Mortar` | [`seam::Mortar`] + its [`seam::Transfer`] ([`mortar::PyMortar`]) |
//! | `seam.solve`, `seam.Solution` | [`seam_case::solve`], GIL released ([`solve::PySolution`]) |
//! | `seam.catalogue` | [`seam::catalogue`]: the element kinds and their tables |
//! | exceptions, `seam.OutputWarning` | [`error`] |
//! | the `seam` command (`seam._cli`) | [`seam_cli::run`] (`cli::cli`) |
#![forbid(unsafe_code)]
// A cdylib without a Rust API: its crate doc is a map of its private parts.
#![allow(rustdoc::private_intra_doc_links)]

mod catalogue;
mod check;
mod cli;
mod convert;
mod error;
mod mesh;
mod mortar;
mod solve;

use pyo3::prelude::*;

#[pymodule]
fn _seam(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<mesh::PyMesh>()?;
    m.add_class::<mortar::PyMortar>()?;
    m.add_function(wrap_pyfunction!(mesh::read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(mortar::assemble, m)?)?;
    m.add_class::<solve::PySolution>()?;
    m.add_function(wrap_pyfunction!(check::check, m)?)?;
    m.add_function(wrap_pyfunction!(catalogue::catalogue, m)?)?;
    m.add_function(wrap_pyfunction!(solve::solve, m)?)?;
    m.add_function(wrap_pyfunction!(error::_panic_in, m)?)?;
    m.add_function(wrap_pyfunction!(cli::cli, m)?)?;
    m.add("MeshError", py.get_type::<error::MeshError>())?;
    m.add("MshError", py.get_type::<error::MshError>())?;
    m.add("MortarError", py.get_type::<error::MortarError>())?;
    m.add("InvalidOptionError", py.get_type::<error::InvalidOptionError>())?;
    m.add("NoOverlapError", py.get_type::<error::NoOverlapError>())?;
    m.add("FactorizationError", py.get_type::<error::FactorizationError>())?;
    m.add("SolveError", py.get_type::<error::SolveError>())?;
    m.add("CaseError", py.get_type::<error::CaseError>())?;
    m.add("NoCouplingError", py.get_type::<error::NoCouplingError>())?;
    m.add("ConvergenceError", py.get_type::<error::ConvergenceError>())?;
    m.add("OutputWarning", py.get_type::<error::OutputWarning>())?;
    seam_case::output::set_notice_handler(error::warn_notice);
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
