//! Compressed sparse row matrices: the output format of the mortar assembly.
//!
//! ```text
//!     [ 1 . 2 ]      indptr  = [0, 2, 2, 3]     row i owns indices/values
//! A = [ . . . ]      indices = [0, 2, 1]        indptr[i]..indptr[i+1];
//!     [ . 3 . ]      values  = [1, 2, 3]        columns ascending, no duplicates
//! ```

/// A CSR matrix with sorted, unique column indices in each row.
///
/// # Invariants
/// `indptr.len() == nrows + 1`, `indptr` non-decreasing from 0 to `indices.len()`,
/// `indices.len() == values.len()`, every index `< ncols`, strictly increasing
/// within a row. [`CsrMatrix::from_rows`] builds matrices that satisfy them.
#[derive(Clone, Debug, PartialEq)]
pub struct CsrMatrix {
    /// Number of rows.
    pub nrows: usize,
    /// Number of columns.
    pub ncols: usize,
    /// Row pointers, length `nrows + 1`.
    pub indptr: Vec<usize>,
    /// Column indices.
    pub indices: Vec<usize>,
    /// Values.
    pub values: Vec<f64>,
}

impl CsrMatrix {
    /// An all-zero matrix.
    pub fn zeros(nrows: usize, ncols: usize) -> Self {
        CsrMatrix { nrows, ncols, indptr: vec![0; nrows + 1], indices: Vec::new(), values: Vec::new() }
    }

    /// Concatenates rows given as (column, value) lists already sorted and unique.
    ///
    /// # Panics
    /// If a column index is out of range (a caller bug).
    pub fn from_rows<'a>(ncols: usize, rows: impl IntoIterator<Item = (&'a [usize], &'a [f64])>) -> Self {
        let mut m = CsrMatrix { nrows: 0, ncols, indptr: vec![0], indices: Vec::new(), values: Vec::new() };
        for (cols, vals) in rows {
            assert!(cols.iter().all(|&c| c < ncols), "column index out of range: ncols = {ncols}");
            m.indices.extend_from_slice(cols);
            m.values.extend_from_slice(vals);
            m.indptr.push(m.indices.len());
            m.nrows += 1;
        }
        m
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// The first row holding a NaN or infinite value, if any.
    pub fn first_non_finite_row(&self) -> Option<usize> {
        let entry = self.values.iter().position(|v| !v.is_finite())?;
        Some(self.indptr.partition_point(|&start| start <= entry) - 1)
    }

    /// Columns and values of row `i`.
    pub fn row(&self, i: usize) -> (&[usize], &[f64]) {
        let r = self.indptr[i]..self.indptr[i + 1];
        (&self.indices[r.clone()], &self.values[r])
    }

    /// The entry (i, j), zero when not stored.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (c, v) = self.row(i);
        c.binary_search(&j).map_or(0.0, |k| v[k])
    }

    /// Row sums A·1.
    pub fn row_sums(&self) -> Vec<f64> {
        (0..self.nrows).map(|i| self.row(i).1.iter().sum()).collect()
    }

    /// Sum of all entries 1ᵀA1.
    pub fn sum(&self) -> f64 {
        self.values.iter().sum()
    }

    /// y = A x for `k` interleaved components (x is ncols×k, y is nrows×k, row-major).
    ///
    /// # Panics
    /// If `x.len() != ncols * k`.
    pub fn mul_vec(&self, x: &[f64], k: usize) -> Vec<f64> {
        assert_eq!(x.len(), self.ncols * k, "x must have ncols × k = {} × {k} entries", self.ncols);
        let mut y = vec![0.0; self.nrows * k];
        for i in 0..self.nrows {
            let (c, v) = self.row(i);
            for (&j, &a) in c.iter().zip(v) {
                for l in 0..k {
                    y[i * k + l] += a * x[j * k + l];
                }
            }
        }
        y
    }

    /// y = Aᵀ x for `k` interleaved components (x is nrows×k, y is ncols×k).
    ///
    /// # Panics
    /// If `x.len() != nrows * k`.
    pub fn transpose_mul_vec(&self, x: &[f64], k: usize) -> Vec<f64> {
        assert_eq!(x.len(), self.nrows * k, "x must have nrows × k = {} × {k} entries", self.nrows);
        let mut y = vec![0.0; self.ncols * k];
        for i in 0..self.nrows {
            let (c, v) = self.row(i);
            for (&j, &a) in c.iter().zip(v) {
                for l in 0..k {
                    y[j * k + l] += a * x[i * k + l];
                }
            }
        }
        y
    }

    /// The matrix with row i scaled by `s[i]`.
    #[must_use]
    pub fn scale_rows(&self, s: &[f64]) -> CsrMatrix {
        let mut m = self.clone();
        for i in 0..m.nrows {
            for v in &mut m.values[m.indptr[i]..m.indptr[i + 1]] {
                *v *= s[i];
            }
        }
        m
    }

    /// Aᵀ, with sorted rows.
    #[must_use]
    pub fn transpose(&self) -> CsrMatrix {
        let mut indptr = vec![0usize; self.ncols + 1];
        for &j in &self.indices {
            indptr[j + 1] += 1;
        }
        for j in 0..self.ncols {
            indptr[j + 1] += indptr[j];
        }
        let mut next = indptr.clone();
        let mut indices = vec![0; self.nnz()];
        let mut values = vec![0.0; self.nnz()];
        for i in 0..self.nrows {
            let (c, v) = self.row(i);
            for (&j, &a) in c.iter().zip(v) {
                indices[next[j]] = i;
                values[next[j]] = a;
                next[j] += 1;
            }
        }
        CsrMatrix { nrows: self.ncols, ncols: self.nrows, indptr, indices, values }
    }

    /// The diagonal (zero where not stored).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.nrows.min(self.ncols)).map(|i| self.get(i, i)).collect()
    }

    /// True when no entry lies off the diagonal.
    pub fn is_diagonal(&self) -> bool {
        (0..self.nrows).all(|i| self.row(i).0.iter().all(|&j| j == i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> CsrMatrix {
        let rows: [(&[usize], &[f64]); 3] = [(&[0, 2], &[1.0, 2.0]), (&[], &[]), (&[1], &[3.0])];
        CsrMatrix::from_rows(3, rows)
    }

    #[test]
    fn layout_matches_the_module_doc() {
        let a = example();
        assert_eq!(a.indptr, vec![0, 2, 2, 3]);
        assert_eq!(a.indices, vec![0, 2, 1]);
        assert_eq!(a.get(0, 2), 2.0);
        assert_eq!(a.get(1, 1), 0.0);
        assert_eq!(a.row_sums(), vec![3.0, 0.0, 3.0]);
    }

    #[test]
    fn the_first_non_finite_row_skips_empty_rows() {
        let mut a = example();
        assert_eq!(a.first_non_finite_row(), None);
        a.values[2] = f64::NAN;
        assert_eq!(a.first_non_finite_row(), Some(2));
        a.values[1] = f64::INFINITY;
        assert_eq!(a.first_non_finite_row(), Some(0));
    }

    #[test]
    fn products_with_two_components() {
        let a = example();
        let x = [1.0, 10.0, 2.0, 20.0, 3.0, 30.0];
        assert_eq!(a.mul_vec(&x, 2), vec![7.0, 70.0, 0.0, 0.0, 6.0, 60.0]);
        assert_eq!(a.transpose_mul_vec(&x, 2), vec![1.0, 10.0, 9.0, 90.0, 2.0, 20.0]);
        let t = a.transpose();
        assert_eq!(t.mul_vec(&x, 2), a.transpose_mul_vec(&x, 2));
        assert_eq!(t.transpose(), a);
    }
}
