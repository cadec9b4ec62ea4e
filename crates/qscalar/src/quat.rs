//! The quaternion type `Quat<T>` and its arithmetic.
//!
//! `q = w + x i + y j + z k`, stored `(w, x, y, z)`, with Hamilton's rules
//! `i² = j² = k² = ijk = −1`. Multiplication does not commute, so there is deliberately
//! no `Div` between quaternions: use [`Quat::right_div`] (`p q⁻¹`) or [`Quat::left_div`]
//! (`q⁻¹ p`), or [`Quat::inv`] explicitly.

use core::fmt;
use core::iter::Sum;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use num_complex::Complex;
use num_traits::{Float, One, Zero};

/// A quaternion `w + x i + y j + z k` over the real type `T`.
///
/// The layout is `#[repr(C)]` with the components in the order `w, x, y, z`, so a slice of `n`
/// quaternions is a slice of `4n` reals in the vertex-interleaved layout of the real-block
/// embedding (docs/MATH.md, "The real-block representation"). [`crate::Scalar::as_reals`] performs
/// that reinterpretation.
#[repr(C)]
#[derive(Copy, Clone, Default, PartialEq)]
pub struct Quat<T> {
    /// Real (scalar) part.
    pub w: T,
    /// Coefficient of `i`.
    pub x: T,
    /// Coefficient of `j`.
    pub y: T,
    /// Coefficient of `k`.
    pub z: T,
}

impl<T> Quat<T> {
    /// `w + x i + y j + z k`.
    pub const fn new(w: T, x: T, y: T, z: T) -> Self {
        Self { w, x, y, z }
    }
}

impl<T: Float> Quat<T> {
    /// The real quaternion `r + 0i + 0j + 0k`.
    pub fn from_real(r: T) -> Self {
        Self::new(r, T::zero(), T::zero(), T::zero())
    }

    /// The imaginary quaternion `v₀ i + v₁ j + v₂ k` that represents the point `v ∈ R³`.
    pub fn from_vector(v: [T; 3]) -> Self {
        Self::new(T::zero(), v[0], v[1], v[2])
    }

    /// The unit `i`.
    pub fn i() -> Self {
        Self::new(T::zero(), T::one(), T::zero(), T::zero())
    }

    /// The unit `j`.
    pub fn j() -> Self {
        Self::new(T::zero(), T::zero(), T::one(), T::zero())
    }

    /// The unit `k`.
    pub fn k() -> Self {
        Self::new(T::zero(), T::zero(), T::zero(), T::one())
    }

    /// The scalar part `w`.
    pub fn scalar_part(self) -> T {
        self.w
    }

    /// The vector (imaginary) part `(x, y, z)`.
    pub fn vector_part(self) -> [T; 3] {
        [self.x, self.y, self.z]
    }

    /// The components `[w, x, y, z]`.
    pub fn to_array(self) -> [T; 4] {
        [self.w, self.x, self.y, self.z]
    }

    /// Builds `a[0] + a[1] i + a[2] j + a[3] k`.
    pub fn from_array(a: [T; 4]) -> Self {
        Self::new(a[0], a[1], a[2], a[3])
    }

    /// Conjugate `q̄ = w − x i − y j − z k`; `conj(pq) = conj(q) conj(p)`.
    #[inline(always)]
    pub fn conj(self) -> Self {
        Self::new(self.w, -self.x, -self.y, -self.z)
    }

    /// `|q|² = q q̄ = w² + x² + y² + z²`.
    #[inline(always)]
    pub fn norm_sqr(self) -> T {
        self.w * self.w + self.x * self.x + self.y * self.y + self.z * self.z
    }

    /// `|q| = sqrt(w² + x² + y² + z²)` (plain square root of the sum, no hypot chain: it is on
    /// hot paths, and inputs here are far from overflow).
    #[inline(always)]
    pub fn norm(self) -> T {
        self.norm_sqr().sqrt()
    }

    /// Two-sided inverse `q⁻¹ = q̄ / |q|²`. The inverse of zero has non-finite components.
    #[inline(always)]
    pub fn inv(self) -> Self {
        self.conj() / self.norm_sqr()
    }

    /// Right division `p q⁻¹` (`self = p`), the solution `x` of `x q = p`.
    pub fn right_div(self, q: Self) -> Self {
        self * q.inv()
    }

    /// Left division `q⁻¹ p` (`self = p`), the solution `x` of `q x = p`.
    pub fn left_div(self, q: Self) -> Self {
        q.inv() * self
    }

    /// `q / |q|`. A zero quaternion gives non-finite components; see [`Quat::try_normalize`].
    pub fn normalize(self) -> Self {
        self / self.norm()
    }

    /// `q / |q|`, or `None` when `|q| <= min_norm`.
    pub fn try_normalize(self, min_norm: T) -> Option<Self> {
        let n = self.norm();
        (n > min_norm).then(|| self / n)
    }

    /// Euclidean inner product of the component 4-vectors, `Re(p̄ q)`.
    pub fn dot(self, q: Self) -> T {
        self.w * q.w + self.x * q.x + self.y * q.y + self.z * q.z
    }

    /// Exponential `e^q = e^w (cos|v| + v/|v| · sin|v|)` with `v` the vector part.
    pub fn exp(self) -> Self {
        let v = self.vector_part();
        let angle = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let scale = self.w.exp();
        // sin(θ)/θ → 1 as θ → 0; below ε the first Taylor term is exact in floating point.
        let sinc = if angle > T::epsilon() {
            angle.sin() / angle
        } else {
            T::one()
        };
        Self::new(
            scale * angle.cos(),
            scale * sinc * v[0],
            scale * sinc * v[1],
            scale * sinc * v[2],
        )
    }

    /// Principal logarithm `ln q = ln|q| + v/|v| · atan2(|v|, w)` (vector part of norm in
    /// `[0, π]`), so that `exp(ln q) = q` for every non-zero `q`. For a negative real `q` the
    /// vector part is `π i`.
    ///
    /// Implemented here rather than delegated: quaternion-core 0.6's `ln` uses `atan(|v|/w)`,
    /// which is only the principal branch for `w > 0`.
    pub fn ln(self) -> Self {
        let v = self.vector_part();
        let vnorm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let angle = vnorm.atan2(self.w);
        let log_norm = self.norm().ln();
        if vnorm > T::zero() {
            let c = angle / vnorm;
            Self::new(log_norm, c * v[0], c * v[1], c * v[2])
        } else {
            Self::new(log_norm, angle, T::zero(), T::zero())
        }
    }

    /// Real power `q^t = exp(t ln q)`; `0^t = 0` for `t > 0`.
    pub fn powf(self, t: T) -> Self {
        if self.norm_sqr().is_zero() && t > T::zero() {
            return Self::from_real(T::zero());
        }
        (self.ln() * t).exp()
    }

    /// Rotates the 3-vector `v` by the unit quaternion `self = r`: returns the vector part of
    /// `r v r̄`. For non-unit `r` the result is additionally scaled by `|r|²`.
    pub fn rotate_vector(self, v: [T; 3]) -> [T; 3] {
        (self * Self::from_vector(v) * self.conj()).vector_part()
    }

    /// The complex pair `(z₁, z₂)` with `q = z₁ + z₂ j`, `z₁ = w + x i`, `z₂ = y + z i`.
    pub fn to_complex_pair(self) -> (Complex<T>, Complex<T>) {
        (Complex::new(self.w, self.x), Complex::new(self.y, self.z))
    }

    /// `q = z₁ + z₂ j`; the inverse of [`Quat::to_complex_pair`].
    pub fn from_complex_pair(z1: Complex<T>, z2: Complex<T>) -> Self {
        Self::new(z1.re, z1.im, z2.re, z2.im)
    }

    /// Whether every component is finite.
    pub fn is_finite(self) -> bool {
        self.w.is_finite() && self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

impl<T: fmt::Debug> fmt::Debug for Quat<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "Quat({:?}, {:?}, {:?}, {:?})",
            self.w, self.x, self.y, self.z
        )
    }
}

impl<T: fmt::Display> fmt::Display for Quat<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} + {}i + {}j + {}k", self.w, self.x, self.y, self.z)
    }
}

impl<T: Float> From<quaternion_core::Quaternion<T>> for Quat<T> {
    fn from((w, [x, y, z]): quaternion_core::Quaternion<T>) -> Self {
        Self::new(w, x, y, z)
    }
}

impl<T: Float> From<Quat<T>> for quaternion_core::Quaternion<T> {
    fn from(q: Quat<T>) -> Self {
        (q.w, [q.x, q.y, q.z])
    }
}

impl<T: Float> Add for Quat<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        Self::new(self.w + b.w, self.x + b.x, self.y + b.y, self.z + b.z)
    }
}

impl<T: Float> Sub for Quat<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        Self::new(self.w - b.w, self.x - b.x, self.y - b.y, self.z - b.z)
    }
}

impl<T: Float> Neg for Quat<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.w, -self.x, -self.y, -self.z)
    }
}

/// The Hamilton product `(s₁, v₁)(s₂, v₂) = (s₁s₂ − v₁·v₂, s₁v₂ + s₂v₁ + v₁×v₂)`.
impl<T: Float> Mul for Quat<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = self;
        Self::new(
            a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
        )
    }
}

/// Multiplication by a real (which commutes with every quaternion).
impl<T: Float> Mul<T> for Quat<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, r: T) -> Self {
        Self::new(self.w * r, self.x * r, self.y * r, self.z * r)
    }
}

/// Division by a real.
impl<T: Float> Div<T> for Quat<T> {
    type Output = Self;
    #[inline(always)]
    fn div(self, r: T) -> Self {
        Self::new(self.w / r, self.x / r, self.y / r, self.z / r)
    }
}

macro_rules! real_times_quat {
    ($($t:ty),*) => {$(
        /// Multiplication of a quaternion by a real on the left.
        impl Mul<Quat<$t>> for $t {
            type Output = Quat<$t>;
            #[inline(always)]
            fn mul(self, q: Quat<$t>) -> Quat<$t> {
                q * self
            }
        }
    )*};
}
real_times_quat!(f32, f64);

impl<T: Float> AddAssign for Quat<T> {
    #[inline(always)]
    fn add_assign(&mut self, b: Self) {
        *self = *self + b;
    }
}

impl<T: Float> SubAssign for Quat<T> {
    #[inline(always)]
    fn sub_assign(&mut self, b: Self) {
        *self = *self - b;
    }
}

/// `a *= b` means `a = a b` (multiplication on the right).
impl<T: Float> MulAssign for Quat<T> {
    #[inline(always)]
    fn mul_assign(&mut self, b: Self) {
        *self = *self * b;
    }
}

impl<T: Float> MulAssign<T> for Quat<T> {
    #[inline(always)]
    fn mul_assign(&mut self, r: T) {
        *self = *self * r;
    }
}

impl<T: Float> DivAssign<T> for Quat<T> {
    #[inline(always)]
    fn div_assign(&mut self, r: T) {
        *self = *self / r;
    }
}

impl<T: Float> Zero for Quat<T> {
    fn zero() -> Self {
        Self::from_real(T::zero())
    }
    fn is_zero(&self) -> bool {
        self.w.is_zero() && self.x.is_zero() && self.y.is_zero() && self.z.is_zero()
    }
}

impl<T: Float> One for Quat<T> {
    fn one() -> Self {
        Self::from_real(T::one())
    }
}

impl<T: Float> Sum for Quat<T> {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::zero(), |a, b| a + b)
    }
}
