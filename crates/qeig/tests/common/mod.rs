//! Shared builders of the integration tests: random sparse Hermitian pencils with known dense
//! truth, cycle-graph Laplacians with closed-form spectra, comparison helpers.
#![allow(dead_code)]

use qeig::dense::{DenseEigen, generalized_hermitian_eigen};
use qscalar::{Quat, Scalar};
use qsparse::{DenseMatrix, SparseMatrix, TripletMatrix, vector};

/// Deterministic uniform numbers in [−1, 1) (xorshift), independent of the crate's generator.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(2_685_821_657_736_338_717).max(1))
    }
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    pub fn scalar<T: Scalar<Real = f64>>(&mut self) -> T {
        let mut v = [T::zero()];
        for x in T::as_reals_mut(&mut v) {
            *x = self.next();
        }
        v[0]
    }
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next() + 1.0) * 0.5 * n as f64) as usize % n
    }
}

/// A random sparse Hermitian matrix: `nnz_per_col` random off-diagonal pairs per column and a
/// real diagonal `diag_shift + random`.
pub fn random_hermitian<T: Scalar<Real = f64>>(
    n: usize,
    nnz_per_col: usize,
    diag_shift: f64,
    rng: &mut Rng,
) -> SparseMatrix<T> {
    let mut t = TripletMatrix::new(n, n);
    for j in 0..n {
        t.push(j, j, T::from_real(diag_shift + rng.next())).unwrap();
        for _ in 0..nnz_per_col {
            let i = rng.below(n);
            if i == j {
                continue;
            }
            let v: T = rng.scalar();
            t.push(i, j, v).unwrap();
            t.push(j, i, v.conj()).unwrap();
        }
    }
    t.to_csc()
}

/// A random sparse Hermitian positive-definite matrix (strictly diagonally dominant).
pub fn random_hpd<T: Scalar<Real = f64>>(n: usize, rng: &mut Rng) -> SparseMatrix<T> {
    let a = random_hermitian::<T>(n, 2, 0.0, rng);
    let mut t = TripletMatrix::new(n, n);
    let mut rowsum = vec![0.0; n];
    for (i, j, v) in a.triplets() {
        if i != j {
            t.push(i, j, v).unwrap();
            rowsum[i] += v.abs();
        }
    }
    for (i, s) in rowsum.iter().enumerate() {
        t.push(i, i, T::from_real(s + 1.0 + rng.next().abs()))
            .unwrap();
    }
    t.to_csc()
}

/// A random Hermitian `K` ([`random_hermitian`] with `nnz_per_col`) and a random HPD `S`, both
/// `n × n`.
pub fn random_pencil<T: Scalar<Real = f64>>(
    n: usize,
    nnz_per_col: usize,
    rng: &mut Rng,
) -> (SparseMatrix<T>, SparseMatrix<T>) {
    let k = random_hermitian::<T>(n, nnz_per_col, 0.0, rng);
    (k, random_hpd::<T>(n, rng))
}

/// Dense truth of the pencil.
pub fn dense_truth<T: Scalar<Real = f64>>(
    k: &SparseMatrix<T>,
    s: &SparseMatrix<T>,
) -> DenseEigen<T> {
    generalized_hermitian_eigen(&k.to_dense(), &s.to_dense()).unwrap()
}

/// `xᴴ S y`.
pub fn s_inner<T: Scalar<Real = f64>>(s: &SparseMatrix<T>, x: &[T], y: &[T]) -> T {
    let mut sy = vec![T::zero(); y.len()];
    s.mul_vec(y, &mut sy).unwrap();
    vector::inner(x, &sy)
}

/// `S`-norm of the component of `x` outside the quaternionic span of the given
/// `S`-orthonormal columns.
pub fn distance_to_span<T: Scalar<Real = f64>>(
    s: &SparseMatrix<T>,
    x: &[T],
    columns: &[Vec<T>],
) -> f64 {
    let mut r = x.to_vec();
    for _ in 0..2 {
        for q in columns {
            let c = s_inner(s, q, &r);
            vector::axpy(&mut r, q, -c);
        }
    }
    s_inner(s, &r, &r).re().max(0.0).sqrt()
}

/// Columns of a dense matrix.
pub fn columns<T: Scalar<Real = f64>>(m: &DenseMatrix<T>, idx: &[usize]) -> Vec<Vec<T>> {
    idx.iter().map(|&j| m.col(j).to_vec()).collect()
}

/// The Laplacian of the cycle graph on `n` vertices with quaternion (real-valued) entries,
/// `L⊗I`; eigenvalues `2 − 2 cos(2π j / n)`, each twice for `0 < j < n/2`.
pub fn cycle_laplacian<T: Scalar<Real = f64>>(n: usize) -> SparseMatrix<T> {
    let mut t = TripletMatrix::new(n, n);
    for i in 0..n {
        let j = (i + 1) % n;
        t.push(i, i, T::from_real(2.0)).unwrap();
        t.push(i, j, T::from_real(-1.0)).unwrap();
        t.push(j, i, T::from_real(-1.0)).unwrap();
    }
    t.to_csc()
}

/// A quaternion with every component random (for generic code paths).
pub fn random_quat(rng: &mut Rng) -> Quat<f64> {
    rng.scalar()
}
