//! Dense Hermitian eigensolvers for small problems, tests and cross-checks, over any
//! [`Scalar`] (real, complex, quaternion).
//!
//! [`hermitian_eigen`] reduces `A = Aᴴ` to a real symmetric tridiagonal matrix with
//! quaternion-aware Householder reflectors and a diagonal unitary scaling, then calls faer's
//! real self-adjoint eigensolver:
//!
//! * reflector `H = I − τ v vᴴ` (`τ = 2/‖v‖²`, real) maps the column `x` below the diagonal to
//!   `e₁ α` with `α = −(x₁/|x₁|) ‖x‖` (so `vᴴx` and `vᴴv` are real and `H x = e₁ α`); the
//!   trailing block is updated as `A ← H A H = A − v wᴴ − w vᴴ` with `p = τ A v`,
//!   `w = p − v (τ vᴴp)/2`;
//! * the Hermitian tridiagonal `T` (real diagonal, quaternionic subdiagonal `tᵢ`) becomes real
//!   with `D = diag(dᵢ)`, `d₀ = 1`, `d_{i+1} = tᵢ dᵢ / |tᵢ|`: `(Dᴴ T D)_{i+1,i} = |tᵢ|`;
//! * eigenvectors are `X = H₀ H₁ ⋯ D Z` with `Z` the real eigenvectors of `Dᴴ T D`.
//!
//! Each quaternionic eigenvalue appears once per quaternionic dimension of its eigenspace
//! (no 2- or 4-fold copies as in the complex-adjoint or real-block embeddings).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{self, ComputeEigenvectors};
use faer::{Mat, MatRef, Par};
use qscalar::Scalar;
use qsparse::DenseMatrix;
use qsparse::vector;

use crate::EigError;
use crate::error::{DenseEigenError, EmbeddedFactorizationError};
use crate::scaling;

/// Eigenvalues (ascending) and eigenvectors (columns) of a dense Hermitian matrix or pencil.
#[derive(Debug, Clone)]
pub struct DenseEigen<T> {
    /// Eigenvalues in ascending order.
    pub values: Vec<f64>,
    /// Column `i` is the eigenvector of `values[i]`: `A xᵢ = xᵢ λᵢ`, orthonormal
    /// (`S`-orthonormal for [`generalized_hermitian_eigen`]).
    pub vectors: DenseMatrix<T>,
}

/// Eigenvalues (ascending) and eigenvectors (columns of the returned matrix) of a real
/// symmetric matrix, of which only the lower triangle is read. Runs sequentially.
pub(crate) fn real_symmetric_eigen(
    a: MatRef<'_, f64>,
) -> Result<(Vec<f64>, Mat<f64>), DenseEigenError> {
    let n = a.nrows();
    if n == 0 {
        return Ok((Vec::new(), Mat::zeros(0, 0)));
    }
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    let mut u = Mat::<f64>::zeros(n, n);
    let mut mem = MemBuffer::new(evd::self_adjoint_evd_scratch::<f64>(
        n,
        ComputeEigenvectors::Yes,
        Par::Seq,
        Default::default(),
    ));
    evd::self_adjoint_evd(
        a,
        s.as_mut(),
        Some(u.as_mut()),
        Par::Seq,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .map_err(|_| DenseEigenError { order: n })?;
    Ok(((0..n).map(|i| s[i]).collect(), u))
}

/// `√(a² + b²)` without overflow or underflow of the squares, faster than `f64::hypot`.
fn norm_of_pair(a: f64, b: f64) -> f64 {
    let (a, b) = (a.abs(), b.abs());
    let (large, small) = if a >= b { (a, b) } else { (b, a) };
    if large == 0.0 {
        return 0.0;
    }
    let ratio = small / large;
    large * (1.0 + ratio * ratio).sqrt()
}

/// Most implicit QL sweeps per eigenvalue in [`tridiagonal_values_and_last_components`] (two
/// or three suffice for almost every eigenvalue; LAPACK's `dsteqr` allows 30).
const QL_SWEEPS: usize = 30;

/// Eigenvalues (ascending) of the real symmetric tridiagonal matrix `T` with diagonal
/// `diagonal` and off-diagonal `off` (`off[i] = T[i + 1, i]`), each with `|zₙ₋₁|`, the last
/// component of its unit eigenvector `z`.
///
/// The implicit QL algorithm with Wilkinson shifts: each sweep chases a bulge with plane
/// rotations `G` from the bottom of an unreduced block to its top, `T ← Gᵀ T G`, and the
/// eigenvector matrix `Z ← Z G` (from `Z = I`) is carried for its last row only, which is all
/// a Lanczos residual estimate `|β zₙ₋₁|` needs: `O(n²)` operations where the eigenvectors
/// cost `O(n³)`. A block splits off when `|T[m + 1, m]| ≤ ε (|T[m, m]| + |T[m + 1, m + 1]|)`.
/// The rotations are orthogonal, so the last components are accurate to about `ε` in
/// absolute terms, the eigenvalues to about `ε ‖T‖`, as with a full eigensolver.
pub(crate) fn tridiagonal_values_and_last_components(
    diagonal: &[f64],
    off: &[f64],
) -> Result<(Vec<f64>, Vec<f64>), DenseEigenError> {
    let n = diagonal.len();
    if diagonal.iter().chain(off).any(|v| !v.is_finite()) {
        return Err(DenseEigenError { order: n });
    }
    if n == 0 {
        return Ok((Vec::new(), Vec::new()));
    }
    let mut d = diagonal.to_vec();
    // e[i] couples i and i + 1; e[n − 1] = 0 is room the sweeps write to.
    let mut e = off[..n - 1].to_vec();
    e.push(0.0);
    let mut z = vec![0.0; n];
    z[n - 1] = 1.0;
    for l in 0..n {
        let mut sweeps = 0;
        loop {
            // The unreduced block starting at l ends at m.
            let mut m = l;
            while m + 1 < n && e[m].abs() > f64::EPSILON * (d[m].abs() + d[m + 1].abs()) {
                m += 1;
            }
            if m == l {
                break;
            }
            sweeps += 1;
            if sweeps > QL_SWEEPS {
                return Err(DenseEigenError { order: n });
            }
            // The shift: the eigenvalue of the leading 2×2 block nearer to d[l].
            let g = (d[l + 1] - d[l]) / (2.0 * e[l]);
            let r = (g * g + 1.0).sqrt();
            let mut g = d[m] - d[l] + e[l] / (g + r.copysign(g));
            let (mut s, mut c, mut p) = (1.0, 1.0, 0.0);
            let mut split = false;
            for i in (l..m).rev() {
                let f = s * e[i];
                let b = c * e[i];
                let r = norm_of_pair(f, g);
                e[i + 1] = r;
                if r == 0.0 {
                    // The bulge vanished: the block splits at i + 1; sweep again.
                    d[i + 1] -= p;
                    e[m] = 0.0;
                    split = true;
                    break;
                }
                s = f / r;
                c = g / r;
                g = d[i + 1] - p;
                let t = (d[i] - g) * s + 2.0 * c * b;
                p = s * t;
                d[i + 1] = g + p;
                g = c * t - b;
                // Columns i, i + 1 of Z, last row only.
                let zi = z[i + 1];
                z[i + 1] = s * z[i] + c * zi;
                z[i] = c * z[i] - s * zi;
            }
            if !split {
                d[l] -= p;
                e[l] = g;
                e[m] = 0.0;
            }
        }
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| d[a].total_cmp(&d[b]));
    Ok((
        order.iter().map(|&i| d[i]).collect(),
        order.iter().map(|&i| z[i].abs()).collect(),
    ))
}

fn check_square<T>(a: &DenseMatrix<T>, which: &'static str) -> Result<(), EigError<T>>
where
    T: Scalar<Real = f64>,
{
    if a.nrows() != a.ncols() {
        return Err(EigError::NotSquare {
            which,
            nrows: a.nrows(),
            ncols: a.ncols(),
        });
    }
    if a.as_slice().iter().any(|v| !v.is_finite()) {
        return Err(EigError::NonFinite(which));
    }
    Ok(())
}

/// `factor · m`, scaled in place (no copy when `factor` is 1).
fn scaled<T: Scalar<Real = f64>>(mut m: DenseMatrix<T>, factor: f64) -> DenseMatrix<T> {
    if factor != 1.0 {
        m.as_mut_slice()
            .iter_mut()
            .for_each(|v| *v = v.scale(factor));
    }
    m
}

/// The Hermitian matrix the lower triangle of the square `a` defines: `aᵢⱼ` below the
/// diagonal, its conjugate above, the real parts on the diagonal. This, not `a`, is what the
/// solvers read, so that the unread entries (the upper triangle, the imaginary parts of the
/// diagonal) can neither change a result nor set the scale of its computation.
fn lower_hermitian<T: Scalar<Real = f64>>(a: &DenseMatrix<T>) -> DenseMatrix<T> {
    DenseMatrix::from_fn(a.nrows(), a.nrows(), |i, j| {
        if i > j {
            a[(i, j)]
        } else if i < j {
            a[(j, i)].conj()
        } else {
            T::from_real(a[(i, i)].re())
        }
    })
}

/// All eigenpairs `A xᵢ = xᵢ λᵢ` of a dense Hermitian matrix (only the lower triangle is
/// read; the upper one is taken to be its conjugate transpose). Eigenvalues ascending,
/// eigenvectors orthonormal.
///
/// A matrix whose largest component is outside `2^±100` is solved as a copy scaled by a
/// power of two and its eigenvalues scaled back (exact), so that no norm of the reduction
/// overflows or underflows (at `1e−200` the off-diagonal entries vanished from the norms and
/// the diagonal came back as the eigenvalues).
pub fn hermitian_eigen<T: Scalar<Real = f64>>(
    a: &DenseMatrix<T>,
) -> Result<DenseEigen<T>, EigError<T>> {
    check_square(a, "A")?;
    Ok(full_hermitian_eigen(lower_hermitian(a))?)
}

/// [`hermitian_eigen`] of a full Hermitian matrix `h` (both triangles consistent), scaled
/// into the unit range first when it is far from it.
fn full_hermitian_eigen<T: Scalar<Real = f64>>(
    h: DenseMatrix<T>,
) -> Result<DenseEigen<T>, DenseEigenError> {
    let factor = scaling::unit_range_factor(T::as_reals(h.as_slice()), false);
    let mut eigen = tridiagonal_eigen(scaled(h, factor))?;
    eigen.values.iter_mut().for_each(|v| *v /= factor);
    Ok(eigen)
}

/// `(x/|x|, |x|)` (`(1, 0)` for `x = 0`), with `x` divided by its largest component before
/// the squares are taken: a component of 1e−160 squared underflows, and the phase of the
/// reflector, off unit length, made the eigenvectors non-orthogonal by 1e−5 (found by the
/// `dense_eigen` fuzz target).
fn polar<T: Scalar<Real = f64>>(x: T) -> (T, f64) {
    let mut y = [x];
    let reals = T::as_reals_mut(&mut y);
    let largest = scaling::largest_magnitude(reals);
    if largest == 0.0 {
        return (T::one(), 0.0);
    }
    reals.iter_mut().for_each(|c| *c /= largest);
    let norm = y[0].abs();
    (y[0].scale(1.0 / norm), largest * norm)
}

/// Largest component below which a column below the diagonal is taken as zero instead of
/// reflected: the squares of such components underflow, so its norm would be inexact (and
/// `τ` overflow), and against the matrix — whose largest component is at least `2⁻¹⁰⁰`
/// after [`full_hermitian_eigen`]'s scaling — they are below `10⁻¹¹⁹` of it, far below
/// rounding.
const NEGLIGIBLE: f64 = 1e-150;

/// The Householder reflectors `(v, τ)` of a reduction to tridiagonal form (`τ = 0`: none
/// needed) and the subdiagonal `tᵢ` it leaves.
pub(crate) struct Tridiagonal<T> {
    pub reflectors: Vec<(Vec<T>, f64)>,
    pub sub: Vec<T>,
}

/// Reduces the full Hermitian `h` in place to `H_{n−2} ⋯ H₀ h H₀ ⋯ H_{n−2}`, whose diagonal (in
/// `h`) and subdiagonal (returned) are the tridiagonal matrix; the other entries of `h` are left
/// stale. Reflector `Hₖ` acts on indices `k + 1..`, so `e₀` is fixed: `H e₀ = e₀` for the product.
pub(crate) fn reduce_to_tridiagonal<T: Scalar<Real = f64>>(
    h: &mut DenseMatrix<T>,
) -> Tridiagonal<T> {
    let n = h.nrows();
    let mut reflectors: Vec<(Vec<T>, f64)> = Vec::with_capacity(n.saturating_sub(1));
    let mut sub = vec![T::zero(); n.saturating_sub(1)];
    let mut p = vec![T::zero(); n];
    for k in 0..n.saturating_sub(1) {
        let m = n - k - 1;
        let mut v: Vec<T> = (0..m).map(|i| h[(k + 1 + i, k)]).collect();
        if scaling::largest_magnitude(T::as_reals(&v)) < NEGLIGIBLE {
            reflectors.push((v, 0.0));
            continue;
        }
        let norm_x = vector::norm(&v);
        let (phase, a0) = polar(v[0]);
        let alpha = -phase.scale(norm_x);
        v[0] -= alpha;
        // `v` divided by `‖x‖`: entries of order 1 and `τ = 2/‖v‖² = 1/(1 + |x₁|/‖x‖)` in
        // `[½, 1]` (`‖x − e₁α‖² = 2‖x‖² + 2‖x‖|x₁|`), where `2/‖x − e₁α‖²` overflowed for a
        // column of norm 1e−160.
        vector::scale(&mut v, 1.0 / norm_x);
        let tau = 1.0 / (1.0 + a0 / norm_x);
        sub[k] = alpha;
        // p = τ A₂₂ v, γ = τ Re(vᴴ p), w = p − v γ/2, A₂₂ ← A₂₂ − v wᴴ − w vᴴ.
        let p = &mut p[..m];
        for (i, pi) in p.iter_mut().enumerate() {
            *pi = (0..m)
                .map(|j| h[(k + 1 + i, k + 1 + j)] * v[j])
                .sum::<T>()
                .scale(tau);
        }
        let gamma = tau * vector::real_inner(&v, p);
        for (pi, &vi) in p.iter_mut().zip(&v) {
            *pi -= vi.scale(gamma / 2.0);
        }
        for j in 0..m {
            for i in 0..m {
                h[(k + 1 + i, k + 1 + j)] -= v[i] * p[j].conj() + p[i] * v[j].conj();
            }
        }
        reflectors.push((v, tau));
    }
    Tridiagonal { reflectors, sub }
}

/// The Householder reduction of the full Hermitian `h` to a real tridiagonal matrix, its
/// eigenpairs, and the eigenvectors carried back (module documentation).
fn tridiagonal_eigen<T: Scalar<Real = f64>>(
    mut h: DenseMatrix<T>,
) -> Result<DenseEigen<T>, DenseEigenError> {
    let n = h.nrows();
    let Tridiagonal { reflectors, sub } = reduce_to_tridiagonal(&mut h);
    // Diagonal unitary scaling making the subdiagonal real and non-negative.
    let mut d = vec![T::one(); n];
    let mut tri = Mat::<f64>::zeros(n, n);
    for i in 0..n {
        tri[(i, i)] = h[(i, i)].re();
    }
    for i in 0..n.saturating_sub(1) {
        let t = sub[i].abs();
        tri[(i + 1, i)] = t;
        tri[(i, i + 1)] = t;
        if t > 0.0 {
            d[i + 1] = (sub[i] * d[i]).scale(1.0 / t);
        }
    }
    let (values, z) = real_symmetric_eigen(tri.as_ref())?;
    let mut x = DenseMatrix::from_fn(n, n, |i, j| d[i].scale(z[(i, j)]));
    for (k, (v, tau)) in reflectors.iter().enumerate().rev() {
        if *tau == 0.0 {
            continue;
        }
        for j in 0..n {
            let col = &mut x.col_mut(j)[k + 1..];
            let c = vector::inner(v, col).scale(*tau);
            vector::axpy(col, v, -c);
        }
    }
    Ok(DenseEigen { values, vectors: x })
}

/// All eigenpairs of the dense Hermitian-definite pencil `K xᵢ = μᵢ S xᵢ` (lower triangles
/// read), through `S = U Λ Uᴴ`, `W = U Λ^{−1/2}` and the Hermitian eigenproblem of `Wᴴ K W`.
/// Eigenvalues ascending; eigenvectors `S`-orthonormal (`xᵢᴴ S xⱼ = δᵢⱼ`).
/// `S` must be positive definite ([`EigError::EmbeddedFactorization`] otherwise).
pub fn generalized_hermitian_eigen<T: Scalar<Real = f64>>(
    k: &DenseMatrix<T>,
    s: &DenseMatrix<T>,
) -> Result<DenseEigen<T>, EigError<T>> {
    check_square(k, "K")?;
    check_square(s, "S")?;
    if k.nrows() != s.nrows() {
        return Err(EigError::DimensionMismatch {
            expected: s.nrows(),
            found: k.nrows(),
            context: "rows of K against S",
        });
    }
    // The matrices as read; far from unit size, `(a K) x' = μ' (b S) x'` with powers of two,
    // `μ = μ' b / a` and `x = x' √b` (`b` a power of four), as in `hermitian_eigen`.
    let (k, s) = (lower_hermitian(k), lower_hermitian(s));
    let (a, b) = (
        scaling::unit_range_factor(T::as_reals(k.as_slice()), false),
        scaling::unit_range_factor(T::as_reals(s.as_slice()), true),
    );
    let (k, s) = (scaled(k, a), scaled(s, b));
    let es = full_hermitian_eigen(s)?;
    let scale = scaling::largest_magnitude(&es.values);
    if let Some(i) = es
        .values
        .iter()
        .position(|&l| l.is_nan() || l <= 1e-14 * scale)
    {
        return Err(EigError::EmbeddedFactorization(
            EmbeddedFactorizationError::NonPositiveEigenvalue {
                index: i,
                value: es.values[i] / b,
            },
        ));
    }
    let n = k.nrows();
    let w = DenseMatrix::from_fn(n, n, |i, j| {
        es.vectors[(i, j)].scale(es.values[j].powf(-0.5))
    });
    let projected = w
        .adjoint()
        .matmul(&k)
        .and_then(|kw| kw.matmul(&w))
        .expect("square factors of equal size");
    // Hermitian up to rounding: its lower triangle is what the solver reads.
    let eigen = full_hermitian_eigen(lower_hermitian(&projected))?;
    let vectors = w
        .matmul(&eigen.vectors)
        .expect("square factors of equal size");
    Ok(DenseEigen {
        // In this order: `b / a` alone can overflow, and `0 · ∞` is NaN.
        values: eigen.values.iter().map(|v| v * b / a).collect(),
        vectors: scaled(vectors, b.sqrt()),
    })
}

#[cfg(test)]
mod tests {
    use super::tridiagonal_values_and_last_components;

    /// The second-difference matrix (2 on the diagonal, −1 beside it) of order `n` has the
    /// eigenvalues `2 − 2 cos(kπ/(n + 1))` with unit eigenvectors
    /// `√(2/(n + 1)) sin(jkπ/(n + 1))`, `j, k = 1..n`.
    #[test]
    fn second_difference_matrix_in_closed_form() {
        for n in [1, 2, 3, 10, 57] {
            let (values, last) =
                tridiagonal_values_and_last_components(&vec![2.0; n], &vec![-1.0; n - 1]).unwrap();
            let angle = std::f64::consts::PI / (n + 1) as f64;
            for k in 1..=n {
                let value = 2.0 - 2.0 * (k as f64 * angle).cos();
                let component =
                    ((2.0 / (n + 1) as f64).sqrt() * (n as f64 * k as f64 * angle).sin()).abs();
                assert!((values[k - 1] - value).abs() < 1e-14, "n {n}, k {k}");
                assert!((last[k - 1] - component).abs() < 1e-14, "n {n}, k {k}");
            }
        }
    }

    /// Zero couplings split the matrix: the eigenvalues are the diagonal, sorted, and only
    /// the last index's own eigenvector has a last component.
    #[test]
    fn decoupled_matrix_is_its_diagonal() {
        let (values, last) =
            tridiagonal_values_and_last_components(&[3.0, -1.0, 2.0], &[0.0, 0.0]).unwrap();
        assert_eq!(values, vec![-1.0, 2.0, 3.0]);
        assert_eq!(last, vec![0.0, 1.0, 0.0]);
    }

    #[test]
    fn non_finite_entries_are_an_error() {
        assert!(tridiagonal_values_and_last_components(&[1.0, 2.0], &[f64::NAN]).is_err());
    }
}
