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

/// A displacement texture on the unit sphere, `f(p)` for `|p| = 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Texture {
    /// `f = (1/n) Σ_m cos(a p·d_m + φ_m)` over `n = directions` unit directions `d_m` and
    /// phases `φ_m ∈ [0, 2π)` drawn from `seed` (`|f| ≤ 1`): an egg-crate for a few
    /// directions, noise of wavelength `2π/a` for many, parallel waves for one. Not
    /// homogeneous for few directions: on the sphere the local frequency of the wave along `d`
    /// is `a sin θ` (`θ` the angle to `d`), from `a` at its equator down to 0 at its poles, so
    /// patches cut at different places carry different textures.
    Waves {
        /// Spatial frequency `a`.
        frequency: f64,
        /// Number of plane waves `n ≥ 1`.
        directions: usize,
        /// Seed of the directions and phases.
        seed: u64,
    },
    /// Sharp-crested ridges `f = 1 − 2|sin(a p·d / 2)|` across the fixed axis
    /// `d ∝ (0.3, 0.5, 0.8)` (`|f| ≤ 1`; inhomogeneous like [`Texture::Waves`]).
    Ridges {
        /// Spatial frequency `a`.
        frequency: f64,
    },
    /// Statistically homogeneous, isotropic noise shaped by a [`NoiseProfile`]: the profile
    /// applied to `g = √(2/n) Σ_m cos(a p·d_m + φ_m)` over [`NOISE_DIRECTIONS`] directions
    /// `d_m` uniform on the sphere and phases `φ_m` uniform in `[0, 2π)`, drawn from `seed`.
    /// At every `p`, `g` has mean 0 and variance 1 over the draws and is close to Gaussian;
    /// since the directions are uniform, the distribution of the local texture is the same
    /// wherever a patch is cut (every local frequency `a sin θ_m` is present everywhere).
    Noise {
        /// Spatial frequency `a` of every plane wave.
        frequency: f64,
        /// Shape of the relief.
        profile: NoiseProfile,
        /// Seed of the directions and phases.
        seed: u64,
    },
}

/// Plane waves of every [`Texture::Noise`].
pub const NOISE_DIRECTIONS: usize = 64;

/// How [`Texture::Noise`] turns the Gaussian-like field `g` (mean 0, variance 1) into relief;
/// each profile has mean 0 and variance 1 when `g` is standard Gaussian.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoiseProfile {
    /// `f = g`: smooth rolling relief.
    Smooth,
    /// `f = (√(2/π) − |g|) / √(1 − 2/π)`: a network of sharp crests along `g = 0`.
    Ridged,
    /// `f = −(√(2/π) − |g|) / √(1 − 2/π)`: the ridged relief inverted, sharp creases down.
    Pitted,
}

impl NoiseProfile {
    /// The profile applied to `g`.
    pub fn apply(self, g: f64) -> f64 {
        // E|g| = √(2/π) and Var|g| = 1 − 2/π for a standard Gaussian g.
        let mean_abs = (2.0 / std::f64::consts::PI).sqrt();
        let sd_abs = (1.0 - 2.0 / std::f64::consts::PI).sqrt();
        match self {
            NoiseProfile::Smooth => g,
            NoiseProfile::Ridged => (mean_abs - g.abs()) / sd_abs,
            NoiseProfile::Pitted => (g.abs() - mean_abs) / sd_abs,
        }
    }
}

/// `count` plane waves: unit directions uniform on the sphere with phases uniform in
/// `[0, 2π)`, from `seed`.
fn random_waves(seed: u64, count: usize) -> Vec<([f64; 3], f64)> {
    let mut rng = SplitMix64::new(seed);
    (0..count)
        .map(|_| {
            let direction = uniform_direction(&mut rng);
            (direction, rng.uniform(0.0, TAU))
        })
        .collect()
}

/// A direction uniform on the unit sphere (Archimedes: `z` uniform in `[−1, 1]`, azimuth
/// uniform).
fn uniform_direction(rng: &mut SplitMix64) -> [f64; 3] {
    let z = rng.uniform(-1.0, 1.0);
    let azimuth = rng.uniform(0.0, TAU);
    let s = (1.0 - z * z).sqrt();
    [s * azimuth.cos(), s * azimuth.sin(), z]
}

/// `Σ_m cos(a p·d_m + φ_m)`.
fn wave_sum(waves: &[([f64; 3], f64)], frequency: f64, p: [f64; 3]) -> f64 {
    waves
        .iter()
        .map(|&(d, phase)| (frequency * dot(p, d) + phase).cos())
        .sum()
}

impl Texture {
    /// The same texture with its spatial frequency multiplied by `scale` (wavelength divided).
    pub fn with_frequency_scale(self, scale: f64) -> Self {
        match self {
            Texture::Waves {
                frequency,
                directions,
                seed,
            } => Texture::Waves {
                frequency: frequency * scale,
                directions,
                seed,
            },
            Texture::Ridges { frequency } => Texture::Ridges {
                frequency: frequency * scale,
            },
            Texture::Noise {
                frequency,
                profile,
                seed,
            } => Texture::Noise {
                frequency: frequency * scale,
                profile,
                seed,
            },
        }
    }

    /// `f` as a function of the unit vector `p`.
    pub fn function(&self) -> Box<dyn Fn([f64; 3]) -> f64> {
        match *self {
            Texture::Waves {
                frequency,
                directions,
                seed,
            } => {
                let waves = random_waves(seed, directions.max(1));
                let count = waves.len() as f64;
                Box::new(move |p| wave_sum(&waves, frequency, p) / count)
            }
            Texture::Ridges { frequency } => {
                let axis = normalize([0.3, 0.5, 0.8]);
                Box::new(move |p| 1.0 - 2.0 * (frequency * dot(p, axis) / 2.0).sin().abs())
            }
            Texture::Noise {
                frequency,
                profile,
                seed,
            } => {
                let waves = random_waves(seed, NOISE_DIRECTIONS);
                let normalization = (2.0 / NOISE_DIRECTIONS as f64).sqrt();
                Box::new(move |p| profile.apply(normalization * wave_sum(&waves, frequency, p)))
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
    every_texture_at_every_amplitude(&textures, &AMPLITUDES)
}

/// One class per amplitude and texture, amplitude-major, named `"<texture> <amplitude>"`.
fn every_texture_at_every_amplitude(
    textures: &[(&str, Texture)],
    amplitudes: &[f64],
) -> Vec<PatchClass> {
    amplitudes
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

/// The texture classes a study of the experiment can use (10 classes each).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureSet {
    /// [`patch_classes`]: five plane-wave textures at two amplitudes (not homogeneous on the
    /// sphere, see [`Texture::Waves`]).
    Original,
    /// [`homogeneous_classes`]: five [`Texture::Noise`] textures at two amplitudes.
    Homogeneous,
    /// [`amplitude_classes`]: one noise texture at ten amplitudes.
    AmplitudeOnly,
    /// [`frequency_classes`]: one noise profile at ten frequencies.
    FrequencyOnly,
}

impl TextureSet {
    /// The ten classes of the set.
    pub fn classes(self) -> Vec<PatchClass> {
        match self {
            TextureSet::Original => patch_classes(),
            TextureSet::Homogeneous => homogeneous_classes(),
            TextureSet::AmplitudeOnly => amplitude_classes(),
            TextureSet::FrequencyOnly => frequency_classes(),
        }
    }

    /// A short name for tables.
    pub fn name(self) -> &'static str {
        match self {
            TextureSet::Original => "original plane waves",
            TextureSet::Homogeneous => "homogeneous noise",
            TextureSet::AmplitudeOnly => "amplitude only",
            TextureSet::FrequencyOnly => "frequency only",
        }
    }
}

/// The two RMS amplitudes of [`homogeneous_classes`]: half of [`AMPLITUDES`], because the
/// noise has unit variance while the original textures have an RMS of about half their peak
/// (0.2 for 12 waves to 0.7 for one), so that both sets carry relief of comparable height.
pub const HOMOGENEOUS_AMPLITUDES: [f64; 2] = [0.0075, 0.015];

/// Ten classes of statistically homogeneous [`Texture::Noise`]: smooth noise of frequency 10
/// and 18, ridged noise of frequency 10 and 18, pitted noise of frequency 14, each at the two
/// [`HOMOGENEOUS_AMPLITUDES`].
pub fn homogeneous_classes() -> Vec<PatchClass> {
    let noise = |frequency, profile, seed| Texture::Noise {
        frequency,
        profile,
        seed,
    };
    let textures = [
        ("smooth", noise(10.0, NoiseProfile::Smooth, 11)),
        ("fine smooth", noise(18.0, NoiseProfile::Smooth, 12)),
        ("ridged", noise(10.0, NoiseProfile::Ridged, 13)),
        ("fine ridged", noise(18.0, NoiseProfile::Ridged, 14)),
        ("pitted", noise(14.0, NoiseProfile::Pitted, 15)),
    ];
    every_texture_at_every_amplitude(&textures, &HOMOGENEOUS_AMPLITUDES)
}

/// Ten classes that differ only in amplitude: smooth noise of frequency 14 (one seed) at RMS
/// amplitudes `0.004 · 1.25^c`, `c = 0, …, 9` (0.004 to 0.030).
pub fn amplitude_classes() -> Vec<PatchClass> {
    let texture = Texture::Noise {
        frequency: 14.0,
        profile: NoiseProfile::Smooth,
        seed: 21,
    };
    (0..10)
        .map(|c| {
            let amplitude = 0.004 * 1.25f64.powi(c);
            PatchClass {
                name: format!("amplitude {amplitude:.4}"),
                texture,
                amplitude,
            }
        })
        .collect()
}

/// Ten classes that differ only in frequency: smooth noise (one seed) of RMS amplitude 0.01 at
/// frequencies `6 · 1.15^c`, `c = 0, …, 9` (6 to 21; the finest wavelength still spans about
/// four edges of the level-4 icosphere).
pub fn frequency_classes() -> Vec<PatchClass> {
    (0..10)
        .map(|c| {
            let frequency = 6.0 * 1.15f64.powi(c);
            PatchClass {
                name: format!("frequency {frequency:.1}"),
                texture: Texture::Noise {
                    frequency,
                    profile: NoiseProfile::Smooth,
                    seed: 22,
                },
                amplitude: 0.01,
            }
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
            let center = uniform_direction(&mut SplitMix64::new(seed));
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
