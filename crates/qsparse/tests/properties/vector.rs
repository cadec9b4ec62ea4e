//! The vector kernels (plain, two-column and fused, with their runtime-dispatched
//! quaternion paths, and the real-coefficient ones) against entry-by-entry scalar arithmetic:
//! `g + a x + b y`, `Σ conj(aᵣ) gᵣ`, `g + a r`, `Re Σ conj(aᵣ) gᵣ`, `sqrt(Σ |aᵣ|²)`.

use num_complex::Complex;
use proptest::prelude::*;
use qscalar::Quat;
use qscalar::strategies::ScalarStrategy;
use qsparse::SparseVector;
use qsparse::strategies::vector;
use qsparse::vector::{
    axpy, axpy_real, axpy_two, axpy_two_then_inner_two, blocked_len, from_blocked,
    gather_from_blocked, inner, inner_two, norm, real_inner, scatter_to_blocked, to_blocked,
};

const TOL: f64 = 1e-12;

/// Four vectors of one length (0 to 40, so that the lane loops of every kernel, up to sixteen
/// entries at a time, run whole chunks and a remainder) and two coefficients.
fn inputs<T: ScalarStrategy>() -> impl Strategy<Value = ([Vec<T>; 4], T, T)> {
    (0..41usize).prop_flat_map(|n| {
        (
            [
                vector::<T>(n),
                vector::<T>(n),
                vector::<T>(n),
                vector::<T>(n),
            ],
            T::strategy(4.0),
            T::strategy(4.0),
        )
    })
}

fn naive_inner<T: ScalarStrategy>(a: &[T], g: &[T]) -> T {
    a.iter()
        .zip(g)
        .fold(T::zero(), |s, (&x, &y)| s + x.conj() * y)
}

fn close<T: ScalarStrategy>(x: T, y: T, scale: f64) -> bool {
    (x - y).abs2().sqrt() <= TOL * (1.0 + scale)
}

fn kernels_match_scalar_arithmetic<T: ScalarStrategy>(
    ([g, a, b, next], x, y): ([Vec<T>; 4], T, T),
) -> Result<(), TestCaseError> {
    let scale = [&g, &a, &b, &next]
        .iter()
        .flat_map(|v| v.iter())
        .map(|v| v.abs2())
        .sum::<f64>()
        * (1.0 + x.abs2() + y.abs2());

    let mut two = g.clone();
    axpy_two(&mut two, &a, &b, x, y);
    let mut one = g.clone();
    axpy(&mut one, &a, x);
    for r in 0..g.len() {
        let expected = g[r] + a[r] * x + b[r] * y;
        prop_assert!(close(two[r], expected, scale), "axpy_two, entry {r}");
        prop_assert!(close(one[r], g[r] + a[r] * x, scale), "axpy, entry {r}");
    }

    let (ia, ib) = inner_two(&a, &b, &g);
    prop_assert!(close(ia, naive_inner(&a, &g), scale));
    prop_assert!(close(ib, naive_inner(&b, &g), scale));
    prop_assert!(close(inner(&a, &g), naive_inner(&a, &g), scale));
    let as_scalar = |x: f64| T::from_real(x);
    prop_assert!(
        close(
            as_scalar(real_inner(&a, &g)),
            as_scalar(naive_inner(&a, &g).re()),
            scale
        ),
        "real_inner"
    );
    let squares: f64 = a.iter().map(|v| v.abs2()).sum();
    prop_assert!(
        close(as_scalar(norm(&a)), as_scalar(squares.sqrt()), scale),
        "norm"
    );
    let r = x.re();
    let mut real = g.clone();
    axpy_real(&mut real, &a, r);
    for i in 0..g.len() {
        prop_assert!(
            close(real[i], g[i] + a[i] * T::from_real(r), scale),
            "axpy_real, entry {i}"
        );
    }

    // The pair step of a Gram–Schmidt sweep, on vectors in the blocked layout: the update by
    // `a` and `b`, then the coefficients of `next` and `a` from the updated vector.
    let blocked = |v: &[T]| {
        let mut out = vec![T::zero(); blocked_len::<T>(v.len())];
        to_blocked(v, &mut out);
        out
    };
    let (mut fused_blocked, a_blocked) = (blocked(&g), blocked(&a));
    let [c_next, c_a] = axpy_two_then_inner_two(
        &mut fused_blocked,
        [&a_blocked, &blocked(&b)],
        [x, y],
        [&blocked(&next), &a_blocked],
    );
    let mut fused = g.clone();
    from_blocked(&fused_blocked, &mut fused);
    prop_assert!(close(c_next, naive_inner(&next, &two), scale));
    prop_assert!(close(c_a, naive_inner(&a, &two), scale));
    for r in 0..g.len() {
        prop_assert!(
            close(fused[r], two[r], scale),
            "axpy_two_then_inner_two, entry {r}"
        );
    }
    Ok(())
}

/// Gathering rows from the blocked layout picks the entries of the ordinary vector; scattering
/// them back (doubled) changes exactly those rows.
fn gather_and_scatter_address_rows<T: ScalarStrategy>(
    (x, picks): (Vec<T>, Vec<prop::sample::Index>),
) -> Result<(), TestCaseError> {
    let mut rows: Vec<usize> = picks.iter().map(|p| p.index(x.len().max(1))).collect();
    rows.retain(|&r| r < x.len());
    rows.sort_unstable();
    rows.dedup();
    let mut blocked = vec![T::zero(); blocked_len::<T>(x.len())];
    to_blocked(&x, &mut blocked);
    let mut gathered = vec![T::zero(); rows.len()];
    gather_from_blocked(&blocked, &rows, &mut gathered);
    for (t, &r) in rows.iter().enumerate() {
        prop_assert_eq!(gathered[t], x[r]);
    }
    let doubled: Vec<T> = gathered.iter().map(|&v| v + v).collect();
    scatter_to_blocked(&doubled, &rows, &mut blocked);
    let mut back = vec![T::zero(); x.len()];
    from_blocked(&blocked, &mut back);
    for (r, (&new, &old)) in back.iter().zip(&x).enumerate() {
        let expected = if rows.binary_search(&r).is_ok() {
            old + old
        } else {
            old
        };
        prop_assert_eq!(new, expected, "row {}", r);
    }
    Ok(())
}

fn rows_of<T: ScalarStrategy>() -> impl Strategy<Value = (Vec<T>, Vec<prop::sample::Index>)> {
    (0..41usize).prop_flat_map(|n| {
        (
            vector::<T>(n),
            prop::collection::vec(any::<prop::sample::Index>(), 0..12),
        )
    })
}

proptest! {
    #[test]
    fn gather_and_scatter_real(input in rows_of::<f64>()) {
        gather_and_scatter_address_rows(input)?;
    }

    #[test]
    fn gather_and_scatter_quaternion(input in rows_of::<Quat<f64>>()) {
        gather_and_scatter_address_rows(input)?;
    }

    #[test]
    fn real_kernels(input in inputs::<f64>()) {
        kernels_match_scalar_arithmetic(input)?;
    }

    #[test]
    fn complex_kernels(input in inputs::<Complex<f64>>()) {
        kernels_match_scalar_arithmetic(input)?;
    }

    #[test]
    fn quaternion_kernels(input in inputs::<Quat<f64>>()) {
        kernels_match_scalar_arithmetic(input)?;
    }
}

/// Two sparse vectors of one dimension (0 to 30) with random supports, and a coefficient.
fn sparse_pair<T: ScalarStrategy>() -> impl Strategy<Value = (Vec<T>, Vec<T>, T)> {
    (0..31usize).prop_flat_map(|n| {
        let sparse = move || {
            (vector::<T>(n), proptest::collection::vec(any::<bool>(), n)).prop_map(|(v, keep)| {
                v.into_iter()
                    .zip(keep)
                    .map(|(x, k)| if k { x } else { T::zero() })
                    .collect::<Vec<T>>()
            })
        };
        (sparse(), sparse(), T::strategy(4.0))
    })
}

fn sparse_operations_match_dense<T: ScalarStrategy>((a, b, c): (Vec<T>, Vec<T>, T)) {
    let (x, y) = (SparseVector::from_dense(&a), SparseVector::from_dense(&b));
    let scale = 1.0 + norm(&a) * norm(&b);
    assert!(close(x.inner_sparse(&y), naive_inner(&a, &b), scale));
    let combined = x.minus_times(&y, c);
    assert!(
        combined.rows.windows(2).all(|w| w[0] < w[1]),
        "rows increase"
    );
    let want: Vec<T> = a.iter().zip(&b).map(|(&p, &q)| p - q * c).collect();
    let got = combined.to_dense(a.len());
    for (g, w) in got.iter().zip(&want) {
        assert!(close(*g, *w, 1.0 + norm(&a) + norm(&b) * c.abs()));
    }
}

proptest! {
    #[test]
    fn sparse_vector_inner_and_combination_match_dense_real(input in sparse_pair::<f64>()) {
        sparse_operations_match_dense(input);
    }

    #[test]
    fn sparse_vector_inner_and_combination_match_dense_quaternion(
        input in sparse_pair::<Quat<f64>>()
    ) {
        sparse_operations_match_dense(input);
    }

    #[test]
    fn sparse_vector_inner_and_combination_match_dense_complex(
        input in sparse_pair::<Complex<f64>>()
    ) {
        sparse_operations_match_dense(input);
    }
}
