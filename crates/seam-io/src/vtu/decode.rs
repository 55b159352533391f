//! Data arrays from their text or bytes: ASCII numbers, base64 text (inline or
//! appended), raw appended bytes; size headers; decompression capped at the
//! declared sizes.
//!
//! Nothing here allocates from a size read from the file before the bytes that
//! size needs are known to be present: an array of `n` bytes needs `n` raw bytes,
//! or `4n/3` base64 characters, still unread; compressed blocks need their
//! compressed sizes present, and decompress into buffers that grow only as data
//! comes out, up to the declared block size and never past it. Errors are one-line
//! messages that the caller prefixes with the array they concern.

use std::borrow::Cow;
use std::io::Read;

/// The numeric types of VTK XML data arrays (`type="Float64"`...).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Scalar {
    Int8,
    UInt8,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Int64,
    UInt64,
    Float32,
    Float64,
}

impl Scalar {
    /// The type called `name` in a `type` attribute.
    pub(super) fn from_name(name: &str) -> Option<Scalar> {
        Some(match name {
            "Int8" => Scalar::Int8,
            "UInt8" => Scalar::UInt8,
            "Int16" => Scalar::Int16,
            "UInt16" => Scalar::UInt16,
            "Int32" => Scalar::Int32,
            "UInt32" => Scalar::UInt32,
            "Int64" => Scalar::Int64,
            "UInt64" => Scalar::UInt64,
            "Float32" => Scalar::Float32,
            "Float64" => Scalar::Float64,
            _ => return None,
        })
    }

    /// Bytes per value.
    pub(super) fn size(self) -> usize {
        match self {
            Scalar::Int8 | Scalar::UInt8 => 1,
            Scalar::Int16 | Scalar::UInt16 => 2,
            Scalar::Int32 | Scalar::UInt32 | Scalar::Float32 => 4,
            Scalar::Int64 | Scalar::UInt64 | Scalar::Float64 => 8,
        }
    }

    /// The range of an integer type; `None` for floating-point types.
    fn int_range(self) -> Option<(i128, i128)> {
        Some(match self {
            Scalar::Int8 => (i8::MIN.into(), i8::MAX.into()),
            Scalar::UInt8 => (0, u8::MAX.into()),
            Scalar::Int16 => (i16::MIN.into(), i16::MAX.into()),
            Scalar::UInt16 => (0, u16::MAX.into()),
            Scalar::Int32 => (i32::MIN.into(), i32::MAX.into()),
            Scalar::UInt32 => (0, u32::MAX.into()),
            Scalar::Int64 => (i64::MIN.into(), i64::MAX.into()),
            Scalar::UInt64 => (0, u64::MAX.into()),
            Scalar::Float32 | Scalar::Float64 => return None,
        })
    }

    /// True for the integer types.
    pub(super) fn is_integer(self) -> bool {
        self.int_range().is_some()
    }
}

/// A value as stored: an integer of any VTK integer type, or a float.
#[derive(Clone, Copy, Debug)]
pub(super) enum Raw {
    Int(i128),
    Float(f64),
}

/// What a data array is decoded into: `f64` (fields, points) or `u64` (cell
/// connectivity, offsets and types).
pub(super) trait Number: Sized + Send {
    /// `raw` as `Self`, if it is one.
    fn from_raw(raw: Raw) -> Option<Self>;

    /// The values of `bytes` as [`from_bytes`] reads them, for the types VTU
    /// files use most; `None` for other types, or if a value is not a `Self`.
    fn from_words(bytes: &[u8], ty: Scalar, big_endian: bool) -> Option<Vec<Self>>;
}

impl Number for f64 {
    fn from_words(bytes: &[u8], ty: Scalar, big_endian: bool) -> Option<Vec<f64>> {
        match ty {
            Scalar::Float64 => convert(bytes, big_endian, |w| Some(f64::from_le_bytes(w))),
            Scalar::Float32 => convert(bytes, big_endian, |w| Some(f32::from_le_bytes(w).into())),
            _ => None,
        }
    }

    fn from_raw(raw: Raw) -> Option<f64> {
        Some(match raw {
            // Exact up to 2⁵³, rounded beyond, as any reader of Int64 fields into f64.
            Raw::Int(v) => v as f64,
            Raw::Float(v) => v,
        })
    }
}

impl Number for u64 {
    fn from_words(bytes: &[u8], ty: Scalar, big_endian: bool) -> Option<Vec<u64>> {
        let b = big_endian;
        match ty {
            Scalar::Int64 => convert(bytes, b, |w| u64::try_from(i64::from_le_bytes(w)).ok()),
            Scalar::UInt64 => convert(bytes, b, |w| Some(u64::from_le_bytes(w))),
            Scalar::Int32 => convert(bytes, b, |w| u64::try_from(i32::from_le_bytes(w)).ok()),
            Scalar::UInt32 => convert(bytes, b, |w| Some(u32::from_le_bytes(w).into())),
            Scalar::UInt8 => Some(bytes.iter().map(|&v| u64::from(v)).collect()),
            _ => None,
        }
    }

    fn from_raw(raw: Raw) -> Option<u64> {
        match raw {
            Raw::Int(v) => u64::try_from(v).ok(),
            Raw::Float(_) => None,
        }
    }
}

fn describe(raw: Raw) -> String {
    match raw {
        Raw::Int(v) => v.to_string(),
        Raw::Float(v) => v.to_string(),
    }
}

/// The compressors of VTK XML files (`compressor="vtkZLibDataCompressor"`...).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Compressor {
    /// zlib streams (RFC 1950), one per block.
    Zlib,
    /// LZ4 blocks (the LZ4 block format, without frame).
    Lz4,
    /// `.xz` streams (`lzma_easy_buffer_encode`), one per block.
    Lzma,
}

impl Compressor {
    /// The compressor called `name` in the `compressor` attribute.
    pub(super) fn from_name(name: &str) -> Option<Compressor> {
        Some(match name {
            "vtkZLibDataCompressor" => Compressor::Zlib,
            "vtkLZ4DataCompressor" => Compressor::Lz4,
            "vtkLZMADataCompressor" => Compressor::Lzma,
            _ => return None,
        })
    }
}

/// How the binary data of a file is laid out (attributes of `<VTKFile>`).
#[derive(Clone, Copy, Debug)]
pub(super) struct Layout {
    /// Bytes of a header integer: 4 (`header_type="UInt32"`, the default) or 8.
    pub(super) header: usize,
    /// `byte_order="BigEndian"`: header integers and values are big-endian.
    pub(super) big_endian: bool,
    /// The compressor, if the binary arrays are compressed.
    pub(super) compressor: Option<Compressor>,
}

/// The memory limit of the LZMA decoder: enough for the dictionary of any
/// `xz`/liblzma preset (64 MiB at preset 9; VTK uses preset 5, 8 MiB). A
/// stream that asks for more is an error, not an allocation.
const LZMA_MEMLIMIT: u64 = 128 << 20;

/// Reads the bytes of binary arrays: raw appended bytes, or base64 text (inline
/// or appended), which may be several independently padded chunks (VTK and
/// meshio encode a compression header on its own) and may hold whitespace.
pub(super) enum Cursor<'a> {
    /// Raw bytes, from the current position on.
    Raw(&'a [u8]),
    /// Base64 text from the current position on; `quad[next..end]` are bytes
    /// decoded but not yet taken.
    Base64 { text: &'a [u8], quad: [u8; 3], next: usize, end: usize },
}

impl<'a> Cursor<'a> {
    /// A cursor on base64 text.
    pub(super) fn base64(text: &'a [u8]) -> Cursor<'a> {
        Cursor::Base64 { text, quad: [0; 3], next: 0, end: 0 }
    }

    /// An upper bound of the bytes left: exact for raw bytes, 3 per 4 characters
    /// left (whitespace included) for base64.
    pub(super) fn max_left(&self) -> usize {
        match self {
            Cursor::Raw(bytes) => bytes.len(),
            Cursor::Base64 { text, next, end, .. } => end.saturating_sub(*next) + text.len() / 4 * 3,
        }
    }

    /// The next `n` bytes. Fails, without allocating, if fewer can be left.
    pub(super) fn take(&mut self, n: usize) -> Result<Cow<'a, [u8]>, String> {
        let left = self.max_left();
        if n > left {
            return Err(format!("needs {n} more bytes but at most {left} are left in the data"));
        }
        match self {
            Cursor::Raw(bytes) => {
                let (taken, rest) = bytes.split_at_checked(n).ok_or("the data ends early")?;
                *bytes = rest;
                Ok(Cow::Borrowed(taken))
            }
            Cursor::Base64 { text, quad, next, end } => {
                // `n` is at most 3/4 of the characters present: not a claimed size.
                let mut out = Vec::with_capacity(n);
                loop {
                    let k = (n - out.len()).min(end.saturating_sub(*next));
                    out.extend_from_slice(quad.get(*next..*next + k).unwrap_or_default());
                    *next += k;
                    if out.len() == n {
                        return Ok(Cow::Owned(out));
                    }
                    // The groups of 4 plain characters (no whitespace, no
                    // padding) that whole bytes still needed take, at once.
                    let groups = (n - out.len()) / 3;
                    if groups > 0 {
                        let run = decode_groups(text, groups, &mut out);
                        *text = text.get(run..).unwrap_or_default();
                        if out.len() == n {
                            return Ok(Cow::Owned(out));
                        }
                    }
                    (*quad, *end) = next_quad(text)?.ok_or("the base64 data ends early")?;
                    *next = 0;
                }
            }
        }
    }
}

/// The value of each base64 character; [`NOT_BASE64`] for any other byte.
const SEXTETS: [u8; 256] = {
    let mut table = [NOT_BASE64; 256];
    let mut i = 0;
    while i < 64 {
        let c = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/"[i];
        table[c as usize] = i as u8;
        i += 1;
    }
    table
};
const NOT_BASE64: u8 = 0xFF;

/// Base64 text decoded in one go by a thread (in groups of 4 characters).
const PARALLEL_GROUPS: usize = 1 << 15;

/// Decodes the longest run of at most `max_groups` groups of 4 base64
/// characters at the start of `text` that holds neither whitespace nor padding
/// nor any other byte (what [`next_quad`] decodes one group at a time, with the
/// same result), appending the bytes to `out`; returns the characters decoded.
/// Long runs are decoded by several threads, each into its own part of `out`.
fn decode_groups(text: &[u8], max_groups: usize, out: &mut Vec<u8>) -> usize {
    let head = text.get(..max_groups.saturating_mul(4).min(text.len())).unwrap_or_default();
    let plain = head.iter().position(|&c| SEXTETS[usize::from(c)] == NOT_BASE64).unwrap_or(head.len());
    let run = head.get(..plain / 4 * 4).unwrap_or_default();
    let start = out.len();
    out.resize(start + run.len() / 4 * 3, 0);
    let dest = out.get_mut(start..).unwrap_or_default();
    let decode = |chars: &[u8], bytes: &mut [u8]| {
        for (c, b) in chars.chunks_exact(4).zip(bytes.chunks_exact_mut(3)) {
            let s = |i: usize| u32::from(SEXTETS[usize::from(c[i])]);
            let bits = s(0) << 18 | s(1) << 12 | s(2) << 6 | s(3);
            let [_, x, y, z] = bits.to_be_bytes();
            b.copy_from_slice(&[x, y, z]);
        }
    };
    if run.len() >= 8 * PARALLEL_GROUPS {
        use rayon::prelude::*;
        run.par_chunks(4 * PARALLEL_GROUPS)
            .zip(dest.par_chunks_mut(3 * PARALLEL_GROUPS))
            .for_each(|(chars, bytes)| decode(chars, bytes));
    } else {
        decode(run, dest);
    }
    run.len()
}

/// The value of a base64 character.
fn sextet(c: u8) -> Result<u32, String> {
    Ok(u32::from(match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => return Err(format!("invalid base64 character {:?}", char::from(c))),
    }))
}

/// Decodes the next 4 base64 characters of `text` (skipping whitespace) into
/// 3 bytes, or 2 or 1 if they end with padding (`(bytes, count)`); `None` at the
/// end of the text.
fn next_quad(text: &mut &[u8]) -> Result<Option<([u8; 3], usize)>, String> {
    let mut chars = [0u8; 4];
    let mut k = 0;
    while k < 4 {
        let Some((&c, rest)) = text.split_first() else {
            return if k == 0 { Ok(None) } else { Err("the base64 data ends inside a group of 4".into()) };
        };
        *text = rest;
        if !c.is_ascii_whitespace() {
            if let Some(slot) = chars.get_mut(k) {
                *slot = c;
            }
            k += 1;
        }
    }
    let [a, b, c, d] = chars;
    let (a, b) = (sextet(a)?, sextet(b)?);
    let (bits, count) = match (c, d) {
        (b'=', b'=') => (a << 18 | b << 12, 1),
        (c, b'=') => (a << 18 | b << 12 | sextet(c)? << 6, 2),
        (c, d) => (a << 18 | b << 12 | sextet(c)? << 6 | sextet(d)?, 3),
    };
    let [_, x, y, z] = bits.to_be_bytes();
    Ok(Some(([x, y, z], count)))
}

/// An unsigned header integer (4 or 8 bytes).
fn uint(bytes: &[u8], big_endian: bool) -> Result<u64, String> {
    let value = match (<[u8; 4]>::try_from(bytes), <[u8; 8]>::try_from(bytes)) {
        (Ok(b), _) => u64::from(if big_endian { u32::from_be_bytes(b) } else { u32::from_le_bytes(b) }),
        (_, Ok(b)) => {
            if big_endian {
                u64::from_be_bytes(b)
            } else {
                u64::from_le_bytes(b)
            }
        }
        _ => return Err(format!("a header integer of {} bytes", bytes.len())),
    };
    Ok(value)
}

/// The bytes of a binary data array, whose values take `expected` bytes, from
/// `cursor`: uncompressed, a header integer (its byte count, which must be
/// `expected`) then the bytes; compressed, the header `[nb][nu][np][nc_1]…[nc_nb]`
/// then `nb` compressed blocks (see [`read_compressed`]).
pub(super) fn read_binary<'a>(
    cursor: &mut Cursor<'a>,
    layout: &Layout,
    expected: usize,
) -> Result<Cow<'a, [u8]>, String> {
    let h = layout.header;
    let Some(compressor) = layout.compressor else {
        let size = uint(&cursor.take(h)?, layout.big_endian)?;
        if size != expected as u64 {
            return Err(format!("the size header says {size} bytes, expected {expected}"));
        }
        return cursor.take(expected);
    };
    read_compressed(cursor, layout, compressor, expected).map(Cow::Owned)
}

/// A compressed array: `nb` blocks that decompress to `nu` bytes each but the
/// last, which decompresses to `np` bytes (`np = 0` means `nu`: VTK writes 0 when
/// the array size is a multiple of the block size); `nc_i` is the compressed size
/// of block `i`. The total must be `expected`.
fn read_compressed(
    cursor: &mut Cursor<'_>,
    layout: &Layout,
    compressor: Compressor,
    expected: usize,
) -> Result<Vec<u8>, String> {
    let (h, big) = (layout.header, layout.big_endian);
    let head = cursor.take(3 * h)?;
    let field = |i: usize| uint(head.get(i * h..(i + 1) * h).unwrap_or_default(), big);
    let (nb, nu, np) = (field(0)?, field(1)?, field(2)?);
    let room = cursor.max_left() / h;
    let nb = usize::try_from(nb).ok().filter(|&nb| nb <= room).ok_or_else(|| {
        format!("the compression header claims {nb} blocks, more than the data left can describe")
    })?;
    // nb × h bytes are present (checked just above).
    let sizes = cursor.take(nb * h)?;
    if np > nu {
        return Err(format!("the last block size {np} exceeds the block size {nu}"));
    }
    let last = if np == 0 { nu } else { np };
    let total = match nb {
        0 => Some(0),
        _ => (nb as u64 - 1).checked_mul(nu).and_then(|t| t.checked_add(last)),
    };
    if total != Some(expected as u64) {
        let total = total.map_or_else(|| "more than 2^64".to_string(), |t| t.to_string());
        return Err(format!(
            "the compression header declares {total} bytes ({nb} blocks of {nu}, the last of {np}), \
             expected {expected}"
        ));
    }
    let mut compressed = Vec::with_capacity(nb);
    let mut sum = 0u64;
    for chunk in sizes.chunks_exact(h) {
        let nc = uint(chunk, big)?;
        sum = sum.saturating_add(nc);
        compressed.push(nc);
    }
    let left = cursor.max_left();
    if sum > left as u64 {
        return Err(format!(
            "the compressed blocks take {sum} bytes but at most {left} are left in the data"
        ));
    }
    let mut out = Vec::new();
    for (i, &nc) in compressed.iter().enumerate() {
        // Each size is at most `left`, which is a usize.
        let block = cursor.take(usize::try_from(nc).unwrap_or(usize::MAX))?;
        let size = if i + 1 == nb { last } else { nu };
        // size ≤ total = expected, a usize.
        let size = usize::try_from(size).unwrap_or(usize::MAX);
        let start = out.len();
        decompress(compressor, &block, size, &mut out).map_err(|e| format!("block {i}: {e}"))?;
        let got = out.len() - start;
        if got != size {
            return Err(format!("block {i} decompresses to {got} bytes, expected {size}"));
        }
    }
    Ok(out)
}

/// Appends the decompressed `block` to `out`: at most `size` bytes (a block that
/// holds more is an error), growing `out` only as data comes out.
fn decompress(compressor: Compressor, block: &[u8], size: usize, out: &mut Vec<u8>) -> Result<(), String> {
    let cap = (size as u64).saturating_add(1);
    let result = match compressor {
        Compressor::Zlib => flate2::read::ZlibDecoder::new(block).take(cap).read_to_end(out),
        Compressor::Lzma => {
            let stream = xz2::stream::Stream::new_stream_decoder(LZMA_MEMLIMIT, 0)
                .map_err(|e| format!("LZMA decoder: {e}"))?;
            xz2::read::XzDecoder::new_stream(block, stream).take(cap).read_to_end(out)
        }
        Compressor::Lz4 => return decompress_lz4(block, size, out),
    };
    let name = if compressor == Compressor::Zlib { "zlib" } else { "LZMA" };
    let n = result.map_err(|e| format!("bad {name} data: {}", super::error::one_line(&e.to_string())))?;
    if n > size {
        return Err(format!("the data decompresses to more than the declared {size} bytes"));
    }
    Ok(())
}

/// LZ4 blocks carry no size: decompress into a buffer that starts at 4 times the
/// compressed size and doubles while too small, up to `size`. It never exceeds
/// twice what the block actually decompresses to (or `size`).
fn decompress_lz4(block: &[u8], size: usize, out: &mut Vec<u8>) -> Result<(), String> {
    let start = out.len();
    let mut room = size.min(block.len().saturating_mul(4).max(256));
    loop {
        out.resize(start + room, 0);
        match lz4_flex::block::decompress_into(block, out.get_mut(start..).unwrap_or_default()) {
            Ok(n) => {
                out.truncate(start + n);
                return Ok(());
            }
            Err(lz4_flex::block::DecompressError::OutputTooSmall { .. }) if room < size => {
                room = room.saturating_mul(2).min(size);
            }
            Err(lz4_flex::block::DecompressError::OutputTooSmall { .. }) => {
                return Err(format!("the data decompresses to more than the declared {size} bytes"));
            }
            Err(e) => return Err(format!("bad LZ4 data: {}", super::error::one_line(&e.to_string()))),
        }
    }
}

/// The values of `bytes` (`N`-byte words in the given byte order), as little-endian words.
fn words<const N: usize>(bytes: &[u8], big_endian: bool) -> impl Iterator<Item = [u8; N]> + '_ {
    bytes.chunks_exact(N).map(move |c| {
        let mut word = <[u8; N]>::try_from(c).unwrap_or([0; N]);
        if big_endian {
            word.reverse();
        }
        word
    })
}

/// `words` converted by `f`, or `None` if `f` fails on one.
fn convert<const N: usize, T>(
    bytes: &[u8],
    big_endian: bool,
    f: impl Fn([u8; N]) -> Option<T>,
) -> Option<Vec<T>> {
    words(bytes, big_endian).map(f).collect()
}

/// The values of `bytes` (values of type `ty` in the given byte order) as `T`.
pub(super) fn from_bytes<T: Number>(bytes: &[u8], ty: Scalar, big_endian: bool) -> Result<Vec<T>, String> {
    // The common types straight into `T`; anything that fails (a negative
    // index...) goes through the general path below for its message.
    if let Some(values) = T::from_words(bytes, ty, big_endian) {
        return Ok(values);
    }
    let b = big_endian;
    let raw: Box<dyn Iterator<Item = Raw> + '_> = match ty {
        Scalar::Int8 => Box::new(words(bytes, b).map(|w| Raw::Int(i8::from_le_bytes(w).into()))),
        Scalar::UInt8 => Box::new(words(bytes, b).map(|w| Raw::Int(u8::from_le_bytes(w).into()))),
        Scalar::Int16 => Box::new(words(bytes, b).map(|w| Raw::Int(i16::from_le_bytes(w).into()))),
        Scalar::UInt16 => Box::new(words(bytes, b).map(|w| Raw::Int(u16::from_le_bytes(w).into()))),
        Scalar::Int32 => Box::new(words(bytes, b).map(|w| Raw::Int(i32::from_le_bytes(w).into()))),
        Scalar::UInt32 => Box::new(words(bytes, b).map(|w| Raw::Int(u32::from_le_bytes(w).into()))),
        Scalar::Int64 => Box::new(words(bytes, b).map(|w| Raw::Int(i64::from_le_bytes(w).into()))),
        Scalar::UInt64 => Box::new(words(bytes, b).map(|w| Raw::Int(u64::from_le_bytes(w).into()))),
        Scalar::Float32 => Box::new(words(bytes, b).map(|w| Raw::Float(f32::from_le_bytes(w).into()))),
        Scalar::Float64 => Box::new(words(bytes, b).map(|w| Raw::Float(f64::from_le_bytes(w)))),
    };
    let mut values = Vec::with_capacity(bytes.len() / ty.size());
    for (i, raw) in raw.enumerate() {
        values.push(T::from_raw(raw).ok_or_else(|| format!("value {i} is {}, not an index", describe(raw)))?);
    }
    Ok(values)
}

/// ASCII data is parsed in pieces of about this many bytes, in parallel.
const ASCII_PIECE: usize = 1 << 18;

/// Why a value of an ASCII array is wrong.
enum Bad<'t> {
    /// The token is not a number of the array's type.
    NotANumber(&'t [u8]),
    /// The number is not a `T`.
    Not(Raw),
}

/// The `count` whitespace-separated numbers of type `ty` in `text`, as `T`.
/// Integer types take integers in their range; `Float32` values are parsed as
/// `f32` (as a binary file would hold them).
///
/// Long text is cut at whitespace into pieces (where depends on its length
/// only) that are parsed in parallel; the first error in text order is
/// reported, as if the values were read one by one.
pub(super) fn parse_ascii<T: Number>(text: &[u8], ty: Scalar, count: usize) -> Result<Vec<T>, String> {
    let mut cuts = vec![0];
    let n_pieces = text.len() / ASCII_PIECE + 1;
    for k in 1..n_pieces {
        let from = (k * ASCII_PIECE).max(cuts.last().copied().unwrap_or(0));
        let cut = text.get(from..).and_then(|t| t.iter().position(u8::is_ascii_whitespace)).map(|i| from + i);
        cuts.push(cut.unwrap_or(text.len()));
    }
    cuts.push(text.len());
    let piece = |k: usize| text.get(cuts[k]..cuts[k + 1]).unwrap_or_default();
    let parsed: Vec<Result<Vec<T>, (usize, Bad<'_>)>> = if n_pieces > 1 {
        use rayon::prelude::*;
        (0..n_pieces).into_par_iter().map(|k| parse_piece(piece(k), ty)).collect()
    } else {
        vec![parse_piece(text, ty)]
    };
    // A value takes at least 2 characters with its separator.
    let mut values = Vec::with_capacity(count.min(text.len() / 2 + 1));
    for result in parsed {
        let (ok, bad) = match result {
            Ok(ok) => (ok, None),
            Err((j, bad)) => (Vec::new(), Some((values.len() + j, bad))),
        };
        // The value after the last expected one comes first.
        if values.len() + ok.len() > count || bad.as_ref().is_some_and(|(i, _)| *i >= count) {
            return Err(format!("more than the {count} values expected"));
        }
        match bad {
            Some((i, Bad::NotANumber(token))) => {
                let shown = String::from_utf8_lossy(token.get(..24).unwrap_or(token)).into_owned();
                return Err(format!("value {i} {shown:?} is not a {ty:?} number"));
            }
            Some((i, Bad::Not(raw))) => return Err(format!("value {i} is {}, not an index", describe(raw))),
            None => values.extend(ok),
        }
    }
    if values.len() != count {
        return Err(format!("{} values, expected {count}", values.len()));
    }
    Ok(values)
}

/// The numbers of type `ty` in `text`, as `T`; the first bad one (its index
/// in `text`).
fn parse_piece<T: Number>(text: &[u8], ty: Scalar) -> Result<Vec<T>, (usize, Bad<'_>)> {
    let mut values = Vec::with_capacity(text.len() / 8);
    for token in text.split(u8::is_ascii_whitespace).filter(|t| !t.is_empty()) {
        let raw = match (ty.int_range(), ty) {
            (Some((min, max)), _) => integer(token).filter(|v| (min..=max).contains(v)).map(Raw::Int),
            (None, Scalar::Float32) => {
                let word = std::str::from_utf8(token).ok();
                word.and_then(|w| w.parse::<f32>().ok()).map(|v| Raw::Float(v.into()))
            }
            (None, _) => std::str::from_utf8(token).ok().and_then(|w| w.parse::<f64>().ok()).map(Raw::Float),
        };
        let raw = raw.ok_or((values.len(), Bad::NotANumber(token)))?;
        values.push(T::from_raw(raw).ok_or((values.len(), Bad::Not(raw)))?);
    }
    Ok(values)
}

/// The integer `token` spells, as `str::parse::<i128>` reads it (plain digits
/// read directly).
fn integer(token: &[u8]) -> Option<i128> {
    if token.len() <= 18 && token.iter().all(u8::is_ascii_digit) && !token.is_empty() {
        return Some(token.iter().fold(0i128, |v, &d| v * 10 + i128::from(d - b'0')));
    }
    std::str::from_utf8(token).ok()?.parse::<i128>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use base64::prelude::{Engine as _, BASE64_STANDARD};

    const LE64: Layout = Layout { header: 8, big_endian: false, compressor: None };

    fn words(values: &[u64], h: usize, big: bool) -> Vec<u8> {
        let mut out = Vec::new();
        for &v in values {
            match (h, big) {
                (4, false) => out.extend_from_slice(&(v as u32).to_le_bytes()),
                (4, true) => out.extend_from_slice(&(v as u32).to_be_bytes()),
                (_, false) => out.extend_from_slice(&v.to_le_bytes()),
                (_, true) => out.extend_from_slice(&v.to_be_bytes()),
            }
        }
        out
    }

    #[test]
    fn base64_chunks_padded_separately_decode_as_one() {
        let (a, b) = (b"header!".as_slice(), b"the data".as_slice());
        let text = format!("{}\n  {}", BASE64_STANDARD.encode(a), BASE64_STANDARD.encode(b));
        let mut cursor = Cursor::base64(text.as_bytes());
        assert_eq!(&*cursor.take(3).unwrap(), b"hea");
        assert_eq!(&*cursor.take(12).unwrap(), b"der!the data");
        assert!(cursor.take(1).unwrap_err().contains("at most 0"));
        let mut cursor = Cursor::base64(b"QUJD#EVG");
        assert_eq!(cursor.take(4).unwrap_err(), "invalid base64 character '#'");
        let mut cursor = Cursor::base64(b"QUJD RE   ");
        assert_eq!(cursor.take(4).unwrap_err(), "the base64 data ends inside a group of 4");
    }

    #[test]
    fn long_base64_runs_decode_as_group_by_group() {
        // Over 8 × PARALLEL_GROUPS groups: decoded by several threads.
        let data: Vec<u8> = (0..3 * 9 * PARALLEL_GROUPS + 7).map(|i| (i * 7 + i / 255) as u8).collect();
        let (a, b) = data.split_at(3 * 5 * PARALLEL_GROUPS + 1);
        let mut text = BASE64_STANDARD.encode(a).into_bytes();
        let middle = text.len() / 3 / 4 * 4;
        text.splice(middle..middle, *b"\n\t ");
        text.extend_from_slice(BASE64_STANDARD.encode(b).as_bytes());
        let mut cursor = Cursor::base64(&text);
        assert_eq!(&*cursor.take(5).unwrap(), &data[..5]);
        assert_eq!(&*cursor.take(data.len() - 6).unwrap(), &data[5..data.len() - 1]);
        assert_eq!(&*cursor.take(1).unwrap(), &data[data.len() - 1..]);
        assert!(cursor.take(1).is_err());
        let bad = text.len() * 2 / 3 / 4 * 4 + 1;
        text[bad] = b'#';
        let e = Cursor::base64(&text).take(data.len()).unwrap_err();
        assert_eq!(e, "invalid base64 character '#'");
    }

    #[test]
    fn uncompressed_arrays_need_their_declared_size_present() {
        let mut bytes = words(&[16], 8, false);
        bytes.extend_from_slice(&[1; 16]);
        let text = BASE64_STANDARD.encode(&bytes);
        let read = read_binary(&mut Cursor::base64(text.as_bytes()), &LE64, 16).unwrap();
        assert_eq!(&*read, &[1; 16]);
        let e = read_binary(&mut Cursor::base64(text.as_bytes()), &LE64, 24).unwrap_err();
        assert_eq!(e, "the size header says 16 bytes, expected 24");
        // A huge expected size with a matching header: an error before any allocation.
        let mut huge = words(&[1 << 50], 8, false);
        huge.extend_from_slice(&[0; 8]);
        let e = read_binary(&mut Cursor::Raw(&huge), &LE64, 1 << 50).unwrap_err();
        assert!(e.starts_with("needs 1125899906842624 more bytes but at most 8"), "{e}");
    }

    fn compressed(layout: &Layout, nb: u64, nu: u64, np: u64, blocks: &[Vec<u8>]) -> Vec<u8> {
        let mut header = vec![nb, nu, np];
        header.extend(blocks.iter().map(|b| b.len() as u64));
        let mut bytes = words(&header, layout.header, layout.big_endian);
        bytes.extend(blocks.iter().flatten());
        bytes
    }

    fn zlib(data: &[u8]) -> Vec<u8> {
        use std::io::Write;
        let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        e.write_all(data).unwrap();
        e.finish().unwrap()
    }

    #[test]
    fn compressed_blocks_decode_with_a_zero_last_size_meaning_full() {
        let layout = Layout { header: 4, big_endian: true, compressor: Some(Compressor::Zlib) };
        let data: Vec<u8> = (0..64).collect();
        let blocks: Vec<Vec<u8>> = data.chunks(32).map(zlib).collect();
        let bytes = compressed(&layout, 2, 32, 0, &blocks);
        assert_eq!(&*read_binary(&mut Cursor::Raw(&bytes), &layout, 64).unwrap(), &data[..]);
        let layout = Layout { compressor: Some(Compressor::Lz4), ..layout };
        let blocks: Vec<Vec<u8>> = data.chunks(32).map(lz4_flex::block::compress).collect();
        let bytes = compressed(&layout, 2, 32, 0, &blocks);
        assert_eq!(&*read_binary(&mut Cursor::Raw(&bytes), &layout, 64).unwrap(), &data[..]);
    }

    #[test]
    fn empty_compressed_arrays_hold_no_blocks() {
        // What VTK writes for an array without values (vtkio could not read it).
        let layout = Layout { header: 4, big_endian: false, compressor: Some(Compressor::Zlib) };
        let bytes = compressed(&layout, 0, 32768, 0, &[]);
        assert!(read_binary(&mut Cursor::Raw(&bytes), &layout, 0).unwrap().is_empty());
        let e = read_binary(&mut Cursor::Raw(&bytes), &layout, 8).unwrap_err();
        assert_eq!(
            e,
            "the compression header declares 0 bytes (0 blocks of 32768, the last of 0), expected 8"
        );
    }

    #[test]
    fn lying_compression_headers_are_errors() {
        let layout = Layout { header: 8, big_endian: false, compressor: Some(Compressor::Lz4) };
        let zeros = vec![0u8; 4096];
        let block = lz4_flex::block::compress(&zeros);
        let check = |nb: u64, nu: u64, np: u64, expected: usize, what: &str| {
            let bytes = compressed(&layout, nb, nu, np, std::slice::from_ref(&block));
            let e = read_binary(&mut Cursor::Raw(&bytes), &layout, expected).unwrap_err();
            assert!(e.contains(what), "{e}");
        };
        check(1, 4096, 0, 4096 * 2, "declares 4096 bytes");
        check(1 << 60, 4096, 0, 4096, "claims 1152921504606846976 blocks");
        check(
            1,
            7_696_581_394_432,
            0,
            7_696_581_394_432,
            "decompresses to 4096 bytes, expected 7696581394432",
        );
        check(1, 4096, 5000, 5000, "last block size 5000 exceeds the block size 4096");
        check(1, 2048, 0, 2048, "more than the declared 2048 bytes");
        let mut bytes = compressed(&layout, 1, 4096, 0, std::slice::from_ref(&block));
        bytes[24..32].copy_from_slice(&u64::MAX.to_le_bytes());
        let e = read_binary(&mut Cursor::Raw(&bytes), &layout, 4096).unwrap_err();
        assert!(e.starts_with("the compressed blocks take 18446744073709551615 bytes"), "{e}");
        let layout = Layout { compressor: Some(Compressor::Zlib), ..layout };
        let bytes = compressed(&layout, 1, 4096, 0, &[zlib(&zeros)]);
        let e = read_binary(&mut Cursor::Raw(&bytes), &layout, 4096 - 8 + 8).map(|b| b.len());
        assert_eq!(e, Ok(4096));
        let bytes = compressed(&layout, 1, 1000, 0, &[zlib(&zeros)]);
        let e = read_binary(&mut Cursor::Raw(&bytes), &layout, 1000).unwrap_err();
        assert_eq!(e, "block 0: the data decompresses to more than the declared 1000 bytes");
    }

    #[test]
    fn ascii_numbers_are_checked_against_type_and_count() {
        assert_eq!(parse_ascii::<f64>(b" 1 -2.5e1\n3 ", Scalar::Float64, 3).unwrap(), [1.0, -25.0, 3.0]);
        assert_eq!(parse_ascii::<f64>(b"0.1", Scalar::Float32, 1).unwrap(), [f64::from(0.1f32)]);
        assert_eq!(parse_ascii::<u64>(b"0 255", Scalar::UInt8, 2).unwrap(), [0, 255]);
        let e = parse_ascii::<u64>(b"0 256", Scalar::UInt8, 2).unwrap_err();
        assert_eq!(e, "value 1 \"256\" is not a UInt8 number");
        let e = parse_ascii::<u64>(b"-1", Scalar::Int32, 1).unwrap_err();
        assert_eq!(e, "value 0 is -1, not an index");
        assert_eq!(parse_ascii::<f64>(b"1 2", Scalar::Int8, 3).unwrap_err(), "2 values, expected 3");
        assert_eq!(
            parse_ascii::<f64>(b"1 2", Scalar::Int8, 1).unwrap_err(),
            "more than the 1 values expected"
        );
    }

    #[test]
    fn long_ascii_arrays_report_the_first_error_in_text_order() {
        let n = 3 * ASCII_PIECE / 7;
        let text: String = (0..n).map(|i| format!("{i} ")).collect();
        let values = parse_ascii::<u64>(text.as_bytes(), Scalar::Int64, n).unwrap();
        assert!(values.iter().enumerate().all(|(i, &v)| v == i as u64));
        let floats = parse_ascii::<f64>(text.as_bytes(), Scalar::Float64, n).unwrap();
        assert!(floats.iter().enumerate().all(|(i, &v)| v == i as f64));
        assert_eq!(
            parse_ascii::<u64>(text.as_bytes(), Scalar::Int64, n - 1).unwrap_err(),
            format!("more than the {} values expected", n - 1)
        );
        assert_eq!(
            parse_ascii::<u64>(text.as_bytes(), Scalar::Int64, n + 1).unwrap_err(),
            format!("{n} values, expected {}", n + 1)
        );
        // Errors in several pieces: the first one.
        let bad = text.replace(" 200000 ", " -5 ").replace(" 20000 ", " x ").replace(" 200 ", " -1 ");
        let e = parse_ascii::<u64>(bad.as_bytes(), Scalar::Int64, n).unwrap_err();
        assert_eq!(e, "value 200 is -1, not an index");
        let bad = text.replace(" 200000 ", " -5 ").replace(" 20000 ", " x ");
        let e = parse_ascii::<u64>(bad.as_bytes(), Scalar::Int64, n).unwrap_err();
        assert_eq!(e, "value 20000 \"x\" is not a Int64 number");
        // Past the expected count before a bad value: too many values.
        let e = parse_ascii::<u64>(bad.as_bytes(), Scalar::Int64, 100).unwrap_err();
        assert_eq!(e, "more than the 100 values expected");
        let e = parse_ascii::<u64>(bad.as_bytes(), Scalar::Int64, 20000).unwrap_err();
        assert_eq!(e, "more than the 20000 values expected");
        let e = parse_ascii::<u64>(bad.as_bytes(), Scalar::Int64, 20001).unwrap_err();
        assert_eq!(e, "value 20000 \"x\" is not a Int64 number");
        assert_eq!(parse_ascii::<u64>(b"+7 -0 007", Scalar::Int8, 3).unwrap(), [7, 0, 7]);
    }

    #[test]
    fn binary_values_of_every_type_and_byte_order() {
        let be: Vec<u8> = [-2i16, 300].iter().flat_map(|v| v.to_be_bytes()).collect();
        assert_eq!(from_bytes::<f64>(&be, Scalar::Int16, true).unwrap(), [-2.0, 300.0]);
        let le: Vec<u8> = [1.5f32, -0.0].iter().flat_map(|v| v.to_le_bytes()).collect();
        assert_eq!(from_bytes::<f64>(&le, Scalar::Float32, false).unwrap(), [1.5, -0.0]);
        assert_eq!(from_bytes::<u64>(&[7, 200], Scalar::UInt8, false).unwrap(), [7, 200]);
        let e = from_bytes::<u64>(&(-3i64).to_le_bytes(), Scalar::Int64, false).unwrap_err();
        assert_eq!(e, "value 0 is -3, not an index");
        let e = from_bytes::<u64>(&1f64.to_le_bytes(), Scalar::Float64, false).unwrap_err();
        assert_eq!(e, "value 0 is 1, not an index");
    }
}
