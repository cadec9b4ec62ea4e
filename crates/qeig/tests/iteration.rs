//! Deflation, locking, the non-convergence path, both-ends selection, progress reporting and
//! bad input, against dense truth.

mod common;

use common::{Rng, columns, dense_truth, distance_to_span, random_hermitian, random_hpd, s_inner};
use qeig::{ComplexAdjoint, EigError, LanczosOptions, Native, Pencil, RealBlock, Which};
use qscalar::{Quat, Scalar};
use qsparse::{SparseMatrix, SparseVector, TripletMatrix};

type Q = Quat<f64>;

fn pencil(seed: u64, n: usize) -> (SparseMatrix<Q>, SparseMatrix<Q>) {
    let mut rng = Rng::new(seed);
    (
        random_hermitian(n, 3, 0.0, &mut rng),
        random_hpd(n, &mut rng),
    )
}

fn by_magnitude(values: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[b].abs().total_cmp(&values[a].abs()));
    order
}

#[test]
fn deflating_eigenvectors_removes_them() {
    let (k_mat, s_mat) = pencil(31, 50);
    let truth = dense_truth(&k_mat, &s_mat);
    let order = by_magnitude(&truth.values);
    // Deflate the two dominant eigenvectors (multiplied by arbitrary quaternions on the right:
    // the quaternionic span is what counts).
    let q = Quat::new(0.3, -1.0, 0.5, 2.0);
    let deflation: Vec<Vec<Q>> = columns(&truth.vectors, &order[..2])
        .into_iter()
        .map(|v| v.into_iter().map(|x| x * q).collect())
        .collect();
    // `S`-orthogonality to `d` is the constraint `(S d)ᴴ x = 0`.
    let constraints: Vec<Vec<Q>> = deflation
        .iter()
        .map(|d| {
            let mut sd = vec![Q::default(); d.len()];
            s_mat.mul_vec(d, &mut sd).unwrap();
            sd
        })
        .collect();
    let eig = Pencil::new(&k_mat, &s_mat)
        .unwrap()
        .with_constraints(SparseMatrix::from_dense_columns(s_mat.nrows(), &constraints).unwrap())
        .unwrap()
        .solve(&Native, &LanczosOptions::new(4, Which::LargestMagnitude))
        .unwrap();
    for (i, &mu) in eig.values.iter().enumerate() {
        let want = truth.values[order[i + 2]];
        assert!((mu - want).abs() < 1e-9 * want.abs(), "{mu} vs {want}");
        for d in &deflation {
            assert!(s_inner(&s_mat, d, &eig.vectors[i]).abs() < 1e-8);
        }
    }
}

/// A constraint `cᴴ x = 0` with `c` no eigenvector's image: the residual `K x − μ S x` of a
/// pair of the constrained pencil is a multiple of `c`, not zero, so the reported residual is
/// its part orthogonal to `c`, at rounding, where the whole of it is not.
#[test]
fn residuals_under_a_constraint_are_what_the_constrained_pencil_misses() {
    let (k_mat, s_mat) = pencil(47, 30);
    let mut rng = Rng::new(5);
    let c: Vec<Q> = (0..30).map(|_| rng.scalar()).collect();
    let eig = Pencil::new(&k_mat, &s_mat)
        .unwrap()
        .with_constraints(SparseMatrix::from_dense_columns(30, std::slice::from_ref(&c)).unwrap())
        .unwrap()
        .solve(&Native, &LanczosOptions::new(4, Which::LargestMagnitude))
        .unwrap();
    for (i, (&mu, x)) in eig.values.iter().zip(&eig.vectors).enumerate() {
        let along: Q = c.iter().zip(x).map(|(c, v)| c.conj() * *v).sum();
        assert!(along.abs() < 1e-10, "{i}: cᴴx = {along:?}");
        let (mut kx, mut sx) = (vec![Q::default(); 30], vec![Q::default(); 30]);
        k_mat.mul_vec(x, &mut kx).unwrap();
        s_mat.mul_vec(x, &mut sx).unwrap();
        let r: Vec<Q> = kx.iter().zip(&sx).map(|(k, s)| *k - s.scale(mu)).collect();
        let scale = mu.abs() * norm(&sx);
        // `r = c a` with `a = cᴴr / cᴴc`: what is left is rounding.
        let a = c
            .iter()
            .zip(&r)
            .map(|(c, r)| c.conj() * *r)
            .sum::<Q>()
            .scale(1.0 / norm(&c).powi(2));
        let left: Vec<Q> = r.iter().zip(&c).map(|(r, c)| *r - *c * a).collect();
        assert!(norm(&r) > 1e-3 * scale, "{i}: the constraint does not bind");
        assert!(norm(&left) < 1e-9 * scale, "{i}: {}", norm(&left) / scale);
        assert!(eig.residuals[i] < 1e-9, "{i}: {}", eig.residuals[i]);
    }
}

/// Euclidean norm.
fn norm(x: &[Q]) -> f64 {
    x.iter().map(|v| v.abs2()).sum::<f64>().sqrt()
}

#[test]
fn locking_allows_more_pairs_than_the_basis_holds() {
    let (k_mat, s_mat) = pencil(41, 80);
    let truth = dense_truth(&k_mat, &s_mat);
    let order = by_magnitude(&truth.values);
    let k = 14;
    let options = LanczosOptions {
        max_dim: 8,
        ..LanczosOptions::new(k, Which::LargestMagnitude)
    };
    let eig = Pencil::new(&k_mat, &s_mat)
        .unwrap()
        .solve(&Native, &options)
        .unwrap();
    assert!(eig.statistics.locked >= k && eig.statistics.restarts > 1);
    let scale = truth.values[order[0]].abs();
    for (i, &mu) in eig.values.iter().enumerate() {
        let want = truth.values[order[i]];
        assert!((mu - want).abs() < 1e-9 * scale, "{i}: {mu} vs {want}");
        let space: Vec<usize> = (0..truth.values.len())
            .filter(|&j| (truth.values[j] - mu).abs() < 1e-6 * scale)
            .collect();
        assert!(distance_to_span(&s_mat, &eig.vectors[i], &columns(&truth.vectors, &space)) < 1e-6);
    }
}

#[test]
fn non_convergence_returns_converged_pairs_and_statistics() {
    let (k_mat, s_mat) = pencil(51, 120);
    let truth = dense_truth(&k_mat, &s_mat);
    let limit = 40;
    let options = LanczosOptions {
        max_dim: 12,
        max_operator_applications: limit,
        ..LanczosOptions::new(20, Which::LargestMagnitude)
    };
    match Pencil::new(&k_mat, &s_mat)
        .unwrap()
        .solve(&Native, &options)
    {
        Err(EigError::NotConverged { wanted, partial }) => {
            assert_eq!(wanted, 20);
            assert!(partial.values.len() < 20);
            assert!(partial.statistics.operator_applications <= limit);
            assert!(partial.statistics.iterations > 0);
            // Whatever converged is a true eigenpair.
            for (&mu, r) in partial.values.iter().zip(&partial.residuals) {
                assert!(*r <= 1e-9);
                assert!(
                    truth
                        .values
                        .iter()
                        .any(|&t| (t - mu).abs() < 1e-8 * t.abs())
                );
            }
        }
        other => panic!("expected NotConverged, got {other:?}"),
    }
}

#[test]
fn largest_magnitude_takes_both_ends() {
    // K indefinite with a spectrum symmetric-ish about 0: the wanted window must mix signs.
    let (k_mat, s_mat) = pencil(61, 70);
    let truth = dense_truth(&k_mat, &s_mat);
    let order = by_magnitude(&truth.values);
    let k = 10;
    let expected: Vec<f64> = order[..k].iter().map(|&i| truth.values[i]).collect();
    assert!(expected.iter().any(|&v| v > 0.0) && expected.iter().any(|&v| v < 0.0));
    for eig in [
        Pencil::new(&k_mat, &s_mat)
            .unwrap()
            .solve(&Native, &LanczosOptions::new(k, Which::LargestMagnitude)),
        Pencil::new(&k_mat, &s_mat)
            .unwrap()
            .solve(&RealBlock, &LanczosOptions::new(k, Which::LargestMagnitude)),
        Pencil::new(&k_mat, &s_mat).unwrap().solve(
            &ComplexAdjoint,
            &LanczosOptions::new(k, Which::LargestMagnitude),
        ),
    ] {
        let eig = eig.unwrap();
        for (got, want) in eig.values.iter().zip(&expected) {
            assert!((got - want).abs() < 1e-9 * want.abs(), "{got} vs {want}");
        }
    }
}

#[test]
fn progress_is_reported() {
    let (k_mat, s_mat) = pencil(71, 60);
    let mut calls = Vec::new();
    let mut callback = |p: &qeig::Progress| {
        calls.push(*p);
        std::ops::ControlFlow::Continue(())
    };
    let eig = Pencil::new(&k_mat, &s_mat)
        .unwrap()
        .solve_with_progress(
            &Native,
            &LanczosOptions::new(5, Which::LargestAlgebraic),
            Some(&mut callback),
        )
        .unwrap();
    // Every restart is reported (and, on a slow machine, steps between them too).
    let restarts: std::collections::BTreeSet<usize> = calls.iter().map(|p| p.restarts).collect();
    assert!((1..=eig.statistics.restarts).all(|r| restarts.contains(&r)));
    assert!(calls.windows(2).all(|w| {
        w[0].operator_applications <= w[1].operator_applications && w[0].restarts <= w[1].restarts
    }));
    assert_eq!(calls.last().unwrap().wanted, 5);
}

#[test]
fn same_seed_same_result() {
    let (k_mat, s_mat) = pencil(81, 50);
    let options = LanczosOptions::new(4, Which::LargestMagnitude);
    let a = Pencil::new(&k_mat, &s_mat)
        .unwrap()
        .solve(&Native, &options)
        .unwrap();
    let b = Pencil::new(&k_mat, &s_mat)
        .unwrap()
        .solve(&Native, &options)
        .unwrap();
    assert_eq!(a.values, b.values);
    assert_eq!(a.vectors, b.vectors);
}

#[test]
fn bad_input_is_a_typed_error() {
    let (k_mat, s_mat) = pencil(91, 20);
    let p = Pencil::new(&k_mat, &s_mat).unwrap();
    let opts = |k| LanczosOptions::new(k, Which::LargestMagnitude);
    assert!(matches!(
        p.solve(&Native, &opts(0)),
        Err(EigError::InvalidCount { .. })
    ));
    assert!(matches!(
        p.solve(&Native, &opts(21)),
        Err(EigError::InvalidCount { .. })
    ));
    let bad_tol = LanczosOptions {
        tolerance: 0.0,
        ..opts(2)
    };
    assert!(matches!(
        p.solve(&Native, &bad_tol),
        Err(EigError::InvalidOption(_))
    ));
    let rect = SparseMatrix::<Q>::zeros(20, 19);
    assert!(matches!(
        Pencil::new(&rect, &s_mat),
        Err(EigError::NotSquare { .. })
    ));
    let small = SparseMatrix::<Q>::identity(19);
    assert!(matches!(
        Pencil::new(&small, &s_mat),
        Err(EigError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        p.clone().with_constraints(SparseMatrix::identity(3)),
        Err(EigError::DimensionMismatch { .. })
    ));
    let beyond = SparseVector {
        rows: vec![20],
        values: vec![Q::from_real(1.0)],
    };
    assert!(matches!(
        p.clone().with_low_rank_update(vec![(beyond, 1.0)]),
        Err(EigError::DimensionMismatch { .. })
    ));
    let malformed = SparseVector {
        rows: vec![1, 2],
        values: vec![Q::from_real(1.0)],
    };
    assert!(matches!(
        p.clone().with_low_rank_update(vec![(malformed, 1.0)]),
        Err(EigError::DimensionMismatch { .. })
    ));
    let not_finite = SparseVector {
        rows: vec![3],
        values: vec![Q::from_real(f64::NAN)],
    };
    assert!(matches!(
        p.clone().with_low_rank_update(vec![(not_finite, 1.0)]),
        Err(EigError::NonFinite(_))
    ));
    // S indefinite: the factorisation error of each backend.
    let indefinite = SparseMatrix::from_diagonal(&[Q::from_real(1.0), Q::from_real(-1.0)]);
    let k2 = SparseMatrix::<Q>::identity(2);
    let p2 = Pencil::new(&k2, &indefinite).unwrap();
    assert!(matches!(
        p2.solve(&Native, &opts(1)),
        Err(EigError::Factorization(_))
    ));
    assert!(matches!(
        p2.solve(&RealBlock, &opts(1)),
        Err(EigError::EmbeddedFactorization(_))
    ));
    assert!(matches!(
        p2.solve(&ComplexAdjoint, &opts(1)),
        Err(EigError::EmbeddedFactorization(
            qeig::EmbeddedFactorizationError::NotPositiveDefinite { .. }
        ))
    ));
}

/// A matrix that is not Hermitian (one triangle only, or one entry changed) is refused with
/// the entry furthest from Hermitian; rounding-level asymmetry is accepted.
#[test]
fn non_hermitian_matrices_are_refused_with_the_entry() {
    let (k_mat, s_mat) = pencil(93, 20);
    let with = |m: &SparseMatrix<Q>, keep: &dyn Fn(usize, usize) -> bool, change: Q| {
        let mut t = TripletMatrix::new(20, 20);
        for (i, j, v) in m.triplets().filter(|&(i, j, _)| keep(i, j)) {
            t.push(i, j, v).unwrap();
        }
        t.push(7, 3, change).unwrap(); // duplicates are summed
        t.to_csc()
    };
    let lower = with(&k_mat, &|i, j| i >= j, Q::from_real(0.0));
    match Pencil::new(&lower, &s_mat) {
        Err(EigError::NotHermitian {
            which, row, col, ..
        }) => {
            assert_eq!(which, "K");
            assert!(row != col && k_mat.get(row, col).abs() > 0.0);
        }
        other => panic!("lower triangle of K accepted: {other:?}"),
    }
    let changed = with(&s_mat, &|_, _| true, Q::new(0.0, 1e-3, 0.0, 0.0));
    match Pencil::new(&k_mat, &changed) {
        Err(EigError::NotHermitian {
            which,
            row,
            col,
            defect,
            ..
        }) => {
            assert_eq!(which, "S");
            assert!(
                (row, col) == (7, 3) || (row, col) == (3, 7),
                "({row}, {col})"
            );
            assert!((defect - 1e-3).abs() < 1e-12, "{defect}");
        }
        other => panic!("changed S accepted: {other:?}"),
    }
    let largest = k_mat.values().iter().fold(0.0f64, |l, v| l.max(v.abs()));
    let rounding = with(&k_mat, &|_, _| true, Q::from_real(1e-15 * largest));
    assert!(Pencil::new(&rounding, &s_mat).is_ok());
}

/// A basis that does not fit in the memory limit is refused before the iteration, with what
/// it needs; the memory figures of a run that fits are what it holds.
#[test]
fn basis_beyond_the_memory_limit_is_refused() {
    let (k_mat, s_mat) = pencil(7, 200);
    let p = Pencil::new(&k_mat, &s_mat).unwrap();
    // k = 4: 4 locked + max(8, 36) active + 1 continuation = 41 vectors of 200 quaternions.
    let options = |limit| LanczosOptions {
        memory_limit: Some(limit),
        ..LanczosOptions::new(4, Which::LargestMagnitude)
    };
    let needed = 41 * 200 * 32;
    match p.solve(&Native, &options(needed - 1)) {
        Err(EigError::BasisTooLarge(e)) => {
            assert_eq!(e.bytes_needed(), needed);
            assert_eq!((e.vectors, e.dimension), (41, 200));
            assert!(e.to_string().contains("fewer pairs"), "{e}");
        }
        other => panic!("expected BasisTooLarge, got {other:?}"),
    }
    let eig = p.solve(&Native, &options(needed)).unwrap();
    assert_eq!(eig.statistics.basis_bytes as u64, needed);
    let factor = qsparse::SparseCholesky::factorize(&s_mat).unwrap();
    assert_eq!(eig.statistics.factor_bytes, factor.stats().factor_bytes);
}

#[test]
fn small_problem_is_solved_completely() {
    // k = n: the Krylov space exhausts the whole space.
    let (k_mat, s_mat) = pencil(101, 12);
    let truth = dense_truth(&k_mat, &s_mat);
    let eig = Pencil::new(&k_mat, &s_mat)
        .unwrap()
        .solve(&Native, &LanczosOptions::new(12, Which::SmallestAlgebraic))
        .unwrap();
    let scale = truth.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (got, want) in eig.values.iter().zip(&truth.values) {
        assert!((got - want).abs() < 1e-9 * scale, "{got} vs {want}");
    }
}
