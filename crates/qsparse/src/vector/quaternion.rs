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
//! The exception is the Gram–Schmidt kernel [`blocked_pair_step`]: the Krylov basis is stored
//! transposed once and for all, four rows at a time component after component (the blocked
//! layout of [`super::blocked_len`]), so it needs neither shuffles nor broadcasts of entries.
//!
//! Safety contract of every kernel: AVX2 and FMA are available, every slice length is a
//! multiple of four, and the input slices are at least as long as the first one.

use core::arch::x86_64::{
    __m256d, _mm256_add_pd, _mm256_broadcast_sd, _mm256_fmadd_pd, _mm256_fnmadd_pd,
    _mm256_loadu_pd, _mm256_permute_pd, _mm256_permute4x64_pd, _mm256_setr_pd, _mm256_setzero_pd,
    _mm256_storeu_pd,
};

use super::prefetch_ahead;

/// Outer-product accumulators `S[κ][λ]`.
pub(super) type Outer = [[f64; 4]; 4];

/// Asks for both cache lines of the block (sixteen `f64`) as far ahead as
/// [`super::prefetch_ahead`]. Measured on Zen 1: with only the first line of each block asked
/// for, the Gram–Schmidt sweep ran 15–25 % slower.
#[inline(always)]
fn prefetch_block(block: &[f64]) {
    prefetch_ahead(block);
    prefetch_ahead(&block[8..]);
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
        prefetch_ahead(ar);
        prefetch_ahead(br);
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
        prefetch_ahead(ar);
        prefetch_ahead(br);
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

/// Signs of the products in the components of `conj(n) g`: component `λ` is
/// `Σ_κ INNER_SIGNS[κ][λ] n_κ g_{κ⊕λ}` (`⊕` the bitwise exclusive or of the indices, since
/// `e_κ e_μ = ±e_{κ⊕μ}` for the units `1, i, j, k`).
const INNER_SIGNS: [[f64; 4]; 4] = [
    [1.0, 1.0, 1.0, 1.0],
    [1.0, -1.0, 1.0, -1.0],
    [1.0, -1.0, -1.0, 1.0],
    [1.0, 1.0, -1.0, -1.0],
];

/// `wᵣ ← wᵣ + vᵣ c + uᵣ d` (`v, u` the step's columns, `c, d` their factors), then the inner
/// products of the step's next two columns with the new `w`, for vectors in the blocked
/// layout (sixteen `f64` per block of four rows: component `κ` of the block's rows at
/// `4κ..4κ + 4`, [`super::blocked_len`]): two columns of a modified Gram–Schmidt sweep per
/// read and write of `w`.
///
/// With one register per component of four rows, `(v c)_λ = Σ_κ v_κ (e_κ c)_λ` is sixteen
/// multiply-adds by the broadcast entries of `e_κ c` (constants, read from the first-level
/// cache), and the inner product accumulates component `λ` of `conj(n) g` directly
/// ([`INNER_SIGNS`]) in one register per component, summed across its four rows at the end.
///
/// # Safety
/// AVX2 and FMA; every slice as long as `w`, whose length is a multiple of sixteen.
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn blocked_pair_step(w: &mut [f64], step: &PairStep<'_>) -> [[f64; 4]; 2] {
    let PairStep {
        columns: [v, u],
        factors,
        next: [next, after],
    } = *step;
    // `constants[g][κ][λ]`: the entry `(e_κ c_g)_λ` in all four lanes.
    let constants = factors.map(|m| m.map(|row| row.map(|x| [x; 4])));
    let constant = |g: usize, kappa: usize, lambda: usize| {
        // SAFETY: four contiguous `f64`.
        unsafe { _mm256_loadu_pd(constants[g][kappa][lambda].as_ptr()) }
    };
    let load = |block: &[f64], kappa: usize| {
        // SAFETY: a block holds sixteen `f64`.
        unsafe { _mm256_loadu_pd(block[4 * kappa..4 * kappa + 4].as_ptr()) }
    };
    let mut s = [_mm256_setzero_pd(); 4];
    let mut t = s;
    for ((((wb, vb), ub), nb), ab) in w
        .chunks_exact_mut(16)
        .zip(v.chunks_exact(16))
        .zip(u.chunks_exact(16))
        .zip(next.chunks_exact(16))
        .zip(after.chunks_exact(16))
    {
        for stream in [nb, ab] {
            prefetch_block(stream);
        }
        let mut g = [0, 1, 2, 3].map(|lambda| load(wb, lambda));
        for (column, factor) in [(vb, 0), (ub, 1)] {
            for kappa in 0..4 {
                let x = load(column, kappa);
                for (lambda, gl) in g.iter_mut().enumerate() {
                    *gl = _mm256_fmadd_pd(x, constant(factor, kappa, lambda), *gl);
                }
            }
        }
        for (lambda, gl) in g.iter().enumerate() {
            // SAFETY: four `f64` of the block.
            unsafe { _mm256_storeu_pd(wb[4 * lambda..4 * lambda + 4].as_mut_ptr(), *gl) };
        }
        for kappa in 0..4 {
            let (n, a) = (load(nb, kappa), load(ab, kappa));
            for lambda in 0..4 {
                let gk = g[kappa ^ lambda];
                if INNER_SIGNS[kappa][lambda] > 0.0 {
                    s[lambda] = _mm256_fmadd_pd(n, gk, s[lambda]);
                    t[lambda] = _mm256_fmadd_pd(a, gk, t[lambda]);
                } else {
                    s[lambda] = _mm256_fnmadd_pd(n, gk, s[lambda]);
                    t[lambda] = _mm256_fnmadd_pd(a, gk, t[lambda]);
                }
            }
        }
    }
    [s, t].map(|acc| acc.map(horizontal_sum))
}

/// The sum of a register's four lanes.
#[inline(always)]
fn horizontal_sum(x: __m256d) -> f64 {
    let mut lanes = [0.0; 4];
    // SAFETY: `lanes` holds four `f64`; only called from functions compiled with AVX2.
    unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), x) };
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3])
}
