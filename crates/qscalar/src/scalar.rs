//! The generic `Scalar` trait: what algorithms over `f32`, `f64`, `Complex<f32|f64>` and
//! `Quat<f32|f64>` need, written once.
//!
//! Algorithms written over [`Scalar`] must keep operand order: `a * b` and `b * a` differ for
//! quaternions ([`Scalar::IS_COMMUTATIVE`] is `false`). The conventions of the workspace
//! (docs/ARCHITECTURE.md, "Conventions") are: matrices act by left multiplication, vectors form a
//! right module, the inner product is `⟨x, y⟩ = Σ conj(xᵢ) yᵢ`, and Gram–Schmidt coefficients
//! multiply on the right.

use core::fmt::{Debug, Display, LowerExp};
use core::iter::Sum;
use core::ops::{Add, AddAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use num_complex::Complex;
use num_traits::{Float, One, Zero};

use crate::Quat;
use crate::blocks;

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
    impl<T> Sealed for num_complex::Complex<T> {}
    impl<T> Sealed for crate::Quat<T> {}
}

/// A scalar of one of the three real division algebras (ℝ, ℂ, ℍ) over `f32` or `f64`.
///
/// Sealed: [`Scalar::as_reals`] relies on every implementor being `#[repr(C)]` with exactly
/// [`Scalar::REAL_DIM`] components of type [`Scalar::Real`].
pub trait Scalar:
    sealed::Sealed
    + Copy
    + Send
    + Sync
    + Debug
    + PartialEq
    + Default
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + Zero
    + One
    + Sum
{
    /// The underlying real type.
    type Real: RealScalar;
    /// Number of real components: 1 (real), 2 (complex), 4 (quaternion).
    const REAL_DIM: usize;
    /// Size of the complex-adjoint block: 1 for real and complex, 2 for quaternions.
    const COMPLEX_DIM: usize;
    /// `false` for quaternions.
    const IS_COMMUTATIVE: bool;

    /// Conjugate (identity on reals).
    fn conj(self) -> Self;
    /// Real part.
    fn re(self) -> Self::Real;
    /// Squared modulus `|x|² = x x̄` (sum of the squared components).
    fn abs2(self) -> Self::Real;
    /// Modulus `|x|`.
    fn abs(self) -> Self::Real {
        self.abs2().sqrt()
    }
    /// Multiplication by a real, `x r` (reals commute with everything).
    fn scale(self, r: Self::Real) -> Self;
    /// Two-sided inverse `x⁻¹ = x̄ / |x|²`.
    fn inv(self) -> Self;
    /// Embeds a real.
    fn from_real(r: Self::Real) -> Self;
    /// Whether every component is finite.
    fn is_finite(self) -> bool;
    /// Writes the real left-multiplication block (`REAL_DIM × REAL_DIM`, row-major) into
    /// `out[..REAL_DIM²]`: the matrix of `v ↦ self · v` on the components of `v` (`L(q)` of
    /// docs/MATH.md, "The real-block representation", for quaternions, `[[a, −b], [b, a]]` for
    /// `a + bi`).
    fn real_block(self, out: &mut [Self::Real]);
    /// Writes the complex-adjoint block (`COMPLEX_DIM × COMPLEX_DIM`, row-major) into `out`:
    /// `χ(z₁ + z₂ j) = [[z₁, −z₂], [z̄₂, z̄₁]]` for quaternions, the number itself otherwise.
    fn complex_adjoint_block(self, out: &mut [Complex<Self::Real>]);
    /// Writes the image of a vector entry in the complex-adjoint embedding (`COMPLEX_DIM`
    /// values): `(z₁, z̄₂)` for a quaternion `z₁ + z₂ j`.
    fn to_complex_column(self, out: &mut [Complex<Self::Real>]);
    /// Inverse of [`Scalar::to_complex_column`]; for a real scalar the imaginary part is dropped.
    fn from_complex_column(c: &[Complex<Self::Real>]) -> Self;

    /// Reinterprets `n` scalars as `n · REAL_DIM` reals (components interleaved per entry, the
    /// real-block vector layout of docs/MATH.md, "The real-block representation"). Zero-copy.
    fn as_reals(s: &[Self]) -> &[Self::Real] {
        // SAFETY: the trait is sealed; every implementor is `#[repr(C)]` (f32/f64 trivially,
        // `num_complex::Complex` and `Quat` by declaration) and consists of exactly `REAL_DIM`
        // fields of type `Self::Real`, with the alignment of `Self::Real` and no padding.
        unsafe {
            core::slice::from_raw_parts(s.as_ptr().cast::<Self::Real>(), s.len() * Self::REAL_DIM)
        }
    }

    /// Mutable version of [`Scalar::as_reals`].
    fn as_reals_mut(s: &mut [Self]) -> &mut [Self::Real] {
        // SAFETY: as in `as_reals`; the exclusive borrow is carried over.
        unsafe {
            core::slice::from_raw_parts_mut(
                s.as_mut_ptr().cast::<Self::Real>(),
                s.len() * Self::REAL_DIM,
            )
        }
    }
}

/// `f32` or `f64`.
pub trait RealScalar: Scalar<Real = Self> + Float + PartialOrd + Display + LowerExp {
    /// Converts from `f64` (rounding for `f32`).
    fn from_f64(x: f64) -> Self;
    /// Converts to `f64`.
    fn to_f64(self) -> f64;
}

macro_rules! impl_real {
    ($($t:ty),*) => {$(
        impl Scalar for $t {
            type Real = $t;
            const REAL_DIM: usize = 1;
            const COMPLEX_DIM: usize = 1;
            const IS_COMMUTATIVE: bool = true;
            #[inline(always)]
            fn conj(self) -> Self { self }
            #[inline(always)]
            fn re(self) -> Self { self }
            #[inline(always)]
            fn abs2(self) -> Self { self * self }
            #[inline(always)]
            fn abs(self) -> Self { <$t>::abs(self) }
            #[inline(always)]
            fn scale(self, r: Self) -> Self { self * r }
            #[inline(always)]
            fn inv(self) -> Self { 1.0 / self }
            #[inline(always)]
            fn from_real(r: Self) -> Self { r }
            #[inline(always)]
            fn is_finite(self) -> bool { <$t>::is_finite(self) }
            fn real_block(self, out: &mut [Self]) { out[0] = self; }
            fn complex_adjoint_block(self, out: &mut [Complex<Self>]) { out[0] = Complex::new(self, 0.0); }
            fn to_complex_column(self, out: &mut [Complex<Self>]) { out[0] = Complex::new(self, 0.0); }
            fn from_complex_column(c: &[Complex<Self>]) -> Self { c[0].re }
        }

        impl RealScalar for $t {
            #[inline(always)]
            fn from_f64(x: f64) -> Self { x as $t }
            #[inline(always)]
            fn to_f64(self) -> f64 { self as f64 }
        }

        impl Scalar for Complex<$t> {
            type Real = $t;
            const REAL_DIM: usize = 2;
            const COMPLEX_DIM: usize = 1;
            const IS_COMMUTATIVE: bool = true;
            #[inline(always)]
            fn conj(self) -> Self { Complex::conj(&self) }
            #[inline(always)]
            fn re(self) -> $t { self.re }
            #[inline(always)]
            fn abs2(self) -> $t { self.norm_sqr() }
            #[inline(always)]
            fn scale(self, r: $t) -> Self { Complex::new(self.re * r, self.im * r) }
            #[inline(always)]
            fn inv(self) -> Self { Complex::conj(&self).unscale(self.norm_sqr()) }
            #[inline(always)]
            fn from_real(r: $t) -> Self { Complex::new(r, 0.0) }
            #[inline(always)]
            fn is_finite(self) -> bool { Complex::is_finite(self) }
            fn real_block(self, out: &mut [$t]) {
                out[..4].copy_from_slice(&[self.re, -self.im, self.im, self.re]);
            }
            fn complex_adjoint_block(self, out: &mut [Complex<$t>]) { out[0] = self; }
            fn to_complex_column(self, out: &mut [Complex<$t>]) { out[0] = self; }
            fn from_complex_column(c: &[Complex<$t>]) -> Self { c[0] }
        }

        impl Scalar for Quat<$t> {
            type Real = $t;
            const REAL_DIM: usize = 4;
            const COMPLEX_DIM: usize = 2;
            const IS_COMMUTATIVE: bool = false;
            #[inline(always)]
            fn conj(self) -> Self { Quat::conj(self) }
            #[inline(always)]
            fn re(self) -> $t { self.w }
            #[inline(always)]
            fn abs2(self) -> $t { self.norm_sqr() }
            #[inline(always)]
            fn abs(self) -> $t { self.norm() }
            #[inline(always)]
            fn scale(self, r: $t) -> Self { self * r }
            #[inline(always)]
            fn inv(self) -> Self { Quat::inv(self) }
            #[inline(always)]
            fn from_real(r: $t) -> Self { Quat::from_real(r) }
            #[inline(always)]
            fn is_finite(self) -> bool { Quat::is_finite(self) }
            fn real_block(self, out: &mut [$t]) {
                let b = blocks::left_block(self);
                for (row, chunk) in b.iter().zip(out.chunks_exact_mut(4)) {
                    chunk.copy_from_slice(row);
                }
            }
            fn complex_adjoint_block(self, out: &mut [Complex<$t>]) {
                let b = blocks::complex_adjoint(self);
                out[..4].copy_from_slice(&[b[0][0], b[0][1], b[1][0], b[1][1]]);
            }
            fn to_complex_column(self, out: &mut [Complex<$t>]) {
                out[..2].copy_from_slice(&blocks::complex_column(self));
            }
            fn from_complex_column(c: &[Complex<$t>]) -> Self {
                blocks::from_complex_column([c[0], c[1]])
            }
        }
    )*};
}
impl_real!(f32, f64);
