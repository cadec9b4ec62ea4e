//! Mass-orthonormal eigenvectors in canonical phase (paper §4.3; docs/MATH.md, "Canonical phase").
//!
//! A quaternionic eigenvector is defined up to a unit quaternion on the right, `φ ↦ φ c`. The
//! paper fixes it with `q = Σ_p Ā_p φ_p⁻¹`, `φ ← φ q/|q|` (right multiplication), which is
//! equivariant: `φ c` gives `q' ∝ c⁻¹ q` and the same canonical form. Under a rotation of the
//! mesh `f ↦ r f r̄` the canonical forms satisfy `φ̃ = r φ r̄`.
//!
//! Written once over [`Scalar`]: a real eigenvector (of a real operator solved in real
//! arithmetic) is a quaternionic one with zero imaginary part, its `q` is real and the phase is
//! its sign, exactly what the quaternionic formulas give on it.

use qscalar::Scalar;
use qsparse::vector::axpy;

/// `⟨x, y⟩_M = Σ_p Ā_p conj(x_p) y_p`.
pub fn mass_inner<T: Scalar<Real = f64>>(masses: &[f64], x: &[T], y: &[T]) -> T {
    masses
        .iter()
        .zip(x.iter().zip(y))
        .map(|(&m, (&a, &b))| (a.conj() * b).scale(m))
        .sum()
}

/// `‖x‖_M = sqrt(Σ_p Ā_p |x_p|²)`.
pub fn mass_norm<T: Scalar<Real = f64>>(masses: &[f64], x: &[T]) -> f64 {
    masses
        .iter()
        .zip(x)
        .map(|(&m, q)| m * q.abs2())
        .sum::<f64>()
        .sqrt()
}

/// Puts `phi` in canonical phase and scales it to unit mass norm:
/// `q = Σ_p Ā_p φ_p⁻¹` over the vertices with `|φ_p|` above `10⁻⁸ max|φ|` (near-zeros would
/// dominate the sum), `φ ← φ q/|q|`, then `φ ← φ / ‖φ‖_M`. When `q` vanishes (a real
/// Laplacian mode can have `Σ Ā/g = 0`) only the normalisation is applied.
pub fn canonicalize<T: Scalar<Real = f64>>(masses: &[f64], phi: &mut [T]) {
    let largest = phi.iter().map(|q| q.abs()).fold(0.0, f64::max);
    let q: T = masses
        .iter()
        .zip(phi.iter())
        .filter(|(_, p)| p.abs() > 1e-8 * largest)
        .map(|(&m, &p)| p.inv().scale(m))
        .sum();
    let size = q.abs();
    if size > 1e-300 {
        let unit = q.scale(1.0 / size);
        for p in phi.iter_mut() {
            *p *= unit;
        }
    }
    let norm = mass_norm(masses, phi);
    if norm > 0.0 {
        for p in phi.iter_mut() {
            *p = p.scale(1.0 / norm);
        }
    }
}

/// Mass-orthonormalises, within every cluster of equal eigenvalues (consecutive values, in the
/// given order, within `relative_gap · |λ|` of the cluster's first; exact zeros, such as a
/// kernel's, form one cluster), the eigenvectors by Gram–Schmidt with coefficients on the
/// right (`v ← v − u ⟨u, v⟩_M`), then puts each in canonical phase. Eigenvectors of distinct
/// eigenvalues are left as the pencil made them.
///
/// The width is relative only: eigenvalues scale with the mesh (`1/s²` for the Laplacian), so
/// an absolute floor such as `max(|λ|, 1)` merged distinct eigenvalues of a mesh in
/// micrometres and mixed their eigenvectors.
pub fn orthonormalize_and_canonicalize<T: Scalar<Real = f64>>(
    masses: &[f64],
    values: &[f64],
    vectors: &mut [Vec<T>],
    relative_gap: f64,
) {
    let mut start = 0;
    while start < vectors.len() {
        let mut end = start + 1;
        while end < vectors.len()
            && (values[end] - values[start]).abs() <= relative_gap * values[start].abs()
        {
            end += 1;
        }
        for i in start..end {
            let (done, rest) = vectors.split_at_mut(i);
            let v = &mut rest[0];
            for u in &done[start..i] {
                let coefficient = mass_inner(masses, u, v);
                axpy(v, u, -coefficient);
            }
            let norm = mass_norm(masses, v);
            if norm > 0.0 {
                v.iter_mut().for_each(|p| *p = p.scale(1.0 / norm));
            }
        }
        start = end;
    }
    for v in vectors.iter_mut() {
        canonicalize(masses, v);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `|⟨u, v⟩_M| / (‖u‖_M ‖v‖_M)`: 1 for parallel vectors, 0 for orthogonal ones.
    fn cosine(masses: &[f64], u: &[f64], v: &[f64]) -> f64 {
        mass_inner(masses, u, v).abs() / (mass_norm(masses, u) * mass_norm(masses, v))
    }

    /// Clusters are relative at every magnitude: two eigenvalues 5 % apart are distinct whether
    /// they are near 1 or near 10⁻⁸ (a mesh in micrometres), and their eigenvectors are left
    /// as they are; two equal to 10⁻¹² relative are one eigenspace and come out orthonormal.
    #[test]
    fn clusters_are_relative_at_every_magnitude() {
        let masses = [1.0, 2.0, 0.5];
        let (u, v) = (vec![1.0, 1.0, 0.0], vec![1.0, 0.0, 1.0]);
        for magnitude in [1.0, 1e-8, 1e8] {
            let mut distinct = vec![u.clone(), v.clone()];
            let values = [magnitude, 1.05 * magnitude];
            orthonormalize_and_canonicalize(&masses, &values, &mut distinct, 1e-8);
            assert!(
                (cosine(&masses, &distinct[1], &v) - 1.0).abs() < 1e-14,
                "λ ≈ {magnitude:e}: the second eigenvector was changed"
            );
            let mut equal = vec![u.clone(), v.clone()];
            let values = [magnitude, (1.0 + 1e-12) * magnitude];
            orthonormalize_and_canonicalize(&masses, &values, &mut equal, 1e-8);
            assert!(
                cosine(&masses, &equal[0], &equal[1]) < 1e-14,
                "λ ≈ {magnitude:e}"
            );
        }
    }
}
