//! Thick-restart (Krylov–Schur) Lanczos with full reorthogonalisation, locking, deflation and
//! rounds that recover every copy of a multiple eigenvalue.
//!
//! Generic over the field `V` of the iteration space (`f64`, `Complex<f64>`, `Quat<f64>`),
//! one implementation. For a Hermitian operator `A` the Lanczos coefficients
//! `αⱼ = ⟨qⱼ, A qⱼ⟩` and `βⱼ = ‖rⱼ‖` are real even over the quaternions, so the projected
//! matrix (tridiagonal, with the arrowhead of a thick restart) is real symmetric and its
//! eigenpairs come from faer's real self-adjoint solver; Ritz vectors are `Q y` with real `y`.
//!
//! # Algorithm
//!
//! * **Expansion.** `w = A qⱼ`; the three-term recurrence `w −= qⱼ αⱼ + qⱼ₋₁ βⱼ₋₁` is followed
//!   by a full Gram–Schmidt pass (modified, column by column, each basis vector read from
//!   memory once) against the deflation vectors, the locked vectors and the whole active
//!   basis, repeated once when it removed more than `1 − 1/√2` of the norm (coefficients on
//!   the right). If `βⱼ` vanishes (an invariant subspace) a fresh random vector orthogonal to
//!   everything is appended with coupling `0`, which keeps the projected matrix exact.
//! * **Thick restart.** When the basis is full (or earlier, every few steps, when the round
//!   may be finished) the projected matrix is diagonalised. Ritz pairs whose estimated residual
//!   `|βₘ yₘ| ≤ tol |θ|` and whose true residual (measured by the operator, for a pencil
//!   `‖K x − θ S x‖ / (|θ| ‖S x‖)`) is below `tol` are **locked**: moved out of the active
//!   basis, never changed again, and orthogonalised against from then on. The best unconverged
//!   Ritz vectors are kept with the residual vector as continuation (`A U = U Θ + q sᵀ`).
//! * **Attainable accuracy.** The estimate measures the residual of the operator the iteration
//!   sees: the computed `A`, restricted to the complement of the deflation and locked vectors.
//!   The true residual differs from it by the rounding errors of applying `A` (about
//!   `eps ‖A‖`, which for an ill-conditioned `S` is far above `tol |θ|` for the small `θ`) and
//!   by the coupling `Σ x_L ⟨r_L, y⟩` to the locked pairs, whose residuals `r_L` are only below
//!   `tol`. Neither shrinks with further steps, so a pair whose estimate is at rounding level,
//!   `|βₘ yₘ| ≤ 64 eps ‖A‖` (`‖A‖` estimated by the largest `|θ|` seen), is locked when its
//!   true residual is below `√tol` instead of `tol`: it is as accurate as the arithmetic allows,
//!   and its true residual, possibly above `tol`, is what the result reports. A tolerance far
//!   below what the arithmetic can reach (true residual above `√tol` at rounding level) still
//!   ends in [`crate::EigError::NotConverged`] rather than in a false success.
//! * **Rounds (multiplicities).** A single Krylov sequence holds one direction per eigenspace,
//!   so a second copy of an exactly multiple eigenvalue never appears in it. A round therefore
//!   ends once the wanted number of pairs is locked and the extreme remaining Ritz values at the
//!   wanted end(s) are known (converged, or with `θ ± est` outside the window) not to belong
//!   to the window; then a **new round starts from a fresh seeded random vector deflated
//!   against everything locked**. It converges first to whatever wanted eigenvalue is still
//!   missing — a further copy of a multiple eigenvalue, or a value the previous round skipped.
//!   The run stops after a round that locked nothing better than the current `k`-th pair. An
//!   eigenvalue of multiplicity `m` is complete after at most `m + 1` rounds; ties at the
//!   window's edge are broken arbitrarily.
//! * **Deflation.** A user subspace (orthonormalised) sits in front of the basis and every
//!   vector is orthogonalised against it, so the iteration never leaves its complement.
//!
//! Tolerance: relative, `tol` on the estimate and on the true residual of every locked pair,
//! except pairs at rounding level (`√tol` on the true residual, above).

use std::time::{Duration, Instant};

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, Par};
use qscalar::Scalar;
use qsparse::vector;

use qscalar::random::SplitMix64;

use crate::basis::{Basis, GramSchmidt, append_orthonormal};
use crate::dense::real_symmetric_eigen;
use crate::{EigError, Eigen, Progress, ProgressCallback, Statistics};

/// Which end(s) of the spectrum are wanted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Which {
    /// The `k` eigenvalues of largest `|μ|`, from both ends at once (the shift-and-invert use:
    /// `μ = 1/(λ − σ)` large means `λ` close to `σ`).
    #[default]
    LargestMagnitude,
    /// The `k` largest eigenvalues.
    LargestAlgebraic,
    /// The `k` smallest eigenvalues.
    SmallestAlgebraic,
}

impl Which {
    /// The ordering key: larger is more wanted.
    pub(crate) fn score(self, theta: f64) -> f64 {
        match self {
            Which::LargestMagnitude => theta.abs(),
            Which::LargestAlgebraic => theta,
            Which::SmallestAlgebraic => -theta,
        }
    }
}

/// Options of the Lanczos iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LanczosOptions {
    /// Number of eigenpairs wanted (quaternionic pairs for the pencil solvers).
    pub k: usize,
    /// Which eigenvalues.
    pub which: Which,
    /// Relative residual tolerance: a pair `(μ, x)` is accepted when
    /// `‖K x − μ S x‖ / (|μ| ‖S x‖) ≤ tolerance`, or `≤ √tolerance` when its Lanczos residual
    /// estimate is at the rounding level of the operator (see [the module documentation](self));
    /// the returned residuals are the true ones.
    pub tolerance: f64,
    /// Largest active basis dimension (locked and deflation vectors come on top).
    /// `0` chooses `max(2k, k + 32)` (for the iteration-space `k`), capped by the dimension.
    pub max_dim: usize,
    /// Largest number of thick restarts before giving up.
    pub max_restarts: usize,
    /// Largest number of operator applications before giving up.
    pub max_operator_applications: usize,
    /// Seed of the random start vectors (runs are deterministic for a given seed).
    pub seed: u64,
}

impl LanczosOptions {
    /// `k` pairs of the given end with tolerance `1e−10`, automatic dimension, 1000 restarts,
    /// no limit on operator applications, seed 0.
    pub fn new(k: usize, which: Which) -> Self {
        Self {
            k,
            which,
            tolerance: 1e-10,
            max_dim: 0,
            max_restarts: 1000,
            max_operator_applications: usize::MAX,
            seed: 0,
        }
    }
}

/// A Hermitian linear operator on `Vⁿ` (`⟨x, A y⟩ = ⟨A x, y⟩`), the input of the Lanczos core.
pub trait HermitianOperator<V> {
    /// Dimension `n`.
    fn dim(&self) -> usize;
    /// `y = A x` (`x` and `y` have length `n`).
    fn apply(&mut self, x: &[V], y: &mut [V]);
    /// The relative residual by which the pair `(θ, y)` (`y` a unit vector of the iteration
    /// space) is accepted; for a pencil, that of the mapped-back pair.
    fn relative_residual(&mut self, y: &[V], theta: f64) -> f64;
    /// Triangular solves so far and the time they took (zero for operators without any).
    fn solve_statistics(&self) -> (usize, Duration) {
        (0, Duration::ZERO)
    }
}

/// What the core hands back: locked pairs sorted by wantedness, in the iteration space.
#[derive(Debug)]
pub(crate) struct Outcome<V> {
    pub values: Vec<f64>,
    pub vectors: Vec<Vec<V>>,
    pub converged: bool,
    pub statistics: Statistics,
}

/// Steps between early convergence checks.
const CHECK_INTERVAL: usize = 10;
/// Multiply-adds from which the Ritz vectors `Q Y` of a restart are computed on all cores.
const PARALLEL_RITZ_FLOPS: usize = 1 << 24;

/// Rounding level of an estimated residual relative to `‖A‖`: a Ritz pair with
/// `|βₘ yₘ| ≤ ROUNDING ‖A‖` is an eigenpair of the computed operator up to the rounding errors
/// of applying `A` (and of the coupling to the locked pairs, which the iteration cannot see),
/// so no further step can improve its true residual.
pub(crate) const ROUNDING: f64 = 64.0 * f64::EPSILON;

/// `a` is better than `b` by more than the rounding slack of a converged eigenvalue.
fn better(which: Which, a: f64, b: f64, tol: f64) -> bool {
    which.score(a) > which.score(b) + 100.0 * tol.max(1e-14) * b.abs()
}

/// The `k`-th best of `values` (by `which`), if there are `k`.
fn kth_best(which: Which, values: &[f64], k: usize) -> Option<f64> {
    if values.len() < k || k == 0 {
        return None;
    }
    let mut s: Vec<f64> = values.to_vec();
    s.sort_by(|a, b| which.score(*b).total_cmp(&which.score(*a)));
    Some(s[k - 1])
}

struct RitzPairs {
    theta: Vec<f64>,
    y: Mat<f64>,
    estimate: Vec<f64>,
    /// Indices by decreasing wantedness.
    order: Vec<usize>,
}

fn ritz(h: &Mat<f64>, size: usize, beta: f64, which: Which) -> Result<RitzPairs, String> {
    let (theta, y) = real_symmetric_eigen(h.as_ref().submatrix(0, 0, size, size))?;
    let estimate = (0..size).map(|i| (beta * y[(size - 1, i)]).abs()).collect();
    let mut order: Vec<usize> = (0..size).collect();
    order.sort_by(|&a, &b| which.score(theta[b]).total_cmp(&which.score(theta[a])));
    Ok(RitzPairs {
        theta,
        y,
        estimate,
        order,
    })
}

/// Whether the round can end: `k` pairs locked, and at every wanted end the extreme Ritz value
/// not chosen for locking is known not to enter the window.
fn round_finished(
    which: Which,
    tol: f64,
    locked: &[f64],
    k: usize,
    pairs: &RitzPairs,
    remaining: &[usize],
) -> bool {
    let Some(kth) = kth_best(which, locked, k) else {
        return false;
    };
    let clear = |i: usize| {
        let (t, e) = (pairs.theta[i], pairs.estimate[i]);
        let converged = e <= tol * t.abs() && !better(which, t, kth, tol);
        let bound = match which {
            Which::LargestMagnitude => t.abs() + e,
            Which::LargestAlgebraic => t + e,
            Which::SmallestAlgebraic => -(t - e),
        };
        converged || bound < which.score(kth)
    };
    let by_value = |a: &&usize, b: &&usize| pairs.theta[**a].total_cmp(&pairs.theta[**b]);
    let (top, bottom) = (
        remaining.iter().max_by(by_value),
        remaining.iter().min_by(by_value),
    );
    match which {
        Which::LargestAlgebraic => top.is_none_or(|&i| clear(i)),
        Which::SmallestAlgebraic => bottom.is_none_or(|&i| clear(i)),
        Which::LargestMagnitude => {
            top.is_none_or(|&i| clear(i)) && bottom.is_none_or(|&i| clear(i))
        }
    }
}

/// Runs the iteration for `k` pairs of `op` in the orthogonal complement of the orthonormal
/// columns already in `basis`.
pub(crate) fn run<V, O>(
    op: &mut O,
    options: &LanczosOptions,
    k: usize,
    mut basis: Basis<V>,
    mut progress: Option<ProgressCallback>,
) -> Result<Outcome<V>, String>
where
    V: Scalar<Real = f64>,
    O: HermitianOperator<V> + ?Sized,
{
    let start_time = Instant::now();
    let n = op.dim();
    let nd = basis.cols();
    let (which, tol) = (options.which, options.tolerance);
    let m_max = if options.max_dim == 0 {
        (2 * k).max(k + 32)
    } else {
        options.max_dim
    }
    .min(n - nd)
    .max(1);
    let mut rng = SplitMix64::new(options.seed);
    let mut gs = GramSchmidt::new();
    let mut stats = Statistics::default();
    let mut orth_time = Duration::ZERO;
    let mut locked: Vec<f64> = Vec::new();
    let mut h = Mat::<f64>::zeros(m_max + 1, m_max + 1);
    let mut w = vec![V::zero(); n];
    let mut coef: Vec<V> = Vec::new();
    let mut ritz_block: Vec<V> = Vec::new();
    let mut limit_hit = false;
    // Largest |Ritz value| so far: a lower bound of ‖A‖ for the rounding level of estimates.
    let mut norm_estimate = 0.0f64;

    'rounds: loop {
        let mut base = nd + locked.len();
        if base >= n {
            break;
        }
        let mut m = m_max.min(n - base);
        stats.rounds += 1;
        basis.truncate(base);
        rng.fill_symmetric(&mut w);
        let t = Instant::now();
        let started = append_orthonormal(&mut basis, &mut gs, &mut w, &mut coef);
        orth_time += t.elapsed();
        if !started {
            break;
        }
        let mut new_in_round = 0usize;
        let mut p = 0usize; // kept Ritz vectors in front of the active basis
        let mut j = 0usize; // active vector being expanded
        h.fill(0.0);
        loop {
            // ---- expansion ----
            let mut invariant = false;
            let mut check_now = false;
            while j < m {
                if stats.operator_applications >= options.max_operator_applications {
                    limit_hit = true;
                    break 'rounds;
                }
                op.apply(basis.col(base + j), &mut w);
                stats.operator_applications += 1;
                stats.iterations += 1;
                let t = Instant::now();
                let raw = vector::norm(&w);
                let mut alpha = 0.0;
                if j > p {
                    let qj = basis.col(base + j);
                    alpha = vector::inner(qj, &w).re();
                    vector::axpy(&mut w, qj, V::from_real(-alpha));
                    vector::axpy(
                        &mut w,
                        basis.col(base + j - 1),
                        V::from_real(-h[(j, j - 1)]),
                    );
                }
                gs.orthogonalize(&basis, base + j + 1, &mut w, &mut coef);
                h[(j, j)] = alpha + coef[base + j].re();
                let beta = vector::norm(&w);
                let appended = if beta > 1e-12 * raw {
                    vector::scale(&mut w, 1.0 / beta);
                    basis.push(&w);
                    h[(j + 1, j)] = beta;
                    h[(j, j + 1)] = beta;
                    true
                } else {
                    // Invariant subspace: continue from a fresh direction, decoupled.
                    rng.fill_symmetric(&mut w);
                    append_orthonormal(&mut basis, &mut gs, &mut w, &mut coef)
                };
                orth_time += t.elapsed();
                j += 1;
                if !appended {
                    invariant = true;
                    break;
                }
                if (j - p).is_multiple_of(CHECK_INTERVAL) && j < m && locked.len() + j >= k {
                    check_now = true;
                    break;
                }
            }
            let size = j;
            let beta_last = if invariant { 0.0 } else { h[(size, size - 1)] };
            let pairs = ritz(&h, size, beta_last, which)?;
            norm_estimate = pairs
                .theta
                .iter()
                .fold(norm_estimate, |a, t| a.max(t.abs()));

            // ---- locking candidates (by estimate), in order of wantedness ----
            let mut candidate_values = locked.clone();
            let mut candidates = Vec::new();
            for &i in &pairs.order {
                let theta = pairs.theta[i];
                if pairs.estimate[i] > tol * theta.abs() {
                    continue;
                }
                let wanted = match kth_best(which, &candidate_values, k) {
                    None => true,
                    Some(kth) => !better(which, kth, theta, tol),
                };
                if wanted {
                    candidates.push(i);
                    candidate_values.push(theta);
                }
            }
            if check_now {
                let remaining: Vec<usize> = pairs
                    .order
                    .iter()
                    .copied()
                    .filter(|i| !candidates.contains(i))
                    .collect();
                if !round_finished(which, tol, &candidate_values, k, &pairs, &remaining) {
                    continue; // keep expanding
                }
            }

            // ---- restart: Ritz vectors of the candidates and of the best others ----
            stats.restarts += 1;
            let needed = k.saturating_sub(locked.len()).max(1);
            let keep_max = if invariant {
                0
            } else {
                (needed + (m - needed.min(m)) / 2).min(m - 1)
            };
            let mut selection = candidates.clone();
            let keep_max = keep_max.min(size.saturating_sub(candidates.len()));
            selection.extend(
                pairs
                    .order
                    .iter()
                    .copied()
                    .filter(|i| !candidates.contains(i))
                    .take(keep_max),
            );
            let t = Instant::now();
            ritz_block.resize(n * (selection.len() + 1), V::zero());
            {
                let ysel =
                    Mat::<f64>::from_fn(size, selection.len(), |r, c| pairs.y[(r, selection[c])]);
                let out = MatMut::from_column_major_slice_mut(
                    V::as_reals_mut(&mut ritz_block[..n * selection.len()]),
                    V::REAL_DIM * n,
                    selection.len(),
                );
                // The one compute-bound step: on all cores once it is large (a few per run).
                let par = if V::REAL_DIM * n * size * selection.len() >= PARALLEL_RITZ_FLOPS
                    && qsparse::threads::second_thread_allowed()
                {
                    Par::rayon(0)
                } else {
                    Par::Seq
                };
                matmul(
                    out,
                    Accum::Replace,
                    basis.reals(base, size),
                    ysel.as_ref(),
                    1.0,
                    par,
                );
            }
            if !invariant {
                let cont = selection.len();
                ritz_block[cont * n..(cont + 1) * n].copy_from_slice(basis.col(base + size));
            }
            orth_time += t.elapsed();

            let kth_before = kth_best(which, &locked, k);
            let mut newly_locked = Vec::new();
            for (c, &i) in selection.iter().enumerate().take(candidates.len()) {
                let theta = pairs.theta[i];
                let y = &ritz_block[c * n..(c + 1) * n];
                let at_rounding_level = pairs.estimate[i] <= ROUNDING * norm_estimate;
                let residual = op.relative_residual(y, theta);
                if residual <= tol || at_rounding_level {
                    newly_locked.push(c);
                    locked.push(theta);
                    let is_new = kth_before.is_none_or(|kth| better(which, theta, kth, tol));
                    new_in_round += usize::from(is_new);
                }
            }
            stats.locked = locked.len();
            let new_base = nd + locked.len();
            let m_new = m_max.min(n - new_base);
            // New layout: [deflation | locked (old, new) | kept | continuation].
            let kept: Vec<usize> = (0..selection.len())
                .filter(|c| !newly_locked.contains(c))
                .take(keep_max.min(m_new.saturating_sub(1)))
                .collect();
            let t = Instant::now();
            basis.truncate(base);
            for &c in newly_locked.iter().chain(&kept) {
                basis.push(&ritz_block[c * n..(c + 1) * n]);
            }
            orth_time += t.elapsed();
            if let Some(cb) = progress.as_deref_mut() {
                let report = Progress {
                    round: stats.rounds,
                    restarts: stats.restarts,
                    operator_applications: stats.operator_applications,
                    locked: locked.len(),
                    wanted: k,
                };
                if cb(&report).is_break() {
                    limit_hit = true;
                    break 'rounds;
                }
            }
            let unlocked: Vec<usize> = pairs
                .order
                .iter()
                .copied()
                .filter(|&i| !newly_locked.iter().any(|&c| selection[c] == i))
                .collect();
            if invariant || m_new == 0 || round_finished(which, tol, &locked, k, &pairs, &unlocked)
            {
                if new_in_round == 0 {
                    break 'rounds;
                }
                continue 'rounds;
            }
            if stats.restarts >= options.max_restarts {
                limit_hit = true;
                break 'rounds;
            }
            // Continue the Krylov–Schur sequence from the residual vector.
            h.fill(0.0);
            p = kept.len();
            for (r, &c) in kept.iter().enumerate() {
                let i = selection[c];
                h[(r, r)] = pairs.theta[i];
                let s = beta_last * pairs.y[(size - 1, i)];
                h[(p, r)] = s;
                h[(r, p)] = s;
            }
            basis.push(&ritz_block[selection.len() * n..(selection.len() + 1) * n]);
            base = new_base;
            m = m_new;
            j = p;
        }
    }

    // Locked pairs, best first.
    let mut order: Vec<usize> = (0..locked.len()).collect();
    order.sort_by(|&a, &b| which.score(locked[b]).total_cmp(&which.score(locked[a])));
    let (solves, solve_time) = op.solve_statistics();
    stats.solves = solves;
    stats.solve_time = solve_time;
    stats.orthogonalization_time = orth_time;
    stats.total_time = start_time.elapsed();
    Ok(Outcome {
        values: order.iter().map(|&i| locked[i]).collect(),
        vectors: order.iter().map(|&i| basis.col(nd + i).to_vec()).collect(),
        converged: !limit_hit && locked.len() >= k,
        statistics: stats,
    })
}

/// The `options.k` eigenpairs `A yᵢ = yᵢ θᵢ` of a Hermitian operator selected by
/// `options.which`, in the orthogonal complement of `deflation` (any vectors; they are
/// orthonormalised, dependent ones dropped). Vectors are orthonormal; residuals are the
/// operator's [`HermitianOperator::relative_residual`]. Ordering as in [`Eigen`].
pub fn hermitian_eigs<V, O>(
    op: &mut O,
    options: &LanczosOptions,
    deflation: &[Vec<V>],
    progress: Option<ProgressCallback>,
) -> Result<Eigen<V>, EigError<V>>
where
    V: Scalar<Real = f64>,
    O: HermitianOperator<V> + ?Sized,
{
    let n = op.dim();
    validate_options(options)?;
    let mut basis = Basis::new(n);
    let mut gs = GramSchmidt::new();
    let mut coef = Vec::new();
    for d in deflation {
        if d.len() != n {
            return Err(EigError::DimensionMismatch {
                expected: n,
                found: d.len(),
                context: "deflation vector",
            });
        }
        let mut v = d.clone();
        append_orthonormal(&mut basis, &mut gs, &mut v, &mut coef);
    }
    let available = n - basis.cols();
    if options.k == 0 || options.k > available {
        return Err(EigError::InvalidCount {
            k: options.k,
            available,
        });
    }
    let outcome = run(op, options, options.k, basis, progress).map_err(EigError::DenseEigen)?;
    let count = outcome.values.len().min(options.k);
    let residuals = outcome.vectors[..count]
        .iter()
        .zip(&outcome.values)
        .map(|(y, &theta)| op.relative_residual(y, theta))
        .collect();
    let result = Eigen {
        values: outcome.values[..count].to_vec(),
        vectors: outcome.vectors.into_iter().take(count).collect(),
        residuals,
        statistics: outcome.statistics,
    };
    if outcome.converged && count == options.k {
        Ok(result)
    } else {
        Err(EigError::NotConverged {
            wanted: options.k,
            partial: Box::new(result),
        })
    }
}

/// Checks the options that do not depend on the problem size.
pub(crate) fn validate_options<T>(options: &LanczosOptions) -> Result<(), EigError<T>> {
    if !(options.tolerance > 0.0 && options.tolerance < 1.0) {
        return Err(EigError::InvalidOption("tolerance must lie in (0, 1)"));
    }
    if options.max_restarts == 0 {
        return Err(EigError::InvalidOption("max_restarts must be positive"));
    }
    if options.max_operator_applications == 0 {
        return Err(EigError::InvalidOption(
            "max_operator_applications must be positive",
        ));
    }
    Ok(())
}
