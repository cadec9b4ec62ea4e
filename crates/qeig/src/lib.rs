//! # qeig
//!
//! Hermitian eigensolvers generic over [`qscalar::Scalar`] (`f64`, `Complex<f64>`,
//! `Quat<f64>`), one implementation for all three:
//!
//! * [`Pencil`]: the `k` extreme eigenpairs of a Hermitian-definite pencil `K x = μ S x`
//!   (`S` Hermitian positive definite) — largest `|μ|` (both ends at once), largest or smallest
//!   — by a thick-restart Lanczos ([`lanczos`]) on `C⁻¹ K C⁻ᴴ` with `S = C Cᴴ`, behind three
//!   [`Backend`]s: [`Native`] (the matrices as given, native Cholesky), [`RealBlock`] (4n×4n
//!   real embedding, faer's Cholesky) and [`ComplexAdjoint`] (2n×2n complex adjoint, faer's
//!   Cholesky), which all return one pair per quaternionic eigenvalue with its multiplicity;
//! * [`hermitian_eigs`]: the same iteration on any [`HermitianOperator`];
//! * [`dense`]: all eigenpairs of small dense Hermitian matrices and pencils.
//!
//! Conventions (docs/ARCHITECTURE.md, "Conventions"): vectors are a right module,
//! `⟨x, y⟩ = Σ conj(xᵢ) yᵢ`, eigen-equations read `A x = x λ` with real `λ` (for a pencil,
//! `K x = μ S x`), Gram–Schmidt coefficients multiply on the right. Pencil eigenvectors are
//! `S`-orthonormal.
//!
//! **Multiplicities.** A single Krylov sequence contains one direction per eigenspace. The
//! iteration runs in *rounds*: each round is a thick-restart Lanczos run from a fresh seeded
//! random vector, within the constraints and `S`-orthogonal to every pair locked so far; a
//! round ends once `k` pairs are locked and the remaining extreme Ritz values are known to lie
//! outside the window, and the run ends after a round that found nothing better than the
//! current `k`-th pair. An eigenvalue of multiplicity `m` is thus found `m` times after at
//! most `m + 1` rounds (see [`lanczos`]).
//!
//! **Accuracy.** A pair is accepted when its true relative residual is below the tolerance,
//! or when its Lanczos estimate is at the rounding level of the operator (`≤ 64 eps ‖A‖`):
//! then no further step can improve it (ill-conditioned `S`, coupling to locked pairs), and the
//! reported residual is the attainable one (see [`lanczos`]).
//!
//! **Non-convergence** returns [`EigError::NotConverged`] with the pairs that did converge and
//! the [`Statistics`].
//!
//! **Parallelism.** Two threads where the work is long enough and a second core is free
//! ([`qsparse::threads::second_thread_allowed`]: not from a rayon worker, so a parallel batch
//! of problems does not oversubscribe): the native backend's triangular solves
//! ([`qsparse::SolveThreads`]) and the Gram–Schmidt passes over long vectors (rows split,
//! partial coefficients exchanged per column and added in a fixed order), the Ritz vectors of
//! a restart (rows split) and large sparse products. The second thread is one helper that
//! waits between pieces of work ([`qsparse::threads::join`]); faer runs with `Par::Seq`.
//! Results do not depend on timing. [`threads::set_second_thread_allowed`]`(false)` keeps
//! everything on the calling thread.

mod backend;
mod basis;
mod constraints;
pub mod dense;
mod error;
pub mod lanczos;
mod memory;
mod pencil;
mod result;
mod scaling;

pub use backend::{
    Backend, ComplexAdjoint, ComplexAdjointOperator, Factor, FactoredPencil, FaerCholesky, MatVec,
    Native, NativeFactor, NativeOperator, PencilOperator, RealBlock, RealBlockOperator,
    VECTORS_PER_PASS,
};
pub use error::{BasisTooLarge, DenseEigenError, EigError, EmbeddedFactorizationError};
pub use lanczos::{HermitianOperator, LanczosOptions, Which, hermitian_eigs};
pub use pencil::{Pencil, relative_cluster_width};
/// When the eigensolver may use a second thread (re-exported from `qsparse`).
pub use qsparse::threads;
pub use result::{Eigen, Progress, ProgressCallback, Statistics};
