//! The section readers. Each section has one reader for ASCII and binary (the
//! [`Cursor`] reads values in either encoding); only MSH 2.2 `$Elements`, whose
//! binary layout groups elements under headers, has two loops around a shared
//! per-element reader.

use std::collections::HashMap;

use seam::Point3;

use super::builder::{ElementRecord, MshBuilder};
use super::cursor::{number as parse_number, quote, tokens, trim, Cursor};
use super::element_types::{element_type, ElementType};
use super::{Msh, MshError, MshErrorKind, MshFormat, MshVersion, NodeData, PhysicalName};

/// The largest number of `$NodeData` components accepted (Gmsh uses 1, 3, 9).
const MAX_COMPONENTS: usize = 9;

/// The least bytes an element is counted for when making room for the
/// elements a section header announces (a 4-node element in binary MSH 4.1
/// takes 40): the room is at most a few times the file size, whatever the
/// count says.
const ELEMENT_BYTES: usize = 24;

/// The least bytes of an MSH 2.2 element: "1 15 0 1\n" in text, two ints in
/// binary.
const ELEMENT_V2_BYTES: usize = 8;

/// Parses a whole MSH file.
pub(crate) fn parse_msh(bytes: &[u8]) -> Result<Msh, MshError> {
    let mut cur = Cursor::new(bytes);
    let format = read_mesh_format(&mut cur)?;
    let mut parser = Parser { cur, format, msh: MshBuilder::new(format), entity_physicals: HashMap::new() };
    parser.read_sections()?;
    Ok(parser.msh.finish())
}

/// Reads `$MeshFormat` and sets the cursor's encoding.
fn read_mesh_format(cur: &mut Cursor<'_>) -> Result<MshFormat, MshError> {
    cur.skip_whitespace();
    let Some((at, first)) = cur.line() else {
        return Err(cur.error(0, MshErrorKind::NotMsh { found: "an empty file".into() }));
    };
    match first {
        b"$MeshFormat" => {}
        b"$NOD" | b"$NOE" => {
            return Err(cur.error(at, MshErrorKind::UnsupportedVersion { version: "1".into() }));
        }
        _ => return Err(cur.error(at, MshErrorKind::NotMsh { found: quote(first) })),
    }
    let Some((at, line)) = cur.line() else {
        return Err(cur.truncated());
    };
    let (version, binary, size_bytes) = parse_format_line(line).map_err(|kind| cur.error(at, kind))?;
    if binary {
        read_endianness(cur, size_bytes)?;
    }
    cur.expect_section_end()?;
    Ok(MshFormat { version, binary })
}

/// `version file-type data-size`, for example `4.1 0 8`: the version, whether
/// the file is binary, and `sizeof(size_t)` (MSH 4.1; 8 for 2.2).
fn parse_format_line(line: &[u8]) -> Result<(MshVersion, bool, usize), MshErrorKind> {
    let text = String::from_utf8_lossy(line);
    let words: Vec<&str> = text.split_whitespace().collect();
    let [version, file_type, data_size, ..] = words[..] else {
        return Err(parse_kind("the MSH version, file type and data size, such as 4.1 0 8", &text));
    };
    let version = match version {
        "4.1" => MshVersion::V4_1,
        "2.2" | "2.1" | "2.0" | "2" => MshVersion::V2_2,
        v if v.parse::<f64>().is_ok() => return Err(MshErrorKind::UnsupportedVersion { version: v.into() }),
        v => return Err(parse_kind("an MSH version number such as 4.1", v)),
    };
    let binary = match file_type {
        "0" => false,
        "1" => true,
        t => return Err(parse_kind("file type 0 (ASCII) or 1 (binary)", t)),
    };
    let size_bytes = match (version, data_size) {
        (MshVersion::V4_1, "4") => 4,
        (_, "8") => 8,
        (MshVersion::V4_1, d) => return Err(parse_kind("data size 4 or 8", d)),
        (_, d) => return Err(parse_kind("data size 8", d)),
    };
    Ok((version, binary, size_bytes))
}

fn parse_kind(expected: &str, found: &str) -> MshErrorKind {
    MshErrorKind::Parse { expected: expected.into(), found: quote(found.as_bytes()) }
}

/// Reads the binary int 1 that tells the byte order, and switches to binary.
fn read_endianness(cur: &mut Cursor<'_>, size_bytes: usize) -> Result<(), MshError> {
    cur.mark_binary_file();
    let at = cur.pos();
    let one: [u8; 4] = cur.take(4)?.try_into().expect("take(4) gives 4 bytes");
    let big_endian = match (u32::from_le_bytes(one), u32::from_be_bytes(one)) {
        (1, _) => false,
        (_, 1) => true,
        _ => return Err(cur.parse_error(at, "the binary integer 1 (byte order check)".into(), quote(&one))),
    };
    cur.set_binary(size_bytes, big_endian);
    Ok(())
}

struct Parser<'a> {
    cur: Cursor<'a>,
    format: MshFormat,
    msh: MshBuilder,
    /// MSH 4.1 `$Entities`: physical tags of each (dimension, entity tag).
    entity_physicals: HashMap<(i32, i32), Vec<i32>>,
}

impl Parser<'_> {
    fn read_sections(&mut self) -> Result<(), MshError> {
        while let Some((at, name)) = self.cur.next_section()? {
            self.cur.enter_section(&name);
            let v4 = self.format.version == MshVersion::V4_1;
            match name.as_str() {
                "PhysicalNames" => self.cur.text(|cur| read_physical_names(cur, &mut self.msh))?,
                "Entities" if v4 => self.read_entities()?,
                "Nodes" if v4 => self.read_nodes_v4()?,
                "Nodes" => self.read_nodes_v2()?,
                "Elements" if v4 => self.read_elements_v4()?,
                "Elements" if self.format.binary => self.read_elements_v2_binary()?,
                "Elements" => self.read_elements_v2_ascii()?,
                "NodeData" => self.read_node_data()?,
                "MeshFormat" => return Err(self.unexpected_section(at, &name)),
                _ if name.starts_with("End") => return Err(self.unexpected_section(at, &name)),
                _ => {
                    self.cur.skip_section()?;
                    continue;
                }
            }
            self.cur.expect_section_end()?;
        }
        Ok(())
    }

    fn unexpected_section(&self, at: usize, name: &str) -> MshError {
        let found = quote(format!("${name}").as_bytes());
        self.cur.parse_error(at, "a section header such as $Nodes".into(), found)
    }

    // ----- $Entities (4.1) --------------------------------------------------

    fn read_entities(&mut self) -> Result<(), MshError> {
        let mut counts = [0u64; 4];
        // An entity takes at least "1 0 0 0 0\n", or a tag, 3 doubles and a size_t.
        let sb = self.cur.size_bytes().unwrap_or(0);
        let entity_bytes = self.cur.record_bytes(10, 28 + sb);
        for (dim, count) in counts.iter_mut().enumerate() {
            *count = self.cur.count(entity_bytes, || format!("the number of entities of dimension {dim}"))?;
        }
        self.cur.end_record(|| "the entity counts".into())?;
        for (dim, &count) in (0..).zip(&counts) {
            for _ in 0..count {
                self.read_entity(dim)?;
            }
        }
        Ok(())
    }

    /// One entity: tag, point or bounding box, physical tags, bounding entities.
    fn read_entity(&mut self, dim: i32) -> Result<(), MshError> {
        let cur = &mut self.cur;
        let tag = cur.int(|| format!("the tag of an entity of dimension {dim}"))?;
        let mut bounds = [0.0; 6];
        let n_bounds = if dim == 0 { 3 } else { 6 };
        cur.doubles(&mut bounds[..n_bounds], || format!("{n_bounds} coordinates of entity ({dim}, {tag})"))?;
        let physical_tags = read_tag_list(cur, || format!("the physical tags of entity ({dim}, {tag})"))?;
        if dim > 0 {
            read_tag_list(cur, || format!("the bounding entities of entity ({dim}, {tag})"))?;
        }
        cur.end_record(|| format!("entity ({dim}, {tag})"))?;
        self.entity_physicals.insert((dim, tag), physical_tags);
        Ok(())
    }

    // ----- $Nodes -------------------------------------------------------------

    fn read_nodes_v2(&mut self) -> Result<(), MshError> {
        // A node takes at least "1 0 0 0\n", or an int and 3 doubles.
        let node_bytes = if self.format.binary { 28 } else { 8 };
        let count = self.cur.text(|cur| read_count(cur, node_bytes, "the number of nodes"))?;
        self.msh.reserve_nodes(self.cur.capacity(count, 8));
        // Long ASCII blocks of well-formed records at once (in parallel); any
        // other block record by record.
        let block = self.cur.ascii_block(count, |line, nodes: &mut Vec<(u64, Point3)>| {
            let mut tokens = tokens(line);
            let tag = parse_number::<u64>(tokens.next()?)?;
            nodes.push((tag, coordinates(&mut tokens, 0)?));
            Some(())
        });
        if let Some((nodes, starts)) = block {
            for ((tag, xyz), at) in nodes.into_iter().zip(starts) {
                self.msh.add_node(tag, xyz).map_err(|kind| self.cur.error(at, kind))?;
            }
            return Ok(());
        }
        // Binary records (`int` tag, 3 doubles) all present: checked in the
        // same order as one by one, without the cursor.
        const RECORD: usize = 4 + 24;
        if let Some((start, block)) = self.cur.binary_block(count, RECORD) {
            for (i, record) in block.chunks_exact(RECORD).enumerate() {
                let cur = &self.cur;
                let at = start + i * RECORD;
                let word = |k: usize| cur.word(record.get(k..k + 8).unwrap_or_default());
                let tag = cur.word(record.get(..4).unwrap_or_default()) as u32 as i32;
                let tag = u64::try_from(tag)
                    .map_err(|_| cur.parse_error(at, "a node tag".into(), tag.to_string()))?;
                let xyz = [f64::from_bits(word(4)), f64::from_bits(word(12)), f64::from_bits(word(20))];
                if !xyz.iter().all(|x| x.is_finite()) {
                    byte_swapped_node(cur, at, record, tag)?;
                    return Err(cur.error(at + 4, MshErrorKind::NonFiniteCoordinate { node_tag: tag }));
                }
                self.msh.add_node(tag, xyz).map_err(|kind| self.cur.error(at, kind))?;
            }
            return Ok(());
        }
        for _ in 0..count {
            let at = self.cur.pos();
            let tag = self.cur.int_tag(|| "a node tag".into())?;
            self.read_node(at, tag, 0)?;
        }
        Ok(())
    }

    fn read_nodes_v4(&mut self) -> Result<(), MshError> {
        // A block header takes at least "0 1 0 0\n" (3 ints and a size_t in
        // binary); a node "1\n0 0 0\n" (a size_t and 3 doubles).
        let sb = self.cur.size_bytes().unwrap_or(0);
        let sizes = (self.cur.record_bytes(8, 12 + sb), self.cur.record_bytes(8, sb + 24));
        let [blocks, count, _, _] = read_v4_header(&mut self.cur, "node", sizes)?;
        self.msh.reserve_nodes(self.cur.capacity(count, 8));
        for _ in 0..blocks {
            self.read_node_block_v4()?;
        }
        Ok(())
    }

    /// A 4.1 node block: header, all tags, then all coordinates.
    fn read_node_block_v4(&mut self) -> Result<(), MshError> {
        let cur = &mut self.cur;
        let at = cur.pos();
        let dim = cur.int(|| "the entity dimension of a node block".into())?;
        let entity = cur.int(|| "the entity tag of a node block".into())?;
        let parametric =
            cur.int(|| format!("the parametric flag of the node block of entity ({dim}, {entity})"))?;
        let count_at = cur.pos();
        let count = cur.size(|| format!("the number of nodes of entity ({dim}, {entity})"))?;
        cur.end_record(|| format!("the node block header of entity ({dim}, {entity})"))?;
        let n_parametric = match (parametric, dim) {
            (0, 0..=3) => 0,
            (1, 0..=3) => dim as usize,
            _ => {
                let found = format!("dimension {dim}, parametric flag {parametric}");
                return Err(cur.parse_error(
                    at,
                    "a node block of dimension 0 to 3 with flag 0 or 1".into(),
                    found,
                ));
            }
        };
        // A node takes at least "1\n0 0 0\n", or a size_t and 3 doubles
        // (and its parametric coordinates).
        let sb = cur.size_bytes();
        let node_bytes = cur.record_bytes(8 + 2 * n_parametric, sb.unwrap_or(0) + 8 * (3 + n_parametric));
        cur.check_count(count_at, count, sb, node_bytes, || {
            format!("the number of nodes of entity ({dim}, {entity})")
        })?;
        // Long ASCII blocks of well-formed records at once (in parallel); any
        // other block record by record.
        if let Some(sb) = cur.size_bytes() {
            if let Some((tags_at, tag_bytes)) = cur.binary_block(count, sb) {
                let record = 8 * (3 + n_parametric);
                let Some((coords_at, coords)) = cur.binary_block(count, record) else {
                    // The file ends inside the coordinates: node by node.
                    let tags: Vec<(usize, u64)> = (tag_bytes.chunks_exact(sb).enumerate())
                        .map(|(i, word)| (tags_at + i * sb, cur.word(word)))
                        .collect();
                    for (at, tag) in tags {
                        self.read_node(at, tag, n_parametric)?;
                    }
                    return Ok(());
                };
                for (i, (word, values)) in
                    tag_bytes.chunks_exact(sb).zip(coords.chunks_exact(record)).enumerate()
                {
                    let cur = &self.cur;
                    let tag = cur.word(word);
                    let x =
                        |k: usize| f64::from_bits(cur.word(values.get(8 * k..8 * k + 8).unwrap_or_default()));
                    let xyz = [x(0), x(1), x(2)];
                    if !xyz.iter().all(|x| x.is_finite()) {
                        let kind = MshErrorKind::NonFiniteCoordinate { node_tag: tag };
                        return Err(cur.error(coords_at + i * record, kind));
                    }
                    self.msh.add_node(tag, xyz).map_err(|kind| self.cur.error(tags_at + i * sb, kind))?;
                }
                return Ok(());
            }
        }
        let block = cur.ascii_block(count, |line, tags: &mut Vec<u64>| {
            let mut tokens = tokens(line);
            tags.push(parse_number(tokens.next()?)?);
            tokens.next().is_none().then_some(())
        });
        let tags = match block {
            Some((tags, starts)) => starts.into_iter().zip(tags).collect(),
            None => {
                let mut tags = Vec::with_capacity(cur.capacity(count, 2));
                for _ in 0..count {
                    let at = cur.pos();
                    tags.push((at, cur.size(|| format!("a node tag of entity ({dim}, {entity})"))?));
                    cur.end_record(|| "a node tag".into())?;
                }
                tags
            }
        };
        let block = cur.ascii_block(count, |line, points: &mut Vec<Point3>| {
            points.push(coordinates(&mut tokens(line), n_parametric)?);
            Some(())
        });
        if let Some((points, _)) = block {
            for ((at, tag), xyz) in tags.into_iter().zip(points) {
                self.msh.add_node(tag, xyz).map_err(|kind| self.cur.error(at, kind))?;
            }
            return Ok(());
        }
        for (at, tag) in tags {
            self.read_node(at, tag, n_parametric)?;
        }
        Ok(())
    }

    /// The coordinates of node `tag` (whose record starts at `at`), skipping
    /// `n_parametric` parametric coordinates.
    fn read_node(&mut self, at: usize, tag: u64, n_parametric: usize) -> Result<(), MshError> {
        let cur = &mut self.cur;
        let start = cur.pos();
        let mut values = [0.0; 6];
        cur.doubles(&mut values[..3 + n_parametric], || match n_parametric {
            0 => format!("3 coordinates for node {tag}"),
            n => format!("3 coordinates and {n} parametric coordinates for node {tag}"),
        })?;
        cur.end_record(|| format!("node {tag}"))?;
        let xyz = [values[0], values[1], values[2]];
        if !xyz.iter().all(|x| x.is_finite()) {
            return Err(cur.error(start, MshErrorKind::NonFiniteCoordinate { node_tag: tag }));
        }
        self.msh.add_node(tag, xyz).map_err(|kind| cur.error(at, kind))
    }

    // ----- $Elements ----------------------------------------------------------

    fn read_elements_v4(&mut self) -> Result<(), MshError> {
        // A block header takes at least "2 1 2 0\n" (3 ints and a size_t in
        // binary); an element "1 1\n" (2 size_t).
        let sb = self.cur.size_bytes().unwrap_or(0);
        let sizes = (self.cur.record_bytes(8, 12 + sb), self.cur.record_bytes(4, 2 * sb));
        let [blocks, count, _, _] = read_v4_header(&mut self.cur, "element", sizes)?;
        self.msh.reserve_elements(self.cur.capacity(count, ELEMENT_BYTES));
        for _ in 0..blocks {
            self.read_element_block_v4()?;
        }
        Ok(())
    }

    /// A 4.1 element block: header, then one record (tag, node tags) per element.
    fn read_element_block_v4(&mut self) -> Result<(), MshError> {
        let cur = &mut self.cur;
        let dim = cur.int(|| "the entity dimension of an element block".into())?;
        let entity = cur.int(|| "the entity tag of an element block".into())?;
        let at = cur.pos();
        let number = cur.int(|| format!("the element type of the block of entity ({dim}, {entity})"))?;
        let count_at = cur.pos();
        let count = cur.size(|| format!("the number of elements of entity ({dim}, {entity})"))?;
        cur.end_record(|| format!("the element block header of entity ({dim}, {entity})"))?;
        let element_type =
            known_type(cur, at, number, || format!("the element block of entity ({dim}, {entity})"))?;
        let sb = cur.size_bytes();
        // An element is its tag and node tags: a digit and a blank each, or size_t.
        let element_bytes = cur.record_bytes(2, sb.unwrap_or(0)) * (element_type.nodes + 1);
        cur.check_count(count_at, count, sb, element_bytes, || {
            format!("the number of elements of entity ({dim}, {entity})")
        })?;
        let physical_tags = self.entity_physicals.get(&(dim, entity)).cloned().unwrap_or_default();
        // Long ASCII blocks of well-formed records at once (in parallel); any
        // other block record by record.
        let per_line = element_type.nodes + 1;
        if let Some(sb) = cur.size_bytes() {
            if let Some((at, block)) = cur.binary_block(count, per_line * sb) {
                let mut node_tags = Vec::with_capacity(element_type.nodes);
                for (i, record) in block.chunks_exact(per_line * sb).enumerate() {
                    let cur = &self.cur;
                    let (tag, nodes) = record.split_at(sb);
                    let tag = cur.word(tag);
                    node_tags.clear();
                    node_tags.extend(nodes.chunks_exact(sb).map(|word| cur.word(word)));
                    let physical_tags = &physical_tags;
                    let record =
                        ElementRecord { tag, element_type, entity, physical_tags, node_tags: &node_tags };
                    self.msh.add_element(record).map_err(|kind| cur.error(at + i * per_line * sb, kind))?;
                }
                return Ok(());
            }
        }
        let block = cur.ascii_block(count, |line, values: &mut Vec<u64>| {
            let before = values.len();
            for token in tokens(line) {
                if values.len() - before == per_line {
                    return None;
                }
                values.push(parse_number(token)?);
            }
            (values.len() - before == per_line).then_some(())
        });
        if let Some((values, starts)) = block {
            for (record, at) in values.chunks_exact(per_line).zip(starts) {
                let (&tag, node_tags) = record.split_first().unwrap_or((&0, &[]));
                let record =
                    ElementRecord { tag, element_type, entity, physical_tags: &physical_tags, node_tags };
                self.msh.add_element(record).map_err(|kind| self.cur.error(at, kind))?;
            }
            return Ok(());
        }
        let mut node_tags = Vec::with_capacity(element_type.nodes);
        for _ in 0..count {
            let cur = &mut self.cur;
            let at = cur.pos();
            let tag = cur.size(|| format!("an element tag of entity ({dim}, {entity})"))?;
            node_tags.clear();
            for _ in 0..element_type.nodes {
                node_tags.push(cur.size(|| format!("{} node tags for element {tag}", element_type.nodes))?);
            }
            cur.end_record(|| format!("element {tag}"))?;
            let record = ElementRecord {
                tag,
                element_type,
                entity,
                physical_tags: &physical_tags,
                node_tags: &node_tags,
            };
            self.msh.add_element(record).map_err(|kind| self.cur.error(at, kind))?;
        }
        Ok(())
    }

    /// 2.2 ASCII: `tag type ntags tags... nodes...` per line.
    fn read_elements_v2_ascii(&mut self) -> Result<(), MshError> {
        let count = read_count(&mut self.cur, ELEMENT_V2_BYTES, "the number of elements")?;
        for _ in 0..count {
            let cur = &mut self.cur;
            let at = cur.pos();
            let tag = cur.int_tag(|| "an element tag".into())?;
            let number = cur.int(|| format!("the type of element {tag}"))?;
            let n_tags = cur.int(|| format!("the number of tags of element {tag}"))?;
            self.read_element_v2(at, tag, number, n_tags)?;
        }
        Ok(())
    }

    /// 2.2 binary: headers `type count ntags`, each followed by `count` records
    /// `tag tags... nodes...`.
    fn read_elements_v2_binary(&mut self) -> Result<(), MshError> {
        let total = self.cur.text(|cur| read_count(cur, ELEMENT_V2_BYTES, "the number of elements"))?;
        let mut read = 0u64;
        while read < total {
            let cur = &mut self.cur;
            let at = cur.pos();
            let number = cur.int(|| "the element type of an element header".into())?;
            let count = cur.int(|| "the number of elements of an element header".into())?;
            let n_tags = cur.int(|| "the number of tags of an element header".into())?;
            let what = || "the number of elements of an element header".to_string();
            match cur.check_count(at + 4, u64::from(count as u32), Some(4), ELEMENT_V2_BYTES, what) {
                // A negative count is named as such below.
                Err(e) if count >= 0 || matches!(e.kind(), MshErrorKind::ByteSwapped { .. }) => {
                    return Err(e)
                }
                _ => {}
            }
            let count = u64::try_from(count).ok().filter(|&c| c <= total - read).ok_or_else(|| {
                let expected = format!("at most {} elements in an element header", total - read);
                cur.parse_error(at, expected, count.to_string())
            })?;
            if !self.read_element_block_v2(count, number, n_tags)? {
                for _ in 0..count {
                    let at = self.cur.pos();
                    let tag = self.cur.int_tag(|| "an element tag".into())?;
                    self.read_element_v2(at, tag, number, n_tags)?;
                }
            }
            read += count;
        }
        Ok(())
    }

    /// 2.2 binary: the `count` records of a known element type with `n_tags`
    /// tags if they are all present, checked in the same order as one by one,
    /// without the cursor; false (nothing read) otherwise.
    fn read_element_block_v2(&mut self, count: u64, number: i32, n_tags: i32) -> Result<bool, MshError> {
        let element_type = u32::try_from(number).ok().and_then(element_type);
        let (Some(element_type), Ok(n_tags)) = (element_type, usize::try_from(n_tags)) else {
            return Ok(false);
        };
        let Some(ints) = n_tags.checked_add(1 + element_type.nodes) else { return Ok(false) };
        let Some((start, block)) = self.cur.binary_block(count, 4 * ints) else { return Ok(false) };
        let mut node_tags = Vec::with_capacity(element_type.nodes);
        for (i, record) in block.chunks_exact(4 * ints).enumerate() {
            let cur = &self.cur;
            let at = start + i * 4 * ints;
            let int = |k: usize| cur.word(record.get(4 * k..4 * k + 4).unwrap_or_default()) as u32 as i32;
            let tag = u64::try_from(int(0))
                .map_err(|_| cur.parse_error(at, "an element tag".into(), int(0).to_string()))?;
            let physical = if n_tags > 0 { int(1) } else { 0 };
            let entity = if n_tags > 1 { int(2) } else { 0 };
            node_tags.clear();
            for k in 1 + n_tags..ints {
                let node = u64::try_from(int(k)).map_err(|_| {
                    let what = format!("{} node tags for element {tag}", element_type.nodes);
                    cur.parse_error(at + 4 * k, what, int(k).to_string())
                })?;
                node_tags.push(node);
            }
            let physical_tags: &[i32] = if physical == 0 { &[] } else { &[physical] };
            let record = ElementRecord { tag, element_type, entity, physical_tags, node_tags: &node_tags };
            self.msh.add_element(record).map_err(|kind| cur.error(at, kind))?;
        }
        Ok(true)
    }

    /// The rest of a 2.2 element after its tag: `n_tags` ints (physical tag,
    /// entity tag, partitions...) and the node tags.
    fn read_element_v2(&mut self, at: usize, tag: u64, number: i32, n_tags: i32) -> Result<(), MshError> {
        let cur = &mut self.cur;
        let element_type = known_type(cur, at, number, || format!("element {tag}"))?;
        let n_tags = u32::try_from(n_tags).map_err(|_| {
            cur.parse_error(at, format!("the number of tags of element {tag}"), n_tags.to_string())
        })?;
        let (mut physical, mut entity) = (0, 0);
        for i in 0..n_tags {
            let value = cur.int(|| format!("{n_tags} tags for element {tag}"))?;
            match i {
                0 => physical = value,
                1 => entity = value,
                _ => {}
            }
        }
        let mut node_tags = Vec::with_capacity(element_type.nodes);
        for _ in 0..element_type.nodes {
            node_tags.push(cur.int_tag(|| format!("{} node tags for element {tag}", element_type.nodes))?);
        }
        cur.end_record(|| format!("element {tag}"))?;
        let physical_tags: &[i32] = if physical == 0 { &[] } else { &[physical] };
        let record = ElementRecord { tag, element_type, entity, physical_tags, node_tags: &node_tags };
        self.msh.add_element(record).map_err(|kind| cur.error(at, kind))
    }

    // ----- $NodeData ----------------------------------------------------------

    fn read_node_data(&mut self) -> Result<(), MshError> {
        let header = self.cur.text(read_node_data_header)?;
        let (name, components) = (header.name, header.components);
        let mut values = vec![f64::NAN; self.msh.node_count() * components];
        let mut entry = [0.0; MAX_COMPONENTS];
        for _ in 0..header.entries {
            let cur = &mut self.cur;
            let at = cur.pos();
            let node_tag = cur.int_tag(|| format!("a node tag of node data {name:?}"))?;
            let index = self.msh.node_index(node_tag).ok_or_else(|| {
                cur.error(at, MshErrorKind::UnknownDataNode { name: name.clone(), node_tag })
            })?;
            cur.doubles(&mut entry[..components], || format!("{components} values for node {node_tag}"))?;
            cur.end_record(|| format!("the values of node {node_tag}"))?;
            values[index * components..(index + 1) * components].copy_from_slice(&entry[..components]);
        }
        self.msh.add_node_data(NodeData { name, time_step: header.time_step, components, values });
        Ok(())
    }
}

/// The error for an MSH 2.2 binary node record (int tag, 3 doubles) at `at`
/// with a non-finite coordinate when, byte-swapped, it is a node with finite
/// coordinates and a positive tag: the data are in the other byte order.
fn byte_swapped_node(cur: &Cursor<'_>, at: usize, record: &[u8], tag: u64) -> Result<(), MshError> {
    let Some(big_endian) = cur.big_endian() else { return Ok(()) };
    let swapped = |k: usize, n: usize| {
        let word = cur.word(record.get(k..k + n).unwrap_or_default());
        if n == 4 {
            u64::from((word as u32).swap_bytes())
        } else {
            word.swap_bytes()
        }
    };
    let other_tag = swapped(0, 4) as u32 as i32;
    let xyz = [4, 12, 20].map(|k| f64::from_bits(swapped(k, 8)));
    if other_tag <= 0 || !xyz.iter().all(|x| x.is_finite()) {
        return Ok(());
    }
    let kind = MshErrorKind::ByteSwapped {
        what: "a node record".into(),
        announced: format!("node {tag} with a non-finite coordinate"),
        other: format!("node {other_tag} at ({}, {}, {})", xyz[0], xyz[1], xyz[2]),
        big_endian,
    };
    Err(cur.error(at, kind))
}

/// The 3 finite coordinates, then `n_parametric` numbers, that end an ASCII
/// node record (as [`Parser::read_node`] reads them); `None` if the record is
/// anything else.
fn coordinates<'t>(tokens: &mut impl Iterator<Item = &'t [u8]>, n_parametric: usize) -> Option<Point3> {
    let mut xyz = [0.0; 3];
    for x in &mut xyz {
        *x = parse_number::<f64>(tokens.next()?)?;
    }
    for _ in 0..n_parametric {
        parse_number::<f64>(tokens.next()?)?;
    }
    let finite = xyz.iter().all(|x| x.is_finite());
    (finite && tokens.next().is_none()).then_some(xyz)
}

/// A count alone on its line, of records of at least `record_bytes` bytes.
fn read_count(cur: &mut Cursor<'_>, record_bytes: usize, what: &str) -> Result<u64, MshError> {
    let count = cur.count(record_bytes, || what.to_string())?;
    cur.end_record(|| what.to_string())?;
    Ok(count)
}

/// A `size_t` count followed by that many `int` tags.
fn read_tag_list(cur: &mut Cursor<'_>, what: impl Fn() -> String) -> Result<Vec<i32>, MshError> {
    let count = cur.count(cur.record_bytes(2, 4), &what)?;
    let mut tags = Vec::with_capacity(cur.capacity(count, 2));
    for _ in 0..count {
        tags.push(cur.int(&what)?);
    }
    Ok(tags)
}

/// The 4.1 `$Nodes`/`$Elements` header: blocks, count, smallest and largest
/// tag; `item` is "node" or "element", `sizes` the least bytes of a block
/// and of an item.
fn read_v4_header(cur: &mut Cursor<'_>, item: &str, sizes: (usize, usize)) -> Result<[u64; 4], MshError> {
    let names = [
        format!("the number of {item} blocks"),
        format!("the number of {item}s"),
        format!("the smallest {item} tag"),
        format!("the largest {item} tag"),
    ];
    let mut header = [0; 4];
    for (i, (value, name)) in header.iter_mut().zip(&names).enumerate() {
        *value = match i {
            0 => cur.count(sizes.0, || name.clone())?,
            1 => cur.count(sizes.1, || name.clone())?,
            _ => cur.size(|| name.clone())?,
        };
    }
    cur.end_record(|| format!("the {item} section header"))?;
    Ok(header)
}

/// The element type with this number, or an error about `whose` type it is.
fn known_type(
    cur: &Cursor<'_>,
    at: usize,
    number: i32,
    whose: impl Fn() -> String,
) -> Result<ElementType, MshError> {
    u32::try_from(number).ok().and_then(element_type).ok_or_else(|| {
        cur.parse_error(at, format!("a known Gmsh element type for {}", whose()), number.to_string())
    })
}

fn read_physical_names(cur: &mut Cursor<'_>, msh: &mut MshBuilder) -> Result<(), MshError> {
    let count = read_count(cur, 7, "the number of physical names")?;
    for _ in 0..count {
        let at = cur.pos();
        let dim = cur.int(|| "the dimension of a physical name".into())?;
        let tag = cur.int(|| format!("the tag of a physical name of dimension {dim}"))?;
        let dim = u8::try_from(dim)
            .ok()
            .filter(|&d| d <= 3)
            .ok_or_else(|| cur.parse_error(at, "a dimension from 0 to 3".into(), dim.to_string()))?;
        let (at, rest) = cur.rest_of_line();
        let name = unquote(rest).ok_or_else(|| {
            cur.parse_error(at, format!("the quoted name of physical group ({dim}, {tag})"), quote(rest))
        })?;
        msh.add_physical_name(PhysicalName { dim, tag, name });
    }
    Ok(())
}

/// What the text header of a `$NodeData` section says.
struct NodeDataHeader {
    name: String,
    time_step: i32,
    components: usize,
    entries: u64,
}

/// String tags (the first is the name), real tags (the first is the time),
/// integer tags (time step, components, number of entries, ...).
fn read_node_data_header(cur: &mut Cursor<'_>) -> Result<NodeDataHeader, MshError> {
    let n_strings = read_count(cur, 1, "the number of string tags")?;
    let mut name = None;
    for _ in 0..n_strings {
        let (_, line) = cur.line().ok_or_else(|| cur.truncated())?;
        let text = unquote(line).unwrap_or_else(|| String::from_utf8_lossy(line).into_owned());
        name.get_or_insert(text);
    }
    let n_reals = read_count(cur, 2, "the number of real tags")?;
    for _ in 0..n_reals {
        cur.doubles(&mut [0.0], || "a real tag".into())?;
        cur.end_record(|| "a real tag".into())?;
    }
    let at = cur.pos();
    let n_ints = read_count(cur, 2, "the number of integer tags")?;
    let mut ints = Vec::with_capacity(cur.capacity(n_ints, 2));
    for _ in 0..n_ints {
        ints.push(cur.int(|| "an integer tag".into())?);
        cur.end_record(|| "an integer tag".into())?;
    }
    let &[time_step, components, entries, ..] = ints.as_slice() else {
        let expected = "at least 3 integer tags (time step, components, number of nodes)";
        return Err(cur.parse_error(at, expected.into(), n_ints.to_string()));
    };
    let components = usize::try_from(components)
        .ok()
        .filter(|c| (1..=MAX_COMPONENTS).contains(c))
        .ok_or_else(|| cur.parse_error(at, "1 to 9 components".into(), components.to_string()))?;
    let entries = u64::try_from(entries)
        .map_err(|_| cur.parse_error(at, "a number of nodes".into(), entries.to_string()))?;
    Ok(NodeDataHeader { name: name.unwrap_or_default(), time_step, components, entries })
}

/// `"name"` → `name`; `None` if not quoted.
fn unquote(text: &[u8]) -> Option<String> {
    let inner = trim(text).strip_prefix(b"\"")?.strip_suffix(b"\"")?;
    Some(String::from_utf8_lossy(inner).into_owned())
}
