//! Termination on pencils whose true residuals cannot reach the tolerance: an isolated
//! eigenvalue `10¹⁰` times the rest (rounding floor of the residual), with multiplicities,
//! against closed forms.

use qeig::{Backend, ComplexAdjoint, LanczosOptions, Native, Pencil, RealBlock, Which};
use qscalar::Quat;
use qsparse::{SparseMatrix, TripletMatrix};

/// `M x = μ (L + ε M) x` with `L = I₂ ⊗ (path-graph Laplacian)` (interleaved copies, so every
/// eigenvalue is double), `M = I`, `ε = 2⁻³³ ≈ 1.2·10⁻¹⁰` (so that `S = L + ε M` is stored
/// exactly) and no deflation: `μ = 1/(λⱼ + ε)`, `λⱼ = 2 − 2 cos(π j / n)`,
/// `j = 0, 0, 1, 1, 2, 2, …`. The two copies of `μ = 1/ε` dwarf the rest by `10¹⁰`, so the
/// true residuals of every pair have a rounding floor above the tolerance; `k = 7` ends the
/// window between the two copies of `j = 3`. The old locking rule spun to `max_restarts`.
fn huge_isolated_pair<B: Backend<Quat<f64>>>(backend: &B) {
    let (n, copies) = (30, 2);
    let eps = 2f64.powi(-33);
    let mut t = TripletMatrix::new(copies * n, copies * n);
    for c in 0..copies {
        let at = |i: usize| copies * i + c;
        for i in 0..n {
            let degree = if i == 0 || i == n - 1 { 1.0 } else { 2.0 };
            t.push(at(i), at(i), Quat::from_real(degree + eps)).unwrap();
            if i + 1 < n {
                t.push(at(i), at(i + 1), Quat::from_real(-1.0)).unwrap();
                t.push(at(i + 1), at(i), Quat::from_real(-1.0)).unwrap();
            }
        }
    }
    let s = t.to_csc();
    let mass = SparseMatrix::<Quat<f64>>::identity(copies * n);
    let k = 7;
    let eig = Pencil::new(&mass, &s)
        .unwrap()
        .solve(backend, &LanczosOptions::new(k, Which::LargestAlgebraic))
        .unwrap_or_else(|e| panic!("{}: {e:?}", backend.name()));
    let lambda = |j: usize| 2.0 - 2.0 * (std::f64::consts::PI * j as f64 / n as f64).cos();
    let expected: Vec<f64> = (0..k).map(|i| 1.0 / (lambda(i / 2) + eps)).collect();
    assert_eq!(eig.values.len(), k);
    // A backward error `δS` of the Cholesky factorisation (`‖δS‖ ≈ eps ‖S‖`, `‖S‖ ≤ 4`) moves
    // `μ = 1/(λ + ε)` by `μ² ‖δS‖` (relative `κ eps` for `μ = 1/ε`): that is the attainable accuracy.
    for (got, want) in eig.values.iter().zip(&expected) {
        let bound = 1e-10 + 10.0 * f64::EPSILON * 4.0 * want;
        assert!(
            (got - want).abs() <= bound * want,
            "{}: {got} vs {want}",
            backend.name()
        );
    }
    assert!(
        eig.statistics.restarts < 100,
        "{}: {:?}",
        backend.name(),
        eig.statistics
    );
}

#[test]
fn huge_isolated_pair_native() {
    huge_isolated_pair(&Native);
}

#[test]
fn huge_isolated_pair_real_block() {
    huge_isolated_pair(&RealBlock);
}

#[test]
fn huge_isolated_pair_complex_adjoint() {
    huge_isolated_pair(&ComplexAdjoint);
}
