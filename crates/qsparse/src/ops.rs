//! Products and algebra of sparse matrices: `y = A x`, `y = Aᴴ x`, `Aᴴ`, scaling, linear
//! combinations, entry maps, the Hermitian check and row extraction.

use num_traits::{Float, Zero};
use qscalar::Scalar;

use crate::{SparseError, SparseMatrix, threads, vector};

impl<T: Scalar> SparseMatrix<T> {
    /// Whether a product with this matrix is split between two threads: at least
    /// [`threads::SPLIT_REALS`] stored reals, and a second thread allowed.
    fn products_split(&self) -> bool {
        self.nnz() * T::REAL_DIM >= threads::SPLIT_REALS && threads::second_thread_allowed()
    }

    fn check_dim(
        &self,
        len: usize,
        expected: usize,
        context: &'static str,
    ) -> Result<(), SparseError> {
        if len != expected {
            return Err(SparseError::DimensionMismatch {
                expected,
                found: len,
                context,
            });
        }
        Ok(())
    }

    /// `y = A x` (entries multiply from the left: `yᵢ = Σⱼ Aᵢⱼ xⱼ`).
    ///
    /// Column by column, each column scattered into `y` times `xⱼ` (one right multiplier per
    /// column). Large products run on two threads, each owning half of the rows of `y`: a
    /// thread scatters the part of every column that falls in its rows (the rows of a column
    /// are sorted, so that part is one end of the column), so no output is shared and the
    /// result is bit for bit the one-thread product.
    pub fn mul_vec(&self, x: &[T], y: &mut [T]) -> Result<(), SparseError> {
        self.check_dim(x.len(), self.ncols, "x in A x")?;
        self.check_dim(y.len(), self.nrows, "y in A x")?;
        if self.products_split() {
            let split = self.nrows / 2;
            let (top, bottom) = y.split_at_mut(split);
            threads::join(
                || self.scatter_rows(x, top, 0),
                || self.scatter_rows(x, bottom, split),
            );
        } else {
            self.scatter_rows(x, y, 0);
        }
        Ok(())
    }

    /// `y = (A x)[first..first + y.len()]`: the rows of the product from `first` on.
    fn scatter_rows(&self, x: &[T], y: &mut [T], first: usize) {
        y.fill(T::zero());
        let end = first + y.len();
        for (j, &xj) in x.iter().enumerate() {
            let (rows, vals) = self.col(j);
            // A column holds a handful of entries: counting those outside `y` from either end
            // costs less than the branches of a bisection, and nothing when `y` reaches that end.
            let start = if first == 0 {
                0
            } else {
                rows.len() - rows.iter().rev().take_while(|&&r| r >= first).count()
            };
            let stop = if end == self.nrows {
                rows.len()
            } else {
                rows.iter().take_while(|&&r| r < end).count()
            };
            vector::scatter_axpy(y, first, &rows[start..stop], &vals[start..stop], xj);
        }
    }

    /// `y = Aᴴ x`, i.e. `yⱼ = Σᵢ conj(Aᵢⱼ) xᵢ`: for a Hermitian `A`, the product `A x`, and
    /// the faster way to compute it.
    ///
    /// Each `yⱼ` is the inner product of column `j` with `x` ([`vector::gather_inner_columns`]),
    /// accumulated in registers and written once, where [`SparseMatrix::mul_vec`] scatters
    /// every column into `y` (a read-modify-write per entry, chained through the rows that
    /// neighbouring columns share). Large products run on two threads, each computing the
    /// entries of `y` of half the stored entries: the result is bit for bit the one-thread one.
    pub fn adjoint_mul_vec(&self, x: &[T], y: &mut [T]) -> Result<(), SparseError>
    where
        T: Scalar<Real = f64>,
    {
        self.check_dim(x.len(), self.nrows, "x in Aᴴ x")?;
        self.check_dim(y.len(), self.ncols, "y in Aᴴ x")?;
        if self.products_split() {
            let split = self.col_ptr.partition_point(|&p| p < self.nnz() / 2);
            let (first, second) = y.split_at_mut(split.min(self.ncols));
            threads::join(
                || self.gather_columns(x, first, 0),
                || self.gather_columns(x, second, split),
            );
        } else {
            self.gather_columns(x, y, 0);
        }
        Ok(())
    }

    /// `y = (Aᴴ x)[first..first + y.len()]`: the entries of the product from `first` on.
    fn gather_columns(&self, x: &[T], y: &mut [T], first: usize)
    where
        T: Scalar<Real = f64>,
    {
        let col_ptr = &self.col_ptr[first..first + y.len() + 1];
        vector::gather_inner_columns(col_ptr, &self.row_idx, &self.values, x, y);
    }

    /// The adjoint (conjugate transpose) `Aᴴ`, with `(Aᴴ)ᵢⱼ = conj(Aⱼᵢ)`: an `ncols × nrows`
    /// matrix with the same number of stored entries.
    pub fn adjoint(&self) -> SparseMatrix<T> {
        // Counting sort by row: column i of Aᴴ collects row i of A; visiting the columns of A in
        // order keeps the row indices of Aᴴ sorted.
        let mut col_ptr = vec![0usize; self.nrows + 1];
        for &i in &self.row_idx {
            col_ptr[i + 1] += 1;
        }
        for i in 0..self.nrows {
            col_ptr[i + 1] += col_ptr[i];
        }
        let mut next = col_ptr.clone();
        let mut row_idx = vec![0usize; self.nnz()];
        let mut values = vec![T::zero(); self.nnz()];
        for (i, j, v) in self.triplets() {
            row_idx[next[i]] = j;
            values[next[i]] = v.conj();
            next[i] += 1;
        }
        SparseMatrix::from_parts_unchecked(self.ncols, self.nrows, col_ptr, row_idx, values)
    }

    /// `A ← A r` for a real `r` (every stored entry scaled; the pattern is unchanged).
    pub fn scale(&mut self, r: T::Real) {
        vector::scale(&mut self.values, r);
    }

    /// `α A + β B`, entry by entry `α Aᵢⱼ + β Bᵢⱼ` (the scalars multiply from the **left**).
    ///
    /// The pattern is the union of the two patterns; an entry stored in only one operand
    /// contributes `α Aᵢⱼ` or `β Bᵢⱼ`, and no entry is dropped, even if it sums to zero.
    /// Fails with [`SparseError::DimensionMismatch`] if the shapes differ.
    pub fn linear_combination(alpha: T, a: &Self, beta: T, b: &Self) -> Result<Self, SparseError> {
        a.check_dim(b.nrows, a.nrows, "rows of B in α A + β B")?;
        a.check_dim(b.ncols, a.ncols, "columns of B in α A + β B")?;
        let mut col_ptr = Vec::with_capacity(a.ncols + 1);
        let mut row_idx = Vec::with_capacity(a.nnz().max(b.nnz()));
        let mut values = Vec::with_capacity(a.nnz().max(b.nnz()));
        col_ptr.push(0);
        for j in 0..a.ncols {
            let ((rows_a, vals_a), (rows_b, vals_b)) = (a.col(j), b.col(j));
            let (mut p, mut q) = (0, 0);
            while p < rows_a.len() || q < rows_b.len() {
                let ra = rows_a.get(p).copied().unwrap_or(usize::MAX);
                let rb = rows_b.get(q).copied().unwrap_or(usize::MAX);
                let mut value = T::zero();
                if ra <= rb {
                    value += alpha * vals_a[p];
                    p += 1;
                }
                if rb <= ra {
                    value += beta * vals_b[q];
                    q += 1;
                }
                row_idx.push(ra.min(rb));
                values.push(value);
            }
            col_ptr.push(row_idx.len());
        }
        Ok(Self::from_parts_unchecked(
            a.nrows, a.ncols, col_ptr, row_idx, values,
        ))
    }

    /// The matrix with the same pattern and entries `f(Aᵢⱼ)`, possibly over another scalar type:
    /// for example `l.map(Quat::from_real)` turns a real Laplacian `L` into `L ⊗ I` over the
    /// quaternions. `f` is applied to stored entries only, so `f(0)` should be `0`; the values
    /// are not re-validated (an `f` producing NaN yields a matrix with NaN entries).
    pub fn map<U: Scalar>(&self, f: impl Fn(T) -> U) -> SparseMatrix<U> {
        SparseMatrix::from_parts_unchecked(
            self.nrows,
            self.ncols,
            self.col_ptr.clone(),
            self.row_idx.clone(),
            self.values.iter().map(|&v| f(v)).collect(),
        )
    }

    /// The Hermitian defect `maxᵢⱼ |Aᵢⱼ − conj(Aⱼᵢ)|` (over both triangles, unstored entries
    /// counting as zero); `0` for a Hermitian matrix and `+∞` for a non-square one.
    pub fn hermitian_defect(&self) -> T::Real {
        if self.nrows != self.ncols {
            return T::Real::infinity();
        }
        self.largest_hermitian_defect()
            .map_or(T::Real::zero(), |worst| worst.defect)
    }

    /// The entry where a square `A` is furthest from Hermitian: the largest
    /// `|Aᵢⱼ − conj(Aⱼᵢ)|` (unstored entries counting as zero), the first in column order
    /// among ties. `None` if `A` is not square or is exactly Hermitian.
    pub fn largest_hermitian_defect(&self) -> Option<HermitianDefect<T::Real>> {
        let difference =
            Self::linear_combination(T::one(), self, -T::one(), &self.adjoint()).ok()?;
        let mut worst: Option<HermitianDefect<T::Real>> = None;
        for (row, col, v) in difference.triplets() {
            let defect = v.abs();
            if defect > worst.map_or(T::Real::zero(), |w| w.defect) {
                worst = Some(HermitianDefect { row, col, defect });
            }
        }
        worst
    }

    /// Whether `A` is square and Hermitian up to a relative tolerance:
    /// `hermitian_defect() ≤ tolerance · maxᵢⱼ |Aᵢⱼ|`.
    pub fn is_hermitian(&self, tolerance: T::Real) -> bool {
        let largest = self
            .values
            .iter()
            .fold(T::Real::zero(), |m, v| m.max(v.abs()));
        self.nrows == self.ncols && self.hermitian_defect() <= tolerance * largest
    }

    /// Column indices (increasing) and values of row `i`. Costs `O(ncols · log(nnz per column))`
    /// (CSC storage is by column).
    ///
    /// # Panics
    /// If `i ≥ nrows`, like [`SparseMatrix::col`] for a column index.
    pub fn row(&self, i: usize) -> (Vec<usize>, Vec<T>) {
        assert!(
            i < self.nrows,
            "row {i} out of bounds ({} rows)",
            self.nrows
        );
        (0..self.ncols)
            .filter_map(|j| {
                let (rows, vals) = self.col(j);
                rows.binary_search(&i).ok().map(|k| (j, vals[k]))
            })
            .unzip()
    }
}

/// Where a square matrix is furthest from Hermitian ([`SparseMatrix::largest_hermitian_defect`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HermitianDefect<R> {
    /// Row `i` of the entry `Aᵢⱼ`.
    pub row: usize,
    /// Column `j` of the entry `Aᵢⱼ`.
    pub col: usize,
    /// `|Aᵢⱼ − conj(Aⱼᵢ)|`.
    pub defect: R,
}
