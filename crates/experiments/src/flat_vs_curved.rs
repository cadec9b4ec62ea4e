//! Experiment 4 (paper Fig. 5, Fig. 9): the relative Dirac operator `D_N` vanishes wherever
//! the surface is flat, so on a cube — flat away from its edges — it has a large kernel and
//! many small eigenvalues, while on a sphere its kernel is the constants and its smallest
//! nonzero `|λ|` is `√(4π)` at unit area.
//!
//! Both counts come from all eigenvalues `ν` of the dense pencil `A x = ν M x` (`A = D_N* M_F
//! D_N`, [`qeig::dense`]) on the mesh scaled to unit area, so `√ν` approximates `|λ(D_N)|`:
//! * kernel dimension: the `ν ≤ 10⁻⁹ ν_max`;
//! * small eigenvalues: the nonzero `√ν <` [`SMALL`].
//!
//! A hand-derivable lower bound for the kernel: `D_N δ_p = 0` whenever all neighbours of `p`
//! share one normal (each face `pqr` contributes `−(N_r − N_q)/(2A)`), and the constants are
//! in the kernel too, so `dim ker ≥ #{such p} + 1` (when not every vertex qualifies). On the
//! `n × n`-per-side cube that is `6 (n − 3)² + 1` for `n ≥ 3`.

use dirac::TriMesh;
use dirac::geometry::{barycentric_masses, vertex_normals};
use dirac::operators::{DiracPencil, normal_dirac};
use dirac::spectrum::{Operator, SpectrumOptions, spectrum};
use qeig::dense::hermitian_eigen;
use qscalar::Quat;
use qsparse::DenseMatrix;

use crate::ExperimentError;

/// `|λ|` below which an eigenvalue counts as small at unit area: below the sphere's smallest
/// nonzero `|λ| = 4π ≈ 12.6` (`λ = 1` on the unit sphere; `D_N` scales like `1/area`).
pub const SMALL: f64 = 10.0;

/// Relative threshold `ν ≤ 10⁻⁹ ν_max` of the kernel.
pub const KERNEL_TOLERANCE: f64 = 1e-9;

/// The counts of one mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KernelCounts {
    /// Vertices.
    pub vertices: usize,
    /// `dim ker D_N` (constants included).
    pub kernel: usize,
    /// The flat-neighbourhood lower bound of the kernel (module documentation).
    pub flat_bound: usize,
    /// Nonzero eigenvalues with `√ν <` [`SMALL`].
    pub small: usize,
    /// Smallest nonzero `√ν`.
    pub smallest_nonzero: f64,
}

/// The counts of `mesh` (scaled to unit area first). Dense: use meshes of at most a few
/// thousand vertices.
pub fn kernel_counts(mesh: &TriMesh) -> Result<KernelCounts, ExperimentError> {
    let area: f64 = (0..mesh.face_count()).map(|t| mesh.face_area(t)).sum();
    let mesh = mesh.scaled(1.0 / area.sqrt())?;
    let n = mesh.vertex_count();
    let stiffness = DiracPencil::new(&mesh, &normal_dirac(&mesh)?)?.stiffness;
    let inverse_root_mass: Vec<f64> = barycentric_masses(&mesh)
        .iter()
        .map(|m| 1.0 / m.sqrt())
        .collect();
    // M^{−1/2} A M^{−1/2}: same eigenvalues as the pencil.
    let mut matrix = DenseMatrix::<Quat<f64>>::zeros(n, n);
    for (i, j, v) in stiffness.triplets() {
        matrix.col_mut(j)[i] = v * (inverse_root_mass[i] * inverse_root_mass[j]);
    }
    let values = hermitian_eigen(&matrix)
        .map_err(|e| ExperimentError::Eigen(e.to_string()))?
        .values;
    let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let is_zero = |v: f64| v <= KERNEL_TOLERANCE * largest;
    let nonzero: Vec<f64> = values
        .iter()
        .filter(|&&v| !is_zero(v))
        .map(|v| v.sqrt())
        .collect();
    Ok(KernelCounts {
        vertices: n,
        kernel: values.iter().filter(|&&v| is_zero(v)).count(),
        flat_bound: flat_bound(&mesh)?,
        small: nonzero.iter().filter(|&&s| s < SMALL).count(),
        smallest_nonzero: nonzero.iter().copied().fold(f64::INFINITY, f64::min),
    })
}

/// The first `count` eigenpairs of `operator` on `mesh` with `λ ≠ 0` (`|λ| > 10⁻⁸ max |λ|`):
/// `(λ, |φ|)` with `|φ(p)|` the quaternion norm at every vertex (what the paper plots, §4.1).
pub fn eigenfunction_magnitudes(
    mesh: &TriMesh,
    operator: Operator,
    count: usize,
) -> Result<Vec<(f64, Vec<f64>)>, ExperimentError> {
    // At most one zero mode (the constants) is reported, so one extra pair suffices.
    let k = (count + 1).min(mesh.vertex_count());
    let result = spectrum(mesh, &SpectrumOptions::new(operator, k)).map_err(|source| {
        ExperimentError::Spectrum {
            operator,
            mesh: 0,
            source,
        }
    })?;
    let largest = result
        .eigenvalues
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    Ok(result
        .eigenvalues
        .iter()
        .zip(&result.eigenvectors)
        .filter(|(l, _)| l.abs() > 1e-8 * largest)
        .take(count)
        .map(|(&l, phi)| (l, phi.iter().map(|q| q.norm()).collect()))
        .collect())
}

/// `#{p : all neighbours of p have the same vertex normal} + 1` (capped at the vertex count).
fn flat_bound(mesh: &TriMesh) -> Result<usize, ExperimentError> {
    let normals = vertex_normals(mesh).map_err(|vertex| {
        ExperimentError::Eigen(format!("vertex {vertex} has no normal (degenerate mesh)"))
    })?;
    let n = mesh.vertex_count();
    let mut reference: Vec<Option<[f64; 3]>> = vec![None; n];
    let mut flat = vec![true; n];
    for edge in mesh.edges() {
        let [a, b] = edge.vertices;
        for (p, q) in [(a, b), (b, a)] {
            match reference[p] {
                None => reference[p] = Some(normals[q]),
                Some(r) => {
                    flat[p] &= (0..3).all(|c| (r[c] - normals[q][c]).abs() < 1e-12);
                }
            }
        }
    }
    Ok((flat.iter().filter(|&&f| f).count() + 1).min(n))
}
