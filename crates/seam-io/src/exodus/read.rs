//! The netCDF side: dimensions and variables of an Exodus II file, read
//! under the file-size bound, into an [`Msh`].

use std::collections::{HashMap, HashSet};

use netcdf_reader::{NcAttrValue, NcFile, NcGroup, NcOpenOptions, NcType, NcVariable};
use seam::{CellKind, Point3};

use super::types::{exodus_type, gmsh_positions, local_face, n_sides, ExodusType, SUPPORTED};
use super::ExodusError;
use crate::abaqus::face_element;
use crate::msh::{Msh, MshElement, MshFormat, MshVersion, PhysicalName, UnusableGroup};

/// A NetCDF-4 (HDF5) file's arrays may be compressed: zlib's best ratio is
/// about 1032 to 1.
const MAX_COMPRESSION: usize = 1100;

/// Ids of face elements must stay below 10¹⁸ / 10 … (see `face_tag`).
const MAX_ID: i64 = 99_999_999_999_999_999;

/// The longest cause quoted from netcdf-reader (its messages may quote
/// names and numbers from the file).
const MAX_CAUSE: usize = 200;

/// The open file, its metadata and its size bound.
struct File {
    nc: NcFile,
    /// The dimensions, variables and attributes, all read when the file is
    /// opened (a damaged header is refused then, whatever it hides).
    root: NcGroup,
    /// The most values any one array may declare.
    max_values: usize,
}

fn error(message: impl Into<String>) -> ExodusError {
    ExodusError::new(message)
}

/// `what: cause`, the cause netcdf-reader's message on one line of at most
/// [`MAX_CAUSE`] characters.
fn nc_error(what: &str, e: netcdf_reader::Error) -> ExodusError {
    let text = e.to_string();
    let mut cause: String = text.split_whitespace().collect::<Vec<_>>().join(" ");
    if let Some((at, _)) = cause.char_indices().nth(MAX_CAUSE) {
        cause.truncate(at);
        cause.push('…');
    }
    error(format!("{what}: {cause}"))
}

/// A variable of the integer type `T`, each value as an `i64` (`None`: out
/// of range); the error's cause.
fn integers<T: netcdf_reader::NcReadable + Copy>(
    nc: &NcFile,
    name: &str,
    convert: impl Fn(T) -> Option<i64>,
) -> Result<Vec<i64>, Result<String, netcdf_reader::Error>> {
    let array = nc.read_variable::<T>(name).map_err(Err)?;
    array
        .iter()
        .map(|&v| convert(v).ok_or_else(|| Ok("a value is larger than 2^63 - 1".to_string())))
        .collect()
}

/// A netCDF type that is no integer, as the netCDF manual names it.
fn type_name(ty: &NcType) -> &'static str {
    match ty {
        NcType::Char => "char",
        NcType::Float => "float",
        NcType::Double => "double",
        NcType::String => "string",
        _ => "a user-defined type",
    }
}

impl File {
    fn dim(&self, name: &str) -> Option<usize> {
        let size = self.root.dimension(name)?.size;
        Some(usize::try_from(size).unwrap_or(usize::MAX))
    }

    /// A count the file declares (0 without the dimension), no larger than
    /// what a file of its size can hold.
    fn count(&self, name: &str) -> Result<usize, ExodusError> {
        let Some(n) = self.root.dimension(name).map(|d| d.size) else { return Ok(0) };
        if !usize::try_from(n).is_ok_and(|n| n <= self.max_values) {
            return Err(error(format!("dimension {name} = {n} is more than a file of this size can hold")));
        }
        Ok(n as usize)
    }

    /// The variable, its declared length checked against the file size.
    fn var(&self, name: &str, what: &str) -> Result<Option<&NcVariable>, ExodusError> {
        let Some(var) = self.root.variable(name) else { return Ok(None) };
        let len = var
            .dimensions()
            .iter()
            .map(|d| usize::try_from(d.size).unwrap_or(usize::MAX))
            .fold(1_usize, usize::saturating_mul);
        if len > self.max_values {
            return Err(error(format!(
                "{what}: {name} declares {len} values, more than a file of this size can hold"
            )));
        }
        Ok(Some(var))
    }

    fn f64s(&self, name: &str, what: &str) -> Result<Option<Vec<f64>>, ExodusError> {
        match self.var(name, what)? {
            None => Ok(None),
            Some(_) => match self.nc.read_variable_as_f64(name) {
                Ok(array) => Ok(Some(array.iter().copied().collect())),
                Err(e) => Err(nc_error(&format!("{what}: {name}"), e)),
            },
        }
    }

    /// An integer variable (of any of netCDF's integer types) as `i64`.
    fn i64s(&self, name: &str, what: &str) -> Result<Option<Vec<i64>>, ExodusError> {
        let Some(var) = self.var(name, what)? else { return Ok(None) };
        let nc = &self.nc;
        let values = match &var.dtype {
            NcType::Byte => integers(nc, name, |v: i8| Some(v.into())),
            NcType::UByte => integers(nc, name, |v: u8| Some(v.into())),
            NcType::Short => integers(nc, name, |v: i16| Some(v.into())),
            NcType::UShort => integers(nc, name, |v: u16| Some(v.into())),
            NcType::Int => integers(nc, name, |v: i32| Some(v.into())),
            NcType::UInt => integers(nc, name, |v: u32| Some(v.into())),
            NcType::Int64 => integers(nc, name, |v: i64| Some(v)),
            NcType::UInt64 => integers(nc, name, |v: u64| i64::try_from(v).ok()),
            other => Err(Ok(format!("values of type {}, not integers", type_name(other)))),
        };
        match values {
            Ok(values) => Ok(Some(values)),
            Err(Ok(cause)) => Err(error(format!("{what}: {name}: {cause}"))),
            Err(Err(e)) => Err(nc_error(&format!("{what}: {name}"), e)),
        }
    }

    /// The rows of a character array (`eb_names`, `ss_names`), trimmed at
    /// the first NUL; `n` empty names without it.
    fn names(&self, name: &str, n: usize) -> Result<Vec<String>, ExodusError> {
        let Some(var) = self.var(name, name)? else { return Ok(vec![String::new(); n]) };
        let dims = var.dimensions();
        if !(dims.len() == 2 && dims[0].size == n as u64) {
            return Ok(vec![String::new(); n]);
        }
        let rows = self.nc.read_variable_as_strings(name).map_err(|e| nc_error(name, e))?;
        Ok((0..n)
            .map(|i| {
                let row = rows.get(i).map_or("", String::as_str);
                row.split('\0').next().unwrap_or("").trim().to_string()
            })
            .collect())
    }

    /// A text attribute of a variable.
    fn text_attribute(var: &NcVariable, name: &str) -> Option<String> {
        let attribute = var.attributes.iter().find(|a| a.name == name)?;
        let text = match &attribute.value {
            NcAttrValue::Chars(s) => s.clone(),
            NcAttrValue::Strings(v) => v.first()?.clone(),
            NcAttrValue::UBytes(v) => String::from_utf8_lossy(v).into_owned(),
            NcAttrValue::Bytes(v) => {
                String::from_utf8_lossy(&v.iter().map(|&c| c as u8).collect::<Vec<u8>>()).into_owned()
            }
            _ => return None,
        };
        Some(text.trim_end_matches('\0').trim().to_string())
    }
}

/// An entity's ids (`eb_prop1`, `ss_prop1`), 1, 2, … without them; each a
/// non-negative `i32` (a physical tag; meshio numbers blocks from 0).
fn entity_ids(file: &File, var: &str, n: usize, what: &str) -> Result<Vec<i32>, ExodusError> {
    let ids = match file.i64s(var, what)? {
        Some(ids) if ids.len() == n => ids,
        Some(ids) => return Err(error(format!("{what}: {var} has {} values for {n} {what}", ids.len()))),
        None => (1..=n as i64).collect(),
    };
    let mut seen = HashSet::new();
    ids.into_iter()
        .map(|id| {
            let tag = i32::try_from(id).ok().filter(|&t| t >= 0).ok_or_else(|| {
                error(format!("{what}: id {id} in {var} is not a non-negative 32-bit number"))
            })?;
            if !seen.insert(tag) {
                return Err(error(format!("{what}: id {id} appears twice in {var}")));
            }
            Ok(tag)
        })
        .collect()
}

/// "element block 2 (\"steel\")" or "element block 2".
fn label(kind: &str, id: i32, name: &str) -> String {
    if name.is_empty() {
        format!("{kind} {id}")
    } else {
        format!("{kind} {id} (\"{name}\")")
    }
}

/// A number map (`node_num_map`, `elem_num_map`): `n` distinct positive ids.
fn num_map(file: &File, var: &str, n: usize, what: &str) -> Result<Vec<u64>, ExodusError> {
    let Some(map) = file.i64s(var, what)? else { return Ok((1..=n as u64).collect()) };
    if map.len() != n {
        return Err(error(format!("{var} has {} ids for {n} {what}", map.len())));
    }
    let mut seen = HashSet::with_capacity(n);
    map.into_iter()
        .map(|id| {
            if !(1..=MAX_ID).contains(&id) {
                return Err(error(format!("{var}: id {id} is not between 1 and {MAX_ID}")));
            }
            if !seen.insert(id) {
                return Err(error(format!("{var}: id {id} appears twice")));
            }
            Ok(id as u64)
        })
        .collect()
}

/// Reads the file from its bytes.
pub(super) fn read(bytes: &[u8]) -> Result<Msh, ExodusError> {
    let classic = bytes.starts_with(b"CDF");
    if !classic && !bytes.starts_with(b"\x89HDF\r\n\x1a\n") {
        return Err(error(
            "not an Exodus II file: neither a netCDF classic/64-bit-offset nor a NetCDF-4 (HDF5) file",
        ));
    }
    let max_values = if classic { bytes.len() } else { bytes.len().saturating_mul(MAX_COMPRESSION) };
    // The bound holds for HDF5's own reads too: a dataset whose dataspace is
    // larger than its netCDF dimensions say is refused before it is read.
    let max_bytes = max_values.saturating_mul(8);
    let options = NcOpenOptions {
        max_read_bytes: max_bytes,
        max_chunk_bytes: max_bytes.min(NcOpenOptions::default().max_chunk_bytes),
        ..NcOpenOptions::default()
    };
    let nc = NcFile::from_bytes_with_options(bytes, options)
        .map_err(|e| nc_error("not a readable netCDF file (truncated or corrupt)", e))?;
    let root = nc
        .root_group()
        .map_err(|e| nc_error("not a readable netCDF file (truncated or corrupt)", e))?
        .clone();
    let file = File { nc, root, max_values };

    let num_dim = file.dim("num_dim").ok_or_else(|| error("not an Exodus II file: no dimension num_dim"))?;
    if num_dim != 3 {
        return Err(error(format!(
            "a {num_dim}-dimensional mesh (num_dim = {num_dim}): seam reads 3D models"
        )));
    }
    let n_nodes = file.count("num_nodes")?;
    let nodes = coordinates(&file, n_nodes)?;
    let node_tags = num_map(&file, "node_num_map", n_nodes, "nodes")?;
    let n_elem = file.count("num_elem")?;
    let elem_ids = num_map(&file, "elem_num_map", n_elem, "elements")?;

    let mut msh = Msh::empty(MshFormat { version: MshVersion::ExodusII, binary: false });
    msh.nodes = nodes;
    msh.node_tags = node_tags;

    // Element blocks: cells, and where each element (global 0-based index)
    // went: its cell index, or the block it is in when it is no cell.
    let n_blocks = file.count("num_el_blk")?;
    let block_ids = entity_ids(&file, "eb_prop1", n_blocks, "element blocks")?;
    let block_names = file.names("eb_names", n_blocks)?;
    let mut element_cell: Vec<Result<usize, usize>> = Vec::with_capacity(n_elem);
    let mut cell_kinds: Vec<CellKind> = Vec::new();
    for b in 0..n_blocks {
        let what = label("element block", block_ids[b], &block_names[b]);
        let k = b + 1;
        let count = file.count(&format!("num_el_in_blk{k}"))?;
        if element_cell.len() + count > n_elem {
            return Err(error(format!("{what}: the blocks hold more than num_elem = {n_elem} elements")));
        }
        if !block_names[b].is_empty() {
            msh.physical_names.push(PhysicalName { dim: 3, tag: block_ids[b], name: block_names[b].clone() });
        }
        if count == 0 {
            continue;
        }
        let per = file.count(&format!("num_nod_per_el{k}"))?;
        let name = format!("connect{k}");
        let var = file
            .var(&name, &what)?
            .ok_or_else(|| error(format!("{what}: the file has no variable {name}")))?;
        let ty = File::text_attribute(var, "elem_type").unwrap_or_default();
        let problem = match exodus_type(&ty, per) {
            ExodusType::Solid(kind) => {
                let connect = file.i64s(&name, &what)?.unwrap_or_default();
                if Some(connect.len()) != count.checked_mul(per) {
                    return Err(error(format!("{what}: connect{k} has {} values for {count} elements of {per} nodes", connect.len())));
                }
                let tag = block_ids[b];
                let positions = gmsh_positions(kind);
                for row in connect.chunks_exact(per) {
                    let mut nodes = vec![0; per];
                    for (&n, &p) in row.iter().zip(&positions) {
                        nodes[p] = usize::try_from(n).ok().filter(|&n| (1..=n_nodes).contains(&n)).map(|n| n - 1).ok_or_else(|| {
                            error(format!("{what}: connect{k} refers to node {n}, the file has {n_nodes} nodes"))
                        })?;
                    }
                    let index = element_cell.len();
                    element_cell.push(Ok(msh.elements.len()));
                    cell_kinds.push(kind);
                    msh.elements.push(MshElement {
                        tag: elem_ids[index],
                        gmsh_type: kind.info().gmsh_type.unwrap_or(0),
                        dim: 3,
                        entity: tag,
                        nodes,
                        physical_tags: vec![tag],
                    });
                }
                None
            }
            ExodusType::Unverified => Some(format!(
                "{what}: element type {ty} is not read yet (its Exodus node order is not verified); seam reads {SUPPORTED}"
            )),
            ExodusType::Other => Some(format!(
                "{what}: element type {ty:?} with {per} nodes is not a solid seam reads ({SUPPORTED})"
            )),
        };
        if let Some(reason) = problem {
            element_cell.extend(std::iter::repeat_n(Err(b), count));
            msh.unusable_groups.push(UnusableGroup { dim: 3, tag: block_ids[b], reason });
        }
    }
    if element_cell.len() != n_elem {
        return Err(error(format!(
            "the element blocks hold {} elements, num_elem is {n_elem}",
            element_cell.len()
        )));
    }

    side_sets(&file, &mut msh, &element_cell, &cell_kinds, &block_ids, &block_names)?;
    Ok(msh)
}

/// The nodes: `coord` (num_dim × num_nodes) or `coordx`, `coordy`, `coordz`.
fn coordinates(file: &File, n: usize) -> Result<Vec<Point3>, ExodusError> {
    let what = "coordinates";
    let axes: [Vec<f64>; 3] = if let Some(all) = file.f64s("coord", what)? {
        if all.len() != 3 * n {
            return Err(error(format!("coord has {} values for {n} nodes", all.len())));
        }
        [all[..n].to_vec(), all[n..2 * n].to_vec(), all[2 * n..].to_vec()]
    } else {
        let mut axes: [Vec<f64>; 3] = Default::default();
        for (axis, name) in axes.iter_mut().zip(["coordx", "coordy", "coordz"]) {
            *axis = match file.f64s(name, what)? {
                Some(v) if v.len() == n => v,
                Some(v) => return Err(error(format!("{name} has {} values for {n} nodes", v.len()))),
                None if n == 0 => Vec::new(),
                None => return Err(error(format!("the file has no coordinates (coord or {name})"))),
            };
        }
        axes
    };
    (0..n)
        .map(|i| {
            let p: Point3 = [axes[0][i], axes[1][i], axes[2][i]];
            if p.iter().all(|c| c.is_finite()) {
                Ok(p)
            } else {
                Err(error(format!("node {} has a non-finite coordinate", i + 1)))
            }
        })
        .collect()
}

/// The side sets, as face elements in surface groups.
fn side_sets(
    file: &File,
    msh: &mut Msh,
    element_cell: &[Result<usize, usize>],
    cell_kinds: &[CellKind],
    block_ids: &[i32],
    block_names: &[String],
) -> Result<(), ExodusError> {
    let n_sets = file.count("num_side_sets")?;
    let ids = entity_ids(file, "ss_prop1", n_sets, "side sets")?;
    let names = file.names("ss_names", n_sets)?;
    let mut faces: HashMap<(usize, usize), usize> = HashMap::new();
    let mut face_elements: Vec<MshElement> = Vec::new();
    for s in 0..n_sets {
        let what = label("side set", ids[s], &names[s]);
        let k = s + 1;
        let tag = ids[s];
        if !names[s].is_empty() {
            msh.physical_names.push(PhysicalName { dim: 2, tag, name: names[s].clone() });
        }
        let count = file.count(&format!("num_side_ss{k}"))?;
        if count == 0 {
            continue;
        }
        let elems = file
            .i64s(&format!("elem_ss{k}"), &what)?
            .ok_or_else(|| error(format!("{what}: the file has no variable elem_ss{k}")))?;
        let sides = file
            .i64s(&format!("side_ss{k}"), &what)?
            .ok_or_else(|| error(format!("{what}: the file has no variable side_ss{k}")))?;
        if elems.len() != count || sides.len() != count {
            return Err(error(format!(
                "{what}: elem_ss{k} and side_ss{k} do not both have num_side_ss{k} = {count} values"
            )));
        }
        let mut unusable = None;
        let mut list = Vec::with_capacity(count);
        for (&e, &side) in elems.iter().zip(&sides) {
            let index =
                usize::try_from(e).ok().filter(|&e| (1..=element_cell.len()).contains(&e)).ok_or_else(
                    || {
                        error(format!(
                            "{what}: elem_ss{k} refers to element {e}, the file has {} elements",
                            element_cell.len()
                        ))
                    },
                )? - 1;
            match element_cell[index] {
                Err(b) => {
                    unusable = Some(format!(
                        "{what}: it has sides of elements in {}, whose type seam does not read",
                        label("element block", block_ids[b], &block_names[b])
                    ));
                    break;
                }
                Ok(cell) => {
                    let kind = cell_kinds[cell];
                    let ok = usize::try_from(side).ok().filter(|&f| (1..=n_sides(kind)).contains(&f));
                    let Some(f) = ok else {
                        return Err(error(format!(
                            "{what}: side {side} of element {} (a {}), which has sides 1 to {}",
                            msh.elements[cell].tag,
                            kind.info().name,
                            n_sides(kind)
                        )));
                    };
                    list.push((cell, kind, f));
                }
            }
        }
        if let Some(reason) = unusable {
            msh.unusable_groups.push(UnusableGroup { dim: 2, tag, reason });
            continue;
        }
        for (cell, kind, f) in list {
            let index = *faces.entry((cell, f)).or_insert_with(|| {
                let element = &msh.elements[cell];
                let local =
                    local_face(kind, f).expect("every side 1…n of a cell kind is one of its local faces");
                face_elements.push(face_element(element, local, f as u8));
                face_elements.len() - 1
            });
            if !face_elements[index].physical_tags.contains(&tag) {
                face_elements[index].physical_tags.push(tag);
            }
        }
    }
    msh.elements.extend(face_elements);
    Ok(())
}
