//! Matrix Market `coordinate real general` files, 1-based
//! ([NIST format](https://math.nist.gov/MatrixMarket/formats.html)).
//!
//! Values are written with the shortest decimal form that reads back to the
//! same `f64` (ryu), so a written matrix round-trips bit for bit.

use seam::CsrMatrix;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// Writes `m` as `coordinate real general` with 1-based indices; `comment`
/// lines (without the leading `%`) follow the header.
///
/// # Errors
/// Any I/O error of `w`.
pub fn write_matrix_market<W: Write>(mut w: W, m: &CsrMatrix, comment: &[&str]) -> io::Result<()> {
    writeln!(w, "%%MatrixMarket matrix coordinate real general")?;
    for line in comment {
        writeln!(w, "% {line}")?;
    }
    writeln!(w, "{} {} {}", m.nrows, m.ncols, m.nnz())?;
    let (mut int, mut float) = (itoa::Buffer::new(), ryu::Buffer::new());
    for i in 0..m.nrows {
        let (cols, vals) = m.row(i);
        for (&j, &v) in cols.iter().zip(vals) {
            w.write_all(int.format(i + 1).as_bytes())?;
            w.write_all(b" ")?;
            w.write_all(int.format(j + 1).as_bytes())?;
            w.write_all(b" ")?;
            w.write_all(float.format(v).as_bytes())?;
            w.write_all(b"\n")?;
        }
    }
    w.flush()
}

/// Writes `m` to the file `path` (created or truncated).
///
/// # Errors
/// Creating or writing the file.
pub fn write_matrix_market_file(path: impl AsRef<Path>, m: &CsrMatrix, comment: &[&str]) -> io::Result<()> {
    write_matrix_market(BufWriter::with_capacity(1 << 20, File::create(path)?), m, comment)
}

/// What is wrong with a Matrix Market text.
#[derive(Debug, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct MatrixMarketError {
    /// 1-based line number.
    pub line: usize,
    /// What was expected.
    pub message: String,
}

/// Reads a `coordinate real general` matrix (as written by
/// [`write_matrix_market`]); duplicate entries are summed.
///
/// # Errors
/// A [`MatrixMarketError`] naming the line that is wrong.
pub fn read_matrix_market_str(text: &str) -> Result<CsrMatrix, MatrixMarketError> {
    let err = |line: usize, message: &str| MatrixMarketError { line, message: message.to_string() };
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    match lines.next() {
        Some((_, h)) if h.to_lowercase().starts_with("%%matrixmarket matrix coordinate real general") => {}
        _ => return Err(err(1, "expected the header %%MatrixMarket matrix coordinate real general")),
    }
    let mut data = lines.filter(|(_, l)| !l.starts_with('%') && !l.trim().is_empty());
    let (n, size) = data.next().ok_or_else(|| err(2, "missing the size line"))?;
    let size: Vec<usize> = size
        .split_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|_| err(n, "bad size line"))?;
    let [nrows, ncols, nnz] = size[..] else {
        return Err(err(n, "the size line needs rows, columns, entries"));
    };
    let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nrows];
    let mut count = 0;
    for (n, l) in data {
        let f: Vec<&str> = l.split_whitespace().collect();
        let [i, j, v] = f[..] else { return Err(err(n, "expected: row column value")) };
        let (i, j): (usize, usize) = match (i.parse(), j.parse()) {
            (Ok(i), Ok(j)) if (1..=nrows).contains(&i) && (1..=ncols).contains(&j) => (i, j),
            _ => return Err(err(n, "index out of range")),
        };
        let v: f64 = v.parse().map_err(|_| err(n, "bad value"))?;
        rows[i - 1].push((j - 1, v));
        count += 1;
    }
    if count != nnz {
        return Err(err(0, &format!("the size line announces {nnz} entries, found {count}")));
    }
    let merged: Vec<(Vec<usize>, Vec<f64>)> = rows
        .into_iter()
        .map(|mut r| {
            r.sort_by_key(|e| e.0);
            let (mut c, mut v): (Vec<usize>, Vec<f64>) = (Vec::new(), Vec::new());
            for (j, x) in r {
                if c.last() == Some(&j) {
                    *v.last_mut().unwrap() += x;
                } else {
                    c.push(j);
                    v.push(x);
                }
            }
            (c, v)
        })
        .collect();
    Ok(CsrMatrix::from_rows(ncols, merged.iter().map(|(c, v)| (c.as_slice(), v.as_slice()))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_is_bit_exact() {
        let rows: [(&[usize], &[f64]); 3] =
            [(&[0, 2], &[1.0 / 3.0, -2.5e-300]), (&[], &[]), (&[1], &[std::f64::consts::PI])];
        let m = CsrMatrix::from_rows(3, rows);
        let mut out = Vec::new();
        write_matrix_market(&mut out, &m, &["rows: slave nodes"]).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text
            .starts_with("%%MatrixMarket matrix coordinate real general\n% rows: slave nodes\n3 3 3\n1 1 "));
        assert_eq!(read_matrix_market_str(&text).unwrap(), m);
    }

    #[test]
    fn errors_name_the_line() {
        let e = read_matrix_market_str("%%MatrixMarket matrix coordinate real general\n2 2 1\n3 1 1.0\n")
            .unwrap_err();
        assert_eq!(e.to_string(), "line 3: index out of range");
    }
}
