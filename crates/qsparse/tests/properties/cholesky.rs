//! The native supernodal Cholesky over real, complex and quaternion scalars: residuals of
//! random sparse HPD systems (one and many right-hand sides), the triangular halves
//! (`C⁻¹ A C⁻ᴴ = I`), refactorisation, agreement with faer's sparse Cholesky on the same matrix
//! and on the real-block and complex-adjoint embeddings, large supernodes (panel blocking and
//! the packed GEMM), solves on two threads against one, and typed errors for every kind of
//! bad input.

use faer::linalg::solvers::Solve;
use faer::{ColMut, Side};
use num_complex::Complex;
use proptest::prelude::*;
use proptest::sample::Index;
use qscalar::strategies::ScalarStrategy;
use qscalar::{Quat, Scalar};
use qsparse::embedding::{complex_adjoint_vector, from_complex_adjoint_vector};
use qsparse::strategies::{hpd_matrix, vector};
use qsparse::{
    CholeskyError, SolveThreads, SparseCholesky, SparseMatrix, SparseVector, SymbolicCholesky,
    TripletMatrix,
};

use crate::common::{
    Lcg, assert_close, assert_whitens, grid_connection_laplacian, relative_residual, to_faer,
    unit_from_components,
};

/// Bound on relative residuals `‖A x − b‖ / ‖b‖`.
const RESIDUAL: f64 = 1e-10;
/// Bound on the relative distance between two solutions of a system with `κ(A) ≲ 10⁴`.
const AGREEMENT: f64 = 1e-10;

/// An HPD matrix of size in `size` with `rhs` random right-hand sides (column-major).
fn system<T: ScalarStrategy>(
    size: core::ops::Range<usize>,
    density: f64,
    rhs: usize,
) -> impl Strategy<Value = (SparseMatrix<T>, Vec<T>)> {
    hpd_matrix::<T>(size, density).prop_flat_map(move |a| {
        let n = a.nrows();
        (Just(a), vector::<T>(n * rhs))
    })
}

fn solves_one_and_many<T: ScalarStrategy>(
    (a, rhs): (SparseMatrix<T>, Vec<T>),
) -> Result<(), TestCaseError> {
    let n = a.nrows();
    let chol = SparseCholesky::factorize(&a).unwrap();
    let x = chol.solve(&rhs[..n]).unwrap();
    let residual = relative_residual(&a, &x, &rhs[..n]);
    prop_assert!(residual < RESIDUAL, "one rhs: residual {residual:e}");
    let mut many = rhs.clone();
    let ncols = rhs.len() / n;
    chol.solve_many_in_place(&mut many, ncols).unwrap();
    for (x, b) in many.chunks_exact(n).zip(rhs.chunks_exact(n)) {
        let residual = relative_residual(&a, x, b);
        prop_assert!(residual < RESIDUAL, "many rhs: residual {residual:e}");
    }
    Ok(())
}

/// `solve_lower_in_place` then `solve_upper_in_place` solves `A x = b`, and column by column
/// `C⁻¹ A C⁻ᴴ = I`.
fn triangular_halves<T: ScalarStrategy>(
    (a, b): (SparseMatrix<T>, Vec<T>),
) -> Result<(), TestCaseError> {
    let chol = SparseCholesky::factorize(&a).unwrap();
    let mut x = b.clone();
    chol.solve_lower_in_place(&mut x).unwrap();
    chol.solve_upper_in_place(&mut x).unwrap();
    let residual = relative_residual(&a, &x, &b);
    prop_assert!(residual < RESIDUAL, "residual {residual:e}");
    assert_whitens(&chol, &a, AGREEMENT)
}

/// Refactorisation with new values `s A + D` (same pattern, `s > 0`, `D ≥ 0` diagonal), also
/// after a failed refactorisation with non-positive-definite values.
fn refactorizes<T: ScalarStrategy>(
    ((a, b), s, shift): ((SparseMatrix<T>, Vec<T>), f64, Vec<f64>),
) -> Result<(), TestCaseError> {
    let n = a.nrows();
    let d = SparseMatrix::from_diagonal(
        &shift[..n]
            .iter()
            .map(|&v| T::from_real(v))
            .collect::<Vec<_>>(),
    );
    let new = SparseMatrix::linear_combination(T::from_real(s), &a, T::one(), &d).unwrap();
    let mut negated = a.clone();
    negated.scale(-1.0);
    let mut chol = SparseCholesky::factorize(&a).unwrap();
    let failure = chol.refactorize(&negated);
    prop_assert!(
        matches!(failure, Err(CholeskyError::NotPositiveDefinite { .. })),
        "{failure:?}"
    );
    chol.refactorize(&new).unwrap();
    let x = chol.solve(&b).unwrap();
    let residual = relative_residual(&new, &x, &b);
    prop_assert!(residual < RESIDUAL, "residual {residual:e}");
    // A second factorisation sharing the symbolic analysis gives the same solution.
    let shared = SparseCholesky::factorize_with_symbolic(chol.symbolic().clone(), &new).unwrap();
    prop_assert_eq!(shared.solve(&b).unwrap(), x);
    Ok(())
}

/// The native solve equals faer's Cholesky solve on the real-block and the complex-adjoint
/// embedding of the same matrix.
fn agrees_with_faer_on_embeddings<T: ScalarStrategy>(
    (a, b): (SparseMatrix<T>, Vec<T>),
) -> Result<(), TestCaseError> {
    let x = SparseCholesky::factorize(&a).unwrap().solve(&b).unwrap();

    let block = a.to_real_block().sp_cholesky(Side::Lower).unwrap();
    let mut x_block = b.clone();
    block.solve_in_place(ColMut::from_slice_mut(T::as_reals_mut(&mut x_block)));
    assert_close(&x, &x_block, AGREEMENT)?;

    let chi = a.to_complex_adjoint().sp_cholesky(Side::Lower).unwrap();
    let mut x_chi = complex_adjoint_vector(&b);
    chi.solve_in_place(ColMut::from_slice_mut(&mut x_chi));
    assert_close(&x, &from_complex_adjoint_vector::<T>(&x_chi), AGREEMENT)
}

/// Adding `big·u` at `(i, j)` and its conjugate at `(j, i)`, with `big = Aᵢᵢ + Aⱼⱼ` and `|u| = 1`,
/// makes the principal `2 × 2` minor `AᵢᵢAⱼⱼ − |Aᵢⱼ + big u|²` negative (strict diagonal
/// dominance gives `|Aᵢⱼ| < min(Aᵢᵢ, Aⱼⱼ)`), while the diagonal stays positive.
fn indefinite_is_rejected<T: ScalarStrategy>(
    (a, i, j, u): (SparseMatrix<T>, Index, Index, T),
) -> Result<(), TestCaseError> {
    let n = a.nrows();
    let (i, j) = (i.index(n), j.index(n));
    prop_assume!(i != j && u.abs() > 0.1);
    let big = (a.get(i, i) + a.get(j, j)).re();
    let u = u.scale(big / u.abs());
    let perturbation = TripletMatrix::from_triplets(n, n, [(i, j, u), (j, i, u.conj())])
        .unwrap()
        .to_csc();
    let indefinite =
        SparseMatrix::linear_combination(T::one(), &a, T::one(), &perturbation).unwrap();
    match SparseCholesky::factorize(&indefinite) {
        Err(CholeskyError::NotPositiveDefinite { index, pivot }) => {
            prop_assert!(index < n);
            prop_assert!(pivot <= 0.0, "pivot {pivot}");
        }
        other => prop_assert!(false, "expected NotPositiveDefinite, got {other:?}"),
    }
    Ok(())
}

/// Negating one diagonal entry `Aₖₖ`: every principal submatrix without `k` stays strictly
/// diagonally dominant, so the first failing pivot is exactly `k`, and it is negative.
fn negative_diagonal_is_rejected_at_its_index<T: ScalarStrategy>(
    (a, k): (SparseMatrix<T>, Index),
) -> Result<(), TestCaseError> {
    let n = a.nrows();
    let k = k.index(n);
    let mut shift = vec![T::zero(); n];
    shift[k] = a.get(k, k).scale(-2.0);
    let negated = SparseMatrix::linear_combination(
        T::one(),
        &a,
        T::one(),
        &SparseMatrix::from_diagonal(&shift),
    )
    .unwrap();
    match SparseCholesky::factorize(&negated) {
        Err(CholeskyError::NotPositiveDefinite { index, pivot }) => {
            prop_assert_eq!(index, k);
            prop_assert!(pivot < 0.0, "pivot {pivot}");
        }
        other => prop_assert!(false, "expected NotPositiveDefinite, got {other:?}"),
    }
    Ok(())
}

/// A NaN or infinite component in a read (lower-triangle) entry is reported at that entry.
fn non_finite_is_rejected<T: ScalarStrategy>(
    (mut a, entry, component, bad): (SparseMatrix<T>, Index, Index, f64),
) -> Result<(), TestCaseError> {
    let lower: Vec<(usize, usize, usize)> = a
        .triplets()
        .enumerate()
        .filter(|&(_, (i, j, _))| i >= j)
        .map(|(k, (i, j, _))| (k, i, j))
        .collect();
    let (k, row, col) = lower[entry.index(lower.len())];
    T::as_reals_mut(&mut a.values_mut()[k..=k])[component.index(T::REAL_DIM)] = bad;
    prop_assert_eq!(
        SparseCholesky::factorize(&a).unwrap_err(),
        CholeskyError::NonFinite { row, col }
    );
    Ok(())
}

/// The factorisation on two threads gives exactly the one-thread factor (the same
/// operations; compared through one-thread solves, bit for bit), and the half-solves and the
/// full solve on two threads agree with one thread (the same sums in another order) and solve
/// the system; returns whether the tree split at all.
fn two_threads_agree<T: Scalar<Real = f64>>(a: &SparseMatrix<T>, b: &[T]) -> bool {
    let mut one = SparseCholesky::factorize(a).unwrap();
    one.set_solve_threads(SolveThreads::One);
    one.refactorize(a).unwrap();
    let mut two = one.clone();
    two.set_solve_threads(SolveThreads::Two);
    two.refactorize(a).unwrap();
    let mut factored_on_two = two.clone();
    factored_on_two.set_solve_threads(SolveThreads::One);
    assert_eq!(
        factored_on_two.solve(b).unwrap(),
        one.solve(b).unwrap(),
        "the factor computed on two threads differs"
    );
    for half in [
        SparseCholesky::<T>::solve_lower_in_place,
        SparseCholesky::<T>::solve_upper_in_place,
        SparseCholesky::<T>::solve_in_place,
    ] {
        let (mut x_one, mut x_two) = (b.to_vec(), b.to_vec());
        half(&one, &mut x_one).unwrap();
        half(&two, &mut x_two).unwrap();
        let distance = crate::common::relative_distance(&x_two, &x_one);
        assert!(distance < 1e-13, "two threads differ by {distance:e}");
    }
    let x = two.solve(b).unwrap();
    let residual = relative_residual(a, &x, b);
    assert!(residual < RESIDUAL, "residual {residual:e}");
    two.stats().split_columns.is_some()
}

/// The many-column half-solves give every column exactly what the one-column half-solve gives
/// it (the same operations in the same order), on one thread and on two; wrong lengths are
/// typed errors.
fn many_columns_are_single_columns<T: Scalar<Real = f64>>(
    a: &SparseMatrix<T>,
    rhs: &[T],
) -> Result<(), TestCaseError> {
    let n = a.nrows();
    let ncols = rhs.len() / n.max(1);
    let mut chol = SparseCholesky::factorize(a).unwrap();
    let mut work = Vec::new();
    for threads in [SolveThreads::One, SolveThreads::Two] {
        chol.set_solve_threads(threads);
        for lower in [true, false] {
            let mut many = rhs.to_vec();
            let mut single = rhs.to_vec();
            if lower {
                chol.solve_lower_many_in_place_with(&mut many, ncols, &mut work)
                    .unwrap();
            } else {
                chol.solve_upper_many_in_place_with(&mut many, ncols, &mut work)
                    .unwrap();
            }
            for column in single.chunks_exact_mut(n.max(1)) {
                if lower {
                    chol.solve_lower_in_place(column).unwrap();
                } else {
                    chol.solve_upper_in_place(column).unwrap();
                }
            }
            prop_assert!(
                many == single,
                "{ncols} columns, {threads:?}, lower {lower}: differs from one column at a time"
            );
        }
    }
    let mut short = vec![T::zero(); n * ncols + 1];
    prop_assert_eq!(
        chol.solve_lower_many_in_place_with(&mut short, ncols, &mut work),
        Err(CholeskyError::RhsDimension {
            expected: n * ncols,
            found: n * ncols + 1
        })
    );
    Ok(())
}

/// The 30 × 30 grid splits into two subtrees below a small top, and the two-thread solves
/// agree with the one-thread ones.
fn grid_two_threads<T: Scalar<Real = f64>>() {
    let a = grid_connection_laplacian::<T>(30);
    let n = a.nrows();
    let b: Vec<T> = Lcg(5).vector(n);
    assert!(two_threads_agree(&a, &b), "the grid's tree should split");
    let [first, second, top] = SparseCholesky::factorize(&a)
        .unwrap()
        .stats()
        .split_columns
        .expect("split");
    assert_eq!(first + second + top, n);
    assert!(
        top < n / 5 && first.min(second) > n / 5,
        "{first} {second} {top}"
    );
}

/// `C⁻¹ b` for `b` restricted to the rows `keep` says, sparse against dense, twice with one
/// workspace (it must be clean after a solve): equal to rounding, and every nonzero of the
/// dense result among the sparse result's rows.
fn sparse_right_hand_sides<T: Scalar<Real = f64>>(
    a: &SparseMatrix<T>,
    b: &[T],
    keep: &[bool],
) -> Result<(), TestCaseError> {
    let n = a.nrows();
    let chol = SparseCholesky::factorize(a).unwrap();
    let mut work = chol.sparse_solve_workspace();
    for round in 0..2 {
        let sparse: Vec<T> = (0..n)
            .map(|i| {
                if keep[(i + round) % keep.len()] {
                    b[i]
                } else {
                    T::zero()
                }
            })
            .collect();
        let mut dense = sparse.clone();
        chol.solve_lower_in_place(&mut dense).unwrap();
        let result = chol
            .solve_lower_sparse(&SparseVector::from_dense(&sparse), &mut work)
            .unwrap();
        prop_assert!(result.rows.windows(2).all(|w| w[0] < w[1]), "rows increase");
        let scale = dense.iter().map(|v| v.abs()).fold(1.0, f64::max);
        let full = result.to_dense(n);
        for (i, (x, y)) in full.iter().zip(&dense).enumerate() {
            prop_assert!(
                (*x - *y).abs() <= 1e-12 * scale,
                "round {round}, row {i}: {x:?} against {y:?}"
            );
        }
    }
    Ok(())
}

macro_rules! instantiate {
    ($($module:ident: $t:ty),*) => {$(
        mod $module {
            use super::*;

            proptest! {
                #![proptest_config(ProptestConfig::with_cases(64))]

                #[test]
                fn solves_sparse(input in system::<$t>(1..40, 0.15, 3)) {
                    solves_one_and_many(input)?;
                }

                /// Random patterns: about nine in ten split (forests and bushy trees).
                #[test]
                fn two_threads(input in system::<$t>(1..60, 0.1, 1)) {
                    two_threads_agree(&input.0, &input.1);
                }

                #[test]
                fn many_columns(input in (1..6usize).prop_flat_map(|ncols| system::<$t>(1..60, 0.1, ncols))) {
                    many_columns_are_single_columns(&input.0, &input.1)?;
                }

                #[test]
                fn sparse_rhs(
                    input in system::<$t>(1..60, 0.1, 1),
                    keep in proptest::collection::vec(proptest::bool::weighted(0.1), 1..8)
                ) {
                    sparse_right_hand_sides(&input.0, &input.1, &keep)?;
                }

                #[test]
                fn triangular_halves_and_congruence(input in system::<$t>(1..12, 0.3, 1)) {
                    triangular_halves(input)?;
                }

                #[test]
                fn refactorize(
                    input in (system::<$t>(1..30, 0.2, 1), 0.1..3.0f64, proptest::collection::vec(0.0..1.0f64, 30))
                ) {
                    refactorizes(input)?;
                }

                #[test]
                fn agrees_with_faer(input in system::<$t>(1..30, 0.2, 1)) {
                    agrees_with_faer_on_embeddings(input)?;
                }

                #[test]
                fn indefinite(
                    input in (hpd_matrix::<$t>(2..20, 0.2), any::<Index>(), any::<Index>(), <$t>::strategy(1.0))
                ) {
                    indefinite_is_rejected(input)?;
                }

                #[test]
                fn negative_diagonal(input in (hpd_matrix::<$t>(1..20, 0.2), any::<Index>())) {
                    negative_diagonal_is_rejected_at_its_index(input)?;
                }

                #[test]
                fn non_finite(
                    input in (
                        hpd_matrix::<$t>(1..20, 0.2),
                        any::<Index>(),
                        any::<Index>(),
                        prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)],
                    )
                ) {
                    non_finite_is_rejected(input)?;
                }
            }

            proptest! {
                #![proptest_config(ProptestConfig::with_cases(6))]

                /// Dense-ish patterns give supernodes wider than one 32-column panel.
                #[test]
                fn solves_dense_ish(input in system::<$t>(40..90, 0.5, 2)) {
                    solves_one_and_many(input)?;
                }
            }

            #[test]
            fn grid_on_two_threads() {
                grid_two_threads::<$t>();
            }

            /// The grid's tree splits, so the two-thread many-column path runs its buffers.
            #[test]
            fn grid_many_columns_on_two_threads() {
                let a = grid_connection_laplacian::<$t>(30);
                let rhs: Vec<$t> = Lcg(9).vector(3 * a.nrows());
                many_columns_are_single_columns(&a, &rhs).unwrap();
            }

            /// The grid's supernodes are renumbered for two threads: ascending order must
            /// still be an elimination order for the sparse solve.
            #[test]
            fn grid_sparse_right_hand_sides() {
                let a = grid_connection_laplacian::<$t>(30);
                let b: Vec<$t> = Lcg(5).vector(a.nrows());
                let mut keep = vec![false; 97];
                keep[3] = true;
                keep[50] = true;
                sparse_right_hand_sides(&a, &b, &keep).unwrap();
            }

            #[test]
            fn grid_with_large_supernodes() {
                large_supernodes::<$t>();
            }

            #[test]
            fn empty_and_zero_matrices() {
                empty_and_zero::<$t>();
            }
        }
    )*};
}

instantiate!(real: f64, complex: Complex<f64>, quaternion: Quat<f64>);

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The `f64` instance agrees with faer's sparse Cholesky of the very same matrix.
    #[test]
    fn real_instance_agrees_with_faer((a, b) in system::<f64>(1..40, 0.2, 1)) {
        let x = SparseCholesky::factorize(&a).unwrap().solve(&b).unwrap();
        let llt = to_faer(&a).sp_cholesky(Side::Lower).unwrap();
        let mut expected = b.clone();
        llt.solve_in_place(ColMut::from_slice_mut(&mut expected));
        assert_close(&x, &expected, AGREEMENT)?;
    }
}

/// Grid side: AMD's top separators of a 60 × 60 grid give supernodes ~90 columns wide.
const GRID_SIDE: usize = 60;

/// On the 60 × 60 grid connection Laplacian the widest supernode spans more than two
/// 32-column panels, so the blocked factorisation of `cholesky/dense.rs` runs its trailing
/// updates, and these (at least `32 · 32 · 32 ≥ 16384` scalar products for a width `w ≥ 64`)
/// take the packed-GEMM path for every scalar type. Checked: residuals for 1 and 3 right-hand
/// sides, and agreement with faer's sparse Cholesky of the real-block embedding.
fn large_supernodes<T: Scalar<Real = f64>>() {
    let a = grid_connection_laplacian::<T>(GRID_SIDE);
    let n = a.nrows();
    let chol = SparseCholesky::factorize(&a).unwrap();
    let stats = chol.stats();
    assert!(stats.max_supernode_width >= 64, "{stats:?}");

    let mut rng = Lcg(11);
    let b: Vec<T> = rng.vector(3 * n);
    let x = chol.solve(&b[..n]).unwrap();
    let residual = relative_residual(&a, &x, &b[..n]);
    assert!(residual < RESIDUAL, "residual {residual:e}");
    let mut many = b.clone();
    chol.solve_many_in_place(&mut many, 3).unwrap();
    for (x, b) in many.chunks_exact(n).zip(b.chunks_exact(n)) {
        let residual = relative_residual(&a, x, b);
        assert!(residual < RESIDUAL, "residual {residual:e}");
    }

    let llt = a.to_real_block().sp_cholesky(Side::Lower).unwrap();
    let mut expected = b[..n].to_vec();
    llt.solve_in_place(ColMut::from_slice_mut(T::as_reals_mut(&mut expected)));
    let distance = crate::common::relative_distance(&x, &expected);
    assert!(distance < AGREEMENT, "distance to faer {distance:e}");
}

/// The empty matrix factors (vacuously positive definite); zero matrices, with or without a
/// stored diagonal, fail with a zero pivot.
fn empty_and_zero<T: Scalar<Real = f64>>() {
    let empty = SparseCholesky::factorize(&SparseMatrix::<T>::zeros(0, 0)).unwrap();
    assert_eq!(empty.solve(&[]).unwrap(), Vec::<T>::new());
    for n in [1, 5] {
        for zero in [
            SparseMatrix::<T>::zeros(n, n),
            SparseMatrix::from_diagonal(&vec![T::zero(); n]),
        ] {
            match SparseCholesky::factorize(&zero) {
                Err(CholeskyError::NotPositiveDefinite { index, pivot }) => {
                    assert!(index < n);
                    assert_eq!(pivot, 0.0);
                }
                other => panic!("expected NotPositiveDefinite, got {other:?}"),
            }
        }
    }
}

#[test]
fn not_square() {
    let a = SparseMatrix::<Quat<f64>>::zeros(2, 3);
    let expected = CholeskyError::NotSquare { nrows: 2, ncols: 3 };
    assert_eq!(SparseCholesky::factorize(&a).unwrap_err(), expected);
    assert_eq!(SymbolicCholesky::analyze(&a).unwrap_err(), expected);
}

#[test]
fn rhs_dimension() {
    let a = grid_connection_laplacian::<Quat<f64>>(3);
    let chol = SparseCholesky::factorize(&a).unwrap();
    let wrong = |found| CholeskyError::RhsDimension { expected: 9, found };
    let mut short = vec![Quat::default(); 8];
    assert_eq!(chol.solve(&short).unwrap_err(), wrong(8));
    assert_eq!(chol.solve_in_place(&mut short).unwrap_err(), wrong(8));
    assert_eq!(chol.solve_lower_in_place(&mut short).unwrap_err(), wrong(8));
    assert_eq!(chol.solve_upper_in_place(&mut short).unwrap_err(), wrong(8));
    let mut many = vec![Quat::default(); 17];
    assert_eq!(
        chol.solve_many_in_place(&mut many, 2).unwrap_err(),
        CholeskyError::RhsDimension {
            expected: 18,
            found: 17
        }
    );
}

/// Refactorising (or factorising with a shared analysis) a matrix of another pattern or size is
/// rejected; an equal pattern with other values is accepted.
#[test]
fn pattern_mismatch() {
    let a = grid_connection_laplacian::<Quat<f64>>(4);
    let mut chol = SparseCholesky::factorize(&a).unwrap();
    let symbolic = chol.symbolic().clone();
    let diagonal_only = SparseMatrix::from_diagonal(&vec![Quat::from_real(1.0); 16]);
    let other_size = grid_connection_laplacian::<Quat<f64>>(3);
    for other in [&diagonal_only, &other_size] {
        assert_eq!(
            chol.refactorize(other).unwrap_err(),
            CholeskyError::PatternMismatch
        );
        assert_eq!(
            SparseCholesky::factorize_with_symbolic(symbolic.clone(), other).unwrap_err(),
            CholeskyError::PatternMismatch
        );
    }
    let mut scaled = a.clone();
    scaled.scale(2.0);
    chol.refactorize(&scaled).unwrap();
    let b: Vec<Quat<f64>> = Lcg(3).vector(16);
    assert!(relative_residual(&scaled, &chol.solve(&b).unwrap(), &b) < RESIDUAL);
    // Also a pattern with a unit transport on every edge: same pattern, accepted.
    let unit: Quat<f64> = unit_from_components(&[1.0, 2.0, 3.0, 4.0]);
    let rotated = a.map(|v| if v.re() > 0.0 { v } else { v * unit });
    assert!(SparseCholesky::factorize_with_symbolic(symbolic, &rotated).is_ok());
}
