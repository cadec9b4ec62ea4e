//! Experiment 3 (paper Fig. 12): a rectangle `[−1, 1] × [−½, ½]` with an outward bump and an
//! inward bump of the same shape, `z = a (g(x − c_out) − g(x − c_in))`,
//! `g(d) = exp(−|d|²/s²)`, `c_out = (−½, −0.15)`, `c_in = (½, −0.15)`, `a = 0.2`, `s = 0.15`,
//! whose strip `y > y₀ = 0.15` is then rolled up isometrically onto a cylinder of radius
//! `R = 0.3`: `(y, z) ↦ (y₀ + R sin θ, z + R (1 − cos θ))`, `θ = (y − y₀)/R`.
//!
//! The reflection `x ↦ −x` maps the surface's metric to itself (a bump and a dent of one
//! profile are isometric; the roll bends a region where `z < 0.005`), so any intrinsic
//! descriptor (HKS) confuses the two bumps. Without the roll the sheet would also be
//! *extrinsically* symmetric — the half turn about the y axis maps the bump onto the dent with
//! the orientation reversed, which only flips the signs of the Dirac eigenvalues — and every
//! descriptor would be equally confused (the paper's remark on extrinsic symmetry); the roll
//! breaks that symmetry, so the extrinsic Dirac operator `D_f` can see the difference. Two tessellations — a regular grid and a
//! finer, jittered one — are matched vertex by vertex by nearest descriptor
//! ([`crate::correspondence`]); the error of a match is the geodesic distance, on the target,
//! to the target vertex nearest the source vertex in space.

use dirac::TriMesh;
use dirac::descriptors::{Modes, default_times, dirac_kernel_signature, heat_kernel_signature};
use dirac::generators::grid;
use dirac::spectrum::{Operator, SolverBackend, SpectrumOptions, spectrum};
use qscalar::random::SplitMix64;

use crate::ExperimentError;
use crate::correspondence::{geodesic_errors, nearest_descriptor, nearest_vertex, normalized_rows};
use crate::spectra::TOLERANCE;

/// Bump height `a`.
pub const HEIGHT: f64 = 0.2;
/// Bump width `s`.
pub const WIDTH: f64 = 0.15;
/// Centres of the outward and the inward bump.
pub const CENTRES: [[f64; 2]; 2] = [[-0.5, -0.15], [0.5, -0.15]];
/// Where the roll starts, `y₀`.
pub const ROLL_START: f64 = 0.15;
/// Radius `R` of the roll.
pub const ROLL_RADIUS: f64 = 0.3;
/// A match within this geodesic distance counts as correct (a third of the bump width).
pub const RADIUS: f64 = 0.05;

/// Sizes of the experiment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BumpsConfig {
    /// Cells along `x` of the regular source grid (half as many along `y`); the target has
    /// `5/4` as many, jittered.
    pub cells: usize,
    /// Eigenpairs per descriptor.
    pub k: usize,
    /// Source vertices evaluated (evenly strided).
    pub samples: usize,
}

impl BumpsConfig {
    /// Quick default: 48 × 24 cells (1225 vertices) against 60 × 30 jittered, 60 pairs,
    /// 150 samples.
    pub const DEFAULT: Self = Self {
        cells: 48,
        k: 60,
        samples: 150,
    };
    /// `--full`: 80 × 40 against 100 × 50, 100 pairs, 400 samples.
    pub const FULL: Self = Self {
        cells: 80,
        k: 100,
        samples: 400,
    };
}

/// The point of the surface over `(x, y)`: height `z(x, y)`, then the roll.
pub fn point(x: f64, y: f64) -> [f64; 3] {
    let g = |c: [f64; 2]| (-((x - c[0]).powi(2) + (y - c[1]).powi(2)) / (WIDTH * WIDTH)).exp();
    let z = HEIGHT * (g(CENTRES[0]) - g(CENTRES[1]));
    if y <= ROLL_START {
        [x, y, z]
    } else {
        let theta = (y - ROLL_START) / ROLL_RADIUS;
        [
            x,
            ROLL_START + ROLL_RADIUS * theta.sin(),
            z + ROLL_RADIUS * (1.0 - theta.cos()),
        ]
    }
}

/// The surface on a `cells × cells/2` grid; with `jitter_seed`, interior vertices move by up
/// to a quarter cell in `x` and `y` first (boundary vertices stay on the boundary).
pub fn surface(cells: usize, jitter_seed: Option<u64>) -> Result<TriMesh, ExperimentError> {
    let flat = grid(cells, cells.div_ceil(2), 2.0, 1.0)?;
    let spacing = [2.0 / cells as f64, 1.0 / cells.div_ceil(2) as f64];
    let mut rng = jitter_seed.map(SplitMix64::new);
    Ok(flat.map_positions(|[mut x, mut y, _]| {
        if let Some(rng) = rng.as_mut() {
            let interior = (x.abs() - 1.0).abs() > 1e-9 && (y.abs() - 0.5).abs() > 1e-9;
            let (dx, dy) = (rng.uniform(-0.25, 0.25), rng.uniform(-0.25, 0.25));
            if interior {
                x += dx * spacing[0];
                y += dy * spacing[1];
            }
        }
        point(x, y)
    })?)
}

/// Errors of one descriptor's correspondence.
#[derive(Debug, Clone, PartialEq)]
pub struct MatchErrors {
    /// Descriptor name (`HKS`, `DKS`).
    pub descriptor: &'static str,
    /// Geodesic error of every sampled source vertex.
    pub errors: Vec<f64>,
    /// The bump (index into [`CENTRES`]) each sampled source vertex lies on (within `2s` of
    /// its centre), if any.
    pub source_bump: Vec<Option<usize>>,
    /// The bump the matched target vertex lies on, if any.
    pub matched_bump: Vec<Option<usize>>,
}

impl MatchErrors {
    /// Mean error over all samples, or over the bump samples only.
    pub fn mean(&self, bumps_only: bool) -> f64 {
        let chosen: Vec<f64> = self
            .errors
            .iter()
            .zip(&self.source_bump)
            .filter(|(_, b)| !bumps_only || b.is_some())
            .map(|(e, _)| *e)
            .collect();
        chosen.iter().sum::<f64>() / chosen.len().max(1) as f64
    }

    /// Share of the samples on a bump that were matched onto the other bump (in ↔ out).
    pub fn swapped(&self) -> f64 {
        let on_bump = self.source_bump.iter().filter(|b| b.is_some()).count();
        let swapped = self
            .source_bump
            .iter()
            .zip(&self.matched_bump)
            .filter(|(s, m)| matches!((s, m), (Some(a), Some(b)) if a != b))
            .count();
        swapped as f64 / on_bump.max(1) as f64
    }

    /// Share of samples matched within [`RADIUS`].
    pub fn within_radius(&self) -> f64 {
        self.errors.iter().filter(|&&e| e <= RADIUS).count() as f64
            / self.errors.len().max(1) as f64
    }
}

/// The bump a surface point lies on (within `2s` of its centre). Bumps lie in the part that
/// is not rolled, where `(x, y)` are the plane coordinates.
pub fn bump_of(p: [f64; 3]) -> Option<usize> {
    CENTRES
        .iter()
        .position(|c| (p[0] - c[0]).hypot(p[1] - c[1]) < 2.0 * WIDTH)
}

/// The descriptor rows (normalised) of HKS (Laplace) and DKS (extrinsic Dirac) on `mesh`.
fn descriptors(
    mesh: &TriMesh,
    k: usize,
    backend: SolverBackend,
) -> Result<[Vec<Vec<f64>>; 2], ExperimentError> {
    let solve = |operator: Operator| {
        let mut options = SpectrumOptions::new(operator, k);
        options.backend = backend;
        options.tolerance = TOLERANCE;
        spectrum(mesh, &options).map_err(|source| ExperimentError::Spectrum {
            operator,
            mesh: 0,
            source,
        })
    };
    let laplace = solve(Operator::Laplace)?;
    let dirac = solve(Operator::ExtrinsicDirac)?;
    let heat = Modes::from_spectrum(&laplace)?;
    let hks = heat_kernel_signature(&heat, &default_times(&heat, 100)?)?;
    let spin = Modes::from_spectrum(&dirac)?;
    let dks = dirac_kernel_signature(&spin, &default_times(&spin, 100)?)?;
    Ok([normalized_rows(mesh, &hks), normalized_rows(mesh, &dks)])
}

/// Runs the correspondence from the regular tessellation to the jittered one for HKS and DKS.
pub fn run(
    config: &BumpsConfig,
    backend: SolverBackend,
) -> Result<(TriMesh, TriMesh, [MatchErrors; 2]), ExperimentError> {
    let source = surface(config.cells, None)?;
    let target = surface(config.cells * 5 / 4, Some(12))?;
    let n = source.vertex_count();
    let stride = (n / config.samples.max(1)).max(1);
    let samples: Vec<usize> = (0..n).step_by(stride).collect();
    let truth: Vec<usize> = samples
        .iter()
        .map(|&s| nearest_vertex(&target, source.positions()[s]))
        .collect();
    let source_bump: Vec<Option<usize>> = samples
        .iter()
        .map(|&s| bump_of(source.positions()[s]))
        .collect();
    let [source_hks, source_dks] = descriptors(&source, config.k, backend)?;
    let [target_hks, target_dks] = descriptors(&target, config.k, backend)?;
    let mut results = Vec::new();
    for (name, s, t) in [
        ("HKS", &source_hks, &target_hks),
        ("DKS", &source_dks, &target_dks),
    ] {
        let matched = nearest_descriptor(s, t, &samples);
        results.push(MatchErrors {
            descriptor: name,
            errors: geodesic_errors(&target, &matched, &truth)?,
            source_bump: source_bump.clone(),
            matched_bump: matched
                .iter()
                .map(|&m| bump_of(target.positions()[m]))
                .collect(),
        });
    }
    let [hks, dks]: [MatchErrors; 2] = results.try_into().expect("two descriptors");
    Ok((source, target, [hks, dks]))
}
