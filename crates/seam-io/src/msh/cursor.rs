//! A cursor over the bytes of an MSH file that reads the same logical values
//! (ints, sizes, doubles, records) from ASCII text or from binary data, so that
//! each section has one reader whatever the encoding.
//!
//! ASCII reading is line-aware: a value is looked for on the current line only,
//! and [`Cursor::end_record`] requires the rest of the line to be blank. A missing
//! or extra value is therefore reported on its own line instead of shifting every
//! value after it. In binary mode records have no terminator and `end_record`
//! does nothing.

use std::str::FromStr;

use super::error::{Location, MshError, MshErrorKind};

/// How the values of the current section are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Encoding {
    /// Whitespace-separated text, one record per line.
    Ascii,
    /// Raw values: `int` 4 bytes, `size_t` 4 or 8 bytes, `double` 8 bytes.
    Binary {
        /// `sizeof(size_t)` from `$MeshFormat` (MSH 4.1).
        size_bytes: usize,
        /// Whether the endianness check read 1 as big-endian.
        big_endian: bool,
    },
}

/// Reading position in an MSH file, with what is needed to locate errors.
pub(crate) struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    encoding: Encoding,
    binary_file: bool,
    section: String,
    /// Where the current section's last `$End<Section>` line starts, if the
    /// file has one: the bytes its counts must fit in ([`Cursor::check_count`]).
    section_end: Option<usize>,
}

/// The lines of ASCII blocks that one thread parses at a time; shorter blocks
/// are read value by value.
pub(crate) const BLOCK_LINES: usize = 4096;

/// A description of an expected value, built only when an error needs it.
pub(crate) trait What: Fn() -> String {}
impl<F: Fn() -> String> What for F {}

impl<'a> Cursor<'a> {
    /// A cursor at the start of `bytes`, reading ASCII.
    pub fn new(bytes: &'a [u8]) -> Self {
        Cursor {
            bytes,
            pos: 0,
            encoding: Encoding::Ascii,
            binary_file: false,
            section: "MeshFormat".into(),
            section_end: None,
        }
    }

    /// The current byte offset.
    pub fn pos(&self) -> usize {
        self.pos
    }

    /// Switches to binary values; from now on errors are located by byte offset.
    pub fn set_binary(&mut self, size_bytes: usize, big_endian: bool) {
        self.binary_file = true;
        self.encoding = Encoding::Binary { size_bytes, big_endian };
    }

    /// Locates errors by byte offset (the file is binary, even where it has text).
    pub fn mark_binary_file(&mut self) {
        self.binary_file = true;
    }

    /// Records the section being read, for truncation messages, and where
    /// its last `$End<Section>` line is.
    pub fn enter_section(&mut self, name: &str) {
        self.section = name.to_string();
        let marker = format!("$End{name}");
        let rest = &self.bytes[self.pos..];
        self.section_end = memchr::memmem::rfind_iter(rest, marker.as_bytes())
            .find(|&i| {
                let after = rest.get(i + marker.len());
                (i == 0 || rest[i - 1] == b'\n') && after.is_none_or(|b| b.is_ascii_whitespace())
            })
            .map(|i| self.pos + i);
    }

    /// Runs `read` on text (`$PhysicalNames`, counts of MSH 2.2, `$NodeData`
    /// headers), which binary files also store as ASCII.
    pub fn text<T>(&mut self, read: impl FnOnce(&mut Self) -> Result<T, MshError>) -> Result<T, MshError> {
        let encoding = std::mem::replace(&mut self.encoding, Encoding::Ascii);
        let result = read(self);
        self.encoding = encoding;
        result
    }

    /// A count of the records that follow (a `size_t`), each at least
    /// `record_bytes` long: checked by [`Cursor::check_count`].
    pub fn count(&mut self, record_bytes: usize, what: impl What) -> Result<u64, MshError> {
        let at = self.pos;
        let count = self.size(&what)?;
        self.check_count(at, count, self.size_bytes(), record_bytes, what)?;
        Ok(count)
    }

    /// Checks `count`, written at byte `at` (a binary integer `width` bytes
    /// wide, or text for `None`), records of at least `record_bytes` bytes:
    /// more than fit before the section's `$End` line is an error at the
    /// count, before anything is read or allocated for it; in binary, when
    /// the count would fit in the other byte order, the data are
    /// byte-swapped against the byte-order check. Without an `$End` line
    /// (a truncated file) nothing is checked: reading reports the truncation.
    pub fn check_count(
        &self,
        at: usize,
        count: u64,
        width: Option<usize>,
        record_bytes: usize,
        what: impl What,
    ) -> Result<(), MshError> {
        let Some(end) = self.section_end.filter(|&end| end >= self.pos) else { return Ok(()) };
        let bytes = (end - self.pos) as u64;
        let room = bytes / record_bytes.max(1) as u64;
        if count <= room {
            return Ok(());
        }
        if let (Some(width), Encoding::Binary { big_endian, .. }) = (width, self.encoding) {
            let swapped = match width {
                4 => u64::from((count as u32).swap_bytes()),
                _ => count.swap_bytes(),
            };
            if swapped <= room {
                let (announced, other) = (count.to_string(), swapped.to_string());
                return Err(
                    self.error(at, MshErrorKind::ByteSwapped { what: what(), announced, other, big_endian })
                );
            }
        }
        let section = self.section.clone();
        Err(self.error(at, MshErrorKind::CountTooLarge { what: what(), count, bytes, room, section }))
    }

    /// Whether the binary data are read as big-endian (`None` in ASCII).
    pub fn big_endian(&self) -> Option<bool> {
        match self.encoding {
            Encoding::Binary { big_endian, .. } => Some(big_endian),
            Encoding::Ascii => None,
        }
    }

    /// The least bytes of a record that takes `ascii` bytes in text and
    /// `binary` in binary, in the current encoding.
    pub fn record_bytes(&self, ascii: usize, binary: usize) -> usize {
        match self.encoding {
            Encoding::Ascii => ascii,
            Encoding::Binary { .. } => binary,
        }
    }

    /// How many records of at least `min_record_bytes` bytes can still follow:
    /// a safe capacity for a count read from the file.
    pub fn capacity(&self, count: u64, min_record_bytes: usize) -> usize {
        let remaining = (self.bytes.len() - self.pos) / min_record_bytes.max(1);
        usize::try_from(count).unwrap_or(usize::MAX).min(remaining)
    }

    // ----- errors -------------------------------------------------------------

    /// The location of byte `pos`: its line in ASCII files, the offset in binary ones.
    pub fn location(&self, pos: usize) -> Location {
        let pos = pos.min(self.bytes.len());
        if self.binary_file {
            Location::Offset(pos)
        } else {
            Location::Line(1 + self.bytes[..pos].iter().filter(|&&b| b == b'\n').count())
        }
    }

    /// An error located at byte `pos`.
    pub fn error(&self, pos: usize, kind: MshErrorKind) -> MshError {
        MshError::at(self.location(pos), kind)
    }

    /// A parse error at byte `pos`.
    pub fn parse_error(&self, pos: usize, expected: String, found: String) -> MshError {
        self.error(pos, MshErrorKind::Parse { expected, found })
    }

    /// The error for a file that ends inside the current section, located at the
    /// end of the file (in ASCII, on its last line).
    pub fn truncated(&self) -> MshError {
        let end = self.bytes.len() - usize::from(!self.binary_file && self.bytes.ends_with(b"\n"));
        self.error(end, MshErrorKind::Truncated { section: self.section.clone() })
    }

    // ----- lines and sections -------------------------------------------------

    /// Skips spaces and line breaks (and a UTF-8 byte order mark at the start).
    pub fn skip_whitespace(&mut self) {
        if self.pos == 0 && self.bytes.starts_with(b"\xEF\xBB\xBF") {
            self.pos = 3;
        }
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// The rest of the current line without its line break (which is consumed),
    /// with its start offset; `None` at the end of the file.
    pub fn line(&mut self) -> Option<(usize, &'a [u8])> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let start = self.pos;
        let end = self.line_end(start);
        self.pos = (end + 1).min(self.bytes.len());
        Some((start, trim(&self.bytes[start..end])))
    }

    /// The next `$Section` header, or `None` at the end of the file.
    pub fn next_section(&mut self) -> Result<Option<(usize, String)>, MshError> {
        self.skip_whitespace();
        let Some((at, line)) = self.line() else {
            return Ok(None);
        };
        match line.strip_prefix(b"$") {
            Some(name) if !name.is_empty() => {
                Ok(Some((at, String::from_utf8_lossy(name).trim().to_string())))
            }
            _ => Err(self.parse_error(at, "a section header such as $Nodes".into(), quote(line))),
        }
    }

    /// Reads the `$End<Section>` line closing the current section.
    pub fn expect_section_end(&mut self) -> Result<(), MshError> {
        self.skip_whitespace();
        let Some((at, line)) = self.line() else {
            return Err(self.truncated());
        };
        if line.strip_prefix(b"$End") == Some(self.section.as_bytes()) {
            Ok(())
        } else {
            let kind = MshErrorKind::MissingEnd { section: self.section.clone(), found: quote(line) };
            Err(self.error(at, kind))
        }
    }

    /// Skips the rest of the current section, through its `$End<Section>` line.
    pub fn skip_section(&mut self) -> Result<(), MshError> {
        let marker = format!("$End{}", self.section);
        let marker = marker.as_bytes();
        let mut from = self.pos;
        while let Some(i) = find(self.bytes, marker, from) {
            let starts_line = i == 0 || self.bytes[i - 1] == b'\n';
            let after = self.bytes.get(i + marker.len());
            if starts_line && after.is_none_or(|b| b.is_ascii_whitespace()) {
                self.pos = i;
                self.line();
                return Ok(());
            }
            from = i + 1;
        }
        Err(self.truncated())
    }

    // ----- records --------------------------------------------------------------

    /// Ends a record: in ASCII the rest of the line must be blank; in binary
    /// there is nothing to do.
    pub fn end_record(&mut self, what: impl What) -> Result<(), MshError> {
        if self.encoding != Encoding::Ascii {
            return Ok(());
        }
        match self.token() {
            None => {
                self.pos = (self.pos + 1).min(self.bytes.len());
                Ok(())
            }
            Some((at, token)) => {
                Err(self.parse_error(at, format!("the end of the line after {}", what()), quote(token)))
            }
        }
    }

    /// The rest of the current line, trimmed (ASCII only), with its start offset.
    pub fn rest_of_line(&mut self) -> (usize, &'a [u8]) {
        self.line().unwrap_or((self.bytes.len(), b""))
    }

    // ----- blocks of binary records ----------------------------------------------

    /// `sizeof(size_t)` of a binary section; `None` in ASCII.
    pub fn size_bytes(&self) -> Option<usize> {
        match self.encoding {
            Encoding::Binary { size_bytes, .. } => Some(size_bytes),
            Encoding::Ascii => None,
        }
    }

    /// In a binary section, the next `count` records of `record` bytes each,
    /// with their offset, if all are present (the cursor moves past them).
    /// `None`, with the cursor where it was, in ASCII or if the file ends
    /// before: the caller then reads them value by value, which reports where
    /// the data ends.
    pub fn binary_block(&mut self, count: u64, record: usize) -> Option<(usize, &'a [u8])> {
        self.size_bytes()?;
        let n = usize::try_from(count).ok()?.checked_mul(record)?;
        let at = self.pos;
        let block = self.bytes.get(at..at.checked_add(n)?)?;
        self.pos = at + n;
        Some((at, block))
    }

    /// An unsigned integer of 4 or 8 bytes of a binary block, in the file's
    /// byte order (as [`Cursor::int`] and [`Cursor::size`] read them).
    pub fn word(&self, bytes: &[u8]) -> u64 {
        let big_endian = matches!(self.encoding, Encoding::Binary { big_endian: true, .. });
        if let Ok(word) = <[u8; 8]>::try_from(bytes) {
            return if big_endian { u64::from_be_bytes(word) } else { u64::from_le_bytes(word) };
        }
        if let Ok(word) = <[u8; 4]>::try_from(bytes) {
            return u64::from(if big_endian { u32::from_be_bytes(word) } else { u32::from_le_bytes(word) });
        }
        let fold = |v: u64, &b: &u8| (v << 8) | u64::from(b);
        if big_endian {
            bytes.iter().fold(0, fold)
        } else {
            bytes.iter().rev().fold(0, fold)
        }
    }

    // ----- blocks of ASCII records ---------------------------------------------

    /// The next `count` lines of an ASCII section, each parsed by `parse_line`
    /// (which appends what the line holds to its vector, or fails), with the
    /// offset of each line; the cursor moves past them. `None`, with the cursor
    /// where it was, if the block is short (fewer than [`BLOCK_LINES`] lines:
    /// not worth it), binary, or if any line fails: the caller then reads the
    /// block value by value, which finds the first problem and reports it as
    /// usual. Long blocks are parsed by several threads; the result does not
    /// depend on how many.
    pub fn ascii_block<V: Send>(
        &mut self,
        count: u64,
        parse_line: impl Fn(&[u8], &mut Vec<V>) -> Option<()> + Sync,
    ) -> Option<(Vec<V>, Vec<usize>)> {
        if self.encoding != Encoding::Ascii || count < BLOCK_LINES as u64 {
            return None;
        }
        let count = usize::try_from(count).ok()?;
        let rest = self.bytes.get(self.pos..)?;
        // Every line takes at least 2 bytes: no room, no block.
        if count.checked_mul(2)? > rest.len() + 1 {
            return None;
        }
        let mut starts = Vec::with_capacity(count + 1);
        starts.push(self.pos);
        for end in memchr::memchr_iter(b'\n', rest).take(count) {
            starts.push(self.pos + end + 1);
        }
        if starts.len() < count {
            return None;
        }
        if starts.len() == count {
            // The last line ends the file without a line break.
            starts.push(self.bytes.len() + 1);
        }
        let bytes = self.bytes;
        let parse_lines = |first: usize, lines: &[usize]| -> Option<Vec<V>> {
            let mut values = Vec::with_capacity(lines.len());
            let mut start = first;
            for &next in lines {
                parse_line(bytes.get(start..next - 1)?, &mut values)?;
                start = next;
            }
            Some(values)
        };
        use rayon::prelude::*;
        let ends = starts.get(1..)?;
        let chunks: Vec<Vec<V>> = ends
            .par_chunks(BLOCK_LINES)
            .enumerate()
            .map(|(k, lines)| parse_lines(starts[k * BLOCK_LINES], lines))
            .collect::<Option<_>>()?;
        let mut values = Vec::with_capacity(chunks.iter().map(Vec::len).sum());
        chunks.into_iter().for_each(|chunk| values.extend(chunk));
        self.pos = ends.last().map_or(self.pos, |&end| end.min(self.bytes.len()));
        starts.truncate(count);
        Some((values, starts))
    }

    // ----- values ---------------------------------------------------------------

    /// A C `int`.
    pub fn int(&mut self, what: impl What) -> Result<i32, MshError> {
        match self.encoding {
            Encoding::Ascii => self.ascii_value(what),
            Encoding::Binary { .. } => Ok(self.uint(4)? as u32 as i32),
        }
    }

    /// A `size_t` (MSH 4.1 counts and tags).
    pub fn size(&mut self, what: impl What) -> Result<u64, MshError> {
        match self.encoding {
            Encoding::Ascii => self.ascii_value(what),
            Encoding::Binary { size_bytes, .. } => self.uint(size_bytes),
        }
    }

    /// A non-negative tag stored as an `int` (MSH 2.2 tags, `$NodeData` node tags).
    pub fn int_tag(&mut self, what: impl What) -> Result<u64, MshError> {
        match self.encoding {
            Encoding::Ascii => self.ascii_value(what),
            Encoding::Binary { .. } => {
                let at = self.pos;
                let value = self.int(&what)?;
                u64::try_from(value).map_err(|_| self.parse_error(at, what(), value.to_string()))
            }
        }
    }

    /// Fills `out` with doubles. In ASCII, a missing or malformed number reports
    /// the whole rest of the line: `expected 3 coordinates for node 4, found "1 abc"`.
    pub fn doubles(&mut self, out: &mut [f64], what: impl What) -> Result<(), MshError> {
        if self.encoding != Encoding::Ascii {
            for x in out.iter_mut() {
                *x = f64::from_bits(self.uint(8)?);
            }
            return Ok(());
        }
        let start = self.pos;
        for x in out.iter_mut() {
            match self.token().map(|(_, token)| parse_ascii::<f64>(token)) {
                Some(Some(value)) => *x = value,
                None if self.pos >= self.bytes.len() => return Err(self.truncated()),
                _ => return Err(self.rest_of_line_error(start, what)),
            }
        }
        Ok(())
    }

    /// The next whitespace-separated token of the current line (ASCII).
    fn token(&mut self) -> Option<(usize, &'a [u8])> {
        let is_blank = |b: u8| b.is_ascii_whitespace() && b != b'\n';
        while self.pos < self.bytes.len() && is_blank(self.bytes[self.pos]) {
            self.pos += 1;
        }
        if self.pos >= self.bytes.len() || self.bytes[self.pos] == b'\n' {
            return None;
        }
        let start = self.pos;
        while self.pos < self.bytes.len() && !self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        Some((start, &self.bytes[start..self.pos]))
    }

    fn ascii_value<T: Number>(&mut self, what: impl What) -> Result<T, MshError> {
        match self.token() {
            Some((at, token)) => parse_ascii(token).ok_or_else(|| self.parse_error(at, what(), quote(token))),
            None if self.pos >= self.bytes.len() => Err(self.truncated()),
            None => Err(self.parse_error(self.pos, what(), "end of line".into())),
        }
    }

    fn rest_of_line_error(&self, start: usize, what: impl What) -> MshError {
        let rest = trim(&self.bytes[start..self.line_end(start)]);
        let found = if rest.is_empty() { "end of line".into() } else { quote(rest) };
        self.parse_error(start, what(), found)
    }

    /// An unsigned binary integer of `n` ≤ 8 bytes in the file's byte order.
    fn uint(&mut self, n: usize) -> Result<u64, MshError> {
        let bytes = self.take(n)?;
        Ok(self.word(bytes))
    }

    /// The next `n` raw bytes.
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], MshError> {
        if self.bytes.len() - self.pos < n {
            self.pos = self.bytes.len();
            return Err(self.truncated());
        }
        self.pos += n;
        Ok(&self.bytes[self.pos - n..self.pos])
    }

    /// Offset of the line break ending the line that contains `pos` (or the end).
    fn line_end(&self, pos: usize) -> usize {
        self.bytes[pos..].iter().position(|&b| b == b'\n').map_or(self.bytes.len(), |i| pos + i)
    }
}

/// A number type of ASCII MSH records.
pub(crate) trait Number: FromStr {
    /// `v` as `Self`, when it fits (`None` for floating-point types, which take
    /// the general path).
    fn from_digits(v: u64) -> Option<Self>;
}

impl Number for i32 {
    fn from_digits(v: u64) -> Option<i32> {
        i32::try_from(v).ok()
    }
}

impl Number for u64 {
    fn from_digits(v: u64) -> Option<u64> {
        Some(v)
    }
}

impl Number for f64 {
    fn from_digits(_: u64) -> Option<f64> {
        None
    }
}

/// The number `token` spells (as `str::parse` reads it). Plain decimal
/// integers of up to 18 digits, the usual tags and counts, are read directly.
fn parse_ascii<T: Number>(token: &[u8]) -> Option<T> {
    if !token.is_empty() && token.len() <= 18 && token.iter().all(u8::is_ascii_digit) {
        let v = token.iter().fold(0u64, |v, &d| v * 10 + u64::from(d - b'0'));
        if let Some(value) = T::from_digits(v) {
            return Some(value);
        }
    }
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// The tokens of an ASCII line.
pub(crate) fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(u8::is_ascii_whitespace).filter(|t| !t.is_empty())
}

/// The number `token` spells, as the cursor reads it (public to the section readers).
pub(crate) fn number<T: Number>(token: &[u8]) -> Option<T> {
    parse_ascii(token)
}

/// `bytes` without leading and trailing whitespace.
pub(crate) fn trim(bytes: &[u8]) -> &[u8] {
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace()).unwrap_or(bytes.len());
    let end = bytes.iter().rposition(|b| !b.is_ascii_whitespace()).map_or(start, |i| i + 1);
    &bytes[start..end]
}

/// Text from the file for an error message: quoted, escaped, at most 60 characters.
pub(crate) fn quote(bytes: &[u8]) -> String {
    const MAX: usize = 60;
    let text = String::from_utf8_lossy(bytes);
    if text.chars().count() <= MAX {
        format!("{text:?}")
    } else {
        let head: String = text.chars().take(MAX).collect();
        format!("{head:?}...")
    }
}

/// Position of `needle` in `haystack` at or after `from`.
fn find(haystack: &[u8], needle: &[u8], from: usize) -> Option<usize> {
    if needle.is_empty() || from >= haystack.len() {
        return None;
    }
    haystack[from..].windows(needle.len()).position(|w| w == needle).map(|i| from + i)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_values_stay_on_their_line() {
        let mut c = Cursor::new(b"1 2.5\n3\n");
        assert_eq!(c.int(|| "a".into()).unwrap(), 1);
        let mut x = [0.0];
        c.doubles(&mut x, || "b".into()).unwrap();
        assert_eq!(x[0], 2.5);
        let e = c.int(|| "the count".into()).unwrap_err();
        assert_eq!(e.to_string(), "line 1: expected the count, found end of line");
        c.end_record(|| "x".into()).unwrap();
        assert_eq!(c.size(|| "c".into()).unwrap(), 3);
    }

    #[test]
    fn extra_values_are_reported() {
        let mut c = Cursor::new(b"1 2\n");
        c.int(|| "a".into()).unwrap();
        let e = c.end_record(|| "node 1".into()).unwrap_err();
        assert_eq!(e.to_string(), "line 1: expected the end of the line after node 1, found \"2\"");
    }

    #[test]
    fn bad_doubles_report_the_rest_of_the_line() {
        let mut c = Cursor::new(b"\n4 1.0 abc\n");
        c.line();
        c.int(|| "tag".into()).unwrap();
        let mut xyz = [0.0; 3];
        let e = c.doubles(&mut xyz, || "3 coordinates for node 4".into()).unwrap_err();
        assert_eq!(e.to_string(), "line 2: expected 3 coordinates for node 4, found \"1.0 abc\"");
    }

    #[test]
    fn binary_values_follow_the_byte_order() {
        let mut bytes = vec![];
        bytes.extend(7i32.to_le_bytes());
        bytes.extend(9u64.to_le_bytes());
        bytes.extend(1.5f64.to_le_bytes());
        bytes.extend((-2i32).to_be_bytes());
        let mut c = Cursor::new(&bytes);
        c.set_binary(8, false);
        assert_eq!(c.int(|| "i".into()).unwrap(), 7);
        assert_eq!(c.size(|| "s".into()).unwrap(), 9);
        let mut x = [0.0];
        c.doubles(&mut x, || "d".into()).unwrap();
        assert_eq!(x[0], 1.5);
        c.set_binary(8, true);
        assert_eq!(c.int(|| "i".into()).unwrap(), -2);
        let e = c.int(|| "i".into()).unwrap_err();
        assert!(matches!(e.kind(), MshErrorKind::Truncated { .. }));
        assert_eq!(e.location(), Some(Location::Offset(bytes.len())));
    }

    #[test]
    fn skipping_finds_the_end_marker_at_a_line_start() {
        let mut c = Cursor::new(b"x $EndFoo\n$EndFooBar\n$EndFoo\nnext\n");
        c.enter_section("Foo");
        c.skip_section().unwrap();
        assert_eq!(c.line().unwrap().1, b"next");
        let mut c = Cursor::new(b"data\n");
        c.enter_section("Foo");
        let e = c.skip_section().unwrap_err();
        assert!(e.to_string().contains("ends inside the $Foo section"));
    }

    #[test]
    fn capacity_is_bounded_by_the_remaining_bytes() {
        let c = Cursor::new(b"0123456789");
        assert_eq!(c.capacity(u64::MAX, 2), 5);
        assert_eq!(c.capacity(3, 2), 3);
    }

    #[test]
    fn quotes_are_short_and_escaped() {
        assert_eq!(quote(b"a\"b\x01"), "\"a\\\"b\\u{1}\"");
        assert!(quote(&[b'x'; 100]).ends_with("\"..."));
    }
}
