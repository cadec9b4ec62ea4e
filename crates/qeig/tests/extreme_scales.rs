//! Pencils whose entries are far from 1 (near `1e±200`): the same spectrum as the scaled
//! problem, never NaN values or a non-Hermitian matrix accepted because a norm overflowed.
//! Found by the `pencil` fuzz target.

use qeig::{EigError, LanczosOptions, Native, Pencil, Which};
use qscalar::{Quat, Scalar};
use qsparse::{SparseMatrix, TripletMatrix};

type Q = Quat<f64>;

fn matrix(n: usize, entries: &[(usize, usize, Q)]) -> SparseMatrix<Q> {
    let mut t = TripletMatrix::new(n, n);
    for &(i, j, v) in entries {
        t.push(i, j, v).unwrap();
    }
    t.to_csc()
}

fn identity(n: usize) -> SparseMatrix<Q> {
    SparseMatrix::identity(n)
}

fn refused(k: &SparseMatrix<Q>, s: &SparseMatrix<Q>) -> Option<&'static str> {
    match Pencil::new(k, s) {
        Err(EigError::NotHermitian { which, .. }) => Some(which),
        _ => None,
    }
}

#[test]
fn a_matrix_that_is_not_hermitian_is_refused_at_any_scale() {
    for value in [1e200, 1.0, 1e-200] {
        let k = matrix(2, &[(0, 1, Q::from_real(value))]);
        assert_eq!(
            refused(&k, &identity(2)),
            Some("K"),
            "K₀₁ = {value:e} alone"
        );
    }
    let s = matrix(
        2,
        &[
            (0, 0, Q::from_real(1.0)),
            (1, 1, Q::new(1.0, 1e188, 0.0, 0.0)),
        ],
    );
    assert_eq!(refused(&identity(2), &s), Some("S"));
    // Hermitian at those scales: accepted.
    for value in [1e200, 1e-200] {
        let q = Q::new(0.5, -2.0, 1.0, 0.25) * Q::from_real(value);
        let k = matrix(2, &[(0, 1, q), (1, 0, q.conj())]);
        assert!(Pencil::new(&k, &identity(2)).is_ok(), "{value:e}");
    }
}

/// `K` zero but for `K₄₀ = q`, `K₀₄ = q̄`, `S = I`: eigenvalues `±|q|` and four zeros.
#[test]
fn huge_entries_give_the_eigenvalues() {
    let q = Q::new(4.03e175, 1.2e-158, -25.125, 54.0);
    let size = 4.03e175; // |q|: the other components are below its last digit
    let k = matrix(6, &[(4, 0, q), (0, 4, q.conj())]);
    let eig = Pencil::new(&k, &identity(6))
        .unwrap()
        .solve(&Native, &LanczosOptions::new(4, Which::LargestAlgebraic))
        .unwrap();
    assert!(
        (eig.values[0] - size).abs() <= 1e-12 * size,
        "{:?}",
        eig.values
    );
    for &v in &eig.values[1..] {
        assert!(v.abs() <= 1e-10 * size, "{:?}", eig.values);
    }
    for x in &eig.vectors {
        let norm = x.iter().map(|v| v.abs2()).sum::<f64>().sqrt();
        assert!((norm - 1.0).abs() < 1e-12, "‖x‖ = {norm}");
    }
}

/// `K = diag(1e−111, 0, …, 0)`, `S = I`: eigenvalues `1e−111` and zeros.
#[test]
fn tiny_entries_give_the_eigenvalues() {
    let k = matrix(8, &[(0, 0, Q::from_real(1e-111))]);
    let eig = Pencil::new(&k, &identity(8))
        .unwrap()
        .solve(&Native, &LanczosOptions::new(6, Which::LargestAlgebraic))
        .unwrap();
    assert!(
        (eig.values[0] - 1e-111).abs() <= 1e-12 * 1e-111,
        "{:?}",
        eig.values
    );
    for &v in &eig.values[1..] {
        assert!(v.abs() <= 1e-10 * 1e-111, "{:?}", eig.values);
    }
}

/// `K = diag(1, 2, 3, 4)`, `S = 1e−200 I`: `μ = 1e200 · (4, 3, 2, 1)`, eigenvectors of norm
/// `1e100` (`xᴴ S x = 1`).
#[test]
fn a_tiny_s_scales_values_and_vectors() {
    let k = SparseMatrix::from_diagonal(&[1.0, 2.0, 3.0, 4.0].map(Q::from_real));
    let s = SparseMatrix::from_diagonal(&[Q::from_real(1e-200); 4]);
    let eig = Pencil::new(&k, &s)
        .unwrap()
        .solve(&Native, &LanczosOptions::new(2, Which::LargestAlgebraic))
        .unwrap();
    for (v, expected) in eig.values.iter().zip([4e200, 3e200]) {
        assert!((v - expected).abs() <= 1e-12 * expected, "{:?}", eig.values);
    }
    for x in &eig.vectors {
        // ‖x‖ without overflow: scale first.
        let norm = x
            .iter()
            .map(|v| (v.scale(1e-100)).abs2())
            .sum::<f64>()
            .sqrt();
        assert!((norm - 1.0).abs() < 1e-12, "‖x‖ = {norm} · 1e100");
    }
}

/// `K = I` and an `S` whose diagonal spans `1` to `2.8e180` (cond `S` beyond the
/// floating-point range, so no single scaling helps): the largest `μ` is `1` (six times).
/// Either it is found, or the run says it did not converge; never a NaN pair reported as
/// converged (which it was).
#[test]
fn an_s_spanning_the_floating_point_range_is_never_a_nan_success() {
    let q = Q::new(103.375, 103.375, -0.625, 40.0);
    let mut entries: Vec<(usize, usize, Q)> = (0..8).map(|i| (i, i, Q::from_real(1.0))).collect();
    entries[0].2 = Q::from_real(152.56903336433865);
    entries[4].2 = Q::from_real(2.77448001759404e180);
    entries.extend([(4, 0, q), (0, 4, q.conj())]);
    let s = matrix(8, &entries);
    let options = LanczosOptions {
        tolerance: 1e-3,
        ..LanczosOptions::new(1, Which::LargestAlgebraic)
    };
    match Pencil::new(&identity(8), &s)
        .unwrap()
        .solve(&Native, &options)
    {
        Ok(eig) => assert!((eig.values[0] - 1.0).abs() < 1e-3, "{:?}", eig.values),
        Err(EigError::NotConverged { partial, .. }) => {
            assert!(partial.values.iter().all(|v| (v - 1.0).abs() < 1e-3));
        }
        Err(e) => panic!("{e}"),
    }
}

/// The tridiagonal `[[2, 1, 0], [1, 3, 1], [0, 1, 4]]` (eigenvalues `3 − √3, 3, 3 + √3`) times
/// a scale, in quaternions.
fn tridiagonal(scale: f64) -> qsparse::DenseMatrix<Q> {
    let entries = [[2.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 4.0]];
    qsparse::DenseMatrix::from_fn(3, 3, |i, j| Q::from_real(entries[i][j] * scale))
}

const TRIDIAGONAL: [f64; 3] = [
    3.0 - 1.732_050_807_568_877_2,
    3.0,
    3.0 + 1.732_050_807_568_877_2,
];

/// The dense solvers at `1e±200`: the closed-form eigenvalues, scaled (at `1e−200` the
/// diagonal came back as the eigenvalues, at `1e200` the solver reported no convergence).
#[test]
fn dense_solvers_at_any_scale() {
    for scale in [1e-200, 1e-120, 1e120, 1e200] {
        let eigen = qeig::dense::hermitian_eigen(&tridiagonal(scale)).unwrap();
        for (v, expected) in eigen.values.iter().zip(TRIDIAGONAL) {
            assert!(
                (v / scale - expected).abs() < 1e-12,
                "{scale:e}: {:?}",
                eigen.values
            );
        }
    }
    // K = 1e150 T, S = 1e−150 I: μ = 1e300 λ, eigenvectors of norm 1e75 (xᴴ S x = 1).
    let s =
        qsparse::DenseMatrix::from_fn(3, 3, |i, j| Q::from_real(if i == j { 1e-150 } else { 0.0 }));
    let eigen = qeig::dense::generalized_hermitian_eigen(&tridiagonal(1e150), &s).unwrap();
    for (v, expected) in eigen.values.iter().zip(TRIDIAGONAL) {
        assert!((v / 1e300 - expected).abs() < 1e-12, "{:?}", eigen.values);
    }
    for j in 0..3 {
        let norm = (0..3)
            .map(|i| eigen.vectors[(i, j)].scale(1e-75).abs2())
            .sum::<f64>()
            .sqrt();
        assert!((norm - 1.0).abs() < 1e-12, "‖x‖ = {norm} · 1e75");
    }
}

/// The dense solvers read the lower triangles and the real parts of the diagonals only: huge
/// values elsewhere change nothing, bit for bit. They used to set the scale of the
/// computation, and with a diagonal of `S` whose real part was subnormal behind an imaginary
/// part of 0.7 (found by the `dense_eigen` fuzz target) the projected matrix overflowed and
/// the solver reported a non-finite matrix `A` the caller never passed.
#[test]
fn dense_solvers_ignore_what_they_do_not_read() {
    let garbage = |m: &qsparse::DenseMatrix<Q>, value: f64| {
        qsparse::DenseMatrix::from_fn(3, 3, |i, j| {
            let mut q = m[(i, j)];
            if i < j {
                q = Q::new(value, -value, value, value);
            } else if i == j {
                q.x = value;
                q.z = -value;
            }
            q
        })
    };
    let k = tridiagonal(1.0);
    let s = qsparse::DenseMatrix::from_fn(3, 3, |i, j| {
        Q::from_real(if i == j { 2.0 + i as f64 } else { 0.0 })
    });
    let clean = qeig::dense::hermitian_eigen(&k).unwrap();
    let pencil = qeig::dense::generalized_hermitian_eigen(&k, &s).unwrap();
    for value in [1e250, 1e-250, 0.7] {
        let dirty = qeig::dense::hermitian_eigen(&garbage(&k, value)).unwrap();
        assert_eq!(dirty.values, clean.values, "{value:e}");
        assert_eq!(
            dirty.vectors.as_slice(),
            clean.vectors.as_slice(),
            "{value:e}"
        );
        let dirty =
            qeig::dense::generalized_hermitian_eigen(&garbage(&k, value), &garbage(&s, value))
                .unwrap();
        assert_eq!(dirty.values, pencil.values, "{value:e}");
        assert_eq!(
            dirty.vectors.as_slice(),
            pencil.vectors.as_slice(),
            "{value:e}"
        );
    }
    // The fuzzer's case: S = [2⁻¹⁰⁶⁰ + 0.7 i] (a subnormal real part), K = [2⁻⁴⁰]: μ = 2¹⁰²⁰.
    let s = qsparse::DenseMatrix::from_fn(1, 1, |_, _| Q::new(2f64.powi(-1060), 0.7, 0.0, 0.0));
    let k = qsparse::DenseMatrix::from_fn(1, 1, |_, _| Q::from_real(2f64.powi(-40)));
    let eigen = qeig::dense::generalized_hermitian_eigen(&k, &s).unwrap();
    assert_eq!(eigen.values, [2f64.powi(1020)]);
}

/// Columns far below the matrix's scale (found by the `dense_eigen` fuzz target): a first
/// column with components of 1e−160 next to one of 0.5 (its phase, from underflowing
/// squares, was off unit length: eigenvectors orthogonal only to 5e−5), and a second column
/// of norm 1e−160 below a first one already reduced (whose reflector's `τ` overflowed: NaN
/// eigenvectors, and the solver failed).
#[test]
fn dense_solver_with_columns_far_below_the_scale() {
    let tiny = 3.6e-160;
    let cases = [
        [
            Q::new(1.6e-180, -tiny, -tiny, -tiny),
            Q::new(-tiny, -7.7e-179, -0.5, 0.0),
            Q::new(1e-176, 1e-176, 1e-176, 1e-176),
        ],
        [
            Q::new(0.75, 0.0, 0.5, 0.0),
            Q::default(),
            Q::new(tiny, tiny, 0.0, -tiny),
        ],
    ];
    for [a10, a20, a21] in cases {
        let a = qsparse::DenseMatrix::from_fn(3, 3, |i, j| match (i, j) {
            (1, 0) => a10,
            (2, 0) => a20,
            (2, 1) => a21,
            (0, 1) => a10.conj(),
            (0, 2) => a20.conj(),
            (1, 2) => a21.conj(),
            (1, 1) => Q::from_real(0.25),
            _ => Q::default(),
        });
        let eigen = qeig::dense::hermitian_eigen(&a).unwrap();
        let x = &eigen.vectors;
        let gram = x.adjoint().matmul(x).unwrap();
        let ax = a.matmul(x).unwrap();
        for i in 0..3 {
            for j in 0..3 {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (gram[(i, j)] - Q::from_real(expected)).abs() < 1e-14,
                    "XᴴX ({i}, {j})"
                );
                let r = ax[(i, j)] - x[(i, j)].scale(eigen.values[j]);
                assert!(r.abs() < 1e-14, "residual ({i}, {j}): {:e}", r.abs());
            }
        }
    }
}
