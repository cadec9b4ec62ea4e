//! Proptest strategies for the scalar types, exported for the property tests of every crate
//! above this one (the nalgebra habit: the crate that owns a type exports its strategies).

use num_complex::Complex;
use proptest::prelude::*;

use crate::{Quat, Scalar};

/// A real in `[-magnitude, magnitude]`.
pub fn real(magnitude: f64) -> BoxedStrategy<f64> {
    (-magnitude..=magnitude).boxed()
}

/// A quaternion with every component in `[-magnitude, magnitude]`.
pub fn quat(magnitude: f64) -> BoxedStrategy<Quat<f64>> {
    [
        real(magnitude),
        real(magnitude),
        real(magnitude),
        real(magnitude),
    ]
    .prop_map(Quat::from_array)
    .boxed()
}

/// A quaternion with components in `[-magnitude, magnitude]` and norm at least `min_norm`.
pub fn nonzero_quat(magnitude: f64, min_norm: f64) -> BoxedStrategy<Quat<f64>> {
    quat(magnitude)
        .prop_filter("norm too small", move |q| q.norm() >= min_norm)
        .boxed()
}

/// A unit quaternion (uniform direction up to the rejection of tiny draws).
pub fn unit_quat() -> BoxedStrategy<Quat<f64>> {
    nonzero_quat(1.0, 0.1).prop_map(Quat::normalize).boxed()
}

/// A complex number with both parts in `[-magnitude, magnitude]`.
pub fn complex(magnitude: f64) -> BoxedStrategy<Complex<f64>> {
    (real(magnitude), real(magnitude))
        .prop_map(|(re, im)| Complex::new(re, im))
        .boxed()
}

/// Scalars that have a strategy, so property tests can be written once over [`Scalar`].
pub trait ScalarStrategy: Scalar<Real = f64> {
    /// Every real component in `[-magnitude, magnitude]`.
    fn strategy(magnitude: f64) -> BoxedStrategy<Self>;
}

impl ScalarStrategy for f64 {
    fn strategy(magnitude: f64) -> BoxedStrategy<Self> {
        real(magnitude)
    }
}

impl ScalarStrategy for Complex<f64> {
    fn strategy(magnitude: f64) -> BoxedStrategy<Self> {
        complex(magnitude)
    }
}

impl ScalarStrategy for Quat<f64> {
    fn strategy(magnitude: f64) -> BoxedStrategy<Self> {
        quat(magnitude)
    }
}
