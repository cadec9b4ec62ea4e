//! Sparse × sparse products and diagonal scalings.

use qscalar::Scalar;

use crate::{SparseError, SparseMatrix};

impl<T: Scalar> SparseMatrix<T> {
    /// The product `A B` (`self = A`), `(A B)ᵢⱼ = Σₖ Aᵢₖ Bₖⱼ` with operand order kept (entries
    /// of `A` on the left). Column-by-column Gustavson algorithm with a dense accumulator:
    /// `O(flops + ncols)` time; every structurally reached entry is stored, even if it sums to 0.
    pub fn matmul(&self, b: &SparseMatrix<T>) -> Result<SparseMatrix<T>, SparseError> {
        if self.ncols != b.nrows {
            return Err(SparseError::DimensionMismatch {
                expected: self.ncols,
                found: b.nrows,
                context: "rows of B in A B",
            });
        }
        let mut accumulator = vec![T::zero(); self.nrows];
        let mut occupied = vec![false; self.nrows];
        let mut rows_touched: Vec<usize> = Vec::new();
        let mut col_ptr = Vec::with_capacity(b.ncols + 1);
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        col_ptr.push(0);
        for j in 0..b.ncols {
            let (b_rows, b_vals) = b.col(j);
            for (&k, &b_kj) in b_rows.iter().zip(b_vals) {
                let (a_rows, a_vals) = self.col(k);
                for (&i, &a_ik) in a_rows.iter().zip(a_vals) {
                    if !occupied[i] {
                        occupied[i] = true;
                        rows_touched.push(i);
                    }
                    accumulator[i] += a_ik * b_kj;
                }
            }
            rows_touched.sort_unstable();
            for &i in &rows_touched {
                row_idx.push(i);
                values.push(accumulator[i]);
                accumulator[i] = T::zero();
                occupied[i] = false;
            }
            rows_touched.clear();
            col_ptr.push(row_idx.len());
        }
        Ok(SparseMatrix::from_parts_unchecked(
            self.nrows, b.ncols, col_ptr, row_idx, values,
        ))
    }

    /// `diag(d) A`: row `i` multiplied by the real `dᵢ`.
    pub fn scale_rows(&self, d: &[T::Real]) -> Result<SparseMatrix<T>, SparseError> {
        if d.len() != self.nrows {
            return Err(SparseError::DimensionMismatch {
                expected: self.nrows,
                found: d.len(),
                context: "row scaling",
            });
        }
        let mut scaled = self.clone();
        for (v, &i) in scaled.values.iter_mut().zip(&self.row_idx) {
            *v = v.scale(d[i]);
        }
        Ok(scaled)
    }
}
