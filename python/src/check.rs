//! `seam.check`: the report of `seam check --json` as a dict.

use std::path::PathBuf;

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::error::{check_error, detach, msh_error, Entry};
use crate::mesh::{MeshArg, PyMesh};
use crate::mortar::Coupling;

/// A side of `check` and its name in the report: a path read as `read_mesh`
/// reads it (named by the path), else as `assemble` takes it (named by its
/// role, `what`). Faces keep the Gmsh element tags `read_mesh` gives them.
fn side<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<(MeshArg<'py>, String)> {
    match obj.extract::<PathBuf>() {
        Ok(path) => {
            let (inner, face_tags) =
                detach(obj.py(), Entry::ReadMesh, || seam_io::read_tagged_surface_file(&path, None))?
                    .map_err(msh_error)?;
            let mesh = Bound::new(obj.py(), PyMesh { inner, face_tags })?;
            Ok((MeshArg::Object(mesh), path.display().to_string()))
        }
        Err(_) => match MeshArg::extract(obj, what) {
            Ok(mesh) => Ok((mesh, what.to_string())),
            Err(e) if e.is_instance_of::<PyTypeError>(obj.py()) && !obj.is_instance_of::<PyTuple>() => {
                Err(PyTypeError::new_err(format!(
                    "{what} must be a seam.Mesh, a (points, faces) tuple or the path of an MSH file, got {}",
                    obj.get_type().name()?
                )))
            }
            Err(e) => Err(e),
        },
    }
}

/// Reports how two surfaces meet: the report of `seam check --json`, as a dict.
///
/// Assembles the operator as `assemble` does, then measures the coverage, the
/// signed normal gaps of the covered slave points, the orientation and the
/// quality of both surfaces, and invariants of the operator: D·1 = B·1,
/// 1ᵀD1 = covered area, T·1 = 1, the covered area at most the slave area,
/// D's row sums at most the nodal areas, and (standard and dual multipliers)
/// linear fields reproduced on flat parts. The GIL is released while
/// computing.
///
/// Args:
///     master: The master (mortar) side: a Mesh, a (points, faces) tuple, or the
///         path of a Gmsh MSH file (str or os.PathLike), read as `read_mesh`
///         reads it (all 2-D elements; for a physical group, pass
///         `read_mesh(path, group)`).
///     slave: The slave (non-mortar) side, of the same kinds.
///     multiplier, max_gap, facing, threads, max_angle, warped_quad_degree:
///         As for `assemble`.
///
/// Returns:
///     A dict with the keys, in this order, of `seam check --json`: master,
///     slave (the path given for a file, else "master" and "slave"),
///     slave_faces, master_faces, slave_area, master_area, covered_area,
///     covered_fraction, uncovered_slave_nodes, uncovered_examples (up to five
///     [1-based row, [x, y, z]]), gap_histogram (ten bins {from, to, nodes}),
///     min_normal_gap, max_normal_gap (None if no slave point is covered),
///     slave_orientation_conflicts, master_orientation_conflicts,
///     slave_quality and master_quality ({min_angle_degrees,
///     max_angle_degrees, max_warp}), invariants ([{name, value, tolerance,
///     ok, offending_faces, offending_nodes}]: where an invariant fails, up
///     to five slave faces and slave nodes as 1-based rows, worst first), ok
///     (every slave point covered, every invariant kept) and face_ids (how
///     offending_faces names faces: "gmsh element tags" for a slave read
///     from the elements of an MSH file, by path or `read_mesh`, else
///     "1-based face indices").
///
/// Raises:
///     As `assemble`; for a path as `read_mesh` (FileNotFoundError, MshError,
///     ...); FactorizationError when T = D⁻¹B cannot be formed.
#[pyfunction]
#[pyo3(signature = (master, slave, *, multiplier = "standard", max_gap = None, facing = "any", threads = None, max_angle = 45.0, warped_quad_degree = None))]
#[allow(clippy::too_many_arguments)]
pub fn check<'py>(
    py: Python<'py>,
    master: &Bound<'py, PyAny>,
    slave: &Bound<'py, PyAny>,
    multiplier: &str,
    max_gap: Option<f64>,
    facing: &str,
    threads: Option<i64>,
    max_angle: f64,
    warped_quad_degree: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let coupling =
        Coupling::new(multiplier, max_gap, facing, max_angle, warped_quad_degree)?.on_threads(threads)?;
    let (master, master_name) = side(master, "master")?;
    let (slave, slave_name) = side(slave, "slave")?;
    let (m, s, tags) = (master.get(), slave.get(), slave.face_tags());
    let json = coupling
        .run(py, |options| {
            let check = seam_case::check(m, s, options, (&master_name, &slave_name), tags)?;
            Ok(serde_json::to_string(&check.report))
        })?
        .map_err(check_error)?
        .map_err(|e| PyValueError::new_err(format!("cannot convert the report: {e}")))?;
    // json.loads: exactly what a script reading `seam check --json` gets.
    py.import("json")?.call_method1("loads", (json,))?.cast_into::<PyDict>().map_err(PyErr::from)
}
