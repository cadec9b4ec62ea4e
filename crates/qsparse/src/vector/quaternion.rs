//! AVX2/FMA kernels over quaternion vectors stored as `(w, x, y, z)` `f64` quadruples, in the
//! *array-of-structures* form: one quaternion is one 256-bit register.
//!
//! * A product `a c` with a fixed right factor `c` is `Σ_κ a_κ (e_κ c)`: four broadcast
//!   multiply-adds against the precomputed columns `e_κ c` ([`super::unit_products`]).
//! * An inner product `Σ conj(aᵣ) gᵣ` accumulates the real outer products
//!   `S_κλ = Σᵣ aᵣ,κ gᵣ,λ` (four registers, one per `κ`), combined once by the caller
//!   ([`super::combine_outer_products`]).
//!
//! The compiler's own vectorisation of the generic loops transposes four quaternions at a time
//! instead, which costs more in shuffles than it saves on the short vectors of sparse
//! triangular solves (measured about 1.5× slower per entry on cache-resident factors).
//!
//! Safety contract of every kernel: AVX2 and FMA are available, every slice length is a
//! multiple of four, and the input slices are at least as long as the first one.

use core::arch::x86_64::{
    __m256d, _MM_HINT_T0, _mm_prefetch, _mm256_add_pd, _mm256_broadcast_sd, _mm256_fmadd_pd,
    _mm256_loadu_pd, _mm256_permute_pd, _mm256_permute4x64_pd, _mm256_setr_pd, _mm256_setzero_pd,
    _mm256_storeu_pd,
};

/// Outer-product accumulators `S[κ][λ]`.
pub(super) type Outer = [[f64; 4]; 4];

/// How far ahead a streamed vector is prefetched, in `f64` (eight cache lines).
const PREFETCH_DISTANCE: usize = 64;

/// Asks for the cache line `PREFETCH_DISTANCE` values ahead of `p` (a hint: it never faults,
/// also past the end of the slice). Hardware prefetchers lose track of the many short column
/// streams of a sparse factor.
#[inline(always)]
fn prefetch(p: *const f64) {
    // SAFETY: prefetching has no memory effects.
    unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(PREFETCH_DISTANCE).cast()) }
}

/// Loads the four columns `e_κ c`.
#[inline(always)]
fn load_columns(m: &Outer) -> [__m256d; 4] {
    // SAFETY: each row is four contiguous `f64`.
    m.map(|row| unsafe { _mm256_loadu_pd(row.as_ptr()) })
}

/// `Σ_κ aκ mκ + acc` for one quaternion `a` (four broadcasts from memory).
///
/// # Safety
/// AVX2 and FMA; `a` holds at least four values.
#[inline(always)]
unsafe fn times_columns(a: &[f64], m: &[__m256d; 4], acc: __m256d) -> __m256d {
    // SAFETY: the caller guarantees the features and the length.
    unsafe {
        let mut acc = _mm256_fmadd_pd(_mm256_broadcast_sd(&a[0]), m[0], acc);
        acc = _mm256_fmadd_pd(_mm256_broadcast_sd(&a[1]), m[1], acc);
        acc = _mm256_fmadd_pd(_mm256_broadcast_sd(&a[2]), m[2], acc);
        _mm256_fmadd_pd(_mm256_broadcast_sd(&a[3]), m[3], acc)
    }
}

/// `S[κ]` (over `λ`) `+= aκ · g`: one quaternion's outer products.
///
/// # Safety
/// AVX2 and FMA; `a` holds at least four values.
#[inline(always)]
unsafe fn accumulate_outer(s: &mut [__m256d; 4], a: &[f64], g: __m256d) {
    for (kappa, row) in s.iter_mut().enumerate() {
        // SAFETY: the caller guarantees the features and the length.
        *row = unsafe { _mm256_fmadd_pd(_mm256_broadcast_sd(&a[kappa]), g, *row) };
    }
}

/// `gᵣ ← gᵣ + aᵣ x + bᵣ y` with `mx[κ] = e_κ x`, `my[κ] = e_κ y`.
///
/// # Safety
/// See the module documentation.
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn multiply_add_two(g: &mut [f64], a: &[f64], b: &[f64], mx: &Outer, my: &Outer) {
    let (cx, cy) = (load_columns(mx), load_columns(my));
    for ((gr, ar), br) in g
        .chunks_exact_mut(4)
        .zip(a.chunks_exact(4))
        .zip(b.chunks_exact(4))
    {
        prefetch(ar.as_ptr());
        prefetch(br.as_ptr());
        // SAFETY: every chunk holds four `f64`.
        unsafe {
            // Two independent chains, joined once.
            let first = times_columns(ar, &cx, _mm256_loadu_pd(gr.as_ptr()));
            let second = times_columns(br, &cy, _mm256_setzero_pd());
            _mm256_storeu_pd(gr.as_mut_ptr(), _mm256_add_pd(first, second));
        }
    }
}

/// `(⟨a, g⟩, ⟨b, g⟩)` as four `f64` each, reading `g` once: the outer products of `a` and of
/// `b` with `g`, combined in registers (on the short columns of a triangular solve the
/// combination is a large part of the work).
///
/// # Safety
/// See the module documentation.
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn inner_two(a: &[f64], b: &[f64], g: &[f64]) -> ([f64; 4], [f64; 4]) {
    let mut sa = [_mm256_setzero_pd(); 4];
    let mut sb = [_mm256_setzero_pd(); 4];
    for ((gr, ar), br) in g
        .chunks_exact(4)
        .zip(a.chunks_exact(4))
        .zip(b.chunks_exact(4))
    {
        prefetch(ar.as_ptr());
        prefetch(br.as_ptr());
        // SAFETY: every chunk holds four `f64`.
        unsafe {
            let gv = _mm256_loadu_pd(gr.as_ptr());
            accumulate_outer(&mut sa, ar, gv);
            accumulate_outer(&mut sb, br, gv);
        }
    }
    (store_combined(sa), store_combined(sb))
}

/// `Σ_κ conj(e_κ) S_κ`, the inner product from its outer products (as
/// [`super::combine_outer_products`], in registers): `conj(e₁) s = −i s = (s₁, −s₀, s₃, −s₂)`,
/// `−j s = (s₂, −s₃, −s₀, s₁)`, `−k s = (s₃, s₂, −s₁, −s₀)`.
#[inline(always)]
fn combine_in_registers(s: [__m256d; 4]) -> __m256d {
    // SAFETY: only called from functions compiled with AVX2 and FMA.
    unsafe {
        let minus_i = _mm256_permute_pd::<0b0101>(s[1]);
        let minus_j = _mm256_permute4x64_pd::<0b01_00_11_10>(s[2]);
        let minus_k = _mm256_permute4x64_pd::<0b00_01_10_11>(s[3]);
        let mut q = _mm256_fmadd_pd(minus_i, _mm256_setr_pd(1.0, -1.0, 1.0, -1.0), s[0]);
        q = _mm256_fmadd_pd(minus_j, _mm256_setr_pd(1.0, -1.0, -1.0, 1.0), q);
        _mm256_fmadd_pd(minus_k, _mm256_setr_pd(1.0, 1.0, -1.0, -1.0), q)
    }
}

/// `Σₚ conj(aₚ) x[rows[p]]` in a register: the outer products `S_κλ = Σₚ aₚ,κ x[rows[p]],λ`,
/// even and odd entries on separate accumulators (two chains of multiply-adds at once),
/// combined in registers.
///
/// # Safety
/// AVX2 and FMA; `a` holds four values per entry of `rows`. Rows outside `x` panic.
#[inline(always)]
unsafe fn gathered_inner(a: &[f64], rows: &[usize], x: &[f64]) -> __m256d {
    // SAFETY: the caller guarantees the features.
    let mut even = [unsafe { _mm256_setzero_pd() }; 4];
    let mut odd = even;
    let load = |r: usize| {
        let entry = &x[4 * r..4 * r + 4];
        // SAFETY: `entry` holds four `f64`.
        unsafe { _mm256_loadu_pd(entry.as_ptr()) }
    };
    for (ar, r) in a.chunks_exact(8).zip(rows.chunks_exact(2)) {
        let (first, second) = (load(r[0]), load(r[1]));
        // SAFETY: `ar` holds two quaternions.
        unsafe {
            accumulate_outer(&mut even, &ar[..4], first);
            accumulate_outer(&mut odd, &ar[4..], second);
        }
    }
    if rows.len() % 2 == 1 {
        let last = rows.len() - 1;
        // SAFETY: the last entry's four values.
        unsafe { accumulate_outer(&mut even, &a[4 * last..4 * last + 4], load(rows[last])) };
    }
    for (e, o) in even.iter_mut().zip(odd) {
        // SAFETY: the caller guarantees the features.
        *e = unsafe { _mm256_add_pd(*e, o) };
    }
    combine_in_registers(even)
}

/// `yⱼ = Σₚ conj(aₚ) x[rows[p]]` over `p ∈ col_ptr[j]..col_ptr[j + 1]` for every `j`: the
/// inner products of consecutive columns of a compressed matrix (values `a`, four per entry)
/// with `x`, in one call — a mesh operator's column has about seven entries, and a call per
/// column cost about as much as its arithmetic.
///
/// # Safety
/// AVX2 and FMA; `col_ptr` has one entry more than `y` has quaternions. Pointers outside
/// `rows` and `a` (four values per row) and rows outside `x` panic.
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn gathered_inner_columns(
    col_ptr: &[usize],
    rows: &[usize],
    a: &[f64],
    x: &[f64],
    y: &mut [f64],
) {
    for (range, yj) in col_ptr.windows(2).zip(y.chunks_exact_mut(4)) {
        let (start, end) = (range[0], range[1]);
        // SAFETY: the caller guarantees the features and the layout; `yj` holds four `f64`.
        unsafe {
            let q = gathered_inner(&a[4 * start..4 * end], &rows[start..end], x);
            _mm256_storeu_pd(yj.as_mut_ptr(), q);
        }
    }
}

/// The inner product `Σ_κ conj(e_κ) S_κ` of the outer products `s`, as four `f64`.
#[inline(always)]
fn store_combined(s: [__m256d; 4]) -> [f64; 4] {
    let mut q = [0.0; 4];
    // SAFETY: `q` holds four `f64`.
    unsafe { _mm256_storeu_pd(q.as_mut_ptr(), combine_in_registers(s)) };
    q
}

/// What a step of a Gram–Schmidt sweep over a pair of columns reads besides `w`: the two
/// columns it updates by, the columns `e_κ c` of their right factors, and the next two
/// columns, whose inner products with the updated `w` it returns.
pub(super) struct PairStep<'a> {
    pub(super) columns: [&'a [f64]; 2],
    pub(super) factors: [&'a Outer; 2],
    pub(super) next: [&'a [f64]; 2],
}

/// Defines a compilation of [`pair_step`] for the given target features.
macro_rules! pair_step_compiled_for {
    ($(#[$attribute:meta])* $name:ident, $features:literal) => {
        $(#[$attribute])*
        #[target_feature(enable = $features)]
        pub(super) unsafe fn $name(w: &mut [f64], step: &PairStep<'_>) -> [[f64; 4]; 2] {
            // SAFETY: the caller guarantees the contract.
            unsafe { pair_step(w, step) }
        }
    };
}

pair_step_compiled_for! {
    /// `wᵣ ← wᵣ + vᵣ c + uᵣ d` (`v, u` the step's columns, `c, d` their factors), then the
    /// inner products of the step's next two columns with the new `w`, combined in
    /// registers: two columns of a modified Gram–Schmidt sweep per read and write of `w`.
    ///
    /// # Safety
    /// See the module documentation.
    multiply_add_two_then_inner_two, "avx2,fma"
}

pair_step_compiled_for! {
    /// [`multiply_add_two_then_inner_two`] compiled for AVX-512VL as well: the same 256-bit
    /// operations, with 32 vector registers instead of 16, enough for the eight constant
    /// columns and the eight accumulators of a pair without spilling.
    ///
    /// # Safety
    /// See the module documentation; AVX-512F and AVX-512VL are available too.
    multiply_add_two_then_inner_two_wide, "avx2,fma,avx512f,avx512vl"
}

/// The body of [`multiply_add_two_then_inner_two`], inlined into each of its compilations.
///
/// # Safety
/// AVX2 and FMA; see the module documentation.
#[inline(always)]
unsafe fn pair_step(w: &mut [f64], step: &PairStep<'_>) -> [[f64; 4]; 2] {
    let PairStep {
        columns: [v, u],
        factors: [mc, md],
        next: [next, after],
    } = *step;
    let (cc, cd) = (load_columns(mc), load_columns(md));
    // SAFETY: the caller guarantees the features.
    let mut s = [unsafe { _mm256_setzero_pd() }; 4];
    let mut t = s;
    for ((((wr, vr), ur), nr), ar) in w
        .chunks_exact_mut(4)
        .zip(v.chunks_exact(4))
        .zip(u.chunks_exact(4))
        .zip(next.chunks_exact(4))
        .zip(after.chunks_exact(4))
    {
        prefetch(nr.as_ptr());
        prefetch(ar.as_ptr());
        // SAFETY: every chunk holds four `f64`; the caller guarantees the features.
        unsafe {
            // Two independent chains, joined once.
            let first = times_columns(vr, &cc, _mm256_loadu_pd(wr.as_ptr()));
            let second = times_columns(ur, &cd, _mm256_setzero_pd());
            let updated = _mm256_add_pd(first, second);
            _mm256_storeu_pd(wr.as_mut_ptr(), updated);
            accumulate_outer(&mut s, nr, updated);
            accumulate_outer(&mut t, ar, updated);
        }
    }
    [store_combined(s), store_combined(t)]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pair kernel gives the same bits compiled for 16 or for 32 registers (the same
    /// operations in the same order), so the CPU a run lands on does not change its results.
    #[test]
    fn both_compilations_of_the_pair_step_agree() {
        if !(crate::simd::has_avx2_fma() && crate::simd::has_avx512vl()) {
            return; // Only one of them can run here.
        }
        let mut rng = qscalar::random::SplitMix64::new(11);
        let mut vector = |len: usize| {
            let mut v = vec![0.0; len];
            rng.fill_symmetric(&mut v);
            v
        };
        for len in [0, 4, 8, 44, 400] {
            let (v, u, next, after) = (vector(len), vector(len), vector(len), vector(len));
            let (mc, md) = ([[0.5, -1.0, 0.25, 2.0]; 4], [[1.5, 0.0, -0.75, 0.125]; 4]);
            let (mut narrow, mut wide) = (vector(len), Vec::new());
            wide.clone_from(&narrow);
            let step = PairStep {
                columns: [&v, &u],
                factors: [&mc, &md],
                next: [&next, &after],
            };
            // SAFETY: AVX2, FMA and AVX-512VL are available (checked above); lengths are
            // equal multiples of four.
            let (a, b) = unsafe {
                (
                    multiply_add_two_then_inner_two(&mut narrow, &step),
                    multiply_add_two_then_inner_two_wide(&mut wide, &step),
                )
            };
            assert_eq!(a, b, "coefficients, length {len}");
            assert_eq!(narrow, wide, "updated vector, length {len}");
        }
    }
}
