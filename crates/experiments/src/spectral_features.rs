//! What a spectrum becomes before the Euclidean distance of paper §6.1: how many eigenvalues,
//! which function of each, and which normalisation. The paper compares the spectra themselves
//! (`|λ|` for the Dirac-type operators, §7); [`SpectralFeatures`] names the alternatives the
//! patch study measures, all derived from one computed spectrum per shape.

use crate::ExperimentError;

/// The function applied to every eigenvalue `λ` (spectra are ordered by `|λ|`, and that order
/// is kept).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EigenvalueTransform {
    /// `|λ|` (the paper's default for the Dirac-type operators, §7).
    Magnitude,
    /// `λ` with its sign.
    Signed,
    /// `λ²` (for `D_N` the eigenvalues of `D_N²`, the operator the family interpolates).
    Squared,
    /// `ln|λ|`: the Euclidean distance of these is, to first order in the differences, twice
    /// the relative distance `(Σ_i (|λ_i − μ_i| / (|λ_i| + |μ_i|))²)^{1/2}`, so large and small
    /// eigenvalues weigh alike. Fails on `λ = 0`.
    LogMagnitude,
}

impl EigenvalueTransform {
    /// The name used in tables: `|λ|`, `λ`, `λ²`, `log|λ|`.
    pub fn name(self) -> &'static str {
        match self {
            EigenvalueTransform::Magnitude => "|λ|",
            EigenvalueTransform::Signed => "λ",
            EigenvalueTransform::Squared => "λ²",
            EigenvalueTransform::LogMagnitude => "log|λ|",
        }
    }
}

/// A normalisation of the transformed vectors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FeatureScaling {
    /// None: the Euclidean distance of the transformed eigenvalues.
    None,
    /// Each shape's vector divided by the magnitude of its first entry whose `|λ|` exceeds
    /// [`NONZERO`] times its largest `|λ|` (the first nonzero eigenvalue): removes the overall
    /// scale of a spectrum and keeps its shape. Applied to the transformed values; for
    /// `log|λ|` it subtracts the first nonzero `ln|λ|` instead (the same scale removal).
    FirstNonzero,
    /// Every coordinate `i` divided by its standard deviation over all shapes (a diagonal
    /// Mahalanobis distance; no labels used): every eigenvalue index weighs alike. A
    /// coordinate constant over the collection is left as is.
    Standardised,
}

impl FeatureScaling {
    /// The name used in tables.
    pub fn name(self) -> &'static str {
        match self {
            FeatureScaling::None => "none",
            FeatureScaling::FirstNonzero => "÷ first nonzero",
            FeatureScaling::Standardised => "standardised",
        }
    }
}

/// `|λ| ≤ NONZERO · max|λ|` counts as zero for [`FeatureScaling::FirstNonzero`].
pub const NONZERO: f64 = 1e-8;

/// One way to turn spectra into vectors for the Euclidean distance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SpectralFeatures {
    /// The number of eigenvalues kept (the first, by `|λ|`).
    pub count: usize,
    /// The function of every eigenvalue.
    pub transform: EigenvalueTransform,
    /// The normalisation after the transform.
    pub scaling: FeatureScaling,
}

impl SpectralFeatures {
    /// The paper's protocol with this experiment's 20 eigenvalues: `|λ|`, no normalisation.
    pub const PAPER: Self = Self {
        count: 20,
        transform: EigenvalueTransform::Magnitude,
        scaling: FeatureScaling::None,
    };

    /// A short description for tables: `20 × |λ|, none`.
    pub fn describe(&self) -> String {
        format!(
            "{} × {}, {}",
            self.count,
            self.transform.name(),
            self.scaling.name()
        )
    }

    /// The feature vector of every spectrum (`spectra[s]` the eigenvalues of shape `s` ordered
    /// by `|λ|`). Errors name the shape: a spectrum shorter than `count`, `λ = 0` under
    /// `log|λ|`, a spectrum without a nonzero eigenvalue under
    /// [`FeatureScaling::FirstNonzero`].
    pub fn vectors(&self, spectra: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, ExperimentError> {
        let mut vectors = spectra
            .iter()
            .enumerate()
            .map(|(shape, spectrum)| self.shape_vector(shape, spectrum))
            .collect::<Result<Vec<_>, _>>()?;
        if self.scaling == FeatureScaling::Standardised {
            standardise(&mut vectors);
        }
        Ok(vectors)
    }

    /// The transform and the per-shape scaling of one spectrum.
    fn shape_vector(&self, shape: usize, spectrum: &[f64]) -> Result<Vec<f64>, ExperimentError> {
        if spectrum.len() < self.count {
            return Err(ExperimentError::TooFewEigenvalues {
                shape,
                available: spectrum.len(),
                wanted: self.count,
            });
        }
        let kept = &spectrum[..self.count];
        let mut vector = kept
            .iter()
            .enumerate()
            .map(|(index, &lambda)| match self.transform {
                EigenvalueTransform::Magnitude => Ok(lambda.abs()),
                EigenvalueTransform::Signed => Ok(lambda),
                EigenvalueTransform::Squared => Ok(lambda * lambda),
                EigenvalueTransform::LogMagnitude if lambda == 0.0 => {
                    Err(ExperimentError::ZeroEigenvalue { shape, index })
                }
                EigenvalueTransform::LogMagnitude => Ok(lambda.abs().ln()),
            })
            .collect::<Result<Vec<f64>, _>>()?;
        if self.scaling == FeatureScaling::FirstNonzero {
            let largest = kept.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let first = kept
                .iter()
                .position(|v| v.abs() > NONZERO * largest)
                .ok_or(ExperimentError::NoNonzeroEigenvalue { shape })?;
            let pivot = vector[first];
            if self.transform == EigenvalueTransform::LogMagnitude {
                vector.iter_mut().for_each(|v| *v -= pivot);
            } else {
                vector.iter_mut().for_each(|v| *v /= pivot.abs());
            }
        }
        Ok(vector)
    }
}

/// Divides every coordinate by its (population) standard deviation over the vectors, leaving
/// constant coordinates as they are.
fn standardise(vectors: &mut [Vec<f64>]) {
    let n = vectors.len() as f64;
    let dimension = vectors.first().map_or(0, Vec::len);
    for i in 0..dimension {
        let mean = vectors.iter().map(|v| v[i]).sum::<f64>() / n;
        let variance = vectors.iter().map(|v| (v[i] - mean).powi(2)).sum::<f64>() / n;
        if variance > 0.0 {
            let sd = variance.sqrt();
            vectors.iter_mut().for_each(|v| v[i] /= sd);
        }
    }
}
