//! Experiment 2 (paper Fig. 7, Fig. 10): textured surface patches with ragged boundaries.
//!
//! Each texture class is a unit sphere displaced along its normal, `p ↦ p (1 + h f(p))` for
//! `|p| = 1`, with a texture `f` ([`Texture`], `|f| ≤ 1`) and amplitude `h`. A patch is a
//! [`SpherePatch`] of the plain icosphere around a random centre with a random ragged boundary,
//! displaced by its class's texture afterwards, so patches of one class differ in where they
//! were cut from the textured surface and in their boundary. Spectra are computed inside the
//! infinite potential well ([`well`]) centred on the vertex nearest the patch centre.

use std::f64::consts::TAU;

use dirac::TriMesh;
use dirac::generators::SpherePatch;
use dirac::geometry::{dot, normalize, scale};
use dirac::well::PotentialWell;
use qscalar::random::SplitMix64;

use crate::ExperimentError;

/// A displacement texture on the unit sphere, `f(p)` with `|f| ≤ 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Texture {
    /// `f = (1/n) Σ_m cos(a p·d_m + φ_m)` over `n = directions` unit directions `d_m` and
    /// phases `φ_m ∈ [0, 2π)` drawn from `seed`: an egg-crate for a few directions, isotropic
    /// noise of wavelength `2π/a` for many, parallel waves for one.
    Waves {
        /// Spatial frequency `a`.
        frequency: f64,
        /// Number of plane waves `n ≥ 1`.
        directions: usize,
        /// Seed of the directions and phases.
        seed: u64,
    },
    /// Sharp-crested ridges `f = 1 − 2|sin(a p·d / 2)|` across the fixed axis
    /// `d ∝ (0.3, 0.5, 0.8)`.
    Ridges {
        /// Spatial frequency `a`.
        frequency: f64,
    },
}

impl Texture {
    /// `f` as a function of the unit vector `p`.
    pub fn function(&self) -> Box<dyn Fn([f64; 3]) -> f64> {
        match *self {
            Texture::Waves {
                frequency,
                directions,
                seed,
            } => {
                let mut rng = SplitMix64::new(seed);
                let waves: Vec<([f64; 3], f64)> = (0..directions.max(1))
                    .map(|_| {
                        let z = rng.uniform(-1.0, 1.0);
                        let azimuth = rng.uniform(0.0, TAU);
                        let s = (1.0 - z * z).sqrt();
                        let d = [s * azimuth.cos(), s * azimuth.sin(), z];
                        (d, rng.uniform(0.0, TAU))
                    })
                    .collect();
                Box::new(move |p| {
                    waves
                        .iter()
                        .map(|&(d, phase)| (frequency * dot(p, d) + phase).cos())
                        .sum::<f64>()
                        / waves.len() as f64
                })
            }
            Texture::Ridges { frequency } => {
                let axis = normalize([0.3, 0.5, 0.8]);
                Box::new(move |p| 1.0 - 2.0 * (frequency * dot(p, axis) / 2.0).sin().abs())
            }
        }
    }
}

/// A texture class: name, texture and amplitude `h`.
#[derive(Debug, Clone, PartialEq)]
pub struct PatchClass {
    /// Name for the tables and plots.
    pub name: String,
    /// The texture `f`.
    pub texture: Texture,
    /// The amplitude `h`.
    pub amplitude: f64,
}

/// The two amplitudes of every texture (the sphere has radius 1).
pub const AMPLITUDES: [f64; 2] = [0.015, 0.03];

/// Ten classes: five textures (coarse and fine egg-crate bumps, parallel waves, sharp ridges,
/// isotropic noise), each at the two [`AMPLITUDES`].
pub fn patch_classes() -> Vec<PatchClass> {
    let textures = [
        (
            "bumps",
            Texture::Waves {
                frequency: 10.0,
                directions: 3,
                seed: 1,
            },
        ),
        (
            "fine bumps",
            Texture::Waves {
                frequency: 18.0,
                directions: 3,
                seed: 2,
            },
        ),
        (
            "waves",
            Texture::Waves {
                frequency: 14.0,
                directions: 1,
                seed: 3,
            },
        ),
        ("ridges", Texture::Ridges { frequency: 14.0 }),
        (
            "noise",
            Texture::Waves {
                frequency: 14.0,
                directions: 12,
                seed: 5,
            },
        ),
    ];
    AMPLITUDES
        .iter()
        .flat_map(|&amplitude| {
            textures.iter().map(move |&(name, texture)| PatchClass {
                name: format!("{name} {amplitude}"),
                texture,
                amplitude,
            })
        })
        .collect()
}

/// Sizes and shape of the experiment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchConfig {
    /// Icosphere level the patches are cut from.
    pub level: u32,
    /// Patches per class.
    pub per_class: usize,
    /// Eigenvalues per spectrum.
    pub k: usize,
    /// Geodesic radius (radians) every patch keeps.
    pub radius: f64,
    /// Extra reach of the ragged band (radians).
    pub raggedness: f64,
    /// Radius `β` of the potential well.
    pub well_radius: f64,
}

impl PatchConfig {
    /// Quick default: the paper's 100 patches (10 classes × 10) cut from a level-4 icosphere
    /// (about 700 vertices each), 20 eigenvalues, kept radius 0.9, ragged band 0.3, well
    /// radius 0.85.
    pub const DEFAULT: Self = Self {
        level: 4,
        per_class: 10,
        k: 20,
        radius: 0.9,
        raggedness: 0.3,
        well_radius: 0.85,
    };
    /// `--full`: the same from a level-5 icosphere (about 2600 vertices each).
    pub const FULL: Self = Self {
        level: 5,
        ..Self::DEFAULT
    };
}

/// One patch with its class and centre vertex.
#[derive(Debug, Clone)]
pub struct Patch {
    /// Index into the class list.
    pub class: usize,
    /// The displaced patch.
    pub mesh: TriMesh,
    /// The vertex nearest the patch centre (the centre of its well).
    pub center: usize,
}

/// Patch `i` of class `c` (seeded by `100 c + i`): a uniformly random centre direction and a
/// random ragged boundary, then the displacement `p (1 + h f(p))`.
pub fn patches(
    config: &PatchConfig,
    classes: &[PatchClass],
) -> Result<Vec<Patch>, ExperimentError> {
    let mut patches = Vec::with_capacity(classes.len() * config.per_class);
    for (class, texture) in classes.iter().enumerate() {
        let f = texture.texture.function();
        for i in 0..config.per_class {
            let seed = 100 * class as u64 + i as u64;
            let mut rng = SplitMix64::new(seed);
            let z = rng.uniform(-1.0, 1.0);
            let azimuth = rng.uniform(0.0, TAU);
            let s = (1.0 - z * z).sqrt();
            let center = [s * azimuth.cos(), s * azimuth.sin(), z];
            let plain = SpherePatch {
                level: config.level,
                center,
                radius: config.radius,
                raggedness: config.raggedness,
                bump_amplitude: 0.0,
                seed,
            }
            .mesh()?;
            let mesh = plain.map_positions(|p| {
                let unit = normalize(p);
                scale(unit, 1.0 + texture.amplitude * f(unit))
            })?;
            let center_vertex = (0..plain.vertex_count())
                .max_by(|&a, &b| {
                    dot(plain.positions()[a], center).total_cmp(&dot(plain.positions()[b], center))
                })
                .unwrap_or(0);
            patches.push(Patch {
                class,
                mesh,
                center: center_vertex,
            });
        }
    }
    Ok(patches)
}

/// The paper's well (`γ = 100`, `c = 10¹⁰`) of radius `config.well_radius` around the patch
/// centre.
pub fn well(config: &PatchConfig, patch: &Patch) -> PotentialWell {
    PotentialWell {
        center: Some(patch.center),
        ..PotentialWell::with_radius(config.well_radius)
    }
}
