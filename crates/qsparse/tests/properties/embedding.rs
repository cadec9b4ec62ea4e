//! The real-block and complex-adjoint embeddings commute with the SpMV and with the adjoint
//! (docs/MATH.md, "The real-block representation"): `block(A) · reals(x) = reals(A x)`,
//! `block(Aᴴ) = block(A)ᵀ`, `χ(A) · χ(x) = χ(A x)`, `χ(Aᴴ) = χ(A)ᴴ`.

use faer::ColRef;
use num_complex::Complex;
use proptest::prelude::*;
use qscalar::Quat;
use qscalar::strategies::ScalarStrategy;
use qsparse::SparseMatrix;
use qsparse::embedding::{complex_adjoint_vector, from_complex_adjoint_vector};
use qsparse::strategies::{sparse_matrix, vector};

use crate::common::assert_close;

const TOL: f64 = 1e-12;

fn matrix_and_vector<T: ScalarStrategy>() -> impl Strategy<Value = (SparseMatrix<T>, Vec<T>)> {
    (0..8usize, 0..8usize, 0.0..=1.0)
        .prop_flat_map(|(m, n, d)| (sparse_matrix::<T>(m, n, d), vector::<T>(n)))
}

/// `A x` from the dense product (independent of the sparse kernels).
fn dense_product<T: ScalarStrategy>(a: &SparseMatrix<T>, x: &[T]) -> Vec<T> {
    a.to_dense().mul_vec(x).unwrap()
}

fn real_block_commutes_with_spmv<T: ScalarStrategy>(
    (a, x): (SparseMatrix<T>, Vec<T>),
) -> Result<(), TestCaseError> {
    let block = a.to_real_block();
    prop_assert_eq!(
        (block.nrows(), block.ncols()),
        (T::REAL_DIM * a.nrows(), T::REAL_DIM * a.ncols())
    );
    let y = block.as_ref() * ColRef::from_slice(T::as_reals(&x));
    let found: Vec<f64> = (0..y.nrows()).map(|i| y[i]).collect();
    let expected = dense_product(&a, &x);
    assert_close(&found, T::as_reals(&expected), TOL)
}

fn complex_adjoint_commutes_with_spmv<T: ScalarStrategy>(
    (a, x): (SparseMatrix<T>, Vec<T>),
) -> Result<(), TestCaseError> {
    let chi = a.to_complex_adjoint();
    prop_assert_eq!(
        (chi.nrows(), chi.ncols()),
        (T::COMPLEX_DIM * a.nrows(), T::COMPLEX_DIM * a.ncols())
    );
    let image = complex_adjoint_vector(&x);
    prop_assert_eq!(&from_complex_adjoint_vector::<T>(&image), &x);
    let y = chi.as_ref() * ColRef::from_slice(&image);
    let found: Vec<Complex<f64>> = (0..y.nrows()).map(|i| y[i]).collect();
    let expected = complex_adjoint_vector(&dense_product(&a, &x));
    assert_close(&found, &expected, TOL)
}

/// Exact: conjugation, transposition and the block maps do no arithmetic.
fn embeddings_commute_with_adjoint<T: ScalarStrategy>(
    a: SparseMatrix<T>,
) -> Result<(), TestCaseError> {
    let adjoint = a.adjoint();
    prop_assert_eq!(
        adjoint.to_real_block().to_dense(),
        a.to_real_block().to_dense().transpose().to_owned()
    );
    prop_assert_eq!(
        adjoint.to_complex_adjoint().to_dense(),
        a.to_complex_adjoint().to_dense().adjoint().to_owned()
    );
    Ok(())
}

macro_rules! instantiate {
    ($($module:ident: $t:ty),*) => {$(
        mod $module {
            use super::*;

            proptest! {
                #[test]
                fn real_block_spmv(input in matrix_and_vector::<$t>()) {
                    real_block_commutes_with_spmv(input)?;
                }

                #[test]
                fn complex_adjoint_spmv(input in matrix_and_vector::<$t>()) {
                    complex_adjoint_commutes_with_spmv(input)?;
                }

                #[test]
                fn adjoint(input in matrix_and_vector::<$t>()) {
                    embeddings_commute_with_adjoint(input.0)?;
                }
            }
        }
    )*};
}

instantiate!(real: f64, complex: Complex<f64>, quaternion: Quat<f64>);
