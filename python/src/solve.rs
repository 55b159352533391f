//! `seam.solve`: a case (file or dict) solved as `seam solve` solves it.

use std::path::{Path, PathBuf};

use numpy::ndarray::Array2;
use numpy::{PyArray1, ToPyArray};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyList, PyTuple};
use seam_case::solve::{LinearSolver, SolveOptions, Solved, StepState};
use seam_case::Case;
use seam_case::Failure;

use crate::error::{detach, failure_error, CaseError, Entry};
use crate::mortar::thread_pool;

/// A solved case: `summary`, `bodies`, `interfaces`, `steps` and `write`.
#[pyclass(name = "Solution", module = "seam", frozen)]
pub struct PySolution {
    inner: Solved,
}

/// An (n, k) float64 array of `values` (k per row).
fn rows<'py>(py: Python<'py>, values: Vec<f64>, k: usize) -> PyResult<Bound<'py, PyAny>> {
    let n = values.len() / k;
    let array = Array2::from_shape_vec((n, k), values)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    Ok(array.to_pyarray(py).into_any())
}

/// A `types.SimpleNamespace` of `items`.
fn namespace<'py>(py: Python<'py>, items: &Bound<'py, PyDict>) -> PyResult<Bound<'py, PyAny>> {
    py.import("types")?.getattr("SimpleNamespace")?.call((), Some(items))
}

#[pymethods]
impl PySolution {
    /// The content of summary.json, a dict (as `json.loads` reads the file).
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let json = serde_json::to_string(&self.inner.summary).map_err(|e| {
            pyo3::exceptions::PyValueError::new_err(format!("cannot convert the summary: {e}"))
        })?;
        py.import("json")?.call_method1("loads", (json,))
    }

    /// Per body name, in case order: an object with `points` (n×3),
    /// `displacement` (n×3; row i is the i-th node of the body's mesh file),
    /// `stress` (cells×6, Voigt xx yy zz yz xz xy, at the cell centres) and
    /// `von_mises` (per cell), all float64, and `node_id` (n) and
    /// `element_id` (per cell), int64: the mesh file's ids (Gmsh tags or
    /// Abaqus ids); the final state.
    #[getter]
    fn bodies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        bodies(py, &self.inner, self.inner.last())
    }

    /// Per interface, in case order: an object with `master`, `slave`
    /// ("body:surface"), `kind` ("glue" or "contact") and the point fields of
    /// its VTU file on the slave surface's own points, as float64 arrays:
    /// `points`, `traction`, `normal_traction`, `tangential_traction`,
    /// `normal`, `displacement`, `constrained`, `body_point` and `node_id`
    /// (int64: the 0-based index in the body's mesh and the file's id), and for
    /// contact `contact_pressure`, `gap`, `initial_gap`, `active`; the final
    /// state.
    #[getter]
    fn interfaces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        interfaces(py, &self.inner, self.inner.last())
    }

    /// Per load step (`[load]`), oldest first, the last one the final
    /// state: an object with `time`, `summary` (the step's entry of
    /// `summary["steps"]`), `bodies` and `interfaces` as those of the
    /// Solution.
    #[getter]
    fn steps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let summary = self.summary(py)?;
        let out = PyList::empty(py);
        for (k, state) in self.inner.steps.iter().enumerate() {
            let items = PyDict::new(py);
            items.set_item("time", state.time)?;
            items.set_item("summary", summary.get_item("steps")?.get_item(k)?)?;
            items.set_item("bodies", bodies(py, &self.inner, state)?)?;
            items.set_item("interfaces", interfaces(py, &self.inner, state)?)?;
            out.append(namespace(py, &items)?)?;
        }
        Ok(out)
    }

    /// Writes exactly the files `seam solve` writes, into `dir`: `<body>.vtu`
    /// per body, `<slave body>_<surface>_interface.vtu` per interface (with
    /// several load steps also `steps/` and a `.pvd` collection per body
    /// and interface) and summary.json last, all-or-nothing. Existing files are only replaced
    /// with `force`. Returns the summary written, a dict.
    ///
    /// While another run (a `seam` process, another thread) writes into
    /// `dir`, this one waits for it; what an interrupted run left there is
    /// recovered first. Each is said in a `seam.OutputWarning`.
    ///
    /// Raises:
    ///     SolveError: an output exists without force, or cannot be written.
    #[pyo3(signature = (dir, force = false))]
    fn write<'py>(&self, py: Python<'py>, dir: PathBuf, force: bool) -> PyResult<Bound<'py, PyAny>> {
        let summary = detach(py, Entry::Solve, || self.inner.write(&dir, force))?.map_err(failure_error)?;
        let json = serde_json::to_string(&summary).map_err(|e| {
            pyo3::exceptions::PyValueError::new_err(format!("cannot convert the summary: {e}"))
        })?;
        py.import("json")?.call_method1("loads", (json,))
    }

    fn __repr__(&self) -> String {
        let s = &self.inner.summary;
        format!("<seam.Solution of {}: {} bodies, {} interfaces>", s.case, s.bodies.len(), s.interfaces.len())
    }
}

/// The field `name` of `fields`, as an (n, k) array (k its components).
fn field<'py>(py: Python<'py>, fields: &[seam_io::Field], name: &str) -> PyResult<Bound<'py, PyAny>> {
    let f = fields
        .iter()
        .find(|f| f.name == name)
        .ok_or_else(|| pyo3::exceptions::PyValueError::new_err(format!("no field {name}")))?;
    match f.components {
        1 => Ok(PyArray1::from_slice(py, &f.values).into_any()),
        k => rows(py, f.values.clone(), k),
    }
}

/// The id field `name` of `fields` (whole numbers), as an int64 array.
fn ids<'py>(py: Python<'py>, fields: &[seam_io::Field], name: &str) -> PyResult<Bound<'py, PyAny>> {
    let f = fields
        .iter()
        .find(|f| f.name == name)
        .ok_or_else(|| pyo3::exceptions::PyValueError::new_err(format!("no field {name}")))?;
    Ok(PyArray1::from_vec(py, f.values.iter().map(|&v| v as i64).collect()).into_any())
}

/// [`PySolution::bodies`] of the load step `state`.
fn bodies<'py>(py: Python<'py>, s: &Solved, state: &StepState) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    for (body, (point, cell)) in s.problem.bodies.iter().zip(&state.body_files) {
        let items = PyDict::new(py);
        items.set_item("name", &body.name)?;
        items.set_item("points", rows(py, body.mesh.points().iter().flatten().copied().collect(), 3)?)?;
        items.set_item("displacement", field(py, point, "displacement")?)?;
        items.set_item("stress", field(py, cell, "stress")?)?;
        items.set_item("von_mises", field(py, cell, "von_mises")?)?;
        items.set_item("node_id", ids(py, point, "node_id")?)?;
        items.set_item("element_id", ids(py, cell, "element_id")?)?;
        out.set_item(&body.name, namespace(py, &items)?)?;
    }
    Ok(out)
}

/// [`PySolution::interfaces`] of the load step `state`.
fn interfaces<'py>(py: Python<'py>, s: &Solved, state: &StepState) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for (r, f) in state.interfaces.iter().zip(&s.summary.interfaces) {
        let items = PyDict::new(py);
        items.set_item("master", &f.master)?;
        items.set_item("slave", &f.slave)?;
        items.set_item("kind", f.kind)?;
        items.set_item("points", rows(py, r.mesh.points().iter().flatten().copied().collect(), 3)?)?;
        for field in &r.fields {
            match (field.name.as_str(), field.components) {
                ("body_point", _) => {
                    let body_point: Vec<i64> = r.body_point.iter().map(|&p| p as i64).collect();
                    items.set_item("body_point", PyArray1::from_vec(py, body_point))?
                }
                ("node_id", _) => items.set_item("node_id", ids(py, &r.fields, "node_id")?)?,
                (name, 1) => items.set_item(name, PyArray1::from_slice(py, &field.values))?,
                (name, k) => items.set_item(name, rows(py, field.values.clone(), k)?)?,
            }
        }
        out.append(namespace(py, &items)?)?;
    }
    Ok(out)
}

/// The first float that is not finite in `value` (dicts and lists looked
/// into), as "`path`: inf is not a finite number", the path written as
/// `body[0].young`.
fn non_finite(value: &Bound<'_, PyAny>, path: &str) -> PyResult<Option<String>> {
    if let Ok(x) = value.cast::<PyFloat>() {
        let x = x.value();
        return Ok((!x.is_finite()).then(|| format!("{path}: {x} is not a finite number")));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        for (key, item) in dict.iter() {
            let key = key.str()?.to_string();
            let path = if path.is_empty() { key } else { format!("{path}.{key}") };
            if let Some(problem) = non_finite(&item, &path)? {
                return Ok(Some(problem));
            }
        }
    } else if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        for (i, item) in value.try_iter()?.enumerate() {
            if let Some(problem) = non_finite(&item?, &format!("{path}[{i}]"))? {
                return Ok(Some(problem));
            }
        }
    }
    Ok(None)
}

/// Solves a case as `seam solve` does, without writing anything.
///
/// Args:
///     case: The path of a case file (str or os.PathLike), or a dict with the
///         schema of a case file, whose relative paths are relative to the
///         current working directory.
///     solver: "direct", "pcg" or "petsc" (a PETSc KSP, by default CG with
///         algebraic multigrid; needs the module built with the cargo
///         feature `petsc`).
///     threads: Worker threads (default: all cores).
///     rtol: PCG and PETSc stop when ‖r‖₂ ≤ rtol ‖b‖₂ (`seam solve --rtol`),
///         in (0, 1).
///     petsc_options: PETSc options as on its command line
///         (`seam solve --petsc-options`), e.g. "-pc_type hypre"; they stay
///         in PETSc's options database for later solves of the process.
///
/// Returns:
///     A Solution: `summary`, `bodies`, `interfaces`, `steps`, `write(dir, force)`.
///
/// Raises:
///     SolveError: with the one-line message of `seam solve`; its subclasses
///         CaseError (a bad case, option or mesh), NoCouplingError (surfaces
///         that do not meet) and ConvergenceError (an iteration that did not
///         converge); SolveError itself for anything else (a singular
///         system, an unwritable output, …).
///     ValueError: an unknown solver, threads < 1.
#[pyfunction]
#[pyo3(signature = (case, solver = "direct", threads = None, *, rtol = 1e-10, petsc_options = None))]
pub fn solve(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    solver: &str,
    threads: Option<i64>,
    rtol: f64,
    petsc_options: Option<&str>,
) -> PyResult<PySolution> {
    let solver: LinearSolver = crate::mortar::parse(solver)?;
    if petsc_options.is_some() && solver != LinearSolver::Petsc {
        return Err(pyo3::exceptions::PyValueError::new_err("petsc_options needs solver=\"petsc\""));
    }
    let petsc_options = petsc_options.map(str::to_string);
    let options = SolveOptions { solver, petsc_options, rtol, ..SolveOptions::default() };
    let pool = thread_pool(threads)?;
    let source = match case.cast::<PyDict>() {
        Ok(dict) => {
            // JSON has no inf or NaN: name the field that holds one.
            if let Some(problem) = non_finite(dict.as_any(), "")? {
                return Err(CaseError::new_err(format!("case dict: {problem}")));
            }
            let json: String = py.import("json")?.call_method1("dumps", (dict,))?.extract()?;
            Err(json)
        }
        Err(_) => Ok(case.extract::<PathBuf>()?),
    };
    let run = move || -> Result<Solved, Failure> {
        match &source {
            Ok(path) => seam_case::solve::solve_case(path, &options),
            Err(json) => {
                let bad = |e: seam_case::CaseError| Failure::Case(format!("case dict: {e}"));
                let case = Case::from_json(json, Path::new("")).map_err(bad)?;
                case.check_mesh_files().map_err(bad)?;
                seam_case::solve::solve_checked_case(case, Path::new("<case dict>"), &options)
            }
        }
    };
    let solved = detach(py, Entry::Solve, || match &pool {
        Some(pool) => pool.install(run),
        None => run(),
    })?
    .map_err(failure_error)?;
    Ok(PySolution { inner: solved })
}
