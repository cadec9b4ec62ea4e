//! Embeddings of a sparse matrix over ℂ or ℍ into larger real or complex faer matrices, the
//! baselines the native quaternion code is compared with (docs/MATH.md, "The real-block
//! representation").
//!
//! * Real block: every entry `a` becomes its `REAL_DIM × REAL_DIM` left-multiplication block
//!   `L(a)`, vertex-interleaved: row `R·i + c`, column `R·j + κ`. The vector map is the
//!   component layout itself ([`Scalar::as_reals`]), so `block(A) · reals(x) = reals(A x)` and
//!   `block(Aᴴ) = block(A)ᵀ`.
//! * Complex adjoint: every entry becomes `χ(a)` (`COMPLEX_DIM × COMPLEX_DIM`), and a vector
//!   entry `z₁ + z₂ j` maps to `(z₁, z̄₂)`; `χ(A) · col(x) = col(A x)` and `χ(Aᴴ) = χ(A)ᴴ`.
//!
//! Exact zeros inside a block (for example the twelve off-diagonal zeros of the block of a real
//! entry) are not stored: this is the matrix a user of the embedded path would assemble.

use faer::c64;
use faer::sparse::{SparseColMat, Triplet};
use qscalar::Scalar;

use crate::SparseMatrix;

impl<T: Scalar<Real = f64>> SparseMatrix<T> {
    /// The real `R·m × R·n` matrix with each entry replaced by its left-multiplication block
    /// (`R = REAL_DIM`: 4 for quaternions).
    pub fn to_real_block(&self) -> SparseColMat<usize, f64> {
        let r = T::REAL_DIM;
        let mut block = [0.0; 16];
        let mut triplets = Vec::with_capacity(self.nnz() * r * r);
        for (i, j, v) in self.triplets() {
            v.real_block(&mut block);
            for row in 0..r {
                for col in 0..r {
                    let b = block[row * r + col];
                    if b != 0.0 {
                        triplets.push(Triplet::new(r * i + row, r * j + col, b));
                    }
                }
            }
        }
        SparseColMat::try_new_from_triplets(r * self.nrows, r * self.ncols, &triplets)
            .expect("block indices lie inside the embedded matrix")
    }

    /// The complex `C·m × C·n` matrix with each entry replaced by its complex adjoint block
    /// (`C = COMPLEX_DIM`: 2 for quaternions, 1 otherwise).
    pub fn to_complex_adjoint(&self) -> SparseColMat<usize, c64> {
        let r = T::COMPLEX_DIM;
        let mut block = [c64::new(0.0, 0.0); 4];
        let mut triplets = Vec::with_capacity(self.nnz() * r * r);
        for (i, j, v) in self.triplets() {
            v.complex_adjoint_block(&mut block);
            for row in 0..r {
                for col in 0..r {
                    let b = block[row * r + col];
                    if b != c64::new(0.0, 0.0) {
                        triplets.push(Triplet::new(r * i + row, r * j + col, b));
                    }
                }
            }
        }
        SparseColMat::try_new_from_triplets(r * self.nrows, r * self.ncols, &triplets)
            .expect("block indices lie inside the embedded matrix")
    }
}

/// The image of `x` in the complex-adjoint embedding (`COMPLEX_DIM` complex numbers per entry).
pub fn complex_adjoint_vector<T: Scalar<Real = f64>>(x: &[T]) -> Vec<c64> {
    let r = T::COMPLEX_DIM;
    let mut out = vec![c64::new(0.0, 0.0); r * x.len()];
    for (v, chunk) in x.iter().zip(out.chunks_exact_mut(r)) {
        v.to_complex_column(chunk);
    }
    out
}

/// Inverse of [`complex_adjoint_vector`] (`z.len()` must be a multiple of `COMPLEX_DIM`).
pub fn from_complex_adjoint_vector<T: Scalar<Real = f64>>(z: &[c64]) -> Vec<T> {
    z.chunks_exact(T::COMPLEX_DIM)
        .map(T::from_complex_column)
        .collect()
}
