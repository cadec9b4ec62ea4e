//! Fuzz target: small arbitrary quaternion matrices, Hermitian-ised or not, with NaN, ∞, zero,
//! huge and moderate entries → `SparseCholesky::factorize` then `solve`. The outcome must be
//! `Ok` (with a finite solution when every value is moderate) or a typed `CholeskyError`,
//! never a panic.

#![no_main]

use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use qscalar::Quat;
use qsparse::{CholeskyError, SparseCholesky, TripletMatrix};

type Q = Quat<f64>;

/// A component value; `moderate` is cleared when it is not a multiple of 1/16 in ±2048.
fn component(u: &mut Unstructured, moderate: &mut bool) -> Result<f64> {
    Ok(match u.int_in_range(0..=15u8)? {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => f64::NEG_INFINITY,
        3 => {
            *moderate = false;
            f64::from_bits(u.arbitrary()?)
        }
        _ => f64::from(u.arbitrary::<i16>()? >> 4) / 16.0,
    })
    .inspect(|v| *moderate &= v.is_finite())
}

fn quat(u: &mut Unstructured, moderate: &mut bool) -> Result<Q> {
    let mut c = [0.0; 4];
    for v in &mut c {
        *v = component(u, moderate)?;
    }
    Ok(Quat::from_array(c))
}

fn run(u: &mut Unstructured) -> Result<()> {
    let n = u.int_in_range(0..=8usize)?;
    let ncols = if u.ratio(1, 16)? { n + 1 } else { n };
    let hermitise = u.arbitrary::<bool>()?;
    let mut moderate = true;
    let mut t = TripletMatrix::new(n, ncols);
    for _ in 0..u.int_in_range(0..=40)? {
        if n == 0 {
            break;
        }
        let (i, j) = (u.int_in_range(0..=n - 1)?, u.int_in_range(0..=n - 1)?);
        let mut v = quat(u, &mut moderate)?;
        if i == j && hermitise {
            v = Quat::from_real(v.w);
        }
        // Non-finite values are rejected by the assembly; put them in through `values_mut`
        // below so that the factorisation sees them.
        let finite = if v.is_finite() { v } else { Q::default() };
        t.push(i, j, finite).expect("in range and finite");
        if hermitise && i != j {
            t.push(j, i, finite.conj()).expect("in range and finite");
        }
    }
    if hermitise && u.arbitrary::<bool>()? {
        // Make it strictly diagonally dominant (positive definite if every value is finite),
        // so that the factor-and-solve path is reached often.
        let mut row_sums = vec![1.0; n];
        for &(i, _, v) in t.entries() {
            row_sums[i] += v.norm();
        }
        for (i, &d) in row_sums.iter().enumerate() {
            // A sum of huge values can overflow; such a row is left as it is.
            if d.is_finite() {
                t.push(i, i, Quat::from_real(d))
                    .expect("in range and finite");
            }
        }
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
