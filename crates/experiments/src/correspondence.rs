//! Point-to-point correspondence by nearest descriptor (paper §6.3) and its geodesic error.
//!
//! Descriptors are per-vertex tables (rows = vertices). To compare two tessellations of one
//! surface, every column is divided by its mass-weighted mean over its own mesh,
//! `h_j(v) / (Σ_p Ā_p h_j(p) / Σ_p Ā_p)` (the scale-invariant form of Sun, Ovsjanikov and Guibas
//! 2009's heat-trace normalisation), and a source vertex is matched to the target vertex whose
//! normalised descriptor is nearest in the Euclidean norm.

use dirac::TriMesh;
use dirac::descriptors::DescriptorTable;
use dirac::geometry::{barycentric_masses, norm, sub};
use dirac::well::geodesic_distance;

use crate::ExperimentError;

/// The rows of `table` with every column divided by its mass-weighted mean on `mesh`.
pub fn normalized_rows(mesh: &TriMesh, table: &DescriptorTable) -> Vec<Vec<f64>> {
    let masses = barycentric_masses(mesh);
    let total: f64 = masses.iter().sum();
    let means: Vec<f64> = (0..table.column_count())
        .map(|j| {
            let weighted: f64 = table
                .column(j)
                .iter()
                .zip(&masses)
                .map(|(h, m)| h * m)
                .sum();
            weighted / total
        })
        .collect();
    (0..table.vertex_count())
        .map(|v| {
            table
                .row(v)
                .iter()
                .zip(&means)
                .map(|(h, mean)| if *mean != 0.0 { h / mean } else { *h })
                .collect()
        })
        .collect()
}

/// For each of `sources` (rows of `source`), the index of the nearest row of `target`.
pub fn nearest_descriptor(
    source: &[Vec<f64>],
    target: &[Vec<f64>],
    sources: &[usize],
) -> Vec<usize> {
    sources
        .iter()
        .map(|&s| {
            (0..target.len())
                .min_by(|&a, &b| {
                    crate::metrics::euclidean(&source[s], &target[a])
                        .total_cmp(&crate::metrics::euclidean(&source[s], &target[b]))
                })
                .unwrap_or(0)
        })
        .collect()
}

/// The vertex of `mesh` nearest (in space) to `point`: the ground-truth correspondent of a
/// point of another tessellation of the same surface.
pub fn nearest_vertex(mesh: &TriMesh, point: [f64; 3]) -> usize {
    let p = mesh.positions();
    (0..mesh.vertex_count())
        .min_by(|&a, &b| norm(sub(p[a], point)).total_cmp(&norm(sub(p[b], point))))
        .unwrap_or(0)
}

/// Geodesic distances on `mesh` (heat method) between `matched[i]` and `truth[i]`.
pub fn geodesic_errors(
    mesh: &TriMesh,
    matched: &[usize],
    truth: &[usize],
) -> Result<Vec<f64>, ExperimentError> {
    matched
        .iter()
        .zip(truth)
        .map(|(&m, &t)| {
            if m == t {
                Ok(0.0)
            } else {
                Ok(geodesic_distance(mesh, &[t])?[m].max(0.0))
            }
        })
        .collect()
}
