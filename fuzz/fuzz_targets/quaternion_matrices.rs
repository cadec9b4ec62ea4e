//! Arbitrary small quaternion matrices for the `cholesky` and `pencil` targets: values from
//! moderate to NaN, random entries (Hermitian-ised or not), strict diagonal dominance.

use libfuzzer_sys::arbitrary::{Result, Unstructured};
use qscalar::Quat;
use qsparse::TripletMatrix;

pub type Q = Quat<f64>;

/// A component value: NaN, ±∞ or raw bits one time in 32 each, otherwise a multiple of 1/16
/// in ±2048; `moderate` is cleared when it is not one of the latter.
pub fn component(u: &mut Unstructured, moderate: &mut bool) -> Result<f64> {
    Ok(match u.int_in_range(0..=31u8)? {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => f64::NEG_INFINITY,
        3 | 4 => {
            *moderate = false;
            f64::from_bits(u.arbitrary()?)
        }
        _ => f64::from(u.arbitrary::<i16>()? >> 4) / 16.0,
    })
    .inspect(|v| *moderate &= v.is_finite())
}

pub fn quat(u: &mut Unstructured, moderate: &mut bool) -> Result<Q> {
    let mut c = [0.0; 4];
    for v in &mut c {
        *v = component(u, moderate)?;
    }
    Ok(Quat::from_array(c))
}

/// Pushes up to `most` random entries into the leading `n × n` block of `t`, with their
/// mirrors `(j, i, conj)` and real diagonals if `hermitise`. Non-finite values, which the
/// assembly rejects, are pushed as zero (plant them through `values_mut` instead).
pub fn push_entries(
    u: &mut Unstructured,
    t: &mut TripletMatrix<Q>,
    n: usize,
    most: usize,
    hermitise: bool,
    moderate: &mut bool,
) -> Result<()> {
    for _ in 0..u.int_in_range(0..=most)? {
        if n == 0 {
            break;
        }
        let (i, j) = (u.int_in_range(0..=n - 1)?, u.int_in_range(0..=n - 1)?);
        let mut v = quat(u, moderate)?;
        if i == j && hermitise {
            v = Quat::from_real(v.w);
        }
        let finite = if v.is_finite() { v } else { Q::default() };
        t.push(i, j, finite).expect("in range and finite");
        if hermitise && i != j {
            t.push(j, i, finite.conj()).expect("in range and finite");
        }
    }
    Ok(())
}

/// Adds `1 + Σⱼ |tᵢⱼ|` to every diagonal entry of the `n × n` matrix `t`: strictly diagonally
/// dominant, hence positive definite if it is Hermitian with finite values. Returns `false`
/// if a row sum overflowed (that row is left as it is).
pub fn make_dominant(t: &mut TripletMatrix<Q>, n: usize) -> bool {
    let mut row_sums = vec![1.0; n];
    for &(i, _, v) in t.entries() {
        row_sums[i] += v.norm();
    }
    let mut all = true;
    for (i, &d) in row_sums.iter().enumerate() {
        if d.is_finite() {
            t.push(i, i, Quat::from_real(d))
                .expect("in range and finite");
        } else {
            all = false;
        }
    }
    all
}
