//! A contiguous block of vectors and the Gram–Schmidt kernels of the Lanczos iteration.
//!
//! Vectors form a right module over the scalar `V` (docs/ARCHITECTURE.md, "Conventions"), so
//! projecting `w` onto the span of orthonormal `v₀ … v_{m−1}` is `w ← w − Σᵢ vᵢ ⟨vᵢ, w⟩` with
//! the coefficient on the right. The orthogonalisation is memory-bound (the basis is far
//! larger than the caches), so a pass is *modified* Gram–Schmidt, column by column, with the
//! update by `vᵢ` and the coefficient of `vᵢ₊₁` fused in one sweep: each basis vector is read
//! from memory once per pass (its second read, and `w`, come from cache), half the traffic of
//! a classical pass through a matrix product (`Vᵀ w`, then `V G`), which streams the basis
//! twice. The kernels ([`vector::inner_long`], [`vector::axpy_then_inner`]) work on the real
//! component layout ([`Scalar::as_reals`]): writing `e₀ … e_{R−1}` for the units of `V`
//! (`1, i, j, k` for quaternions, `R = REAL_DIM`), `⟨v, w⟩` is `Σ_κλ S_κλ conj(e_κ) e_λ` with
//! the real outer products `S_κλ = Σₗ vₗ,κ wₗ,λ`, and `(v c)_λ = Σ_κ v_κ (e_κ c)_λ`; both are
//! pure multiply-adds over independent lanes.

use std::marker::PhantomData;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use faer::MatRef;
use qscalar::Scalar;
use qsparse::vector;

/// `n`-vectors stored contiguously column after column.
#[derive(Debug, Clone)]
pub(crate) struct Basis<V> {
    n: usize,
    data: Vec<V>,
}

impl<V: Scalar<Real = f64>> Basis<V> {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            n,
            data: Vec::new(),
        }
    }

    pub(crate) fn cols(&self) -> usize {
        self.data.len().checked_div(self.n).unwrap_or(0)
    }

    pub(crate) fn col(&self, i: usize) -> &[V] {
        &self.data[i * self.n..(i + 1) * self.n]
    }

    pub(crate) fn push(&mut self, v: &[V]) {
        self.data.extend_from_slice(v);
    }

    pub(crate) fn truncate(&mut self, cols: usize) {
        self.data.truncate(cols * self.n);
    }

    /// Columns `start..start + count` as a real `(R n) × count` matrix.
    pub(crate) fn reals(&self, start: usize, count: usize) -> MatRef<'_, f64> {
        let slice = &self.data[start * self.n..(start + count) * self.n];
        MatRef::from_column_major_slice(V::as_reals(slice), V::REAL_DIM * self.n, count)
    }
}

/// The Gram–Schmidt passes (no workspace: the kernels allocate nothing).
#[derive(Debug)]
pub(crate) struct GramSchmidt<V>(PhantomData<V>);

impl<V: Scalar<Real = f64>> GramSchmidt<V> {
    pub(crate) fn new() -> Self {
        Self(PhantomData)
    }

    /// One modified Gram–Schmidt pass against columns `0..m` of `basis` (orthonormal):
    /// `w ← w − vᵢ ⟨vᵢ, w⟩` for `i = 0 … m−1` in turn, adding the coefficients to `coef[i]`.
    ///
    /// Column by column, each update `w −= vᵢ cᵢ` fused with the next coefficient
    /// `⟨vᵢ₊₁, w⟩` in one sweep: each basis vector is read from memory once per pass (the
    /// second read finds it in cache), where a classical pass reads the whole basis twice.
    ///
    /// Long vectors are split by rows between two threads (the sweep is bound by the latency
    /// of its loads, so two cores nearly halve it): each sweeps its rows, and after every
    /// column the two partial coefficients are exchanged through [`Exchange`] and added in a
    /// fixed order (first half, then second), so that both threads use the same coefficient
    /// and the result does not depend on timing.
    fn pass(&self, basis: &Basis<V>, m: usize, w: &mut [V], coef: &mut [V]) {
        let two_threads =
            w.len() * V::REAL_DIM >= PARALLEL_REALS && qsparse::threads::second_thread_allowed();
        pass(basis, m, w, coef, two_threads);
    }

    /// Orthogonalises `w` against columns `0..m` of `basis`, with a second pass when the first
    /// one removed more than `1 − 1/√2` of the norm ("twice is enough", Daniel–Gragg–Kaufman–
    /// Stewart). `coef[..m]` receives the total coefficients. Returns `‖w‖` before and after.
    pub(crate) fn orthogonalize(
        &mut self,
        basis: &Basis<V>,
        m: usize,
        w: &mut [V],
        coef: &mut Vec<V>,
    ) -> (f64, f64) {
        coef.clear();
        coef.resize(m, V::zero());
        let before = vector::norm(w);
        let mut last = before;
        for _ in 0..3 {
            self.pass(basis, m, w, coef);
            let now = vector::norm(w);
            let stop = now > std::f64::consts::FRAC_1_SQRT_2 * last;
            last = now;
            if stop {
                break;
            }
        }
        (before, last)
    }
}

/// Vectors of at least this many reals are orthogonalised on two threads: below it, the
/// exchange after every column costs more than half a column's sweep saves.
const PARALLEL_REALS: usize = 1 << 15;

/// The meeting point of the two threads of a Gram–Schmidt pass: per thread, a partial
/// coefficient for each column parity (double buffering: a thread can be at most one column
/// ahead) and the number of partials published so far.
struct Exchange {
    partials: [[[AtomicU64; 4]; 2]; 2],
    published: [AtomicUsize; 2],
}

impl Exchange {
    fn new() -> Self {
        Self {
            partials: Default::default(),
            published: Default::default(),
        }
    }

    /// Publishes thread `half`'s partial coefficient of column `i`, waits for the other
    /// thread's, and returns their sum (first half + second half, on both threads).
    fn total<V: Scalar<Real = f64>>(&self, half: usize, i: usize, partial: V) -> V {
        let slot = &self.partials[half][i % 2];
        for (cell, &x) in slot.iter().zip(V::as_reals(&[partial])) {
            cell.store(x.to_bits(), Ordering::Relaxed);
        }
        self.published[half].store(i + 1, Ordering::Release);
        let other = 1 - half;
        let mut spins = 0u32;
        while self.published[other].load(Ordering::Acquire) <= i {
            spins += 1;
            if spins < 1 << 12 {
                std::hint::spin_loop();
            } else {
                // The other thread is descheduled (a busy machine): give it the core.
                std::thread::yield_now();
            }
        }
        let mut theirs = [V::zero()];
        for (x, cell) in V::as_reals_mut(&mut theirs)
            .iter_mut()
            .zip(&self.partials[other][i % 2])
        {
            *x = f64::from_bits(cell.load(Ordering::Relaxed));
        }
        let (a, b) = if half == 0 {
            (partial, theirs[0])
        } else {
            (theirs[0], partial)
        };
        a + b
    }
}

/// [`GramSchmidt::pass`], on two threads if `two_threads`.
fn pass<V: Scalar<Real = f64>>(
    basis: &Basis<V>,
    m: usize,
    w: &mut [V],
    coef: &mut [V],
    two_threads: bool,
) {
    if m == 0 {
        return;
    }
    let n = w.len();
    if !two_threads {
        sweep(basis, m, 0..n, w, Some(coef), |_, c| c);
        return;
    }
    let split = n / 2;
    let (first, second) = w.split_at_mut(split);
    let exchange = Exchange::new();
    let exchange = &exchange;
    std::thread::scope(|scope| {
        scope.spawn(|| {
            let _abandon = Abandon(&exchange.published[1]);
            sweep(basis, m, split..n, second, None, |i, c| {
                exchange.total(1, i, c)
            });
        });
        let _abandon = Abandon(&exchange.published[0]);
        sweep(basis, m, 0..split, first, Some(coef), |i, c| {
            exchange.total(0, i, c)
        });
    });
}

/// The fused modified Gram–Schmidt sweep over the rows `rows` (held by `w`) of columns `0..m`;
/// `total(i, partial)` turns the partial coefficient of column `i` over these rows into the
/// full one. Adds the coefficients to `coef` if given.
fn sweep<V: Scalar<Real = f64>>(
    basis: &Basis<V>,
    m: usize,
    rows: std::ops::Range<usize>,
    w: &mut [V],
    mut coef: Option<&mut [V]>,
    total: impl Fn(usize, V) -> V,
) {
    let column = |i: usize| &basis.col(i)[rows.clone()];
    let mut c = total(0, vector::inner_long(column(0), w));
    for i in 0..m {
        if let Some(coef) = coef.as_deref_mut() {
            coef[i] += c;
        }
        let next = (i + 1 < m).then(|| column(i + 1));
        let partial = update_then_inner(w, column(i), V::zero() - c, next);
        if i + 1 < m {
            c = total(i + 1, partial);
        }
    }
}

/// Marks a thread's side of an [`Exchange`] as abandoned if the thread panics, so that the
/// other thread stops waiting (and the scope then propagates the panic) instead of hanging.
struct Abandon<'a>(&'a AtomicUsize);

impl Drop for Abandon<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.store(usize::MAX, Ordering::Release);
        }
    }
}

/// `w ← w + v c`, then `⟨next, w⟩` (zero without `next`), in one sweep over the vectors.
fn update_then_inner<V: Scalar<Real = f64>>(w: &mut [V], v: &[V], c: V, next: Option<&[V]>) -> V {
    match next {
        Some(next) => vector::axpy_then_inner(w, v, c, next),
        None => {
            vector::axpy(w, v, c);
            V::zero()
        }
    }
}

/// Appends to `basis` the normalised component of `v` orthogonal to all its columns, if that
/// component is not negligible (`‖v⊥‖ > 1e−8 ‖v‖`); returns whether it was appended.
pub(crate) fn append_orthonormal<V: Scalar<Real = f64>>(
    basis: &mut Basis<V>,
    gs: &mut GramSchmidt<V>,
    v: &mut [V],
    coef: &mut Vec<V>,
) -> bool {
    let (before, after) = gs.orthogonalize(basis, basis.cols(), v, coef);
    if after.is_nan() || after <= 1e-8 * before || after == 0.0 {
        return false;
    }
    vector::scale(v, 1.0 / after);
    basis.push(v);
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use qscalar::{Complex, Quat};

    /// The kernels of a pass agree with the plain `qsparse` ones, remainders included.
    fn check<V: Scalar<Real = f64>>() {
        let mut rng = qscalar::random::SplitMix64::new(7);
        for n in [0usize, 1, 2, 3, 5, 8, 13, 64, 101] {
            let (mut v, mut w, mut next) =
                (vec![V::zero(); n], vec![V::zero(); n], vec![V::zero(); n]);
            rng.fill_symmetric(&mut v);
            rng.fill_symmetric(&mut w);
            rng.fill_symmetric(&mut next);
            let mut c = [V::zero()];
            rng.fill_symmetric(&mut c);
            let scale = 1.0 + n as f64;
            assert!((vector::inner_long(&v, &w) - vector::inner(&v, &w)).abs() <= 1e-13 * scale);
            let mut expected = w.clone();
            vector::axpy(&mut expected, &v, c[0]);
            let expected_inner = vector::inner(&next, &expected);
            let got = update_then_inner(&mut w, &v, c[0], Some(&next));
            assert!((got - expected_inner).abs() <= 1e-13 * scale);
            for (a, b) in w.iter().zip(&expected) {
                assert!((*a - *b).abs() <= 1e-14 * scale);
            }
        }
    }

    #[test]
    fn kernels_match_reference() {
        check::<f64>();
        check::<Complex<f64>>();
        check::<Quat<f64>>();
    }

    /// The two-thread pass gives the one-thread result up to rounding, for vectors long
    /// enough to take it by default.
    fn two_threads_match_one<V: Scalar<Real = f64>>() {
        let n = PARALLEL_REALS / V::REAL_DIM + 3;
        let mut rng = qscalar::random::SplitMix64::new(5);
        let mut basis = Basis::<V>::new(n);
        let mut gs = GramSchmidt::new();
        let mut coef = Vec::new();
        for _ in 0..5 {
            let mut v = vec![V::zero(); n];
            rng.fill_symmetric(&mut v);
            assert!(append_orthonormal(&mut basis, &mut gs, &mut v, &mut coef));
        }
        let mut w = vec![V::zero(); n];
        rng.fill_symmetric(&mut w);
        let (mut one, mut two) = (w.clone(), w);
        let (mut coef_one, mut coef_two) = (vec![V::zero(); 5], vec![V::zero(); 5]);
        pass(&basis, 5, &mut one, &mut coef_one, false);
        pass(&basis, 5, &mut two, &mut coef_two, true);
        for (a, b) in coef_one.iter().zip(&coef_two) {
            assert!((*a - *b).abs() < 1e-12, "coefficients differ");
        }
        for (a, b) in one.iter().zip(&two) {
            assert!((*a - *b).abs() < 1e-12, "vectors differ");
        }
        for i in 0..5 {
            assert!(vector::inner(basis.col(i), &two).abs() < 1e-12);
        }
    }

    #[test]
    fn two_thread_pass() {
        two_threads_match_one::<f64>();
        two_threads_match_one::<Complex<f64>>();
        two_threads_match_one::<Quat<f64>>();
    }

    #[test]
    fn orthogonalize_gives_orthonormal_complement() {
        let n = 37;
        let mut rng = qscalar::random::SplitMix64::new(3);
        let mut basis = Basis::<Quat<f64>>::new(n);
        let mut gs = GramSchmidt::new();
        let mut coef = Vec::new();
        for _ in 0..6 {
            let mut v = vec![Quat::from_real(0.0); n];
            rng.fill_symmetric(&mut v);
            assert!(append_orthonormal(&mut basis, &mut gs, &mut v, &mut coef));
        }
        for a in 0..6 {
            for b in 0..6 {
                let g = vector::inner(basis.col(a), basis.col(b));
                let expected = if a == b { 1.0 } else { 0.0 };
                assert!((g - Quat::from_real(expected)).abs() < 1e-13);
            }
        }
    }
}
