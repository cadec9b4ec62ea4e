//! One path per [`Form`]: reduce to the complement of the exact kernel, solve with `qeig`, map
//! the pairs back to the operator's `λ` and to full vectors.

use qeig::{
    ComplexAdjoint, EigError, Eigen, LanczosOptions, Native, Pencil, RealBlock, Statistics, Which,
};
use qscalar::Scalar;
use qsparse::{CholeskyError, SparseMatrix, SparseVector, threads, vector};

use super::kernel::{Coupling, ExactKernel, KernelMode, Reduction, Restoration, mass_norm_squared};
use super::pencil::{Form, Matrices};
use super::{SolverBackend, SpectrumError, SpectrumOptions};

/// Computed eigenpairs of the operator over the scalar `T`, not yet sorted or normalised.
#[derive(Debug, Clone)]
pub(super) struct Pairs<T> {
    /// `λ`.
    pub values: Vec<f64>,
    /// Full-length eigenvectors.
    pub vectors: Vec<Vec<T>>,
    /// Statistics summed over every solve.
    pub statistics: Statistics,
    /// Whether the eigensolver converged all wanted pairs.
    pub complete: bool,
}

/// The progress callback, reborrowed for each solve.
pub(super) type ProgressCallback<'a, 'b> = &'a mut Option<qeig::ProgressCallback<'b>>;

/// What can stop a solve.
pub(super) enum SolveError {
    /// `S` is not numerically positive definite; the vertex of the failing pivot (`None` for
    /// the embedded backends, which do not say where).
    Singular(Option<usize>),
    /// Anything else.
    Other(SpectrumError),
}

impl From<SpectrumError> for SolveError {
    fn from(e: SpectrumError) -> Self {
        Self::Other(e)
    }
}

impl<T> Pairs<T> {
    /// No pair: what is known when nothing outside the kernel is wanted.
    pub fn none() -> Self {
        Self {
            values: Vec::new(),
            vectors: Vec::new(),
            statistics: Statistics::default(),
            complete: true,
        }
    }
}

/// The problem one form hands to `qeig`: `K y = μ S y` on the reduced space with
/// constraints `cᴴ y = 0`, over the scalar `T` of the operator's pencil.
pub(super) struct Reduced<T> {
    reduction: Reduction,
    k: SparseMatrix<T>,
    s: SparseMatrix<T>,
    /// One column per constraint (local to its piece: sparse).
    constraints: SparseMatrix<T>,
    low_rank: Vec<(SparseVector<T>, f64)>,
}

impl<T: Scalar> Reduced<T> {
    /// Dimension left for eigenpairs.
    pub fn available(&self) -> usize {
        self.reduction
            .kept
            .len()
            .saturating_sub(self.constraints.ncols())
    }
}

/// The eigenproblem one form solves: the reduced problem [`reduce`] built, and what maps its
/// pairs back to the operator's.
pub(super) struct Problem<'a, T> {
    /// The reduced problem, built by [`reduce`] with the same form, matrices, kernel and
    /// masses.
    pub reduced: &'a Reduced<T>,
    pub form: Form,
    pub matrices: &'a Matrices<T>,
    pub kernel: &'a ExactKernel<T>,
    pub masses: &'a [f64],
}

/// The pairs of the operator a solve found, with those of the reduced pencil they come from
/// when they can be refined ([`Problem::refine`]; the literal form, which solves several
/// times, keeps none).
pub(super) struct Solved<T> {
    pub pairs: Pairs<T>,
    pub reduced: Option<Eigen<T>>,
}

impl<T: Scalar<Real = f64>> Problem<'_, T> {
    /// The `count` nonzero eigenpairs of smallest `|λ|`.
    pub fn solve(
        &self,
        count: usize,
        options: &SpectrumOptions,
        progress: ProgressCallback,
    ) -> Result<Solved<T>, SolveError> {
        let which = match self.form {
            Form::Shifted { .. } => Which::LargestAlgebraic,
            Form::Pinned => Which::LargestMagnitude,
            Form::Literal { sigma } => {
                let pairs = literal(self.reduced, sigma, count, options, progress)?;
                return Ok(Solved {
                    pairs: self.completed(pairs),
                    reduced: None,
                });
            }
        };
        let (eigen, complete) = run(self.reduced, count, which, options, progress)?;
        Ok(Solved {
            pairs: self.completed(self.mapped(&eigen, complete)),
            reduced: Some(eigen),
        })
    }

    /// The pairs of `eigen`, pairs of the reduced pencil that [`Problem::solve`] found, after
    /// one step of [`Pencil::refine`] (the vectors of the Lanczos can be less accurate than
    /// rounding allows where the reduced `S` is ill-conditioned and eigenvalues cluster).
    pub fn refine(&self, eigen: &Eigen<T>, complete: bool) -> Result<Solved<T>, SolveError> {
        let refined = (pencil(self.reduced).and_then(|p| p.refine(eigen)))
            .map_err(|e| solve_error(self.reduced, e))?;
        Ok(Solved {
            pairs: self.completed(self.mapped(&refined, complete)),
            reduced: Some(refined),
        })
    }

    /// The pairs of the operator from those of the reduced pencil (`complete`: all wanted
    /// converged), before [`Problem::completed`].
    fn mapped(&self, eigen: &Eigen<T>, complete: bool) -> Pairs<T> {
        map_pairs(eigen, complete, self.reduced, self.masses.len(), self.form)
    }

    /// The kernel's components of each pair as its form leaves them to be set, and `λ` as the
    /// Rayleigh quotient in the pinned form.
    fn completed(&self, mut pairs: Pairs<T>) -> Pairs<T> {
        let (form, kernel, matrices, masses) = (self.form, self.kernel, self.matrices, self.masses);
        // Pair by pair, on two threads: each pair costs a few sparse products.
        let each = pairs.vectors.iter_mut().zip(&mut pairs.values).collect();
        threads::map_on_two_threads(each, |(x, lambda): (&mut Vec<T>, &mut f64)| {
            if form == Form::Pinned && !kernel.restoration.is_empty() {
                restore_modes(matrices, &kernel.restoration, *lambda, x);
            }
            for mode in &kernel.modes {
                match (form, mode.coupling) {
                    (Form::Pinned, Coupling::Orthogonal) => {}
                    (Form::Pinned, Coupling::Oblique) => project_oblique(mode, x),
                    _ => remove_mass_component(masses, &mode.vector, x),
                }
            }
            if form == Form::Pinned {
                // The Rayleigh quotient is stationary at eigenvectors of the Hermitian pencil:
                // its error is second order in the vector's, where `1/μ` is first order.
                let (px, qx) = products(matrices, x);
                *lambda = vector::real_inner(x, &px) / vector::real_inner(x, &qx);
            }
        });
        pairs
    }
}

/// `(P x, Q x)`, computed as `(Pᴴ x, Qᴴ x)`: both are Hermitian, and the adjoint product is
/// the faster one.
pub(super) fn products<T: Scalar<Real = f64>>(m: &Matrices<T>, x: &[T]) -> (Vec<T>, Vec<T>) {
    let (mut px, mut qx) = (vec![T::zero(); x.len()], vec![T::zero(); x.len()]);
    m.stiffness
        .adjoint_mul_vec(x, &mut px)
        .expect("square operator of the vector's size");
    m.coupling
        .adjoint_mul_vec(x, &mut qx)
        .expect("square operator of the vector's size");
    (px, qx)
}

/// The reduced problem of each form (docs/MATH.md, "The exact kernel"):
/// * shifted: `Q y = μ (P + εQ) y` without the flat vertices, `(Q k)* y = 0` per mode `k`;
/// * pinned: `Q' y = μ P y` without the flat vertices and the pin of every mode (one vertex of
///   each piece for its constant, another for its linear function: the modes are then outside
///   the space, so `P` is definite there), with per mode `g = Q k`: nothing if it is free, the
///   constraint `g* y = 0` if it is orthogonal, and if it is oblique the compression
///   `Q' = Q − g g*/(k* g)` of `Q` by the projection `x = y − k (g* y)/(k* g)` onto
///   `{g* x = 0}` (exact: `P x = P y`);
/// * literal: `M y = μ (P + σM) y`, constrained like the shifted form (`(M 𝟙_S)* y = 0` for
///   each constant `P` annihilates: `G 𝟙 = 0` on a closed piece).
pub(super) fn reduce<T: Scalar<Real = f64>>(
    form: Form,
    m: &Matrices<T>,
    kernel: &ExactKernel<T>,
    masses: &[f64],
) -> Result<Reduced<T>, SpectrumError> {
    let flat = kernel.flat_vertices.iter().copied();
    let pins = kernel.modes.iter().map(|mode| mode.pin);
    let reduction = match form {
        Form::Pinned => Reduction::without(masses, flat.chain(pins)),
        Form::Shifted { .. } | Form::Literal { .. } => Reduction::without(masses, flat),
    };
    // The constraints' columns, in CSC arrays.
    let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
    let mut low_rank = Vec::new();
    for mode in &kernel.modes {
        let g = &mode.image;
        match (form, mode.coupling) {
            (Form::Pinned, Coupling::Free) => {}
            (Form::Shifted { .. } | Form::Literal { .. }, _)
            | (Form::Pinned, Coupling::Orthogonal) => {
                let c = reduction.functional(g);
                row_idx.extend(c.rows);
                values.extend(c.values);
                col_ptr.push(row_idx.len());
            }
            (Form::Pinned, Coupling::Oblique) => {
                let along = mode.vector.inner_sparse(g).re();
                low_rank.push((reduction.functional(g), 1.0 / along));
            }
        }
    }
    let size = reduction.kept.len();
    let constraints = SparseMatrix::try_from_csc(size, col_ptr.len() - 1, col_ptr, row_idx, values)
        .map_err(|e| SpectrumError::Operator(e.into()))?;
    let scaled = |x| reduction.matrix(x).ok_or(SpectrumError::ScaleOutOfRange);
    let (p, q) = (scaled(&m.stiffness)?, scaled(&m.coupling)?);
    let s = match form {
        Form::Shifted { epsilon: shift } | Form::Literal { sigma: shift } => {
            SparseMatrix::linear_combination(T::one(), &p, T::from_real(shift), &q)
                .map_err(|e| SpectrumError::Operator(e.into()))?
        }
        Form::Pinned => p,
    };
    Ok(Reduced {
        reduction,
        k: q,
        s,
        constraints,
        low_rank,
    })
}

/// `x ← x − k (g* x)/(k* g)`, `g = Q k`: the eigenvector of an oblique mode from the pinned
/// one.
fn project_oblique<T: Scalar<Real = f64>>(mode: &KernelMode<T>, x: &mut [T]) {
    let along = mode.vector.inner_sparse(&mode.image).re();
    let c = mode.image.inner(x).scale(1.0 / along);
    mode.vector.add_to(x, -c);
}

/// The eigenvalues `μ` of the reduced pencil mapped to the operator's `λ` as `form` says, with
/// full vectors.
fn map_pairs<T: Scalar<Real = f64>>(
    eigen: &Eigen<T>,
    complete: bool,
    reduced: &Reduced<T>,
    n: usize,
    form: Form,
) -> Pairs<T> {
    Pairs {
        values: (eigen.values.iter())
            .map(|&mu| form.eigenvalue(mu))
            .collect(),
        vectors: (eigen.vectors.iter())
            .map(|y| reduced.reduction.expand(y, n))
            .collect(),
        statistics: eigen.statistics,
        complete,
    }
}

/// How many pairs from the bottom of its spectrum the literal family may compute, for
/// `count` wanted ones, before [`SpectrumError::IndefiniteLiteralFamily`]: its cost grows
/// with the square of the pairs held, and a mesh with more negative eigenvalues than this
/// (curved regions where `τG` outweighs `(1−τ)L`) usually has hundreds of them.
fn literal_limit(count: usize) -> usize {
    (8 * count).max(64)
}

/// The literal family: eigenvalues from the bottom until the `count` of smallest `|λ|` are
/// certain (every `λ` below the highest one computed is known), doubling the pairs computed
/// up to [`literal_limit`].
fn literal<T: Scalar<Real = f64>>(
    reduced: &Reduced<T>,
    sigma: f64,
    count: usize,
    options: &SpectrumOptions,
    progress: ProgressCallback,
) -> Result<Pairs<T>, SolveError> {
    let n = reduced.reduction.kept.len();
    let mut statistics = Statistics::default();
    let mut computed = (2 * count).min(n);
    loop {
        let eigen = run(
            reduced,
            computed,
            Which::LargestAlgebraic,
            options,
            progress,
        )?;
        statistics += &eigen.0.statistics;
        let (eigen, complete) = eigen;
        let mut pairs = map_pairs(&eigen, complete, reduced, n, Form::Literal { sigma });
        let highest = pairs
            .values
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        let mut magnitudes: Vec<f64> = pairs.values.iter().map(|v| v.abs()).collect();
        magnitudes.sort_by(f64::total_cmp);
        let certain = magnitudes.len() >= count && magnitudes[count - 1] <= highest;
        if certain || computed == n || !pairs.complete {
            pairs.statistics = statistics;
            return Ok(pairs);
        }
        if computed >= literal_limit(count) {
            return Err(SpectrumError::IndefiniteLiteralFamily {
                wanted: count,
                negative: pairs.values.iter().filter(|&&v| v < 0.0).count(),
                lowest: pairs.values.iter().copied().fold(f64::INFINITY, f64::min),
            }
            .into());
        }
        computed = (2 * computed).min(n).min(literal_limit(count));
    }
}

/// Solves the reduced pencil for `count` pairs with the chosen backend; the flag says whether
/// all of them converged. [`super::compute`] hands a real operator to the embedded backends
/// over the quaternions (`P⊗I`), as before there was a real path, so here `T = f64` only
/// meets [`Native`] in practice (a real-block or complex-adjoint backend over `f64` would be
/// faer's Cholesky on the same `n × n` matrix).
fn run<T: Scalar<Real = f64>>(
    reduced: &Reduced<T>,
    count: usize,
    which: Which,
    options: &SpectrumOptions,
    progress: ProgressCallback,
) -> Result<(Eigen<T>, bool), SolveError> {
    let pencil = pencil(reduced).map_err(|e| solve_error(reduced, e))?;
    let mut lanczos = LanczosOptions::new(count, which);
    lanczos.tolerance = options.tolerance;
    lanczos.seed = options.seed;
    lanczos.max_restarts = options.max_restarts;
    let progress: Option<qeig::ProgressCallback> = match progress {
        Some(callback) => Some(&mut **callback),
        None => None,
    };
    let result = match options.backend {
        SolverBackend::Native => pencil.solve_with_progress(&Native, &lanczos, progress),
        SolverBackend::RealBlock => pencil.solve_with_progress(&RealBlock, &lanczos, progress),
        SolverBackend::ComplexAdjoint => {
            pencil.solve_with_progress(&ComplexAdjoint, &lanczos, progress)
        }
    };
    match result {
        Ok(e) => Ok((e, true)),
        Err(EigError::NotConverged { partial, .. }) => Ok((*partial, false)),
        Err(e) => Err(solve_error(reduced, e)),
    }
}

/// The reduced problem as `qeig` takes it.
fn pencil<T: Scalar<Real = f64>>(reduced: &Reduced<T>) -> Result<Pencil<'_, T>, EigError<T>> {
    Pencil::new(&reduced.k, &reduced.s)
        .and_then(|p| p.with_constraints(reduced.constraints.clone()))
        .and_then(|p| p.with_low_rank_update(reduced.low_rank.clone()))
}

/// An error of `qeig` on the reduced problem: a factorisation that fails is a singular
/// operator, at the vertex of the failing pivot when known.
fn solve_error<T: Scalar<Real = f64>>(reduced: &Reduced<T>, error: EigError<T>) -> SolveError {
    match error {
        EigError::Factorization(CholeskyError::NotPositiveDefinite { index, .. }) => {
            SolveError::Singular(Some(reduced.reduction.kept[index]))
        }
        EigError::EmbeddedFactorization(_) => SolveError::Singular(None),
        e => SpectrumError::Eigen(std::sync::Arc::new(e)).into(),
    }
}

/// `x ← x + Σ_i k_i c_i`, `c = (GᴴG)⁻¹ Gᴴ r / λ` by group of modes with images `G`,
/// `r = P x − λ Q x`: the components along the orthogonally coupled modes that make `x`
/// satisfy `P x = λ Q x` when it was solved with them pinned to zero (least squares, exact
/// when the rest is exact; the images of different groups are orthogonal, so one residual
/// serves every group, `P k_i = 0` leaving it unchanged but for `λ G c`).
fn restore_modes<T: Scalar<Real = f64>>(
    m: &Matrices<T>,
    modes: &[Restoration<T>],
    lambda: f64,
    x: &mut [T],
) {
    let residual = pencil_residual_vector(m, lambda, x);
    for group in modes {
        match group {
            Restoration::Fit { vectors, images } => {
                let coefficients = images.coefficients(&residual);
                for (k, c) in vectors.iter().zip(coefficients) {
                    k.add_to(x, c.scale(1.0 / lambda));
                }
            }
            Restoration::Orthogonal { vector, image } => {
                let c = (image.inner(&residual)).scale(1.0 / (lambda * image.norm_squared()));
                vector.add_to(x, c);
            }
        }
    }
}

/// `P x − λ Q x`.
fn pencil_residual_vector<T: Scalar<Real = f64>>(m: &Matrices<T>, lambda: f64, x: &[T]) -> Vec<T> {
    let (mut px, qx) = products(m, x);
    vector::axpy_real(&mut px, &qx, -lambda);
    px
}

/// `x ← x − k ⟨k, x⟩_M / ⟨k, k⟩_M`: the mass-orthogonal representative modulo a mode (the
/// modes of one piece are mass-orthogonal to each other, so one after the other is exact).
fn remove_mass_component<T: Scalar<Real = f64>>(masses: &[f64], k: &SparseVector<T>, x: &mut [T]) {
    let along: T = (k.rows.iter().zip(&k.values))
        .map(|(&p, v)| (v.conj() * x[p]).scale(masses[p]))
        .sum();
    k.add_to(x, -along.scale(1.0 / mass_norm_squared(masses, k)));
}
