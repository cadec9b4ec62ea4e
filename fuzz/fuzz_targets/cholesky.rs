//! Fuzz target: small arbitrary quaternion matrices, Hermitian-ised or not, with NaN, ∞, zero,
//! huge and moderate entries → `SparseCholesky::factorize` then `solve`. The outcome must be
//! `Ok` (with a finite solution when every value is moderate) or a typed `CholeskyError`,
//! never a panic.

#![no_main]

use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use qsparse::{CholeskyError, SparseCholesky, TripletMatrix};

#[path = "quaternion_matrices.rs"]
mod quaternion_matrices;
use quaternion_matrices::{Q, make_dominant, push_entries, quat};

fn run(u: &mut Unstructured) -> Result<()> {
    let n = u.int_in_range(0..=8usize)?;
    let ncols = if u.ratio(1, 16)? { n + 1 } else { n };
    let hermitise = u.arbitrary::<bool>()?;
    let mut moderate = true;
    let mut t = TripletMatrix::new(n, ncols);
    push_entries(u, &mut t, n, 40, hermitise, &mut moderate)?;
    if hermitise && u.arbitrary::<bool>()? {
        // Positive definite if every value is finite, so that the factor-and-solve path is
        // reached often.
        make_dominant(&mut t, n);
    }
    let mut a = t.to_csc();
    if !moderate && a.nnz() > 0 {
        // Plant one raw value (possibly NaN/∞) to check the factorisation's own validation.
        let k = u.int_in_range(0..=a.nnz() - 1)?;
        a.values_mut()[k] = quat(u, &mut moderate)?;
        moderate = false;
    }

    let chol = match SparseCholesky::factorize(&a) {
        Ok(chol) => chol,
        Err(CholeskyError::NotSquare { nrows, ncols }) => {
            assert!(nrows != ncols);
            return Ok(());
        }
        Err(CholeskyError::NotPositiveDefinite { index, .. }) => {
            assert!(index < n);
            return Ok(());
        }
        Err(CholeskyError::NonFinite { row, col }) => {
            assert!(row >= col && !a.get(row, col).is_finite());
            return Ok(());
        }
        Err(e) => panic!("unexpected error: {e}"),
    };
    let mut rhs_moderate = true;
    let b = (0..n)
        .map(|_| quat(u, &mut rhs_moderate))
        .collect::<Result<Vec<_>>>()?;
    let rhs_finite = b.iter().all(|v| v.is_finite());
    let x = chol.solve(&b).expect("right length");
    if moderate && rhs_moderate {
        assert!(x.iter().all(|v| v.is_finite()), "non-finite solution {x:?}");
    }
    if rhs_finite {
        let mut many = [b.clone(), b].concat();
        chol.solve_many_in_place(&mut many, 2)
            .expect("right length");
    }
    assert!(matches!(
        chol.solve(&vec![Q::default(); n + 1]),
        Err(CholeskyError::RhsDimension { .. })
    ));
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
