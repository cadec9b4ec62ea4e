//! The dense quaternion Hermitian eigensolver against faer's complex-adjoint eigenvalues
//! (each quaternionic eigenvalue is a complex pair) and the defining identities.

mod common;

use common::Rng;
use faer::{Mat, Side, c64};
use qeig::dense::{generalized_hermitian_eigen, hermitian_eigen};
use qscalar::{Quat, Scalar};
use qsparse::DenseMatrix;

fn random_hermitian(n: usize, rng: &mut Rng) -> DenseMatrix<Quat<f64>> {
    let upper = DenseMatrix::from_fn(n, n, |_, _| rng.scalar::<Quat<f64>>());
    DenseMatrix::from_fn(n, n, |i, j| {
        if i < j {
            upper[(i, j)]
        } else if i > j {
            upper[(j, i)].conj()
        } else {
            Quat::from_real(upper[(i, i)].w)
        }
    })
}

#[test]
fn quaternion_eigenvalues_match_complex_adjoint_pairs() {
    let mut rng = Rng::new(3);
    for n in [1, 2, 5, 17] {
        let a = random_hermitian(n, &mut rng);
        let eig = hermitian_eigen(&a).unwrap();
        let chi = Mat::<c64>::from_fn(2 * n, 2 * n, |r, c| {
            let mut b = [c64::new(0.0, 0.0); 4];
            a[(r / 2, c / 2)].complex_adjoint_block(&mut b);
            b[(r % 2) * 2 + c % 2]
        });
        let complex = chi.self_adjoint_eigenvalues(Side::Lower).unwrap();
        for i in 0..n {
            for c in 0..2 {
                assert!(
                    (eig.values[i] - complex[2 * i + c]).abs() < 1e-10,
                    "n={n} i={i}"
                );
            }
        }
        // A x = x λ and XᴴX = I.
        let x = &eig.vectors;
        let ax = a.matmul(x).unwrap();
        let gram = x.adjoint().matmul(x).unwrap();
        for j in 0..n {
            for i in 0..n {
                assert!((ax[(i, j)] - x[(i, j)] * eig.values[j]).abs() < 1e-10);
                let target = if i == j { 1.0 } else { 0.0 };
                assert!((gram[(i, j)] - Quat::from_real(target)).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn generalized_pencil_identities() {
    let mut rng = Rng::new(5);
    let n = 9;
    let k = random_hermitian(n, &mut rng);
    let b = random_hermitian(n, &mut rng);
    // S = BᴴB + I is positive definite.
    let mut s = b.adjoint().matmul(&b).unwrap();
    for i in 0..n {
        s[(i, i)] += Quat::from_real(1.0);
    }
    let eig = generalized_hermitian_eigen(&k, &s).unwrap();
    let x = &eig.vectors;
    let (kx, sx) = (k.matmul(x).unwrap(), s.matmul(x).unwrap());
    let gram = x.adjoint().matmul(&sx).unwrap();
    for j in 0..n {
        for i in 0..n {
            assert!((kx[(i, j)] - sx[(i, j)] * eig.values[j]).abs() < 1e-9);
            let target = if i == j { 1.0 } else { 0.0 };
            assert!((gram[(i, j)] - Quat::from_real(target)).abs() < 1e-10);
        }
    }
    assert!(eig.values.windows(2).all(|w| w[0] <= w[1]));
}

#[test]
fn dense_bad_input() {
    let rect = DenseMatrix::<Quat<f64>>::zeros(2, 3);
    assert!(hermitian_eigen(&rect).is_err());
    let k = DenseMatrix::<Quat<f64>>::identity(2);
    let mut s = DenseMatrix::<Quat<f64>>::identity(2);
    s[(1, 1)] = Quat::from_real(-1.0);
    assert!(generalized_hermitian_eigen(&k, &s).is_err());
}
