//! Sparse vectors with the Cholesky factor of their Gram matrix: least squares fits by them
//! and projections onto the complement of their span at the cost of their supports.
//!
//! Orthonormalising overlapping sparse vectors (Gram–Schmidt) fills each in with the supports
//! of all the earlier ones: `c` vectors chained by overlaps become `c` dense vectors over their
//! union, `c²` times its size to build and `c` times it per projection. Kept as they are, with
//! `ZᴴZ = L Lᴴ`, a fit `t = (ZᴴZ)⁻¹ Zᴴ w` costs their supports and two triangular solves of
//! order `c`. Its rounding error grows as the square of the condition number of `Z`, so
//! [`Gram::new`] accepts only vectors clearly independent of each other and checks the
//! projection it gives on a random vector.

use std::collections::HashMap;

use qscalar::Scalar;
use qscalar::random::SplitMix64;

use crate::SparseVector;

/// Sparse vectors `Z = [z₁ … z_c]` and the Cholesky factor `L` of `ZᴴZ = L Lᴴ`.
#[derive(Debug, Clone)]
pub struct Gram<T> {
    members: Vec<SparseVector<T>>,
    /// Rows of the lower triangle of `L`, packed (row `i` holds `i + 1` entries; real diagonal).
    factor: Vec<T>,
}

/// A vector whose squared norm orthogonal to the earlier ones is at most this fraction of its
/// own is not clearly independent of them: the difference `‖z‖² − ‖L⁻¹ Zᴴ z‖²` that measures
/// it would be dominated by rounding further down.
const INDEPENDENT: f64 = 1e-8;

/// The largest component along a member that a projection of a random vector may leave
/// ([`Gram::new`]), relative to the norms of the member and of the vector and to `√m` for `m`
/// entries: sixteen times the rounding of an inner product of that length. Modified
/// Gram–Schmidt against an orthonormal basis leaves about that (`~10⁻¹⁷` for 512 directions
/// over 5,632 entries), the Gram form `~ε κ(Z)²`.
const GRAM_ACCURACY: f64 = 16.0 * f64::EPSILON;

impl<T: Scalar<Real = f64>> Gram<T> {
    /// The Gram form of `members`, grown one member at a time:
    /// `L r = Zᴴ z` and pivot `‖z‖² − ‖r‖²`, the squared norm of the member's component
    /// orthogonal to the earlier ones. `None` unless every member is clearly independent of
    /// the earlier ones (pivot above `10⁻⁸ ‖z‖²`) and the projection of a random vector leaves
    /// at most `16 ε √m` along each member (`m` the entries of their supports, relative to the
    /// norms of the member and the vector): then an orthonormal basis is the way.
    pub fn new(members: &[SparseVector<T>]) -> Option<Self> {
        // For each row, the earlier members that touch it: `Zᴴ z` costs the overlaps only.
        let mut at_row: HashMap<usize, Vec<(usize, T)>> = HashMap::new();
        let mut factor: Vec<T> = Vec::new();
        let mut r: Vec<T> = Vec::new();
        for (j, z) in members.iter().enumerate() {
            r.clear();
            r.resize(j, T::zero());
            for (&row, &value) in z.rows.iter().zip(&z.values) {
                for &(i, earlier) in at_row.get(&row).into_iter().flatten() {
                    r[i] += earlier.conj() * value;
                }
            }
            forward(&factor, &mut r);
            let squared = z.norm_squared();
            let pivot = squared - r.iter().map(|x| x.abs2()).sum::<f64>();
            // A NaN pivot (entries out of range) is refused too.
            if pivot.is_nan() || pivot <= INDEPENDENT * squared {
                return None;
            }
            factor.extend(r.iter().map(|x| x.conj()));
            factor.push(T::from_real(pivot.sqrt()));
            for (&row, &value) in z.rows.iter().zip(&z.values) {
                at_row.entry(row).or_default().push((j, value));
            }
        }
        let gram = Self {
            members: members.to_vec(),
            factor,
        };
        gram.projects_accurately().then_some(gram)
    }

    /// The members.
    pub fn members(&self) -> &[SparseVector<T>] {
        &self.members
    }

    /// Bytes of the members and the factor.
    pub fn bytes(&self) -> usize {
        let entries: usize = self.members.iter().map(|z| z.rows.len()).sum();
        let size = std::mem::size_of::<T>();
        entries * (size + std::mem::size_of::<usize>()) + self.factor.len() * size
    }

    /// `t = (ZᴴZ)⁻¹ Zᴴ w`: the coefficients of the least squares fit `Z t` of `w` (coefficients
    /// on the right).
    pub fn coefficients(&self, w: &[T]) -> Vec<T> {
        let mut t: Vec<T> = self.members.iter().map(|z| z.inner(w)).collect();
        forward(&self.factor, &mut t);
        // `Lᴴ t = u`, by columns of `Lᴴ` (rows of `L`).
        for k in (0..t.len()).rev() {
            let l = row(&self.factor, k);
            t[k] = t[k].scale(1.0 / l[k].re());
            let tk = t[k];
            for i in 0..k {
                t[i] -= l[i].conj() * tk;
            }
        }
        t
    }

    /// `w ← w − Z (ZᴴZ)⁻¹ Zᴴ w`: the projection onto the complement of the span.
    pub fn project(&self, w: &mut [T]) {
        let t = self.coefficients(w);
        for (z, &c) in self.members.iter().zip(&t) {
            z.add_to(w, -c);
        }
    }

    /// Whether [`Gram::project`] leaves, of a random vector, components along every member of
    /// at most [`GRAM_ACCURACY`] relative to the two norms and `√m`. The vector lives on the union of
    /// the supports (entries elsewhere are left as they are), numbered locally, so that the
    /// check costs the supports whatever the length of the vectors.
    fn projects_accurately(&self) -> bool {
        let mut rows: Vec<usize> = (self.members.iter())
            .flat_map(|z| z.rows.iter().copied())
            .collect();
        rows.sort_unstable();
        rows.dedup();
        let local = Self {
            members: (self.members.iter())
                .map(|z| SparseVector {
                    rows: (z.rows.iter())
                        .map(|row| rows.binary_search(row).unwrap_or_default())
                        .collect(),
                    values: z.values.clone(),
                })
                .collect(),
            factor: self.factor.clone(),
        };
        let mut w = vec![T::zero(); rows.len()];
        SplitMix64::new(rows.len() as u64).fill_symmetric(&mut w);
        let bound = GRAM_ACCURACY * (rows.len() as f64).sqrt() * crate::vector::norm(&w);
        local.project(&mut w);
        (local.members.iter()).all(|z| z.inner(&w).abs2().sqrt() <= bound * z.norm_squared().sqrt())
    }
}

/// Row `i` of the packed lower triangle.
fn row<T>(factor: &[T], i: usize) -> &[T] {
    &factor[i * (i + 1) / 2..(i + 1) * (i + 2) / 2]
}

/// `t ← L⁻¹ t` for the packed rows `factor` of `L` (as many as `t` has entries).
fn forward<T: Scalar<Real = f64>>(factor: &[T], t: &mut [T]) {
    for i in 0..t.len() {
        let l = row(factor, i);
        let mut sum = t[i];
        for k in 0..i {
            sum -= l[k] * t[k];
        }
        t[i] = sum.scale(1.0 / l[i].re());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use qscalar::Quat;

    fn member(rows: &[usize], seed: u64) -> SparseVector<Quat<f64>> {
        let mut values = vec![Quat::new(0.0, 0.0, 0.0, 0.0); rows.len()];
        SplitMix64::new(seed).fill_symmetric(&mut values);
        SparseVector {
            rows: rows.to_vec(),
            values,
        }
    }

    /// A chain of overlapping quaternion vectors: the fit's residual is orthogonal to every
    /// member (normal equations, checked by inner products computed here), and the
    /// coefficients reproduce a vector in the span exactly.
    #[test]
    fn fits_are_orthogonal_residuals_and_reproduce_the_span() {
        let n = 40;
        let members: Vec<_> = (0..12)
            .map(|i| {
                member(
                    &[3 * i, 3 * i + 1, 3 * i + 2, 3 * i + 3, 3 * i + 4],
                    i as u64,
                )
            })
            .collect();
        let gram = Gram::new(&members).expect("independent members");
        let mut w = vec![Quat::new(0.0, 0.0, 0.0, 0.0); n];
        SplitMix64::new(99).fill_symmetric(&mut w);
        let norm = crate::vector::norm(&w);
        let mut projected = w.clone();
        gram.project(&mut projected);
        for z in &members {
            assert!(z.inner(&projected).abs() < 1e-14 * norm);
        }
        // A combination of the members is fitted exactly, with its own coefficients.
        let want: Vec<Quat<f64>> = (0..12)
            .map(|i| Quat::new(i as f64, 1.0, -0.5 * i as f64, 2.0))
            .collect();
        let mut combination = vec![Quat::new(0.0, 0.0, 0.0, 0.0); n];
        for (z, &c) in members.iter().zip(&want) {
            z.add_to(&mut combination, c);
        }
        for (got, want) in gram.coefficients(&combination).iter().zip(&want) {
            assert!((*got - *want).abs() < 1e-12, "{got:?} against {want:?}");
        }
    }

    /// A member in the span of the earlier ones (to rounding, or nearly) is refused: the
    /// orthonormal form is for such sets.
    #[test]
    fn dependent_members_are_refused() {
        let a = member(&[0, 1, 2], 1);
        let b = member(&[2, 3], 2);
        let sum = SparseVector {
            rows: vec![0, 1, 2, 3],
            values: vec![
                a.values[0],
                a.values[1],
                a.values[2] + b.values[0],
                b.values[1],
            ],
        };
        assert!(Gram::new(&[a.clone(), b.clone()]).is_some());
        assert!(Gram::new(&[a.clone(), b.clone(), sum.clone()]).is_none());
        let mut nearly = sum;
        nearly.values[3] += Quat::new(1e-6, 0.0, 0.0, 0.0);
        assert!(Gram::new(&[a, b, nearly]).is_none());
    }
}
