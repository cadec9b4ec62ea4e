//! Property tests of qsparse against independent truth: dense products, algebraic identities,
//! and faer's own sparse Cholesky. One test binary, so the helpers in `common` are shared.

mod cholesky;
mod common;
mod embedding;
mod errors;
mod ops;
mod vector;
