//! Real and complex matrix representations of a quaternion (docs/MATH.md, "The real-block
//! representation").
//!
//! * [`left_block`]: `L(q)` with `L(q)·vec(p) = vec(q p)`. The map `q ↦ L(q)` is an algebra
//!   homomorphism (`L(pq) = L(p)L(q)`) with `L(q̄) = L(q)ᵀ`, so a quaternion-Hermitian matrix
//!   becomes a real symmetric one when every entry is replaced by its block.
//! * [`right_block`]: `R(u)` with `R(u)·vec(p) = vec(p u)`; `R(uv) = R(v)R(u)`, and every
//!   `L(·)` commutes with every `R(·)`.
//! * [`complex_adjoint`]: `χ(z₁ + z₂ j) = [[z₁, −z₂], [z̄₂, z̄₁]]`, a homomorphism into 2×2
//!   complex matrices with `χ(q̄) = χ(q)ᴴ`. Its first column `(z₁, z̄₂)` is the image of a
//!   quaternion vector entry ([`complex_column`]), since `χ(q)·(z₁', z̄₂')ᵀ` is the first column of
//!   `χ(q q')`.
//!
//! All matrices are row-major arrays: `m[row][col]`.

use num_complex::Complex;
use num_traits::Float;

use crate::Quat;

/// The left-multiplication matrix `L(q)` of `q = a + b i + c j + d k`:
/// ```text
/// [ a  -b  -c  -d ]
/// [ b   a  -d   c ]
/// [ c   d   a  -b ]
/// [ d  -c   b   a ]
/// ```
pub fn left_block<T: Float>(q: Quat<T>) -> [[T; 4]; 4] {
    let Quat {
        w: a,
        x: b,
        y: c,
        z: d,
    } = q;
    [[a, -b, -c, -d], [b, a, -d, c], [c, d, a, -b], [d, -c, b, a]]
}

/// The right-multiplication matrix `R(u)` of `u = a + b i + c j + d k`:
/// ```text
/// [ a  -b  -c  -d ]
/// [ b   a   d  -c ]
/// [ c  -d   a   b ]
/// [ d   c  -b   a ]
/// ```
pub fn right_block<T: Float>(u: Quat<T>) -> [[T; 4]; 4] {
    let Quat {
        w: a,
        x: b,
        y: c,
        z: d,
    } = u;
    [[a, -b, -c, -d], [b, a, d, -c], [c, -d, a, b], [d, c, -b, a]]
}

/// The complex adjoint `χ(q) = [[z₁, −z₂], [z̄₂, z̄₁]]` of `q = z₁ + z₂ j`.
pub fn complex_adjoint<T: Float>(q: Quat<T>) -> [[Complex<T>; 2]; 2] {
    let (z1, z2) = q.to_complex_pair();
    [[z1, -z2], [z2.conj(), z1.conj()]]
}

/// The image `(z₁, z̄₂)` of a vector entry `q = z₁ + z₂ j` in the complex-adjoint embedding.
pub fn complex_column<T: Float>(q: Quat<T>) -> [Complex<T>; 2] {
    let (z1, z2) = q.to_complex_pair();
    [z1, z2.conj()]
}

/// Inverse of [`complex_column`].
pub fn from_complex_column<T: Float>(c: [Complex<T>; 2]) -> Quat<T> {
    Quat::from_complex_pair(c[0], c[1].conj())
}

/// Multiplies two row-major 4×4 matrices (used by tests of the homomorphisms).
pub fn mat4_mul<T: Float>(a: &[[T; 4]; 4], b: &[[T; 4]; 4]) -> [[T; 4]; 4] {
    let mut c = [[T::zero(); 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            c[i][j] = (0..4).fold(T::zero(), |s, k| s + a[i][k] * b[k][j]);
        }
    }
    c
}
