//! The Hermitian-definite pencil solver: `K x = μ S x` with `S` Hermitian positive definite.
//!
//! With `S = C Cᴴ` from the backend's Cholesky, the Lanczos core runs on
//! `A = C⁻¹ K C⁻ᴴ` (same eigenvalues `μ`; `x = C⁻ᴴ y`), restricted to the subspace of the
//! linear constraints `cᴴ x = 0` (in the iteration space `(C⁻¹ c)ᴴ y = 0`, one triangular solve
//! with the factor it already holds per constraint). The converged pairs are then **folded**: sorted by value, grouped into clusters
//! (consecutive values closer than `max(100 tol, 1e−8)` relative plus the rounding level
//! `64 eps maxᵢ |μᵢ|` of the operator, which bounds the spread of copies of one eigenvalue
//! accepted at that level), and in each cluster an
//! `S`-orthonormal quaternionic basis is extracted by pivoted Gram–Schmidt with coefficients
//! on the right (a vector whose remaining `S`-norm is below 0.1 lies in the quaternionic span
//! of the others: for the embedded backends these are the 4 or 2 copies `x`, `x i`, `x j`,
//! `x k` of one quaternionic eigenvector). For the embedded backends, clusters within `√tol`
//! of each other (the accuracy accepted at the rounding level) become one when together they
//! span less than apart: copies of one eigenvalue computed further apart than the cluster
//! width (an ill-conditioned `S` leaves errors far above the tolerance in the eigenvalues of a
//! small `|λ|`) would otherwise each count as a quaternionic eigenvalue of their own.
//! A Rayleigh–Ritz step on the cluster
//! (`Qᴴ K Q`, dense quaternion solver) gives the returned pairs. For the native backend this
//! only re-orthonormalises; for the embedded ones it returns one pair per quaternionic
//! eigenvalue with its quaternionic multiplicity.

use std::borrow::Cow;
use std::time::Instant;

use qscalar::Scalar;
use qsparse::{DenseMatrix, SparseCholesky, SparseMatrix, SparseVector, threads, vector};

use crate::backend::{MatVec, VECTORS_PER_PASS};
use crate::basis::Basis;
use crate::constraints::Constraints;
use crate::dense::hermitian_eigen;
use crate::lanczos::{ROUNDING, run, validate_options};
use crate::scaling;
use crate::{
    Backend, EigError, Eigen, HermitianOperator, LanczosOptions, PencilOperator, ProgressCallback,
    Which,
};

/// A Hermitian-definite pencil `K x = μ S x` (`K` Hermitian, `S` Hermitian positive definite)
/// with optional linear constraints `cᴴ x = 0`.
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
pub struct Pencil<'a, T: Clone> {
    /// `a K` and `b S`: the matrices as given, or copies scaled into the safe range
    /// ([`Scaling`]).
    k: Cow<'a, SparseMatrix<T>>,
    s: Cow<'a, SparseMatrix<T>>,
    scaling: Scaling,
    /// Constraint vectors `c` (columns): solutions satisfy `cᴴ x = 0`.
    constraints: SparseMatrix<T>,
    /// `(u, a w)`: the terms of `a (K − Σ w u uᴴ)`.
    low_rank: Vec<(SparseVector<T>, f64)>,
}

/// The powers of two `a` and `b` by which the pencil solves `(a K) x = μ' (b S) x` instead of
/// `K x = μ S x` (then `μ = μ' b / a` and `x = x' √b`), as LAPACK's `dsyev` scales a matrix
/// whose norm is outside its safe range: `1` while the largest component of an entry lies in
/// `[2⁻¹⁰⁰, 2¹⁰⁰]` (any matrix from a mesh of reasonable units, which are then solved exactly
/// as given), otherwise the power that brings it to `[½, 1)`. Squares of components, norms
/// and residual products then stay far from overflow and underflow, which for entries near
/// `1e±150` turned eigenvalues into NaN. `b` is a power of four, so that `√b` is exact.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Scaling {
    a: f64,
    b: f64,
}

impl Scaling {
    /// The power of two (of four if `even`) that brings the largest component of `m` into
    /// `[½, 1)`, or `1` when it is already within `2^±100` ([`scaling`]).
    fn of<T: Scalar<Real = f64>>(m: &SparseMatrix<T>, even: bool) -> f64 {
        scaling::unit_range_factor(T::as_reals(m.values()), even)
    }

    /// The copy `factor · m`, or `m` itself when `factor` is `1`.
    fn apply<T: Scalar<Real = f64>>(m: &SparseMatrix<T>, factor: f64) -> Cow<'_, SparseMatrix<T>> {
        if factor == 1.0 {
            Cow::Borrowed(m)
        } else {
            Cow::Owned(m.map(|v| v.scale(factor)))
        }
    }
}

impl<'a, T: Scalar<Real = f64>> Pencil<'a, T> {
    /// How far from Hermitian `K` and `S` may be, relative to their largest entry:
    /// `|Aᵢⱼ − conj(Aⱼᵢ)| ≤ HERMITIAN_TOLERANCE · maxᵢⱼ |Aᵢⱼ|`. Rounding in an assembly
    /// leaves defects near `1e−16`; a matrix given by one triangle, or a non-Hermitian one,
    /// has defects of the size of its entries.
    pub const HERMITIAN_TOLERANCE: f64 = 1e-10;

    /// The pencil `K x = μ S x`. Both matrices must be square of the same size and Hermitian
    /// (both triangles stored, [`EigError::NotHermitian`] otherwise): the factorisations read
    /// the lower triangles and the products the whole matrices, so a matrix that is not
    /// Hermitian would give a wrong spectrum, not an error, further on.
    ///
    /// A matrix whose largest entry is outside `2^±100` is solved as a copy scaled by a power
    /// of two (exact; the results are scaled back), so that no norm overflows or underflows.
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
        let scaling = Scaling {
            a: Scaling::of(k, false),
            b: Scaling::of(s, true),
        };
        let (k, s) = (Scaling::apply(k, scaling.a), Scaling::apply(s, scaling.b));
        for (which, m, factor) in [("K", &k, scaling.a), ("S", &s, scaling.b)] {
            // On the scaled matrix, where no norm overflows or underflows.
            let largest = m.values().iter().fold(0.0f64, |l, v| l.max(v.abs()));
            if let Some(worst) = m.largest_hermitian_defect()
                && worst.defect > Self::HERMITIAN_TOLERANCE * largest
            {
                return Err(EigError::NotHermitian {
                    which,
                    row: worst.row,
                    col: worst.col,
                    defect: worst.defect / factor,
                    largest: largest / factor,
                });
            }
        }
        let n = s.nrows();
        Ok(Self {
            k,
            s,
            scaling,
            constraints: SparseMatrix::zeros(n, 0),
            low_rank: Vec::new(),
        })
    }

    /// Restricts the pencil to `{x : cᴴ x = 0 for every c in the quaternionic span of the
    /// columns of constraints}` (an `n × c` sparse matrix: constraints local to parts of the
    /// problem, one per component of a mesh, cost the size of their supports, not `c · n`):
    /// the eigenpairs of the pencil compressed to that subspace, with test vectors from the
    /// same subspace (`K x − μ S x ∈ span(S⁻¹…)` is not required; the compression is what
    /// [`Pencil::solve`] returns). Two common uses:
    /// * `c = S d` keeps the iteration `S`-orthogonal to `d` (deflation of a known eigenvector
    ///   `d`: the remaining pairs are the others);
    /// * `c = M 𝟙` for the Laplacian pencil `M x = μ (L + εM) x` makes every vector exactly
    ///   mass-orthogonal to the constants.
    ///
    /// Dense vectors become such a matrix with [`SparseMatrix::from_dense_columns`].
    pub fn with_constraints(mut self, constraints: SparseMatrix<T>) -> Result<Self, EigError<T>> {
        let n = self.dim();
        if constraints.nrows() != n {
            return Err(EigError::DimensionMismatch {
                expected: n,
                found: constraints.nrows(),
                context: "constraint vector",
            });
        }
        if constraints.values().iter().any(|v| !v.is_finite()) {
            return Err(EigError::NonFinite("constraint vector"));
        }
        self.constraints = constraints;
        Ok(self)
    }

    /// Replaces `K` by the Hermitian `K − Σ w u uᴴ` over the given `(u, w)` (`u uᴴ` acting on
    /// the quaternionic span of `u`: `x ↦ u (uᴴ x)`), without forming it: for example the
    /// compression `PᴴKP` of `K` by an oblique projection `P = I − 𝟙 gᴴ / (gᴴ𝟙)`. The
    /// vectors are sparse (the constant of one piece of a mesh touches that piece: a dense
    /// term per piece would cost `n` per piece and application).
    pub fn with_low_rank_update(
        mut self,
        terms: Vec<(SparseVector<T>, f64)>,
    ) -> Result<Self, EigError<T>> {
        let n = self.dim();
        for (u, w) in &terms {
            if u.values.len() != u.rows.len() {
                return Err(EigError::DimensionMismatch {
                    expected: u.rows.len(),
                    found: u.values.len(),
                    context: "low-rank update vector (values against rows)",
                });
            }
            if let Some(&row) = u.rows.iter().find(|&&row| row >= n) {
                return Err(EigError::DimensionMismatch {
                    expected: n,
                    found: row + 1,
                    context: "low-rank update vector (a row beyond the dimension)",
                });
            }
            if u.values.iter().any(|v| !v.is_finite()) || !w.is_finite() {
                return Err(EigError::NonFinite("low-rank update"));
            }
        }
        self.low_rank = (terms.into_iter())
            .map(|(u, w)| (u, w * self.scaling.a))
            .collect();
        Ok(self)
    }

    /// `(K − Σ w u uᴴ) x`.
    fn k_mul(&self, x: &[T]) -> Vec<T> {
        let mut y = vec![T::zero(); x.len()];
        self.k.mul(x, &mut y);
        for (u, w) in &self.low_rank {
            u.add_to(&mut y, u.inner(x) * T::from_real(-w));
        }
        y
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

    /// [`Pencil::solve`] with a progress callback ([`ProgressCallback`]: after every restart, and
    /// between restarts at least every 0.1 s).
    pub fn solve_with_progress<B: Backend<T>>(
        &self,
        backend: &B,
        options: &LanczosOptions,
        progress: Option<ProgressCallback>,
    ) -> Result<Eigen<T>, EigError<T>> {
        let start = Instant::now();
        validate_options(options)?;
        let n = self.dim();
        let available = n.saturating_sub(self.constraints.ncols());
        if options.k == 0 || options.k > available {
            return Err(EigError::InvalidCount {
                k: options.k,
                available,
            });
        }
        let mut op = backend.prepare(&self.k, &self.s)?;
        // A term u uᴴ over T is Σ_e (u e)(u e)ᴴ over the units e in the embedded field, where
        // the REAL_DIM units give each distinct term REAL_DIM / COPIES times.
        op.subtract_low_rank(
            (self.low_rank.iter())
                .flat_map(|(u, w)| (0..T::REAL_DIM).map(move |c| (u.times(unit(c)), *w)))
                .map(|(ue, w)| {
                    (
                        backend.embed_sparse(&ue, n),
                        w * B::COPIES as f64 / T::REAL_DIM as f64,
                    )
                })
                .collect(),
        );
        let factorization_time = start.elapsed();

        // Constraints in the iteration space: C⁻¹ (c e_u) for every unit e_u, orthonormalised
        // (and stored over their supports: one per component of a mesh is local). Where each
        // eigenvalue occurs once (the iteration runs over `T` itself) the `c e_u` are one
        // direction `c` over the field, and the others would only be found dependent after a
        // Gram–Schmidt pass each (an open prism of 256 flat panels: 2,048 members against up
        // to 512 directions, 50 s).
        let dim = op.dim();
        let constraints = &self.constraints;
        let units = if B::COPIES == 1 { 1 } else { T::REAL_DIM };
        let directions = columns(constraints)
            .flat_map(|c| (0..units).map(move |u| c.times(unit(u))))
            .map(|ce| op.constraint_direction(&backend.embed_sparse(&ce, n)));
        let basis = Basis::constrained(dim, directions);

        let outcome = run(&mut op, options, options.k * B::COPIES, basis, progress)?;
        let mut values = Vec::new();
        let mut vectors = Vec::new();
        // `x = C⁻ᴴ y`, a few pairs per read of the factor, consuming the iteration vectors as
        // it goes, so that they and the pencil's are never all held at once (at a million
        // unknowns, k vectors are gigabytes).
        let mut iteration_vectors = outcome.vectors.into_iter();
        for thetas in outcome.values.chunks(VECTORS_PER_PASS) {
            let mut block: Vec<B::Field> = (iteration_vectors.by_ref())
                .take(thetas.len())
                .flatten()
                .collect();
            op.eigenvectors_in_place(&mut block);
            for (y, &theta) in block.chunks_exact(dim).zip(thetas) {
                for x in backend.extract(y) {
                    values.push(theta);
                    vectors.push(x);
                }
            }
        }
        let mut pairs = fold(
            |x| self.k_mul(x),
            &self.s,
            &TestSpace::of(&self.constraints),
            Converged {
                values: &values,
                vectors,
                copies: B::COPIES > 1,
            },
            options.which,
            options.tolerance,
        )?;
        // Back from the scaled pencil (exact: powers of two).
        let Scaling { a, b } = self.scaling;
        for p in &mut pairs {
            // In this order: `b / a` alone can overflow (`2¹⁰²²/2⁻¹⁰²²`), and `0 · ∞` is NaN.
            p.value = p.value * b / a;
            if b != 1.0 {
                vector::scale(&mut p.vector, b.sqrt());
            }
        }
        // A pencil whose entries span more than the floating-point range (an `S` with
        // diagonal entries 1 and 1e180) can overflow inside the fold: such a pair has not
        // converged, whatever the Lanczos estimate said.
        pairs.retain(|p| p.value.is_finite() && p.vector.iter().all(|v| v.is_finite()));
        pairs.truncate(options.k);
        let values = pairs.iter().map(|p| p.value).collect();
        let residuals = pairs.iter().map(|p| p.residual).collect();
        let vectors = pairs.into_iter().map(|p| p.vector).collect();
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

impl<T: Scalar<Real = f64>> Pencil<'_, T> {
    /// Computed pairs of largest `|μ|` improved by one step of subspace iteration: `X' = T K X`,
    /// `T` the solution operator of `S` on the constrained subspace (`x' = S⁻¹(K x − C a)`, with
    /// `a` such that `Cᴴ x' = 0`), then a Rayleigh–Ritz step on `span X'` with `K` and `S`
    /// themselves. Components along eigenvectors outside the window shrink by `|μ_out / μᵢ|`,
    /// and the Rayleigh–Ritz step is as accurate as the products with the matrices: where the
    /// Lanczos vectors carry errors well above rounding (an ill-conditioned `S` and clustered
    /// eigenvalues, such as the smallest of a Dirac operator on a finely faceted cylinder),
    /// a step or two bring them to it.
    ///
    /// For the pairs of largest magnitude only ([`Which::LargestMagnitude`], or
    /// [`Which::LargestAlgebraic`] where every eigenvalue is positive), as [`Pencil::solve`]
    /// returned them: the `eigen.values.len()` of largest `|μ|` in the span are returned, in
    /// that order, with their residuals (as [`Eigen`] says). The step runs over `T` with its
    /// own factorisation of `S`, whatever backend computed the pairs, and costs a solve per
    /// pair and one per constraint.
    pub fn refine(&self, eigen: &Eigen<T>) -> Result<Eigen<T>, EigError<T>> {
        let start = Instant::now();
        let Scaling { a, b } = self.scaling;
        let factor = SparseCholesky::factorize(&self.s)?;
        let constrained = ConstrainedSolve::new(&factor, &self.constraints)?;
        // `S`-orthonormal by two passes of Gram–Schmidt (coefficients on the right), each
        // vector with its products; one found dependent on the others is dropped.
        let mut basis: Vec<WithProducts<T>> = Vec::with_capacity(eigen.vectors.len());
        for x in &eigen.vectors {
            // Into the scaled pencil: `x' = x / √b`.
            let x: Vec<T> = x.iter().map(|v| v.scale(1.0 / b.sqrt())).collect();
            let mut next = self.k_mul(&x);
            constrained.solve_in_place(&mut next)?;
            let s_norm = |x: &[T]| {
                let mut sx = vec![T::zero(); x.len()];
                self.s.mul(x, &mut sx);
                (vector::real_inner(x, &sx).max(0.0).sqrt(), sx)
            };
            let (before, _) = s_norm(&next);
            for _ in 0..2 {
                for q in &basis {
                    let c = vector::inner(&q.sx, &next);
                    vector::axpy(&mut next, &q.x, -c);
                }
            }
            let (norm, mut sx) = s_norm(&next);
            // A NaN norm is dependent too.
            if norm.is_nan() || norm <= DEPENDENT * before {
                continue;
            }
            vector::scale(&mut next, 1.0 / norm);
            vector::scale(&mut sx, 1.0 / norm);
            let kx = self.k_mul(&next);
            basis.push(WithProducts { x: next, kx, sx });
        }
        let m = basis.len();
        let h = DenseMatrix::from_fn(m, m, |i, j| vector::inner(&basis[i].x, &basis[j].kx));
        let ritz = hermitian_eigen(&h)?;
        let mut order: Vec<usize> = (0..m).collect();
        order.sort_by(|&i, &j| ritz.values[j].abs().total_cmp(&ritz.values[i].abs()));
        order.truncate(eigen.values.len());
        let test_space = TestSpace::of(&self.constraints);
        let pairs: Vec<Folded<T>> = (order.iter())
            .map(|&j| {
                WithProducts::combination(&basis, |i| ritz.vectors[(i, j)])
                    .relative_residual(ritz.values[j], &test_space)
            })
            .collect();
        let mut statistics = eigen.statistics;
        statistics.solves += 2 * (eigen.vectors.len() + self.constraints.ncols());
        statistics.total_time += start.elapsed();
        Ok(Eigen {
            values: pairs.iter().map(|p| p.value * b / a).collect(),
            residuals: pairs.iter().map(|p| p.residual).collect(),
            vectors: (pairs.into_iter())
                .map(|p| p.vector.iter().map(|v| v.scale(b.sqrt())).collect())
                .collect(),
            statistics,
        })
    }
}

/// A vector of [`Pencil::refine`]'s step whose `S`-norm falls below this fraction of its
/// norm when orthogonalised against the previous ones is in their span.
const DEPENDENT: f64 = 1e-10;

/// Solves with `S` on the subspace `Cᴴ x = 0`: `x = S⁻¹(y − C a)` with `a` such that
/// `Cᴴ x = 0`, i.e. `x = S⁻¹ y − W G⁻¹ Wᴴ y` with `W = S⁻¹ C` and `G = Cᴴ S⁻¹ C`.
struct ConstrainedSolve<'f, T: Scalar> {
    factor: &'f SparseCholesky<T>,
    /// The columns of `C`.
    columns: Vec<SparseVector<T>>,
    /// `W = S⁻¹ C`, by column.
    solved: Vec<Vec<T>>,
    /// `G⁻¹` through `G = U Λ Uᴴ`: the columns `U` and `1/Λ` (zero for a direction where `G`
    /// is singular to rounding: dependent constraints).
    eigenvectors: DenseMatrix<T>,
    inverse_values: Vec<f64>,
}

impl<'f, T: Scalar<Real = f64>> ConstrainedSolve<'f, T> {
    fn new(factor: &'f SparseCholesky<T>, c: &'f SparseMatrix<T>) -> Result<Self, EigError<T>> {
        let columns: Vec<SparseVector<T>> = columns(c).collect();
        let mut solved = Vec::with_capacity(columns.len());
        for column in &columns {
            let mut w = column.to_dense(c.nrows());
            factor.solve_in_place(&mut w)?;
            solved.push(w);
        }
        let g = DenseMatrix::from_fn(columns.len(), columns.len(), |i, j| {
            columns[i].inner(&solved[j])
        });
        let eigen = hermitian_eigen(&g)?;
        let largest = scaling::largest_magnitude(&eigen.values);
        let inverse_values = (eigen.values.iter())
            .map(|&l| if l > 1e-12 * largest { 1.0 / l } else { 0.0 })
            .collect();
        Ok(Self {
            factor,
            columns,
            solved,
            eigenvectors: eigen.vectors,
            inverse_values,
        })
    }

    /// `y ← x` with `S x = y − C a`, `Cᴴ x = 0`.
    fn solve_in_place(&self, y: &mut [T]) -> Result<(), EigError<T>> {
        self.factor.solve_in_place(y)?;
        // `t = Cᴴ S⁻¹ y`, then `y ← S⁻¹ y − W G⁻¹ t`.
        let projections: Vec<T> = self.columns.iter().map(|c| c.inner(y)).collect();
        let u = &self.eigenvectors;
        for (col, &inverse) in self.inverse_values.iter().enumerate() {
            if inverse == 0.0 {
                continue;
            }
            let along: T = (0..projections.len())
                .map(|i| u[(i, col)].conj() * projections[i])
                .sum();
            let along = along.scale(inverse);
            for (i, w) in self.solved.iter().enumerate() {
                vector::axpy(y, w, -(u[(i, col)] * along));
            }
        }
        Ok(())
    }
}

/// A pair of the pencil after folding, with its relative residual
/// (`WithProducts::relative_residual`).
struct Folded<T> {
    value: f64,
    vector: Vec<T>,
    residual: f64,
}

/// A basis vector `x` of a cluster with `K x` and `S x`, carried through the linear
/// combinations of the Rayleigh–Ritz step so that the residuals need no further products.
struct WithProducts<T> {
    x: Vec<T>,
    kx: Vec<T>,
    sx: Vec<T>,
}

impl<T: Scalar<Real = f64>> WithProducts<T> {
    /// `Σₐ basisₐ c(a)` (`basis` not empty), all three vectors.
    fn combination(basis: &[Self], c: impl Fn(usize) -> T) -> Self {
        let scaled = |v: &[T]| v.iter().map(|&e| e * c(0)).collect();
        let mut sum = Self {
            x: scaled(&basis[0].x),
            kx: scaled(&basis[0].kx),
            sx: scaled(&basis[0].sx),
        };
        for (a, q) in basis.iter().enumerate().skip(1) {
            sum.axpy(q, c(a));
        }
        sum
    }

    /// `self ← self + other c`, all three vectors.
    fn axpy(&mut self, other: &Self, c: T) {
        vector::axpy(&mut self.x, &other.x, c);
        vector::axpy(&mut self.kx, &other.kx, c);
        vector::axpy(&mut self.sx, &other.sx, c);
    }

    /// `‖Π (K x − μ S x)‖ / (|μ| ‖S x‖)`, `Π` the projection of `test_space`.
    fn relative_residual(mut self, mu: f64, test_space: &TestSpace<T>) -> Folded<T> {
        let s_norm = vector::norm(&self.sx);
        vector::axpy_real(&mut self.kx, &self.sx, -mu);
        test_space.project(&mut self.kx);
        Folded {
            value: mu,
            residual: vector::norm(&self.kx) / (mu.abs() * s_norm),
            vector: self.x,
        }
    }
}

/// The space a constrained pencil tests its residuals against, `{z : Cᴴ z = 0}`: the
/// residual `K x − μ S x` of one of its pairs is orthogonal to it, i.e. lies in the span of the
/// constraints, and only its component outside that span, `Π r = r − C (CᴴC)⁻¹ Cᴴ r`, measures
/// what the pair misses (without constraints, all of `r`).
struct TestSpace<T> {
    /// The constraints' span with its projection (none without constraints).
    constraints: Option<Constraints<T>>,
}

impl<T: Scalar<Real = f64>> TestSpace<T> {
    /// The test space of the constraints `c` (columns).
    fn of(c: &SparseMatrix<T>) -> Self {
        Self {
            constraints: (c.ncols() > 0).then(|| Constraints::new(c.nrows(), columns(c))),
        }
    }

    /// `r ← Π r`.
    fn project(&self, r: &mut [T]) {
        let Some(constraints) = &self.constraints else {
            return;
        };
        // The projection works on the blocked layout of the Krylov basis (a copy only where
        // it differs).
        if vector::blocked_is_ordinary::<T>() {
            constraints.project(r);
            return;
        }
        let mut blocked = vec![T::zero(); vector::blocked_len::<T>(r.len())];
        vector::to_blocked(r, &mut blocked);
        constraints.project(&mut blocked);
        vector::from_blocked(&blocked, r);
    }
}

/// The columns of `c` as sparse vectors.
fn columns<T: Scalar>(c: &SparseMatrix<T>) -> impl Iterator<Item = SparseVector<T>> + '_ {
    (0..c.ncols()).map(|j| {
        let (rows, values) = c.col(j);
        SparseVector {
            rows: rows.to_vec(),
            values: values.to_vec(),
        }
    })
}

/// The unit `e_u` whose only non-zero component is component `u` (`1, i, j, k` for
/// quaternions; `u < REAL_DIM`).
fn unit<T: Scalar<Real = f64>>(u: usize) -> T {
    let mut e = [T::zero()];
    T::as_reals_mut(&mut e)[u] = 1.0;
    e[0]
}

/// The relative distance within which two computed eigenvalues of a pencil solved to the
/// relative tolerance `tolerance` count as copies of one eigenvalue: `max(100 tol, 10⁻⁸)`.
/// The fold clusters by it (plus the rounding level of the operator), and callers that order
/// eigenvalues use it to tell a tie from a difference.
pub fn relative_cluster_width(tolerance: f64) -> f64 {
    (100.0 * tolerance).max(1e-8)
}

/// The pairs a Lanczos run converged to, as pencil vectors.
struct Converged<'a, T> {
    values: &'a [f64],
    vectors: Vec<Vec<T>>,
    /// Whether several of them may be copies of one quaternionic eigenvector (`x`, `x i`,
    /// … from an embedded backend).
    copies: bool,
}

/// A member of a cluster: a vector `x` with `S x`.
type Member<T> = (Vec<T>, Vec<T>);

/// Folds converged pairs into one quaternionic pair per eigenvalue (module documentation);
/// returns them sorted by wantedness, with their residuals. `k(x)` is `K x`.
fn fold<T: Scalar<Real = f64>>(
    k: impl Fn(&[T]) -> Vec<T> + Sync,
    s: &SparseMatrix<T>,
    test_space: &TestSpace<T>,
    converged: Converged<'_, T>,
    which: Which,
    tol: f64,
) -> Result<Vec<Folded<T>>, EigError<T>> {
    let Converged {
        values,
        vectors,
        copies,
    } = converged;
    let gap = relative_cluster_width(tol);
    let floor = ROUNDING * scaling::largest_magnitude(values);
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut vectors: Vec<Option<Vec<T>>> = vectors.into_iter().map(Some).collect();
    let mut clusters: Vec<Vec<Vec<T>>> = Vec::new();
    // The smallest and largest value of each cluster.
    let mut ranges = Vec::new();
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
        clusters.push(
            order[start..end]
                .iter()
                .map(|&i| vectors[i].take().expect("each vector is used once"))
                .collect(),
        );
        ranges.push((values[order[start]], values[order[end - 1]]));
        start = end;
    }
    // Cluster by cluster, on two threads: each costs a few sparse products per member.
    let with_images = |members: Vec<Vec<T>>| -> Vec<Member<T>> {
        (members.into_iter())
            .map(|x| {
                let mut sx = vec![T::zero(); x.len()];
                s.mul(&x, &mut sx);
                (x, sx)
            })
            .collect()
    };
    let folded = if copies {
        let clusters = threads::map_on_two_threads(clusters, with_images);
        let width = tol.sqrt().max(gap);
        let near =
            |a: (f64, f64), b: (f64, f64)| b.0 - a.1 <= width * a.1.abs().max(b.0.abs()) + floor;
        let clusters = join_copies(clusters, &ranges, near);
        threads::map_on_two_threads(clusters, |members| rayleigh_ritz(members, &k, test_space))
    } else {
        // The images of one cluster at a time: those of all `k` pairs would double the
        // eigenvectors' memory.
        threads::map_on_two_threads(clusters, |members| {
            rayleigh_ritz(with_images(members), &k, test_space)
        })
    };
    let mut pairs = Vec::new();
    for cluster in folded {
        pairs.extend(cluster?);
    }
    pairs.sort_by(|a, b| which.score(b.value).total_cmp(&which.score(a.value)));
    Ok(pairs)
}

/// The clusters (in order of value, with their value `ranges`) grouped into neighbourhoods of
/// consecutive clusters that are `near` each other; a neighbourhood whose clusters together
/// span less than apart (quaternionic dimensions by [`span_basis`]) shares copies of an
/// eigenvector between its clusters, and becomes one cluster.
fn join_copies<T: Scalar<Real = f64>>(
    clusters: Vec<Vec<Member<T>>>,
    ranges: &[(f64, f64)],
    near: impl Fn((f64, f64), (f64, f64)) -> bool,
) -> Vec<Vec<Member<T>>> {
    let mut joined = Vec::new();
    let mut neighbourhood: Vec<Vec<Member<T>>> = Vec::new();
    for (i, cluster) in clusters.into_iter().enumerate() {
        if i > 0 && !near(ranges[i - 1], ranges[i]) {
            joined.extend(settle(std::mem::take(&mut neighbourhood)));
        }
        neighbourhood.push(cluster);
    }
    joined.extend(settle(neighbourhood));
    joined
}

/// A neighbourhood of clusters ([`join_copies`]): as it is, or as one cluster if together its
/// clusters span less than apart.
fn settle<T: Scalar<Real = f64>>(neighbourhood: Vec<Vec<Member<T>>>) -> Vec<Vec<Member<T>>> {
    if neighbourhood.len() < 2 {
        return neighbourhood;
    }
    let dimension = |members: &[Member<T>]| span_basis(members.to_vec()).len();
    let apart: usize = neighbourhood.iter().map(|c| dimension(c)).sum();
    if dimension(&neighbourhood.concat()) < apart {
        vec![neighbourhood.concat()]
    } else {
        neighbourhood
    }
}

/// A member whose `S`-norm left outside the span of the others is below this lies in it.
const DEPENDENT_NORM: f64 = 0.1;

/// An `S`-orthonormal basis of the quaternionic span of `members`, with `S` times each vector:
/// pivoted Gram–Schmidt with coefficients on the right, members whose remaining `S`-norm is
/// below [`DEPENDENT_NORM`] dropped as dependent.
fn span_basis<T: Scalar<Real = f64>>(mut members: Vec<Member<T>>) -> Vec<Member<T>> {
    let mut basis = Vec::new();
    while !members.is_empty() {
        let norms: Vec<f64> = (members.iter())
            .map(|(x, sx)| vector::real_inner(x, sx).max(0.0).sqrt())
            .collect();
        let (best, &norm) = (norms.iter().enumerate())
            .max_by(|a, b| a.1.total_cmp(b.1))
            .expect("non-empty");
        if norm < DEPENDENT_NORM {
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
        basis.push((q, sq));
    }
    basis
}

/// One cluster: an `S`-orthonormal basis of its span ([`span_basis`]), then the eigenpairs of
/// `Qᴴ K Q` (`K q` is computed once per basis vector, not for the dropped members: an
/// embedded backend's cluster holds several copies of one quaternionic vector).
fn rayleigh_ritz<T: Scalar<Real = f64>>(
    members: Vec<Member<T>>,
    k: impl Fn(&[T]) -> Vec<T>,
    test_space: &TestSpace<T>,
) -> Result<Vec<Folded<T>>, EigError<T>> {
    let basis: Vec<WithProducts<T>> = (span_basis(members).into_iter())
        .map(|(x, sx)| WithProducts { kx: k(&x), x, sx })
        .collect();
    let m = basis.len();
    let h = DenseMatrix::from_fn(m, m, |a, b| vector::inner(&basis[a].x, &basis[b].kx));
    let eig = hermitian_eigen(&h)?;
    Ok((eig.values.iter().enumerate())
        .map(|(j, &mu)| {
            WithProducts::combination(&basis, |a| eig.vectors[(a, j)])
                .relative_residual(mu, test_space)
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use qscalar::Quat;

    /// `e_i q`: the `i`-th unit vector of length `n` times `q`.
    fn unit_vector(n: usize, i: usize, q: Quat<f64>) -> Vec<Quat<f64>> {
        let mut x = vec![Quat::from_real(0.0); n];
        x[i] = q;
        x
    }

    /// The values of `fold` on `K = diag(1, 1 + 10⁻⁷, 3)`, `S = I`, given converged pairs:
    /// the copies `e₀`, `e₀ i`, `e₀ j` of the eigenvector of `1` with values computed up to
    /// `3·10⁻⁷` apart (the cluster width is `10⁻⁸`), interleaved with `e₁` (a distinct
    /// eigenvalue `10⁻⁷` above), and `e₂`.
    fn folded_values(copies: bool) -> Vec<f64> {
        let n = 3;
        let diagonal = [1.0, 1.0 + 1e-7, 3.0].map(Quat::from_real);
        let k = SparseMatrix::from_diagonal(&diagonal);
        let s = SparseMatrix::identity(n);
        let i = |u: usize| unit::<Quat<f64>>(u);
        let values = [1.0, 1.0 + 1e-7, 1.0 + 2e-7, 1.0 + 3e-7, 3.0];
        let vectors = vec![
            unit_vector(n, 0, i(0)),
            unit_vector(n, 1, i(0)),
            unit_vector(n, 0, i(1)),
            unit_vector(n, 0, i(2)),
            unit_vector(n, 2, i(0)),
        ];
        let k_mul = |x: &[Quat<f64>]| {
            let mut y = vec![Quat::from_real(0.0); x.len()];
            k.mul(x, &mut y);
            y
        };
        let converged = Converged {
            values: &values,
            vectors,
            copies,
        };
        let test_space = TestSpace::of(&SparseMatrix::zeros(n, 0));
        let pairs = fold(
            k_mul,
            &s,
            &test_space,
            converged,
            Which::SmallestAlgebraic,
            1e-10,
        )
        .expect("a dense solve of order 3");
        pairs.iter().map(|p| p.value).collect()
    }

    #[test]
    fn copies_computed_apart_fold_into_one_eigenvalue() {
        let values = folded_values(true);
        assert_eq!(values.len(), 3, "{values:?}");
        for (value, exact) in values.iter().zip([1.0, 1.0 + 1e-7, 3.0]) {
            assert!((value - exact).abs() <= 1e-15, "{values:?}");
        }
        // Without the join each value cluster counted as an eigenvalue of its own.
        assert_eq!(folded_values(false).len(), 5);
    }
}
