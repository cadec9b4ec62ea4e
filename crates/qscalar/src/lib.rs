//! # qscalar
//!
//! The scalar layer of dirac-spectra: the quaternion type [`Quat`], the generic [`Scalar`]
//! trait implemented for `f32`, `f64`, `Complex<f32|f64>` and `Quat<f32|f64>`, and the real
//! 4×4 left/right-multiplication blocks and complex 2×2 adjoint of a quaternion ([`blocks`]).
//! With the `proptest-support` feature (off by default), `strategies` exports proptest
//! strategies for reals, complex numbers and quaternions.
//!
//! Conventions (docs/ARCHITECTURE.md, "Conventions"): `q = w + x i + y j + z k` is stored
//! `(w, x, y, z)`; points of R³ are imaginary quaternions; matrices act on vectors by left
//! multiplication and vectors form a right module, so scalar coefficients multiply vectors on the
//! right.
//!
//! ```
//! use qscalar::{Quat, Scalar};
//! let (i, j, k) = (Quat::<f64>::i(), Quat::j(), Quat::k());
//! assert_eq!(i * j, k);
//! assert_eq!(j * i, -k); // quaternions do not commute
//! let q = Quat::new(1.0, 2.0, -1.0, 0.5);
//! assert!((q * q.inv() - Quat::from_real(1.0)).abs() < 1e-15);
//! ```

pub mod blocks;
mod quat;
pub mod random;
mod scalar;
#[cfg(feature = "proptest-support")]
pub mod strategies;

pub use quat::Quat;
pub use scalar::{RealScalar, Scalar};

/// Re-export of the complex type used throughout (the same type as `faer::c64` for `f64`).
pub use num_complex::Complex;
