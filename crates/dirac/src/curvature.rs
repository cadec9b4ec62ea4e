//! Discrete curvature per vertex, and the Willmore potential `U = κ₁² + κ₂²` of the modified
//! Dirichlet energy (paper §4.1, Hildebrandt et al. 2012), whose Hessian `Δ + U` is
//! [`crate::spectrum::Operator::ModifiedDirichlet`].
//!
//! Conventions, at an interior vertex `p` with barycentric mass `Ā_p`:
//! * mean curvature from the cotangent Laplacian of the positions: `(L f)_p = 2 H_p N_p Ā_p`
//!   (the integrated mean curvature normal), so `|H_p| = |(L f)_p| / (2 Ā_p)`;
//! * Gaussian curvature from the angle defect: `K_p = (2π − Σ_{t∋p} θ_t^p) / Ā_p`;
//! * `κ₁² + κ₂² = 4H² − 2K`, clamped below at 0 (the two discretisations are not exactly
//!   consistent, and the continuum value is never negative).
//!
//! On a boundary vertex neither formula measures the surface (`(L f)_p` picks up the boundary's
//! curvature, the angle defect its turning angle), so [`willmore_potential`] gives a boundary
//! vertex the mean of the values at its interior neighbours (0 if it has none). On the unit
//! sphere `U → 2`; on a plane `U = 0` exactly, boundary included.

use std::f64::consts::TAU;

use crate::TriMesh;
use crate::geometry::{barycentric_masses, cotan_laplacian, cross, dot, norm, sub};

/// `|H_p| = |(L f)_p| / (2 Ā_p)` at every vertex (meaningful at interior vertices only).
pub fn mean_curvature(mesh: &TriMesh) -> Vec<f64> {
    let positions = mesh.positions();
    let masses = barycentric_masses(mesh);
    let mut curvature_normal = vec![[0.0; 3]; mesh.vertex_count()];
    for (p, q, w) in cotan_laplacian(mesh).triplets() {
        for c in 0..3 {
            curvature_normal[p][c] += w * positions[q][c];
        }
    }
    curvature_normal
        .iter()
        .zip(&masses)
        .map(|(&h, &m)| norm(h) / (2.0 * m))
        .collect()
}

/// The angle defect per area `K_p = (2π − Σ_{t∋p} θ_t^p) / Ā_p` at every vertex (meaningful
/// at interior vertices only).
pub fn gaussian_curvature(mesh: &TriMesh) -> Vec<f64> {
    let positions = mesh.positions();
    let mut angle_sum = vec![0.0; mesh.vertex_count()];
    for face in mesh.faces() {
        for corner in 0..3 {
            let (p, q, r) = (face[corner], face[(corner + 1) % 3], face[(corner + 2) % 3]);
            let (e1, e2) = (
                sub(positions[q], positions[p]),
                sub(positions[r], positions[p]),
            );
            angle_sum[p] += norm(cross(e1, e2)).atan2(dot(e1, e2));
        }
    }
    angle_sum
        .iter()
        .zip(barycentric_masses(mesh))
        .map(|(&theta, m)| (TAU - theta) / m)
        .collect()
}

/// The Willmore potential `U_p = max(4H_p² − 2K_p, 0) = κ₁² + κ₂²` at every vertex; boundary
/// vertices take the mean over their interior neighbours (see the module documentation).
pub fn willmore_potential(mesh: &TriMesh) -> Vec<f64> {
    let n = mesh.vertex_count();
    let mut potential: Vec<f64> = mean_curvature(mesh)
        .iter()
        .zip(gaussian_curvature(mesh))
        .map(|(&h, k)| (4.0 * h * h - 2.0 * k).max(0.0))
        .collect();
    let mut on_boundary = vec![false; n];
    for [a, b] in mesh.boundary_edges() {
        on_boundary[a] = true;
        on_boundary[b] = true;
    }
    let mut sum = vec![0.0; n];
    let mut count = vec![0usize; n];
    for edge in mesh.edges() {
        let [a, b] = edge.vertices;
        for (boundary, interior) in [(a, b), (b, a)] {
            if on_boundary[boundary] && !on_boundary[interior] {
                sum[boundary] += potential[interior];
                count[boundary] += 1;
            }
        }
    }
    for p in (0..n).filter(|&p| on_boundary[p]) {
        potential[p] = if count[p] > 0 {
            sum[p] / count[p] as f64
        } else {
            0.0
        };
    }
    potential
}
