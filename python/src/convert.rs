//! NumPy and SciPy ↔ Rust conversions, with the shape, dtype and sign checks
//! that keep bad input away from the Rust crates (which would panic on it).

use numpy::ndarray::Array2;
use numpy::{
    dtype, Element, IntoPyArray, PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};
use seam::{CsrMatrix, Face, Point3};

use crate::error::MeshError;

/// A shape the way NumPy prints it: `(10, 2)`, `(5,)`, `()`.
fn shape_str(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")),
    }
}

/// A number with at most 6 decimals, trailing zeros dropped (for `__repr__`).
pub fn short(x: f64) -> String {
    let s = format!("{x:.6}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `numpy.asarray(obj)`; a failure (ragged nested lists, ...) names `what`.
fn as_array<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    let py = obj.py();
    let array = py.import("numpy")?.call_method1("asarray", (obj,)).map_err(|e| {
        let message = format!("{what} cannot be converted to an array: {}", e.value(py));
        if e.is_instance_of::<PyTypeError>(py) {
            PyTypeError::new_err(message)
        } else {
            PyValueError::new_err(message)
        }
    })?;
    Ok(array.cast_into::<PyUntypedArray>()?)
}

/// The array as float64 (copied unless it already is); integers are accepted,
/// anything but real numbers is a `TypeError`.
fn as_f64<'py>(array: &Bound<'py, PyUntypedArray>, what: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    let py = array.py();
    let dt = array.dtype();
    if !matches!(dt.kind(), b'f' | b'i' | b'u') {
        return Err(PyTypeError::new_err(format!("{what} must be real numbers, got dtype {dt}")));
    }
    if dt.is_equiv_to(&dtype::<f64>(py)) {
        return Ok(array.clone());
    }
    Ok(array.call_method1("astype", (dtype::<f64>(py),))?.cast_into::<PyUntypedArray>()?)
}

/// Points from an n×3 array-like of real numbers.
pub fn points_from(obj: &Bound<'_, PyAny>) -> PyResult<Vec<Point3>> {
    let array = as_array(obj, "points")?;
    if array.ndim() != 2 || array.shape()[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "points must be an n×3 array (x, y, z per row), got shape {}",
            shape_str(array.shape())
        )));
    }
    let points = as_f64(&array, "points")?.cast_into::<PyArray2<f64>>()?;
    let points = points.readonly();
    Ok(points.as_array().rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect())
}

/// The face widths (nodes per face) and what they make, for messages.
const WIDTHS: &str = "3 (triangles), 4 (quads), 6 (Tri6), 7 (Tri7), 8 (Quad8) or 9 (Quad9)";

/// Whether `n` nodes make a face: 3 (Tri3), 4 (Quad4), 6 (Tri6), 7 (Tri7), 8
/// (Quad8), 9 (Quad9).
fn is_face_width(n: usize) -> bool {
    seam::FaceKind::with_nodes(n).is_some()
}

/// Faces from an m×k integer array (k = 3, 4, 6, 7, 8 or 9: Tri3, Quad4,
/// Tri6, Tri7, Quad8, Quad9, nodes in Gmsh order), or a list/tuple whose items are such
/// arrays or single faces (k indices); faces are numbered in that order.
pub fn faces_from(obj: &Bound<'_, PyAny>) -> PyResult<Vec<Face>> {
    let mut faces = Vec::new();
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        for (i, item) in obj.try_iter()?.enumerate() {
            let what = format!("faces[{i}]");
            let array = as_array(&item?, &what)?;
            match array.ndim() {
                1 if is_face_width(array.len()) => {
                    let row =
                        array.call_method1("reshape", (1, array.len()))?.cast_into::<PyUntypedArray>()?;
                    push_faces(&row, &what, &mut faces)?
                }
                1 => {
                    return Err(PyValueError::new_err(format!(
                        "{what} must list {WIDTHS} node indices, got {}",
                        array.len()
                    )))
                }
                2 => push_faces(&array, &what, &mut faces)?,
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "{what} must be one face or an m×k array of faces, with k = {WIDTHS} \
                         node indices per face, got shape {}",
                        shape_str(array.shape())
                    )))
                }
            }
        }
    } else {
        let array = as_array(obj, "faces")?;
        if array.ndim() != 2 {
            return Err(PyValueError::new_err(format!(
                "faces must be an m×k array with k = {WIDTHS} node indices per face, or a list of \
                 such arrays, got shape {}",
                shape_str(array.shape())
            )));
        }
        push_faces(&array, "faces", &mut faces)?;
    }
    Ok(faces)
}

/// Appends the rows of a 2-D array as faces.
fn push_faces(array: &Bound<'_, PyUntypedArray>, what: &str, faces: &mut Vec<Face>) -> PyResult<()> {
    let shape = array.shape();
    if !is_face_width(shape[1]) {
        return Err(PyValueError::new_err(format!(
            "{what} must have {WIDTHS} columns, got shape {}",
            shape_str(shape)
        )));
    }
    if shape[0] == 0 {
        return Ok(());
    }
    let py = array.py();
    let dt = array.dtype();
    match dt.kind() {
        b'i' => push_rows::<i64>(&array.call_method1("astype", (dtype::<i64>(py),))?, faces),
        b'u' => push_rows::<u64>(&array.call_method1("astype", (dtype::<u64>(py),))?, faces),
        _ => Err(PyTypeError::new_err(format!("{what} must be integer node indices, got dtype {dt}"))),
    }
}

fn push_rows<T: Element + Copy + Into<i128>>(
    array: &Bound<'_, PyAny>,
    faces: &mut Vec<Face>,
) -> PyResult<()> {
    let array = array.cast::<PyArray2<T>>()?.readonly();
    for row in array.as_array().rows() {
        let f = faces.len();
        let mut nodes = [0usize; 9];
        for (corner, &v) in row.iter().enumerate() {
            let v: i128 = v.into();
            nodes[corner] = usize::try_from(v).map_err(|_| {
                MeshError::new_err(format!(
                    "face {f} corner {corner} refers to node {v}; node indices are 0-based and cannot be negative"
                ))
            })?;
        }
        // The width was checked by `push_faces`.
        faces.push(Face::from_nodes(&nodes[..row.len()]));
    }
    Ok(())
}

/// Nodal values of shape (rows,) or (rows, k), row-major; `k` is `None` for 1-D.
pub fn nodal_values_from(
    obj: &Bound<'_, PyAny>,
    what: &str,
    rows: usize,
    per: &str,
) -> PyResult<(Vec<f64>, Option<usize>)> {
    let array = as_array(obj, what)?;
    let shape = array.shape().to_vec();
    let k = match shape[..] {
        [n] if n == rows => None,
        [n, k] if n == rows => Some(k),
        _ => {
            return Err(PyValueError::new_err(format!(
                "{what} must have shape ({rows},) or ({rows}, k), one row per {per}, got shape {}",
                shape_str(&shape)
            )))
        }
    };
    let array = as_f64(&array, what)?;
    let values: Vec<f64> = match k {
        None => array.cast_into::<PyArray1<f64>>()?.readonly().as_array().iter().copied().collect(),
        Some(_) => array.cast_into::<PyArray2<f64>>()?.readonly().as_array().iter().copied().collect(),
    };
    finite(&values, what, k, per)?;
    Ok((values, k))
}

/// `Ok` if every value is finite; else a ValueError naming the first other
/// one by its row (a `per`) and column: nothing non-finite is transferred or
/// returned.
pub fn finite(values: &[f64], what: &str, k: Option<usize>, per: &str) -> PyResult<()> {
    let Some(i) = values.iter().position(|v| !v.is_finite()) else { return Ok(()) };
    let at = match k {
        None => format!("{what}[{i}]"),
        Some(k) => format!("{what}[{}, {}]", i / k.max(1), i % k.max(1)),
    };
    Err(PyValueError::new_err(format!(
        "{at} is {} ({per} {}): only finite values can be used",
        values[i],
        i / k.unwrap_or(1).max(1)
    )))
}

/// Row-major nodal values as a NumPy array of shape (rows,) or (rows, k).
pub fn nodal_values_into(
    py: Python<'_>,
    values: Vec<f64>,
    rows: usize,
    k: Option<usize>,
) -> PyResult<Bound<'_, PyAny>> {
    let array = PyArray1::from_vec(py, values);
    Ok(match k {
        None => array.into_any(),
        Some(k) => array.reshape([rows, k])?.into_any(),
    })
}

/// An n×m int64 array from rows of indices.
pub fn index_rows<'a>(
    py: Python<'_>,
    width: usize,
    rows: impl Iterator<Item = &'a [usize]>,
) -> PyResult<Bound<'_, PyArray2<i64>>> {
    let flat: Vec<i64> = rows.flatten().map(|&i| i as i64).collect();
    let array = Array2::from_shape_vec((flat.len() / width, width), flat)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(array.into_pyarray(py))
}

/// A `scipy.sparse.csr_matrix` from the CSR arrays (copied); int32 indices when
/// they fit, as SciPy would choose.
pub fn csr_matrix<'py>(py: Python<'py>, m: &CsrMatrix) -> PyResult<Bound<'py, PyAny>> {
    let data = PyArray1::from_slice(py, &m.values);
    let fits = m.nnz().max(m.nrows).max(m.ncols) <= i32::MAX as usize;
    let (indices, indptr) = if fits {
        let i32s = |v: &[usize]| PyArray1::from_vec(py, v.iter().map(|&i| i as i32).collect()).into_any();
        (i32s(&m.indices), i32s(&m.indptr))
    } else {
        let i64s = |v: &[usize]| PyArray1::from_vec(py, v.iter().map(|&i| i as i64).collect()).into_any();
        (i64s(&m.indices), i64s(&m.indptr))
    };
    py.import("scipy.sparse")?.getattr("csr_matrix")?.call1(((data, indices, indptr), (m.nrows, m.ncols)))
}
