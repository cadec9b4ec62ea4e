//! Experiment 1 (paper Fig. 8): one base torus (`R = 1`, `r = 0.4`) with several kinds of
//! added detail — bumps, ridges, noise, each at two amplitudes — and several random
//! tessellations of every textured surface. The texture is the class; the tessellation is the
//! nuisance an operator must see through.

use dirac::TriMesh;
use dirac::generators::{Detail, RandomTessellation, Torus};

use crate::ExperimentError;

/// Major radius of the base torus.
pub const MAJOR_RADIUS: f64 = 1.0;
/// Tube radius of the base torus.
pub const MINOR_RADIUS: f64 = 0.4;
/// The two detail amplitudes (in units of the major radius).
pub const AMPLITUDES: [f64; 2] = [0.015, 0.03];
/// Largest vertex offset of the random tessellations, in grid spacings.
pub const JITTER: f64 = 0.25;

/// A texture class: a name and the detail added to the base torus.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureClass {
    /// Name for the tables and plots (`bumps 0.015`, …).
    pub name: String,
    /// The detail.
    pub detail: Detail,
}

/// The six classes: bumps (`cos 12u · cos 6v`), ridges (10 sharp crests around the tube) and
/// smooth noise (fixed seed), each at the two [`AMPLITUDES`].
pub fn texture_classes() -> Vec<TextureClass> {
    let mut classes = Vec::new();
    for amplitude in AMPLITUDES {
        for (kind, detail) in [
            (
                "bumps",
                Detail::Bumps {
                    amplitude,
                    frequency: [12, 6],
                },
            ),
            (
                "ridges",
                Detail::Ridges {
                    amplitude,
                    frequency: 10,
                },
            ),
            (
                "noise",
                Detail::Noise {
                    amplitude,
                    seed: 2017,
                },
            ),
        ] {
            classes.push(TextureClass {
                name: format!("{kind} {amplitude}"),
                detail,
            });
        }
    }
    classes
}

/// Sizes of the experiment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ToriConfig {
    /// Grid points around the major circle (the tube gets half as many).
    pub major_segments: usize,
    /// Random tessellations per texture class.
    pub tessellations: usize,
    /// Eigenvalues per spectrum.
    pub k: usize,
}

impl ToriConfig {
    /// Quick default: 64 × 32 grid (2048 vertices), 4 tessellations, 60 eigenvalues.
    pub const DEFAULT: Self = Self {
        major_segments: 64,
        tessellations: 4,
        k: 60,
    };
    /// `--full`: 96 × 48 grid (4608 vertices), 10 tessellations, 60 eigenvalues.
    pub const FULL: Self = Self {
        major_segments: 96,
        tessellations: 10,
        k: 60,
    };
}

/// A generated mesh with its class.
#[derive(Debug, Clone)]
pub struct LabelledMesh {
    /// Index into the class list.
    pub class: usize,
    /// The mesh.
    pub mesh: TriMesh,
}

/// Every class × tessellation: tessellation `t` of class `c` uses seed `1000 c + t`.
pub fn meshes(
    config: &ToriConfig,
    classes: &[TextureClass],
) -> Result<Vec<LabelledMesh>, ExperimentError> {
    let mut meshes = Vec::with_capacity(classes.len() * config.tessellations);
    for (class, texture) in classes.iter().enumerate() {
        for t in 0..config.tessellations {
            let torus = Torus {
                detail: texture.detail,
                tessellation: Some(RandomTessellation {
                    jitter: JITTER,
                    seed: 1000 * class as u64 + t as u64,
                }),
                ..Torus::new(
                    MAJOR_RADIUS,
                    MINOR_RADIUS,
                    config.major_segments,
                    config.major_segments / 2,
                )
            };
            meshes.push(LabelledMesh {
                class,
                mesh: torus.mesh()?,
            });
        }
    }
    Ok(meshes)
}
