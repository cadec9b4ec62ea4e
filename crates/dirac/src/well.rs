//! The infinite potential well of paper §5.1 and the heat method for geodesic distance it is
//! built on (Crane, Weischedel, Wardetzky 2013); docs/MATH.md, "The infinite potential well"
//! and "Geodesic distance by the heat method".

use qscalar::Quat;
use qsparse::{CholeskyError, SparseCholesky, SparseError, SparseMatrix};
use thiserror::Error;

use crate::TriMesh;
use crate::geometry::{
    barycentric_masses, corner_cotangent, cotan_laplacian, dot, hat_gradients, norm, scale, sub,
};

/// Why a distance or potential could not be computed.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum WellError {
    /// No source vertex was given.
    #[error("the heat method needs at least one source vertex")]
    NoSource,
    /// A source index is not a vertex of the mesh.
    #[error("source vertex {vertex} does not exist (the mesh has {vertex_count} vertices)")]
    SourceOutOfRange {
        /// The bad index.
        vertex: usize,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// The well's centre is not a vertex of the mesh.
    #[error(
        "the well's centre vertex {vertex} does not exist (the mesh has {vertex_count} \
         vertices): give one from 0 to {}, or leave the centre out for the vertex nearest the \
         area centroid",
        vertex_count.saturating_sub(1)
    )]
    CenterOutOfRange {
        /// The bad index.
        vertex: usize,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// A parameter of the well is negative or not a finite number.
    #[error("well parameter {name} = {value} is invalid: it must be a finite number ≥ 0")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A linear solve failed.
    #[error(transparent)]
    Solve(#[from] CholeskyError),
    /// Assembling a matrix failed.
    #[error(transparent)]
    Sparse(#[from] SparseError),
}

/// Geodesic distance from the `sources` by the heat method with Neumann boundary conditions:
///
/// 1. heat flow for time `t = h²` (`h` the mean edge length): `(M + t L) u = δ_sources`;
/// 2. per face `X_t = −∇u / |∇u|`, with `∇u = (1/(2A_t)) Σ_p u_p (n_t × e_p)` (`e_p` the edge
///    opposite `p`, counter-clockwise);
/// 3. integrated divergence `b_i = ½ Σ_{t∋i} [cot θ₁ (e₁·X_t) + cot θ₂ (e₂·X_t)]` over the
///    edges `e₁, e₂` of `t` leaving `i` (angles `θ₁, θ₂` opposite them);
/// 4. Poisson `L φ = −b` (PSD `L`, regularised by `10⁻¹⁰`·scale·`M` on closed meshes), shifted
///    so that the smallest value over the sources is 0.
pub fn geodesic_distance(mesh: &TriMesh, sources: &[usize]) -> Result<Vec<f64>, WellError> {
    let n = mesh.vertex_count();
    if sources.is_empty() {
        return Err(WellError::NoSource);
    }
    if let Some(&vertex) = sources.iter().find(|&&v| v >= n) {
        return Err(WellError::SourceOutOfRange {
            vertex,
            vertex_count: n,
        });
    }
    let p = mesh.positions();
    let laplacian = cotan_laplacian(mesh);
    let mass = barycentric_masses(mesh);
    let mass_matrix = SparseMatrix::from_diagonal(&mass);

    let (edge_sum, edge_count) = mesh
        .faces()
        .iter()
        .fold((0.0, 0usize), |(s, c), &[i, j, k]| {
            (
                s + norm(sub(p[j], p[i])) + norm(sub(p[k], p[j])) + norm(sub(p[i], p[k])),
                c + 3,
            )
        });
    let h = edge_sum / edge_count as f64;
    let heat_operator = SparseMatrix::linear_combination(1.0, &mass_matrix, h * h, &laplacian)?;
    let mut u = vec![0.0; n];
    for &s in sources {
        u[s] = 1.0;
    }
    SparseCholesky::factorize(&heat_operator)?.solve_in_place(&mut u)?;

    let mut divergence = vec![0.0; n];
    for (t, &face) in mesh.faces().iter().enumerate() {
        let mut gradient = [0.0; 3];
        for (&v, g) in face.iter().zip(hat_gradients(mesh, t)) {
            for c in 0..3 {
                gradient[c] += u[v] * g[c];
            }
        }
        let length = norm(gradient);
        if length == 0.0 {
            continue;
        }
        let x = scale(gradient, -1.0 / length);
        for corner in 0..3 {
            let (a, b, c) = (face[corner], face[(corner + 1) % 3], face[(corner + 2) % 3]);
            let (e1, e2) = (sub(p[b], p[a]), sub(p[c], p[a]));
            // θ₁ (opposite e₁ = ab) sits at c, θ₂ (opposite e₂ = ac) sits at b.
            let cot1 = corner_cotangent(p[c], p[a], p[b]);
            let cot2 = corner_cotangent(p[b], p[a], p[c]);
            divergence[a] += 0.5 * (cot1 * dot(e1, x) + cot2 * dot(e2, x));
        }
    }

    let stiffness_scale = laplacian
        .values()
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let mass_scale = mass.iter().fold(0.0f64, |m, v| m.max(*v));
    let regularised = SparseMatrix::linear_combination(
        1.0,
        &laplacian,
        1e-10 * stiffness_scale / mass_scale,
        &mass_matrix,
    )?;
    let mut phi: Vec<f64> = divergence.iter().map(|b| -b).collect();
    SparseCholesky::factorize(&regularised)?.solve_in_place(&mut phi)?;
    let offset = sources
        .iter()
        .map(|&s| phi[s])
        .fold(f64::INFINITY, f64::min);
    Ok(phi.into_iter().map(|d| d - offset).collect())
}

/// The potential well of paper §5.1: `U(d) = c · σ(γ (d − β))` with `σ(s) = 1/(1 + e^{−s})`,
/// `d` the geodesic distance from the centre, `β` the radius of the region of interest, `γ` the
/// steepness and `c` the height. `U ≈ 0` inside radius `β` and `≈ c` outside.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PotentialWell {
    /// Centre vertex; `None` picks the vertex nearest the area-weighted centroid.
    pub center: Option<usize>,
    /// Radius `β` of the region of interest (geodesic distance).
    pub radius: f64,
    /// Steepness `γ` (paper: 100).
    pub steepness: f64,
    /// Height `c` (paper: 10¹⁰).
    pub height: f64,
}

impl PotentialWell {
    /// The paper's steepness `γ = 100` and height `c = 10¹⁰` around the centroid vertex, with
    /// the given radius. The constants are absolute, so they assume meshes of unit scale
    /// (docs/MATH.md, "The infinite potential well": normalise patches first).
    pub fn with_radius(radius: f64) -> Self {
        Self {
            center: None,
            radius,
            steepness: 100.0,
            height: 1e10,
        }
    }

    /// The potential `U` at every vertex.
    pub fn potential(&self, mesh: &TriMesh) -> Result<Vec<f64>, WellError> {
        for (name, value) in [
            ("radius", self.radius),
            ("steepness", self.steepness),
            ("height", self.height),
        ] {
            if !value.is_finite() || value < 0.0 {
                return Err(WellError::InvalidParameter { name, value });
            }
        }
        let center = self.center.unwrap_or_else(|| centroid_vertex(mesh));
        if center >= mesh.vertex_count() {
            return Err(WellError::CenterOutOfRange {
                vertex: center,
                vertex_count: mesh.vertex_count(),
            });
        }
        let distance = geodesic_distance(mesh, &[center])?;
        Ok(distance
            .into_iter()
            .map(|d| self.height * logistic(self.steepness * (d - self.radius)))
            .collect())
    }
}

/// `σ(s) = 1/(1 + e^{−s})`, evaluated without overflow for large `|s|`.
fn logistic(s: f64) -> f64 {
    if s >= 0.0 {
        1.0 / (1.0 + (-s).exp())
    } else {
        let e = s.exp();
        e / (1.0 + e)
    }
}

/// The vertex nearest (in space) to the area-weighted centroid of the surface.
pub fn centroid_vertex(mesh: &TriMesh) -> usize {
    let p = mesh.positions();
    let (mut weighted, mut total) = ([0.0; 3], 0.0);
    for (t, &[i, j, k]) in mesh.faces().iter().enumerate() {
        let area = mesh.face_area(t);
        for c in 0..3 {
            weighted[c] += area * (p[i][c] + p[j][c] + p[k][c]) / 3.0;
        }
        total += area;
    }
    let centroid = scale(weighted, 1.0 / total);
    (0..mesh.vertex_count())
        .min_by(|&a, &b| norm(sub(p[a], centroid)).total_cmp(&norm(sub(p[b], centroid))))
        .unwrap_or(0)
}

/// `D' = D + B diag(U)`: `(D'ψ)_t = (Dψ)_t + (1/3) Σ_{p∈t} U_p ψ_p` (paper §5.1, read
/// pointwise with the unweighted `U_p`; docs/MATH.md, "The infinite potential well").
pub fn dirac_with_well(
    mesh: &TriMesh,
    dirac: &SparseMatrix<Quat<f64>>,
    potential: &[f64],
) -> Result<SparseMatrix<Quat<f64>>, WellError> {
    let averaged =
        crate::operators::averaging(mesh).matmul(&SparseMatrix::from_diagonal(potential))?;
    let one = Quat::from_real(1.0);
    Ok(SparseMatrix::linear_combination(
        one,
        dirac,
        one,
        &crate::operators::quaternionic(&averaged),
    )?)
}

/// `L' = L + diag(Ā_p U_p)` (paper §5.1).
pub fn laplacian_with_well(
    mesh: &TriMesh,
    laplacian: &SparseMatrix<f64>,
    potential: &[f64],
) -> Result<SparseMatrix<f64>, WellError> {
    let weighted: Vec<f64> = barycentric_masses(mesh)
        .iter()
        .zip(potential)
        .map(|(m, u)| m * u)
        .collect();
    Ok(SparseMatrix::linear_combination(
        1.0,
        laplacian,
        1.0,
        &SparseMatrix::from_diagonal(&weighted),
    )?)
}
