//! `seam.assemble` and `seam.Mortar`.

use std::sync::OnceLock;

use numpy::PyArray1;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use seam::{MaxGap, MortarOptions, Named, Transfer};

use crate::convert::{csr_matrix, finite, nodal_values_from, nodal_values_into, short};
use crate::error::{detach, mortar_error, Entry};
use crate::mesh::MeshArg;

/// A scalar of the summary (numbers; anything else as its JSON text).
fn json_scalar(py: Python<'_>, value: serde_json::Value) -> PyResult<Bound<'_, PyAny>> {
    use pyo3::IntoPyObjectExt;
    match value {
        serde_json::Value::Number(n) => match (n.as_u64(), n.as_i64(), n.as_f64()) {
            (Some(u), _, _) => u.into_bound_py_any(py),
            (None, Some(i), _) => i.into_bound_py_any(py),
            (None, None, Some(f)) => f.into_bound_py_any(py),
            _ => n.to_string().into_bound_py_any(py),
        },
        serde_json::Value::Bool(b) => b.into_bound_py_any(py),
        serde_json::Value::String(s) => s.into_bound_py_any(py),
        serde_json::Value::Null => f64::NAN.into_bound_py_any(py),
        other => other.to_string().into_bound_py_any(py),
    }
}

/// The value of a [`Named`] option called `name`; a `ValueError` naming the others.
pub(crate) fn parse<T: Named>(name: &str) -> PyResult<T> {
    T::from_name(name).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The coupling options `assemble` and `check` share, checked, and the worker
/// threads to run on.
pub struct Coupling {
    options: MortarOptions,
    /// `None`: rayon's global pool (all cores).
    pool: Option<rayon::ThreadPool>,
}

impl Coupling {
    /// The options from the keyword arguments of `assemble` and `check`.
    pub fn new(
        multiplier: &str,
        max_gap: Option<f64>,
        facing: &str,
        max_angle: f64,
        warped_quad_degree: Option<usize>,
    ) -> PyResult<Self> {
        let options = MortarOptions {
            multiplier: parse(multiplier)?,
            facing: parse(facing)?,
            max_gap: max_gap.map_or(MaxGap::DEFAULT, MaxGap::Absolute),
            max_angle_degrees: max_angle,
            warped_quad_degree,
            ..MortarOptions::default()
        };
        Ok(Coupling { options, pool: None })
    }

    /// Runs on `threads` worker threads (checked against the cores), or on all
    /// cores for `None`.
    pub fn on_threads(self, threads: Option<i64>) -> PyResult<Self> {
        Ok(Coupling { pool: thread_pool(threads)?, ..self })
    }

    /// `f(options)` on the worker threads, the GIL released; a panic becomes
    /// `seam.MortarError`.
    pub fn run<T: Send>(&self, py: Python<'_>, f: impl FnOnce(&MortarOptions) -> T + Send) -> PyResult<T> {
        detach(py, Entry::Mortar, || match &self.pool {
            Some(pool) => pool.install(|| f(&self.options)),
            None => f(&self.options),
        })
    }
}

/// Assembles the mortar matrices B and D between two surface meshes.
///
/// Rows are slave points and columns master points, numbered as in the meshes;
/// points off the interface get empty rows and columns. The result is the same,
/// bit for bit, for any number of threads. The GIL is released while assembling.
///
/// Args:
///     master: The master (mortar) side: a Mesh or a (points, faces) tuple.
///     slave: The slave (non-mortar) side, carrying the multipliers: a Mesh or
///         a (points, faces) tuple.
///     multiplier: "standard" (D is the slave mass matrix of the covered part),
///         "dual" (biorthogonal basis, D diagonal) or "lumped" (row-summed D).
///     max_gap: Largest normal distance between paired points, a length;
///         None for half the local slave face diameter.
///     facing: "any" (either normal orientation) or "opposite" (the faces face
///         each other, as outward normals of two bodies do).
///     threads: Worker threads (at most 4 per core); None uses all cores.
///     max_angle: Largest angle between slave and master normals, in degrees.
///     warped_quad_degree: Triangle-rule degree (1 to 20) on warped slave quads;
///         None chooses it per face.
///
/// Returns:
///     The assembled operator, a Mortar.
///
/// Raises:
///     NoOverlapError: No master face meets a slave face within the limits.
///     InvalidOptionError: An option out of range (negative gap, angle outside
///         (0, 90), degree outside 1..20).
///     MeshError: A (points, faces) tuple that is not a valid mesh.
///     ValueError: An unknown multiplier or facing, threads < 1 or more than
///         4 per core, wrong shapes.
///     TypeError: master or slave of another type.
#[pyfunction]
#[pyo3(signature = (master, slave, multiplier = "standard", max_gap = None, facing = "any", threads = None, *, max_angle = 45.0, warped_quad_degree = None))]
#[allow(clippy::too_many_arguments)]
pub fn assemble(
    py: Python<'_>,
    master: &Bound<'_, PyAny>,
    slave: &Bound<'_, PyAny>,
    multiplier: &str,
    max_gap: Option<f64>,
    facing: &str,
    threads: Option<i64>,
    max_angle: f64,
    warped_quad_degree: Option<usize>,
) -> PyResult<PyMortar> {
    let coupling = Coupling::new(multiplier, max_gap, facing, max_angle, warped_quad_degree)?;
    let master = MeshArg::extract(master, "master")?;
    let slave = MeshArg::extract(slave, "slave")?;
    let coupling = coupling.on_threads(threads)?;
    let (m, s) = (master.get(), slave.get());
    let mortar = coupling.run(py, |options| seam::assemble(m, s, options))?.map_err(mortar_error)?;
    Ok(PyMortar::from(mortar))
}

/// The assembled mortar operator: B, D and the transfer T = D⁻¹B.
///
/// Rows of B and D are slave points, columns of B master points. The transfer
/// is restricted to the covered slave points: uncovered ones receive 0.
#[pyclass(name = "Mortar", module = "seam", frozen)]
pub struct PyMortar {
    inner: seam::Mortar,
    /// Built on first use (for standard multipliers it prepares D_CC for
    /// conjugate gradients, factorised once they have cost as much).
    transfer: OnceLock<Transfer>,
}

impl From<seam::Mortar> for PyMortar {
    fn from(inner: seam::Mortar) -> Self {
        PyMortar { inner, transfer: OnceLock::new() }
    }
}

impl From<PyMortar> for seam::Mortar {
    fn from(m: PyMortar) -> Self {
        m.inner
    }
}

impl PyMortar {
    fn transfer_operator(&self, py: Python<'_>) -> PyResult<&Transfer> {
        if let Some(t) = self.transfer.get() {
            return Ok(t);
        }
        let t = detach(py, Entry::Mortar, || self.inner.transfer())?.map_err(mortar_error)?;
        Ok(self.transfer.get_or_init(|| t))
    }
}

#[pymethods]
impl PyMortar {
    /// B, scipy.sparse.csr_matrix of shape (n_slave_points, n_master_points):
    /// B[p, q] = ∫ ψ_p (λ_q ∘ Φ) over the slave surface. A new matrix at each access.
    #[getter(B)]
    fn b<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        csr_matrix(py, &self.inner.b)
    }

    /// D, scipy.sparse.csr_matrix of shape (n_slave_points, n_slave_points):
    /// D[p, q] = ∫ ψ_p λ_q over the covered slave surface (diagonal for "dual"
    /// and "lumped"). A new matrix at each access.
    #[getter(D)]
    fn d<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        csr_matrix(py, &self.inner.d)
    }

    /// T = D⁻¹B as a scipy.sparse.csr_matrix of shape (n_slave_points,
    /// n_master_points) when D is diagonal ("dual", "lumped"), with empty rows
    /// for uncovered slave points; None otherwise (T is dense in general: use
    /// `transfer`).
    #[getter(T)]
    fn t<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.transfer_operator(py)?.matrix().map(|t| csr_matrix(py, t)).transpose()
    }

    /// Transfers nodal values from the master to the slave points: u_s = T u_m.
    ///
    /// Works for every multiplier (for "standard", by solving with D restricted
    /// to the covered slave points: conjugate gradients, or a sparse Cholesky
    /// factorisation once applied often enough that it pays).
    /// Uncovered slave points get 0. The GIL is released during the solve.
    ///
    /// Args:
    ///     values: Array-like of shape (n_master_points,) or (n_master_points, k).
    ///
    /// Returns:
    ///     float64 array of shape (n_slave_points,) or (n_slave_points, k).
    ///
    /// Raises:
    ///     ValueError: values of the wrong shape, or not finite (NaN, inf).
    ///     FactorizationError: D on the covered points is not positive definite.
    fn transfer<'py>(&self, py: Python<'py>, values: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let (rows, cols) = (self.inner.b.nrows, self.inner.b.ncols);
        let (v, k) = nodal_values_from(values, "values", cols, "master point")?;
        let t = self.transfer_operator(py)?;
        let width = k.unwrap_or(1);
        let out = if width == 0 { Vec::new() } else { detach(py, Entry::Mortar, || t.apply(&v, width))? };
        finite(&out, "the result", k, "slave point")?;
        nodal_values_into(py, out, rows, k)
    }

    /// Transfers nodal loads from the slave to the master points conservatively:
    /// f_m = Tᵀ f_s, so that the total is kept, sum(f_m) = sum(f_s), for loads
    /// on covered slave points (loads on uncovered ones are dropped).
    ///
    /// Args:
    ///     loads: Array-like of shape (n_slave_points,) or (n_slave_points, k).
    ///
    /// Returns:
    ///     float64 array of shape (n_master_points,) or (n_master_points, k).
    ///
    /// Raises:
    ///     ValueError: loads of the wrong shape, or not finite (NaN, inf).
    ///     FactorizationError: D on the covered points is not positive definite.
    fn transfer_conservative<'py>(
        &self,
        py: Python<'py>,
        loads: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (rows, cols) = (self.inner.b.nrows, self.inner.b.ncols);
        let (f, k) = nodal_values_from(loads, "loads", rows, "slave point")?;
        let t = self.transfer_operator(py)?;
        let width = k.unwrap_or(1);
        let out =
            if width == 0 { Vec::new() } else { detach(py, Entry::Mortar, || t.apply_transpose(&f, width))? };
        finite(&out, "the result", k, "master point")?;
        nodal_values_into(py, out, cols, k)
    }

    /// Totals over the interface, a dict: the fields of the Rust MortarSummary
    /// (slave_nodes, master_nodes, slave_faces, master_faces, candidate_pairs,
    /// intersecting_pairs, segments, slave_area, covered_area,
    /// uncovered_slave_nodes, max_gap, max_overlap, inverse_failures,
    /// dual_fallbacks) and multiplier.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        // Through serde, so that fields added to the Rust struct appear here too.
        let d = match serde_json::to_value(&self.inner.summary) {
            Ok(serde_json::Value::Object(fields)) => {
                let d = PyDict::new(py);
                for (key, value) in fields {
                    d.set_item(key, json_scalar(py, value)?)?;
                }
                d
            }
            other => return Err(PyValueError::new_err(format!("cannot convert the summary: {other:?}"))),
        };
        d.set_item("multiplier", self.inner.multiplier.name())?;
        Ok(d)
    }

    /// Per slave point, the covered fraction of ∫ λ_p (0 off the surface),
    /// float64 array of shape (n_slave_points,).
    #[getter]
    fn coverage<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.node_coverage)
    }

    /// Per slave point, whether it counts as covered (coverage above 1e-10),
    /// bool array of shape (n_slave_points,): the rows T acts on.
    #[getter]
    fn covered<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        PyArray1::from_slice(py, &self.inner.covered)
    }

    /// Per slave point, whether some slave face uses it, bool array of shape
    /// (n_slave_points,).
    #[getter]
    fn on_surface<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        PyArray1::from_slice(py, &self.inner.on_surface)
    }

    /// The slave points on the surface that are not covered, ascending int64
    /// array.
    #[getter]
    fn uncovered_nodes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_vec(py, self.inner.uncovered_nodes().into_iter().map(|p| p as i64).collect())
    }

    /// The multiplier the matrices were built with: "standard", "dual" or
    /// "lumped".
    #[getter]
    fn multiplier(&self) -> &'static str {
        self.inner.multiplier.name()
    }

    /// (n_slave_points, n_master_points), the shape of B and T.
    #[getter]
    fn shape(&self) -> (usize, usize) {
        (self.inner.b.nrows, self.inner.b.ncols)
    }

    fn __repr__(&self) -> String {
        let s = &self.inner.summary;
        format!(
            "<seam.Mortar: {} multipliers, {} slave × {} master points, B nnz {}, D nnz {}, \
             covered area {} of {}, {} uncovered slave nodes>",
            self.inner.multiplier.name(),
            self.inner.b.nrows,
            self.inner.b.ncols,
            self.inner.b.nnz(),
            self.inner.d.nnz(),
            short(s.covered_area),
            short(s.slave_area),
            s.uncovered_slave_nodes
        )
    }
}

/// A pool of `threads` worker threads (`None`: rayon's global pool).
///
/// Raises ValueError for fewer than 1 or more than a few per core.
pub fn thread_pool(threads: Option<i64>) -> PyResult<Option<rayon::ThreadPool>> {
    let Some(n) = threads else { return Ok(None) };
    let n = match usize::try_from(n) {
        Ok(n) if n >= 1 => seam_case::threads::check_threads(n)
            .map_err(|e| PyValueError::new_err(format!("threads={n}: {e}")))?,
        _ => return Err(PyValueError::new_err(format!("threads must be at least 1, got {n}"))),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map_err(|e| PyOSError::new_err(format!("cannot start {n} worker threads: {e}")))?;
    Ok(Some(pool))
}
