//! Typed errors of the eigensolvers. Nothing in this crate panics on user input.

use qsparse::CholeskyError;
use thiserror::Error;

use crate::Eigen;

/// Errors of the sparse and dense eigensolvers.
#[derive(Debug, Clone, Error)]
#[non_exhaustive]
pub enum EigError<T> {
    /// A matrix that must be square is not.
    #[error("{which} is {nrows}×{ncols}, not square")]
    NotSquare {
        /// Which operand (`"K"`, `"S"`, `"A"`).
        which: &'static str,
        /// Rows.
        nrows: usize,
        /// Columns.
        ncols: usize,
    },
    /// Operand shapes do not fit together.
    #[error("dimension mismatch: expected {expected}, found {found} ({context})")]
    DimensionMismatch {
        /// What was expected.
        expected: usize,
        /// What was found.
        found: usize,
        /// Which operand.
        context: &'static str,
    },
    /// The number of wanted eigenpairs is zero or exceeds the dimension left by the constraints.
    #[error("cannot compute {k} eigenpairs: between 1 and {available} are available")]
    InvalidCount {
        /// Requested number of pairs.
        k: usize,
        /// Dimension minus the number of constraint vectors.
        available: usize,
    },
    /// An option is out of range (the message names it).
    #[error("invalid option: {0}")]
    InvalidOption(&'static str),
    /// An input value is NaN or infinite.
    #[error("non-finite input: {0}")]
    NonFinite(&'static str),
    /// The native Cholesky factorisation of `S` failed (for example `S` is not positive definite).
    #[error("factorisation of S failed: {0}")]
    Factorization(#[from] CholeskyError),
    /// faer's Cholesky of the embedded `S` failed (embedded backends), or a dense `S` is not
    /// positive definite.
    #[error("factorisation of S failed: {0}")]
    EmbeddedFactorization(String),
    /// faer's dense self-adjoint eigensolver reported a failure.
    #[error("dense eigensolver failed: {0}")]
    DenseEigen(String),
    /// The iteration stopped (restart, operator-application or dimension limit) before the
    /// wanted pairs converged. `partial` holds the pairs that did converge, in the same
    /// order and normalisation as a successful result, and the statistics of the run.
    #[error("Lanczos did not converge: {} of {wanted} pairs converged", partial.values.len())]
    NotConverged {
        /// Number of pairs asked for.
        wanted: usize,
        /// Converged pairs and statistics.
        partial: Box<Eigen<T>>,
    },
}
