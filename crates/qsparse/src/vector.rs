//! Vector kernels in the workspace conventions: vectors form a right module, so coefficients
//! multiply on the right, and the inner product conjugates its first argument.

use num_traits::{Float, Zero};
use qscalar::Scalar;

/// `⟨x, y⟩ = Σᵢ conj(xᵢ) yᵢ`. Slices of unequal length are compared over the shorter one.
pub fn inner<T: Scalar>(x: &[T], y: &[T]) -> T {
    x.iter().zip(y).map(|(&a, &b)| a.conj() * b).sum()
}

/// `‖x‖ = sqrt(Σᵢ |xᵢ|²)`.
pub fn norm<T: Scalar>(x: &[T]) -> T::Real {
    x.iter().fold(T::Real::zero(), |s, v| s + v.abs2()).sqrt()
}

/// `y ← y + x c` (coefficient on the right, as in a Gram–Schmidt update `w −= v ⟨v, w⟩`).
pub fn axpy<T: Scalar>(y: &mut [T], x: &[T], c: T) {
    for (yi, &xi) in y.iter_mut().zip(x) {
        *yi += xi * c;
    }
}

/// `x ← x r` for a real `r`.
pub fn scale<T: Scalar>(x: &mut [T], r: T::Real) {
    for v in x {
        *v = v.scale(r);
    }
}
