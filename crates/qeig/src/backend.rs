//! Backends: how the pencil `K x = μ S x` is represented and factorised.
//!
//! Every backend factorises `S = C Cᴴ` and hands the Lanczos core the Hermitian operator
//! `A = C⁻¹ K C⁻ᴴ` on its own vector space; an eigenvector `y` of `A` maps back to
//! `x = C⁻ᴴ y`, and `S`-orthogonality to a vector `d` is plain orthogonality to `Cᴴ d`.
//!
//! * [`Native`]: the matrices as they are (quaternion, complex or real), the native
//!   supernodal Cholesky of `qsparse` (`C = Pᵀ L`).
//! * [`RealBlock`]: the `REAL_DIM n × REAL_DIM n` real matrices of left-multiplication blocks
//!   (docs/MATH.md, "The real-block representation"), faer's supernodal Cholesky (`C = Pᵀ L` again,
//!   through faer's `L` and `Lᴴ` half-solves). Each quaternionic eigenvalue appears 4 times.
//! * [`ComplexAdjoint`]: the `COMPLEX_DIM n × COMPLEX_DIM n` complex adjoint, faer's
//!   Cholesky. Each quaternionic eigenvalue appears twice.
//!
//! The embedded backends run the same Lanczos code on `f64` / `Complex<f64>` vectors; the
//! pencil solver folds their copies back to one quaternionic pair per eigenvalue.

use std::time::{Duration, Instant};

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::SparseColMat;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky, supernodal::SupernodalLltRef,
};
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::traits::ComplexField;
use faer::{Accum, Conj, MatMut, MatRef, Par, Side, c64};
use qscalar::Scalar;
use qsparse::embedding::{complex_adjoint_vector, from_complex_adjoint_vector};
use qsparse::{SparseCholesky, SparseMatrix, SparseSolveWorkspace, SparseVector, vector};

use crate::error::EmbeddedFactorizationError;
use crate::{EigError, HermitianOperator};

/// A representation of Hermitian-definite pencils over `T`.
pub trait Backend<T: Scalar<Real = f64>> {
    /// Scalar field of the iteration space.
    type Field: Scalar<Real = f64>;
    /// The factorised operator `C⁻¹ K C⁻ᴴ`.
    type Operator: PencilOperator<Self::Field>;
    /// How many times each eigenvalue of the `T` pencil occurs in the iteration space.
    const COPIES: usize;
    /// Short label (`"native"`, `"real-block"`, `"complex-adjoint"`).
    fn name(&self) -> &'static str;
    /// Builds the representation of `K` and `S` and factorises `S`.
    fn prepare(
        &self,
        k: &SparseMatrix<T>,
        s: &SparseMatrix<T>,
    ) -> Result<Self::Operator, EigError<T>>;
    /// The image of a vector of `Tⁿ` in the iteration space.
    fn embed(&self, x: &[T]) -> Vec<Self::Field>;
    /// [`Backend::embed`] for a sparse vector of `Tⁿ` (through the dense one unless the
    /// backend keeps sparsity).
    fn embed_sparse(&self, x: &SparseVector<T>, n: usize) -> SparseVector<Self::Field> {
        SparseVector::from_dense(&self.embed(&x.to_dense(n)))
    }
    /// Vectors of `Tⁿ` spanning (over `T`, with the other results) what `y` represents:
    /// the inverse of [`Backend::embed`], and for real `T` in the complex adjoint, the real
    /// and imaginary parts (both are eigenvectors when `y` is one).
    fn extract(&self, y: &[Self::Field]) -> Vec<Vec<T>>;
}

/// The operator `A = C⁻¹ K C⁻ᴴ` of a pencil with `S = C Cᴴ`, and the maps to and from the
/// pencil's vectors.
pub trait PencilOperator<V>: HermitianOperator<V> {
    /// `X ← C⁻ᴴ Y` for the columns of `ys` (column after column): the pencil eigenvectors
    /// `x = C⁻ᴴ y` of eigenvectors `y` of `A` (`xᴴ S x = yᴴ y`).
    fn eigenvectors_in_place(&mut self, ys: &mut [V]);
    /// `C⁻¹ c`: the constraint `cᴴ x = 0` on pencil vectors is orthogonality to this vector
    /// in the iteration space (`cᴴ x = cᴴ C⁻ᴴ y = (C⁻¹ c)ᴴ y`). Sparse: the constraint of one
    /// piece of a mesh stays on that piece.
    fn constraint_direction(&mut self, c: &SparseVector<V>) -> SparseVector<V>;
    /// Replaces `K` by `K − Σ w u uᴴ` over the given `(u, w)` (sparse vectors of the
    /// iteration field, already embedded).
    fn subtract_low_rank(&mut self, terms: Vec<(SparseVector<V>, f64)>);
}

/// Vectors that share one read of the factor in the many-vector half-solves
/// ([`Factor::lower_many`]): a supernode's block is reused from cache for all of them, which
/// cut the time per vector of the two half-solves by 2.2× at 41k and 1.5× at 164k unknowns
/// (docs/PERFORMANCE.md), while eight quaternion vectors of a 40k-vertex mesh are only 11 MB
/// of work space. (Sparse
/// products gain nothing from the same sharing: their quaternion multiply-adds, not the
/// matrix's memory traffic, bound them.)
pub const VECTORS_PER_PASS: usize = 8;

/// Half-solves with the Cholesky factor `C` of `S = C Cᴴ`.
pub trait Factor<V> {
    /// `x ← C⁻¹ x`.
    fn lower(&mut self, x: &mut [V]);
    /// `x ← C⁻ᴴ x`.
    fn upper(&mut self, x: &mut [V]);
    /// `X ← C⁻¹ X` for the `ncols` columns of `x` (column after column); factors that read
    /// their values once for all columns override it.
    fn lower_many(&mut self, x: &mut [V], ncols: usize) {
        let n = x.len() / ncols.max(1);
        x.chunks_exact_mut(n.max(1)).for_each(|c| self.lower(c));
    }
    /// `X ← C⁻ᴴ X`, as [`Factor::lower_many`].
    fn upper_many(&mut self, x: &mut [V], ncols: usize) {
        let n = x.len() / ncols.max(1);
        x.chunks_exact_mut(n.max(1)).for_each(|c| self.upper(c));
    }
    /// `C⁻¹ b` for a sparse `b` of dimension `n`; factors that can touch only what `b`
    /// reaches override the dense solve.
    fn lower_sparse(&mut self, b: &SparseVector<V>, n: usize) -> SparseVector<V>
    where
        V: Scalar,
    {
        let mut x = b.to_dense(n);
        self.lower(&mut x);
        SparseVector::from_dense(&x)
    }
    /// Bytes of the stored factor values.
    fn bytes(&self) -> usize;
}

/// A matrix–vector product `y = M x`.
pub trait MatVec<V> {
    /// `y = M x` (lengths are checked by the caller).
    fn mul(&self, x: &[V], y: &mut [V]);
}

/// `C⁻¹ K C⁻ᴴ` for a factor `F` of `S` and matrices of type `M`.
#[derive(Debug)]
pub struct FactoredPencil<V, F, M> {
    factor: F,
    k: M,
    low_rank: Vec<(SparseVector<V>, f64)>,
    s: M,
    work: Vec<V>,
    solves: usize,
    solve_time: Duration,
}

impl<V: Scalar<Real = f64>, F: Factor<V>, M: MatVec<V>> FactoredPencil<V, F, M> {
    fn new(factor: F, k: M, s: M, n: usize) -> Self {
        Self {
            factor,
            k,
            low_rank: Vec::new(),
            s,
            work: vec![V::zero(); n],
            solves: 0,
            solve_time: Duration::ZERO,
        }
    }

    /// `y = (K − Σ w u uᴴ) x`.
    fn k_mul(&self, x: &[V], y: &mut [V]) {
        self.k.mul(x, y);
        for (u, w) in &self.low_rank {
            u.add_to(y, u.inner(x) * V::from_real(-w));
        }
    }

    /// `X ← C⁻¹ X` (`lower`) or `X ← C⁻ᴴ X` for the `ncols` columns of `x`, timed and counted
    /// (one solve per column).
    fn timed(&mut self, x: &mut [V], ncols: usize, lower: bool) {
        self.counted(ncols, |factor| {
            if lower {
                factor.lower_many(x, ncols);
            } else {
                factor.upper_many(x, ncols);
            }
        });
    }

    /// `solve(factor)`, timed and counted as `solves` solves.
    fn counted<R>(&mut self, solves: usize, solve: impl FnOnce(&mut F) -> R) -> R {
        let t = Instant::now();
        let result = solve(&mut self.factor);
        self.solve_time += t.elapsed();
        self.solves += solves;
        result
    }
}

impl<V: Scalar<Real = f64>, F: Factor<V>, M: MatVec<V>> HermitianOperator<V>
    for FactoredPencil<V, F, M>
{
    fn dim(&self) -> usize {
        self.work.len()
    }

    fn apply(&mut self, x: &[V], y: &mut [V]) {
        let mut t = std::mem::take(&mut self.work);
        t.copy_from_slice(x);
        self.timed(&mut t, 1, false);
        self.k_mul(&t, y);
        self.timed(y, 1, true);
        self.work = t;
    }

    /// `‖K x − θ S x‖ / (|θ| ‖S x‖)` with `x = C⁻ᴴ y` (Euclidean norms, which the real-block
    /// and complex-adjoint embeddings preserve).
    fn relative_residual(&mut self, y: &[V], theta: f64) -> f64 {
        self.relative_residuals(y, &[theta])[0]
    }

    /// [`HermitianOperator::relative_residual`] of [`VECTORS_PER_PASS`] pairs at a time, each
    /// half-solve reading the factor once for all of them.
    fn relative_residuals(&mut self, ys: &[V], thetas: &[f64]) -> Vec<f64> {
        let n = self.dim();
        let mut residuals = Vec::with_capacity(thetas.len());
        for (ys, thetas) in ys
            .chunks(VECTORS_PER_PASS * n)
            .zip(thetas.chunks(VECTORS_PER_PASS))
        {
            let mut x = ys.to_vec();
            self.eigenvectors_in_place(&mut x);
            let (mut kx, mut sx) = (vec![V::zero(); n], vec![V::zero(); n]);
            for (x, &theta) in x.chunks_exact(n).zip(thetas) {
                self.k_mul(x, &mut kx);
                self.s.mul(x, &mut sx);
                let s_norm = vector::norm(&sx);
                vector::axpy_real(&mut kx, &sx, -theta);
                residuals.push(vector::norm(&kx) / (theta.abs() * s_norm));
            }
        }
        residuals
    }

    fn solve_statistics(&self) -> (usize, Duration) {
        (self.solves, self.solve_time)
    }

    fn factor_bytes(&self) -> usize {
        self.factor.bytes()
    }
}

impl<V: Scalar<Real = f64>, F: Factor<V>, M: MatVec<V>> PencilOperator<V>
    for FactoredPencil<V, F, M>
{
    fn eigenvectors_in_place(&mut self, ys: &mut [V]) {
        let ncols = ys.len() / self.dim();
        self.timed(ys, ncols, false);
    }

    fn constraint_direction(&mut self, c: &SparseVector<V>) -> SparseVector<V> {
        let n = self.dim();
        self.counted(1, |factor| factor.lower_sparse(c, n))
    }

    fn subtract_low_rank(&mut self, terms: Vec<(SparseVector<V>, f64)>) {
        self.low_rank = terms;
    }
}

/// The native Cholesky factor with the workspaces of its solves.
#[derive(Debug)]
pub struct NativeFactor<T> {
    cholesky: SparseCholesky<T>,
    work: Vec<T>,
    /// Built at the first sparse solve.
    sparse_work: Option<SparseSolveWorkspace<T>>,
}

impl<T> NativeFactor<T> {
    fn new(cholesky: SparseCholesky<T>) -> Self {
        Self {
            cholesky,
            work: Vec::new(),
            sparse_work: None,
        }
    }
}

impl<T: Scalar<Real = f64>> Factor<T> for NativeFactor<T> {
    fn lower(&mut self, x: &mut [T]) {
        self.cholesky
            .solve_lower_in_place_with(x, &mut self.work)
            .expect("vector length equals the factor dimension");
    }

    fn upper(&mut self, x: &mut [T]) {
        self.cholesky
            .solve_upper_in_place_with(x, &mut self.work)
            .expect("vector length equals the factor dimension");
    }

    fn lower_many(&mut self, x: &mut [T], ncols: usize) {
        self.cholesky
            .solve_lower_many_in_place_with(x, ncols, &mut self.work)
            .expect("vector lengths equal the factor dimension");
    }

    fn upper_many(&mut self, x: &mut [T], ncols: usize) {
        self.cholesky
            .solve_upper_many_in_place_with(x, ncols, &mut self.work)
            .expect("vector lengths equal the factor dimension");
    }

    fn lower_sparse(&mut self, b: &SparseVector<T>, _n: usize) -> SparseVector<T> {
        let work = (self.sparse_work).get_or_insert_with(|| self.cholesky.sparse_solve_workspace());
        self.cholesky
            .solve_lower_sparse(b, work)
            .expect("rows below the factor dimension")
    }

    fn bytes(&self) -> usize {
        self.cholesky.stats().factor_bytes
    }
}

impl<T: Scalar<Real = f64>> MatVec<T> for SparseMatrix<T> {
    /// `y = M x` as `Mᴴ x` (the pencil's matrices are Hermitian), gathered column by column:
    /// 1.4× faster than the scattered `mul_vec` on a 41k-vertex mesh (docs/PERFORMANCE.md).
    fn mul(&self, x: &[T], y: &mut [T]) {
        self.adjoint_mul_vec(x, y)
            .expect("vector lengths equal the matrix dimension");
    }
}

impl<E: ComplexField + Scalar<Real = f64>> MatVec<E> for SparseColMat<usize, E> {
    fn mul(&self, x: &[E], y: &mut [E]) {
        let n = x.len();
        sparse_dense_matmul(
            MatMut::from_column_major_slice_mut(y, n, 1),
            Accum::Replace,
            self.as_ref(),
            MatRef::from_column_major_slice(x, n, 1),
            E::from_real(1.0),
            Par::Seq,
        );
    }
}

/// faer's supernodal sparse Cholesky `P S Pᵀ = L Lᴴ` of an embedded `S`, with the half-solves
/// `C⁻¹ = L⁻¹ P` and `C⁻ᴴ = Pᵀ L⁻ᴴ` (`C = Pᵀ L`).
pub struct FaerCholesky<E> {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<E>,
    perm: Vec<usize>,
    permuted: Vec<E>,
    mem: MemBuffer,
}

impl<E> std::fmt::Debug for FaerCholesky<E> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FaerCholesky")
            .field("n", &self.perm.len())
            .field("factor_entries", &self.values.len())
            .finish()
    }
}

impl<E: ComplexField + Scalar<Real = f64>> FaerCholesky<E> {
    /// Symbolic analysis (AMD, forced supernodal) and numeric `LLᴴ` of `s` (lower triangle
    /// read), sequential.
    pub fn factorize(s: &SparseColMat<usize, E>) -> Result<Self, EmbeddedFactorizationError> {
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(s.symbolic(), Side::Lower, SymmetricOrdering::Amd, params)?;
        let mut values = vec![E::default(); symbolic.len_val()];
        let mut mem = MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<E>(Par::Seq, Default::default()),
        );
        symbolic.factorize_numeric_llt(
            &mut values,
            s.as_ref(),
            Side::Lower,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        )?;
        let n = s.nrows();
        let perm = match symbolic.perm() {
            Some(p) => p.arrays().0.to_vec(),
            None => (0..n).collect(),
        };
        Ok(Self {
            mem: MemBuffer::new(symbolic.solve_in_place_scratch::<E>(1, Par::Seq)),
            symbolic,
            values,
            perm,
            permuted: vec![E::default(); n],
        })
    }

    fn supernodal(&self) -> SupernodalLltRef<'_, usize, E> {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(sn) => SupernodalLltRef::new(sn, &self.values),
            SymbolicCholeskyRaw::Simplicial(_) => {
                unreachable!("the analysis forces the supernodal structure")
            }
        }
    }
}

impl<E: ComplexField + Scalar<Real = f64>> Factor<E> for FaerCholesky<E> {
    fn lower(&mut self, x: &mut [E]) {
        let n = x.len();
        let mut permuted = std::mem::take(&mut self.permuted);
        for (dst, &old) in permuted.iter_mut().zip(&self.perm) {
            *dst = x[old];
        }
        let mut mem = std::mem::replace(
            &mut self.mem,
            MemBuffer::new(faer::dyn_stack::StackReq::EMPTY),
        );
        self.supernodal().l_solve_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut permuted, n, 1),
            Par::Seq,
            MemStack::new(&mut mem),
        );
        self.mem = mem;
        x.copy_from_slice(&permuted);
        self.permuted = permuted;
    }

    fn upper(&mut self, x: &mut [E]) {
        let n = x.len();
        let mut mem = std::mem::replace(
            &mut self.mem,
            MemBuffer::new(faer::dyn_stack::StackReq::EMPTY),
        );
        self.supernodal().l_transpose_solve_with_conj(
            Conj::Yes,
            MatMut::from_column_major_slice_mut(x, n, 1),
            Par::Seq,
            MemStack::new(&mut mem),
        );
        self.mem = mem;
        let mut permuted = std::mem::take(&mut self.permuted);
        permuted.copy_from_slice(x);
        for (&v, &old) in permuted.iter().zip(&self.perm) {
            x[old] = v;
        }
        self.permuted = permuted;
    }

    fn bytes(&self) -> usize {
        self.values.len() * std::mem::size_of::<E>()
    }
}

/// The native representation: the matrices as given, `qsparse`'s supernodal Cholesky.
#[derive(Debug, Clone, Copy, Default)]
pub struct Native;

/// The real `REAL_DIM n` embedding with left-multiplication blocks, faer's Cholesky.
#[derive(Debug, Clone, Copy, Default)]
pub struct RealBlock;

/// The complex `COMPLEX_DIM n` adjoint embedding, faer's Cholesky.
#[derive(Debug, Clone, Copy, Default)]
pub struct ComplexAdjoint;

/// The operator of the [`Native`] backend.
pub type NativeOperator<T> = FactoredPencil<T, NativeFactor<T>, SparseMatrix<T>>;
/// The operator of the [`RealBlock`] backend.
pub type RealBlockOperator = FactoredPencil<f64, FaerCholesky<f64>, SparseColMat<usize, f64>>;
/// The operator of the [`ComplexAdjoint`] backend.
pub type ComplexAdjointOperator = FactoredPencil<c64, FaerCholesky<c64>, SparseColMat<usize, c64>>;

impl<T: Scalar<Real = f64>> Backend<T> for Native {
    type Field = T;
    type Operator = NativeOperator<T>;
    const COPIES: usize = 1;

    fn name(&self) -> &'static str {
        "native"
    }

    fn prepare(
        &self,
        k: &SparseMatrix<T>,
        s: &SparseMatrix<T>,
    ) -> Result<Self::Operator, EigError<T>> {
        let factor = NativeFactor::new(SparseCholesky::factorize(s)?);
        Ok(FactoredPencil::new(factor, k.clone(), s.clone(), s.nrows()))
    }

    fn embed(&self, x: &[T]) -> Vec<T> {
        x.to_vec()
    }

    fn embed_sparse(&self, x: &SparseVector<T>, _n: usize) -> SparseVector<T> {
        x.clone()
    }

    fn extract(&self, y: &[T]) -> Vec<Vec<T>> {
        vec![y.to_vec()]
    }
}

impl<T: Scalar<Real = f64>> Backend<T> for RealBlock {
    type Field = f64;
    type Operator = RealBlockOperator;
    const COPIES: usize = T::REAL_DIM;

    fn name(&self) -> &'static str {
        "real-block"
    }

    fn prepare(
        &self,
        k: &SparseMatrix<T>,
        s: &SparseMatrix<T>,
    ) -> Result<Self::Operator, EigError<T>> {
        let s_block = s.to_real_block();
        let factor = FaerCholesky::factorize(&s_block).map_err(EigError::EmbeddedFactorization)?;
        let n = s_block.nrows();
        Ok(FactoredPencil::new(factor, k.to_real_block(), s_block, n))
    }

    fn embed(&self, x: &[T]) -> Vec<f64> {
        T::as_reals(x).to_vec()
    }

    fn extract(&self, y: &[f64]) -> Vec<Vec<T>> {
        let mut x = vec![T::zero(); y.len() / T::REAL_DIM];
        T::as_reals_mut(&mut x).copy_from_slice(y);
        vec![x]
    }
}

impl<T: Scalar<Real = f64>> Backend<T> for ComplexAdjoint {
    type Field = c64;
    type Operator = ComplexAdjointOperator;
    const COPIES: usize = T::COMPLEX_DIM;

    fn name(&self) -> &'static str {
        "complex-adjoint"
    }

    fn prepare(
        &self,
        k: &SparseMatrix<T>,
        s: &SparseMatrix<T>,
    ) -> Result<Self::Operator, EigError<T>> {
        let s_adjoint = s.to_complex_adjoint();
        let factor =
            FaerCholesky::factorize(&s_adjoint).map_err(EigError::EmbeddedFactorization)?;
        let n = s_adjoint.nrows();
        Ok(FactoredPencil::new(
            factor,
            k.to_complex_adjoint(),
            s_adjoint,
            n,
        ))
    }

    fn embed(&self, x: &[T]) -> Vec<c64> {
        complex_adjoint_vector(x)
    }

    fn extract(&self, y: &[c64]) -> Vec<Vec<T>> {
        if T::REAL_DIM == 1 {
            let imaginary: Vec<c64> = y.iter().map(|z| c64::new(z.im, 0.0)).collect();
            vec![
                from_complex_adjoint_vector(y),
                from_complex_adjoint_vector(&imaginary),
            ]
        } else {
            vec![from_complex_adjoint_vector(y)]
        }
    }
}
