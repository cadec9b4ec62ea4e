//! Vector kernels in the workspace conventions: vectors form a right module, so coefficients
//! multiply on the right, and the inner product conjugates its first argument.

use num_traits::{Float, One, Zero};
use qscalar::Scalar;

use crate::simd::dispatch_avx2_fma;

dispatch_avx2_fma! {
/// `⟨x, y⟩ = Σᵢ conj(xᵢ) yᵢ`. Slices of unequal length are compared over the shorter one.
///
/// Accumulates the real `REAL_DIM × REAL_DIM` outer products `S_κλ = Σᵢ xᵢ,κ yᵢ,λ` (pure
/// multiply-adds that vectorise) and combines them once with the unit products:
/// `⟨x, y⟩ = Σ_κλ S_κλ conj(e_κ) e_λ`.
pub fn inner[T: Scalar](x: &[T], y: &[T]) -> T => inner_kernel[T,]
}

/// `a b + c`, fused when the caller is compiled with FMA (without hardware FMA, `mul_add`
/// would fall back to a slow software routine).
#[inline(always)]
fn multiply_add<R: qscalar::RealScalar, const FUSED: bool>(a: R, b: R, c: R) -> R {
    if FUSED { a.mul_add(b, c) } else { a * b + c }
}

#[inline(always)]
fn inner_kernel<T: Scalar, const FUSED: bool>(x: &[T], y: &[T]) -> T {
    // Short products (the small blocks of sparse triangular solves): the combination step
    // below would cost more than it saves.
    if x.len().min(y.len()) < 4 {
        return x.iter().zip(y).map(|(&a, &b)| a.conj() * b).sum();
    }
    // Independent accumulation chains: `REAL_DIM²` per entry, and entries spread over lanes
    // until there are sixteen, so that a real product is not bound by the latency of one
    // chain (16 lanes for `f64`, 4 for complex numbers, 1 for quaternions).
    let lanes = (16 / (T::REAL_DIM * T::REAL_DIM)).max(1);
    let mut outer = [[[T::Real::zero(); 4]; 4]; 16];
    let len = x.len().min(y.len());
    let whole = len / lanes * lanes;
    let (x, y) = (&x[..len], &y[..len]);
    for (xs, ys) in x[..whole]
        .chunks_exact(lanes)
        .zip(y[..whole].chunks_exact(lanes))
    {
        for ((lane, a), b) in outer.iter_mut().zip(xs).zip(ys) {
            outer_product_add::<T, FUSED>(lane, *a, *b);
        }
    }
    for (a, b) in x[whole..].iter().zip(&y[whole..]) {
        outer_product_add::<T, FUSED>(&mut outer[0], *a, *b);
    }
    let (first, rest) = outer.split_first_mut().expect("sixteen lanes");
    for lane in &rest[..lanes - 1] {
        for (row, lane_row) in first.iter_mut().zip(lane) {
            for (s, &t) in row.iter_mut().zip(lane_row) {
                *s += t;
            }
        }
    }
    combine_outer_products(first)
}

/// `S_κλ ← S_κλ + a_κ b_λ` over the components of `a` and `b`.
#[inline(always)]
fn outer_product_add<T: Scalar, const FUSED: bool>(outer: &mut [[T::Real; 4]; 4], a: T, b: T) {
    let (a, b) = ([a], [b]);
    let (ar, br) = (T::as_reals(&a), T::as_reals(&b));
    for (row, &a_kappa) in outer.iter_mut().zip(ar) {
        for (s, &b_lambda) in row.iter_mut().zip(br) {
            *s = multiply_add::<_, FUSED>(a_kappa, b_lambda, *s);
        }
    }
}

/// The unit `e_κ` whose only non-zero component is component `κ` (1, i, j, k for quaternions;
/// `κ < REAL_DIM`).
#[inline(always)]
pub(crate) fn unit<T: Scalar>(kappa: usize) -> T {
    let mut e = [T::zero()];
    T::as_reals_mut(&mut e)[kappa] = T::Real::one();
    e[0]
}

/// `‖x‖ = sqrt(Σᵢ |xᵢ|²)`, summed as [`real_inner`]`(x, x)` (independent chains, not one).
pub fn norm<T: Scalar>(x: &[T]) -> T::Real {
    real_inner(x, x).sqrt()
}

/// `Re⟨x, y⟩ = Σᵢ Re(conj(xᵢ) yᵢ)`: the dot product of the real components, a quarter of the
/// arithmetic of [`inner`] for quaternions, and the same in the blocked layout of a Gram–Schmidt
/// sweep as in the ordinary one.
pub fn real_inner<T: Scalar>(x: &[T], y: &[T]) -> T::Real {
    inner(T::as_reals(x), T::as_reals(y))
}

/// `y ← y + x r` for a real `r`: the real components of `x` times `r` (see [`real_inner`]).
pub fn axpy_real<T: Scalar>(y: &mut [T], x: &[T], r: T::Real) {
    axpy(T::as_reals_mut(y), T::as_reals(x), r);
}

dispatch_avx2_fma! {
/// `y ← y + x c` (coefficient on the right, as in a Gram–Schmidt update `w −= v ⟨v, w⟩`).
///
/// Computed through `RightMultiplier`, which the compiler turns into broadcast multiply-adds
/// over the components instead of a scalar quaternion product per entry.
pub fn axpy[T: Scalar](y: &mut [T], x: &[T], c: T) => axpy_kernel[T,]
}

dispatch_avx2_fma! {
/// `y[rows[i] − first] ← y[rows[i] − first] + x[i] c`: the scattered `axpy` of a sparse
/// column times `c` into the rows of `y`, which start at row `first` (panics if a row index
/// is outside them, like slice indexing).
pub(crate) fn scatter_axpy[T: Scalar](y: &mut [T], first: usize, rows: &[usize], x: &[T], c: T)
    => scatter_axpy_kernel[T,]
}

#[inline(always)]
fn scatter_axpy_kernel<T: Scalar, const FUSED: bool>(
    y: &mut [T],
    first: usize,
    rows: &[usize],
    x: &[T],
    c: T,
) {
    let times_c = RightMultiplier::new(c);
    for (&row, &xi) in rows.iter().zip(x) {
        times_c.mul_add_kernel::<FUSED>(&mut y[row - first], xi);
    }
}

#[inline(always)]
fn axpy_kernel<T: Scalar, const FUSED: bool>(y: &mut [T], x: &[T], c: T) {
    let times_c = RightMultiplier::new(c);
    for (yi, &xi) in y.iter_mut().zip(x) {
        times_c.mul_add_kernel::<FUSED>(yi, xi);
    }
}

/// Multiplication on the right by a fixed scalar `c`, precomputed as the real matrix of
/// `x ↦ x c` (for quaternions the right block `R(c)`, docs/MATH.md, "The real-block
/// representation"): column `κ` holds the components of `e_κ c`, so `x c = Σ_κ x_κ (e_κ c)` is
/// `REAL_DIM` multiply-adds of `REAL_DIM`-vectors — the same arithmetic as the Hamilton product,
/// in a form that vectorises.
#[derive(Debug, Clone, Copy)]
struct RightMultiplier<T: Scalar> {
    columns: [[T::Real; 4]; 4],
}

impl<T: Scalar> RightMultiplier<T> {
    /// Precomputes `x ↦ x c`.
    #[inline(always)]
    fn new(c: T) -> Self {
        Self {
            columns: unit_products(c),
        }
    }

    /// `acc ← acc + x c`.
    #[inline(always)]
    fn mul_add_kernel<const FUSED: bool>(&self, acc: &mut T, x: T) {
        let x = [x];
        let xr = T::as_reals(&x);
        let acc = T::as_reals_mut(core::slice::from_mut(acc));
        for (kappa, &x_kappa) in xr.iter().enumerate() {
            for (a, &e) in acc.iter_mut().zip(&self.columns[kappa]) {
                *a = multiply_add::<_, FUSED>(x_kappa, e, *a);
            }
        }
    }
}

/// `x ← x r` for a real `r`.
pub fn scale<T: Scalar>(x: &mut [T], r: T::Real) {
    for v in x {
        *v = v.scale(r);
    }
}

mod lanes;
#[cfg(target_arch = "x86_64")]
mod quaternion;

/// Bytes [`prefetch_head`] asks for: the size of a typical supernode block, and small enough
/// not to evict the working set.
const PREFETCH_HEAD_BYTES: usize = 16 * 1024;

/// Asks the caches (L2) for the first 16 KiB of `values`: a hint that never faults and does
/// nothing on targets without a prefetch instruction.
#[inline]
pub(crate) fn prefetch_head<T>(values: &[T]) {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{_MM_HINT_T1, _mm_prefetch};
        let bytes = core::mem::size_of_val(values).min(PREFETCH_HEAD_BYTES);
        let start = values.as_ptr().cast::<i8>();
        for offset in (0..bytes).step_by(64) {
            // SAFETY: prefetching has no memory effects; the address is inside `values`.
            unsafe { _mm_prefetch::<_MM_HINT_T1>(start.wrapping_add(offset)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = values;
}

/// How far ahead [`prefetch_ahead`] asks for a streamed vector, in bytes (eight cache lines).
const PREFETCH_AHEAD_BYTES: usize = 512;

/// Asks the first-level cache for the line `PREFETCH_AHEAD_BYTES` after the start of
/// `stream`: a hint that never faults (also past the end) and does nothing on targets without
/// a prefetch instruction. Hardware prefetchers lose track of the many short column streams of
/// a sparse factor, and on Zen 1 they left the Gram–Schmidt sweeps 10–25 % slower than with
/// this hint.
#[inline(always)]
fn prefetch_ahead<T>(stream: &[T]) {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let line = stream
            .as_ptr()
            .cast::<i8>()
            .wrapping_add(PREFETCH_AHEAD_BYTES);
        // SAFETY: prefetching has no memory effects.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(line) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = stream;
}

/// Whether the quaternion kernels of [`quaternion`] apply to `T` on this CPU.
#[inline]
fn quaternion_kernels<T: Scalar<Real = f64>>() -> bool {
    T::REAL_DIM == 4 && crate::simd::has_avx2_fma()
}

/// The components of `e_κ c` for `κ < REAL_DIM` (zero-padded): `x c = Σ_κ x_κ (e_κ c)`, the
/// columns of the real matrix of `x ↦ x c` (for quaternions the right block `R(c)`).
fn unit_products<T: Scalar>(c: T) -> [[T::Real; 4]; 4] {
    let mut columns = [[T::Real::zero(); 4]; 4];
    for (kappa, column) in columns.iter_mut().enumerate().take(T::REAL_DIM) {
        let product = [unit::<T>(kappa) * c];
        column[..T::REAL_DIM].copy_from_slice(T::as_reals(&product));
    }
    columns
}

/// The scalar with the components `q` (the first `REAL_DIM` of them).
fn from_components<T: Scalar>(q: [T::Real; 4]) -> T {
    let mut result = [T::zero()];
    T::as_reals_mut(&mut result).copy_from_slice(&q[..T::REAL_DIM]);
    result[0]
}

/// `Σ_κλ S_κλ conj(e_κ) e_λ`: the inner product `⟨a, g⟩` from the real outer products
/// `S_κλ = Σᵣ aᵣ,κ gᵣ,λ` of the components (`κ, λ < REAL_DIM`).
fn combine_outer_products<T: Scalar>(s: &[[T::Real; 4]; 4]) -> T {
    let mut result = T::zero();
    for (kappa, row) in s.iter().enumerate().take(T::REAL_DIM) {
        result += unit::<T>(kappa).conj() * from_components::<T>(*row);
    }
    result
}

/// `g ← g + a x + b y` (coefficients on the right): two columns of a matrix times two
/// coefficients, reading and writing `g` once.
///
/// # Panics
/// If `a` or `b` is not as long as `g`.
pub fn axpy_two<T: Scalar<Real = f64>>(g: &mut [T], a: &[T], b: &[T], x: T, y: T) {
    assert!(
        a.len() == g.len() && b.len() == g.len(),
        "axpy_two: lengths differ"
    );
    #[cfg(target_arch = "x86_64")]
    if quaternion_kernels::<T>() {
        let (mx, my) = (unit_products(x), unit_products(y));
        // SAFETY: AVX2 and FMA are available; `T` has four `f64` components, so the component
        // slices hold four numbers per entry, with equal lengths (checked above).
        unsafe {
            quaternion::multiply_add_two(
                T::as_reals_mut(g),
                T::as_reals(a),
                T::as_reals(b),
                &mx,
                &my,
            )
        };
        return;
    }
    axpy(g, a, x);
    axpy(g, b, y);
}

/// `(⟨a, g⟩, ⟨b, g⟩)`, reading `g` once.
///
/// # Panics
/// If `a` or `b` is not as long as `g`.
pub fn inner_two<T: Scalar<Real = f64>>(a: &[T], b: &[T], g: &[T]) -> (T, T) {
    assert!(
        a.len() == g.len() && b.len() == g.len(),
        "inner_two: lengths differ"
    );
    #[cfg(target_arch = "x86_64")]
    if quaternion_kernels::<T>() {
        // SAFETY: as in `axpy_two`.
        let (qa, qb) =
            unsafe { quaternion::inner_two(T::as_reals(a), T::as_reals(b), T::as_reals(g)) };
        return (from_components(qa), from_components(qb));
    }
    let (a, b, g) = (T::as_reals(a), T::as_reals(b), T::as_reals(g));
    let [sa, sb] = match T::REAL_DIM {
        1 => lanes::inner_two::<1>(a, b, g).map(lanes::widen),
        2 => lanes::inner_two::<2>(a, b, g).map(lanes::widen),
        _ => lanes::inner_two::<4>(a, b, g).map(lanes::widen),
    };
    (combine_outer_products(&sa), combine_outer_products(&sb))
}

/// Entries of `T` an `n`-vector takes in the *blocked layout* of a Gram–Schmidt sweep: `n`
/// rounded up to a multiple of four for quaternions on CPUs with AVX2 and FMA, `n` otherwise.
///
/// In the blocked layout ([`to_blocked`]) quaternions are stored four rows at a time, component
/// after component (`w₀ w₁ w₂ w₃, x₀ x₁ x₂ x₃, y₀ …, z₀ …`, padded with zero rows), so that one
/// 256-bit register holds one component of four rows: a quaternion product is then sixteen
/// multiply-adds of whole registers, without the sixteen broadcasts per entry that the
/// interleaved layout needs (1.4–1.5× faster sweeps on a core whose 256-bit multiply-adds
/// are split in two; docs/PERFORMANCE.md). Other scalars, and quaternions without AVX2, keep
/// their layout. The real part of an inner product, norms, real multiples and real linear
/// combinations do not depend on the layout.
pub fn blocked_len<T: Scalar<Real = f64>>(n: usize) -> usize {
    if quaternion_kernels::<T>() {
        n.next_multiple_of(BLOCK_ROWS)
    } else {
        n
    }
}

/// Whether vectors of `T` in the blocked layout ([`blocked_len`]) are stored as ordinary
/// vectors (every scalar but quaternions on CPUs with AVX2 and FMA).
pub fn blocked_is_ordinary<T: Scalar<Real = f64>>() -> bool {
    !quaternion_kernels::<T>()
}

/// Rows of a block of the blocked layout.
const BLOCK_ROWS: usize = 4;

/// `out ← x` in the blocked layout ([`blocked_len`]), padding rows zero.
///
/// # Panics
/// If `out.len() != blocked_len::<T>(x.len())`.
pub fn to_blocked<T: Scalar<Real = f64>>(x: &[T], out: &mut [T]) {
    assert_eq!(out.len(), blocked_len::<T>(x.len()), "to_blocked: lengths");
    if !quaternion_kernels::<T>() {
        out.copy_from_slice(x);
        return;
    }
    let (x, out) = (T::as_reals(x), T::as_reals_mut(out));
    out.fill(0.0);
    for (r, q) in x.chunks_exact(4).enumerate() {
        for (component, &value) in q.iter().enumerate() {
            out[quaternion_blocked_real(r, component)] = value;
        }
    }
}

/// `out ← x` from the blocked layout ([`blocked_len`]) back to entries of `T`.
///
/// # Panics
/// If `x.len() != blocked_len::<T>(out.len())`.
pub fn from_blocked<T: Scalar<Real = f64>>(x: &[T], out: &mut [T]) {
    assert_eq!(
        x.len(),
        blocked_len::<T>(out.len()),
        "from_blocked: lengths"
    );
    if !quaternion_kernels::<T>() {
        out.copy_from_slice(x);
        return;
    }
    let (x, out) = (T::as_reals(x), T::as_reals_mut(out));
    for (r, q) in out.chunks_exact_mut(4).enumerate() {
        for (component, value) in q.iter_mut().enumerate() {
            *value = x[quaternion_blocked_real(r, component)];
        }
    }
}

/// Position of row `row`'s component `component` among the reals of a vector of `T` in the
/// blocked layout ([`blocked_len`]).
#[inline]
fn blocked_real<T: Scalar<Real = f64>>(row: usize, component: usize) -> usize {
    if quaternion_kernels::<T>() {
        quaternion_blocked_real(row, component)
    } else {
        T::REAL_DIM * row + component
    }
}

/// [`blocked_real`] for quaternions with the quaternion kernels: four rows per block, component
/// after component.
#[inline]
fn quaternion_blocked_real(row: usize, component: usize) -> usize {
    16 * (row / BLOCK_ROWS) + BLOCK_ROWS * component + row % BLOCK_ROWS
}

/// `out[t] ← x[rows[t]]`: rows of a vector in the blocked layout ([`blocked_len`]) as an
/// ordinary vector.
///
/// # Panics
/// If `out` is shorter than `rows` or a row lies outside `x`.
pub fn gather_from_blocked<T: Scalar<Real = f64>>(x: &[T], rows: &[usize], out: &mut [T]) {
    let (x, out) = (T::as_reals(x), T::as_reals_mut(&mut out[..rows.len()]));
    for (value, &row) in out.chunks_exact_mut(T::REAL_DIM).zip(rows) {
        for (component, v) in value.iter_mut().enumerate() {
            *v = x[blocked_real::<T>(row, component)];
        }
    }
}

/// `x[rows[t]] ← values[t]`: the inverse of [`gather_from_blocked`].
///
/// # Panics
/// If `values` is shorter than `rows` or a row lies outside `x`.
pub fn scatter_to_blocked<T: Scalar<Real = f64>>(values: &[T], rows: &[usize], x: &mut [T]) {
    let (values, x) = (T::as_reals(&values[..rows.len()]), T::as_reals_mut(x));
    for (value, &row) in values.chunks_exact(T::REAL_DIM).zip(rows) {
        for (component, &v) in value.iter().enumerate() {
            x[blocked_real::<T>(row, component)] = v;
        }
    }
}

/// `w ← w + v₁ c₁ + v₂ c₂`, then `(⟨n₁, w⟩, ⟨n₂, w⟩)` with the new `w`: two columns of a
/// modified Gram–Schmidt sweep (classical within the pair: both coefficients of the next pair
/// come from the same `w`), reading and writing `w` once. All vectors are in the blocked
/// layout ([`blocked_len`]); the coefficients are ordinary scalars.
///
/// Blocked quaternions go through sixteen register multiply-adds per four rows and column;
/// other scalars (and quaternions without AVX2) through eight independent lanes over their
/// components.
///
/// # Panics
/// If a slice is not as long as `w`, or, blocked, `w.len()` is not a multiple of four.
pub fn axpy_two_then_inner_two<T: Scalar<Real = f64>>(
    w: &mut [T],
    v: [&[T]; 2],
    c: [T; 2],
    next: [&[T]; 2],
) -> [T; 2] {
    assert!(
        v.iter().chain(&next).all(|x| x.len() == w.len()),
        "axpy_two_then_inner_two: lengths differ"
    );
    #[cfg(target_arch = "x86_64")]
    if quaternion_kernels::<T>() {
        assert!(
            w.len().is_multiple_of(BLOCK_ROWS),
            "axpy_two_then_inner_two: a blocked vector holds whole blocks"
        );
        let (mc, md) = (unit_products(c[0]), unit_products(c[1]));
        let step = quaternion::PairStep {
            columns: v.map(T::as_reals),
            factors: [&mc, &md],
            next: next.map(T::as_reals),
        };
        // SAFETY: AVX2 and FMA are available; `T` has four `f64` components, so the component
        // slices hold sixteen numbers per block, with equal lengths (checked above).
        let [a, b] = unsafe { quaternion::blocked_pair_step(T::as_reals_mut(w), &step) };
        return [from_components(a), from_components(b)];
    }
    let rows = c.map(unit_products);
    let (wr, v, next) = (
        T::as_reals_mut(w),
        v.map(T::as_reals),
        next.map(T::as_reals),
    );
    let s = match T::REAL_DIM {
        1 => lanes::fused_two::<1>(wr, v, rows.map(lanes::narrow), next).map(lanes::widen),
        2 => lanes::fused_two::<2>(wr, v, rows.map(lanes::narrow), next).map(lanes::widen),
        _ => lanes::fused_two::<4>(wr, v, rows.map(lanes::narrow), next).map(lanes::widen),
    };
    s.map(|s| combine_outer_products(&s))
}

/// `yⱼ = Σₚ conj(aₚ) x[rows[p]]` over `p ∈ col_ptr[j]..col_ptr[j + 1]`: the inner products
/// of consecutive columns of a compressed sparse column matrix (row indices `rows`, values
/// `a`) with the dense `x`, that is the rows of `Aᴴ x` of those columns. `col_ptr` is the
/// window of the column pointers from the first column to one past the last
/// (`col_ptr.len() == y.len() + 1`).
///
/// Quaternions (with AVX2 and FMA) accumulate the real outer products in registers, two
/// entries at a time on independent accumulators, and combine them there, every column in one
/// call of the kernel; other scalars sum their products directly.
///
/// # Panics
/// If `col_ptr` does not have `y.len() + 1` entries, `rows` and `a` differ in length, a
/// pointer is outside them or a row is outside `x`.
pub fn gather_inner_columns<T: Scalar<Real = f64>>(
    col_ptr: &[usize],
    rows: &[usize],
    a: &[T],
    x: &[T],
    y: &mut [T],
) {
    assert_eq!(col_ptr.len(), y.len() + 1, "gather_inner_columns: pointers");
    assert_eq!(a.len(), rows.len(), "gather_inner_columns: lengths differ");
    #[cfg(target_arch = "x86_64")]
    if quaternion_kernels::<T>() {
        // SAFETY: AVX2 and FMA are available; `T` has four `f64` components, so `a` holds
        // four numbers per row of `rows`, `x` and `y` four per entry (the kernel slices by
        // the pointers and indexes by the rows with bounds checks).
        unsafe {
            quaternion::gathered_inner_columns(
                col_ptr,
                rows,
                T::as_reals(a),
                T::as_reals(x),
                T::as_reals_mut(y),
            )
        };
        return;
    }
    for (range, yj) in col_ptr.windows(2).zip(y.iter_mut()) {
        let (rows, a) = (&rows[range[0]..range[1]], &a[range[0]..range[1]]);
        *yj = a.iter().zip(rows).map(|(&v, &r)| v.conj() * x[r]).sum();
    }
}
