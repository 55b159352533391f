//! A plain little-endian byte encoding of numbers and arrays, for handing the
//! parts of an assembly between processes ([`crate::parts`]): a length before
//! every array, nothing else.

/// Appends numbers and arrays to a byte buffer.
#[derive(Default)]
pub(crate) struct Writer(pub(crate) Vec<u8>);

impl Writer {
    pub(crate) fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }

    pub(crate) fn usize(&mut self, v: usize) {
        self.u64(v as u64);
    }

    pub(crate) fn f64(&mut self, v: f64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }

    pub(crate) fn usizes(&mut self, v: &[usize]) {
        self.usize(v.len());
        self.0.reserve(8 * v.len());
        v.iter().for_each(|&x| self.0.extend_from_slice(&(x as u64).to_le_bytes()));
    }

    pub(crate) fn u32s(&mut self, v: &[u32]) {
        self.usize(v.len());
        self.0.reserve(4 * v.len());
        v.iter().for_each(|&x| self.0.extend_from_slice(&x.to_le_bytes()));
    }

    pub(crate) fn f64s(&mut self, v: &[f64]) {
        self.usize(v.len());
        self.0.reserve(8 * v.len());
        v.iter().for_each(|&x| self.0.extend_from_slice(&x.to_le_bytes()));
    }
}

/// Reads what a [`Writer`] wrote, in the same order; every read checks the
/// bytes left, so a short or corrupt buffer is an error, never a panic or an
/// allocation beyond the buffer's size.
pub(crate) struct Reader<'a>(pub(crate) &'a [u8]);

/// Bytes that are not a part (`seam::parts`): short, or not what was written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("a part's bytes end early or are corrupt")]
pub struct WireError;

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], WireError> {
        let (head, rest) = self.0.split_first_chunk::<N>().ok_or(WireError)?;
        self.0 = rest;
        Ok(*head)
    }

    pub(crate) fn u64(&mut self) -> Result<u64, WireError> {
        self.take::<8>().map(u64::from_le_bytes)
    }

    pub(crate) fn usize(&mut self) -> Result<usize, WireError> {
        usize::try_from(self.u64()?).map_err(|_| WireError)
    }

    pub(crate) fn f64(&mut self) -> Result<f64, WireError> {
        self.take::<8>().map(f64::from_le_bytes)
    }

    /// The bytes of an array of `size`-byte items (its length first), if
    /// they fit in what is left.
    fn array(&mut self, size: usize) -> Result<&[u8], WireError> {
        let n = self.usize()?;
        let bytes = n.checked_mul(size).filter(|&b| b <= self.0.len()).ok_or(WireError)?;
        let (head, rest) = self.0.split_at(bytes);
        self.0 = rest;
        Ok(head)
    }

    pub(crate) fn usizes(&mut self) -> Result<Vec<usize>, WireError> {
        self.array(8)?
            .chunks_exact(8)
            .map(|c| {
                usize::try_from(u64::from_le_bytes(c.try_into().expect("8 bytes"))).map_err(|_| WireError)
            })
            .collect()
    }

    pub(crate) fn u32s(&mut self) -> Result<Vec<u32>, WireError> {
        Ok(self
            .array(4)?
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().expect("4 bytes")))
            .collect())
    }

    pub(crate) fn f64s(&mut self) -> Result<Vec<f64>, WireError> {
        Ok(self
            .array(8)?
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect())
    }

    /// Whether everything was read.
    pub(crate) fn done(&self) -> Result<(), WireError> {
        match self.0.is_empty() {
            true => Ok(()),
            false => Err(WireError),
        }
    }
}
