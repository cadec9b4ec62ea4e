//! Vectors held by their nonzero entries.

use qscalar::Scalar;

/// A vector held by the rows of its stored entries (strictly increasing) and their values:
/// the constant of one piece of a mesh, its image under a sparse matrix, or a triangular solve
/// with such a right-hand side, whose support is a small part of the dimension.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SparseVector<T> {
    /// Rows of the stored entries, strictly increasing.
    pub rows: Vec<usize>,
    /// The entries at those rows.
    pub values: Vec<T>,
}

impl<T: Scalar> SparseVector<T> {
    /// The nonzero entries of `x`.
    pub fn from_dense(x: &[T]) -> Self {
        let (rows, values) = (x.iter().enumerate())
            .filter(|(_, v)| **v != T::zero())
            .map(|(i, &v)| (i, v))
            .unzip();
        Self { rows, values }
    }

    /// The full vector of dimension `n` (panics if a row is not below `n`).
    pub fn to_dense(&self, n: usize) -> Vec<T> {
        let mut x = vec![T::zero(); n];
        for (&i, &v) in self.rows.iter().zip(&self.values) {
            x[i] = v;
        }
        x
    }

    /// `⟨self, x⟩ = Σᵢ conj(selfᵢ) xᵢ` against a full vector `x`.
    pub fn inner(&self, x: &[T]) -> T {
        (self.rows.iter().zip(&self.values))
            .map(|(&i, &v)| v.conj() * x[i])
            .sum()
    }

    /// `y ← y + self c` (coefficient on the right) on a full vector `y`.
    pub fn add_to(&self, y: &mut [T], c: T) {
        for (&i, &v) in self.rows.iter().zip(&self.values) {
            y[i] += v * c;
        }
    }

    /// `self c` (coefficient on the right).
    pub fn times(&self, c: T) -> Self {
        Self {
            rows: self.rows.clone(),
            values: self.values.iter().map(|&v| v * c).collect(),
        }
    }

    /// `Σᵢ |selfᵢ|²`.
    pub fn norm_squared(&self) -> T::Real {
        self.values.iter().map(|v| v.abs2()).sum()
    }
}
