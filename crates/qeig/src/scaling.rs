//! Scaling by powers of two of matrices whose entries are far from unit size, as LAPACK's
//! `dsyev` scales a matrix whose norm is outside its safe range: the norms of this crate are
//! plain square roots of sums of squares (fast, and exact enough in range), which overflow
//! from about `1e154` and underflow below `1e−154`. A power of two scales exactly, so the
//! results are scaled back without rounding.

/// Largest component magnitude, as a binary exponent, within which (`2^±SAFE_EXPONENT`) a
/// matrix is used as given.
const SAFE_EXPONENT: i32 = 100;

/// `maxᵢ |xᵢ|` (0 for an empty slice).
pub(crate) fn largest_magnitude(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |l, v| l.max(v.abs()))
}

/// The power of two (of four if `even`, so that its square root is exact) that brings the
/// largest of `reals` in magnitude into `[½, 1)`; `1` if they are all zero or the largest is
/// within `2^±100` (any matrix of a mesh in reasonable units, which is then used unchanged).
pub(crate) fn unit_range_factor(reals: &[f64], even: bool) -> f64 {
    let largest = largest_magnitude(reals);
    if largest == 0.0 || !largest.is_finite() {
        return 1.0;
    }
    // largest = f · 2^e with f in [½, 1).
    let e = largest.log2().floor() as i32 + 1;
    if e.abs() <= SAFE_EXPONENT {
        return 1.0;
    }
    // A factor above 2^1022 is not representable: a matrix of subnormals only comes up to
    // 2^−52 at least, which is in range.
    let e = e.max(-1022);
    let e = if even { e + e.rem_euclid(2) } else { e };
    // In two halves: 2^−1024 itself is not a normal number.
    2f64.powi(-e / 2) * 2f64.powi(-e + e / 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factors_are_powers_of_two_into_the_unit_range() {
        assert_eq!(unit_range_factor(&[], false), 1.0);
        assert_eq!(unit_range_factor(&[0.0, -0.0], false), 1.0);
        assert_eq!(unit_range_factor(&[3.0, -1e20], false), 1.0);
        for (largest, even) in [
            (1e200, false),
            (-1e200, true),
            (1e-200, false),
            (3e-300, true),
        ] {
            let f = unit_range_factor(&[largest / 3.0, largest], even);
            let scaled = (largest * f).abs();
            assert!((0.25..1.0).contains(&scaled), "{largest:e} → {scaled}");
            assert_eq!(f.log2().fract(), 0.0, "a power of two");
            if even {
                assert_eq!((f.log2() as i64) % 2, 0, "a power of four");
            }
        }
        // Subnormal and near-overflow extremes stay finite and nonzero.
        let subnormal = unit_range_factor(&[5e-324], false);
        assert!(subnormal.is_finite() && 5e-324 * subnormal >= 2f64.powi(-SAFE_EXPONENT));
        assert!(unit_range_factor(&[f64::MAX], true) > 0.0);
    }
}
