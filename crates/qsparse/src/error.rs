//! Typed errors of the sparse layer. Each names the offending element.

use thiserror::Error;

/// Errors from assembling or combining sparse matrices.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SparseError {
    /// An entry's index lies outside the matrix.
    #[error("entry ({row}, {col}) is outside the {nrows}×{ncols} matrix")]
    IndexOutOfBounds {
        /// Row of the entry.
        row: usize,
        /// Column of the entry.
        col: usize,
        /// Number of rows of the matrix.
        nrows: usize,
        /// Number of columns of the matrix.
        ncols: usize,
    },
    /// An entry has a NaN or infinite component.
    #[error("entry ({row}, {col}) is not finite")]
    NonFinite {
        /// Row of the entry.
        row: usize,
        /// Column of the entry.
        col: usize,
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
    /// Compressed storage given by the caller is malformed.
    #[error("invalid compressed storage: {0}")]
    InvalidStorage(&'static str),
}

/// Errors from the sparse Cholesky factorisation.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CholeskyError {
    /// The matrix is not square.
    #[error("matrix is {nrows}×{ncols}, not square")]
    NotSquare {
        /// Rows.
        nrows: usize,
        /// Columns.
        ncols: usize,
    },
    /// A pivot was not positive (or not finite): the matrix is not Hermitian positive definite.
    #[error(
        "matrix is not positive definite: pivot of row/column {index} (original numbering) is {pivot:e}"
    )]
    NotPositiveDefinite {
        /// The failing row/column in the caller's numbering.
        index: usize,
        /// The real value the pivot's square root would have been taken of.
        pivot: f64,
    },
    /// An input value is NaN or infinite.
    #[error("entry ({row}, {col}) is not finite")]
    NonFinite {
        /// Row of the entry.
        row: usize,
        /// Column of the entry.
        col: usize,
    },
    /// A refactorisation was given a matrix whose pattern differs from the analysed one.
    #[error("the sparsity pattern differs from the one the symbolic analysis was done for")]
    PatternMismatch,
    /// A right-hand side has the wrong length.
    #[error("right-hand side has {found} rows, expected {expected}")]
    RhsDimension {
        /// Expected rows.
        expected: usize,
        /// Found rows.
        found: usize,
    },
    /// faer's part of the symbolic analysis (the AMD ordering, the elimination tree and
    /// supernodes) failed: out of memory for a factor this large, or more factor entries than
    /// its index type can count.
    #[error(
        "symbolic analysis failed in {stage}: {source}; the factor of this matrix does not fit (a smaller problem, or more memory)"
    )]
    Symbolic {
        /// The step that failed.
        stage: SymbolicStage,
        /// faer's error.
        #[source]
        source: faer::sparse::FaerError,
    },
}

/// A step of the symbolic analysis done by faer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum SymbolicStage {
    /// The approximate-minimum-degree fill-reducing ordering.
    #[error("the AMD ordering")]
    AmdOrdering,
    /// The elimination tree, column counts and supernodes of the factor.
    #[error("the supernodal structure")]
    Supernodes,
}

#[cfg(test)]
mod tests {
    use std::error::Error;

    use faer::sparse::FaerError;

    use super::{CholeskyError, SymbolicStage};

    #[test]
    fn symbolic_failure_keeps_faer_error_as_its_source() {
        let e = CholeskyError::Symbolic {
            stage: SymbolicStage::AmdOrdering,
            source: FaerError::OutOfMemory,
        };
        let source = e.source().expect("a source");
        assert_eq!(
            source.downcast_ref::<FaerError>(),
            Some(&FaerError::OutOfMemory)
        );
        let message = e.to_string();
        assert!(message.contains("the AMD ordering"), "{message}");
        assert!(
            message.contains(&FaerError::OutOfMemory.to_string()),
            "{message}"
        );
    }
}
