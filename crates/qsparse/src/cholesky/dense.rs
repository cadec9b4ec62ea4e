//! Dense kernels of the supernodal factorisation, generic over the scalar.
//!
//! All matrices are column-major slices with an explicit leading dimension. The one kernel that
//! carries most of the flops, `C = A Bᴴ` ([`gemm_adjoint`]), is quaternion-aware: for large
//! blocks it rewrites the product over an `R`-dimensional algebra (`R = REAL_DIM`) as a **single
//! real GEMM** of shape `m × (R·k)` times `(R·k) × (R·n)`:
//!
//! ```text
//! (a b̄)_c = Σ_κ Rt(b̄)[c][κ] a_κ        (Rt(b̄): the right-multiplication matrix of b̄)
//! [C₀ … C_{R−1}] = [A₀ … A_{R−1}] · Big,  Big[(κ,l), (c,j)] = Rt(conj B_jl)[c][κ]
//! ```
//!
//! where `A_κ` is the real matrix of component `κ` of `A`. This costs `R²·m·n·k` real
//! multiply-adds — for quaternions 16 per quaternion product, a quarter of the 64 that the 4×4
//! real-block expansion performs for the same entries — and runs at the speed of a tuned real
//! GEMM (faer's `matmul`). Small products use a direct loop in scalar arithmetic instead, where
//! packing would cost more than it saves.

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};
use qscalar::Scalar;

use crate::vector::{axpy, unit};

/// Below this many scalar multiply-adds the direct loop beats packing plus a real GEMM.
const PACKED_GEMM_THRESHOLD: usize = 4096;

/// Reusable buffers for the packed GEMM path.
#[derive(Default)]
pub(crate) struct GemmWorkspace {
    packed_lhs: Vec<f64>,
    packed_rhs: Vec<f64>,
    packed_out: Vec<f64>,
}

/// `C = A Bᴴ`, i.e. `C[i, j] = Σ_l A[i, l] · conj(B[j, l])`.
///
/// `A` is `m × k` with leading dimension `lda`, `B` is `n × k` with leading dimension `ldb`,
/// and `C` is `m × n` with leading dimension `m` (overwritten).
pub(crate) fn gemm_adjoint<T: Scalar<Real = f64>>(
    c: &mut [T],
    a: &[T],
    lda: usize,
    b: &[T],
    ldb: usize,
    (m, n, k): (usize, usize, usize),
    work: &mut GemmWorkspace,
) {
    let c = &mut c[..m * n];
    if m * n * k < PACKED_GEMM_THRESHOLD
        || T::REAL_DIM == 1 && m * n * k < 4 * PACKED_GEMM_THRESHOLD
    {
        c.fill(T::zero());
        for l in 0..k {
            let a_col = &a[l * lda..l * lda + m];
            for j in 0..n {
                axpy(&mut c[j * m..(j + 1) * m], a_col, b[l * ldb + j].conj());
            }
        }
        return;
    }

    let r = T::REAL_DIM;
    // Pack A by components: packed_lhs is m × (r·k), column (κ·k + l) = component κ of A[:, l].
    work.packed_lhs.clear();
    work.packed_lhs.resize(m * r * k, 0.0);
    for l in 0..k {
        let a_col = T::as_reals(&a[l * lda..l * lda + m]);
        for kappa in 0..r {
            let dst = &mut work.packed_lhs[(kappa * k + l) * m..(kappa * k + l + 1) * m];
            for (d, s) in dst.iter_mut().zip(a_col.iter().skip(kappa).step_by(r)) {
                *d = *s;
            }
        }
    }
    // Big is (r·k) × (r·n): entry ((κ, l), (c, j)) = component c of e_κ · conj(B[j, l]).
    let rk = r * k;
    work.packed_rhs.clear();
    work.packed_rhs.resize(rk * r * n, 0.0);
    for l in 0..k {
        for j in 0..n {
            let b_conj = b[l * ldb + j].conj();
            for kappa in 0..r {
                let product = unit::<T>(kappa) * b_conj;
                for (comp, &value) in T::as_reals(core::slice::from_ref(&product))
                    .iter()
                    .enumerate()
                {
                    work.packed_rhs[(comp * n + j) * rk + kappa * k + l] = value;
                }
            }
        }
    }
    work.packed_out.clear();
    work.packed_out.resize(m * r * n, 0.0);
    matmul(
        MatMut::from_column_major_slice_mut(&mut work.packed_out, m, r * n),
        Accum::Replace,
        MatRef::from_column_major_slice(&work.packed_lhs, m, rk),
        MatRef::from_column_major_slice(&work.packed_rhs, rk, r * n),
        1.0,
        Par::Seq,
    );
    // Unpack: component c of C[i, j] is packed_out[i, c·n + j].
    for j in 0..n {
        let c_col = T::as_reals_mut(&mut c[j * m..(j + 1) * m]);
        for comp in 0..r {
            let src = &work.packed_out[(comp * n + j) * m..(comp * n + j + 1) * m];
            for (d, s) in c_col.iter_mut().skip(comp).step_by(r).zip(src) {
                *d = *s;
            }
        }
    }
}

/// Factorises the supernode block `L` (`m × w`, leading dimension `m`) in place: the top `w × w`
/// block becomes its lower Cholesky factor `L₁₁` (`A₁₁ = L₁₁ L₁₁ᴴ`), and the rows below become
/// `L₂₁ = A₂₁ L₁₁⁻ᴴ`. Blocked right-looking: panels of `PANEL` columns are factored with a direct
/// left-looking loop, the trailing columns updated with [`gemm_adjoint`].
///
/// Only the lower triangle is read and written. On a non-positive (or non-finite) pivot, returns
/// `Err((local column, pivot value))`.
pub(crate) fn factor_supernode<T: Scalar<Real = f64>>(
    l: &mut [T],
    m: usize,
    w: usize,
    work: &mut GemmWorkspace,
    update: &mut Vec<T>,
) -> Result<(), (usize, f64)> {
    const PANEL: usize = 32;
    let mut p = 0;
    while p < w {
        let b = PANEL.min(w - p);
        for j in p..p + b {
            for kk in p..j {
                let minus_l_jk = -l[kk * m + j].conj();
                let (left, right) = l.split_at_mut(j * m);
                axpy(&mut right[j..m], &left[kk * m + j..kk * m + m], minus_l_jk);
            }
            let pivot = l[j * m + j].re();
            if !(pivot > 0.0 && pivot.is_finite()) {
                return Err((j, pivot));
            }
            let d = pivot.sqrt();
            l[j * m + j] = T::from_real(d);
            let inv = 1.0 / d;
            for v in &mut l[j * m + j + 1..j * m + m] {
                *v = v.scale(inv);
            }
        }
        let next = p + b;
        if next < w {
            // L[next.., next..w] −= L[next.., p..next] · L[next..w, p..next]ᴴ (lower part).
            let (rows, cols) = (m - next, w - next);
            update.clear();
            update.resize(rows * cols, T::zero());
            gemm_adjoint(
                update,
                &l[p * m + next..],
                m,
                &l[p * m + next..],
                m,
                (rows, cols, b),
                work,
            );
            for jj in 0..cols {
                let dst = &mut l[(next + jj) * m + next + jj..(next + jj + 1) * m];
                let src = &update[jj * rows + jj..(jj + 1) * rows];
                for (d, &s) in dst.iter_mut().zip(src) {
                    *d -= s;
                }
            }
        }
        p = next;
    }
    Ok(())
}
