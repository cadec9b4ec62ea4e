//! Compressed sparse column (CSC) storage.
//!
//! CSC was chosen because it is faer's native layout: the symbolic Cholesky analysis and the
//! real-block/complex-adjoint embeddings consume our pattern arrays directly. Row indices within a
//! column are strictly increasing (sorted, no duplicates).

use qscalar::Scalar;

use crate::SparseError;

/// A sparse `nrows × ncols` matrix in CSC form over any [`Scalar`].
///
/// Column `j` holds the entries `values[col_ptr[j]..col_ptr[j+1]]` at rows
/// `row_idx[col_ptr[j]..col_ptr[j+1]]` (strictly increasing).
#[derive(Debug, Clone, PartialEq)]
pub struct SparseMatrix<T> {
    pub(crate) nrows: usize,
    pub(crate) ncols: usize,
    pub(crate) col_ptr: Vec<usize>,
    pub(crate) row_idx: Vec<usize>,
    pub(crate) values: Vec<T>,
}

impl<T: Scalar> SparseMatrix<T> {
    /// Builds a matrix from CSC arrays, validating them: `col_ptr` has `ncols + 1`
    /// non-decreasing entries from 0 to `nnz`, row indices are in range and strictly increasing
    /// within each column, and values are finite.
    pub fn try_from_csc(
        nrows: usize,
        ncols: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        values: Vec<T>,
    ) -> Result<Self, SparseError> {
        if col_ptr.len().checked_sub(1) != Some(ncols) {
            return Err(SparseError::DimensionMismatch {
                expected: ncols.saturating_add(1),
                found: col_ptr.len(),
                context: "col_ptr length",
            });
        }
        if col_ptr[0] != 0 || col_ptr[ncols] != row_idx.len() || row_idx.len() != values.len() {
            return Err(SparseError::InvalidStorage(
                "col_ptr must start at 0 and end at nnz = row_idx.len() = values.len()",
            ));
        }
        // Checked for the whole array first: with the end at nnz, it bounds every column range.
        if col_ptr.windows(2).any(|w| w[0] > w[1]) {
            return Err(SparseError::InvalidStorage(
                "col_ptr must be non-decreasing",
            ));
        }
        for j in 0..ncols {
            let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
            for (k, &r) in rows.iter().enumerate() {
                if r >= nrows {
                    return Err(SparseError::IndexOutOfBounds {
                        row: r,
                        col: j,
                        nrows,
                        ncols,
                    });
                }
                if k > 0 && rows[k - 1] >= r {
                    return Err(SparseError::InvalidStorage(
                        "row indices must be strictly increasing within a column",
                    ));
                }
                if !values[col_ptr[j] + k].is_finite() {
                    return Err(SparseError::NonFinite { row: r, col: j });
                }
            }
        }
        Ok(Self {
            nrows,
            ncols,
            col_ptr,
            row_idx,
            values,
        })
    }

    /// The `nrows × columns.len()` matrix with the given dense columns, storing their nonzero
    /// entries (constraints given as full vectors, for instance). Every column must have
    /// `nrows` finite entries.
    pub fn from_dense_columns(nrows: usize, columns: &[Vec<T>]) -> Result<Self, SparseError> {
        let mut col_ptr = Vec::with_capacity(columns.len() + 1);
        col_ptr.push(0);
        let (mut row_idx, mut values) = (Vec::new(), Vec::new());
        for (j, column) in columns.iter().enumerate() {
            if column.len() != nrows {
                return Err(SparseError::DimensionMismatch {
                    expected: nrows,
                    found: column.len(),
                    context: "dense column length",
                });
            }
            for (i, &v) in column.iter().enumerate() {
                if !v.is_finite() {
                    return Err(SparseError::NonFinite { row: i, col: j });
                }
                if v != T::zero() {
                    row_idx.push(i);
                    values.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        Ok(Self::from_parts_unchecked(
            nrows,
            columns.len(),
            col_ptr,
            row_idx,
            values,
        ))
    }

    /// Builds a matrix from CSC arrays the caller guarantees valid (crate-internal producers).
    pub(crate) fn from_parts_unchecked(
        nrows: usize,
        ncols: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        values: Vec<T>,
    ) -> Self {
        debug_assert_eq!(col_ptr.len(), ncols + 1);
        debug_assert_eq!(row_idx.len(), values.len());
        Self {
            nrows,
            ncols,
            col_ptr,
            row_idx,
            values,
        }
    }

    /// The `nrows × ncols` zero matrix (no stored entries).
    pub fn zeros(nrows: usize, ncols: usize) -> Self {
        Self::from_parts_unchecked(nrows, ncols, vec![0; ncols + 1], Vec::new(), Vec::new())
    }

    /// The diagonal matrix with the given diagonal (every diagonal entry stored).
    pub fn from_diagonal(diagonal: &[T]) -> Self {
        let n = diagonal.len();
        Self::from_parts_unchecked(n, n, (0..=n).collect(), (0..n).collect(), diagonal.to_vec())
    }

    /// The `n × n` identity.
    pub fn identity(n: usize) -> Self {
        Self::from_diagonal(&vec![T::one(); n])
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// Column pointers (`ncols + 1` entries).
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// Row indices of the stored entries, column by column.
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }

    /// Stored values, column by column.
    pub fn values(&self) -> &[T] {
        &self.values
    }

    /// Mutable stored values (the pattern stays fixed).
    pub fn values_mut(&mut self) -> &mut [T] {
        &mut self.values
    }

    /// Row indices and values of column `j`.
    pub fn col(&self, j: usize) -> (&[usize], &[T]) {
        let range = self.col_ptr[j]..self.col_ptr[j + 1];
        (&self.row_idx[range.clone()], &self.values[range])
    }

    /// The entry at `(i, j)`, zero if not stored. `O(log nnz(col j))`.
    pub fn get(&self, i: usize, j: usize) -> T {
        let (rows, vals) = self.col(j);
        rows.binary_search(&i).map_or(T::zero(), |k| vals[k])
    }

    /// Iterates over `(row, col, value)` of the stored entries, column by column.
    pub fn triplets(&self) -> impl Iterator<Item = (usize, usize, T)> + '_ {
        (0..self.ncols).flat_map(move |j| {
            let (rows, vals) = self.col(j);
            rows.iter().zip(vals).map(move |(&i, &v)| (i, j, v))
        })
    }
}
