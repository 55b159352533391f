//! The XML structure of a VTU file, down to its data arrays, and the decoding of
//! each piece's arrays into numbers, checked against the sizes the piece declares.
//!
//! The XML before `<AppendedData>` goes through quick-xml's (iterative) event
//! reader; appended data, which may be raw binary, is never parsed as XML: it
//! starts after the `_` that follows the `<AppendedData>` tag and ends at the last
//! `</AppendedData>`, which only `</VTKFile>` may follow.

use std::borrow::Cow;

use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};

use super::decode::{from_bytes, parse_ascii, read_binary, Compressor, Cursor, Layout, Number, Scalar};
use super::error::one_line;
use super::{Field, VtuError};

/// The sections of a `<Piece>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Section {
    Points,
    Cells,
    PointData,
    CellData,
}

/// Where a data array keeps its values.
enum Data<'a> {
    /// `format="ascii"`: the element's text.
    Ascii(Cow<'a, [u8]>),
    /// `format="binary"`: the element's text, base64.
    Binary(Cow<'a, [u8]>),
    /// `format="appended"`: the `offset` into the appended data.
    Appended(u64),
}

/// A `<DataArray>` element.
struct Array<'a> {
    name: Option<String>,
    ty: Scalar,
    components: usize,
    data: Data<'a>,
}

/// The data arrays of a `<Piece>` and the sizes it declares.
struct PieceArrays<'a> {
    n_points: usize,
    n_cells: usize,
    /// The section elements seen (each may appear once).
    seen: Vec<Section>,
    points: Vec<Array<'a>>,
    cells: Vec<Array<'a>>,
    point_data: Vec<Array<'a>>,
    cell_data: Vec<Array<'a>>,
}

impl<'a> PieceArrays<'a> {
    fn section(&mut self, section: Section) -> &mut Vec<Array<'a>> {
        match section {
            Section::Points => &mut self.points,
            Section::Cells => &mut self.cells,
            Section::PointData => &mut self.point_data,
            Section::CellData => &mut self.cell_data,
        }
    }
}

/// One piece, decoded.
pub(super) struct Piece {
    /// `NumberOfPoints`.
    pub(super) n_points: usize,
    /// The point coordinates, `3 × n_points`.
    pub(super) points: Vec<f64>,
    /// The end of each cell's nodes in `connectivity` (`NumberOfCells` entries),
    /// non-decreasing; the last one is `connectivity.len()`.
    pub(super) offsets: Vec<usize>,
    /// The nodes of the cells (not checked against `n_points`).
    pub(super) connectivity: Vec<usize>,
    /// The VTK cell types.
    pub(super) types: Vec<u8>,
    /// The point data arrays.
    pub(super) point_data: Vec<Field>,
    /// The cell data arrays.
    pub(super) cell_data: Vec<Field>,
}

/// The appended data: the bytes after the `_`, up to `</AppendedData>`.
struct Appended<'a> {
    raw: bool,
    data: &'a [u8],
}

/// A parsed VTU file whose pieces are decoded one at a time.
pub(super) struct Document<'a> {
    big_endian: Option<bool>,
    header: usize,
    compressor: Option<Compressor>,
    pieces: Vec<PieceArrays<'a>>,
    appended: Option<Appended<'a>>,
}

/// An element on the path from the root to the current position.
enum Node {
    File,
    Grid,
    Piece,
    Section(Section),
    Array(Section),
    /// Any other element (its name is not kept: deep nesting costs little).
    Other,
}

impl Node {
    fn name(&self) -> &'static str {
        match self {
            Node::File => "<VTKFile>",
            Node::Grid => "<UnstructuredGrid>",
            Node::Piece => "<Piece>",
            Node::Section(Section::Points) => "<Points>",
            Node::Section(Section::Cells) => "<Cells>",
            Node::Section(Section::PointData) => "<PointData>",
            Node::Section(Section::CellData) => "<CellData>",
            Node::Array(_) => "<DataArray>",
            Node::Other => "an element",
        }
    }
}

fn section_name(section: Section) -> &'static str {
    match section {
        Section::Points => "Points",
        Section::Cells => "Cells",
        Section::PointData => "PointData",
        Section::CellData => "CellData",
    }
}

/// The 1-based line of byte `pos` of `bytes`.
fn line_at(bytes: &[u8], pos: u64) -> usize {
    let pos = usize::try_from(pos).unwrap_or(usize::MAX).min(bytes.len());
    bytes.get(..pos).unwrap_or_default().iter().filter(|&&b| b == b'\n').count() + 1
}

/// The value of attribute `name` of `e`, unescaped.
fn attribute(e: &BytesStart<'_>, name: &str) -> Result<Option<String>, String> {
    for a in e.attributes() {
        let a = a.map_err(|err| xml_error(&err))?;
        if a.key.as_ref() == name.as_bytes() {
            let value = a.normalized_value(XmlVersion::Implicit1_0).map_err(|err| xml_error(&err))?;
            return Ok(Some(value.into_owned()));
        }
    }
    Ok(None)
}

/// An attribute value or name for a message: on one line, at most 40 characters.
fn shown(value: &str) -> String {
    clip(&value.split_whitespace().collect::<Vec<_>>().join(" "), 40)
}

/// `text` cut to `max` characters (marked by `...`).
fn clip(text: &str, max: usize) -> String {
    match text.char_indices().nth(max) {
        Some((end, _)) => format!("{}...", text.get(..end).unwrap_or_default()),
        None => text.to_string(),
    }
}

/// A quick-xml error for a message: one line, at most 160 characters (it may
/// quote a whole misplaced tag).
fn xml_error(e: &impl std::fmt::Display) -> String {
    clip(&one_line(&e.to_string()), 160)
}

/// A count attribute (`NumberOfPoints`...): a non-negative decimal integer.
fn count(value: &str) -> Option<usize> {
    value.trim().parse::<u64>().ok().and_then(|n| usize::try_from(n).ok())
}

/// The last position of `needle` in `hay`.
fn rfind(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).rposition(|w| w == needle)
}

/// `text` starts with `</name`, optional whitespace and `>`; returns the rest.
fn strip_end_tag<'t>(text: &'t [u8], name: &[u8]) -> Option<&'t [u8]> {
    let rest = text.strip_prefix(b"</")?.strip_prefix(name)?;
    rest.trim_ascii_start().strip_prefix(b">")
}

impl<'a> Document<'a> {
    /// Parses the XML of a VTU file down to its data arrays (decoding none).
    ///
    /// # Errors
    /// [`super::VtuErrorKind::Parse`] for bad XML or a file that is not VTK XML,
    /// [`super::VtuErrorKind::Unsupported`] and [`super::VtuErrorKind::Malformed`]
    /// for what the module docs list.
    pub(super) fn parse(bytes: &'a [u8]) -> Result<Document<'a>, VtuError> {
        let mut reader = Reader::from_reader(bytes);
        let mut doc: Option<Document<'a>> = None;
        let mut stack: Vec<Node> = Vec::new();
        let mut grids = 0;
        let mut root_closed = false;
        loop {
            let event = reader
                .read_event()
                .map_err(|e| VtuError::parse(Some(line_at(bytes, reader.error_position())), xml_error(&e)))?;
            let line = || Some(line_at(bytes, reader.buffer_position()));
            let (e, empty) = match event {
                Event::Start(e) => (e, false),
                Event::Empty(e) => (e, true),
                Event::End(_) => {
                    if matches!(stack.pop(), Some(Node::File)) {
                        root_closed = true;
                    }
                    continue;
                }
                Event::Text(t) => {
                    text_of_array(&mut doc, &stack, t.into_inner());
                    continue;
                }
                Event::CData(t) => {
                    text_of_array(&mut doc, &stack, t.into_inner());
                    continue;
                }
                Event::GeneralRef(_) if matches!(stack.last(), Some(Node::Array(_))) => {
                    return Err(VtuError::parse(line(), "an entity reference inside a <DataArray>"));
                }
                Event::Eof => match stack.last() {
                    Some(node) => {
                        let message = format!("the file ends inside {}", node.name());
                        return Err(VtuError::parse(line(), message));
                    }
                    None => break,
                },
                _ => continue,
            };
            let name = e.name();
            let name = name.as_ref();
            let attr = |key: &str| attribute(&e, key).map_err(|m| VtuError::parse(line(), m));
            let Some(top) = stack.last() else {
                if root_closed {
                    return Err(VtuError::parse(line(), "an element after </VTKFile>"));
                }
                if name != b"VTKFile" {
                    let message =
                        format!("the root element is <{}>, not <VTKFile>", String::from_utf8_lossy(name));
                    return Err(VtuError::parse(line(), shown(&message)));
                }
                doc = Some(Document::from_root(&attr)?);
                if !empty {
                    stack.push(Node::File);
                }
                continue;
            };
            // The root is <VTKFile>, so the header is known.
            let Some(doc) = doc.as_mut() else { continue };
            let node = match (top, section(name)) {
                (Node::File, _) if name == b"UnstructuredGrid" => {
                    grids += 1;
                    if grids > 1 {
                        return Err(VtuError::malformed("the file has two <UnstructuredGrid> elements"));
                    }
                    Node::Grid
                }
                (Node::File, _) if name == b"AppendedData" => {
                    let start = usize::try_from(reader.buffer_position()).unwrap_or(usize::MAX);
                    doc.appended = Some(appended(bytes, start, empty, &attr)?);
                    break;
                }
                (Node::Grid, _) if name == b"Piece" => {
                    doc.pieces.push(piece(doc.pieces.len(), &attr)?);
                    Node::Piece
                }
                (Node::Piece, Some(section)) => {
                    let p = doc.pieces.len().saturating_sub(1);
                    let seen = doc.pieces.last_mut().map(|piece| &mut piece.seen);
                    if let Some(seen) = seen {
                        if seen.contains(&section) {
                            let name = section_name(section);
                            return Err(VtuError::malformed(format!("piece {p} has two <{name}> elements")));
                        }
                        seen.push(section);
                    }
                    Node::Section(section)
                }
                (&Node::Section(section), _) if name == b"DataArray" => {
                    let p = doc.pieces.len().saturating_sub(1);
                    let array = array(p, section, &attr)?;
                    if let Some(piece) = doc.pieces.last_mut() {
                        piece.section(section).push(array);
                    }
                    Node::Array(section)
                }
                _ => Node::Other,
            };
            if !empty {
                stack.push(node);
            }
        }
        let doc = doc.ok_or_else(|| VtuError::parse(None, "no <VTKFile> element"))?;
        if grids == 0 {
            return Err(VtuError::malformed("the file has no <UnstructuredGrid> element"));
        }
        Ok(doc)
    }

    /// The header of the file, from the attributes of `<VTKFile>`.
    fn from_root(attr: &dyn Fn(&str) -> Result<Option<String>, VtuError>) -> Result<Document<'a>, VtuError> {
        let kind = attr("type")?.ok_or_else(|| VtuError::malformed("<VTKFile> has no type attribute"))?;
        if kind.trim() != "UnstructuredGrid" {
            return Err(VtuError::unsupported(format!(
                "a VTK {} file, not a serial UnstructuredGrid (.vtu) file",
                shown(&kind)
            )));
        }
        let version =
            attr("version")?.ok_or_else(|| VtuError::malformed("<VTKFile> has no version attribute"))?;
        let v = version.trim();
        let minor_2 = v.strip_prefix("2.").filter(|m| !m.is_empty() && m.bytes().all(|b| b.is_ascii_digit()));
        let known = v == "0.1" || v == "1.0" || minor_2.is_some();
        if !known {
            return Err(VtuError::unsupported(format!(
                "VTK XML file version {:?} is not supported (seam reads 0.1, 1.0 and 2.x)",
                shown(&version)
            )));
        }
        let big_endian = match attr("byte_order")?.as_deref().map(str::trim) {
            None => None,
            Some("LittleEndian") => Some(false),
            Some("BigEndian") => Some(true),
            Some(other) => {
                return Err(VtuError::unsupported(format!(
                    "byte_order {:?} is not supported (LittleEndian or BigEndian)",
                    shown(other)
                )));
            }
        };
        let header = match attr("header_type")?.as_deref().map(str::trim) {
            None | Some("UInt32") => 4,
            Some("UInt64") => 8,
            Some(other) => {
                return Err(VtuError::unsupported(format!(
                    "header_type {:?} is not supported (UInt32 or UInt64)",
                    shown(other)
                )));
            }
        };
        let compressor = match attr("compressor")? {
            None => None,
            Some(name) => Some(Compressor::from_name(name.trim()).ok_or_else(|| {
                VtuError::unsupported(format!(
                    "compressor {:?} is not supported (vtkZLibDataCompressor, vtkLZ4DataCompressor or \
                     vtkLZMADataCompressor)",
                    shown(&name)
                ))
            })?),
        };
        Ok(Document { big_endian, header, compressor, pieces: Vec::new(), appended: None })
    }

    /// The number of pieces.
    pub(super) fn n_pieces(&self) -> usize {
        self.pieces.len()
    }

    /// Decodes piece `p`: its points, cells, point and cell data, each array
    /// checked against the piece's `NumberOfPoints` and `NumberOfCells`.
    ///
    /// # Errors
    /// [`super::VtuErrorKind::Malformed`] naming the piece and array, or the cell.
    pub(super) fn piece(&self, p: usize) -> Result<Piece, VtuError> {
        let arrays = self.pieces.get(p).ok_or_else(|| VtuError::malformed(format!("no piece {p}")))?;
        let (n_points, n_cells) = (arrays.n_points, arrays.n_cells);
        let missing = |what: &str| VtuError::malformed(format!("piece {p} has no {what} array"));
        let points = match (&arrays.points[..], n_points) {
            ([], 0) => Vec::new(),
            ([], _) => return Err(missing("<Points>")),
            ([array], _) => {
                let label = format!("piece {p}, the points array");
                if array.components != 3 {
                    return Err(VtuError::malformed(format!(
                        "{label} has {} components, not 3",
                        array.components
                    )));
                }
                self.values(array, &label, entries(n_points, 3, &label)?)?
            }
            _ => return Err(VtuError::malformed(format!("piece {p}: <Points> has several data arrays"))),
        };

        let cell_array = |name: &str| -> Result<Option<&Array<'a>>, VtuError> {
            let array = arrays.cells.iter().find(|a| a.name.as_deref() == Some(name));
            match array {
                None if n_cells == 0 => Ok(None),
                None => Err(missing(&format!("cell {name}"))),
                Some(a) if a.ty.is_integer() => Ok(Some(a)),
                Some(a) => Err(VtuError::malformed(format!(
                    "piece {p}, the {name} array has type {:?}, not an integer type",
                    a.ty
                ))),
            }
        };
        let index_array = |name: &str, count: usize| -> Result<Vec<u64>, VtuError> {
            match cell_array(name)? {
                None => Ok(Vec::new()),
                Some(array) => self.values::<u64>(array, &format!("piece {p}, the {name} array"), count),
            }
        };
        let offsets = index_array("offsets", n_cells)?;
        let types = index_array("types", n_cells)?;
        let mut ends = Vec::with_capacity(offsets.len());
        let mut previous = 0;
        for (i, &end) in offsets.iter().enumerate() {
            match usize::try_from(end) {
                Ok(end) if end >= previous => {
                    ends.push(end);
                    previous = end;
                }
                _ => {
                    return Err(VtuError::malformed(format!(
                        "piece {p}, cell {i}: offset {end} is less than the previous offset {previous}"
                    )))
                }
            }
        }
        let connectivity = index_array("connectivity", previous)?;
        // Indices past usize (on 32-bit targets) stay out of range.
        let connectivity =
            connectivity.into_iter().map(|n| usize::try_from(n).unwrap_or(usize::MAX)).collect();
        let types = types
            .into_iter()
            .enumerate()
            .map(|(i, t)| {
                u8::try_from(t).map_err(|_| {
                    VtuError::malformed(format!("piece {p}, cell {i} has type {t}, not a VTK cell type"))
                })
            })
            .collect::<Result<Vec<u8>, VtuError>>()?;

        let point_data = self.fields(p, &arrays.point_data, "point", n_points)?;
        let cell_data = self.fields(p, &arrays.cell_data, "cell", n_cells)?;
        Ok(Piece { n_points, points, offsets: ends, connectivity, types, point_data, cell_data })
    }

    /// The point or cell data arrays as fields of `n_entries` entries.
    fn fields(
        &self,
        p: usize,
        arrays: &[Array<'a>],
        what: &str,
        n_entries: usize,
    ) -> Result<Vec<Field>, VtuError> {
        let mut fields = Vec::with_capacity(arrays.len());
        for (i, array) in arrays.iter().enumerate() {
            let name = array.name.clone().ok_or_else(|| {
                VtuError::malformed(format!("piece {p}: {what} data array {i} has no Name attribute"))
            })?;
            let label = format!("piece {p}, {what} data array {:?}", shown(&name));
            let count = entries(n_entries, array.components, &label)?;
            let values = self.values(array, &label, count)?;
            fields.push(Field { name, components: array.components, values });
        }
        Ok(fields)
    }

    /// The `count` values of `array`.
    fn values<T: Number>(&self, array: &Array<'a>, label: &str, count: usize) -> Result<Vec<T>, VtuError> {
        let fail = |m: String| VtuError::malformed(format!("{label} ({count} {:?} values): {m}", array.ty));
        let size = count.checked_mul(array.ty.size()).ok_or_else(|| fail("too many values".into()))?;
        let mut cursor = match &array.data {
            Data::Ascii(text) => return parse_ascii(text, array.ty, count).map_err(fail),
            Data::Binary(text) => Cursor::base64(text),
            Data::Appended(offset) => {
                let appended = self.appended.as_ref();
                let appended =
                    appended.ok_or_else(|| fail("appended, but the file has no <AppendedData>".into()))?;
                let data = usize::try_from(*offset).ok().and_then(|o| appended.data.get(o..));
                let data = data.ok_or_else(|| {
                    let len = appended.data.len();
                    fail(format!("offset {offset} is past the end of the appended data ({len} bytes)"))
                })?;
                if appended.raw {
                    Cursor::Raw(data)
                } else {
                    Cursor::base64(data)
                }
            }
        };
        let layout = self.layout().map_err(fail)?;
        let bytes = read_binary(&mut cursor, &layout, size).map_err(fail)?;
        from_bytes(&bytes, array.ty, layout.big_endian).map_err(fail)
    }

    fn layout(&self) -> Result<Layout, String> {
        let big_endian = self.big_endian.ok_or("binary data, but <VTKFile> has no byte_order attribute")?;
        Ok(Layout { header: self.header, big_endian, compressor: self.compressor })
    }
}

/// `n × components`, or an error naming the array.
fn entries(n: usize, components: usize, label: &str) -> Result<usize, VtuError> {
    n.checked_mul(components)
        .ok_or_else(|| VtuError::malformed(format!("{label}: {n} × {components} values is too many")))
}

fn section(name: &[u8]) -> Option<Section> {
    Some(match name {
        b"Points" => Section::Points,
        b"Cells" => Section::Cells,
        b"PointData" => Section::PointData,
        b"CellData" => Section::CellData,
        _ => return None,
    })
}

/// Adds text to the data array being read, if any (text elsewhere is ignored).
fn text_of_array<'a>(doc: &mut Option<Document<'a>>, stack: &[Node], text: Cow<'a, [u8]>) {
    let (Some(&Node::Array(section)), Some(doc)) = (stack.last(), doc) else { return };
    let Some(array) = doc.pieces.last_mut().and_then(|p| p.section(section).last_mut()) else { return };
    if let Data::Ascii(content) | Data::Binary(content) = &mut array.data {
        if content.is_empty() {
            *content = text;
        } else {
            content.to_mut().extend_from_slice(&text);
        }
    }
}

/// A `<Piece>` element: its sizes.
fn piece<'a>(
    p: usize,
    attr: &dyn Fn(&str) -> Result<Option<String>, VtuError>,
) -> Result<PieceArrays<'a>, VtuError> {
    if let Some(source) = attr("Source")? {
        return Err(VtuError::unsupported(format!("piece {p} refers to another file ({})", shown(&source))));
    }
    let size = |name: &str| -> Result<usize, VtuError> {
        let value = attr(name)?.ok_or_else(|| VtuError::malformed(format!("piece {p} has no {name}")))?;
        count(&value).ok_or_else(|| {
            VtuError::malformed(format!("piece {p}: {name}={:?} is not a count", shown(&value)))
        })
    };
    Ok(PieceArrays {
        n_points: size("NumberOfPoints")?,
        n_cells: size("NumberOfCells")?,
        seen: Vec::new(),
        points: Vec::new(),
        cells: Vec::new(),
        point_data: Vec::new(),
        cell_data: Vec::new(),
    })
}

/// A `<DataArray>` element in `section` of piece `p`.
fn array<'a>(
    p: usize,
    section: Section,
    attr: &dyn Fn(&str) -> Result<Option<String>, VtuError>,
) -> Result<Array<'a>, VtuError> {
    let name = attr("Name")?;
    let label = match (&name, section) {
        (Some(name), Section::PointData | Section::CellData) => {
            let what = if section == Section::PointData { "point" } else { "cell" };
            format!("piece {p}, {what} data array {:?}", shown(name))
        }
        (_, section) => format!("piece {p}, a <DataArray> in <{}>", section_name(section)),
    };
    let malformed = |what: String| VtuError::malformed(format!("{label}: {what}"));
    let ty = attr("type")?.ok_or_else(|| malformed("no type attribute".into()))?;
    let ty = Scalar::from_name(ty.trim()).ok_or_else(|| {
        VtuError::unsupported(format!(
            "{label}: data type {:?} is not supported (Int8 to UInt64, Float32, Float64)",
            shown(&ty)
        ))
    })?;
    let components = match attr("NumberOfComponents")? {
        None => 1,
        Some(value) => count(&value).filter(|&n| n > 0).ok_or_else(|| {
            malformed(format!("NumberOfComponents={:?} is not a positive count", shown(&value)))
        })?,
    };
    let format = attr("format")?.ok_or_else(|| malformed("no format attribute".into()))?;
    let data = match format.trim() {
        "ascii" => Data::Ascii(Cow::Borrowed(b"")),
        "binary" => Data::Binary(Cow::Borrowed(b"")),
        "appended" => {
            let offset =
                attr("offset")?.ok_or_else(|| malformed("appended, but no offset attribute".into()))?;
            let value = offset.trim().parse::<u64>();
            Data::Appended(
                value.map_err(|_| malformed(format!("offset={:?} is not a count", shown(&offset))))?,
            )
        }
        other => {
            return Err(VtuError::unsupported(format!(
                "{label}: format {:?} is not supported (ascii, binary or appended)",
                shown(other)
            )))
        }
    };
    Ok(Array { name, ty, components, data })
}

/// The `<AppendedData>` element whose start tag ends at `start`: its encoding and
/// data; checks that only `</VTKFile>` follows it.
fn appended<'a>(
    bytes: &'a [u8],
    start: usize,
    empty: bool,
    attr: &dyn Fn(&str) -> Result<Option<String>, VtuError>,
) -> Result<Appended<'a>, VtuError> {
    let raw = match attr("encoding")?.as_deref().map(str::trim) {
        Some("raw") => true,
        Some("base64") => false,
        Some(other) => {
            return Err(VtuError::unsupported(format!(
                "<AppendedData> encoding {:?} is not supported (raw or base64)",
                shown(other)
            )))
        }
        None => return Err(VtuError::malformed("<AppendedData> has no encoding attribute")),
    };
    let rest = bytes.get(start..).unwrap_or_default();
    let after = rest.trim_ascii_start().strip_prefix(b"_").filter(|_| !empty);
    let after = after.ok_or_else(|| VtuError::malformed("<AppendedData> does not start with '_'"))?;
    let close = rfind(after, b"</AppendedData")
        .ok_or_else(|| VtuError::parse(None, "the file ends inside <AppendedData> (no </AppendedData>)"))?;
    let tail = after.get(close..).unwrap_or_default();
    let rest = strip_end_tag(tail, b"AppendedData").map(<[u8]>::trim_ascii_start);
    let rest = rest.and_then(|r| strip_end_tag(r, b"VTKFile")).map(<[u8]>::trim_ascii);
    if rest != Some(b"") {
        return Err(VtuError::parse(None, "the file does not end with </AppendedData> and </VTKFile>"));
    }
    Ok(Appended { raw, data: after.get(..close).unwrap_or_default() })
}
