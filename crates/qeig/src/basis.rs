//! A contiguous block of vectors and the Gram–Schmidt kernels of the Lanczos iteration.
//!
//! Vectors form a right module over the scalar `V` (DESIGN.md §2), so projecting `w` onto the
//! span of orthonormal `v₀ … v_{m−1}` is `w ← w − Σᵢ vᵢ ⟨vᵢ, w⟩` with the coefficient on the
//! right. The orthogonalisation is memory-bound (the basis is far larger than the caches), so
//! a pass is *modified* Gram–Schmidt, column by column, with the update by `vᵢ` and the
//! coefficient of `vᵢ₊₁` fused in one sweep: each basis vector is read from memory once per
//! pass (its second read, and `w`, come from cache), half the traffic of a classical pass
//! through a matrix product (`Vᵀ w`, then `V G`), which streams the basis twice. The kernels
//! work on the real component layout ([`Scalar::as_reals`]): writing `e₀ … e_{R−1}` for the
//! units of `V` (`1, i, j, k` for quaternions, `R = REAL_DIM`), `⟨v, w⟩` is
//! `Σ_κλ S_κλ conj(e_κ) e_λ` with the real outer products `S_κλ = Σₗ vₗ,κ wₗ,λ`, and
//! `(v c)_λ = Σ_κ v_κ (e_κ c)_λ`; both are pure multiply-adds over `8 R` independent lanes,
//! the same code for `f64`, complex numbers and quaternions.

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
    let mut c = total(0, inner(column(0), w));
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

/// `⟨v, w⟩ = Σ conj(vₗ) wₗ` through the real component layout with `8 R` independent
/// accumulators (the real `R × R` outer products `S_κλ = Σₗ vₗ,κ wₗ,λ`, combined once as
/// `Σ_κλ S_κλ conj(e_κ) e_λ`), so that the loop is bound by memory, not by the latency of a
/// single accumulation chain (which limits a plain dot product over `f64` or complex numbers).
pub(crate) fn inner<V: Scalar<Real = f64>>(v: &[V], w: &[V]) -> V {
    let (a, b) = (V::as_reals(v), V::as_reals(w));
    let s: [[f64; 4]; 4] = match V::REAL_DIM {
        1 => widen(outer_products::<1>(a, b)),
        2 => widen(outer_products::<2>(a, b)),
        4 => widen(outer_products::<4>(a, b)),
        _ => return v.iter().zip(w).map(|(&x, &y)| x.conj() * y).sum(),
    };
    vector::combine_outer_products(&s)
}

/// `w ← w + v c`, then `⟨next, w⟩` (zero without `next`), in one sweep over the vectors.
pub(crate) fn update_then_inner<V: Scalar<Real = f64>>(
    w: &mut [V],
    v: &[V],
    c: V,
    next: Option<&[V]>,
) -> V {
    let Some(next) = next else {
        vector::axpy(w, v, c);
        return V::zero();
    };
    if V::REAL_DIM == 4 {
        // Quaternions: qsparse's array-of-structures kernel (one quaternion per register).
        return vector::axpy_then_inner(w, v, c, next);
    }
    let rows = vector::unit_products(c);
    let (wr, vr, nr) = (V::as_reals_mut(w), V::as_reals(v), V::as_reals(next));
    let s: [[f64; 4]; 4] = match V::REAL_DIM {
        1 => widen(fused::<1>(wr, vr, narrow(rows), nr)),
        2 => widen(fused::<2>(wr, vr, narrow(rows), nr)),
        _ => {
            vector::axpy(w, v, c);
            return inner(next, w);
        }
    };
    vector::combine_outer_products(&s)
}

fn narrow<const R: usize>(s: [[f64; 4]; 4]) -> [[f64; R]; R] {
    let mut out = [[0.0; R]; R];
    for (o, r) in out.iter_mut().zip(&s) {
        o.copy_from_slice(&r[..R]);
    }
    out
}

fn fused<const R: usize>(
    w: &mut [f64],
    v: &[f64],
    rows: [[f64; R]; R],
    next: &[f64],
) -> [[f64; R]; R] {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU supports the features the function is compiled for.
        return unsafe { fused_avx2_fma::<R>(w, v, rows, next) };
    }
    fused_kernel::<R, false>(w, v, rows, next)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn fused_avx2_fma<const R: usize>(
    w: &mut [f64],
    v: &[f64],
    rows: [[f64; R]; R],
    next: &[f64],
) -> [[f64; R]; R] {
    fused_kernel::<R, true>(w, v, rows, next)
}

#[inline(always)]
fn mul_add<const FUSED: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FUSED { a.mul_add(b, c) } else { a * b + c }
}

/// `w[R l + λ] += Σ_κ v[R l + κ] rows[κ][λ]`, then `S_κλ = Σₗ next[R l + κ] w[R l + λ]`
/// (`R` divides 8; lengths equal).
#[inline(always)]
fn fused_kernel<const R: usize, const FUSED: bool>(
    w: &mut [f64],
    v: &[f64],
    rows: [[f64; R]; R],
    next: &[f64],
) -> [[f64; R]; R] {
    const LANES: usize = 8;
    let len = w.len();
    let (v, next) = (&v[..len], &next[..len]);
    // Row κ of the update spread over the lanes: mult[κ][p] = rows[κ][p mod R].
    let mut mult = [[0.0f64; LANES]; R];
    for (kappa, m) in mult.iter_mut().enumerate() {
        for (p, x) in m.iter_mut().enumerate() {
            *x = rows[kappa][p % R];
        }
    }
    let mut acc = [[0.0f64; LANES]; R];
    let mut cw = w.chunks_exact_mut(LANES);
    let mut cv = v.chunks_exact(LANES);
    let mut cn = next.chunks_exact(LANES);
    for ((w8, v8), n8) in (&mut cw).zip(&mut cv).zip(&mut cn) {
        let w8: &mut [f64; LANES] = w8.try_into().expect("chunk of LANES");
        let v8: &[f64; LANES] = v8.try_into().expect("chunk of LANES");
        let n8: &[f64; LANES] = n8.try_into().expect("chunk of LANES");
        for (kappa, m) in mult.iter().enumerate() {
            for (p, x) in w8.iter_mut().enumerate() {
                *x = mul_add::<FUSED>(v8[(p / R) * R + kappa], m[p], *x);
            }
        }
        for (lambda, row) in acc.iter_mut().enumerate() {
            for (p, s) in row.iter_mut().enumerate() {
                *s = mul_add::<FUSED>(n8[p], w8[(p / R) * R + lambda], *s);
            }
        }
    }
    let mut s = [[0.0f64; R]; R];
    for (lambda, row) in acc.iter().enumerate() {
        for (p, &x) in row.iter().enumerate() {
            s[p % R][lambda] += x;
        }
    }
    let (rw, rv, rn) = (cw.into_remainder(), cv.remainder(), cn.remainder());
    for ((ew, ev), en) in rw
        .chunks_exact_mut(R)
        .zip(rv.chunks_exact(R))
        .zip(rn.chunks_exact(R))
    {
        for (lambda, x) in ew.iter_mut().enumerate() {
            for (kappa, row) in rows.iter().enumerate() {
                *x += ev[kappa] * row[lambda];
            }
        }
        for (kappa, row) in s.iter_mut().enumerate() {
            for (lambda, x) in row.iter_mut().enumerate() {
                *x += en[kappa] * ew[lambda];
            }
        }
    }
    s
}

fn widen<const R: usize>(s: [[f64; R]; R]) -> [[f64; 4]; 4] {
    let mut out = [[0.0; 4]; 4];
    for (o, r) in out.iter_mut().zip(&s) {
        o[..R].copy_from_slice(r);
    }
    out
}

/// `S_κλ = Σₗ a[R l + κ] b[R l + λ]` (`R` divides 8).
fn outer_products<const R: usize>(a: &[f64], b: &[f64]) -> [[f64; R]; R] {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU supports the features the function is compiled for.
        return unsafe { outer_products_avx2_fma::<R>(a, b) };
    }
    outer_products_kernel::<R, false>(a, b)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn outer_products_avx2_fma<const R: usize>(a: &[f64], b: &[f64]) -> [[f64; R]; R] {
    outer_products_kernel::<R, true>(a, b)
}

#[inline(always)]
fn outer_products_kernel<const R: usize, const FUSED: bool>(a: &[f64], b: &[f64]) -> [[f64; R]; R] {
    const LANES: usize = 8;
    let len = a.len().min(b.len());
    let (a, b) = (&a[..len], &b[..len]);
    // acc[λ][p] = Σ over chunks of a[c + p] b[c + R ⌊p/R⌋ + λ].
    let mut acc = [[0.0f64; LANES]; R];
    let mut chunks_a = a.chunks_exact(LANES);
    let mut chunks_b = b.chunks_exact(LANES);
    for (ca, cb) in (&mut chunks_a).zip(&mut chunks_b) {
        let ca: &[f64; LANES] = ca.try_into().expect("chunk of LANES");
        let cb: &[f64; LANES] = cb.try_into().expect("chunk of LANES");
        for (lambda, row) in acc.iter_mut().enumerate() {
            for (p, s) in row.iter_mut().enumerate() {
                let y = cb[(p / R) * R + lambda];
                *s = if FUSED {
                    ca[p].mul_add(y, *s)
                } else {
                    ca[p] * y + *s
                };
            }
        }
    }
    let mut s = [[0.0f64; R]; R];
    for (lambda, row) in acc.iter().enumerate() {
        for (p, &x) in row.iter().enumerate() {
            s[p % R][lambda] += x;
        }
    }
    let (ra, rb) = (chunks_a.remainder(), chunks_b.remainder());
    for (ea, eb) in ra.chunks_exact(R).zip(rb.chunks_exact(R)) {
        for (kappa, row) in s.iter_mut().enumerate() {
            for (lambda, x) in row.iter_mut().enumerate() {
                *x += ea[kappa] * eb[lambda];
            }
        }
    }
    s
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

    /// The fused kernels agree with the plain `qsparse` ones, remainders included.
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
            assert!((inner(&v, &w) - vector::inner(&v, &w)).abs() <= 1e-13 * scale);
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
