//! Rewrites, at the byte level, the two things VTK (and so ParaView) writes that
//! vtkio 0.7.0-rc2 cannot read, before vtkio parses the file:
//!
//! - appended raw binary data (`<AppendedData encoding="raw">`, the default of
//!   ParaView's writer): vtkio only reads it with a `binary` feature that needs a
//!   forked quick-xml. It becomes base64 appended data (each array encoded on its
//!   own, as VTK does), and the `offset` of every data array is rewritten;
//! - compressed arrays whose size is a multiple of the block size (32 KiB in VTK):
//!   VTK then writes 0 as the size of the last, partial block, and vtkio drops the
//!   last block, so the array fails to load, or a point or cell field silently
//!   disappears. The header gets the full block size instead.
//!
//! Files that need neither are passed on untouched.

use std::borrow::Cow;
use std::ops::Range;

use base64::prelude::{Engine as _, BASE64_STANDARD};

use super::VtuError;

/// How the binary data of a file is laid out.
#[derive(Clone, Copy)]
struct Layout {
    /// Size of a header integer: 4 (`UInt32`, the default) or 8 (`UInt64`).
    header: usize,
    big_endian: bool,
    compressed: bool,
}

impl Layout {
    fn read(&self, bytes: &[u8]) -> u64 {
        match (self.header, self.big_endian) {
            (8, false) => u64::from_le_bytes(bytes[..8].try_into().unwrap_or_default()),
            (8, true) => u64::from_be_bytes(bytes[..8].try_into().unwrap_or_default()),
            (_, false) => u32::from_le_bytes(bytes[..4].try_into().unwrap_or_default()).into(),
            (_, true) => u32::from_be_bytes(bytes[..4].try_into().unwrap_or_default()).into(),
        }
    }

    fn write(&self, bytes: &mut [u8], value: u64) {
        match (self.header, self.big_endian) {
            (8, false) => bytes[..8].copy_from_slice(&value.to_le_bytes()),
            (8, true) => bytes[..8].copy_from_slice(&value.to_be_bytes()),
            // `value` is a header entry read with the same layout.
            (_, false) => bytes[..4].copy_from_slice(&(value as u32).to_le_bytes()),
            (_, true) => bytes[..4].copy_from_slice(&(value as u32).to_be_bytes()),
        }
    }

    /// Length in bytes of the compression header `[nb][nu][np][nc_1]..[nc_nb]` that
    /// starts with `first` (at least one header integer), with its `nb`.
    fn compression_header_len(&self, first: &[u8], what: &str) -> Result<(usize, usize), VtuError> {
        let nb = usize::try_from(self.read(first)).unwrap_or(usize::MAX);
        if nb == 0 {
            // vtkio computes `nu * (nb - 1) + np` bytes for it.
            return Err(VtuError::malformed(format!(
                "{what} is an empty compressed array, which vtkio cannot read"
            )));
        }
        let len = nb.checked_add(3).and_then(|n| n.checked_mul(self.header));
        len.map(|len| (len, nb))
            .ok_or_else(|| VtuError::malformed(format!("{what} has a corrupt compression header")))
    }

    /// Sets a zero "last partial block size" to the full block size; returns
    /// whether it changed `header` and the total compressed size.
    fn fix_compression_header(&self, header: &mut [u8]) -> (bool, u64) {
        let h = self.header;
        let nb = (header.len() / h).saturating_sub(3);
        let total = (0..nb).map(|i| self.read(&header[(3 + i) * h..])).fold(0u64, u64::saturating_add);
        let (nu, np) = (self.read(&header[h..]), self.read(&header[2 * h..]));
        if np == 0 && nu != 0 {
            self.write(&mut header[2 * h..], nu);
            return (true, total);
        }
        (false, total)
    }
}

/// Number of base64 characters for `n` bytes (padded).
fn b64_len(n: usize) -> usize {
    n.div_ceil(3).saturating_mul(4)
}

fn find(hay: &[u8], needle: &[u8], from: usize) -> Option<usize> {
    hay.get(from..)?.windows(needle.len()).position(|w| w == needle).map(|i| i + from)
}

/// The value of attribute `name` in the start tag `tag`, as a range of `tag`.
fn attribute(tag: &[u8], name: &str) -> Option<Range<usize>> {
    let name = name.as_bytes();
    let mut from = 0;
    while let Some(at) = find(tag, name, from) {
        from = at + 1;
        if at == 0 || !tag[at - 1].is_ascii_whitespace() {
            continue;
        }
        let mut i = at + name.len();
        while tag.get(i).is_some_and(u8::is_ascii_whitespace) {
            i += 1;
        }
        if tag.get(i) != Some(&b'=') {
            continue;
        }
        i += 1;
        while tag.get(i).is_some_and(u8::is_ascii_whitespace) {
            i += 1;
        }
        let quote = *tag.get(i).filter(|&&q| q == b'"' || q == b'\'')?;
        let end = find(tag, &[quote], i + 1)?;
        return Some(i + 1..end);
    }
    None
}

fn attribute_is(tag: &[u8], name: &str, value: &str) -> bool {
    attribute(tag, name).is_some_and(|r| tag[r].trim_ascii() == value.as_bytes())
}

/// A `<DataArray ...>` start tag in the XML before the appended data.
struct ArrayTag {
    /// Its `offset` value (range in the file) and number, for appended arrays.
    offset: Option<(Range<usize>, usize)>,
    /// Its text content (range in the file, trimmed), for inline binary arrays.
    content: Option<Range<usize>>,
}

fn array_tags(bytes: &[u8], head_end: usize) -> Result<Vec<ArrayTag>, VtuError> {
    let mut tags = Vec::new();
    let mut from = 0;
    while let Some(start) = find(&bytes[..head_end], b"<DataArray", from) {
        let end = find(&bytes[..head_end], b">", start)
            .ok_or_else(|| VtuError::malformed("unclosed <DataArray> tag"))?;
        from = end;
        let tag = &bytes[start..end];
        let mut array = ArrayTag { offset: None, content: None };
        if attribute_is(tag, "format", "appended") {
            let range = attribute(tag, "offset")
                .ok_or_else(|| VtuError::malformed("an appended <DataArray> has no offset"))?;
            let value = std::str::from_utf8(&tag[range.clone()]).ok().and_then(|v| v.trim().parse().ok());
            let value = value.ok_or_else(|| VtuError::malformed("a <DataArray> offset is not a number"))?;
            array.offset = Some((start + range.start..start + range.end, value));
        } else if attribute_is(tag, "format", "binary") && tag.last() != Some(&b'/') {
            let text_end = find(bytes, b"<", end + 1).unwrap_or(bytes.len());
            let text = &bytes[end + 1..text_end];
            let lead = text.len() - text.trim_ascii_start().len();
            let content = end + 1 + lead..end + 1 + lead + text.trim_ascii().len();
            array.content = Some(content);
        }
        tags.push(array);
    }
    Ok(tags)
}

/// Fixes the compression header at the start of the base64 text `text` (the
/// header is encoded on its own, as VTK and meshio do).
fn fix_base64_header(layout: &Layout, text: &mut [u8]) -> Result<(), VtuError> {
    let what = "a binary data array";
    let bad = || VtuError::malformed(format!("{what} has a corrupt compression header"));
    let first = text.get(..b64_len(layout.header)).ok_or_else(bad)?;
    // Whole base64 quads (8 or 12 characters) of a header of at least 12 bytes.
    let first = BASE64_STANDARD.decode(first).map_err(|_| bad())?;
    let (header_len, _) = layout.compression_header_len(&first, what)?;
    let chars = b64_len(header_len);
    let mut header = BASE64_STANDARD.decode(text.get(..chars).ok_or_else(bad)?).map_err(|_| bad())?;
    if header.len() != header_len {
        return Err(bad());
    }
    if layout.fix_compression_header(&mut header).0 {
        text[..chars].copy_from_slice(BASE64_STANDARD.encode(&header).as_bytes());
    }
    Ok(())
}

/// `bytes`, rewritten if vtkio needs it (see the module docs).
pub(crate) fn normalize(bytes: &[u8]) -> Result<Cow<'_, [u8]>, VtuError> {
    let Some(root) = find(bytes, b"<VTKFile", 0) else {
        return Ok(Cow::Borrowed(bytes)); // vtkio will say what is wrong
    };
    let root_end = find(bytes, b">", root).ok_or_else(|| VtuError::malformed("unclosed <VTKFile> tag"))?;
    let root_tag = &bytes[root..root_end];
    let compressor = attribute(root_tag, "compressor").map(|r| &root_tag[r]);
    let layout = Layout {
        header: if attribute_is(root_tag, "header_type", "UInt64") { 8 } else { 4 },
        big_endian: attribute_is(root_tag, "byte_order", "BigEndian"),
        // vtkio reads any other compressor name as no compression.
        compressed: compressor.is_some_and(|c| {
            [&b"vtkZLibDataCompressor"[..], b"vtkLZ4DataCompressor", b"vtkLZMADataCompressor"]
                .contains(&c.trim_ascii())
        }),
    };
    let appended = find(bytes, b"<AppendedData", root_end);
    let head_end = appended.unwrap_or(bytes.len());
    let appended_tag = match appended {
        Some(start) => {
            let end =
                find(bytes, b">", start).ok_or_else(|| VtuError::malformed("unclosed <AppendedData> tag"))?;
            Some((start, end))
        }
        None => None,
    };
    let raw = appended_tag.is_some_and(|(s, e)| attribute_is(&bytes[s..e], "encoding", "raw"));
    if !layout.compressed && !raw {
        return Ok(Cow::Borrowed(bytes));
    }
    let tags = array_tags(bytes, head_end)?;
    let mut out = bytes.to_vec();
    if layout.compressed {
        for content in tags.iter().filter_map(|t| t.content.clone()) {
            fix_base64_header(&layout, &mut out[content])?;
        }
    }
    let Some((tag_start, tag_end)) = appended_tag else {
        return Ok(Cow::Owned(out));
    };
    // The data starts after the first '_' after the tag; offsets count from there.
    let underscore = find(bytes, b"_", tag_end).filter(|&u| bytes[tag_end + 1..u].trim_ascii().is_empty());
    let data_start =
        underscore.ok_or_else(|| VtuError::malformed("<AppendedData> does not start with '_'"))? + 1;
    if !raw {
        // Base64 appended data: fix the compression headers in place.
        for (_, offset) in tags.iter().filter_map(|t| t.offset.clone()) {
            let text = out.get_mut(data_start.saturating_add(offset)..).unwrap_or_default();
            fix_base64_header(&layout, text)?;
        }
        return Ok(Cow::Owned(out));
    }
    let close = bytes
        .windows(b"</AppendedData>".len())
        .rposition(|w| w == b"</AppendedData>")
        .filter(|&c| c >= data_start)
        .ok_or_else(|| VtuError::malformed("no </AppendedData> after the appended data"))?;
    let data = &bytes[data_start..close];

    // Encode every array on its own; remember where each one's text starts.
    let mut offsets: Vec<usize> = tags.iter().filter_map(|t| t.offset.as_ref().map(|o| o.1)).collect();
    offsets.sort_unstable();
    offsets.dedup();
    let mut encoded = String::new();
    let mut new_offsets = Vec::with_capacity(offsets.len());
    for &offset in &offsets {
        new_offsets.push(encoded.len());
        encode_raw_array(&layout, data, offset, &mut encoded)?;
    }

    // The XML before <AppendedData> with new offsets, then the base64 data.
    let mut result = Vec::with_capacity(tag_start + encoded.len() + 64);
    let mut copied = 0;
    for (range, offset) in tags.iter().filter_map(|t| t.offset.clone()) {
        let new = new_offsets[offsets.binary_search(&offset).unwrap_or_default()];
        result.extend_from_slice(&out[copied..range.start]);
        result.extend_from_slice(new.to_string().as_bytes());
        copied = range.end;
    }
    result.extend_from_slice(&out[copied..tag_start]);
    result.extend_from_slice(b"<AppendedData encoding=\"base64\">\n_");
    result.extend_from_slice(encoded.as_bytes());
    result.push(b'\n');
    result.extend_from_slice(&bytes[close..]);
    Ok(Cow::Owned(result))
}

/// Appends the base64 form of the raw array at `offset` of `data` to `out`.
fn encode_raw_array(layout: &Layout, data: &[u8], offset: usize, out: &mut String) -> Result<(), VtuError> {
    let what = format!("the appended array at offset {offset}");
    let past_end = || VtuError::malformed(format!("{what} runs past the end of the appended data"));
    let h = layout.header;
    let first = data.get(offset..offset.saturating_add(h)).ok_or_else(past_end)?;
    if !layout.compressed {
        let size = usize::try_from(layout.read(first)).unwrap_or(usize::MAX);
        let block = data.get(offset..offset.saturating_add(h).saturating_add(size)).ok_or_else(past_end)?;
        BASE64_STANDARD.encode_string(block, out);
        return Ok(());
    }
    let (header_len, _) = layout.compression_header_len(first, &what)?;
    let mut header = data.get(offset..offset.saturating_add(header_len)).ok_or_else(past_end)?.to_vec();
    let (_, total) = layout.fix_compression_header(&mut header);
    let start = offset + header_len;
    let total = usize::try_from(total).unwrap_or(usize::MAX);
    let blocks = data.get(start..start.saturating_add(total)).ok_or_else(past_end)?;
    BASE64_STANDARD.encode_string(&header, out);
    BASE64_STANDARD.encode_string(blocks, out);
    Ok(())
}

/// The names of the point and cell data arrays each `<Piece>` declares, from the
/// XML text (vtkio silently skips arrays it fails to decode).
pub(crate) fn declared_fields(bytes: &[u8]) -> Vec<[Vec<String>; 2]> {
    let head = &bytes[..find(bytes, b"<AppendedData", 0).unwrap_or(bytes.len())];
    let mut pieces = Vec::new();
    let mut from = 0;
    while let Some(start) = find(head, b"<Piece", from) {
        let end = find(head, b"</Piece>", start).unwrap_or(head.len());
        let piece = &head[start..end];
        pieces.push([section_arrays(piece, b"PointData"), section_arrays(piece, b"CellData")]);
        from = end;
    }
    pieces
}

fn section_arrays(piece: &[u8], section: &[u8]) -> Vec<String> {
    let open = [b"<", section].concat();
    let Some(start) = find(piece, &open, 0) else { return Vec::new() };
    let tag_end = find(piece, b">", start).unwrap_or(piece.len());
    if piece[..tag_end].ends_with(b"/") {
        return Vec::new();
    }
    let close = [b"</", section].concat();
    let end = find(piece, &close, start).unwrap_or(piece.len());
    let body = &piece[tag_end..end];
    let mut names = Vec::new();
    let mut from = 0;
    while let Some(at) = find(body, b"<DataArray", from) {
        let tag = &body[at..find(body, b">", at).unwrap_or(body.len())];
        let name = attribute(tag, "Name").map(|r| String::from_utf8_lossy(&tag[r]).into_owned());
        names.push(unescape(&name.unwrap_or_default()));
        from = at + 1;
    }
    names
}

fn unescape(text: &str) -> String {
    text.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attributes_are_found_by_whole_name() {
        let tag = br#"<DataArray Name="offset" format = 'appended' offset="96"  "#;
        assert_eq!(&tag[attribute(tag, "offset").unwrap()], b"96");
        assert!(attribute_is(tag, "format", "appended"));
        assert!(attribute(tag, "type").is_none());
    }

    #[test]
    fn a_zero_partial_block_size_becomes_the_block_size() {
        let layout = Layout { header: 4, big_endian: false, compressed: true };
        let mut header: Vec<u8> = [2u32, 32768, 0, 10, 20].iter().flat_map(|v| v.to_le_bytes()).collect();
        let mut text = BASE64_STANDARD.encode(&header).into_bytes();
        text.extend_from_slice(b"AAAA");
        fix_base64_header(&layout, &mut text).unwrap();
        header[8..12].copy_from_slice(&32768u32.to_le_bytes());
        assert_eq!(BASE64_STANDARD.decode(&text[..text.len() - 4]).unwrap(), header);
    }

    #[test]
    fn files_without_raw_or_compressed_data_are_untouched() {
        let text = br#"<VTKFile type="UnstructuredGrid" version="1.0" header_type="UInt64"><X/></VTKFile>"#;
        assert!(matches!(normalize(text).unwrap(), Cow::Borrowed(_)));
    }

    #[test]
    fn empty_compressed_arrays_are_an_error() {
        let layout = Layout { header: 4, big_endian: false, compressed: true };
        let mut data = 0u32.to_le_bytes().to_vec();
        data.extend_from_slice(&[0; 8]);
        let e = encode_raw_array(&layout, &data, 0, &mut String::new()).unwrap_err();
        assert!(e.to_string().contains("empty compressed array"), "{e}");
    }
}
