//! `seam.catalogue`: seam's element catalogue ([`seam::catalogue`]) as a dict.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use seam::{CellKind, FaceKind};
use serde_json::{json, Value};

/// The fields faces and cells share, from a kind's description.
macro_rules! description {
    ($kind:expr) => {{
        let (kind, info) = ($kind, $kind.info());
        json!({
            "name": info.name,
            "shape": info.shape.noun(),
            "order": kind.order(),
            "linear": info.linear.name(),
            "n_nodes": kind.n_nodes(),
            "corners": info.corners,
            "gmsh_type": info.gmsh_type,
            "vtk_type": info.vtk_type,
            "vtk_order": info.vtk_order,
            "reference_nodes": info.nodes,
            "edges": info.edges,
        })
    }};
}

/// The element kinds seam knows, each with its description from seam's
/// element catalogue.
///
/// Nodes are in Gmsh's order. Reference coordinates are Gmsh's, except that
/// seam's quadrilateral faces live on [0, 1]² (Gmsh's [-1, 1]² mapped by
/// ξ ↦ (ξ + 1)/2).
///
/// Returns:
///     A dict {"faces": [...], "cells": [...]}, one dict per kind in seam's
///     order with the keys name, shape ("triangle", "hexahedron", ...), order
///     (1 or 2), linear (the first-order kind with the same corners), n_nodes,
///     corners, gmsh_type (None for Tri7 and Tet14, which Gmsh does not have),
///     vtk_type, vtk_order (VTK node i is node
///     vtk_order[i]), reference_nodes ([ξ, η] or [ξ, η, ζ] per node), edges
///     (corner pairs; edge k carries node corners + k at second order) and,
///     for cells, faces ([kind name, local nodes] per face, outward).
#[pyfunction]
pub fn catalogue(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let faces: Vec<Value> = FaceKind::ALL.iter().map(|&kind| description!(kind)).collect();
    let cells: Vec<Value> = CellKind::ALL
        .iter()
        .map(|&kind| {
            let mut cell = description!(kind);
            let faces = kind.info().faces.iter().map(|f| json!([f.kind.name(), f.nodes()]));
            cell["faces"] = Value::Array(faces.collect());
            cell
        })
        .collect();
    let text = json!({ "faces": faces, "cells": cells }).to_string();
    py.import("json")?.call_method1("loads", (text,))?.cast_into::<PyDict>().map_err(PyErr::from)
}
