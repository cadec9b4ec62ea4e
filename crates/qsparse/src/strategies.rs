//! Proptest strategies for sparse matrices and vectors over any scalar with a
//! [`ScalarStrategy`], exported for the property tests of this crate and the crates above it.
//!
//! Every entry has each real component uniform in `[-1, 1]`.

use core::ops::Range;

use proptest::prelude::*;
use qscalar::strategies::ScalarStrategy;

use crate::{SparseMatrix, TripletMatrix};

/// A random `nrows × ncols` sparse matrix: each entry is stored independently with probability
/// `density` (in `[0, 1]`).
pub fn sparse_matrix<T: ScalarStrategy>(
    nrows: usize,
    ncols: usize,
    density: f64,
) -> BoxedStrategy<SparseMatrix<T>> {
    proptest::collection::vec(
        proptest::option::weighted(density, T::strategy(1.0)),
        nrows * ncols,
    )
    .prop_map(move |entries| {
        let triplets = entries
            .into_iter()
            .enumerate()
            .filter_map(|(k, v)| v.map(|v| (k % nrows, k / nrows, v)));
        TripletMatrix::from_triplets(nrows, ncols, triplets)
            .expect("indices in range and finite values")
            .to_csc()
    })
    .boxed()
}

/// A random sparse Hermitian positive-definite `n × n` matrix with `n` drawn from `size`.
///
/// Each strictly-lower entry is stored with probability `density` and mirrored,
/// `Aⱼᵢ = conj(Aᵢⱼ)`; the diagonal (always stored) is real,
/// `Aᵢᵢ = Rᵢ + δᵢ` with `Rᵢ = Σ_{j≠i} |Aᵢⱼ|` and `δᵢ ∈ [0.01, 1]`. So `A` is strictly diagonally
/// dominant with a positive diagonal, hence positive definite, and by Gershgorin its spectrum
/// lies in `[minᵢ δᵢ, maxᵢ (2Rᵢ + δᵢ)]`: `κ(A) ≤ 100 · (2 maxᵢ Rᵢ + 1)`.
pub fn hpd_matrix<T: ScalarStrategy>(
    size: Range<usize>,
    density: f64,
) -> BoxedStrategy<SparseMatrix<T>> {
    size.prop_flat_map(move |n| {
        (
            sparse_matrix::<T>(n, n, density),
            proptest::collection::vec(0.01..=1.0, n),
        )
    })
    .prop_map(|(random, margins)| {
        let n = margins.len();
        let mut row_sums = margins;
        let mut t = TripletMatrix::new(n, n);
        for (i, j, v) in random.triplets().filter(|&(i, j, _)| i > j) {
            let magnitude = v.abs();
            row_sums[i] += magnitude;
            row_sums[j] += magnitude;
            for (r, c, value) in [(i, j, v), (j, i, v.conj())] {
                t.push(r, c, value)
                    .expect("indices in range and finite values");
            }
        }
        for (i, &d) in row_sums.iter().enumerate() {
            t.push(i, i, T::from_real(d))
                .expect("indices in range and finite values");
        }
        t.to_csc()
    })
    .boxed()
}

/// A random vector of length `len`.
pub fn vector<T: ScalarStrategy>(len: usize) -> BoxedStrategy<Vec<T>> {
    proptest::collection::vec(T::strategy(1.0), len).boxed()
}
