//! Products and algebra of sparse matrices: `y = A x`, `y = Aᴴ x`, `Aᴴ`, scaling, sums.

use qscalar::Scalar;

use crate::{SparseError, SparseMatrix};

impl<T: Scalar> SparseMatrix<T> {
    fn check_vec(
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
    pub fn mul_vec(&self, x: &[T], y: &mut [T]) -> Result<(), SparseError> {
        self.check_vec(x.len(), self.ncols, "x in A x")?;
        self.check_vec(y.len(), self.nrows, "y in A x")?;
        y.fill(T::zero());
        for (j, &xj) in x.iter().enumerate() {
            let (rows, vals) = self.col(j);
            for (&i, &a) in rows.iter().zip(vals) {
                y[i] += a * xj;
            }
        }
        Ok(())
    }

    /// `y = Aᴴ x`, i.e. `yⱼ = Σᵢ conj(Aᵢⱼ) xᵢ`.
    pub fn adjoint_mul_vec(&self, x: &[T], y: &mut [T]) -> Result<(), SparseError> {
        self.check_vec(x.len(), self.nrows, "x in Aᴴ x")?;
        self.check_vec(y.len(), self.ncols, "y in Aᴴ x")?;
        for (j, yj) in y.iter_mut().enumerate() {
            let (rows, vals) = self.col(j);
            *yj = rows.iter().zip(vals).map(|(&i, &a)| a.conj() * x[i]).sum();
        }
        Ok(())
    }
}
