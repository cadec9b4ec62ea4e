//! A contiguous block of vectors and the blocked Gram–Schmidt kernels of the Lanczos iteration.
//!
//! Vectors form a right module over the scalar `V` (DESIGN.md §2), so projecting `w` onto the
//! span of orthonormal `v₀ … v_{m−1}` is `w ← w − Σᵢ vᵢ ⟨vᵢ, w⟩` with the coefficient on the
//! right. Both halves run as real matrix products on the component layout
//! ([`Scalar::as_reals`]): writing `e₀ … e_{R−1}` for the units of `V` (`1, i, j, k` for
//! quaternions, `R = REAL_DIM`), the `c`-th component of `⟨v, w⟩` is the real dot product of
//! `reals(v)` with `reals(w ē_c)`, so all coefficients are one product `Vᵀ W` with the `R`
//! real columns `W = [reals(w ē₀) …]`, and the update is `w ← w − Σ_c (V G_c) e_c` with the
//! real `m × R` coefficient matrix `G`. Each pass streams the basis twice through faer's
//! matrix product, whatever `V` is.

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};
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

/// The units `e₀ … e_{R−1}` of `V` (`1, i, j, k` for quaternions).
pub(crate) fn unit<V: Scalar<Real = f64>>(c: usize) -> V {
    let mut e = [V::zero()];
    V::as_reals_mut(&mut e)[c] = 1.0;
    e[0]
}

/// Workspace of the blocked Gram–Schmidt passes (no allocation per step).
#[derive(Debug)]
pub(crate) struct GramSchmidt<V> {
    units: Vec<V>,
    conj_units: Vec<V>,
    /// `R` columns `w ē_c`, then reused for the `R` columns `V G_c`.
    columns: Vec<V>,
    /// `m × R` real coefficients.
    coefficients: Vec<f64>,
}

impl<V: Scalar<Real = f64>> GramSchmidt<V> {
    pub(crate) fn new() -> Self {
        let units: Vec<V> = (0..V::REAL_DIM).map(unit).collect();
        Self {
            conj_units: units.iter().map(|e| e.conj()).collect(),
            units,
            columns: Vec::new(),
            coefficients: Vec::new(),
        }
    }

    /// One classical Gram–Schmidt pass against columns `0..m` of `basis` (orthonormal):
    /// `w ← w − Σᵢ vᵢ ⟨vᵢ, w⟩`, adding the coefficients `⟨vᵢ, w⟩` to `coef[i]`.
    fn pass(&mut self, basis: &Basis<V>, m: usize, w: &mut [V], coef: &mut [V]) {
        let (n, r) = (w.len(), V::REAL_DIM);
        if m == 0 {
            return;
        }
        self.columns.resize(n * r, V::zero());
        self.coefficients.resize(m * r, 0.0);
        for (c, &ec) in self.conj_units.iter().enumerate() {
            for (dst, &x) in self.columns[c * n..(c + 1) * n].iter_mut().zip(w.iter()) {
                *dst = x * ec;
            }
        }
        let v = basis.reals(0, m);
        {
            let wmat = MatRef::from_column_major_slice(V::as_reals(&self.columns), r * n, r);
            let g = MatMut::from_column_major_slice_mut(&mut self.coefficients, m, r);
            matmul(g, Accum::Replace, v.transpose(), wmat, 1.0, Par::Seq);
        }
        for (i, ci) in coef[..m].iter_mut().enumerate() {
            for (c, &ec) in self.units.iter().enumerate() {
                *ci += ec.scale(self.coefficients[c * m + i]);
            }
        }
        {
            let g = MatRef::from_column_major_slice(&self.coefficients, m, r);
            let z =
                MatMut::from_column_major_slice_mut(V::as_reals_mut(&mut self.columns), r * n, r);
            matmul(z, Accum::Replace, v, g, 1.0, Par::Seq);
        }
        for (c, &ec) in self.units.iter().enumerate() {
            for (wl, &zl) in w.iter_mut().zip(&self.columns[c * n..(c + 1) * n]) {
                *wl -= zl * ec;
            }
        }
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
        crate::basis::CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        for _ in 0..3 {
            crate::basis::PASSES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
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

pub(crate) static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
pub(crate) static PASSES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
/// A small deterministic generator (SplitMix64) for the seeded start vectors.
#[derive(Debug, Clone)]
pub(crate) struct SplitMix64(u64);

impl SplitMix64 {
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[−1, 1)`.
    pub(crate) fn symmetric(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (2.0 / (1u64 << 53) as f64) - 1.0
    }

    /// Fills every real component of `v` with uniform values in `[−1, 1)`.
    pub(crate) fn fill<V: Scalar<Real = f64>>(&mut self, v: &mut [V]) {
        for x in V::as_reals_mut(v) {
            *x = self.symmetric();
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
