//! A small column-major dense matrix, for conversions, tests and the small dense problems of
//! the eigensolvers. Not a BLAS: products are plain loops.

use core::ops::{Index, IndexMut};

use qscalar::Scalar;

use crate::{SparseError, SparseMatrix};

/// A dense `nrows × ncols` matrix stored column-major.
#[derive(Debug, Clone, PartialEq)]
pub struct DenseMatrix<T> {
    nrows: usize,
    ncols: usize,
    data: Vec<T>,
}

impl<T: Scalar> DenseMatrix<T> {
    /// The zero matrix.
    pub fn zeros(nrows: usize, ncols: usize) -> Self {
        Self {
            nrows,
            ncols,
            data: vec![T::zero(); nrows * ncols],
        }
    }

    /// The `n × n` identity.
    pub fn identity(n: usize) -> Self {
        Self::from_fn(n, n, |i, j| if i == j { T::one() } else { T::zero() })
    }

    /// The matrix with entries `f(i, j)`.
    pub fn from_fn(nrows: usize, ncols: usize, mut f: impl FnMut(usize, usize) -> T) -> Self {
        let mut data = Vec::with_capacity(nrows * ncols);
        for j in 0..ncols {
            for i in 0..nrows {
                data.push(f(i, j));
            }
        }
        Self { nrows, ncols, data }
    }

    /// Wraps column-major data of length `nrows · ncols`.
    pub fn from_column_major(
        nrows: usize,
        ncols: usize,
        data: Vec<T>,
    ) -> Result<Self, SparseError> {
        if data.len() != nrows * ncols {
            return Err(SparseError::DimensionMismatch {
                expected: nrows * ncols,
                found: data.len(),
                context: "dense column-major data",
            });
        }
        Ok(Self { nrows, ncols, data })
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// The column-major data.
    pub fn as_slice(&self) -> &[T] {
        &self.data
    }

    /// The column-major data, mutable.
    pub fn as_mut_slice(&mut self) -> &mut [T] {
        &mut self.data
    }

    /// Column `j`.
    pub fn col(&self, j: usize) -> &[T] {
        &self.data[j * self.nrows..(j + 1) * self.nrows]
    }

    /// Column `j`, mutable.
    pub fn col_mut(&mut self, j: usize) -> &mut [T] {
        &mut self.data[j * self.nrows..(j + 1) * self.nrows]
    }

    /// The conjugate transpose `Aᴴ`.
    pub fn adjoint(&self) -> Self {
        Self::from_fn(self.ncols, self.nrows, |i, j| self[(j, i)].conj())
    }

    /// The product `A B` (operand order kept: entries of `A` multiply from the left).
    pub fn matmul(&self, b: &Self) -> Result<Self, SparseError> {
        if self.ncols != b.nrows {
            return Err(SparseError::DimensionMismatch {
                expected: self.ncols,
                found: b.nrows,
                context: "rows of B in A B",
            });
        }
        let mut c = Self::zeros(self.nrows, b.ncols);
        for j in 0..b.ncols {
            for l in 0..self.ncols {
                let b_lj = b[(l, j)];
                for i in 0..self.nrows {
                    c.data[j * self.nrows + i] += self.data[l * self.nrows + i] * b_lj;
                }
            }
        }
        Ok(c)
    }

    /// `A x`.
    pub fn mul_vec(&self, x: &[T]) -> Result<Vec<T>, SparseError> {
        if x.len() != self.ncols {
            return Err(SparseError::DimensionMismatch {
                expected: self.ncols,
                found: x.len(),
                context: "x in A x",
            });
        }
        let mut y = vec![T::zero(); self.nrows];
        for (j, &xj) in x.iter().enumerate() {
            for (yi, &a) in y.iter_mut().zip(self.col(j)) {
                *yi += a * xj;
            }
        }
        Ok(y)
    }

    /// The sparse matrix of the entries whose modulus exceeds `drop_below` (use `0.0` to keep
    /// every non-zero entry).
    pub fn to_sparse(&self, drop_below: T::Real) -> SparseMatrix<T> {
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        for j in 0..self.ncols {
            for (i, &v) in self.col(j).iter().enumerate() {
                if v.abs() > drop_below {
                    row_idx.push(i);
                    values.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        SparseMatrix::from_parts_unchecked(self.nrows, self.ncols, col_ptr, row_idx, values)
    }
}

impl<T: Scalar> SparseMatrix<T> {
    /// The dense matrix with the same entries.
    pub fn to_dense(&self) -> DenseMatrix<T> {
        let mut d = DenseMatrix::zeros(self.nrows, self.ncols);
        for (i, j, v) in self.triplets() {
            d[(i, j)] = v;
        }
        d
    }
}

impl<T> Index<(usize, usize)> for DenseMatrix<T> {
    type Output = T;
    fn index(&self, (i, j): (usize, usize)) -> &T {
        assert!(
            i < self.nrows && j < self.ncols,
            "index ({i}, {j}) out of bounds"
        );
        &self.data[j * self.nrows + i]
    }
}

impl<T> IndexMut<(usize, usize)> for DenseMatrix<T> {
    fn index_mut(&mut self, (i, j): (usize, usize)) -> &mut T {
        assert!(
            i < self.nrows && j < self.ncols,
            "index ({i}, {j}) out of bounds"
        );
        &mut self.data[j * self.nrows + i]
    }
}
