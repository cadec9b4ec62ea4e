//! Fuzz target: arbitrary bytes → dimensions, `Quat<f64>` triplets (NaN, ∞, huge indices) and
//! raw CSC arrays → `TripletMatrix::push` / `to_csc` and `SparseMatrix::try_from_csc`. Every
//! outcome must be a value or a typed `SparseError`, never a panic; every matrix produced must
//! satisfy the CSC invariants and survive the products and algebra of `qsparse`.

#![no_main]

use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use qscalar::Quat;
use qsparse::{SparseError, SparseMatrix, TripletMatrix};

type Q = Quat<f64>;

/// Assembly allocates `O(ncols + nnz)`; dimensions above this are only used with `push`.
const MAX_ASSEMBLED_COLS: usize = 1 << 12;

/// Mostly small (so that entries collide and duplicates are summed), sometimes any `usize`.
fn size(u: &mut Unstructured) -> Result<usize> {
    if u.ratio(1, 8)? {
        u.arbitrary()
    } else {
        u.int_in_range(0..=12)
    }
}

/// Any bit pattern: NaN, ±∞, subnormals, huge and tiny values.
fn quat(u: &mut Unstructured) -> Result<Q> {
    let mut c = [0.0; 4];
    for v in &mut c {
        *v = f64::from_bits(u.arbitrary()?);
    }
    Ok(Quat::from_array(c))
}

fn assemble(u: &mut Unstructured) -> Result<()> {
    let (nrows, ncols) = (size(u)?, size(u)?);
    let mut t = TripletMatrix::new(nrows, ncols);
    let mut accepted = 0;
    while !u.is_empty() && accepted < 64 {
        let (row, col, value) = (size(u)?, size(u)?, quat(u)?);
        match t.push(row, col, value) {
            Ok(()) => {
                assert!(row < nrows && col < ncols && value.is_finite());
                accepted += 1;
            }
            Err(SparseError::IndexOutOfBounds { .. }) => assert!(row >= nrows || col >= ncols),
            Err(SparseError::NonFinite { .. }) => assert!(!value.is_finite()),
            Err(e) => panic!("unexpected error from push: {e}"),
        }
    }
    assert_eq!(t.entries().len(), accepted);
    if ncols <= MAX_ASSEMBLED_COLS {
        let a = t.to_csc();
        let mut pattern: Vec<_> = t.entries().iter().map(|&(r, c, _)| (c, r)).collect();
        pattern.sort_unstable();
        pattern.dedup();
        let stored: Vec<_> = a.triplets().map(|(r, c, _)| (c, r)).collect();
        assert_eq!(stored, pattern, "one entry per distinct index, sorted");
        // Finite duplicates can overflow to ±∞ when summed: the only way validation may fail.
        match SparseMatrix::try_from_csc(
            nrows,
            ncols,
            a.col_ptr().to_vec(),
            a.row_idx().to_vec(),
            a.values().to_vec(),
        ) {
            Ok(b) => {
                assert_eq!(b, a);
                exercise(&a, true);
            }
            Err(SparseError::NonFinite { .. }) => exercise(&a, false),
            Err(e) => panic!("to_csc produced invalid storage: {e}"),
        }
    }
    Ok(())
}

fn from_raw_csc(u: &mut Unstructured) -> Result<()> {
    let (nrows, ncols) = (size(u)?, size(u)?);
    let len = |u: &mut Unstructured| u.int_in_range(0..=16usize);
    let col_ptr = (0..len(u)?).map(|_| size(u)).collect::<Result<Vec<_>>>()?;
    let row_idx = (0..len(u)?).map(|_| size(u)).collect::<Result<Vec<_>>>()?;
    let values = (0..len(u)?).map(|_| quat(u)).collect::<Result<Vec<_>>>()?;
    if let Ok(a) = SparseMatrix::try_from_csc(nrows, ncols, col_ptr, row_idx, values) {
        assert_eq!(a.col_ptr().len(), ncols + 1);
        assert!(a.triplets().all(|(r, _, v)| r < nrows && v.is_finite()));
        if ncols <= MAX_ASSEMBLED_COLS && nrows <= MAX_ASSEMBLED_COLS {
            exercise(&a, true);
        }
    }
    Ok(())
}

/// Products, adjoint and algebra: results or typed errors, never panics. The exact identities
/// are checked when every value is finite (sums of infinities can be NaN).
fn exercise(a: &SparseMatrix<Q>, finite: bool) {
    if a.nrows() > MAX_ASSEMBLED_COLS {
        return;
    }
    let x = vec![Quat::new(1.0, -0.5, 0.25, 2.0); a.ncols()];
    let mut y = vec![Q::default(); a.nrows()];
    a.mul_vec(&x, &mut y).expect("dimensions fit");
    let mut z = vec![Q::default(); a.ncols()];
    a.adjoint_mul_vec(&y, &mut z).expect("dimensions fit");
    assert!(a.mul_vec(&y, &mut z).is_err() || a.nrows() == a.ncols());
    let adjoint = a.adjoint();
    assert!(!finite || adjoint.adjoint() == *a);
    let sum =
        SparseMatrix::linear_combination(Quat::from_real(1.0), a, Q::i(), a).expect("same shape");
    assert_eq!(sum.nnz(), a.nnz());
    let _ = a.hermitian_defect();
    let _ = a.is_hermitian(1e-12);
    if a.nrows() > 0 {
        let _ = a.row(a.nrows() - 1);
    }
}

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let _ = if u.arbitrary::<bool>().unwrap_or(false) {
        from_raw_csc(&mut u)
    } else {
        assemble(&mut u)
    };
});
