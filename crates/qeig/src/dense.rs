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

/// The copy `factor · m`.
fn scaled<T: Scalar<Real = f64>>(m: &DenseMatrix<T>, factor: f64) -> DenseMatrix<T> {
    DenseMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)].scale(factor))
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
    let n = a.nrows();
    let factor = scaling::unit_range_factor(T::as_reals(a.as_slice()), false);
    if factor != 1.0 {
        let mut eigen = hermitian_eigen(&scaled(a, factor))?;
        eigen.values.iter_mut().for_each(|v| *v /= factor);
        return Ok(eigen);
    }
    // Work on a full Hermitian copy built from the lower triangle.
    let mut h = DenseMatrix::from_fn(n, n, |i, j| {
        if i > j {
            a[(i, j)]
        } else if i < j {
            a[(j, i)].conj()
        } else {
            T::from_real(a[(i, i)].re())
        }
    });
    let mut reflectors: Vec<(Vec<T>, f64)> = Vec::with_capacity(n.saturating_sub(1));
    let mut sub = vec![T::zero(); n.saturating_sub(1)];
    let mut p = vec![T::zero(); n];
    for k in 0..n.saturating_sub(1) {
        let m = n - k - 1;
        let mut v: Vec<T> = (0..m).map(|i| h[(k + 1 + i, k)]).collect();
        let norm_x = vector::norm(&v);
        if norm_x == 0.0 {
            reflectors.push((v, 0.0));
            continue;
        }
        let x0 = v[0];
        let a0 = x0.abs();
        let phase = if a0 > 0.0 {
            x0.scale(1.0 / a0)
        } else {
            T::one()
        };
        let alpha = -phase.scale(norm_x);
        v[0] -= alpha;
        let tau = 2.0 / (2.0 * norm_x * norm_x + 2.0 * norm_x * a0);
        sub[k] = alpha;
        // p = τ A₂₂ v, γ = τ Re(vᴴ p), w = p − v γ/2, A₂₂ ← A₂₂ − v wᴴ − w vᴴ.
        let p = &mut p[..m];
        for (i, pi) in p.iter_mut().enumerate() {
            *pi = (0..m)
                .map(|j| h[(k + 1 + i, k + 1 + j)] * v[j])
                .sum::<T>()
                .scale(tau);
        }
        let gamma = tau * vector::inner(&v, p).re();
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
    // Far from unit size: `(a K) x' = μ' (b S) x'` with powers of two, `μ = μ' b / a` and
    // `x = x' √b` (`b` a power of four), as in `hermitian_eigen`.
    let (a, b) = (
        scaling::unit_range_factor(T::as_reals(k.as_slice()), false),
        scaling::unit_range_factor(T::as_reals(s.as_slice()), true),
    );
    if (a, b) != (1.0, 1.0) {
        let eigen = generalized_hermitian_eigen(&scaled(k, a), &scaled(s, b))?;
        return Ok(DenseEigen {
            values: eigen.values.iter().map(|v| v * (b / a)).collect(),
            vectors: scaled(&eigen.vectors, b.sqrt()),
        });
    }
    let es = hermitian_eigen(s)?;
    let scale = es.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if let Some(i) = es
        .values
        .iter()
        .position(|&l| l.is_nan() || l <= 1e-14 * scale)
    {
        return Err(EigError::EmbeddedFactorization(
            EmbeddedFactorizationError::NonPositiveEigenvalue {
                index: i,
                value: es.values[i],
            },
        ));
    }
    let n = s.nrows();
    let w = DenseMatrix::from_fn(n, n, |i, j| {
        es.vectors[(i, j)].scale(es.values[j].powf(-0.5))
    });
    let full_k = DenseMatrix::from_fn(
        n,
        n,
        |i, j| {
            if i >= j { k[(i, j)] } else { k[(j, i)].conj() }
        },
    );
    let b = w
        .adjoint()
        .matmul(&full_k)
        .and_then(|kw| kw.matmul(&w))
        .expect("square factors of equal size");
    let eb = hermitian_eigen(&b)?;
    let vectors = w.matmul(&eb.vectors).expect("square factors of equal size");
    Ok(DenseEigen {
        values: eb.values,
        vectors,
    })
}
