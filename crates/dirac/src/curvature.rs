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
//!
//! Per face, [`face_principal_curvatures`] estimates the shape operator from the vertex normals
//! (the per-face step of Rusinkiewicz 2004, "Estimating curvatures and their derivatives on
//! triangle meshes") and gives its principal curvatures and directions, which orient the
//! conductivity of the anisotropic Laplacian ([`crate::anisotropic`]).

use std::f64::consts::TAU;

use crate::TriMesh;
use crate::geometry::{barycentric_masses, cotan_laplacian, cross, dot, norm, normalize, sub};

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

/// The principal curvatures of one face and their directions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipalCurvatures {
    /// `κ₁ ≥ κ₂`, signed with the normals' orientation (`dN = S df`: positive on a sphere with
    /// outward normals).
    pub curvatures: [f64; 2],
    /// Unit tangent directions of `κ₁` and `κ₂`, orthogonal, in the plane of the face. At an
    /// umbilic (`κ₁ = κ₂`, a flat face included) every direction is principal and these are
    /// an arbitrary orthonormal pair.
    pub directions: [[f64; 3]; 2],
}

/// Per face `t`, the principal curvatures of the shape operator `S` (`dN = S df`) fitted to
/// the vertex normals `normals`: in an orthonormal frame `(u, v)` of the face's plane, the
/// symmetric `S = [[a, b], [b, c]]` that best satisfies `S e = ΔN` in least squares over the
/// three edges `e = f_b − f_a` with `ΔN = N_b − N_a` (both in `(u, v)` coordinates; six
/// equations, three unknowns; the per-face step of Rusinkiewicz 2004, without the averaging
/// to vertices). Exact wherever the normals are those of a quadric through the corners with
/// constant `S` on the face: on a cylinder of radius `r` with radial normals, `κ = (1/r, 0)`
/// with the first direction around the axis; on a sphere with radial normals `κ = (1/r,
/// 1/r)`. `normals` must hold one unit vector per vertex (area-weighted:
/// [`crate::geometry::vertex_normals`]).
pub fn face_principal_curvatures(mesh: &TriMesh, normals: &[[f64; 3]]) -> Vec<PrincipalCurvatures> {
    let p = mesh.positions();
    mesh.faces()
        .iter()
        .map(|&[i, j, k]| {
            let u = normalize(sub(p[j], p[i]));
            let v = normalize(cross(cross(sub(p[j], p[i]), sub(p[k], p[i])), u));
            let in_frame = |w: [f64; 3]| [dot(w, u), dot(w, v)];
            // Normal equations of the least-squares fit, unknowns `(a, b, c)`:
            // each edge gives `a x₀ + b x₁ = y₀` and `b x₀ + c x₁ = y₁`.
            let mut normal_matrix = [[0.0; 3]; 3];
            let mut rhs = [0.0; 3];
            for (a, b) in [(i, j), (j, k), (k, i)] {
                let x = in_frame(sub(p[b], p[a]));
                let y = in_frame(sub(normals[b], normals[a]));
                for (row, value) in [([x[0], x[1], 0.0], y[0]), ([0.0, x[0], x[1]], y[1])] {
                    for r in 0..3 {
                        rhs[r] += row[r] * value;
                        for c in 0..3 {
                            normal_matrix[r][c] += row[r] * row[c];
                        }
                    }
                }
            }
            let [a, b, c] = solve_symmetric_3x3(normal_matrix, rhs);
            principal(a, b, c, u, v)
        })
        .collect()
}

/// The solution of `m x = rhs` by Cramer's rule; `m` is the Gram matrix of the fit, positive
/// definite on every non-degenerate triangle (its three edges span the plane).
fn solve_symmetric_3x3(m: [[f64; 3]; 3], rhs: [f64; 3]) -> [f64; 3] {
    let det3 = |m: [[f64; 3]; 3]| dot(m[0], cross(m[1], m[2]));
    let determinant = det3(m);
    std::array::from_fn(|column| {
        let mut replaced = m;
        for row in 0..3 {
            replaced[row][column] = rhs[row];
        }
        det3(replaced) / determinant
    })
}

/// Eigenvalues and unit eigenvectors (in 3-D, from the frame `(u, v)`) of `[[a, b], [b, c]]`,
/// the larger first: `κ = (a+c)/2 ± √(((a−c)/2)² + b²)`, the first direction at the angle
/// `θ = atan2(2b, a−c)/2` from `u`.
fn principal(a: f64, b: f64, c: f64, u: [f64; 3], v: [f64; 3]) -> PrincipalCurvatures {
    let mean = 0.5 * (a + c);
    let radius = (0.5 * (a - c)).hypot(b);
    let theta = 0.5 * (2.0 * b).atan2(a - c);
    let (sin, cos) = theta.sin_cos();
    let along = |x: f64, y: f64| normalize([0, 1, 2].map(|i| x * u[i] + y * v[i]));
    PrincipalCurvatures {
        curvatures: [mean + radius, mean - radius],
        directions: [along(cos, sin), along(-sin, cos)],
    }
}
