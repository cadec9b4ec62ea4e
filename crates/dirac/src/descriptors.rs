//! Per-vertex spectral descriptors (paper §6.2–6.3; docs/MATH.md,
//! "Per-vertex descriptors"): the heat, Dirac and wave
//! kernel signatures and the segmentation descriptor, computed from eigenpairs `(λ_i, φ_i)`.
//!
//! Conventions shared by every descriptor:
//!
//! - `φ_i ∈ Hⁿ` holds one quaternion per vertex and is mass-orthonormal,
//!   `Σ_p Ā_p conj(φ_i(p)) φ_j(p) = δ_ij` with the barycentric vertex areas `Ā_p` — what
//!   [`crate::spectrum::spectrum`] returns. Pointwise values therefore scale like `1/area`.
//! - `|φ(v)|² = w² + x² + y² + z²` is the squared quaternion norm: the paper's "sum over real
//!   components" (§6.3). It does not depend on the eigenvector's phase `φ ↦ φ c`, `|c| = 1`, and
//!   is unchanged by a rigid motion of the mesh (`φ ↦ r φ r̄`), so every descriptor is too.
//! - Only the eigenpairs given enter the sums: the descriptors are truncated expansions, and
//!   they are invariant under a change of basis inside an eigenspace only when every member of
//!   that eigenspace is included.
//! - An eigenvalue is *zero* when `|λ| ≤ 10⁻¹⁰ · max_i |λ_i|` ([`ZERO_TOLERANCE`]); the spectra
//!   of [`crate::spectrum`](mod@crate::spectrum) return the constant mode as an exact `0`. Zero modes enter the heat
//!   and Dirac kernel signatures (with weight `e⁰ = 1`, as in Sun–Ovsjanikov–Guibas), carry no
//!   energy in the wave kernel signature (`log 0 = −∞`) and are skipped by the segmentation
//!   descriptor (`1/√0`); the default samplings use the nonzero `|λ|` only.
//!
//! | descriptor | value at vertex `v`, column `j` | column parameter |
//! |---|---|---|
//! | HKS ([`heat_kernel_signature`]) | `Σ_i e^{−t_j λ_i} \|φ_i(v)\|²`, needs `λ_i ≥ 0` | time `t_j > 0` |
//! | DKS ([`dirac_kernel_signature`]) | `Σ_i e^{−t_j \|λ_i\|} \|φ_i(v)\|²` | time `t_j > 0` |
//! | WKS ([`wave_kernel_signature`]) | `Σ_i g_ij \|φ_i(v)\|² / Σ_i g_ij`, `g_ij = exp(−(e_j − ln\|λ_i\|)² / 2σ²)` | energy `e_j` |
//! | segmentation ([`segmentation_descriptor`]) | `\|φ_j(v)\| / √\|λ_j\|` over the nonzero modes | eigenvalue `λ_j` |
//!
//! The paper prints the kernel as `Σ e^{tλ_i} φ_i(x)²`; the missing minus sign is a typo, and `|λ|`
//! is needed because Dirac eigenvalues are signed (docs/MATH.md, "Sign conventions"). The
//! segmentation descriptor is the paper's `(|φ_1|/√λ_1, |φ_2|/√λ_2, …)` with `|λ|` for the same
//! reason.
//!
//! Default samplings ([`default_times`], [`default_wave_sampling`]) follow the original
//! papers; see their documentation.

use qscalar::Quat;
use thiserror::Error;

use crate::spectrum::Spectrum;

/// Number of samples (times or energies) of the default samplings: 100, as in Sun, Ovsjanikov
/// and Guibas (2009) and Aubry, Schlickewei and Cremers (2011).
pub const DEFAULT_SAMPLES: usize = 100;

/// An eigenvalue with `|λ| ≤ ZERO_TOLERANCE · max_i |λ_i|` is treated as zero.
pub const ZERO_TOLERANCE: f64 = 1e-10;

/// Why a descriptor could not be computed. Each variant names the offending element.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DescriptorError {
    /// No eigenpairs were given.
    #[error("the spectrum is empty: a descriptor needs at least one eigenpair")]
    EmptySpectrum,
    /// The numbers of eigenvalues and eigenvectors differ.
    #[error("{eigenvalues} eigenvalues but {eigenvectors} eigenvectors")]
    CountMismatch {
        /// Number of eigenvalues.
        eigenvalues: usize,
        /// Number of eigenvectors.
        eigenvectors: usize,
    },
    /// The eigenvectors have no entries (a mesh without vertices).
    #[error("the eigenvectors have no entries")]
    NoVertices,
    /// An eigenvector's length differs from the first one's.
    #[error("eigenvector {index} has {found} entries, eigenvector 0 has {expected}")]
    VectorLength {
        /// The eigenvector (0-based).
        index: usize,
        /// Length of eigenvector 0.
        expected: usize,
        /// Its length.
        found: usize,
    },
    /// An eigenvalue is NaN or infinite.
    #[error("eigenvalue {index} is {value}, not a finite number")]
    NonFiniteEigenvalue {
        /// The eigenvalue (0-based).
        index: usize,
        /// Its value.
        value: f64,
    },
    /// An eigenvector has a NaN or infinite component.
    #[error("eigenvector {index} has a non-finite entry at vertex {vertex}")]
    NonFiniteEigenvector {
        /// The eigenvector (0-based).
        index: usize,
        /// The vertex (0-based).
        vertex: usize,
    },
    /// The heat kernel signature was asked for a spectrum with a negative eigenvalue.
    #[error(
        "eigenvalue {index} is {value} < 0: the heat kernel signature needs a nonnegative \
         (Laplace) spectrum; use the Dirac kernel signature for signed spectra"
    )]
    NegativeEigenvalue {
        /// The eigenvalue (0-based).
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A time is not positive and finite.
    #[error("time {index} is {value}: times must be positive and finite")]
    BadTime {
        /// The time (0-based).
        index: usize,
        /// Its value.
        value: f64,
    },
    /// An energy is not finite.
    #[error("energy {index} is {value}, not a finite number")]
    BadEnergy {
        /// The energy (0-based).
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The width `σ` of the wave kernel's energy filter is not positive and finite.
    #[error("sigma = {0}: the width of the energy filter must be positive and finite")]
    BadSigma(f64),
    /// No times or energies were given, or a sample count of zero.
    #[error("at least one time or energy is needed")]
    NoSamples,
    /// Every eigenvalue is zero, so there is no scale to sample at and no mode to use.
    #[error("every eigenvalue is zero (|λ| ≤ {ZERO_TOLERANCE} max |λ|)")]
    NoNonzeroEigenvalue,
    /// The default wave sampling needs two distinct nonzero `|λ|` to span a range of energies.
    #[error(
        "every nonzero eigenvalue has |λ| = {0}: default WKS energies need two distinct \
         nonzero |λ| (give energies and sigma explicitly)"
    )]
    SingleScale(f64),
    /// An energy filter that misses every nonzero eigenvalue (its weights underflow to zero),
    /// so the normalised wave kernel signature is undefined there.
    #[error(
        "energy {index} (e = {energy}) lies farther than about 38 sigma = {} from every \
         ln|λ|: its filter weights vanish",
        38.0 * sigma
    )]
    EmptyBand {
        /// The energy (0-based).
        index: usize,
        /// Its value.
        energy: f64,
        /// The filter width.
        sigma: f64,
    },
}

/// Validated eigenpairs from which the descriptors are computed.
#[derive(Debug, Clone, Copy)]
pub struct Modes<'a> {
    eigenvalues: &'a [f64],
    eigenvectors: &'a [Vec<Quat<f64>>],
    /// `max_i |λ_i| · ZERO_TOLERANCE`.
    zero_threshold: f64,
}

impl<'a> Modes<'a> {
    /// Checks that there is at least one pair, one eigenvector per eigenvalue, all of the same
    /// nonzero length, and that everything is finite. The eigenvectors are assumed
    /// mass-orthonormal (see the module documentation); that is not checked.
    pub fn new(
        eigenvalues: &'a [f64],
        eigenvectors: &'a [Vec<Quat<f64>>],
    ) -> Result<Self, DescriptorError> {
        if eigenvalues.len() != eigenvectors.len() {
            return Err(DescriptorError::CountMismatch {
                eigenvalues: eigenvalues.len(),
                eigenvectors: eigenvectors.len(),
            });
        }
        let Some(first) = eigenvectors.first() else {
            return Err(DescriptorError::EmptySpectrum);
        };
        let n = first.len();
        if n == 0 {
            return Err(DescriptorError::NoVertices);
        }
        for (index, (&value, phi)) in eigenvalues.iter().zip(eigenvectors).enumerate() {
            if !value.is_finite() {
                return Err(DescriptorError::NonFiniteEigenvalue { index, value });
            }
            if phi.len() != n {
                return Err(DescriptorError::VectorLength {
                    index,
                    expected: n,
                    found: phi.len(),
                });
            }
            if let Some(vertex) = phi.iter().position(|q| !q.norm_sqr().is_finite()) {
                return Err(DescriptorError::NonFiniteEigenvector { index, vertex });
            }
        }
        let largest = eigenvalues.iter().map(|l| l.abs()).fold(0.0, f64::max);
        Ok(Self {
            eigenvalues,
            eigenvectors,
            zero_threshold: ZERO_TOLERANCE * largest,
        })
    }

    /// The eigenpairs of a computed spectrum ([`Modes::new`] on its fields).
    pub fn from_spectrum(spectrum: &'a Spectrum) -> Result<Self, DescriptorError> {
        Self::new(&spectrum.eigenvalues, &spectrum.eigenvectors)
    }

    /// Number of vertices (the length of every eigenvector).
    pub fn vertex_count(&self) -> usize {
        self.eigenvectors[0].len()
    }

    /// Number of eigenpairs.
    pub fn len(&self) -> usize {
        self.eigenvalues.len()
    }

    /// Always `false`: [`Modes::new`] rejects an empty spectrum.
    pub fn is_empty(&self) -> bool {
        self.eigenvalues.is_empty()
    }

    /// Whether eigenvalue `i` counts as zero (see [`ZERO_TOLERANCE`]).
    pub fn is_zero(&self, i: usize) -> bool {
        self.eigenvalues[i].abs() <= self.zero_threshold
    }

    /// Smallest and largest `|λ|` over the nonzero eigenvalues.
    fn nonzero_range(&self) -> Result<(f64, f64), DescriptorError> {
        let (low, high) = (0..self.len())
            .filter(|&i| !self.is_zero(i))
            .map(|i| self.eigenvalues[i].abs())
            .fold((f64::INFINITY, 0.0_f64), |(lo, hi), l| {
                (lo.min(l), hi.max(l))
            });
        if high == 0.0 {
            Err(DescriptorError::NoNonzeroEigenvalue)
        } else {
            Ok((low, high))
        }
    }

    /// `Σ_i w_ij |φ_i(v)|²` for every vertex `v` and column `j`, row-major.
    fn weighted_sums(&self, weights: &[Vec<f64>], columns: usize) -> Vec<f64> {
        let n = self.vertex_count();
        let mut values = vec![0.0; n * columns];
        for (phi, w) in self.eigenvectors.iter().zip(weights) {
            for (row, q) in values.chunks_exact_mut(columns).zip(phi) {
                let density = q.norm_sqr();
                for (value, &weight) in row.iter_mut().zip(w) {
                    *value += weight * density;
                }
            }
        }
        values
    }
}

/// A per-vertex descriptor: one row per vertex, one column per time, energy or mode.
#[derive(Debug, Clone, PartialEq)]
pub struct DescriptorTable {
    vertices: usize,
    parameters: Vec<f64>,
    values: Vec<f64>,
}

impl DescriptorTable {
    /// Number of rows (vertices, in mesh order).
    pub fn vertex_count(&self) -> usize {
        self.vertices
    }

    /// Number of columns.
    pub fn column_count(&self) -> usize {
        self.parameters.len()
    }

    /// The parameter of each column: the time `t` (HKS, DKS), the energy `e` (WKS) or the
    /// eigenvalue `λ` of the mode (segmentation).
    pub fn parameters(&self) -> &[f64] {
        &self.parameters
    }

    /// All values, row-major: entry `(v, j)` is `values()[v * column_count() + j]`.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The descriptor of vertex `v` (one value per column). Panics if `v` is out of range.
    pub fn row(&self, v: usize) -> &[f64] {
        let m = self.column_count();
        &self.values[v * m..(v + 1) * m]
    }

    /// Column `j` over all vertices. Panics if `j` is out of range.
    pub fn column(&self, j: usize) -> Vec<f64> {
        assert!(j < self.column_count(), "column {j} out of range");
        self.values
            .iter()
            .skip(j)
            .step_by(self.column_count())
            .copied()
            .collect()
    }
}

/// Checks that `times` is non-empty with positive, finite entries.
fn check_times(times: &[f64]) -> Result<(), DescriptorError> {
    if times.is_empty() {
        return Err(DescriptorError::NoSamples);
    }
    match times.iter().position(|&t| !(t.is_finite() && t > 0.0)) {
        Some(index) => Err(DescriptorError::BadTime {
            index,
            value: times[index],
        }),
        None => Ok(()),
    }
}

/// `Σ_i e^{−t_j |λ_i|} |φ_i(v)|²` after checking the times.
fn kernel_signature(modes: &Modes, times: &[f64]) -> Result<DescriptorTable, DescriptorError> {
    check_times(times)?;
    let weights: Vec<Vec<f64>> = modes
        .eigenvalues
        .iter()
        .map(|l| times.iter().map(|t| (-t * l.abs()).exp()).collect())
        .collect();
    Ok(DescriptorTable {
        vertices: modes.vertex_count(),
        parameters: times.to_vec(),
        values: modes.weighted_sums(&weights, times.len()),
    })
}

/// The heat kernel signature (Sun, Ovsjanikov, Guibas 2009) of a Laplace spectrum:
/// `HKS_t(v) = Σ_i e^{−t λ_i} |φ_i(v)|²`, one column per time `t`, zero modes included.
/// With all `n` pairs this is the diagonal of the heat kernel `e^{−t M⁻¹L} M⁻¹`, the
/// amount of heat remaining at `v` at time `t` after a unit point source at `v`.
///
/// Errors: invalid times ([`DescriptorError::BadTime`], [`DescriptorError::NoSamples`]) and
/// negative eigenvalues ([`DescriptorError::NegativeEigenvalue`]; use
/// [`dirac_kernel_signature`] for signed spectra).
pub fn heat_kernel_signature(
    modes: &Modes,
    times: &[f64],
) -> Result<DescriptorTable, DescriptorError> {
    if let Some(index) = modes.eigenvalues.iter().position(|&l| l < 0.0) {
        return Err(DescriptorError::NegativeEigenvalue {
            index,
            value: modes.eigenvalues[index],
        });
    }
    kernel_signature(modes, times)
}

/// The Dirac kernel signature (paper §6.3; docs/MATH.md, "Per-vertex descriptors"):
/// `DKS_t(v) = Σ_i e^{−t |λ_i|} |φ_i(v)|²`, one column per time `t`, zero modes included. For a
/// nonnegative spectrum it equals the heat kernel signature.
pub fn dirac_kernel_signature(
    modes: &Modes,
    times: &[f64],
) -> Result<DescriptorTable, DescriptorError> {
    kernel_signature(modes, times)
}

/// The default times of the heat and Dirac kernel signatures (Sun, Ovsjanikov, Guibas 2009):
/// `count` times spaced logarithmically over `[4 ln 10 / |λ|_max, 4 ln 10 / |λ|_min]`, with
/// `|λ|_min`, `|λ|_max` over the nonzero eigenvalues: at `t_min` the fastest-decaying mode
/// given has decayed to `e^{−4 ln 10} = 10⁻⁴`, at `t_max` the slowest nonzero one has.
/// `t_j = t_min (t_max/t_min)^{j/(count−1)}`; `count = 1` gives `t_min`, and a single nonzero
/// `|λ|` gives `count` equal times.
pub fn default_times(modes: &Modes, count: usize) -> Result<Vec<f64>, DescriptorError> {
    if count == 0 {
        return Err(DescriptorError::NoSamples);
    }
    let (low, high) = modes.nonzero_range()?;
    let scale = 4.0 * std::f64::consts::LN_10;
    let (t_min, t_max) = (scale / high, scale / low);
    let ratio = (t_max / t_min).ln();
    Ok(evenly_spaced(0.0, ratio, count)
        .into_iter()
        .map(|x| t_min * x.exp())
        .collect())
}

/// `count` points spaced evenly over `[first, last]`, ends included (`count = 1`: `first`).
fn evenly_spaced(first: f64, last: f64, count: usize) -> Vec<f64> {
    (0..count)
        .map(|j| {
            let s = if count == 1 {
                0.0
            } else {
                j as f64 / (count - 1) as f64
            };
            first + (last - first) * s
        })
        .collect()
}

/// Energies and filter width of the wave kernel signature.
#[derive(Debug, Clone, PartialEq)]
pub struct WaveSampling {
    /// Log-energies `e_j` (compared with `ln |λ|`).
    pub energies: Vec<f64>,
    /// Width `σ > 0` of the log-normal filter.
    pub sigma: f64,
}

/// The default wave sampling after Aubry, Schlickewei and Cremers (2011, §4): with
/// `e_min = ln |λ|_min`, `e_max = ln |λ|_max` over the nonzero eigenvalues,
/// `σ = 7 (e_max − e_min) / 100` and `count` energies spaced evenly over
/// `[e_min + 2σ, e_max − 2σ]` (`count = 1`: the lower end). Aubry et al. set `σ = 7δ` with the
/// increment `δ = (e_max − e_min)/N` of their `N = 100` energies; here `σ` keeps that value
/// for every `count`, so that the energy band does not collapse (or invert, for `N < 28`)
/// when fewer energies are asked for.
pub fn default_wave_sampling(modes: &Modes, count: usize) -> Result<WaveSampling, DescriptorError> {
    if count == 0 {
        return Err(DescriptorError::NoSamples);
    }
    let (low, high) = modes.nonzero_range()?;
    let (e_min, e_max) = (low.ln(), high.ln());
    let sigma = 7.0 * (e_max - e_min) / DEFAULT_SAMPLES as f64;
    if sigma <= 0.0 {
        return Err(DescriptorError::SingleScale(low));
    }
    let (first, last) = (e_min + 2.0 * sigma, e_max - 2.0 * sigma);
    Ok(WaveSampling {
        energies: evenly_spaced(first, last, count),
        sigma,
    })
}

/// The wave kernel signature (Aubry, Schlickewei, Cremers 2011) with a log-normal energy
/// filter, normalised per energy:
/// `WKS_e(v) = Σ_i g_i(e) |φ_i(v)|² / Σ_i g_i(e)`, `g_i(e) = exp(−(e − ln|λ_i|)² / (2σ²))`,
/// the sums over the nonzero eigenvalues (zero modes have no energy). Because the `φ_i` are
/// mass-normalised, `Σ_v Ā_v WKS_e(v) = 1` for every energy. `|λ|` makes it apply to signed
/// (Dirac) spectra as well.
///
/// Errors: no energies, a non-finite energy, a bad `σ`, no nonzero eigenvalue, and an energy
/// whose filter misses every eigenvalue ([`DescriptorError::EmptyBand`]).
pub fn wave_kernel_signature(
    modes: &Modes,
    sampling: &WaveSampling,
) -> Result<DescriptorTable, DescriptorError> {
    let WaveSampling { energies, sigma } = sampling;
    let sigma = *sigma;
    if energies.is_empty() {
        return Err(DescriptorError::NoSamples);
    }
    if let Some(index) = energies.iter().position(|e| !e.is_finite()) {
        return Err(DescriptorError::BadEnergy {
            index,
            value: energies[index],
        });
    }
    if !(sigma.is_finite() && sigma > 0.0) {
        return Err(DescriptorError::BadSigma(sigma));
    }
    modes.nonzero_range()?;
    let weights: Vec<Vec<f64>> = (0..modes.len())
        .map(|i| {
            let log = modes.eigenvalues[i].abs().ln();
            energies
                .iter()
                .map(|e| {
                    if modes.is_zero(i) {
                        0.0
                    } else {
                        (-(e - log).powi(2) / (2.0 * sigma * sigma)).exp()
                    }
                })
                .collect()
        })
        .collect();
    let mut values = modes.weighted_sums(&weights, energies.len());
    for (index, &energy) in energies.iter().enumerate() {
        let total: f64 = weights.iter().map(|w| w[index]).sum();
        if total == 0.0 {
            return Err(DescriptorError::EmptyBand {
                index,
                energy,
                sigma,
            });
        }
        for row in values.chunks_exact_mut(energies.len()) {
            row[index] /= total;
        }
    }
    Ok(DescriptorTable {
        vertices: modes.vertex_count(),
        parameters: energies.clone(),
        values,
    })
}

/// The segmentation descriptor of paper §6.2: `v ↦ (|φ_1(v)|/√|λ_1|, |φ_2(v)|/√|λ_2|, …)`,
/// one column per nonzero mode in the given order (zero modes are skipped; their column would
/// be infinite). The column parameters are the eigenvalues `λ_i` used. With mass-normalised
/// `φ_i`, column `i` has `Σ_v Ā_v value² = 1/|λ_i|`.
pub fn segmentation_descriptor(modes: &Modes) -> Result<DescriptorTable, DescriptorError> {
    let used: Vec<usize> = (0..modes.len()).filter(|&i| !modes.is_zero(i)).collect();
    if used.is_empty() {
        return Err(DescriptorError::NoNonzeroEigenvalue);
    }
    let n = modes.vertex_count();
    let scales: Vec<f64> = used
        .iter()
        .map(|&i| 1.0 / modes.eigenvalues[i].abs().sqrt())
        .collect();
    let mut values = Vec::with_capacity(n * used.len());
    for v in 0..n {
        values.extend(
            used.iter()
                .zip(&scales)
                .map(|(&i, s)| modes.eigenvectors[i][v].norm() * s),
        );
    }
    Ok(DescriptorTable {
        vertices: n,
        parameters: used.iter().map(|&i| modes.eigenvalues[i]).collect(),
        values,
    })
}
