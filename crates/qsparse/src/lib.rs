//! # qsparse
//!
//! Sparse matrices generic over [`qscalar::Scalar`] (real, complex, quaternion), with
//! triplet assembly, CSC storage, products, the real-block and complex-adjoint embeddings into
//! faer matrices, and a native supernodal sparse Cholesky `A = Pᵀ L Lᴴ P`.
//! With the `proptest-support` feature (off by default), `strategies` exports proptest
//! strategies for random sparse matrices, Hermitian positive-definite matrices and vectors.
//!
//! Conventions (docs/ARCHITECTURE.md, "Conventions"): matrices act by left multiplication,
//! `(A x)ᵢ = Σⱼ Aᵢⱼ xⱼ`; the adjoint is the conjugate transpose, `(Aᴴ)ᵢⱼ = conj(Aⱼᵢ)`; vectors are
//! plain slices.

mod cholesky;
mod csc;
mod dense;
mod disjoint_sets;
pub mod embedding;
mod error;
mod gram;
mod ops;
mod product;
mod simd;
mod sparse_vector;
#[cfg(feature = "proptest-support")]
pub mod strategies;
pub mod threads;
mod triplet;
pub mod vector;

pub use cholesky::{
    CholeskyStats, FillOrdering, SolveThreads, SparseCholesky, SparseSolveWorkspace,
    SymbolicCholesky, ordering,
};
pub use csc::SparseMatrix;
pub use dense::DenseMatrix;
pub use disjoint_sets::DisjointSets;
pub use error::{CholeskyError, SparseError, SymbolicStage};
pub use gram::Gram;
pub use ops::HermitianDefect;
pub use sparse_vector::SparseVector;
pub use triplet::TripletMatrix;
