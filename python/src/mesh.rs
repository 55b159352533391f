//! `seam.Mesh` and `seam.read_mesh`.

use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::{PyArray2, ToPyArray};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use seam::{FaceKind, SurfaceMesh};

use crate::convert::{faces_from, index_rows, points_from, short};
use crate::error::{detach, mesh_error, msh_error, Entry};

/// A surface mesh of linear triangles and bilinear quadrilaterals (quads
/// possibly warped) and their second-order (curved) versions: 6-node triangles
/// (Tri6), 8-node (Quad8) and 9-node (Quad9) quadrilaterals, possibly mixed.
///
/// Points are kept in the order given (or the order of the file), including
/// points no face uses, so that matrix rows and columns follow that numbering.
///
/// Args:
///     points: Array-like of shape (n, 3) with the point coordinates (real
///         numbers; converted to float64).
///     faces: Integer array of shape (m, k) of 0-based point indices, k = 3
///         (triangles), 4 (quads), 6 (Tri6), 8 (Quad8) or 9 (Quad9); nodes in
///         Gmsh order: corners in cyclic order, then (second order) the
///         mid-edge nodes of edges 0-1, 1-2, ..., then (Quad9) the centre. Or a
///         list of such arrays and/or single faces, numbered in list order.
///
/// Raises:
///     ValueError: A wrong shape (also a face width other than 3, 4, 6, 7, 8, 9).
///     TypeError: Points that are not real numbers, faces that are not integers.
///     MeshError: A non-finite coordinate, an index out of range or negative, a
///         repeated corner, a zero-area face, no faces (a ValueError).
#[pyclass(name = "Mesh", module = "seam", frozen)]
pub struct PyMesh {
    pub inner: SurfaceMesh,
    /// The Gmsh element tag of each face, for a mesh `read_mesh` read from
    /// the elements of an MSH file (`check` names faces by them).
    pub face_tags: Option<Vec<u64>>,
}

impl From<SurfaceMesh> for PyMesh {
    fn from(inner: SurfaceMesh) -> Self {
        PyMesh { inner, face_tags: None }
    }
}

impl From<PyMesh> for SurfaceMesh {
    fn from(mesh: PyMesh) -> Self {
        mesh.inner
    }
}

/// Builds and checks a mesh from array-likes (the GIL is released for the check).
pub fn mesh_from_arrays(
    py: Python<'_>,
    points: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
) -> PyResult<SurfaceMesh> {
    let points = points_from(points)?;
    let faces = faces_from(faces)?;
    detach(py, Entry::Mesh, || SurfaceMesh::new(points, faces))?.map_err(mesh_error)
}

/// The same exception, its message prefixed by `what: ` (which side is wrong).
fn with_context(py: Python<'_>, e: PyErr, what: &str) -> PyErr {
    let message = format!("{what}: {}", e.value(py));
    match e.get_type(py).call1((message,)) {
        Ok(value) => PyErr::from_value(value),
        Err(_) => e,
    }
}

/// A master or slave argument: a `Mesh`, or a `(points, faces)` tuple.
pub enum MeshArg<'py> {
    Object(Bound<'py, PyMesh>),
    Built(SurfaceMesh),
}

impl MeshArg<'_> {
    pub fn get(&self) -> &SurfaceMesh {
        match self {
            MeshArg::Object(m) => &m.get().inner,
            MeshArg::Built(m) => m,
        }
    }

    /// The Gmsh element tags of the faces, if the mesh has them.
    pub fn face_tags(&self) -> Option<&[u64]> {
        match self {
            MeshArg::Object(m) => m.get().face_tags.as_deref(),
            MeshArg::Built(_) => None,
        }
    }
}

impl<'py> MeshArg<'py> {
    pub fn extract(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Self> {
        if let Ok(mesh) = obj.cast::<PyMesh>() {
            return Ok(MeshArg::Object(mesh.clone()));
        }
        match obj.cast::<PyTuple>() {
            Ok(t) if t.len() == 2 => mesh_from_arrays(obj.py(), &t.get_item(0)?, &t.get_item(1)?)
                .map(MeshArg::Built)
                .map_err(|e| with_context(obj.py(), e, what)),
            _ => Err(PyTypeError::new_err(format!(
                "{what} must be a seam.Mesh or a (points, faces) tuple, got {}",
                obj.get_type().name()?
            ))),
        }
    }
}

impl PyMesh {
    /// The faces of `kind`, in face order, as an int64 array of their nodes.
    fn rows<'py>(&self, py: Python<'py>, kind: FaceKind) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let faces = self.inner.faces().iter().filter(|f| f.kind() == kind);
        index_rows(py, kind.n_nodes(), faces.map(|f| f.nodes()))
    }
}

#[pymethods]
impl PyMesh {
    #[new]
    fn new(py: Python<'_>, points: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(mesh_from_arrays(py, points, faces)?.into())
    }

    /// Point coordinates, float64 array of shape (n_points, 3) (a copy).
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = self.inner.points().iter().flatten().copied().collect();
        let array = Array2::from_shape_vec((self.inner.n_points(), 3), flat)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        Ok(array.to_pyarray(py))
    }

    /// Linear triangles in face order, int64 array of shape (n, 3) of 0-based
    /// point indices.
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        self.rows(py, FaceKind::Tri3)
    }

    /// Bilinear quadrilaterals in face order, int64 array of shape (n, 4) of
    /// 0-based point indices.
    #[getter]
    fn quads<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        self.rows(py, FaceKind::Quad4)
    }

    /// Second-order 6-node triangles in face order, int64 array of shape
    /// (n, 6): corners, then the mid-edge nodes of edges 0-1, 1-2, 2-0.
    #[getter]
    fn tri6<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        self.rows(py, FaceKind::Tri6)
    }

    /// Second-order 8-node (serendipity) quadrilaterals in face order, int64
    /// array of shape (n, 8): corners, then the mid-edge nodes of edges 0-1,
    /// 1-2, 2-3, 3-0.
    #[getter]
    fn quad8<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        self.rows(py, FaceKind::Quad8)
    }

    /// Second-order 9-node (biquadratic) quadrilaterals in face order, int64
    /// array of shape (n, 9): corners, the mid-edge nodes of edges 0-1, 1-2,
    /// 2-3, 3-0, then the centre.
    #[getter]
    fn quad9<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        self.rows(py, FaceKind::Quad9)
    }

    /// Number of points (including points no face uses).
    #[getter]
    fn n_points(&self) -> usize {
        self.inner.n_points()
    }

    /// Number of faces (of every kind).
    #[getter]
    fn n_faces(&self) -> usize {
        self.inner.n_faces()
    }

    fn __repr__(&self) -> String {
        // First-order faces always, as "triangles" and "quads"; the others
        // by name where there are any.
        let mut kinds = Vec::new();
        for kind in FaceKind::ALL {
            let n = self.inner.faces().iter().filter(|f| f.kind() == kind).count();
            match kind.order() {
                1 => kinds.push(format!("{n} {}", if kind.is_triangle() { "triangles" } else { "quads" })),
                _ if n > 0 => kinds.push(format!("{n} {}", kind.name())),
                _ => {}
            }
        }
        let used = self.inner.used_points().iter().filter(|&&u| u).count();
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in self.inner.points() {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let bounds: Vec<String> = (0..3).map(|a| format!("[{}, {}]", short(lo[a]), short(hi[a]))).collect();
        let n = self.inner.n_points();
        let unused = if used < n { format!(" ({} not on a face)", n - used) } else { String::new() };
        format!("<seam.Mesh: {n} points{unused}, {}, bounds {}>", kinds.join(", "), bounds.join(" × "))
    }
}

/// Reads the surface to couple from a Gmsh MSH file (versions 4.1 and 2.2,
/// ASCII or binary) or, by its extension `.inp`, an Abaqus / CalculiX input
/// file.
///
/// Points are all the nodes of the file, in file order (0-based), whether or not
/// a selected face uses them. Faces are the elements of the physical group
/// `group` (of an `.inp` file: the faces of its `*SURFACE` of that name, in
/// any case); without a group, the 2-D elements of the file, or the boundary of
/// its volume cells if it has any. Faces may be 3-node triangles, 4-node quads
/// and their second-order versions (6-node triangles, 8- and 9-node quads; see
/// the `tri6`, `quad8` and `quad9` properties of Mesh), volume cells
/// tetrahedra, hexahedra, prisms and pyramids of first or second order (the
/// boundary of second-order cells is second order).
///
/// Args:
///     path: The file (str or os.PathLike).
///     group: A physical group of dimension 2, by name or number (`.inp`:
///         a `*SURFACE` name).
///
/// Returns:
///     The surface as a Mesh. Its faces keep their Gmsh element tags (unless
///     they are the boundary of the volume cells), by which `check` names them
///     (`.inp`: face Sk of element E is 10**18 + 10*E + k).
///
/// Raises:
///     FileNotFoundError: The file does not exist (other I/O failures raise
///         the matching OSError).
///     MshError: The file is not a valid MSH (or `.inp`: the message is
///         `FILE:LINE: cause`) file, the group does not exist
///         (the message lists those that do), it has unsupported elements
///         (for example third order; the message names the element tag and
///         type) or degenerate faces (a ValueError).
#[pyfunction]
#[pyo3(signature = (path, group = None))]
pub fn read_mesh(py: Python<'_>, path: PathBuf, group: Option<&Bound<'_, PyAny>>) -> PyResult<PyMesh> {
    let group: Option<String> = match group {
        None => None,
        Some(g) if g.is_none() => None,
        Some(g) => match g.extract::<String>() {
            Ok(name) => Some(name),
            Err(_) => match g.extract::<i64>() {
                Ok(number) => Some(number.to_string()),
                Err(_) => {
                    return Err(PyTypeError::new_err(format!(
                        "group must be a physical group name (str) or number (int), got {}",
                        g.get_type().name()?
                    )))
                }
            },
        },
    };
    detach(py, Entry::ReadMesh, || seam_io::read_tagged_surface_file(&path, group.as_deref()))?
        .map(|(inner, face_tags)| PyMesh { inner, face_tags })
        .map_err(msh_error)
}
