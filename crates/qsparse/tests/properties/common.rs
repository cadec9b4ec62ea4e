//! Helpers shared by the property tests: tolerant comparisons, residuals, faer conversions and a
//! deterministic grid connection Laplacian with large supernodes.

use faer::sparse::{SparseColMat, Triplet};
use proptest::prelude::*;
use qscalar::Scalar;
use qsparse::vector::{axpy, norm};
use qsparse::{SparseCholesky, SparseMatrix, TripletMatrix};

/// `‖found − expected‖ / max(1, ‖expected‖)`.
pub fn relative_distance<T: Scalar<Real = f64>>(found: &[T], expected: &[T]) -> f64 {
    assert_eq!(
        found.len(),
        expected.len(),
        "compared vectors differ in length"
    );
    let mut difference = found.to_vec();
    axpy(&mut difference, expected, -T::one());
    norm(&difference) / norm(expected).max(1.0)
}

/// Fails the case unless `relative_distance(found, expected) ≤ tolerance`.
pub fn assert_close<T: Scalar<Real = f64>>(
    found: &[T],
    expected: &[T],
    tolerance: f64,
) -> Result<(), TestCaseError> {
    let distance = relative_distance(found, expected);
    prop_assert!(
        distance <= tolerance,
        "relative distance {distance:e} > {tolerance:e}\nfound    {found:?}\nexpected {expected:?}"
    );
    Ok(())
}

/// Fails the case unless `C⁻¹ A C⁻ᴴ = I` column by column to `tolerance`, for the factor
/// `A = C Cᴴ`: the factor reproduces `A` in every direction, not only on one right-hand side.
pub fn assert_whitens<T: Scalar<Real = f64>>(
    factor: &SparseCholesky<T>,
    a: &SparseMatrix<T>,
    tolerance: f64,
) -> Result<(), TestCaseError> {
    let n = a.nrows();
    for j in 0..n {
        let mut unit = vec![T::zero(); n];
        unit[j] = T::one();
        let mut column = unit.clone();
        factor.solve_upper_in_place(&mut column).unwrap();
        let mut a_column = vec![T::zero(); n];
        a.mul_vec(&column, &mut a_column).unwrap();
        factor.solve_lower_in_place(&mut a_column).unwrap();
        assert_close(&a_column, &unit, tolerance)?;
    }
    Ok(())
}

/// `‖A x − b‖ / ‖b‖` (or `‖A x‖` for `b = 0`), with `A x` from the SpMV (itself tested
/// against the dense product).
pub fn relative_residual<T: Scalar<Real = f64>>(a: &SparseMatrix<T>, x: &[T], b: &[T]) -> f64 {
    let mut ax = vec![T::zero(); a.nrows()];
    a.mul_vec(x, &mut ax).expect("dimensions fit");
    relative_distance(&ax, b)
}

/// The faer matrix with the same stored entries as `a`, built directly from the triplets.
pub fn to_faer(a: &SparseMatrix<f64>) -> SparseColMat<usize, f64> {
    let triplets: Vec<_> = a
        .triplets()
        .map(|(i, j, v)| Triplet::new(i, j, v))
        .collect();
    SparseColMat::try_new_from_triplets(a.nrows(), a.ncols(), &triplets).expect("indices in range")
}

/// The unit scalar `v / |v|` whose components are `components[..REAL_DIM]`.
pub fn unit_from_components<T: Scalar<Real = f64>>(components: &[f64]) -> T {
    let mut v = [T::zero()];
    T::as_reals_mut(&mut v).copy_from_slice(&components[..T::REAL_DIM]);
    v[0].scale(1.0 / v[0].abs())
}

/// Deterministic values in `[-1, 1)` (a 64-bit linear congruential generator).
pub struct Lcg(pub u64);

impl Lcg {
    /// The next value.
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// A vector of `len` scalars with components in `[-1, 1)`.
    pub fn vector<T: Scalar<Real = f64>>(&mut self, len: usize) -> Vec<T> {
        let mut v = vec![T::zero(); len];
        T::as_reals_mut(&mut v).fill_with(|| self.next());
        v
    }
}

/// The connection Laplacian of the `side × side` grid plus `½ I`: for each grid edge `ij`,
/// `Aᵢⱼ = −rᵢⱼ`, `Aⱼᵢ = −conj(rᵢⱼ)` with a pseudo-random unit `rᵢⱼ`, and
/// `Aᵢᵢ = ½ + deg(i)`. Hermitian positive definite (`x*Ax = Σ_edges |xᵢ − rᵢⱼ xⱼ|² + ½‖x‖²`),
/// with `κ ≤ 17`. AMD on a grid gives separator supernodes of width ~`side`.
pub fn grid_connection_laplacian<T: Scalar<Real = f64>>(side: usize) -> SparseMatrix<T> {
    let n = side * side;
    let mut rng = Lcg(7);
    let mut t = TripletMatrix::new(n, n);
    let mut diagonal = vec![0.5; n];
    for r in 0..side {
        for c in 0..side {
            let i = r * side + c;
            for (dr, dc) in [(0, 1), (1, 0)] {
                if r + dr < side && c + dc < side {
                    let j = (r + dr) * side + c + dc;
                    let transport: T =
                        unit_from_components(&[rng.next(), rng.next(), rng.next(), rng.next()]);
                    t.push(i, j, -transport).expect("in range, finite");
                    t.push(j, i, -transport.conj()).expect("in range, finite");
                    diagonal[i] += 1.0;
                    diagonal[j] += 1.0;
                }
            }
        }
    }
    for (i, &d) in diagonal.iter().enumerate() {
        t.push(i, i, T::from_real(d)).expect("in range, finite");
    }
    t.to_csc()
}
