//! Typed errors of the eigensolvers. Nothing in this crate panics on user input.

use qsparse::CholeskyError;
use thiserror::Error;

use crate::Eigen;
pub use crate::memory::BasisTooLarge;

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
    /// A matrix that must be Hermitian is not: its entries `(row, col)` and `(col, row)` are
    /// not conjugates, beyond [`crate::Pencil::HERMITIAN_TOLERANCE`] times its largest entry.
    /// Pass the whole matrix (both triangles), or symmetrise it as `(A + Aᴴ) / 2`.
    #[error(
        "{which} is not Hermitian: entries ({row}, {col}) and ({col}, {row}) differ from each \
         other's conjugate by {defect:e}, against a largest entry of {largest:e}; pass both \
         triangles of a Hermitian matrix, or symmetrise it as (A + Aᴴ) / 2"
    )]
    NotHermitian {
        /// Which operand (`"K"`, `"S"`).
        which: &'static str,
        /// Row of the entry furthest from Hermitian.
        row: usize,
        /// Its column.
        col: usize,
        /// `|A(row, col) − conj(A(col, row))|`.
        defect: f64,
        /// The largest `|Aᵢⱼ|`.
        largest: f64,
    },
    /// An input value is NaN or infinite.
    #[error("non-finite input: {0}")]
    NonFinite(&'static str),
    /// The native Cholesky factorisation of `S` failed (for example `S` is not positive definite).
    #[error("factorisation of S failed: {0}")]
    Factorization(#[from] CholeskyError),
    /// faer's Cholesky of the embedded `S` failed (embedded backends), or a dense `S` is not
    /// positive definite.
    #[error("factorisation of S failed: {0}")]
    EmbeddedFactorization(#[source] EmbeddedFactorizationError),
    /// faer's dense self-adjoint eigensolver reported a failure.
    #[error("dense eigensolver failed: {0}")]
    DenseEigen(#[from] DenseEigenError),
    /// The Krylov basis would not fit in memory; nothing was allocated for it.
    #[error(transparent)]
    BasisTooLarge(#[from] BasisTooLarge),
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

/// Why a factorisation of `S` by faer (the embedded backends, a dense pencil) failed.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum EmbeddedFactorizationError {
    /// A pivot was not positive: `S` is not (numerically) positive definite. The index is the
    /// pivot's position in faer's elimination order of the embedded matrix.
    #[error("S is not positive definite (pivot {index} of the embedded factorisation)")]
    NotPositiveDefinite {
        /// Pivot position.
        index: usize,
    },
    /// A dense `S` has an eigenvalue that is not positive (relative to its largest, `1e−14`).
    #[error("S is not positive definite: its eigenvalue number {index} is {value:e}")]
    NonPositiveEigenvalue {
        /// Position of the eigenvalue in ascending order.
        index: usize,
        /// The eigenvalue.
        value: f64,
    },
    /// The factor's pattern does not fit in faer's index type.
    #[error("the factor is too large for faer's index type")]
    IndexOverflow,
    /// faer could not allocate the factor.
    #[error("out of memory while factorising")]
    OutOfMemory,
}

impl From<faer::sparse::FaerError> for EmbeddedFactorizationError {
    fn from(e: faer::sparse::FaerError) -> Self {
        match e {
            faer::sparse::FaerError::IndexOverflow => Self::IndexOverflow,
            _ => Self::OutOfMemory,
        }
    }
}

impl From<faer::linalg::cholesky::llt::factor::LltError> for EmbeddedFactorizationError {
    fn from(e: faer::linalg::cholesky::llt::factor::LltError) -> Self {
        match e {
            faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
                Self::NotPositiveDefinite { index }
            }
        }
    }
}

/// faer's dense self-adjoint eigensolver (of the projected matrix, or of a dense problem)
/// did not converge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[error("the dense self-adjoint eigensolver did not converge on a matrix of order {order}")]
pub struct DenseEigenError {
    /// Order of the matrix.
    pub order: usize,
}
