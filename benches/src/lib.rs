//! Shared problem generators and measurement helpers for the criterion benchmarks and the
//! `compare` harness.

pub mod eigs;
pub mod linear;
pub mod spectra;

use std::time::Instant;

use dirac::TriMesh;
use dirac::generators::icosphere;
use dirac::geometry::{barycentric_masses, cotan_laplacian};
use qscalar::Quat;
use qsparse::{SparseMatrix, TripletMatrix};

/// Strength of the connection: the transport along edge `ij` is `exp(STRENGTH·(f_j − f_i)/2)`.
const CONNECTION_STRENGTH: f64 = 3.0;

/// The benchmark matrix of issue 2: `L⊗I + (connection terms) + M` on the unit icosphere of the
/// given level (`10·4^level + 2` quaternion unknowns); [`connection_laplacian_on`] of it.
pub fn connection_laplacian(level: u32) -> SparseMatrix<Quat<f64>> {
    connection_laplacian_on(&icosphere(level))
}

/// The benchmark matrix of issue 2 on `mesh`: one quaternion unknown per vertex, stored
/// entries on the vertex–edge graph (the pattern of the Laplacian, and of the relative Dirac
/// pencil's `D* M_F D`, whose vertices are coupled when they share a face).
///
/// Off-diagonal entries are `−w_ij r_ij` with `w_ij` the cotangent weight of edge `ij` and
/// `r_ij = exp(c (f_j − f_i)/2)` a unit quaternion (`r_ji = r̄_ij`); diagonal entries are
/// `Σ_j w_ij + Ā_i`. This is a quaternionic connection Laplacian (Hermitian positive
/// semidefinite, `x* L x = Σ_ij w_ij |x_i − r_ij x_j|²`) plus the barycentric mass, hence
/// Hermitian positive definite with genuinely quaternionic (not real) off-diagonal entries.
pub fn connection_laplacian_on(mesh: &TriMesh) -> SparseMatrix<Quat<f64>> {
    let laplacian = cotan_laplacian(mesh);
    let mass = barycentric_masses(mesh);
    let n = mesh.vertex_count();
    let p = mesh.positions();
    let mut t = TripletMatrix::with_capacity(n, n, laplacian.nnz());
    for (i, j, l_ij) in laplacian.triplets() {
        let value = if i == j {
            Quat::from_real(l_ij + mass[i])
        } else {
            let d = [p[j][0] - p[i][0], p[j][1] - p[i][1], p[j][2] - p[i][2]];
            let transport = Quat::from_vector(d.map(|c| c * CONNECTION_STRENGTH / 2.0)).exp();
            transport * l_ij
        };
        t.push(i, j, value)
            .expect("valid indices and finite values");
    }
    t.to_csc()
}

/// The smallest icosphere level with at least `unknowns` vertices.
pub fn icosphere_level_for(unknowns: usize) -> u32 {
    (0..12)
        .find(|&s| 10 * 4usize.pow(s) + 2 >= unknowns)
        .unwrap_or(12)
}

/// Median of the samples (sorted in place).
pub fn median(samples: &mut [f64]) -> f64 {
    samples.sort_by(f64::total_cmp);
    let n = samples.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        samples[n / 2]
    } else {
        0.5 * (samples[n / 2 - 1] + samples[n / 2])
    }
}

/// Runs `f` once to warm up, then `repeats` times (at least once), and returns the median
/// wall-clock seconds.
pub fn time_median(repeats: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut samples: Vec<f64> = (0..repeats.max(1))
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .collect();
    median(&mut samples)
}
