//! The quaternionic Laplacian `L⊗I` on icospheres through `qeig`: its eigenvalues equal the real
//! Laplacian's (dense truth) with the same multiplicity, and approach the unit-sphere values
//! `l(l+1)` (multiplicity `2l+1`) as O(h²).

use dirac::generators::icosphere;
use dirac::geometry::{barycentric_masses, cotan_laplacian};
use qeig::dense::generalized_hermitian_eigen;
use qeig::{LanczosOptions, Native, Pencil, RealBlock, Which};
use qscalar::{Quat, Scalar};
use qsparse::{SparseMatrix, TripletMatrix};

const EPSILON: f64 = 1e-3;

/// `K = M`, `S = L + εM` over `T` for the icosphere of the given level.
fn pencil<T: Scalar<Real = f64>>(level: u32) -> (SparseMatrix<T>, SparseMatrix<T>) {
    let mesh = icosphere(level);
    let laplacian = cotan_laplacian(&mesh);
    let mass = barycentric_masses(&mesh);
    let n = mass.len();
    let k = SparseMatrix::from_diagonal(&mass.iter().map(|&m| T::from_real(m)).collect::<Vec<_>>());
    let mut t = TripletMatrix::new(n, n);
    for (i, j, v) in laplacian.triplets() {
        t.push(i, j, T::from_real(v)).unwrap();
    }
    for (i, &m) in mass.iter().enumerate() {
        t.push(i, i, T::from_real(EPSILON * m)).unwrap();
    }
    (k, t.to_csc())
}

/// The `k` smallest non-zero Laplacian eigenvalues `λ = 1/μ − ε` of the quaternionic pencil
/// with the constants deflated, ascending.
fn quaternionic_laplacian_eigenvalues<B: qeig::Backend<Quat<f64>>>(
    backend: &B,
    level: u32,
    k: usize,
) -> Vec<f64> {
    let (k_mat, s_mat) = pencil::<Quat<f64>>(level);
    // Mass-orthogonal to the constants: `(M 𝟙)ᴴ x = 0`, with `K = M` diagonal.
    let eig = Pencil::new(&k_mat, &s_mat)
        .unwrap()
        .with_constraints(
            SparseMatrix::from_dense_columns(k_mat.nrows(), &[k_mat.values().to_vec()]).unwrap(),
        )
        .unwrap()
        .solve(backend, &LanczosOptions::new(k, Which::LargestMagnitude))
        .unwrap();
    eig.values.iter().map(|mu| 1.0 / mu - EPSILON).collect()
}

/// `l(l+1)` repeated `2l+1` times, `l ≥ 1`.
fn sphere_values(count: usize) -> Vec<f64> {
    (1..)
        .flat_map(|l: usize| std::iter::repeat_n((l * (l + 1)) as f64, 2 * l + 1))
        .take(count)
        .collect()
}

#[test]
fn quaternionic_laplacian_matches_real_laplacian_with_multiplicity() {
    let level = 2;
    let (k_real, s_real) = pencil::<f64>(level);
    // Dense truth of the real pencil: μ descending, skipping the constant (μ = 1/ε).
    let truth = generalized_hermitian_eigen(&k_real.to_dense(), &s_real.to_dense()).unwrap();
    let mut real: Vec<f64> = truth.values.iter().map(|mu| 1.0 / mu - EPSILON).collect();
    real.sort_by(f64::total_cmp);
    let real = &real[1..];
    let k = 24; // l = 1, 2, 3 (3 + 5 + 7) and part of l = 4
    for values in [
        quaternionic_laplacian_eigenvalues(&Native, level, k),
        quaternionic_laplacian_eigenvalues(&RealBlock, level, k),
    ] {
        for (i, (q, r)) in values.iter().zip(real).enumerate() {
            assert!((q - r).abs() < 1e-8 * r, "{i}: {q} vs {r}");
        }
        // Multiplicities 3, 5, 7 of l = 1, 2, 3: the clusters around l(l+1) have those sizes.
        for (l, mult) in [(1usize, 3usize), (2, 5), (3, 7)] {
            let target = (l * (l + 1)) as f64;
            let count = values
                .iter()
                .filter(|&&v| (v - target).abs() < 0.15 * target)
                .count();
            assert_eq!(count, mult, "l = {l}: {values:?}");
        }
    }
}

#[test]
fn sphere_eigenvalues_converge_quadratically() {
    let k = 15;
    let exact = sphere_values(k);
    let errors: Vec<f64> = (2..=4)
        .map(|level| {
            let values = quaternionic_laplacian_eigenvalues(&Native, level, k);
            values
                .iter()
                .zip(&exact)
                .map(|(v, e)| ((v - e) / e).abs())
                .fold(0.0, f64::max)
        })
        .collect();
    // docs/MATH.md, "What the tests check against": 5.6 %, 1.4 %, 0.36 %.
    assert!(errors[0] < 0.07 && errors[2] < 0.005, "{errors:?}");
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!((3.3..4.7).contains(&ratio), "ratio {ratio} in {errors:?}");
    }
}
