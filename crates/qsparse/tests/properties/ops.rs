//! Products and algebra (`mul_vec`, `adjoint_mul_vec`, `adjoint`, `scale`,
//! `linear_combination`, `map`, `hermitian_defect`, `row`) and triplet assembly, against dense
//! products and entrywise definitions.

use num_complex::Complex;
use proptest::prelude::*;
use qscalar::strategies::ScalarStrategy;
use qscalar::{Quat, Scalar};
use qsparse::strategies::{hpd_matrix, sparse_matrix, vector};
use qsparse::vector::inner;
use qsparse::{DenseMatrix, SparseMatrix, TripletMatrix};

use crate::common::{assert_close, relative_distance};

const TOL: f64 = 1e-12;

/// A random `m × n` matrix with `m, n ∈ 0..8` and density in `[0, 1]`.
fn matrix<T: ScalarStrategy>() -> impl Strategy<Value = SparseMatrix<T>> {
    (0..8usize, 0..8usize, 0.0..=1.0).prop_flat_map(|(m, n, d)| sparse_matrix::<T>(m, n, d))
}

/// A matrix with a vector for each side: `(A, x ∈ Tⁿ, y ∈ Tᵐ)`.
fn matrix_and_vectors<T: ScalarStrategy>()
-> impl Strategy<Value = (SparseMatrix<T>, Vec<T>, Vec<T>)> {
    matrix::<T>().prop_flat_map(|a| {
        let (m, n) = (a.nrows(), a.ncols());
        (Just(a), vector::<T>(n), vector::<T>(m))
    })
}

/// Two matrices of the same shape.
fn matrix_pair<T: ScalarStrategy>() -> impl Strategy<Value = (SparseMatrix<T>, SparseMatrix<T>)> {
    (0..8usize, 0..8usize, 0.0..=1.0, 0.0..=1.0).prop_flat_map(|(m, n, da, db)| {
        (sparse_matrix::<T>(m, n, da), sparse_matrix::<T>(m, n, db))
    })
}

fn dense_close<T: Scalar<Real = f64>>(
    found: &DenseMatrix<T>,
    expected: &DenseMatrix<T>,
) -> Result<(), TestCaseError> {
    prop_assert_eq!(
        (found.nrows(), found.ncols()),
        (expected.nrows(), expected.ncols())
    );
    assert_close(found.as_slice(), expected.as_slice(), TOL)
}

fn spmv_matches_dense<T: ScalarStrategy>(
    (a, x, y): (SparseMatrix<T>, Vec<T>, Vec<T>),
) -> Result<(), TestCaseError> {
    let dense = a.to_dense();
    let mut ax = vec![T::zero(); a.nrows()];
    a.mul_vec(&x, &mut ax).unwrap();
    assert_close(&ax, &dense.mul_vec(&x).unwrap(), TOL)?;
    let mut ahy = vec![T::zero(); a.ncols()];
    a.adjoint_mul_vec(&y, &mut ahy).unwrap();
    assert_close(&ahy, &dense.adjoint().mul_vec(&y).unwrap(), TOL)
}

/// `⟨A x, y⟩ = ⟨x, Aᴴ y⟩`, with `Aᴴ y` both from `adjoint_mul_vec` and from `adjoint()`.
fn adjoint_identity<T: ScalarStrategy>(
    (a, x, y): (SparseMatrix<T>, Vec<T>, Vec<T>),
) -> Result<(), TestCaseError> {
    let mut ax = vec![T::zero(); a.nrows()];
    a.mul_vec(&x, &mut ax).unwrap();
    let mut ahy = vec![T::zero(); a.ncols()];
    a.adjoint_mul_vec(&y, &mut ahy).unwrap();
    let mut ahy_explicit = vec![T::zero(); a.ncols()];
    a.adjoint().mul_vec(&y, &mut ahy_explicit).unwrap();
    let lhs = inner(&ax, &y);
    assert_close(&[lhs], &[inner(&x, &ahy)], TOL)?;
    assert_close(&[lhs], &[inner(&x, &ahy_explicit)], TOL)
}

fn adjoint_matches_dense<T: ScalarStrategy>(a: SparseMatrix<T>) -> Result<(), TestCaseError> {
    let adjoint = a.adjoint();
    prop_assert_eq!(adjoint.nnz(), a.nnz());
    // Exact: conjugation and transposition do no arithmetic.
    prop_assert_eq!(adjoint.to_dense(), a.to_dense().adjoint());
    prop_assert_eq!(adjoint.adjoint(), a);
    Ok(())
}

fn scale_matches_dense<T: ScalarStrategy>(
    (mut a, r): (SparseMatrix<T>, f64),
) -> Result<(), TestCaseError> {
    let dense = a.to_dense();
    let nnz = a.nnz();
    a.scale(r);
    prop_assert_eq!(a.nnz(), nnz);
    let expected = DenseMatrix::from_fn(dense.nrows(), dense.ncols(), |i, j| {
        dense[(i, j)] * T::from_real(r)
    });
    dense_close(&a.to_dense(), &expected)
}

fn linear_combination_matches_dense<T: ScalarStrategy>(
    (a, b, alpha, beta): (SparseMatrix<T>, SparseMatrix<T>, T, T),
) -> Result<(), TestCaseError> {
    let c = SparseMatrix::linear_combination(alpha, &a, beta, &b).unwrap();
    let (da, db) = (a.to_dense(), b.to_dense());
    let expected = DenseMatrix::from_fn(a.nrows(), a.ncols(), |i, j| {
        alpha * da[(i, j)] + beta * db[(i, j)]
    });
    dense_close(&c.to_dense(), &expected)?;
    // The pattern is the union of the operands' patterns.
    let union = a
        .triplets()
        .chain(b.triplets())
        .map(|(i, j, _)| (i, j))
        .collect::<std::collections::BTreeSet<_>>();
    let pattern = c
        .triplets()
        .map(|(i, j, _)| (i, j))
        .collect::<std::collections::BTreeSet<_>>();
    prop_assert_eq!(pattern, union);
    Ok(())
}

/// `map` with `v ↦ v c` (right multiplication, not commutative for quaternions).
fn map_matches_dense<T: ScalarStrategy>((a, c): (SparseMatrix<T>, T)) -> Result<(), TestCaseError> {
    let mapped = a.map(|v| v * c);
    prop_assert_eq!(mapped.col_ptr(), a.col_ptr());
    prop_assert_eq!(mapped.row_idx(), a.row_idx());
    let dense = a.to_dense();
    let expected = DenseMatrix::from_fn(a.nrows(), a.ncols(), |i, j| dense[(i, j)] * c);
    dense_close(&mapped.to_dense(), &expected)
}

/// `hermitian_defect` against the entrywise definition over all `(i, j)`.
fn hermitian_defect_matches_definition<T: ScalarStrategy>(
    a: SparseMatrix<T>,
) -> Result<(), TestCaseError> {
    if a.nrows() != a.ncols() {
        prop_assert_eq!(a.hermitian_defect(), f64::INFINITY);
        prop_assert!(!a.is_hermitian(f64::INFINITY));
        return Ok(());
    }
    let dense = a.to_dense();
    let n = a.nrows();
    let mut expected = 0.0f64;
    let mut largest = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            expected = expected.max((dense[(i, j)] - dense[(j, i)].conj()).abs());
            largest = largest.max(dense[(i, j)].abs());
        }
    }
    prop_assert_eq!(a.hermitian_defect(), expected);
    prop_assert_eq!(a.is_hermitian(1e-3), expected <= 1e-3 * largest);
    // The entry it names carries that defect (None: exactly Hermitian).
    match a.largest_hermitian_defect() {
        None => prop_assert_eq!(expected, 0.0),
        Some(worst) => {
            let (i, j) = (worst.row, worst.col);
            prop_assert_eq!(worst.defect, expected);
            prop_assert_eq!((dense[(i, j)] - dense[(j, i)].conj()).abs(), expected);
        }
    }
    // A + Aᴴ is Hermitian up to rounding of the sums (exactly: addition commutes).
    let symmetrised =
        SparseMatrix::linear_combination(T::one(), &a, T::one(), &a.adjoint()).unwrap();
    prop_assert!(symmetrised.is_hermitian(0.0));
    Ok(())
}

fn hpd_is_hermitian<T: ScalarStrategy>(a: SparseMatrix<T>) -> Result<(), TestCaseError> {
    prop_assert_eq!(a.hermitian_defect(), 0.0);
    prop_assert!(a.is_hermitian(0.0));
    Ok(())
}

/// `row(i)` lists exactly the stored entries of row `i`, by increasing column.
fn row_matches_triplets<T: ScalarStrategy>(a: SparseMatrix<T>) -> Result<(), TestCaseError> {
    for i in 0..a.nrows() {
        let (cols, vals): (Vec<_>, Vec<_>) = a
            .triplets()
            .filter(|&(r, _, _)| r == i)
            .map(|(_, c, v)| (c, v))
            .unzip();
        prop_assert_eq!(a.row(i), (cols, vals));
    }
    Ok(())
}

/// Triplets with few distinct indices (many duplicates) against dense accumulation.
fn triplets_with_duplicates<T: ScalarStrategy>()
-> impl Strategy<Value = (usize, usize, Vec<(usize, usize, T)>)> {
    (1..5usize, 1..5usize).prop_flat_map(|(m, n)| {
        (
            Just(m),
            Just(n),
            proptest::collection::vec((0..m, 0..n, T::strategy(1.0)), 0..40),
        )
    })
}

fn duplicates_are_summed<T: ScalarStrategy>(
    (m, n, triplets): (usize, usize, Vec<(usize, usize, T)>),
) -> Result<(), TestCaseError> {
    let mut expected = DenseMatrix::zeros(m, n);
    for &(i, j, v) in &triplets {
        expected[(i, j)] += v;
    }
    let a = TripletMatrix::from_triplets(m, n, triplets.iter().copied())
        .unwrap()
        .to_csc();
    dense_close(&a.to_dense(), &expected)?;
    // One stored entry per distinct index pair (explicit zeros and cancellations kept).
    let distinct = triplets
        .iter()
        .map(|&(i, j, _)| (i, j))
        .collect::<std::collections::BTreeSet<_>>();
    prop_assert_eq!(a.nnz(), distinct.len());
    // The result passes the validation of `try_from_csc` (sorted, in range, finite).
    let rebuilt = SparseMatrix::try_from_csc(
        m,
        n,
        a.col_ptr().to_vec(),
        a.row_idx().to_vec(),
        a.values().to_vec(),
    );
    prop_assert_eq!(rebuilt, Ok(a));
    Ok(())
}

macro_rules! instantiate {
    ($($module:ident: $t:ty),*) => {$(
        mod $module {
            use super::*;

            proptest! {
                #[test]
                fn spmv(input in matrix_and_vectors::<$t>()) { spmv_matches_dense(input)?; }

                #[test]
                fn inner_product_adjoint(input in matrix_and_vectors::<$t>()) {
                    adjoint_identity(input)?;
                }

                #[test]
                fn adjoint(a in matrix::<$t>()) { adjoint_matches_dense(a)?; }

                #[test]
                fn scale(input in (matrix::<$t>(), -3.0..3.0f64)) { scale_matches_dense(input)?; }

                #[test]
                fn linear_combination(
                    ((a, b), alpha, beta) in (matrix_pair::<$t>(), <$t>::strategy(2.0), <$t>::strategy(2.0))
                ) {
                    linear_combination_matches_dense((a, b, alpha, beta))?;
                }

                #[test]
                fn map(input in (matrix::<$t>(), <$t>::strategy(2.0))) { map_matches_dense(input)?; }

                #[test]
                fn hermitian_defect(a in matrix::<$t>()) { hermitian_defect_matches_definition(a)?; }

                #[test]
                fn hpd_strategy_is_hermitian(a in hpd_matrix::<$t>(1..12, 0.4)) { hpd_is_hermitian(a)?; }

                #[test]
                fn row(a in matrix::<$t>()) { row_matches_triplets(a)?; }

                #[test]
                fn triplet_duplicates(input in triplets_with_duplicates::<$t>()) {
                    duplicates_are_summed(input)?;
                }
            }
        }
    )*};
}

instantiate!(real: f64, complex: Complex<f64>, quaternion: Quat<f64>);

proptest! {
    /// `L.map(Quat::from_real)` is `L ⊗ I` over the quaternions: it acts on each real component
    /// of `x` separately, `((L ⊗ I) x)_c = L x_c`.
    #[test]
    fn map_real_to_quaternion_is_kronecker_identity(
        (l, x) in matrix::<f64>().prop_flat_map(|l| { let n = l.ncols(); (Just(l), vector::<Quat<f64>>(n)) })
    ) {
        let lifted = l.map(Quat::from_real);
        let mut y = vec![Quat::default(); l.nrows()];
        lifted.mul_vec(&x, &mut y).unwrap();
        let dense = l.to_dense();
        for c in 0..4 {
            let component: Vec<f64> = x.iter().map(|q| q.to_array()[c]).collect();
            let expected = dense.mul_vec(&component).unwrap();
            let found: Vec<f64> = y.iter().map(|q| q.to_array()[c]).collect();
            prop_assert!(relative_distance(&found, &expected) <= TOL);
        }
    }
}

/// `product(x)` on two threads equals the one-thread result bit for bit, and `expected` up to
/// rounding.
fn two_threads_agree(
    product: impl Fn(&[Quat<f64>], &mut [Quat<f64>]) -> Result<(), qsparse::SparseError>,
    x: &[Quat<f64>],
    expected: &[Quat<f64>],
) {
    let mut two = vec![Quat::default(); expected.len()];
    product(x, &mut two).unwrap();
    let mut one = vec![Quat::default(); expected.len()];
    qsparse::threads::on_one_thread(|| product(x, &mut one)).unwrap();
    assert_eq!(one, two);
    assert!(relative_distance(&two, expected) <= TOL);
}

/// A product large enough to run on two threads (each owning half of the rows of `y`) equals
/// the one-thread product bit for bit, and the entrywise sum `Σⱼ Aᵢⱼ xⱼ` up to rounding; also
/// for an odd number of rows and a rectangular matrix. The same for `Aᴴ z` (each thread owning
/// the entries of half of the stored values) against `Σᵢ conj(Aᵢⱼ) zᵢ`.
#[test]
fn two_thread_product_is_the_one_thread_product() {
    let mut rng = qscalar::random::SplitMix64::new(17);
    for (nrows, ncols) in [(20001, 20001), (19999, 20301)] {
        let mut triplets = TripletMatrix::<Quat<f64>>::new(nrows, ncols);
        let mut entries: Vec<(usize, usize, Quat<f64>)> = Vec::new();
        for j in 0..ncols {
            for _ in 0..8 {
                let mut value = [Quat::default()];
                rng.fill_symmetric(&mut value);
                let row = (rng.next_u64() % nrows as u64) as usize;
                triplets.push(row, j, value[0]).unwrap();
                entries.push((row, j, value[0]));
            }
        }
        let a = triplets.to_csc();
        assert!(
            a.nnz() * 4 >= 1 << 19,
            "the product must take the two-thread path"
        );
        let (mut x, mut z) = (vec![Quat::default(); ncols], vec![Quat::default(); nrows]);
        rng.fill_symmetric(&mut x);
        rng.fill_symmetric(&mut z);
        let (mut ax, mut ahz) = (vec![Quat::default(); nrows], vec![Quat::default(); ncols]);
        for &(row, col, value) in &entries {
            ax[row] += value * x[col];
            ahz[col] += value.conj() * z[row];
        }
        two_threads_agree(|x, y| a.mul_vec(x, y), &x, &ax);
        two_threads_agree(|z, y| a.adjoint_mul_vec(z, y), &z, &ahz);
    }
}

proptest! {
    /// For a Hermitian matrix the gathered `Aᴴ x` is the scattered `A x` up to rounding.
    #[test]
    fn hermitian_adjoint_product_is_the_product(
        (a, x) in hpd_matrix::<Quat<f64>>(1..40, 0.3)
            .prop_flat_map(|a| { let n = a.ncols(); (Just(a), vector::<Quat<f64>>(n)) })
    ) {
        let (mut ax, mut ahx) = (vec![Quat::default(); a.nrows()], vec![Quat::default(); a.nrows()]);
        a.mul_vec(&x, &mut ax).unwrap();
        a.adjoint_mul_vec(&x, &mut ahx).unwrap();
        assert_close(&ahx, &ax, TOL)?;
    }
}
