//! The Hermitian-definite pencil solver: `K x = μ S x` with `S` Hermitian positive definite.
//!
//! With `S = C Cᴴ` from the backend's Cholesky, the Lanczos core runs on
//! `A = C⁻¹ K C⁻ᴴ` (same eigenvalues `μ`; `x = C⁻ᴴ y`), `S`-orthogonal to the deflation
//! vectors. The converged pairs are then **folded**: sorted by value, grouped into clusters
//! (consecutive values closer than `max(100 tol, 1e−8)` relative plus the rounding level
//! `64 eps maxᵢ |μᵢ|` of the operator, which bounds the spread of copies of one eigenvalue
//! accepted at that level), and in each cluster an
//! `S`-orthonormal quaternionic basis is extracted by pivoted Gram–Schmidt with coefficients
//! on the right (a vector whose remaining `S`-norm is below 0.1 lies in the quaternionic span
//! of the others: for the embedded backends these are the 4 or 2 copies `x`, `x i`, `x j`,
//! `x k` of one quaternionic eigenvector). A Rayleigh–Ritz step on the cluster
//! (`Qᴴ K Q`, dense quaternion solver) gives the returned pairs. For the native backend this
//! only re-orthonormalises; for the embedded ones it returns one pair per quaternionic
//! eigenvalue with its quaternionic multiplicity.

use std::time::Instant;

use qscalar::Scalar;
use qsparse::{DenseMatrix, SparseMatrix, vector};

use crate::basis::{Basis, GramSchmidt, append_orthonormal};
use crate::dense::hermitian_eigen;
use crate::lanczos::{ROUNDING, run, validate_options};
use crate::{
    Backend, EigError, Eigen, HermitianOperator, LanczosOptions, PencilOperator, Progress, Which,
};

/// A Hermitian-definite pencil `K x = μ S x` (`K` Hermitian, `S` Hermitian positive definite)
/// with an optional deflation subspace.
///
/// ```
/// use qeig::{LanczosOptions, Native, Pencil, Which};
/// use qsparse::SparseMatrix;
/// // K = diag(1, 2, 3, 4), S = 2 I: μ = 0.5, 1, 1.5, 2.
/// let k = SparseMatrix::from_diagonal(&[1.0, 2.0, 3.0, 4.0]);
/// let s = SparseMatrix::from_diagonal(&[2.0; 4]);
/// let eig = Pencil::new(&k, &s)?.solve(&Native, &LanczosOptions::new(2, Which::LargestAlgebraic))?;
/// assert!((eig.values[0] - 2.0).abs() < 1e-12 && (eig.values[1] - 1.5).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct Pencil<'a, T> {
    k: &'a SparseMatrix<T>,
    s: &'a SparseMatrix<T>,
    deflation: Vec<Vec<T>>,
}

impl<'a, T: Scalar<Real = f64>> Pencil<'a, T> {
    /// The pencil `K x = μ S x`. Both matrices must be square of the same size; only their
    /// lower triangles are read by the factorisations (they are taken to be Hermitian).
    pub fn new(k: &'a SparseMatrix<T>, s: &'a SparseMatrix<T>) -> Result<Self, EigError<T>> {
        for (which, m) in [("K", k), ("S", s)] {
            if m.nrows() != m.ncols() {
                return Err(EigError::NotSquare {
                    which,
                    nrows: m.nrows(),
                    ncols: m.ncols(),
                });
            }
            if m.values().iter().any(|v| !v.is_finite()) {
                return Err(EigError::NonFinite(which));
            }
        }
        if k.nrows() != s.nrows() {
            return Err(EigError::DimensionMismatch {
                expected: s.nrows(),
                found: k.nrows(),
                context: "dimension of K against S",
            });
        }
        Ok(Self {
            k,
            s,
            deflation: Vec::new(),
        })
    }

    /// Keeps the iteration `S`-orthogonal to the quaternionic span of `vectors`
    /// (`dᴴ S x = 0`), for example the constants for the Laplacian pencil
    /// `M x = μ (L + εM) x`. Eigenpairs inside that span are not computed.
    pub fn with_deflation(mut self, vectors: Vec<Vec<T>>) -> Result<Self, EigError<T>> {
        let n = self.dim();
        for d in &vectors {
            if d.len() != n {
                return Err(EigError::DimensionMismatch {
                    expected: n,
                    found: d.len(),
                    context: "deflation vector",
                });
            }
            if d.iter().any(|v| !v.is_finite()) {
                return Err(EigError::NonFinite("deflation vector"));
            }
        }
        self.deflation = vectors;
        Ok(self)
    }

    /// Dimension `n`.
    pub fn dim(&self) -> usize {
        self.s.nrows()
    }

    /// The `options.k` eigenpairs selected by `options.which` (see [`Eigen`] for ordering and
    /// normalisation), computed with `backend`.
    pub fn solve<B: Backend<T>>(
        &self,
        backend: &B,
        options: &LanczosOptions,
    ) -> Result<Eigen<T>, EigError<T>> {
        self.solve_with_progress(backend, options, None)
    }

    /// [`Pencil::solve`] with a callback invoked after every restart.
    pub fn solve_with_progress<B: Backend<T>>(
        &self,
        backend: &B,
        options: &LanczosOptions,
        progress: Option<&mut dyn FnMut(&Progress)>,
    ) -> Result<Eigen<T>, EigError<T>> {
        let start = Instant::now();
        validate_options(options)?;
        let n = self.dim();
        let available = n.saturating_sub(self.deflation.len());
        if options.k == 0 || options.k > available {
            return Err(EigError::InvalidCount {
                k: options.k,
                available,
            });
        }
        let mut op = backend.prepare(self.k, self.s)?;
        let factorization_time = start.elapsed();

        // Deflation in the iteration space: Cᴴ (d e_c) for every unit e_c, orthonormalised.
        let dim = op.dim();
        let mut basis = Basis::new(dim);
        let mut gs = GramSchmidt::new();
        let mut coef = Vec::new();
        for d in &self.deflation {
            for c in 0..T::REAL_DIM {
                let e: T = vector::unit(c);
                let dc: Vec<T> = d.iter().map(|&x| x * e).collect();
                let mut y = op.adjoint_factor(&backend.embed(&dc));
                append_orthonormal(&mut basis, &mut gs, &mut y, &mut coef);
            }
        }

        let outcome = run(&mut op, options, options.k * B::COPIES, basis, progress)
            .map_err(EigError::DenseEigen)?;
        let mut values = Vec::new();
        let mut vectors = Vec::new();
        for (y, &theta) in outcome.vectors.iter().zip(&outcome.values) {
            for x in backend.extract(&op.eigenvector(y)) {
                values.push(theta);
                vectors.push(x);
            }
        }
        let (mut values, mut vectors) = fold(
            self.k,
            self.s,
            &values,
            vectors,
            options.which,
            options.tolerance,
        )?;
        values.truncate(options.k);
        vectors.truncate(options.k);
        let residuals = values
            .iter()
            .zip(&vectors)
            .map(|(&mu, x)| relative_residual(self.k, self.s, mu, x))
            .collect();
        let mut statistics = outcome.statistics;
        (statistics.solves, statistics.solve_time) = op.solve_statistics();
        statistics.factorization_time = factorization_time;
        statistics.total_time = start.elapsed();
        let result = Eigen {
            values,
            vectors,
            residuals,
            statistics,
        };
        if outcome.converged && result.values.len() == options.k {
            Ok(result)
        } else {
            Err(EigError::NotConverged {
                wanted: options.k,
                partial: Box::new(result),
            })
        }
    }
}

/// `‖K x − μ S x‖ / (|μ| ‖S x‖)`.
fn relative_residual<T: Scalar<Real = f64>>(
    k: &SparseMatrix<T>,
    s: &SparseMatrix<T>,
    mu: f64,
    x: &[T],
) -> f64 {
    let n = x.len();
    let (mut kx, mut sx) = (vec![T::zero(); n], vec![T::zero(); n]);
    k.mul_vec(x, &mut kx).expect("length n");
    s.mul_vec(x, &mut sx).expect("length n");
    let s_norm = vector::norm(&sx);
    vector::axpy(&mut kx, &sx, T::from_real(-mu));
    vector::norm(&kx) / (mu.abs() * s_norm)
}

/// Eigenvalues and eigenvectors, in matching order.
type Pairs<T> = (Vec<f64>, Vec<Vec<T>>);

/// Folds converged pairs into one quaternionic pair per eigenvalue (module documentation);
/// returns them sorted by wantedness.
fn fold<T: Scalar<Real = f64>>(
    k: &SparseMatrix<T>,
    s: &SparseMatrix<T>,
    values: &[f64],
    vectors: Vec<Vec<T>>,
    which: Which,
    tol: f64,
) -> Result<Pairs<T>, EigError<T>> {
    let n = s.nrows();
    let gap = (100.0 * tol).max(1e-8);
    let floor = ROUNDING * values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut vectors: Vec<Option<Vec<T>>> = vectors.into_iter().map(Some).collect();
    let mut pairs: Vec<(f64, Vec<T>)> = Vec::new();
    let mut start = 0;
    while start < order.len() {
        let mut end = start + 1;
        while end < order.len() {
            let (a, b) = (values[order[end - 1]], values[order[end]]);
            if b - a > gap * a.abs().max(b.abs()) + floor {
                break;
            }
            end += 1;
        }
        // Residual vectors and their S-images, projected as vectors are accepted.
        let mut members: Vec<(Vec<T>, Vec<T>)> = order[start..end]
            .iter()
            .map(|&i| {
                let x = vectors[i].take().expect("each vector is used once");
                let mut sx = vec![T::zero(); n];
                s.mul_vec(&x, &mut sx).expect("length n");
                (x, sx)
            })
            .collect();
        let mut basis: Vec<Vec<T>> = Vec::new();
        while !members.is_empty() {
            let norms: Vec<f64> = members
                .iter()
                .map(|(x, sx)| vector::inner(x, sx).re().max(0.0).sqrt())
                .collect();
            let (best, &norm) = norms
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .expect("non-empty");
            if norm < 0.1 {
                break;
            }
            let (mut q, mut sq) = members.swap_remove(best);
            vector::scale(&mut q, 1.0 / norm);
            vector::scale(&mut sq, 1.0 / norm);
            for (x, sx) in &mut members {
                let c = vector::inner(&sq, x);
                vector::axpy(x, &q, -c);
                vector::axpy(sx, &sq, -c);
            }
            basis.push(q);
        }
        // Rayleigh–Ritz on the cluster: H = Qᴴ K Q.
        let kq: Vec<Vec<T>> = basis
            .iter()
            .map(|q| {
                let mut y = vec![T::zero(); n];
                k.mul_vec(q, &mut y).expect("length n");
                y
            })
            .collect();
        let m = basis.len();
        let h = DenseMatrix::from_fn(m, m, |a, b| vector::inner(&basis[a], &kq[b]));
        let eig = hermitian_eigen(&h)?;
        for (j, &mu) in eig.values.iter().enumerate() {
            let mut x = vec![T::zero(); n];
            for (a, q) in basis.iter().enumerate() {
                vector::axpy(&mut x, q, eig.vectors[(a, j)]);
            }
            pairs.push((mu, x));
        }
        start = end;
    }
    pairs.sort_by(|a, b| which.score(b.0).total_cmp(&which.score(a.0)));
    Ok(pairs.into_iter().unzip())
}
