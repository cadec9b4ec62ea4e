//! A contiguous block of vectors and the Gram–Schmidt kernels of the Lanczos iteration.
//!
//! Vectors form a right module over the scalar `V` (docs/ARCHITECTURE.md, "Conventions"), so
//! projecting `w` onto the span of orthonormal `v₀ … v_{m−1}` is `w ← w − Σᵢ vᵢ ⟨vᵢ, w⟩` with
//! the coefficient on the right. The orthogonalisation is memory-bound (the basis is far
//! larger than the caches), so a pass is *modified* Gram–Schmidt, two columns at a time, with
//! the update by `vᵢ, vᵢ₊₁` and the coefficients of `vᵢ₊₂, vᵢ₊₃` fused in one sweep: each basis
//! vector is read from memory once per pass (its second read, and `w`, come from cache), half
//! the traffic of a classical pass through a matrix product (`Vᵀ w`, then `V G`), which
//! streams the basis twice, and `w` is read and written once per pair of columns.
//!
//! The columns, and the vectors orthogonalised against them, are stored in the **blocked
//! layout** of the kernel [`vector::axpy_two_then_inner_two`] ([`vector::blocked_len`]:
//! quaternions four rows at a time, component after component, so that a register holds one
//! component of four rows and a quaternion product is sixteen whole-register multiply-adds).
//! Writing `e₀ … e_{R−1}` for the units of `V` (`1, i, j, k` for quaternions,
//! `R = REAL_DIM`), `⟨v, w⟩_λ = Σ_κ ±v_κ w_{κ⊕λ}` and `(v c)_λ = Σ_κ v_κ (e_κ c)_λ`, pure
//! multiply-adds of components. Norms, the real parts of inner products, real multiples and
//! the real combinations `Q Y` of a restart do not depend on the layout; the operator sees
//! ordinary vectors ([`Basis::column_to`], [`Basis::to_layout`]).

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use faer::linalg::matmul::matmul;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par};
use qscalar::Scalar;
use qsparse::{SparseVector, vector};

use crate::constraints::Constraints;
use crate::memory::{self, BasisTooLarge};

/// `n`-vectors stored contiguously column after column, in the blocked layout, orthonormal and
/// orthogonal to a set of [`Constraints`], against which every orthogonalisation also projects.
#[derive(Debug)]
pub(crate) struct Basis<V> {
    /// Entries per stored column: `vector::blocked_len(dimension)`.
    n: usize,
    /// Dimension of the vectors.
    dimension: usize,
    data: Vec<V>,
    constraints: Constraints<V>,
    /// Columns read by Gram–Schmidt passes so far (the orthogonalisation's memory traffic is
    /// this times the size of a column).
    columns_read: AtomicUsize,
}

impl<V: Scalar<Real = f64>> Basis<V> {
    /// An empty basis of `dimension`-vectors, without constraints.
    #[cfg(test)]
    pub(crate) fn new(dimension: usize) -> Self {
        Self::constrained(dimension, Vec::new())
    }

    /// An empty basis of `dimension`-vectors in the orthogonal complement of `constraints`
    /// (orthonormalised by [`Constraints::new`]).
    pub(crate) fn constrained(
        dimension: usize,
        constraints: impl IntoIterator<Item = SparseVector<V>>,
    ) -> Self {
        Self {
            n: vector::blocked_len::<V>(dimension),
            dimension,
            data: Vec::new(),
            constraints: Constraints::new(dimension, constraints),
            columns_read: AtomicUsize::new(0),
        }
    }

    /// Orthonormal constraint directions the columns are orthogonal to.
    pub(crate) fn constraint_count(&self) -> usize {
        self.constraints.count()
    }

    /// Bytes of the storage (the largest the basis has been: it never shrinks while
    /// iterating), the constraints included.
    pub(crate) fn reserved_bytes(&self) -> usize {
        self.data.capacity() * std::mem::size_of::<V>() + self.constraints.bytes()
    }

    /// Columns read by Gram–Schmidt passes so far.
    pub(crate) fn columns_read(&self) -> usize {
        self.columns_read.load(Ordering::Relaxed)
    }

    pub(crate) fn cols(&self) -> usize {
        self.data.len().checked_div(self.n).unwrap_or(0)
    }

    /// Column `i`, in the blocked layout.
    pub(crate) fn col(&self, i: usize) -> &[V] {
        &self.data[i * self.n..(i + 1) * self.n]
    }

    /// Length of a vector in the blocked layout (what [`Basis::col`] returns and
    /// [`Basis::orthogonalize`] takes).
    pub(crate) fn layout_len(&self) -> usize {
        self.n
    }

    /// `out ← x` in the blocked layout (`x` an ordinary `dimension`-vector).
    pub(crate) fn to_layout(&self, x: &[V], out: &mut [V]) {
        vector::to_blocked(x, out);
    }

    /// `out ← ` column `i` as an ordinary `dimension`-vector.
    pub(crate) fn column_to(&self, i: usize, out: &mut [V]) {
        vector::from_blocked(self.col(i), out);
    }

    /// Appends a column (growing the storage by one column beyond what
    /// [`Basis::reserve_columns`] reserved, never by doubling: a doubled Krylov basis would not
    /// fit where the reserved one does).
    pub(crate) fn push(&mut self, v: &[V]) {
        assert_eq!(v.len(), self.n, "a basis column in the blocked layout");
        if self.data.len() + self.n > self.data.capacity() {
            self.data.reserve_exact(self.n);
        }
        self.data.extend_from_slice(v);
    }

    pub(crate) fn truncate(&mut self, cols: usize) {
        self.data.truncate(cols * self.n);
    }

    /// Reserves room for `columns` columns in all, after checking that they fit in
    /// `limit` bytes (the memory available to the process when `None`).
    pub(crate) fn reserve_columns(
        &mut self,
        columns: usize,
        limit: Option<u64>,
    ) -> Result<(), BasisTooLarge> {
        let entries = columns.saturating_mul(self.n);
        let available = limit.or_else(memory::available_bytes);
        let too_large = || BasisTooLarge {
            vectors: columns,
            dimension: self.n,
            bytes_per_entry: std::mem::size_of::<V>(),
            bytes_available: available,
        };
        if available.is_some_and(|a| too_large().bytes_needed() > a) {
            return Err(too_large());
        }
        let additional = entries.saturating_sub(self.data.len());
        self.data
            .try_reserve_exact(additional)
            .map_err(|_| too_large())
    }

    /// Columns `start..start + count` as a mutable real `(R n) × count` matrix.
    fn reals_mut(&mut self, start: usize, count: usize) -> MatMut<'_, f64> {
        let slice = &mut self.data[start * self.n..(start + count) * self.n];
        MatMut::from_column_major_slice_mut(V::as_reals_mut(slice), V::REAL_DIM * self.n, count)
    }

    /// Replaces columns `start..start + y.ncols()` by `Q Y`, where `Q` is columns
    /// `start..start + y.nrows()` and `Y` is real (Ritz vectors of a restart), in place.
    ///
    /// A real `Y` acts on every real row of `Q` separately, so `Q` is transformed one block of
    /// rows at a time through a small buffer: the basis is read once and written once, and no
    /// second `n × ncols` block is needed (at a million vertices it would be gigabytes).
    /// Long products run on two threads, each on half of the rows.
    pub(crate) fn combine_in_place(&mut self, start: usize, y: MatRef<'_, f64>) {
        let flops = V::REAL_DIM * self.n * y.nrows() * y.ncols();
        let two_threads = flops >= PARALLEL_RITZ_FLOPS && qsparse::threads::second_thread_allowed();
        self.combine_in_place_on(start, y, two_threads);
    }

    /// [`Basis::combine_in_place`], on two threads if `two_threads`.
    fn combine_in_place_on(&mut self, start: usize, y: MatRef<'_, f64>, two_threads: bool) {
        let rows = V::REAL_DIM * self.n;
        let q = self.reals_mut(start, y.nrows());
        if two_threads {
            let (top, bottom) = q.split_at_row_mut(rows / 2);
            qsparse::threads::join(|| combine_rows(top, y), || combine_rows(bottom, y));
        } else {
            combine_rows(q, y);
        }
    }

    /// Reorders columns in place so that column `start + t` holds the former column
    /// `start + order[t]` (`order` distinct); the columns after `start + order.len()` keep
    /// the others in some order.
    pub(crate) fn select_columns(&mut self, start: usize, order: &[usize]) {
        let span = order
            .iter()
            .map(|&c| c + 1)
            .max()
            .unwrap_or(0)
            .max(order.len());
        // `position[c]`: where the former column `c` is now; `occupant[p]`: whose column `p` holds.
        let mut position: Vec<usize> = (0..span).collect();
        let mut occupant = position.clone();
        for (t, &c) in order.iter().enumerate() {
            let p = position[c];
            if p != t {
                self.swap_columns(start + t, start + p);
                let displaced = occupant[t];
                occupant.swap(t, p);
                position[c] = t;
                position[displaced] = p;
            }
        }
    }

    fn swap_columns(&mut self, a: usize, b: usize) {
        let (low, high) = (a.min(b), a.max(b));
        let n = self.n;
        let (head, tail) = self.data.split_at_mut(high * n);
        head[low * n..(low + 1) * n].swap_with_slice(&mut tail[..n]);
    }

    /// The columns as separate vectors, freeing the basis's memory as they are taken: at no
    /// time is more than one column held twice.
    pub(crate) fn into_columns(mut self) -> Vec<Vec<V>> {
        let mut columns = Vec::with_capacity(self.cols());
        while self.cols() > 0 {
            let last = self.cols() - 1;
            let mut column = vec![V::zero(); self.dimension];
            self.column_to(last, &mut column);
            columns.push(column);
            self.truncate(last);
            self.data.shrink_to_fit();
        }
        columns.reverse();
        columns
    }

    /// Copies column `from` over column `to`.
    pub(crate) fn copy_column(&mut self, from: usize, to: usize) {
        let n = self.n;
        self.data.copy_within(from * n..(from + 1) * n, to * n);
    }

    /// One modified Gram–Schmidt pass against columns `0..m` (orthonormal):
    /// `w ← w − vᵢ ⟨vᵢ, w⟩` for `i = 0 … m−1` in turn, adding the coefficients to `coef[i]`.
    ///
    /// Two columns at a time, each update `w −= vᵢ cᵢ + vᵢ₊₁ cᵢ₊₁` fused with the next two
    /// coefficients in one sweep: each basis vector is read from memory once per pass (the
    /// second read finds it in cache), where a classical pass reads the whole basis twice.
    ///
    /// Long vectors are split by rows between two threads (the sweep is bound by the latency
    /// of its loads, so two cores nearly halve it): each sweeps its rows, and after every
    /// pair of columns the partial coefficients are exchanged through [`Exchange`] and added in a
    /// fixed order (first half, then second), so that both threads use the same coefficient
    /// and the result does not depend on timing.
    fn pass(&self, m: usize, w: &mut [V], coef: &mut [V]) {
        self.columns_read.fetch_add(m, Ordering::Relaxed);
        let two_threads =
            w.len() * V::REAL_DIM >= PARALLEL_REALS && qsparse::threads::second_thread_allowed();
        pass(self, m, w, coef, two_threads);
    }

    /// Orthogonalises `w` against the constraints and columns `0..m`, with a second pass when
    /// the first one removed more than `1 − 1/√2` of the norm ("twice is enough",
    /// Daniel–Gragg–Kaufman–Stewart). `coef[..m]` receives the total coefficients. Returns
    /// `‖w‖` before and after.
    pub(crate) fn orthogonalize(&self, m: usize, w: &mut [V], coef: &mut Vec<V>) -> (f64, f64) {
        coef.clear();
        coef.resize(m, V::zero());
        let before = vector::norm(w);
        let mut last = before;
        for _ in 0..3 {
            self.constraints.project(w);
            self.pass(m, w, coef);
            let now = vector::norm(w);
            let stop = now > std::f64::consts::FRAC_1_SQRT_2 * last;
            last = now;
            if stop {
                break;
            }
        }
        (before, last)
    }

    /// [`Basis::append_orthonormal`] for an ordinary `dimension`-vector `x`.
    pub(crate) fn append_ordinary(&mut self, x: &[V], coef: &mut Vec<V>) -> bool {
        let mut v = vec![V::zero(); self.n];
        self.to_layout(x, &mut v);
        self.append_orthonormal(&mut v, coef)
    }

    /// Appends the normalised component of `v` (blocked layout) orthogonal to all columns, if that component
    /// is not negligible (`‖v⊥‖ > 1e−8 ‖v‖`); returns whether it was appended.
    pub(crate) fn append_orthonormal(&mut self, v: &mut [V], coef: &mut Vec<V>) -> bool {
        let (before, after) = self.orthogonalize(self.cols(), v, coef);
        if after.is_nan() || after <= 1e-8 * before || after == 0.0 {
            return false;
        }
        vector::scale(v, 1.0 / after);
        self.push(v);
        true
    }
}

/// Multiply-adds from which the Ritz vectors `Q Y` of a restart are computed on two threads.
const PARALLEL_RITZ_FLOPS: usize = 1 << 24;

/// Real rows of `Q` transformed per block by [`Basis::combine_in_place`]: the block of `Q`
/// (`ROW_BLOCK × size` reals) and its product stay in the second-level cache.
const ROW_BLOCK: usize = 128;

/// `Q[:, ..count] ← Q Y` block of rows by block of rows (`count = Y.ncols() ≤ Q.ncols()`).
fn combine_rows(mut q: MatMut<'_, f64>, y: MatRef<'_, f64>) {
    let count = y.ncols();
    let mut product = Mat::<f64>::zeros(ROW_BLOCK, count);
    let mut row = 0;
    while row < q.nrows() {
        let rows = ROW_BLOCK.min(q.nrows() - row);
        let mut block = q.rb_mut().subrows_mut(row, rows);
        let mut out = product.as_mut().subrows_mut(0, rows);
        matmul(out.rb_mut(), Accum::Replace, block.rb(), y, 1.0, Par::Seq);
        block.rb_mut().subcols_mut(0, count).copy_from(out.rb());
        row += rows;
    }
}

/// Vectors of at least this many reals are orthogonalised on two threads: below it, the
/// exchange after every pair of columns costs more than half a sweep saves.
const PARALLEL_REALS: usize = 1 << 15;

/// The meeting point of the two threads of a Gram–Schmidt pass: per thread, the partial
/// coefficients of a group of columns for each group parity (double buffering: a thread can
/// be at most one group ahead) and the number of groups published so far.
struct Exchange {
    partials: [[[AtomicU64; 4 * GROUP]; 2]; 2],
    published: [AtomicUsize; 2],
}

impl Exchange {
    fn new() -> Self {
        Self {
            partials: Default::default(),
            published: Default::default(),
        }
    }

    /// Publishes thread `half`'s partial coefficients of group `g`, waits for the other
    /// thread's, and returns their sums (first half + second half, on both threads).
    fn total<V: Scalar<Real = f64>>(&self, half: usize, g: usize, partial: Group<V>) -> Group<V> {
        let slot = &self.partials[half][g % 2];
        for (cell, &x) in slot.iter().zip(V::as_reals(&partial)) {
            cell.store(x.to_bits(), Ordering::Relaxed);
        }
        self.published[half].store(g + 1, Ordering::Release);
        let other = 1 - half;
        let mut spins = 0u32;
        while self.published[other].load(Ordering::Acquire) <= g {
            spins += 1;
            if spins < 1 << 12 {
                std::hint::spin_loop();
            } else {
                // The other thread is descheduled (a busy machine): give it the core.
                std::thread::yield_now();
            }
        }
        let mut theirs = [V::zero(); GROUP];
        for (x, cell) in V::as_reals_mut(&mut theirs)
            .iter_mut()
            .zip(&self.partials[other][g % 2])
        {
            *x = f64::from_bits(cell.load(Ordering::Relaxed));
        }
        let (a, b) = if half == 0 {
            (partial, theirs)
        } else {
            (theirs, partial)
        };
        std::array::from_fn(|i| a[i] + b[i])
    }
}

/// [`Basis::pass`], on two threads if `two_threads`.
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
    // On a block boundary of the blocked layout (blocks of four entries at most).
    let split = n / 2 / 4 * 4;
    let (first, second) = w.split_at_mut(split);
    let exchange = Exchange::new();
    let exchange = &exchange;
    qsparse::threads::join_concurrently(
        || {
            let _abandon = Abandon(&exchange.published[0]);
            sweep(basis, m, 0..split, first, Some(coef), |i, c| {
                exchange.total(0, i, c)
            });
        },
        || {
            let _abandon = Abandon(&exchange.published[1]);
            sweep(basis, m, split..n, second, None, |i, c| {
                exchange.total(1, i, c)
            });
        },
    );
}

/// Columns per step of a sweep: the update by a group and the coefficients of the next
/// group share one read and write of `w`.
const GROUP: usize = 2;

/// The coefficients of a group of columns (the second is zero for a single last column).
type Group<V> = [V; GROUP];

/// The fused modified Gram–Schmidt sweep over the rows `rows` (held by `w`) of columns `0..m`,
/// two columns at a time: the update by columns `2g, 2g + 1` fused with the coefficients of
/// columns `2g + 2, 2g + 3` (both from the same `w`: classical Gram–Schmidt within a pair,
/// which against orthonormal columns is as accurate as modified). `total(g, partials)` turns
/// the partial coefficients of group `g` over these rows into the full ones. Adds the
/// coefficients to `coef` if given.
fn sweep<V: Scalar<Real = f64>>(
    basis: &Basis<V>,
    m: usize,
    rows: std::ops::Range<usize>,
    w: &mut [V],
    mut coef: Option<&mut [V]>,
    total: impl Fn(usize, Group<V>) -> Group<V>,
) {
    let column = |i: usize| &basis.col(i)[rows.clone()];
    // Group `g` holds columns `2g` and, if it exists, `2g + 1`.
    let group = |g: usize| {
        let first = GROUP * g;
        [column(first), column((first + 1).min(m - 1))]
    };
    let pair = |g: usize| GROUP * g + 1 < m;
    let groups = m.div_ceil(GROUP);
    // Step `g` updates by group `g − 1` and computes the coefficients of group `g`; the first
    // step's update is by zero and the last step's "next" columns are its own (coefficients
    // unused), so that every step is the one fused kernel.
    let mut c = [V::zero(); GROUP];
    for g in 0..=groups {
        let update = group(g.saturating_sub(1));
        let next = if g < groups { group(g) } else { update };
        let minus = [V::zero() - c[0], V::zero() - c[1]];
        let partials = vector::axpy_two_then_inner_two(w, update, minus, next);
        if g == groups {
            return;
        }
        // Only the last group can be a single column.
        c = total(
            g,
            [partials[0], if pair(g) { partials[1] } else { V::zero() }],
        );
        if let Some(coef) = coef.as_deref_mut() {
            coef[GROUP * g] += c[0];
            if pair(g) {
                coef[GROUP * g + 1] += c[1];
            }
        }
    }
}

/// Marks a thread's side of an [`Exchange`] as abandoned if the thread panics, so that the
/// other thread stops waiting (and [`qsparse::threads::join_concurrently`] then raises the
/// panic) instead of hanging.
struct Abandon<'a>(&'a AtomicUsize);

impl Drop for Abandon<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.store(usize::MAX, Ordering::Release);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use qscalar::random::SplitMix64;
    use qscalar::{Complex, Quat};

    /// Column `i` as an ordinary vector.
    fn ordinary<V: Scalar<Real = f64>>(basis: &Basis<V>, i: usize) -> Vec<V> {
        let mut x = vec![V::zero(); basis.dimension];
        basis.column_to(i, &mut x);
        x
    }

    /// A random ordinary `n`-vector.
    fn random_vector<V: Scalar<Real = f64>>(n: usize, rng: &mut SplitMix64) -> Vec<V> {
        let mut x = vec![V::zero(); n];
        rng.fill_symmetric(&mut x);
        x
    }

    /// The blocked layout holds the ordinary vector, with zero padding rows.
    #[test]
    fn layout_round_trip() {
        let mut rng = SplitMix64::new(1);
        for n in [0usize, 1, 3, 4, 5, 9] {
            let basis = Basis::<Quat<f64>>::new(n);
            let x = random_vector::<Quat<f64>>(n, &mut rng);
            let mut blocked = vec![Quat::from_real(f64::NAN); basis.layout_len()];
            basis.to_layout(&x, &mut blocked);
            assert!((vector::norm(&blocked) - vector::norm(&x)).abs() < 1e-14);
            let mut back = vec![Quat::from_real(0.0); n];
            vector::from_blocked(&blocked, &mut back);
            assert_eq!(back, x);
        }
    }

    /// A pass over `m` orthonormal columns (pairs and a single last column, on one thread)
    /// is the projection `w − Σᵢ vᵢ ⟨vᵢ, w⟩` with the coefficients `⟨vᵢ, w⟩`, up to rounding;
    /// the arithmetic on the ordinary vectors is the reference.
    fn pass_projects<V: Scalar<Real = f64>>() {
        let mut rng = SplitMix64::new(7);
        for n in [7usize, 13, 64, 101] {
            let mut basis = Basis::<V>::new(n);
            let mut coef = Vec::new();
            for m in 0..6 {
                let w = random_vector::<V>(n, &mut rng);
                let columns: Vec<Vec<V>> = (0..m).map(|i| ordinary(&basis, i)).collect();
                let expected_coef: Vec<V> = columns.iter().map(|v| vector::inner(v, &w)).collect();
                let mut expected = w.clone();
                for (v, &c) in columns.iter().zip(&expected_coef) {
                    vector::axpy(&mut expected, v, V::zero() - c);
                }
                let mut blocked = vec![V::zero(); basis.layout_len()];
                basis.to_layout(&w, &mut blocked);
                let mut got_coef = vec![V::zero(); m];
                pass(&basis, m, &mut blocked, &mut got_coef, false);
                let mut got = vec![V::zero(); n];
                vector::from_blocked(&blocked, &mut got);
                let scale = 1.0 + n as f64;
                for (a, b) in got_coef.iter().zip(&expected_coef) {
                    assert!((*a - *b).abs() <= 1e-13 * scale, "m = {m}: coefficients");
                }
                for (a, b) in got.iter().zip(&expected) {
                    assert!((*a - *b).abs() <= 1e-13 * scale, "m = {m}: vector");
                }
                let v = random_vector::<V>(n, &mut rng);
                assert!(basis.append_ordinary(&v, &mut coef));
            }
        }
    }

    #[test]
    fn pass_is_the_projection() {
        pass_projects::<f64>();
        pass_projects::<Complex<f64>>();
        pass_projects::<Quat<f64>>();
    }

    /// The two-thread pass gives the one-thread result up to rounding, for vectors long
    /// enough to take it by default.
    fn two_threads_match_one<V: Scalar<Real = f64>>() {
        let n = PARALLEL_REALS / V::REAL_DIM + 3;
        let mut rng = SplitMix64::new(5);
        let mut basis = Basis::<V>::new(n);
        let mut coef = Vec::new();
        for _ in 0..5 {
            let v = random_vector::<V>(n, &mut rng);
            assert!(basis.append_ordinary(&v, &mut coef));
        }
        let mut w = vec![V::zero(); basis.layout_len()];
        basis.to_layout(&random_vector::<V>(n, &mut rng), &mut w);
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
        let mut two_ordinary = vec![V::zero(); n];
        vector::from_blocked(&two, &mut two_ordinary);
        for i in 0..5 {
            assert!(vector::inner(&ordinary(&basis, i), &two_ordinary).abs() < 1e-12);
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
        let mut rng = SplitMix64::new(3);
        let mut basis = Basis::<Quat<f64>>::new(n);
        let mut coef = Vec::new();
        for _ in 0..6 {
            let v = random_vector::<Quat<f64>>(n, &mut rng);
            assert!(basis.append_ordinary(&v, &mut coef));
        }
        for a in 0..6 {
            for b in 0..6 {
                let g = vector::inner(&ordinary(&basis, a), &ordinary(&basis, b));
                let expected = if a == b { 1.0 } else { 0.0 };
                assert!((g - Quat::from_real(expected)).abs() < 1e-13);
            }
        }
    }

    /// A random basis of `cols` quaternion columns of length `n` (not orthonormal).
    fn random_basis(n: usize, cols: usize, seed: u64) -> Basis<Quat<f64>> {
        let mut rng = SplitMix64::new(seed);
        let mut basis = Basis::new(n);
        let mut v = vec![Quat::from_real(0.0); basis.layout_len()];
        for _ in 0..cols {
            basis.to_layout(&random_vector(n, &mut rng), &mut v);
            basis.push(&v);
        }
        basis
    }

    /// `Q Y` in place equals the product computed column by column with `axpy`, on one and
    /// on two threads, for row counts that are not multiples of the row block.
    #[test]
    fn combine_in_place_is_the_product() {
        for (n, threads) in [(37, false), (ROW_BLOCK + 5, false), (3000, true)] {
            let (start, size, count) = (2, 7, 4);
            let mut basis = random_basis(n, start + size + 1, 11);
            let y = Mat::<f64>::from_fn(size, count, |r, c| ((r * 7 + c * 3) % 5) as f64 - 1.5);
            let expected: Vec<Vec<Quat<f64>>> = (0..count)
                .map(|c| {
                    let mut x = vec![Quat::from_real(0.0); n];
                    for r in 0..size {
                        vector::axpy(&mut x, basis.col(start + r), Quat::from_real(y[(r, c)]));
                    }
                    x
                })
                .collect();
            let untouched = (basis.col(0).to_vec(), basis.col(start + size).to_vec());
            basis.combine_in_place_on(start, y.as_ref(), threads);
            for (c, x) in expected.iter().enumerate() {
                for (a, b) in basis.col(start + c).iter().zip(x) {
                    assert!((*a - *b).abs() < 1e-12, "column {c} differs (n = {n})");
                }
            }
            assert_eq!(basis.col(0), &untouched.0[..]);
            assert_eq!(basis.col(start + size), &untouched.1[..]);
        }
    }

    /// Selecting columns in any order (a permutation with swaps and cycles) moves exactly
    /// the selected columns to the front.
    #[test]
    fn select_columns_moves_the_selected_to_the_front() {
        let n = 5;
        for order in [
            vec![0, 2, 1, 3],
            vec![3, 0, 1],
            vec![4, 3, 2, 1, 0],
            vec![1, 4],
            vec![],
        ] {
            let mut basis = random_basis(n, 7, 3);
            let before: Vec<Vec<Quat<f64>>> = (0..7).map(|c| basis.col(c).to_vec()).collect();
            basis.select_columns(1, &order);
            assert_eq!(basis.col(0), &before[0][..]);
            for (t, &c) in order.iter().enumerate() {
                assert_eq!(basis.col(1 + t), &before[1 + c][..], "order {order:?}");
            }
            let mut rest: Vec<&[Quat<f64>]> = (1 + order.len()..7).map(|c| basis.col(c)).collect();
            let mut expected_rest: Vec<&[Quat<f64>]> = (0..6)
                .filter(|c| !order.contains(c))
                .map(|c| &before[1 + c][..])
                .collect();
            let key = |v: &&[Quat<f64>]| v[0].re().to_bits();
            rest.sort_by_key(key);
            expected_rest.sort_by_key(key);
            assert_eq!(rest, expected_rest, "order {order:?}");
        }
    }

    /// A basis that does not fit in the memory limit is refused before anything is
    /// allocated, with its size in the error.
    #[test]
    fn reserve_refuses_what_does_not_fit() {
        let mut basis = Basis::<Quat<f64>>::new(1000);
        let error = basis.reserve_columns(100, Some(1 << 20)).unwrap_err();
        assert_eq!(error.bytes_needed(), 100 * 1000 * 32);
        assert_eq!(error.bytes_available, Some(1 << 20));
        assert_eq!(basis.data.capacity(), 0);
        basis.reserve_columns(10, Some(1 << 20)).unwrap();
        assert!(basis.data.capacity() >= 10 * 1000);
    }
}
