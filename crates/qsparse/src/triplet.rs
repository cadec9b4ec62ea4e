//! Triplet (coordinate) assembly: `(row, col, value)` entries, duplicates summed.

use qscalar::Scalar;

use crate::{SparseError, SparseMatrix};

/// A matrix under assembly as a list of `(row, col, value)` triplets. Duplicates are summed when
/// compressed (finite-element style assembly). Indices and values are validated on insertion.
#[derive(Debug, Clone)]
pub struct TripletMatrix<T> {
    nrows: usize,
    ncols: usize,
    entries: Vec<(usize, usize, T)>,
}

impl<T: Scalar> TripletMatrix<T> {
    /// An empty `nrows × ncols` assembly.
    pub fn new(nrows: usize, ncols: usize) -> Self {
        Self {
            nrows,
            ncols,
            entries: Vec::new(),
        }
    }

    /// An empty assembly with room for `capacity` entries.
    pub fn with_capacity(nrows: usize, ncols: usize, capacity: usize) -> Self {
        Self {
            nrows,
            ncols,
            entries: Vec::with_capacity(capacity),
        }
    }

    /// Adds `value` at `(row, col)`; fails on an index outside the matrix or a non-finite value.
    pub fn push(&mut self, row: usize, col: usize, value: T) -> Result<(), SparseError> {
        if row >= self.nrows || col >= self.ncols {
            return Err(SparseError::IndexOutOfBounds {
                row,
                col,
                nrows: self.nrows,
                ncols: self.ncols,
            });
        }
        if !value.is_finite() {
            return Err(SparseError::NonFinite { row, col });
        }
        self.entries.push((row, col, value));
        Ok(())
    }

    /// Builds an assembly from an iterator of triplets, validating each.
    pub fn from_triplets(
        nrows: usize,
        ncols: usize,
        triplets: impl IntoIterator<Item = (usize, usize, T)>,
    ) -> Result<Self, SparseError> {
        let mut m = Self::new(nrows, ncols);
        for (r, c, v) in triplets {
            m.push(r, c, v)?;
        }
        Ok(m)
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// The triplets pushed so far (with duplicates).
    pub fn entries(&self) -> &[(usize, usize, T)] {
        &self.entries
    }

    /// Compresses to CSC, summing duplicates. Explicit zeros (including sums that cancel) are
    /// kept, so the pattern depends only on the indices pushed.
    pub fn to_csc(&self) -> SparseMatrix<T> {
        // Counting sort by column, then by row within each column: O(nnz + n).
        let mut col_count = vec![0usize; self.ncols + 1];
        for &(_, c, _) in &self.entries {
            col_count[c + 1] += 1;
        }
        for c in 0..self.ncols {
            col_count[c + 1] += col_count[c];
        }
        let mut by_col: Vec<(usize, T)> = vec![(0, T::zero()); self.entries.len()];
        let mut next = col_count.clone();
        for &(r, c, v) in &self.entries {
            by_col[next[c]] = (r, v);
            next[c] += 1;
        }
        let mut col_ptr = Vec::with_capacity(self.ncols + 1);
        let mut row_idx = Vec::with_capacity(self.entries.len());
        let mut values = Vec::with_capacity(self.entries.len());
        col_ptr.push(0);
        for c in 0..self.ncols {
            let column = &mut by_col[col_count[c]..col_count[c + 1]];
            column.sort_unstable_by_key(|&(r, _)| r);
            for &(r, v) in column.iter() {
                if row_idx.len() > col_ptr[c] && row_idx[row_idx.len() - 1] == r {
                    *values
                        .last_mut()
                        .expect("a row index was pushed with its value") += v;
                } else {
                    row_idx.push(r);
                    values.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        SparseMatrix::from_parts_unchecked(self.nrows, self.ncols, col_ptr, row_idx, values)
    }
}
