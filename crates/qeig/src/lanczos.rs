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
//!   by a full Gram–Schmidt pass (modified, two columns at a time, each basis vector read
//!   from memory once) against the locked vectors and the whole active basis, after the
//!   projection against the deflation vectors, both repeated once when they removed more than
//!   `1 − 1/√2` of the norm (coefficients on the right). If `βⱼ` vanishes (an invariant
//!   subspace) a fresh random vector orthogonal to everything is appended with coupling `0`,
//!   which keeps the projected matrix exact.
//! * **Thick restart.** When the basis is full (or earlier, at a *check point* after a step,
//!   when the round may be finished) the projected matrix is diagonalised. A check point needs
//!   only the Ritz values and their estimates: the kept block is reduced to tridiagonal form
//!   once per cycle and the eigenvalues come with the last row of the eigenvectors alone, by
//!   implicit QL in `O(m²)`. Ritz pairs whose estimated residual
//!   `|βₘ yₘ| ≤ tol |θ|` and whose true residual (measured by the operator, for a pencil
//!   `‖K x − θ S x‖ / (|θ| ‖S x‖)`) is below `tol` are **locked**: moved out of the active
//!   basis, never changed again, and orthogonalised against from then on. The best unconverged
//!   Ritz vectors are kept with the residual vector as continuation (`A U = U Θ + q sᵀ`).
//!   For a pencil the true residual lags behind the estimate by a factor (the estimate's
//!   residual vector seen through the factor); after a restart whose candidates were all
//!   refused, the check points count only on pairs whose estimates are as much lower than
//!   `tol |θ|` as the refusals showed (the *lock margin*), so that the next restart comes
//!   when they can pass rather than after a fixed wait (Laplace spectra of small meshes: 8 %
//!   fewer operator applications).
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
//! * **Deflation.** Every vector is projected onto the complement of a user subspace
//!   (orthonormalised, and stored over the entries each of its directions touches: the
//!   constant per component of a mesh in many pieces is local), so the iteration never leaves
//!   it.
//!
//! Tolerance: relative, `tol` on the estimate and on the true residual of every locked pair,
//! except pairs at rounding level (`√tol` on the true residual, above).

use std::time::{Duration, Instant};

use faer::{Mat, MatRef};
use qscalar::Scalar;
use qscalar::random::SplitMix64;
use qsparse::{DenseMatrix, SparseVector, vector};

use crate::backend::VECTORS_PER_PASS;
use crate::basis::Basis;
use crate::dense::{
    real_symmetric_eigen, reduce_to_tridiagonal, tridiagonal_values_and_last_components,
};
use crate::error::{BasisTooLarge, DenseEigenError};
use crate::scaling::unit_range_factor;
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
    /// `0` chooses `p + clamp(p, 32, 64)` with `p = min(k, 128)` (for the iteration-space `k`:
    /// twice `k` up to `k = 64`, then 64 more than `k`, at most 192), capped by the dimension,
    /// and after each restart the same rule for the pairs still needed (the basis shrinks as
    /// pairs lock); a nonzero value is kept throughout.
    pub max_dim: usize,
    /// Largest number of thick restarts before giving up.
    pub max_restarts: usize,
    /// Largest number of operator applications before giving up.
    pub max_operator_applications: usize,
    /// Seed of the random start vectors (runs are deterministic for a given seed).
    pub seed: u64,
    /// Largest memory, in bytes, the Krylov basis may take (`None`: what the system reports
    /// as available). The basis — constraints, `k` locked pairs, the active basis and one
    /// continuation vector — is reserved before the iteration starts; a basis that does not
    /// fit is refused then with [`crate::EigError::BasisTooLarge`], which says how much it
    /// needs.
    pub memory_limit: Option<u64>,
}

impl LanczosOptions {
    /// `k` pairs of the given end with tolerance `1e−10`, automatic dimension, 1000 restarts,
    /// no limit on operator applications, seed 0, the basis limited by the available memory.
    pub fn new(k: usize, which: Which) -> Self {
        Self {
            k,
            which,
            tolerance: 1e-10,
            max_dim: 0,
            max_restarts: 1000,
            max_operator_applications: usize::MAX,
            seed: 0,
            memory_limit: None,
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
    /// [`HermitianOperator::relative_residual`] of the pairs `(thetas[j], yⱼ)`, the vectors
    /// `yⱼ` stored column after column in `ys`. Operators that read their data once for
    /// several vectors (a factor's half-solves) override it.
    fn relative_residuals(&mut self, ys: &[V], thetas: &[f64]) -> Vec<f64> {
        let n = self.dim();
        (ys.chunks_exact(n).zip(thetas))
            .map(|(y, &theta)| self.relative_residual(y, theta))
            .collect()
    }
    /// Triangular solves so far and the time they took (zero for operators without any).
    fn solve_statistics(&self) -> (usize, Duration) {
        (0, Duration::ZERO)
    }
    /// Bytes of the factor the operator holds (zero for operators without one).
    fn factor_bytes(&self) -> usize {
        0
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

/// The most pairs an automatic active basis is sized for: with more still needed, it holds
/// room for the next [`ACTIVE_WINDOW`] of them only.
///
/// The Lanczos sequence converges the wanted end first, and locked pairs leave the active
/// basis, so the pairs behind the first hundred or so are not converging in this cycle
/// anyway: holding Ritz vectors for them made every step read them and every restart's `Q Y`
/// recombine them, for about as many operator applications (armadillo, relative Dirac,
/// k = 500: 1,188 → 1,206 applications, 497k → 460k basis columns read, 45.8 → 43.5 s;
/// docs/PERFORMANCE.md, "A window of wanted pairs").
const ACTIVE_WINDOW: usize = 128;

/// The active dimension for `pairs` wanted pairs when the options leave it automatic: the
/// pairs (at most [`ACTIVE_WINDOW`]) and as many again, but at least 32 and at most 64 more.
///
/// Every step orthogonalises against the locked vectors and the active ones, so a step costs
/// about `locked + active` basis reads, and the locked vectors converge one window at a time
/// anyway. Beyond 64 spare vectors the extra room saved no operator applications on the
/// armadillo (relative Dirac, k = 200 and 500: 571 → 561 and 1,183 → 1,180 applications with
/// 64 spare instead of `k`) but read 11–17 % more basis columns (docs/PERFORMANCE.md).
fn active_for(pairs: usize) -> usize {
    let pairs = pairs.min(ACTIVE_WINDOW);
    pairs + pairs.clamp(32, 64)
}

/// Steps a round makes before its first check point, and the most steps between two.
///
/// A round may end only after this many steps: a check point certifies the Ritz values the
/// Krylov space holds, not the absence of others, and a start vector's component along a copy
/// of a multiple eigenvalue that earlier rounds missed needs a few steps to grow (checking
/// from the first step of a round returned six of the seven copies of `l = 3` on a sphere,
/// docs/PERFORMANCE.md).
const CHECK_INTERVAL: usize = 10;

/// Steps between check points for a projected matrix of dimension `size`: every step while
/// a check is cheap against a step (`size < 256`: under 1 ms against 15–30 ms on a
/// 43k-vertex mesh), then fewer, as a check grows with `size` (the reduction of the kept
/// block, once per cycle, as its cube; the eigenvalues at each check as `size²`), up to
/// [`CHECK_INTERVAL`]. A check after every step ends a round as soon as it may end, where a
/// fixed interval of 10 ran up to 9 steps past it.
fn check_interval(size: usize) -> usize {
    let blocks = size / 128;
    (blocks * blocks).clamp(1, CHECK_INTERVAL)
}

/// The longest the iteration runs between two calls of the progress callback: besides after
/// every restart, it is called after the first step this long after the last call, so that a
/// caller stopping the run (Ctrl-C, a time limit) is heard within a step or so, not after a
/// whole cycle (seconds on a 43k-vertex mesh with k = 500, a minute on a million vertices).
const PROGRESS_INTERVAL: Duration = Duration::from_millis(100);

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

/// The eigenvalues `θᵢ` of the projected matrix with the residual estimates `|β yᵢ,ₘ|` of
/// the Ritz pairs they define (`yᵢ` the unit eigenvectors, `m` the last row): all that a check
/// point reads.
struct RitzValues {
    theta: Vec<f64>,
    estimate: Vec<f64>,
    /// Indices by decreasing wantedness.
    order: Vec<usize>,
    /// The coupling `β` of the continuation vector (0 after an invariant subspace).
    beta: f64,
}

/// The eigenpairs `(θᵢ, yᵢ)` of the projected matrix, which a restart combines the basis with.
struct RitzPairs {
    values: RitzValues,
    y: Mat<f64>,
}

impl RitzValues {
    /// The indices of `order` not in `excluded`, in order.
    fn others(&self, excluded: &[usize]) -> Vec<usize> {
        (self.order.iter().copied())
            .filter(|i| !excluded.contains(i))
            .collect()
    }
}

/// The arrowhead block `h[..=kept, ..=kept]` of the projected matrix (the `kept` Ritz values
/// kept at the last restart on the diagonal, coupled to row `kept`; the rest of `h` is
/// tridiagonal) reduced to tridiagonal form, for the check points of one Krylov–Schur cycle:
/// the block changes only at a restart.
///
/// The reduction is by Householder reflectors that fix the block's last index `kept` (the block
/// is reversed, so that [`reduce_to_tridiagonal`]'s fixed first index is `kept`), so the
/// similarity leaves every index from `kept` on alone — `h[kept, kept]`, the coupling to the
/// tridiagonal rest and the last row among them — and the whole becomes tridiagonal.
struct ReducedHead {
    /// The power of two the block was scaled by to bring it near unit size (exact); the rest
    /// of `h` comes from the same operator and is scaled alike.
    factor: f64,
    /// The reduced diagonal at indices `..kept`.
    diagonal: Vec<f64>,
    /// The reduced couplings of indices `i` and `i + 1` for `i < kept`.
    off: Vec<f64>,
}

impl ReducedHead {
    /// The reduction of the block of `h` (at least `kept + 1` square, `h[kept, kept]` set).
    fn new(h: MatRef<'_, f64>, kept: usize) -> Self {
        let head = kept + 1;
        let entries: Vec<f64> = (0..head)
            .flat_map(|j| (0..head).map(move |i| h[(i, j)]))
            .collect();
        let factor = unit_range_factor(&entries, false);
        let mut block = DenseMatrix::from_fn(head, head, |i, j| factor * h[(kept - i, kept - j)]);
        let sub = if head >= 3 {
            reduce_to_tridiagonal(&mut block).sub
        } else {
            (0..kept).map(|i| block[(i + 1, i)]).collect()
        };
        Self {
            factor,
            diagonal: (1..head).rev().map(|i| block[(i, i)]).collect(),
            off: sub.into_iter().rev().collect(),
        }
    }

    /// Eigenvalues (ascending) of the projected matrix `h` (`m × m`, `m > kept`) whose block
    /// this is, with the last components `|yₘ₋₁|` of its unit eigenvectors:
    /// [`tridiagonal_values_and_last_components`], `O(m²)`.
    fn projected_values(
        &self,
        h: MatRef<'_, f64>,
    ) -> Result<(Vec<f64>, Vec<f64>), DenseEigenError> {
        let (m, kept) = (h.nrows(), self.diagonal.len());
        let mut diagonal = Vec::with_capacity(m);
        diagonal.extend_from_slice(&self.diagonal);
        diagonal.push(self.factor * h[(kept, kept)]);
        let mut off = Vec::with_capacity(m);
        off.extend_from_slice(&self.off);
        for j in kept + 1..m {
            diagonal.push(self.factor * h[(j, j)]);
            off.push(self.factor * h[(j, j - 1)]);
        }
        let (mut values, last) = tridiagonal_values_and_last_components(&diagonal, &off)?;
        values.iter_mut().for_each(|v| *v /= self.factor);
        Ok((values, last))
    }
}

/// How an expansion of the active basis ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Expansion {
    /// The active basis is full: restart.
    Full,
    /// `A` maps the basis into itself and no fresh direction is left: restart and end the round.
    Invariant,
    /// A periodic check point: restart only if the round turns out to be finished.
    CheckPoint,
}

/// What comes after a restart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum AfterRestart {
    /// The Krylov–Schur sequence continues from the residual vector.
    Continue,
    /// The round is finished; a new one may start.
    RoundFinished,
}

/// A limit was reached or the progress callback asked to stop: the run ends unconverged.
struct Stopped;

/// The thick-restart Lanczos iteration (module documentation), as a state with one method
/// per step: [`Lanczos::start_round`], [`Lanczos::expand`], [`Lanczos::ritz_pairs`],
/// [`Lanczos::locking_candidates`], [`Lanczos::restart`].
///
/// The basis is laid out as `[locked | kept Ritz vectors | Krylov vectors]`, all orthogonal
/// to the deflation directions the basis holds apart ([`Basis::constrained`]):
/// the *active* basis starts after the locked vectors, its first `kept` columns are the Ritz
/// vectors kept at the last restart, and `h` is the projected matrix of the active basis
/// (an arrowhead for the kept vectors, then tridiagonal).
struct Lanczos<'a, 'p, V, O: ?Sized> {
    op: &'a mut O,
    options: &'a LanczosOptions,
    progress: Option<ProgressCallback<'p>>,
    /// When the progress callback was last called (or the iteration started).
    reported: Instant,
    /// Pairs wanted (iteration space).
    k: usize,
    n: usize,
    /// Deflation directions: the iteration runs in a space of dimension `n − deflation`.
    deflation: usize,
    /// Largest active dimension.
    max_active: usize,
    basis: Basis<V>,
    rng: SplitMix64,
    h: Mat<f64>,
    /// The vector being expanded (`A qⱼ` and its orthogonalisation), in the basis's blocked
    /// layout.
    w: Vec<V>,
    /// The operator's argument and result, ordinary `n`-vectors.
    x: Vec<V>,
    y: Vec<V>,
    coef: Vec<V>,
    /// Locked eigenvalues, in the order of their basis columns.
    locked: Vec<f64>,
    statistics: Statistics,
    orthogonalization_time: Duration,
    /// Largest |Ritz value| so far: a lower bound of ‖A‖ for the rounding level of estimates.
    norm_estimate: f64,
    /// Pairs of this round better than the `k`-th pair locked before them.
    new_in_round: usize,
    /// Active dimension of the current Krylov–Schur cycle.
    active: usize,
    /// Kept Ritz vectors in front of the active basis.
    kept: usize,
    /// The arrowhead of `h` reduced for the check points of this cycle, once one needed it.
    head: Option<ReducedHead>,
    /// Number of active columns expanded so far (the next one to expand).
    expanded: usize,
    /// Lanczos steps of the current round.
    round_steps: usize,
    /// Lanczos steps since the last check point or restart.
    since_check: usize,
    /// Steps after a restart before the next check point may come, and the margin below
    /// `tol |θ|` an estimate needs there for the check point to count on its pair
    /// ([`Lanczos::locking_candidates`]), by what the restart locked:
    /// * some pairs: `1` and `1`, the next check point as soon as the round may end (a restart
    ///   that locks some of its candidates is progress even if others are refused);
    /// * none, its candidates refused by their true residuals: `1` and
    ///   [`Self::lock_margin`], the next check point once the estimates are as low as the
    ///   refusals showed they must be (a check one step later would restart on the same
    ///   candidates again);
    /// * none, without candidates (or without a usable residual): [`CHECK_INTERVAL`] and
    ///   `1` (checking every step restarted without progress: on the camel head, k = 20, 44
    ///   restarts and 277 applications instead of 6 and 107).
    check_delay: usize,
    /// See [`Self::check_delay`].
    check_margin: f64,
    /// The lowest ratio `e / (|θ| r)` of a Lanczos estimate `e` to the true residual `r > tol`
    /// of a refused candidate so far ([`Lanczos::learn_from_refusal`]); `1` before any.
    lock_margin: f64,
}

impl<'a, 'p, V, O> Lanczos<'a, 'p, V, O>
where
    V: Scalar<Real = f64>,
    O: HermitianOperator<V> + ?Sized,
{
    fn new(
        op: &'a mut O,
        options: &'a LanczosOptions,
        k: usize,
        mut basis: Basis<V>,
        progress: Option<ProgressCallback<'p>>,
    ) -> Result<Self, BasisTooLarge> {
        let n = op.dim();
        let deflation = basis.constraint_count();
        let max_active = if options.max_dim == 0 {
            active_for(k)
        } else {
            options.max_dim
        }
        .min(n - deflation)
        .max(1);
        // k locked pairs, the active basis and its continuation vector.
        let columns = (k + max_active + 1).min(n - deflation + 1);
        basis.reserve_columns(columns, options.memory_limit)?;
        let layout_len = basis.layout_len();
        Ok(Self {
            op,
            options,
            progress,
            reported: Instant::now(),
            k,
            n,
            deflation,
            max_active,
            basis,
            rng: SplitMix64::new(options.seed),
            h: Mat::zeros(max_active + 1, max_active + 1),
            w: vec![V::zero(); layout_len],
            x: vec![V::zero(); n],
            y: vec![V::zero(); n],
            coef: Vec::new(),
            locked: Vec::new(),
            statistics: Statistics::default(),
            orthogonalization_time: Duration::ZERO,
            norm_estimate: 0.0,
            new_in_round: 0,
            active: 0,
            kept: 0,
            head: None,
            expanded: 0,
            round_steps: 0,
            since_check: 0,
            check_delay: 1,
            check_margin: 1.0,
            lock_margin: 1.0,
        })
    }

    /// The active dimension after a restart with the active basis starting at `base`: the
    /// rule of [`active_for`] for the pairs still needed, as for the first cycle, and never
    /// more than the first cycle's. Shrinking it as pairs lock keeps the whole basis — the
    /// locked vectors and the active ones, which every step orthogonalises against — near
    /// `k + spare` instead of `k + max_active` (docs/PERFORMANCE.md, "Many pairs").
    fn active_dimension(&self, base: usize) -> usize {
        let wanted = if self.options.max_dim == 0 {
            active_for(self.needed())
        } else {
            self.max_active
        };
        wanted
            .min(self.max_active)
            .min(self.n - self.deflation - base)
    }

    /// Pairs still needed (at least one).
    fn needed(&self) -> usize {
        self.k.saturating_sub(self.locked.len()).max(1)
    }

    /// Ritz vectors a thick restart keeps for an active basis of dimension `active`: the pairs
    /// the basis is sized for (those still needed; with an automatic basis at most
    /// [`ACTIVE_WINDOW`]) and half of the spare room, at most `active − 1` (room for a step).
    ///
    /// Counted for the basis the sequence continues in, after this restart's locking: counted
    /// before it, the first restart of a run (k = 60: 60 needed in 120, keep 90) kept 58
    /// vectors in an active basis of 59, which then restarted after a single step. Counted
    /// for all the pairs needed beyond the window, it would fill the basis and leave a single
    /// step per restart.
    fn keep_count(&self, active: usize) -> usize {
        let sized_for = if self.options.max_dim == 0 {
            self.needed().min(ACTIVE_WINDOW)
        } else {
            self.needed()
        };
        (sized_for + (active - sized_for.min(active)) / 2).min(active.saturating_sub(1))
    }

    /// First column of the active basis.
    fn base(&self) -> usize {
        self.locked.len()
    }

    /// Starts a round from a fresh random vector orthogonal to the deflation and locked
    /// vectors; `false` if there is no room or no such vector left.
    fn start_round(&mut self) -> bool {
        let base = self.base();
        if base + self.deflation >= self.n {
            return false;
        }
        self.statistics.rounds += 1;
        self.basis.truncate(base);
        self.rng.fill_symmetric(&mut self.x);
        let t = Instant::now();
        let started = self.basis.append_ordinary(&self.x, &mut self.coef);
        self.orthogonalization_time += t.elapsed();
        self.active = self.active_dimension(base);
        self.kept = 0;
        self.head = None;
        self.expanded = 0;
        self.round_steps = 0;
        self.since_check = 0;
        self.new_in_round = 0;
        self.h.fill(0.0);
        started
    }

    /// Lanczos steps until the active basis is full, invariant, or at a check point.
    fn expand(&mut self) -> Result<Expansion, Stopped> {
        let base = self.base();
        while self.expanded < self.active {
            if self.statistics.operator_applications >= self.options.max_operator_applications {
                return Err(Stopped);
            }
            let j = self.expanded;
            self.basis.column_to(base + j, &mut self.x);
            self.op.apply(&self.x, &mut self.y);
            self.basis.to_layout(&self.y, &mut self.w);
            self.statistics.operator_applications += 1;
            self.statistics.iterations += 1;
            let t = Instant::now();
            let appended = self.orthogonalize_step(base, j);
            self.orthogonalization_time += t.elapsed();
            self.expanded += 1;
            if !appended {
                return Ok(Expansion::Invariant);
            }
            self.round_steps += 1;
            self.since_check += 1;
            if self.reported.elapsed() >= PROGRESS_INTERVAL {
                self.report_progress()?;
            }
            if self.round_steps >= CHECK_INTERVAL
                && self.since_check >= check_interval(self.expanded).max(self.check_delay)
                && self.expanded < self.active
                && self.locked.len() + self.expanded >= self.k
            {
                self.since_check = 0;
                self.check_delay = 1;
                return Ok(Expansion::CheckPoint);
            }
        }
        Ok(Expansion::Full)
    }

    /// Turns `w = A qⱼ` into the next basis vector: the three-term recurrence (after the kept
    /// vectors' arrowhead), full Gram–Schmidt, the projected matrix's column `j`. Returns
    /// whether a vector was appended (`false`: invariant subspace and no fresh direction).
    fn orthogonalize_step(&mut self, base: usize, j: usize) -> bool {
        let w = &mut self.w;
        let raw = vector::norm(w);
        let mut alpha = 0.0;
        if j > self.kept {
            let qj = self.basis.col(base + j);
            // The real part of an inner product is the same in any layout.
            alpha = vector::real_inner(qj, w);
            vector::axpy_real(w, qj, -alpha);
            let coupling = self.h[(j, j - 1)];
            vector::axpy_real(w, self.basis.col(base + j - 1), -coupling);
        }
        self.basis.orthogonalize(base + j + 1, w, &mut self.coef);
        self.h[(j, j)] = alpha + self.coef[base + j].re();
        let beta = vector::norm(w);
        if beta > 1e-12 * raw {
            vector::scale(w, 1.0 / beta);
            self.basis.push(w);
            self.h[(j + 1, j)] = beta;
            self.h[(j, j + 1)] = beta;
            true
        } else {
            // Invariant subspace: continue from a fresh direction, decoupled.
            self.rng.fill_symmetric(&mut self.x);
            self.basis.append_ordinary(&self.x, &mut self.coef)
        }
    }

    /// The Ritz pairs of the expanded active basis.
    fn ritz_pairs(&mut self, expansion: Expansion) -> Result<RitzPairs, DenseEigenError> {
        let size = self.expanded;
        let beta = match expansion {
            Expansion::Invariant => 0.0,
            _ => self.h[(size, size - 1)],
        };
        let (theta, y) = real_symmetric_eigen(self.h.as_ref().submatrix(0, 0, size, size))?;
        let last = (0..size).map(|i| y[(size - 1, i)]).collect();
        Ok(RitzPairs {
            values: self.ritz_values_from(theta, last, beta),
            y,
        })
    }

    /// The Ritz values and estimates of the expanded active basis at a check point (never
    /// after an invariant subspace), without the vectors: [`ReducedHead::projected_values`],
    /// `O(m²)` where [`Lanczos::ritz_pairs`] costs `O(m³)`. On a 3,000-vertex Laplacian,
    /// faer's eigensolve of the 40–50-dimensional projected matrix took about half as long as
    /// a Lanczos step, and near the end of a round there is a check point after every step.
    fn ritz_values(&mut self) -> Result<RitzValues, DenseEigenError> {
        let size = self.expanded;
        let beta = self.h[(size, size - 1)];
        let h = self.h.as_ref().submatrix(0, 0, size, size);
        let head = (self.head).get_or_insert_with(|| ReducedHead::new(h, self.kept));
        let (theta, last) = head.projected_values(h)?;
        Ok(self.ritz_values_from(theta, last, beta))
    }

    /// [`RitzValues`] from the eigenvalues and the last components of the eigenvectors; the
    /// estimate of `‖A‖` follows the largest `|θ|`.
    fn ritz_values_from(&mut self, theta: Vec<f64>, last: Vec<f64>, beta: f64) -> RitzValues {
        let estimate = last.iter().map(|z| (beta * z).abs()).collect();
        let which = self.options.which;
        let mut order: Vec<usize> = (0..theta.len()).collect();
        order.sort_by(|&a, &b| which.score(theta[b]).total_cmp(&which.score(theta[a])));
        self.norm_estimate = theta.iter().fold(self.norm_estimate, |a, t| a.max(t.abs()));
        RitzValues {
            theta,
            estimate,
            order,
            beta,
        }
    }

    /// Ritz pairs to try to lock, in order of wantedness: estimate below `margin · tol |θ|`
    /// (or at the rounding level, if below `tol |θ|`) and not worse than the `k`-th of the
    /// locked values and the candidates before them.
    ///
    /// A restart tries every pair below `tol |θ|` (`margin` 1: a refusal costs one residual);
    /// a check point counts on those below [`Self::check_margin`] to decide whether the round
    /// may end (a check point that counts on pairs the true residual then refuses restarts
    /// without progress).
    fn locking_candidates(&self, pairs: &RitzValues, margin: f64) -> (Vec<usize>, Vec<f64>) {
        let (which, tol) = (self.options.which, self.options.tolerance);
        let passes = |theta: f64, estimate: f64| {
            estimate <= tol * theta.abs()
                && (estimate <= margin * tol * theta.abs()
                    || estimate <= ROUNDING * self.norm_estimate)
        };
        let mut values = self.locked.clone();
        let mut candidates = Vec::new();
        for &i in &pairs.order {
            let theta = pairs.theta[i];
            if !passes(theta, pairs.estimate[i]) {
                continue;
            }
            let wanted =
                kth_best(which, &values, self.k).is_none_or(|kth| !better(which, kth, theta, tol));
            if wanted {
                candidates.push(i);
                values.push(theta);
            }
        }
        (candidates, values)
    }

    /// Whether the round can end: `k` values among `values` (locked, or locked and
    /// candidates), and at every wanted end the extreme Ritz value among `remaining` is known
    /// not to enter the window.
    fn round_finished(&self, values: &[f64], pairs: &RitzValues, remaining: &[usize]) -> bool {
        let (which, tol) = (self.options.which, self.options.tolerance);
        let Some(kth) = kth_best(which, values, self.k) else {
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
        let top = remaining.iter().max_by(by_value);
        let bottom = remaining.iter().min_by(by_value);
        match which {
            Which::LargestAlgebraic => top.is_none_or(|&i| clear(i)),
            Which::SmallestAlgebraic => bottom.is_none_or(|&i| clear(i)),
            Which::LargestMagnitude => {
                top.is_none_or(|&i| clear(i)) && bottom.is_none_or(|&i| clear(i))
            }
        }
    }

    /// The thick restart: Ritz vectors of the candidates and of the best other pairs (in place
    /// in the active basis), locking of the candidates whose true residual passes, and the new
    /// layout `[locked | kept | continuation]`.
    fn restart(
        &mut self,
        pairs: &RitzPairs,
        candidates: &[usize],
        expansion: Expansion,
    ) -> Result<AfterRestart, Stopped> {
        let ritz = &pairs.values;
        let invariant = expansion == Expansion::Invariant;
        let (base, size) = (self.base(), self.expanded);
        self.statistics.restarts += 1;
        let keep_max = if invariant {
            0
        } else {
            self.keep_count(self.active)
        }
        .min(size.saturating_sub(candidates.len()));
        let mut selection = candidates.to_vec();
        selection.extend(ritz.others(candidates).into_iter().take(keep_max));

        let t = Instant::now();
        let y = Mat::<f64>::from_fn(size, selection.len(), |r, c| pairs.y[(r, selection[c])]);
        self.basis.combine_in_place(base, y.as_ref());
        self.orthogonalization_time += t.elapsed();

        let (newly_locked, informative_refusal) = self.lock(ritz, &selection[..candidates.len()]);
        let new_active = self.active_dimension(self.base());
        let kept: Vec<usize> = (0..selection.len())
            .filter(|c| !newly_locked.contains(c))
            .take(keep_max.min(self.keep_count(new_active)))
            .collect();
        self.relayout(
            base,
            &newly_locked,
            &kept,
            (!invariant).then_some(base + size),
        );
        self.report_progress()?;

        let locked_now: Vec<usize> = newly_locked.iter().map(|&c| selection[c]).collect();
        let unlocked = ritz.others(&locked_now);
        if invariant || new_active == 0 || self.round_finished(&self.locked, ritz, &unlocked) {
            return Ok(AfterRestart::RoundFinished);
        }
        if self.statistics.restarts >= self.options.max_restarts {
            return Err(Stopped);
        }
        // Continue the Krylov–Schur sequence: A U = U Θ + q sᵀ with s = β (last row of Y).
        self.h.fill(0.0);
        let p = kept.len();
        for (r, &c) in kept.iter().enumerate() {
            let i = selection[c];
            self.h[(r, r)] = ritz.theta[i];
            let s = ritz.beta * pairs.y[(size - 1, i)];
            self.h[(p, r)] = s;
            self.h[(r, p)] = s;
        }
        self.kept = p;
        self.head = None;
        self.expanded = p;
        self.since_check = 0;
        (self.check_delay, self.check_margin) = match (newly_locked.is_empty(), informative_refusal)
        {
            (false, _) => (1, 1.0),
            (true, true) => (1, self.lock_margin),
            (true, false) => (CHECK_INTERVAL, 1.0),
        };
        self.active = new_active;
        Ok(AfterRestart::Continue)
    }

    /// Locks the candidates (Ritz pairs `candidates[c]`, whose vectors are now the active
    /// columns `c`) whose true residual passes the tolerance, or whose estimate is at the
    /// rounding level; returns their positions `c`, and whether a refused candidate told how
    /// far its true residual lags ([`Self::learn_from_refusal`]).
    fn lock(&mut self, ritz: &RitzValues, candidates: &[usize]) -> (Vec<usize>, bool) {
        let (which, tol) = (self.options.which, self.options.tolerance);
        let base = self.base();
        let kth_before = kth_best(which, &self.locked, self.k);
        let thetas: Vec<f64> = candidates.iter().map(|&i| ritz.theta[i]).collect();
        // The operator takes ordinary vectors: a few at a time, as many as it reads its data
        // once for.
        let mut residuals = Vec::with_capacity(thetas.len());
        let mut vectors = vec![V::zero(); VECTORS_PER_PASS * self.n];
        for (chunk, chunk_thetas) in thetas.chunks(VECTORS_PER_PASS).enumerate() {
            let vectors = &mut vectors[..chunk_thetas.len() * self.n];
            for (c, x) in vectors.chunks_exact_mut(self.n).enumerate() {
                self.basis.column_to(base + chunk * VECTORS_PER_PASS + c, x);
            }
            residuals.extend(self.op.relative_residuals(vectors, chunk_thetas));
        }
        let mut newly_locked = Vec::new();
        let mut informative_refusal = false;
        for (c, (&i, residual)) in candidates.iter().zip(residuals).enumerate() {
            let (theta, estimate) = (ritz.theta[i], ritz.estimate[i]);
            let at_rounding_level = estimate <= ROUNDING * self.norm_estimate;
            // A NaN or infinite value (an operator out of floating-point range) never locks.
            if theta.is_finite()
                && self.norm_estimate.is_finite()
                && (residual <= tol || at_rounding_level)
            {
                newly_locked.push(c);
                let is_new = kth_before.is_none_or(|kth| better(which, theta, kth, tol));
                self.new_in_round += usize::from(is_new);
            } else {
                informative_refusal |= self.learn_from_refusal(theta, estimate, residual);
            }
        }
        self.locked
            .extend(newly_locked.iter().map(|&c| ritz.theta[candidates[c]]));
        self.statistics.locked = self.locked.len();
        (newly_locked, informative_refusal)
    }

    /// A candidate with estimate `e` had the true residual `r > tol`: for a pencil the two
    /// differ by a factor `r |θ| / e` (the residual `βₘ yₘ qₘ₊₁` of the iteration space seen
    /// through the factor, `‖C qₘ₊₁‖ / ‖C y‖`, which a smooth Ritz vector and a rough Lanczos
    /// vector make large), so candidates need estimates that much lower. Lowers
    /// [`Self::lock_margin`] to `e / (|θ| r)` if that is lower; returns whether the ratio is
    /// usable (positive and finite: not for a zero estimate or a non-finite residual).
    ///
    /// The factor fluctuates with `qₘ₊₁` and between pairs, and near the attainable accuracy
    /// the residual stops following the estimate (a pair with estimate `5.5e−14 |θ|` and
    /// residual `1.3e−10` on psb_285's relative Dirac operator), so the lowest ratio is only
    /// used after a restart that locked nothing ([`Self::check_delay`]), where it replaces a
    /// blind wait; it costs at most a restart at a full basis, which tries every pair below
    /// `tol |θ|` again.
    fn learn_from_refusal(&mut self, theta: f64, estimate: f64, residual: f64) -> bool {
        let margin = estimate / (theta.abs() * residual);
        let usable = margin > 0.0 && margin.is_finite();
        if usable {
            self.lock_margin = self.lock_margin.min(margin);
        }
        usable
    }

    /// Moves the active columns `base + c` to `[newly locked | kept]` from `base` on, followed
    /// by the continuation vector (column `continuation`, if any), and drops the rest.
    fn relayout(
        &mut self,
        base: usize,
        newly_locked: &[usize],
        kept: &[usize],
        continuation: Option<usize>,
    ) {
        let t = Instant::now();
        let layout: Vec<usize> = newly_locked.iter().chain(kept).copied().collect();
        self.basis.select_columns(base, &layout);
        if let Some(column) = continuation {
            self.basis.copy_column(column, base + layout.len());
        }
        let columns = base + layout.len() + usize::from(continuation.is_some());
        self.basis.truncate(columns);
        self.orthogonalization_time += t.elapsed();
    }

    /// Calls the progress callback; `Stopped` if it asks to stop.
    fn report_progress(&mut self) -> Result<(), Stopped> {
        self.reported = Instant::now();
        let Some(callback) = self.progress.as_deref_mut() else {
            return Ok(());
        };
        let report = Progress {
            round: self.statistics.rounds,
            restarts: self.statistics.restarts,
            operator_applications: self.statistics.operator_applications,
            locked: self.locked.len(),
            wanted: self.k,
        };
        if callback(&report).is_break() {
            return Err(Stopped);
        }
        Ok(())
    }

    /// One round: cycles of expansion and restart until the round is finished.
    fn round(&mut self) -> Result<(), LanczosFailure> {
        loop {
            let expansion = self.expand()?;
            if expansion == Expansion::CheckPoint {
                let ritz = self.ritz_values()?;
                let (candidates, values) = self.locking_candidates(&ritz, self.check_margin);
                if !self.round_finished(&values, &ritz, &ritz.others(&candidates)) {
                    continue; // keep expanding
                }
            }
            let pairs = self.ritz_pairs(expansion)?;
            let (candidates, _) = self.locking_candidates(&pairs.values, 1.0);
            if self.restart(&pairs, &candidates, expansion)? == AfterRestart::RoundFinished {
                return Ok(());
            }
        }
    }

    /// The locked pairs, best first.
    fn finish(self, start: Instant, converged: bool) -> Outcome<V> {
        let which = self.options.which;
        let mut order: Vec<usize> = (0..self.locked.len()).collect();
        order.sort_by(|&a, &b| {
            which
                .score(self.locked[b])
                .total_cmp(&which.score(self.locked[a]))
        });
        let mut statistics = self.statistics;
        (statistics.solves, statistics.solve_time) = self.op.solve_statistics();
        statistics.orthogonalization_time = self.orthogonalization_time;
        statistics.basis_columns_read = self.basis.columns_read();
        statistics.basis_bytes = self.basis.reserved_bytes();
        statistics.factor_bytes = self.op.factor_bytes();
        statistics.total_time = start.elapsed();
        let converged = converged && self.locked.len() >= self.k;
        let values = order.iter().map(|&i| self.locked[i]).collect();
        let mut basis = self.basis;
        basis.truncate(self.locked.len());
        basis.select_columns(0, &order);
        Outcome {
            values,
            vectors: basis.into_columns(),
            converged,
            statistics,
        }
    }
}

/// Why a round ended the run early.
enum LanczosFailure {
    /// A limit or the callback: the run ends with what is locked.
    Stopped,
    /// The projected matrix's eigensolver failed.
    DenseEigen(DenseEigenError),
}

impl From<Stopped> for LanczosFailure {
    fn from(_: Stopped) -> Self {
        Self::Stopped
    }
}

impl From<DenseEigenError> for LanczosFailure {
    fn from(e: DenseEigenError) -> Self {
        Self::DenseEigen(e)
    }
}

/// What stops [`run`] without a result.
#[derive(Debug)]
pub(crate) enum RunError {
    /// The basis does not fit in memory.
    BasisTooLarge(BasisTooLarge),
    /// The projected matrix's eigensolver failed.
    DenseEigen(DenseEigenError),
}

impl<T> From<RunError> for EigError<T> {
    fn from(e: RunError) -> Self {
        match e {
            RunError::BasisTooLarge(e) => EigError::BasisTooLarge(e),
            RunError::DenseEigen(e) => EigError::DenseEigen(e),
        }
    }
}

/// Runs the iteration for `k` pairs of `op` in the orthogonal complement of `basis`'s
/// constraints (`basis` holds no columns yet).
pub(crate) fn run<V, O>(
    op: &mut O,
    options: &LanczosOptions,
    k: usize,
    basis: Basis<V>,
    progress: Option<ProgressCallback>,
) -> Result<Outcome<V>, RunError>
where
    V: Scalar<Real = f64>,
    O: HermitianOperator<V> + ?Sized,
{
    let start = Instant::now();
    let mut lanczos =
        Lanczos::new(op, options, k, basis, progress).map_err(RunError::BasisTooLarge)?;
    while lanczos.start_round() {
        match lanczos.round() {
            Ok(()) if lanczos.new_in_round > 0 => {}
            Ok(()) => break,
            Err(LanczosFailure::Stopped) => return Ok(lanczos.finish(start, false)),
            Err(LanczosFailure::DenseEigen(e)) => return Err(RunError::DenseEigen(e)),
        }
    }
    Ok(lanczos.finish(start, true))
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
    if let Some(d) = deflation.iter().find(|d| d.len() != n) {
        return Err(EigError::DimensionMismatch {
            expected: n,
            found: d.len(),
            context: "deflation vector",
        });
    }
    let basis = Basis::constrained(n, deflation.iter().map(|d| SparseVector::from_dense(d)));
    let available = n - basis.constraint_count();
    if options.k == 0 || options.k > available {
        return Err(EigError::InvalidCount {
            k: options.k,
            available,
        });
    }
    let outcome = run(op, options, options.k, basis, progress)?;
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

#[cfg(test)]
mod tests {
    use faer::Mat;
    use proptest::prelude::*;

    use std::ops::ControlFlow;
    use std::time::{Duration, Instant};

    use super::{HermitianOperator, LanczosOptions, PROGRESS_INTERVAL, ReducedHead, Which, run};
    use crate::basis::Basis;
    use crate::dense::real_symmetric_eigen;
    use crate::{EigError, Progress};

    /// `diag(1, 2, …, n)`, applied in no less than `delay` each time: a stand-in for a large
    /// problem whose cycles between restarts are long.
    struct SlowDiagonal {
        n: usize,
        delay: Duration,
    }

    impl HermitianOperator<f64> for SlowDiagonal {
        fn dim(&self) -> usize {
            self.n
        }

        fn apply(&mut self, x: &[f64], y: &mut [f64]) {
            std::thread::sleep(self.delay);
            for (i, (y, x)) in y.iter_mut().zip(x).enumerate() {
                *y = (i + 1) as f64 * x;
            }
        }

        fn relative_residual(&mut self, y: &[f64], theta: f64) -> f64 {
            let norm = y.iter().map(|v| v * v).sum::<f64>().sqrt();
            let residual = (y.iter().enumerate())
                .map(|(i, v)| ((i + 1) as f64 * v - theta * v).powi(2))
                .sum::<f64>()
                .sqrt();
            residual / (theta.abs() * norm)
        }
    }

    #[test]
    fn progress_is_reported_between_restarts_and_a_stop_is_heard_there() {
        // Clustered at the top (gaps of 1 in 300), so that the first restart comes after the
        // first check point (step 10), while a step takes a fifth of the progress interval.
        let delay = PROGRESS_INTERVAL / 5;
        let mut options = LanczosOptions::new(1, Which::LargestAlgebraic);
        options.max_dim = 40;
        let mut calls: Vec<(Progress, Instant)> = Vec::new();
        let start = Instant::now();
        let mut stop_at_first_call = |p: &Progress| {
            calls.push((*p, Instant::now()));
            ControlFlow::Break(())
        };
        let mut op = SlowDiagonal { n: 300, delay };
        let outcome = run(
            &mut op,
            &options,
            1,
            Basis::new(300),
            Some(&mut stop_at_first_call),
        )
        .map_err(EigError::<f64>::from)
        .unwrap();
        assert!(!outcome.converged);
        let [(first, at)] = calls[..] else {
            panic!("one call, which stopped the run: {calls:?}")
        };
        assert_eq!(first.restarts, 0, "{first:?}");
        assert!(first.operator_applications < 10, "{first:?}");
        // Half the 40 steps to the first restart, with room for a busy machine's sleeps.
        assert!(at - start < 20 * delay, "stopped after {:?}", at - start);
    }

    /// A projected matrix of dimension `thetas.len() + tail.len()` as a thick restart leaves
    /// it: the kept Ritz values on the diagonal, coupled by `couplings` to row `kept`, then
    /// tridiagonal with diagonal `tail` and off-diagonal `betas`, all times `scale`.
    fn projected(
        thetas: &[f64],
        couplings: &[f64],
        tail: &[f64],
        betas: &[f64],
        scale: f64,
    ) -> Mat<f64> {
        let (kept, m) = (thetas.len(), thetas.len() + tail.len());
        let mut h = Mat::zeros(m, m);
        for (r, (&theta, &s)) in thetas.iter().zip(couplings).enumerate() {
            h[(r, r)] = scale * theta;
            h[(kept, r)] = scale * s;
            h[(r, kept)] = scale * s;
        }
        for (j, &alpha) in tail.iter().enumerate() {
            h[(kept + j, kept + j)] = scale * alpha;
        }
        for (j, &beta) in betas.iter().enumerate().take(tail.len().saturating_sub(1)) {
            h[(kept + j + 1, kept + j)] = scale * beta;
            h[(kept + j, kept + j + 1)] = scale * beta;
        }
        h
    }

    /// Eigenvalues and last components against faer's full eigensolver of the same matrix.
    /// A last component is unique up to sign only for a simple eigenvalue, and an eigenvector
    /// is perturbed by about `ε ‖H‖ / gap` by rounding, so the squares are compared summed over
    /// clusters of eigenvalues closer than `10⁻⁶ ‖H‖`, to `10⁻⁹`.
    fn agrees_with_full_solver(h: &Mat<f64>, kept: usize) -> Result<(), TestCaseError> {
        let m = h.nrows();
        let (values, last) = ReducedHead::new(h.as_ref(), kept)
            .projected_values(h.as_ref())
            .unwrap();
        let (reference, vectors) = real_symmetric_eigen(h.as_ref()).unwrap();
        let norm = reference
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        let mut start = 0;
        while start < m {
            let mut end = start + 1;
            while end < m && reference[end] - reference[end - 1] <= 1e-6 * norm {
                end += 1;
            }
            for i in start..end {
                prop_assert!(
                    (values[i] - reference[i]).abs() <= 1e-12 * norm,
                    "value {i}: {} against {}",
                    values[i],
                    reference[i]
                );
            }
            let ours: f64 = last[start..end].iter().map(|z| z * z).sum();
            let theirs: f64 = (start..end).map(|i| vectors[(m - 1, i)].powi(2)).sum();
            prop_assert!(
                (ours - theirs).abs() <= 1e-9,
                "cluster {start}..{end}: {ours} against {theirs}"
            );
            start = end;
        }
        Ok(())
    }

    proptest! {
        #[test]
        fn projected_values_agree_with_a_full_eigensolver(
            thetas in prop::collection::vec(-10.0..10.0f64, 0..40),
            couplings in prop::collection::vec(-1.0..1.0f64, 40),
            tail in prop::collection::vec(-10.0..10.0f64, 1..40),
            betas in prop::collection::vec(0.0..3.0f64, 40),
        ) {
            let h = projected(&thetas, &couplings, &tail, &betas, 1.0);
            agrees_with_full_solver(&h, thetas.len())?;
        }

        /// Kept Ritz values that are copies of one value (a multiple eigenvalue the restart
        /// kept several vectors of), at any scale the scaling must bring into range.
        #[test]
        fn repeated_kept_values_at_extreme_scales(
            copies in 2usize..12,
            couplings in prop::collection::vec(-1.0..1.0f64, 12),
            tail in prop::collection::vec(-1.0..1.0f64, 1..20),
            betas in prop::collection::vec(0.0..1.0f64, 20),
            scale in prop::sample::select(vec![1.0, 1e-200, 1e200]),
        ) {
            let thetas = vec![0.5; copies];
            let h = projected(&thetas, &couplings, &tail, &betas, scale);
            let (values, _) = ReducedHead::new(h.as_ref(), copies).projected_values(h.as_ref()).unwrap();
            let unscaled = projected(&thetas, &couplings, &tail, &betas, 1.0);
            agrees_with_full_solver(&unscaled, copies)?;
            let (reference, _) = ReducedHead::new(unscaled.as_ref(), copies)
                .projected_values(unscaled.as_ref())
                .unwrap();
            for (v, r) in values.iter().zip(&reference) {
                prop_assert!((v / scale - r).abs() <= 1e-13, "{v:e} / {scale:e} against {r}");
            }
        }
    }
}
