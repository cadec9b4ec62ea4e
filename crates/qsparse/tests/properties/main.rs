//! Property tests of qsparse against independent truth: dense products, algebraic identities,
//! faer's own sparse Cholesky, and dense solves. One test binary, so the helpers in `common` are
//! shared.

mod cholesky;
mod common;
mod embedding;
mod errors;
mod ops;
mod ordering;
mod vector;
