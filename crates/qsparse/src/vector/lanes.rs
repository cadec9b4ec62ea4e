//! Kernels over the real component layout of `f64`, `Complex<f64>` and `Quat<f64>` vectors
//! (`R = REAL_DIM` reals per entry), spread over eight independent lanes so that a long sweep
//! is bound by memory rather than by the latency of one accumulation chain: the fused pair
//! update of [`super::axpy_two_then_inner_two`] and the paired inner products of
//! [`super::inner_two`] (all scalars but AVX2 quaternions).
//! Outer products come back as `S_κλ`, combined by the caller with
//! [`super::combine_outer_products`].

use super::prefetch_ahead;
use crate::simd::dispatch_avx2_fma;

/// The leading `R × R` block of a `4 × 4` array.
pub(super) fn narrow<const R: usize>(s: [[f64; 4]; 4]) -> [[f64; R]; R] {
    let mut out = [[0.0; R]; R];
    for (o, r) in out.iter_mut().zip(&s) {
        o.copy_from_slice(&r[..R]);
    }
    out
}

/// Independent accumulators per row of outer products: eight `f64`, one 512-bit or two 256-bit
/// registers.
const LANES: usize = 8;

/// `acc[λ][p] += x[p] y[R ⌊p/R⌋ + λ]`: the outer products of the `LANES / R` entries of a chunk,
/// lane `p` carrying component `p mod R` of `x`.
#[inline(always)]
fn accumulate_lanes<const R: usize, const FUSED: bool>(
    acc: &mut [[f64; LANES]; R],
    x: &[f64; LANES],
    y: &[f64; LANES],
) {
    for (lambda, row) in acc.iter_mut().enumerate() {
        for (p, s) in row.iter_mut().enumerate() {
            *s = mul_add::<FUSED>(x[p], y[(p / R) * R + lambda], *s);
        }
    }
}

/// The outer products `S_κλ` of two columns from their lanes: lane `p` of row `λ` holds
/// products of component `p mod R`.
#[inline(always)]
fn fold_lanes<const R: usize>(acc: &[[[f64; LANES]; R]; 2]) -> [[[f64; R]; R]; 2] {
    let mut s = [[[0.0f64; R]; R]; 2];
    for (s, acc) in s.iter_mut().zip(acc) {
        for (lambda, row) in acc.iter().enumerate() {
            for (p, &x) in row.iter().enumerate() {
                s[p % R][lambda] += x;
            }
        }
    }
    s
}

/// `S_κλ += x_κ y_λ` for one entry `x`, `y` of `R` components each.
#[inline(always)]
fn add_entry_products<const R: usize>(s: &mut [[f64; R]; R], x: &[f64], y: &[f64]) {
    for (row, &x_kappa) in s.iter_mut().zip(x) {
        for (sum, &y_lambda) in row.iter_mut().zip(y) {
            *sum += x_kappa * y_lambda;
        }
    }
}

dispatch_avx2_fma! {
/// [`fused_two_kernel`], with FMA where the CPU has it.
pub(super) fn fused_two[const R: usize](
    w: &mut [f64],
    v: [&[f64]; 2],
    rows: [[[f64; R]; R]; 2],
    next: [&[f64]; 2],
) -> [[[f64; R]; R]; 2] => fused_two_kernel[R,]
}

#[inline(always)]
fn mul_add<const FUSED: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FUSED { a.mul_add(b, c) } else { a * b + c }
}

/// `w[R l + λ] += Σ_g Σ_κ v_g[R l + κ] rows_g[κ][λ]`, then, with the new `w`,
/// `S_g,κλ = Σₗ next_g[R l + κ] w[R l + λ]` for `g = 0, 1` (`R` divides 8; lengths equal).
#[inline(always)]
fn fused_two_kernel<const R: usize, const FUSED: bool>(
    w: &mut [f64],
    v: [&[f64]; 2],
    rows: [[[f64; R]; R]; 2],
    next: [&[f64]; 2],
) -> [[[f64; R]; R]; 2] {
    let len = w.len();
    let (v, next) = (v.map(|x| &x[..len]), next.map(|x| &x[..len]));
    // Row κ of update g spread over the lanes: mult[g][κ][p] = rows[g][κ][p mod R].
    let mut mult = [[[0.0f64; LANES]; R]; 2];
    for (m, r) in mult.iter_mut().zip(&rows) {
        for (kappa, m) in m.iter_mut().enumerate() {
            for (p, x) in m.iter_mut().enumerate() {
                *x = r[kappa][p % R];
            }
        }
    }
    let mut acc = [[[0.0f64; LANES]; R]; 2];
    let chunks = len / LANES * LANES;
    for c in (0..chunks).step_by(LANES) {
        let w8: &mut [f64; LANES] = (&mut w[c..c + LANES]).try_into().expect("chunk of LANES");
        for (vg, m) in v.iter().zip(&mult) {
            let v8: &[f64; LANES] = vg[c..c + LANES].try_into().expect("chunk of LANES");
            for (kappa, m) in m.iter().enumerate() {
                for (p, x) in w8.iter_mut().enumerate() {
                    *x = mul_add::<FUSED>(v8[(p / R) * R + kappa], m[p], *x);
                }
            }
        }
        for ng in &next {
            prefetch_ahead(&ng[c..]);
        }
        for (ng, acc) in next.iter().zip(&mut acc) {
            let n8: &[f64; LANES] = ng[c..c + LANES].try_into().expect("chunk of LANES");
            accumulate_lanes::<R, FUSED>(acc, n8, w8);
        }
    }
    let mut s = fold_lanes(&acc);
    for e in (chunks..len).step_by(R) {
        let ew = &mut w[e..e + R];
        for (vg, r) in v.iter().zip(&rows) {
            for (lambda, x) in ew.iter_mut().enumerate() {
                for (kappa, row) in r.iter().enumerate() {
                    *x += vg[e + kappa] * row[lambda];
                }
            }
        }
        for (ng, s) in next.iter().zip(&mut s) {
            add_entry_products(s, &ng[e..e + R], ew);
        }
    }
    s
}

dispatch_avx2_fma! {
/// [`inner_two_kernel`], with FMA where the CPU has it.
pub(super) fn inner_two[const R: usize](a: &[f64], b: &[f64], g: &[f64]) -> [[[f64; R]; R]; 2]
    => inner_two_kernel[R,]
}

/// `S_0,κλ = Σₗ a[R l + κ] g[R l + λ]` and `S_1,κλ` the same with `b`, reading `g` once (the
/// backward substitution of a supernode; `R` divides 8; lengths equal).
#[inline(always)]
fn inner_two_kernel<const R: usize, const FUSED: bool>(
    a: &[f64],
    b: &[f64],
    g: &[f64],
) -> [[[f64; R]; R]; 2] {
    let len = g.len();
    let columns = [&a[..len], &b[..len]];
    let mut acc = [[[0.0f64; LANES]; R]; 2];
    let chunks = len / LANES * LANES;
    for c in (0..chunks).step_by(LANES) {
        let g8: &[f64; LANES] = g[c..c + LANES].try_into().expect("chunk of LANES");
        for (column, acc) in columns.iter().zip(&mut acc) {
            let x8: &[f64; LANES] = column[c..c + LANES].try_into().expect("chunk of LANES");
            accumulate_lanes::<R, FUSED>(acc, x8, g8);
        }
    }
    let mut s = fold_lanes(&acc);
    for e in (chunks..len).step_by(R) {
        for (column, s) in columns.iter().zip(&mut s) {
            add_entry_products(s, &column[e..e + R], &g[e..e + R]);
        }
    }
    s
}

/// An `R × R` array in the leading block of a zero `4 × 4` one.
pub(super) fn widen<const R: usize>(s: [[f64; R]; R]) -> [[f64; 4]; 4] {
    let mut out = [[0.0; 4]; 4];
    for (o, r) in out.iter_mut().zip(&s) {
        o[..R].copy_from_slice(r);
    }
    out
}
