//! Exact multiplicities: every backend returns each eigenvalue as often as its quaternionic
//! (complex, real) multiplicity, against closed forms and block-diagonal constructions.

mod common;

use common::{Rng, cycle_laplacian, dense_truth, random_pencil, s_inner};
use qeig::{Backend, ComplexAdjoint, LanczosOptions, Native, Pencil, RealBlock, Which};
use qscalar::{Quat, Scalar};
use qsparse::{SparseMatrix, TripletMatrix};

/// `M x = μ (L + ε M) x` on the cycle graph with `M = I` and the constants deflated:
/// `μ = 1/(λ + ε)` with `λ = 2 − 2 cos(2π j/n)`, `j = 1, 1, 2, 2, …` (each value twice).
fn cycle_pencil<B: Backend<Quat<f64>>>(backend: &B, n: usize, k: usize) {
    let eps = 1e-2;
    let l = cycle_laplacian::<Quat<f64>>(n);
    let mass = SparseMatrix::<Quat<f64>>::identity(n);
    let mut t = TripletMatrix::new(n, n);
    for (i, j, v) in l.triplets() {
        t.push(i, j, v).unwrap();
    }
    for i in 0..n {
        t.push(i, i, Quat::from_real(eps)).unwrap();
    }
    let s = t.to_csc();
    let eig = Pencil::new(&mass, &s)
        .unwrap()
        // Mass-orthogonal to the constants: the constraint `(M 𝟙)ᴴ x = 0`.
        .with_constraints(SparseMatrix::from_dense_columns(n, &[mass.values().to_vec()]).unwrap())
        .unwrap()
        .solve(backend, &LanczosOptions::new(k, Which::LargestMagnitude))
        .unwrap();
    let expected: Vec<f64> = (0..k)
        .map(|i| {
            let j = (i / 2 + 1) as f64;
            1.0 / (2.0 - 2.0 * (2.0 * std::f64::consts::PI * j / n as f64).cos() + eps)
        })
        .collect();
    assert_eq!(eig.values.len(), k, "{}", backend.name());
    for (got, want) in eig.values.iter().zip(&expected) {
        assert!(
            (got - want).abs() < 1e-9 * want,
            "{}: {got} vs {want}",
            backend.name()
        );
    }
    // The returned vectors are S-orthogonal to the constants.
    let ones = vec![Quat::from_real(1.0); n];
    for x in &eig.vectors {
        assert!(s_inner(&s, &ones, x).abs() < 1e-9);
    }
}

#[test]
fn cycle_graph_pairs_native() {
    cycle_pencil(&Native, 40, 9);
}

/// More pairs than the automatic active basis is sized for (it holds room for the next 128
/// needed): every double eigenvalue still comes out twice, in order.
#[test]
fn cycle_graph_pairs_beyond_the_active_window() {
    cycle_pencil(&Native, 400, 171);
}

#[test]
fn cycle_graph_pairs_real_block() {
    cycle_pencil(&RealBlock, 40, 9);
}

#[test]
fn cycle_graph_pairs_complex_adjoint() {
    cycle_pencil(&ComplexAdjoint, 40, 9);
}

/// `I₃ ⊗ B` (three interleaved copies of a random pencil): every eigenvalue has multiplicity
/// exactly 3, which one Krylov sequence cannot see.
#[test]
fn threefold_block_pencil() {
    let mut rng = Rng::new(7);
    let m = 15;
    let (kb, sb) = random_pencil::<Quat<f64>>(m, 2, &mut rng);
    let truth = dense_truth(&kb, &sb);
    let copies = 3;
    let spread = |a: &SparseMatrix<Quat<f64>>| {
        let mut t = TripletMatrix::new(copies * m, copies * m);
        for (i, j, v) in a.triplets() {
            for c in 0..copies {
                t.push(copies * i + c, copies * j + c, v).unwrap();
            }
        }
        t.to_csc()
    };
    let (k_mat, s_mat) = (spread(&kb), spread(&sb));
    let k = 8;
    let mut expected: Vec<f64> = truth.values.iter().flat_map(|&v| [v; 3]).collect();
    expected.sort_by(|a, b| b.total_cmp(a));
    for backend_result in [
        Pencil::new(&k_mat, &s_mat)
            .unwrap()
            .solve(&Native, &LanczosOptions::new(k, Which::LargestAlgebraic)),
        Pencil::new(&k_mat, &s_mat)
            .unwrap()
            .solve(&RealBlock, &LanczosOptions::new(k, Which::LargestAlgebraic)),
        Pencil::new(&k_mat, &s_mat).unwrap().solve(
            &ComplexAdjoint,
            &LanczosOptions::new(k, Which::LargestAlgebraic),
        ),
    ] {
        let eig = backend_result.unwrap();
        for (got, want) in eig.values.iter().zip(&expected) {
            assert!(
                (got - want).abs() < 1e-9 * want.abs().max(1.0),
                "{got} vs {want}"
            );
        }
    }
}
