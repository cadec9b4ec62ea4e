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

    /// `⟨self, other⟩ = Σᵢ conj(selfᵢ) otherᵢ` of two sparse vectors (rows walked together).
    pub fn inner_sparse(&self, other: &Self) -> T {
        let mut sum = T::zero();
        let mut position = 0;
        for (&row, &value) in other.rows.iter().zip(&other.values) {
            while position < self.rows.len() && self.rows[position] < row {
                position += 1;
            }
            if self.rows.get(position) == Some(&row) {
                sum += self.values[position].conj() * value;
            }
        }
        sum
    }

    /// `self − other c` (coefficient on the right), on the union of the two supports.
    pub fn minus_times(&self, other: &Self, c: T) -> Self {
        let (mut rows, mut values) = (Vec::new(), Vec::new());
        let (mut p, mut q) = (0, 0);
        loop {
            // The next row of either list, and the entry there.
            let (row, value) = match (self.rows.get(p), other.rows.get(q)) {
                (None, None) => break,
                (Some(&i), Some(&j)) if i == j => {
                    (p, q) = (p + 1, q + 1);
                    (i, self.values[p - 1] - other.values[q - 1] * c)
                }
                (Some(&i), Some(&j)) if i < j => {
                    p += 1;
                    (i, self.values[p - 1])
                }
                (Some(&i), None) => {
                    p += 1;
                    (i, self.values[p - 1])
                }
                (_, Some(&j)) => {
                    q += 1;
                    (j, -(other.values[q - 1] * c))
                }
            };
            rows.push(row);
            values.push(value);
        }
        Self { rows, values }
    }

    /// `Σᵢ |selfᵢ|²`.
    pub fn norm_squared(&self) -> T::Real {
        self.values.iter().map(|v| v.abs2()).sum()
    }
}
