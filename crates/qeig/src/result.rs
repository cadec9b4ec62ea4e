//! Results and statistics of an eigensolve.

use std::ops::ControlFlow;
use std::time::Duration;

/// Eigenpairs of a Hermitian-definite pencil, `K xᵢ = μᵢ S xᵢ` (`μᵢ` real), with statistics.
///
/// * `values[i]` is `μᵢ`, ordered by the selection rule: largest magnitude first
///   ([`crate::Which::LargestMagnitude`]), largest first ([`crate::Which::LargestAlgebraic`]),
///   smallest first ([`crate::Which::SmallestAlgebraic`]).
/// * `vectors[i]` is `xᵢ`, `S`-orthonormal: `xᵢᴴ S xⱼ = δᵢⱼ` (quaternionic inner product
///   `⟨x, y⟩ = Σ conj(xₗ) yₗ`). A quaternionic eigenvector is defined up to a unit scalar on the
///   right, `xᵢ q` with `|q| = 1`; no phase is imposed.
/// * `residuals[i]` is the relative residual `‖K xᵢ − μᵢ S xᵢ‖ / (|μᵢ| ‖S xᵢ‖)` (Euclidean
///   norms), recomputed from the returned pair. Under constraints `cᴴ x = 0`
///   ([`crate::Pencil::with_constraints`]) the residual of a pair of the constrained pencil
///   lies in the span of the `c` wherever it is exact, so only its component outside that span
///   counts: `‖Π (K xᵢ − μᵢ S xᵢ)‖`, `Π r = r − C (CᴴC)⁻¹ Cᴴ r`.
#[derive(Debug, Clone)]
pub struct Eigen<T> {
    /// Eigenvalues `μᵢ`.
    pub values: Vec<f64>,
    /// Eigenvectors `xᵢ`, `S`-orthonormal.
    pub vectors: Vec<Vec<T>>,
    /// Relative residuals.
    pub residuals: Vec<f64>,
    /// Counts and timings of the run.
    pub statistics: Statistics,
}

/// Counts and timings of one eigensolve.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Statistics {
    /// Lanczos steps (each one operator application plus orthogonalisation).
    pub iterations: usize,
    /// Thick restarts (Rayleigh–Ritz on the projected matrix followed by locking).
    pub restarts: usize,
    /// Rounds: Krylov sequences started from a fresh random vector (the first one, and each
    /// search for missing copies of multiple eigenvalues; see the crate documentation).
    pub rounds: usize,
    /// Applications of the operator `C⁻¹ K C⁻ᴴ`.
    pub operator_applications: usize,
    /// Triangular solves with `C` or `Cᴴ` (two per operator application, plus one per
    /// eigenvector mapped back and per residual checked).
    pub solves: usize,
    /// Pairs locked by the iteration (in the iteration space: for the embedded backends
    /// every quaternionic pair is found up to 4 or 2 times).
    pub locked: usize,
    /// Symbolic analysis and numeric factorisation of `S`.
    pub factorization_time: Duration,
    /// Time in triangular solves.
    pub solve_time: Duration,
    /// Time in Gram–Schmidt orthogonalisation and basis updates at restarts.
    pub orthogonalization_time: Duration,
    /// Basis vectors read by the Gram–Schmidt passes: the orthogonalisation's memory traffic
    /// is this times the size of a vector. A measure of its work that, unlike its time, does
    /// not depend on the load of the machine.
    pub basis_columns_read: usize,
    /// Bytes of the Krylov basis at its largest (reserved before the iteration, see
    /// [`crate::LanczosOptions::memory_limit`]).
    pub basis_bytes: usize,
    /// Bytes of the stored values of the Cholesky factor of `S`.
    pub factor_bytes: usize,
    /// Wall-clock time of the whole solve.
    pub total_time: Duration,
}

impl std::ops::AddAssign<&Statistics> for Statistics {
    /// Adds the counts and times of another solve (for results assembled from several).
    fn add_assign(&mut self, run: &Statistics) {
        self.iterations += run.iterations;
        self.restarts += run.restarts;
        self.rounds += run.rounds;
        self.operator_applications += run.operator_applications;
        self.solves += run.solves;
        self.locked += run.locked;
        self.factorization_time += run.factorization_time;
        self.solve_time += run.solve_time;
        self.orthogonalization_time += run.orthogonalization_time;
        self.basis_columns_read += run.basis_columns_read;
        // Memory is a peak, not a total: solves run one after the other.
        self.basis_bytes = self.basis_bytes.max(run.basis_bytes);
        self.factor_bytes = self.factor_bytes.max(run.factor_bytes);
        self.total_time += run.total_time;
    }
}

/// What a progress callback sees: the state after a restart, or between restarts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Current round (1-based).
    pub round: usize,
    /// Restarts so far.
    pub restarts: usize,
    /// Operator applications so far.
    pub operator_applications: usize,
    /// Pairs locked so far (iteration space).
    pub locked: usize,
    /// Pairs wanted (iteration space).
    pub wanted: usize,
}

/// The callback of the `*_with_progress` solvers, called after every restart and, between
/// restarts, after the first step at least 0.1 s after its last call. Returning
/// [`ControlFlow::Break`] stops the solve at once: it then reports
/// [`crate::EigError::NotConverged`] with the pairs converged so far (how a caller cancels a
/// long run, for example on Ctrl-C).
pub type ProgressCallback<'a> = &'a mut dyn FnMut(&Progress) -> ControlFlow<()>;
