//! Every `SparseError` variant is produced by some bad input, as a typed error and never a
//! panic.

use qscalar::{Quat, Scalar};
use qsparse::{
    CholeskyError, DenseMatrix, SparseCholesky, SparseError, SparseMatrix, SparseVector,
    TripletMatrix,
};

type Q = Quat<f64>;

fn q(w: f64) -> Q {
    Quat::from_real(w)
}

fn csc(
    nrows: usize,
    ncols: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
    values: &[f64],
) -> Result<SparseMatrix<Q>, SparseError> {
    SparseMatrix::try_from_csc(
        nrows,
        ncols,
        col_ptr.to_vec(),
        row_idx.to_vec(),
        values.iter().copied().map(q).collect(),
    )
}

#[test]
fn index_out_of_bounds() {
    let mut t = TripletMatrix::<Q>::new(2, 3);
    let expected = |row, col| SparseError::IndexOutOfBounds {
        row,
        col,
        nrows: 2,
        ncols: 3,
    };
    assert_eq!(t.push(2, 0, q(1.0)), Err(expected(2, 0)));
    assert_eq!(t.push(0, 3, q(1.0)), Err(expected(0, 3)));
    assert_eq!(
        t.push(usize::MAX, usize::MAX, q(1.0)),
        Err(expected(usize::MAX, usize::MAX))
    );
    assert!(t.entries().is_empty());
    assert_eq!(csc(2, 3, &[0, 1, 1, 1], &[2], &[1.0]), Err(expected(2, 0)));
}

#[test]
fn non_finite() {
    let mut t = TripletMatrix::<Q>::new(2, 2);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let value = Quat::new(0.0, 0.0, bad, 0.0);
        assert_eq!(
            t.push(1, 0, value),
            Err(SparseError::NonFinite { row: 1, col: 0 })
        );
    }
    assert_eq!(
        csc(2, 2, &[0, 1, 2], &[0, 1], &[1.0, f64::NAN]),
        Err(SparseError::NonFinite { row: 1, col: 1 })
    );
}

#[test]
fn dimension_mismatch() {
    let a = SparseMatrix::<Q>::identity(3);
    let mut y = vec![Q::default(); 3];
    assert!(matches!(
        a.mul_vec(&[q(1.0); 2], &mut y),
        Err(SparseError::DimensionMismatch {
            expected: 3,
            found: 2,
            ..
        })
    ));
    assert!(matches!(
        a.adjoint_mul_vec(&[q(1.0); 3], &mut [Q::default(); 4]),
        Err(SparseError::DimensionMismatch {
            expected: 3,
            found: 4,
            ..
        })
    ));
    let b = SparseMatrix::<Q>::zeros(3, 4);
    assert!(matches!(
        SparseMatrix::linear_combination(q(1.0), &a, q(1.0), &b),
        Err(SparseError::DimensionMismatch {
            expected: 3,
            found: 4,
            ..
        })
    ));
    assert!(matches!(
        SparseMatrix::linear_combination(q(1.0), &a, q(1.0), &SparseMatrix::zeros(2, 3)),
        Err(SparseError::DimensionMismatch {
            expected: 3,
            found: 2,
            ..
        })
    ));
    assert!(matches!(
        csc(2, 2, &[0, 0], &[], &[]),
        Err(SparseError::DimensionMismatch {
            expected: 3,
            found: 2,
            ..
        })
    ));
    assert!(matches!(
        DenseMatrix::<Q>::from_column_major(2, 2, vec![q(1.0); 3]),
        Err(SparseError::DimensionMismatch {
            expected: 4,
            found: 3,
            ..
        })
    ));
    assert!(matches!(
        DenseMatrix::<Q>::zeros(2, 3).matmul(&DenseMatrix::zeros(2, 3)),
        Err(SparseError::DimensionMismatch {
            expected: 3,
            found: 2,
            ..
        })
    ));
}

#[test]
fn invalid_storage() {
    let bad = [
        // col_ptr does not start at 0
        csc(2, 2, &[1, 1, 1], &[0], &[1.0]),
        // col_ptr does not end at nnz
        csc(2, 2, &[0, 1, 1], &[0, 1], &[1.0, 1.0]),
        // row_idx and values differ in length
        csc(2, 2, &[0, 1, 1], &[0], &[1.0, 1.0]),
        // decreasing col_ptr
        csc(2, 2, &[0, 2, 1], &[0], &[1.0]),
        // decreasing col_ptr whose middle entry exceeds nnz
        csc(2, 3, &[0, 5, 1, 1], &[0], &[1.0]),
        // unsorted rows in a column
        csc(2, 1, &[0, 2], &[1, 0], &[1.0, 1.0]),
        // duplicate row in a column
        csc(2, 1, &[0, 2], &[1, 1], &[1.0, 1.0]),
    ];
    for (case, result) in bad.into_iter().enumerate() {
        assert!(
            matches!(result, Err(SparseError::InvalidStorage(_))),
            "case {case}: {result:?}"
        );
    }
}

/// Dimensions at the edge of `usize` are rejected, not overflowed.
#[test]
fn huge_dimensions() {
    assert!(matches!(
        csc(1, usize::MAX, &[], &[], &[]),
        Err(SparseError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        csc(1, usize::MAX, &[0], &[], &[]),
        Err(SparseError::DimensionMismatch { .. })
    ));
}

#[test]
fn dense_columns_of_the_wrong_length_or_not_finite() {
    let good = vec![q(1.0), q(0.0), q(2.0)];
    assert_eq!(
        SparseMatrix::from_dense_columns(3, &[good.clone(), vec![q(1.0); 2]]),
        Err(SparseError::DimensionMismatch {
            expected: 3,
            found: 2,
            context: "dense column length",
        })
    );
    let mut bad = good.clone();
    bad[1] = Quat::new(0.0, f64::NAN, 0.0, 0.0);
    assert_eq!(
        SparseMatrix::from_dense_columns(3, &[good.clone(), bad]),
        Err(SparseError::NonFinite { row: 1, col: 1 })
    );
    let m = SparseMatrix::from_dense_columns(3, &[good]).unwrap();
    assert_eq!((m.nrows(), m.ncols(), m.nnz()), (3, 1, 2));
    assert_eq!(m.col(0).0, &[0, 2]);
}

#[test]
fn sparse_right_hand_sides_out_of_range_or_malformed() {
    let a = SparseMatrix::from_diagonal(&[q(2.0), q(3.0), q(4.0)]);
    let chol = SparseCholesky::factorize(&a).unwrap();
    let mut work = chol.sparse_solve_workspace();
    let beyond = SparseVector {
        rows: vec![3],
        values: vec![q(1.0)],
    };
    assert_eq!(
        chol.solve_lower_sparse(&beyond, &mut work),
        Err(CholeskyError::RhsDimension {
            expected: 3,
            found: 4
        })
    );
    let malformed = SparseVector {
        rows: vec![0, 1],
        values: vec![q(1.0)],
    };
    assert!(matches!(
        chol.solve_lower_sparse(&malformed, &mut work),
        Err(CholeskyError::RhsDimension { .. })
    ));
    let other = SparseCholesky::factorize(&SparseMatrix::<Q>::identity(5)).unwrap();
    let good = SparseVector {
        rows: vec![1],
        values: vec![q(9.0)],
    };
    assert!(matches!(
        chol.solve_lower_sparse(&good, &mut other.sparse_solve_workspace()),
        Err(CholeskyError::RhsDimension { .. })
    ));
    // C⁻¹ (9 e₁) is 9/√3 at the place of row 1 in the factor's numbering, as the dense solve
    // says; the workspace is clean after the errors.
    let x = chol.solve_lower_sparse(&good, &mut work).unwrap();
    let mut dense = good.to_dense(3);
    chol.solve_lower_in_place(&mut dense).unwrap();
    assert_eq!(x.to_dense(3), dense);
    assert_eq!(x.rows.len(), 1);
    assert!((x.values[0].re() - 9.0 / 3f64.sqrt()).abs() < 1e-14);
}
