//! The anisotropic Laplacian `Δ_A = div(A grad)` of Andreux, Rodolà, Aubry and Cremers,
//! "Anisotropic Laplace-Beltrami operators for shape analysis" (ECCV workshops 2014), paper §2
//! and §4.1: diffusion slowed along the directions of large principal curvature.
//!
//! In the principal frame `(e₁, e₂)` of a face the conductivity is
//! `A = diag(ψ_α(κ₁), ψ_α(κ₂))` with `ψ_α(κ) = 1/(1 + α|κ|)`, `α ≥ 0` (each principal
//! direction gets the conductivity of its own curvature; `α = 0` is the Laplacian). The
//! stiffness is the P1 finite-element matrix with one tensor `H_t = A` per face,
//!
//! ```text
//! K_ij = Σ_t A_t ∇φ_i · H_t ∇φ_j,      H_t = I − (1 − ψ_α(κ₁)) e₁e₁ᵀ − (1 − ψ_α(κ₂)) e₂e₂ᵀ
//! ```
//!
//! (`∇φ_i` the hat-function gradients, [`crate::geometry::hat_gradients`]), which for `H = I`
//! is the cotangent Laplacian. At an umbilic or flat face (`κ₁ = κ₂`) the directions are not
//! defined, but `H_t = ψ_α(κ) I` is the same for every orthonormal frame, so the arbitrary
//! frame the curvature estimate returns there is harmless. Curvatures per face:
//! [`crate::curvature::face_principal_curvatures`] from the area-weighted vertex normals,
//! unsmoothed (the authors' code smooths curvature over a few rings first; we do not).

use qsparse::{SparseMatrix, TripletMatrix};

use crate::TriMesh;
use crate::curvature::{PrincipalCurvatures, face_principal_curvatures};
use crate::geometry::{dot, hat_gradients, vertex_normals};
use crate::operators::OperatorError;

/// The conductivity `ψ_α(κ) = 1/(1 + α|κ|)` across a principal curvature `κ`: 1 where the
/// surface does not bend in that direction, smaller the more it does.
pub fn conductivity(anisotropy: f64, curvature: f64) -> f64 {
    1.0 / (1.0 + anisotropy * curvature.abs())
}

/// The conductivity tensor `H = I − Σ_i (1 − ψ_α(κ_i)) e_i e_iᵀ` of a face (3 × 3, acting on
/// its tangent vectors as `diag(ψ_α(κ₁), ψ_α(κ₂))` in the principal frame); written as a
/// correction of `I` so that `α = 0` gives `I` exactly.
pub fn conductivity_tensor(principal: &PrincipalCurvatures, anisotropy: f64) -> [[f64; 3]; 3] {
    let mut tensor = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for (&kappa, e) in principal.curvatures.iter().zip(&principal.directions) {
        let deficit = 1.0 - conductivity(anisotropy, kappa);
        for r in 0..3 {
            for c in 0..3 {
                tensor[r][c] -= deficit * e[r] * e[c];
            }
        }
    }
    tensor
}

/// The P1 stiffness `K_ij = Σ_t A_t ∇φ_i · H_t ∇φ_j` of per-face symmetric tensors `H_t`
/// (`tensors[t]`, acting on the face's tangent vectors), positive semidefinite when every
/// `H_t` is, with `K 𝟙 = 0` (the gradients of a face sum to zero). `H_t = I` gives the
/// cotangent Laplacian [`crate::geometry::cotan_laplacian`] (Neumann on boundaries). Fails
/// unless `tensors` holds one finite tensor per face.
pub fn tensor_laplacian(
    mesh: &TriMesh,
    tensors: &[[[f64; 3]; 3]],
) -> Result<SparseMatrix<f64>, OperatorError> {
    if tensors.len() != mesh.face_count() {
        return Err(OperatorError::FaceValueCount {
            expected: mesh.face_count(),
            found: tensors.len(),
        });
    }
    let n = mesh.vertex_count();
    let mut triplets = TripletMatrix::with_capacity(n, n, 9 * mesh.face_count());
    for (t, (face, tensor)) in mesh.faces().iter().zip(tensors).enumerate() {
        let area = mesh.face_area(t);
        let gradients = hat_gradients(mesh, t);
        let flux = gradients.map(|g| tensor.map(|row| dot(row, g)));
        // One value per unordered pair, written to both triangles: `K` is exactly symmetric
        // even where rounding makes `H_t` very slightly not.
        for c in 0..3 {
            for d in c..3 {
                let value = area * dot(gradients[c], flux[d]);
                let (i, j) = (face[c], face[d]);
                // Indices come from a validated mesh; only a non-finite tensor can fail.
                triplets.push(i, j, value)?;
                if i != j {
                    triplets.push(j, i, value)?;
                }
            }
        }
    }
    Ok(triplets.to_csc())
}

/// The anisotropic Laplacian's stiffness `K` with anisotropy `α` (module documentation):
/// [`tensor_laplacian`] of [`conductivity_tensor`] on the principal curvatures of
/// [`face_principal_curvatures`] with area-weighted vertex normals. `α = 0` gives the
/// cotangent Laplacian (to rounding). The range of `α` is checked by
/// [`crate::spectrum::spectrum`].
pub fn anisotropic_laplacian(
    mesh: &TriMesh,
    anisotropy: f64,
) -> Result<SparseMatrix<f64>, OperatorError> {
    let normals =
        vertex_normals(mesh).map_err(|vertex| OperatorError::DegenerateNormal { vertex })?;
    let tensors: Vec<_> = face_principal_curvatures(mesh, &normals)
        .iter()
        .map(|principal| conductivity_tensor(principal, anisotropy))
        .collect();
    tensor_laplacian(mesh, &tensors)
}
