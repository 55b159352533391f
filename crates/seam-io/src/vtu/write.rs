//! Writing: one piece, every array inline binary (base64 of a little-endian
//! `UInt64` byte count followed by the little-endian values, uncompressed).

use base64::prelude::{Engine as _, BASE64_STANDARD};
use seam::{SurfaceMesh, VolumeMesh};

use super::{Field, VtuError, VtuErrorKind};

/// The numbers of components a written field may have.
const COMPONENTS: [usize; 5] = [1, 2, 3, 6, 9];

/// The file for a surface mesh: a triangle or quad cell per face.
pub(super) fn surface_bytes(
    mesh: &SurfaceMesh,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<Vec<u8>, VtuError> {
    let faces = mesh.faces().iter().map(|f| (f.kind().info().vtk_type, f.kind().info().vtk_order, f.nodes()));
    grid_bytes(mesh.points(), GridCells::of(faces), point_data, cell_data)
}

/// The file for a volume mesh. Gmsh's node orders of the corners of the
/// tetrahedron, hexahedron, prism (VTK's wedge) and pyramid are VTK's: VTK
/// computes a positive volume for cells that are positive in Gmsh (checked by
/// `tests/python`).
pub(super) fn volume_bytes(
    mesh: &VolumeMesh,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<Vec<u8>, VtuError> {
    let cells = mesh.cells().iter().map(|c| (c.kind().info().vtk_type, c.kind().info().vtk_order, c.nodes()));
    grid_bytes(mesh.points(), GridCells::of(cells), point_data, cell_data)
}

fn check_fields(fields: &[Field], n_entries: usize, on_cells: bool) -> Result<(), VtuError> {
    for (i, field) in fields.iter().enumerate() {
        if field.name.is_empty() || fields[..i].iter().any(|f| f.name == field.name) {
            return Err(VtuErrorKind::BadFieldName { name: field.name.clone(), on_cells }.into());
        }
        if !COMPONENTS.contains(&field.components) {
            return Err(VtuErrorKind::UnsupportedComponents {
                name: field.name.clone(),
                components: field.components,
            }
            .into());
        }
        let expected = n_entries * field.components;
        if field.values.len() != expected {
            return Err(VtuErrorKind::WrongFieldLength {
                name: field.name.clone(),
                expected,
                found: field.values.len(),
            }
            .into());
        }
    }
    Ok(())
}

/// The cells of a grid to write: VTK types and connectivity.
#[derive(Default)]
struct GridCells {
    types: Vec<u8>,
    connectivity: Vec<u64>,
    offsets: Vec<u64>,
}

impl GridCells {
    /// A cell per element (VTK type, VTK node order, nodes) of the kind's
    /// description ([`seam::FaceType`], [`seam::CellType`]): VTK node i is
    /// `nodes[order[i]]`.
    fn of<'a>(elements: impl Iterator<Item = (u8, &'a [usize], &'a [usize])>) -> GridCells {
        let mut cells = GridCells::default();
        for (vtk_type, order, nodes) in elements {
            cells.connectivity.extend(order.iter().map(|&i| nodes[i] as u64));
            cells.offsets.push(cells.connectivity.len() as u64);
            cells.types.push(vtk_type);
        }
        cells
    }
}

fn grid_bytes(
    points: &[[f64; 3]],
    cells: GridCells,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<Vec<u8>, VtuError> {
    check_fields(point_data, points.len(), false)?;
    check_fields(cell_data, cells.types.len(), true)?;
    let mut out = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\"><UnstructuredGrid>",
    );
    out.push_str(&format!(
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        points.len(),
        cells.types.len()
    ));
    attribute_data(&mut out, "PointData", point_data);
    attribute_data(&mut out, "CellData", cell_data);
    out.push_str("<Points>");
    data_array(&mut out, "Points", 3, &Values::Float64(points.as_flattened()));
    out.push_str("</Points><Cells>");
    // Node indices are far below 2⁶³, so the bytes are the same as unsigned ones.
    // VTK writes `Int64`, and meshio reads unsigned offsets as floats.
    data_array(&mut out, "connectivity", 1, &Values::Int64(&cells.connectivity));
    data_array(&mut out, "offsets", 1, &Values::Int64(&cells.offsets));
    data_array(&mut out, "types", 1, &Values::UInt8(&cells.types));
    out.push_str("</Cells></Piece></UnstructuredGrid></VTKFile>\n");
    Ok(out.into_bytes())
}

/// A parallel file (`.pvtu`, VTK's `PUnstructuredGrid`): the fields that
/// every piece holds (names and components) and the pieces' file names.
pub(super) fn parallel_bytes(
    pieces: &[String],
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<Vec<u8>, VtuError> {
    for (fields, on_cells) in [(point_data, false), (cell_data, true)] {
        let declared: Vec<Field> =
            fields.iter().map(|f| Field::new(f.name.clone(), f.components, Vec::new())).collect();
        check_fields(&declared, 0, on_cells)?;
    }
    let mut out = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\"><PUnstructuredGrid GhostLevel=\"0\">\n",
    );
    for (element, fields) in [("PPointData", point_data), ("PCellData", cell_data)] {
        if fields.is_empty() {
            continue;
        }
        out.push_str(&format!("<{element}{}>\n", active_attributes(fields)));
        for field in fields {
            out.push_str(&format!("<PDataArray type=\"Float64\" Name=\"{}\"", escape(&field.name)));
            if field.components != 1 {
                out.push_str(&format!(" NumberOfComponents=\"{}\"", field.components));
            }
            out.push_str("/>\n");
        }
        out.push_str(&format!("</{element}>\n"));
    }
    out.push_str("<PPoints><PDataArray type=\"Float64\" NumberOfComponents=\"3\"/></PPoints>\n");
    for piece in pieces {
        out.push_str(&format!("<Piece Source=\"{}\"/>\n", escape(piece)));
    }
    out.push_str("</PUnstructuredGrid></VTKFile>\n");
    Ok(out.into_bytes())
}

/// A ParaView collection (`.pvd`): one data set per (time, file), the
/// file names relative to the collection's directory.
pub(super) fn collection_bytes(entries: &[(f64, String)]) -> Vec<u8> {
    let mut out = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n",
    );
    for (time, file) in entries {
        out.push_str(&format!(
            "<DataSet timestep=\"{time:?}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
            escape(file)
        ));
    }
    out.push_str("</Collection>\n</VTKFile>\n");
    out.into_bytes()
}

/// ` Scalars="…" Vectors="…"`: the first 1-component field as the active
/// scalars, the first 3-component one as the active vectors.
fn active_attributes(fields: &[Field]) -> String {
    [("Scalars", 1), ("Vectors", 3)]
        .iter()
        .filter_map(|&(attribute, components)| {
            let field = fields.iter().find(|f| f.components == components)?;
            Some(format!(" {attribute}=\"{}\"", escape(&field.name)))
        })
        .collect()
}

/// `<PointData>` or `<CellData>` (nothing without fields), with the first
/// 1-component field as the active scalars, the first 3-component one as the
/// active vectors.
fn attribute_data(out: &mut String, element: &str, fields: &[Field]) {
    if fields.is_empty() {
        return;
    }
    out.push_str(&format!("<{element}{}>", active_attributes(fields)));
    for field in fields {
        data_array(out, &field.name, field.components, &Values::Float64(&field.values));
    }
    out.push_str("</");
    out.push_str(element);
    out.push('>');
}

/// The values of a data array.
enum Values<'a> {
    Float64(&'a [f64]),
    /// Written as `Int64`: the values are below 2⁶³.
    Int64(&'a [u64]),
    UInt8(&'a [u8]),
}

/// A `<DataArray>` element: base64 of the byte count (`UInt64`) and the values,
/// with the range of the values as `RangeMin`/`RangeMax` (over all components).
fn data_array(out: &mut String, name: &str, components: usize, values: &Values<'_>) {
    let (ty, range, bytes) = match *values {
        Values::Float64(v) => (
            "Float64",
            v.iter().copied().reduce(f64::min).zip(v.iter().copied().reduce(f64::max)),
            v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>(),
        ),
        Values::Int64(v) => (
            "Int64",
            v.iter().min().zip(v.iter().max()).map(|(&a, &b)| (a as f64, b as f64)),
            v.iter().flat_map(|x| x.to_le_bytes()).collect(),
        ),
        Values::UInt8(v) => {
            ("UInt8", v.iter().min().zip(v.iter().max()).map(|(&a, &b)| (a.into(), b.into())), v.to_vec())
        }
    };
    out.push_str(&format!("<DataArray type=\"{ty}\" Name=\"{}\"", escape(name)));
    if components != 1 {
        out.push_str(&format!(" NumberOfComponents=\"{components}\""));
    }
    out.push_str(" format=\"binary\"");
    if let Some((min, max)) = range {
        out.push_str(&format!(" RangeMin=\"{min}\" RangeMax=\"{max}\""));
    }
    out.push('>');
    let mut data = (bytes.len() as u64).to_le_bytes().to_vec();
    data.extend_from_slice(&bytes);
    BASE64_STANDARD.encode_string(&data, out);
    out.push_str("</DataArray>");
}

/// `text` escaped for an attribute value.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '&' => out.push_str("&amp;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}
