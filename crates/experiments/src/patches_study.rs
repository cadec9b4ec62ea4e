//! Which factor limits the purity of experiment 2 ([`crate::patches`]; paper §6.1, Fig. 10)?
//! The study varies one factor at a time from the default — the texture classes, the well's
//! radius against the texture's wavelength, the mesh resolution (each needs new spectra), and
//! the eigenvalue count, transform and normalisation of the distance ([`SpectralFeatures`],
//! derived from the same spectra) — and scores relative Dirac against Laplace (the control)
//! with the paper's protocol: 10 classes × 10 patches, mean purity of k-means with k = 10
//! over many random starts.

use std::time::Instant;

use dirac::spectrum::{Normalization, SolverBackend};

use crate::ExperimentError;
use crate::metrics::mean_kmeans_purity;
use crate::patches::{PatchConfig, TextureSet, patches, well};
use crate::plots::class_means;
use crate::spectra::{LAPLACE, OperatorSpectra, RELATIVE_DIRAC, compute_spectra};
use crate::spectral_features::{EigenvalueTransform, FeatureScaling, SpectralFeatures};

/// Eigenvalues computed per spectrum in the study: the most any [`feature_variants`] uses.
pub const STUDY_EIGENVALUES: usize = 40;

/// Kept radius of a patch beyond its well's radius (the paper: no boundary point inside the
/// region of interest).
pub const PATCH_MARGIN: f64 = 0.05;

/// One setting of the patches: texture classes and sizes (every setting needs its own spectra).
#[derive(Debug, Clone, PartialEq)]
pub struct StudySetting {
    /// The factor changed from the default (`default` for the default itself).
    pub factor: &'static str,
    /// Its value, for tables.
    pub value: String,
    /// The texture classes.
    pub textures: TextureSet,
    /// Factor on every class's texture frequency (1 for the set as defined).
    pub frequency_scale: f64,
    /// Sizes, radii and the number of eigenvalues.
    pub config: PatchConfig,
}

impl StudySetting {
    /// The default of [`crate::patches`] ([`TextureSet::Original`], [`PatchConfig::DEFAULT`])
    /// with [`STUDY_EIGENVALUES`] eigenvalues.
    pub fn default_setting() -> Self {
        Self {
            factor: "default",
            value: "original textures, well radius 0.85, level 4".into(),
            textures: TextureSet::Original,
            frequency_scale: 1.0,
            config: PatchConfig {
                k: STUDY_EIGENVALUES,
                ..PatchConfig::DEFAULT
            },
        }
    }

    /// The default with well radius `well_radius` and a patch of kept radius
    /// `well_radius + PATCH_MARGIN`.
    pub fn with_well_radius(well_radius: f64) -> Self {
        let default = Self::default_setting();
        Self {
            factor: "well radius",
            value: format!("{well_radius}"),
            config: PatchConfig {
                well_radius,
                radius: well_radius + PATCH_MARGIN,
                ..default.config
            },
            ..default
        }
    }

    /// The default with other texture classes.
    pub fn with_textures(textures: TextureSet) -> Self {
        Self {
            factor: "texture",
            value: textures.name().into(),
            textures,
            ..Self::default_setting()
        }
    }

    /// The default cut from an icosphere of another level.
    pub fn with_level(level: u32) -> Self {
        let default = Self::default_setting();
        Self {
            factor: "resolution",
            value: format!("level {level}"),
            config: PatchConfig {
                level,
                ..default.config
            },
            ..default
        }
    }
}

impl StudySetting {
    /// The ten classes: the texture set with the frequency scale applied.
    pub fn classes(&self) -> Vec<crate::patches::PatchClass> {
        self.textures
            .classes()
            .into_iter()
            .map(|class| crate::patches::PatchClass {
                texture: class.texture.with_frequency_scale(self.frequency_scale),
                ..class
            })
            .collect()
    }
}

/// The settings, one factor at a time from [`StudySetting::default_setting`]: the three other
/// [`TextureSet`]s, well radii 0.55, 1.15 and 1.45 (with the default's 0.85 the region of
/// interest, of effective radius about `β − 0.2`, holds 2–4 wavelengths of the original
/// textures; 1.45 about twice as many); then the two largest single effects together
/// (homogeneous noise in a well of radius 1.45); and, if `with_level_5`, the level-5
/// icosphere, alone and with the original textures at twice their frequency (the region then
/// holds 4–8 wavelengths; level 4 would resolve a wavelength by two to four edges only).
pub fn settings(with_level_5: bool) -> Vec<StudySetting> {
    let mut settings = vec![
        StudySetting::default_setting(),
        StudySetting::with_textures(TextureSet::Homogeneous),
        StudySetting::with_textures(TextureSet::AmplitudeOnly),
        StudySetting::with_textures(TextureSet::FrequencyOnly),
        StudySetting::with_well_radius(0.55),
        StudySetting::with_well_radius(1.15),
        StudySetting::with_well_radius(1.45),
        StudySetting {
            factor: "texture + well radius",
            value: "homogeneous noise, 1.45".into(),
            textures: TextureSet::Homogeneous,
            ..StudySetting::with_well_radius(1.45)
        },
    ];
    if with_level_5 {
        settings.push(StudySetting::with_level(5));
        settings.push(StudySetting {
            factor: "frequency (level 5)",
            value: "original textures × 2 frequency, level 5".into(),
            frequency_scale: 2.0,
            ..StudySetting::with_level(5)
        });
    }
    settings
}

/// The distance variants, one factor at a time from [`SpectralFeatures::PAPER`] (20 × `|λ|`,
/// no normalisation), each with the factor it changes: 10 and 40 eigenvalues; signed `λ`,
/// `λ²`, `log|λ|`; division by the first nonzero eigenvalue, per-index standardisation.
pub fn feature_variants() -> Vec<(&'static str, SpectralFeatures)> {
    let paper = SpectralFeatures::PAPER;
    let mut variants = vec![("default", paper)];
    for count in [10, STUDY_EIGENVALUES] {
        variants.push(("eigenvalues", SpectralFeatures { count, ..paper }));
    }
    for transform in [
        EigenvalueTransform::Signed,
        EigenvalueTransform::Squared,
        EigenvalueTransform::LogMagnitude,
    ] {
        variants.push(("transform", SpectralFeatures { transform, ..paper }));
    }
    for scaling in [FeatureScaling::FirstNonzero, FeatureScaling::Standardised] {
        variants.push(("normalisation", SpectralFeatures { scaling, ..paper }));
    }
    variants
}

/// The k-means protocol: random starts and their seed (the paper: 500 starts).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Protocol {
    /// k-means random starts.
    pub starts: usize,
    /// Seed of the starts.
    pub seed: u64,
}

/// The spectra of one setting's patches under relative Dirac and Laplace.
#[derive(Debug, Clone, PartialEq)]
pub struct SettingSpectra {
    /// The setting.
    pub setting: StudySetting,
    /// Class of every patch.
    pub labels: Vec<usize>,
    /// Fewest and most vertices of a patch.
    pub vertices: (usize, usize),
    /// Relative Dirac, then Laplace.
    pub tables: Vec<OperatorSpectra>,
    /// Wall-clock seconds: patches and spectra.
    pub seconds: f64,
}

/// The patches of `setting` and their [`StudySetting::config`]`.k` eigenvalues under relative
/// Dirac and Laplace, inside the well, with `backend`.
pub fn setting_spectra(
    setting: &StudySetting,
    backend: SolverBackend,
) -> Result<SettingSpectra, ExperimentError> {
    let start = Instant::now();
    let config = setting.config;
    let patches = patches(&config, &setting.classes())?;
    let meshes: Vec<_> = patches.iter().map(|p| p.mesh.clone()).collect();
    let sizes = meshes.iter().map(|m| m.vertex_count());
    let vertices = (sizes.clone().min().unwrap_or(0), sizes.max().unwrap_or(0));
    let tables = compute_spectra(
        &meshes,
        &[RELATIVE_DIRAC, LAPLACE],
        config.k,
        backend,
        Normalization::None,
        &|i| Some(well(&config, &patches[i])),
    )?;
    Ok(SettingSpectra {
        setting: setting.clone(),
        labels: patches.iter().map(|p| p.class).collect(),
        vertices,
        tables,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// One row of the study: a setting, a distance variant and the mean k-means purity of each
/// operator.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyRow {
    /// The factor changed (of the setting or of the distance).
    pub factor: &'static str,
    /// The setting's value.
    pub setting: String,
    /// The distance variant.
    pub features: SpectralFeatures,
    /// Mean purity of relative Dirac.
    pub relative_dirac: f64,
    /// Mean purity of Laplace.
    pub laplace: f64,
}

impl SettingSpectra {
    /// The mean k-means purity (k = number of classes) of both operators under `features`,
    /// labelled with `factor`.
    pub fn score(
        &self,
        factor: &'static str,
        features: SpectralFeatures,
        protocol: Protocol,
    ) -> Result<StudyRow, ExperimentError> {
        let classes = self.labels.iter().max().map_or(0, |m| m + 1);
        let purity = |table: &OperatorSpectra| -> Result<f64, ExperimentError> {
            Ok(mean_kmeans_purity(
                &features.vectors(&table.spectra)?,
                &self.labels,
                classes,
                protocol.starts,
                protocol.seed,
            ))
        };
        Ok(StudyRow {
            factor,
            setting: self.setting.value.clone(),
            features,
            relative_dirac: purity(&self.tables[0])?,
            laplace: purity(&self.tables[1])?,
        })
    }
}

/// The purity the k-means protocol reaches on ideal data: every point replaced by its class's
/// centroid (`points` the feature vectors, `labels` their classes), so classes are single
/// points at their actual mutual distances and only the k-means initialisation can lose
/// purity. Lloyd's iteration from `k` random points leaves two classes merged whenever two
/// initial centres fall in one class, so this is below 1 even for perfectly separated classes.
pub fn kmeans_ceiling(points: &[Vec<f64>], labels: &[usize], protocol: Protocol) -> f64 {
    let classes = labels.iter().max().map_or(0, |m| m + 1);
    let names: Vec<String> = (0..classes).map(|c| c.to_string()).collect();
    let centroids = class_means(points, labels, &names);
    let ideal: Vec<Vec<f64>> = labels
        .iter()
        .map(|&l| centroids[l].values.clone())
        .collect();
    mean_kmeans_purity(&ideal, labels, classes, protocol.starts, protocol.seed)
}

/// [`kmeans_ceiling`] when all classes are equidistant: class `c` at the unit vector `e_c`.
pub fn simplex_ceiling(labels: &[usize], protocol: Protocol) -> f64 {
    let classes = labels.iter().max().map_or(0, |m| m + 1);
    let points: Vec<Vec<f64>> = labels
        .iter()
        .map(|&l| (0..classes).map(|c| f64::from(u8::from(c == l))).collect())
        .collect();
    kmeans_ceiling(&points, labels, protocol)
}

impl SettingSpectra {
    /// [`kmeans_ceiling`] of relative Dirac and of Laplace under `features`.
    pub fn ceilings(
        &self,
        features: SpectralFeatures,
        protocol: Protocol,
    ) -> Result<[f64; 2], ExperimentError> {
        let ceiling = |table: &OperatorSpectra| -> Result<f64, ExperimentError> {
            Ok(kmeans_ceiling(
                &features.vectors(&table.spectra)?,
                &self.labels,
                protocol,
            ))
        };
        Ok([ceiling(&self.tables[0])?, ceiling(&self.tables[1])?])
    }
}

/// A Markdown table of study rows: factor, setting, distance, purity of relative Dirac and of
/// Laplace (%). The `|` of `|λ|` is escaped so that it does not split the cell.
pub fn format_study(rows: &[StudyRow]) -> String {
    let mut out = String::from(
        "| factor | setting | distance | relative Dirac | Laplace |\n|---|---|---|---|---|\n",
    );
    for row in rows {
        out.push_str(&format!(
            "| {} | {} | {} | {:.1} | {:.1} |\n",
            row.factor,
            row.setting,
            row.features.describe().replace('|', "\\|"),
            100.0 * row.relative_dirac,
            100.0 * row.laplace
        ));
    }
    out
}
