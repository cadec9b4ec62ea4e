//! All three backends against the dense solution on random sparse Hermitian pencils
//! (eigenvalues to 1e−9 relative, eigenvectors inside the dense eigenspaces of the window).

mod common;

use common::{Rng, columns, dense_truth, distance_to_span, random_pencil, s_inner};
use qeig::{
    Backend, ComplexAdjoint, HermitianOperator, LanczosOptions, Native, Pencil, RealBlock,
    VECTORS_PER_PASS, Which,
};
use qscalar::{Complex, Quat, Scalar};
use qsparse::SparseMatrix;

fn score(which: Which, v: f64) -> f64 {
    match which {
        Which::LargestMagnitude => v.abs(),
        Which::LargestAlgebraic => v,
        Which::SmallestAlgebraic => -v,
    }
}

/// Checks `backend`'s `k` pairs against the dense truth.
fn check<T: Scalar<Real = f64>, B: Backend<T>>(
    backend: &B,
    k_mat: &SparseMatrix<T>,
    s_mat: &SparseMatrix<T>,
    k: usize,
    which: Which,
) {
    let options = LanczosOptions {
        max_dim: (2 * k + 8).max(20),
        ..LanczosOptions::new(k, which)
    };
    check_with(backend, k_mat, s_mat, &options);
}

/// Checks `backend`'s pairs for `options` against the dense truth.
fn check_with<T: Scalar<Real = f64>, B: Backend<T>>(
    backend: &B,
    k_mat: &SparseMatrix<T>,
    s_mat: &SparseMatrix<T>,
    options: &LanczosOptions,
) {
    let (k, which) = (options.k, options.which);
    let truth = dense_truth(k_mat, s_mat);
    let mut order: Vec<usize> = (0..truth.values.len()).collect();
    order.sort_by(|&a, &b| score(which, truth.values[b]).total_cmp(&score(which, truth.values[a])));
    let eig = Pencil::new(k_mat, s_mat)
        .unwrap()
        .solve(backend, options)
        .unwrap_or_else(|e| panic!("{}: {e}", backend.name()));
    assert_eq!(eig.values.len(), k);
    let scale = truth.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (i, (&mu, x)) in eig.values.iter().zip(&eig.vectors).enumerate() {
        let expected = truth.values[order[i]];
        assert!(
            (mu - expected).abs() <= 1e-9 * expected.abs().max(1e-3 * scale),
            "{}: value {i}: {mu} vs {expected}",
            backend.name()
        );
        assert!(
            eig.residuals[i] <= options.tolerance * 10.0,
            "{}",
            eig.residuals[i]
        );
        // x lies in the dense eigenspace of its eigenvalue (principal angle ≈ 0).
        let space: Vec<usize> = (0..truth.values.len())
            .filter(|&j| (truth.values[j] - mu).abs() <= 1e-6 * scale)
            .collect();
        let d = distance_to_span(s_mat, x, &columns(&truth.vectors, &space));
        assert!(
            d < 1e-6,
            "{}: vector {i} is {d:e} away from its eigenspace",
            backend.name()
        );
    }
    // S-orthonormal.
    for a in 0..k {
        for b in 0..k {
            let g = s_inner(s_mat, &eig.vectors[a], &eig.vectors[b]);
            let target = if a == b { 1.0 } else { 0.0 };
            assert!(
                (g - T::from_real(target)).abs() < 1e-8,
                "gram ({a},{b}) = {g:?}"
            );
        }
    }
}

fn all_backends<T: Scalar<Real = f64>>(seed: u64) {
    let mut rng = Rng::new(seed);
    let n = 60;
    let (k_mat, s_mat) = random_pencil::<T>(n, 3, &mut rng);
    for which in [
        Which::LargestMagnitude,
        Which::LargestAlgebraic,
        Which::SmallestAlgebraic,
    ] {
        check(&Native, &k_mat, &s_mat, 6, which);
        check(&RealBlock, &k_mat, &s_mat, 6, which);
        check(&ComplexAdjoint, &k_mat, &s_mat, 6, which);
    }
}

#[test]
fn quaternion_pencils_agree_with_dense() {
    for seed in 1..4 {
        all_backends::<Quat<f64>>(seed);
    }
}

#[test]
fn complex_pencils_agree_with_dense() {
    all_backends::<Complex<f64>>(11);
}

#[test]
fn real_pencils_agree_with_dense() {
    all_backends::<f64>(21);
}

/// More pairs than one pass of the many-vector half-solves holds: the chunked residuals of the
/// candidates and the chunked eigenvector extraction keep every pair right.
#[test]
fn more_pairs_than_one_pass() {
    let mut rng = Rng::new(5);
    let n = 80;
    let (k_mat, s_mat) = random_pencil::<Quat<f64>>(n, 3, &mut rng);
    let k = 2 * VECTORS_PER_PASS + 3;
    check(&Native, &k_mat, &s_mat, k, Which::LargestMagnitude);
    check(&RealBlock, &k_mat, &s_mat, k, Which::SmallestAlgebraic);
}

/// Many pairs with the automatic basis, whose active part (the pairs still needed and 64
/// more) is then smaller than twice the pairs: every pair is still the dense one.
#[test]
fn many_pairs_with_the_automatic_basis() {
    let mut rng = Rng::new(9);
    let (k_mat, s_mat) = random_pencil::<Quat<f64>>(240, 3, &mut rng);
    for which in [Which::LargestMagnitude, Which::SmallestAlgebraic] {
        check_with(&Native, &k_mat, &s_mat, &LanczosOptions::new(90, which));
    }
}

/// More pairs than the automatic active basis is sized for (the next 128 needed, 64 spare):
/// every pair is still the dense one.
#[test]
fn more_pairs_than_the_active_window() {
    let mut rng = Rng::new(10);
    let (k_mat, s_mat) = random_pencil::<Quat<f64>>(420, 3, &mut rng);
    check_with(
        &Native,
        &k_mat,
        &s_mat,
        &LanczosOptions::new(170, Which::LargestMagnitude),
    );
}

/// The residuals of several pairs at once are exactly those of each pair alone (the
/// many-column half-solve gives every column the one-column result).
#[test]
fn residuals_of_many_pairs_are_those_of_each() {
    let mut rng = Rng::new(8);
    let n = 50;
    let (k_mat, s_mat) = random_pencil::<Quat<f64>>(n, 3, &mut rng);
    let mut op = Native.prepare(&k_mat, &s_mat).unwrap();
    let count = VECTORS_PER_PASS + 3;
    let ys: Vec<Quat<f64>> = (0..n * count).map(|_| rng.scalar()).collect();
    let thetas: Vec<f64> = (0..count).map(|i| 0.5 + i as f64).collect();
    let together = op.relative_residuals(&ys, &thetas);
    let each: Vec<f64> = (ys.chunks_exact(n).zip(&thetas))
        .map(|(y, &theta)| op.relative_residual(y, theta))
        .collect();
    assert_eq!(together.len(), count);
    assert_eq!(together, each);
}
