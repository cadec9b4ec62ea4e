//! The spectra of a collection of meshes under several operators, with the time each operator
//! took: the data of the texture experiments. A spectrum is the vector of the `k` eigenvalues
//! of smallest `|λ|`, signed, in the order [`dirac::spectrum::spectrum`] returns them (by
//! `|λ|`); the distance between two shapes is the Euclidean distance of these vectors (paper
//! §6.1).

use std::time::Instant;

use dirac::TriMesh;
use dirac::spectrum::{
    DEFAULT_ANISOTROPY, Normalization, Operator, SolverBackend, Spectrum, SpectrumOptions, spectrum,
};
use dirac::well::PotentialWell;

use crate::ExperimentError;

/// The cotangent Laplacian `Δ`.
pub const LAPLACE: Operator = Operator::Laplace;
/// The family half way, `L(0.5)` (blended pencil).
pub const HALF_WAY: Operator = Operator::Family { tau: 0.5 };
/// The relative Dirac operator `D_N`.
pub const RELATIVE_DIRAC: Operator = Operator::RelativeDirac;
/// The extrinsic Dirac operator `D_f` (the paper's "Dirac").
pub const DIRAC: Operator = Operator::ExtrinsicDirac;
/// The modified Dirichlet energy Hessian `Δ + κ₁² + κ₂²`.
pub const MODIFIED_DIRICHLET: Operator = Operator::ModifiedDirichlet;
/// The anisotropic Laplacian of Andreux et al. at [`DEFAULT_ANISOTROPY`] (`α = 10`).
pub const ANISOTROPIC_LAPLACE: Operator = Operator::AnisotropicLaplace {
    anisotropy: DEFAULT_ANISOTROPY,
};

/// Relative residual tolerance of every eigensolve (eigenvalues to about 8 digits, far below
/// the differences the experiments measure).
pub const TOLERANCE: f64 = 1e-8;

/// One operator's spectra of every mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct OperatorSpectra {
    /// The operator (tables and plots print it as the command line writes it: `laplace`,
    /// `family:0.5`, …).
    pub operator: Operator,
    /// One spectrum per mesh, in the order of the meshes.
    pub spectra: Vec<Vec<f64>>,
    /// Wall-clock seconds of all of this operator's solves (well and assembly included).
    pub seconds: f64,
}

/// The options of every spectrum of the experiments: `operator`, `k` eigenvalues of smallest
/// `|λ|`, `backend`, `normalization`, tolerance [`TOLERANCE`], the operator's default kernel
/// listing, no well.
pub fn experiment_options(
    operator: Operator,
    k: usize,
    backend: SolverBackend,
    normalization: Normalization,
) -> SpectrumOptions {
    let mut options = SpectrumOptions::new(operator, k);
    options.backend = backend;
    options.normalization = normalization;
    options.tolerance = TOLERANCE;
    options
}

/// [`spectrum`] of mesh number `index` of an experiment, its failure named by operator and
/// mesh.
pub fn solve(
    mesh: &TriMesh,
    options: &SpectrumOptions,
    index: usize,
) -> Result<Spectrum, ExperimentError> {
    spectrum(mesh, options).map_err(|source| ExperimentError::Spectrum {
        operator: options.operator,
        mesh: index,
        source,
    })
}

/// The first `k` eigenvalues of every mesh under every operator with `backend` and
/// `normalization`; `well(i)` gives
/// the potential well of mesh `i` (or none).
pub fn compute_spectra(
    meshes: &[TriMesh],
    operators: &[Operator],
    k: usize,
    backend: SolverBackend,
    normalization: Normalization,
    well: &dyn Fn(usize) -> Option<PotentialWell>,
) -> Result<Vec<OperatorSpectra>, ExperimentError> {
    operators
        .iter()
        .map(|&operator| {
            let start = Instant::now();
            let spectra = meshes
                .iter()
                .enumerate()
                .map(|(index, mesh)| {
                    let mut options = experiment_options(operator, k, backend, normalization);
                    options.well = well(index);
                    solve(mesh, &options, index).map(|s| s.eigenvalues)
                })
                .collect::<Result<Vec<_>, _>>()?;
            Ok(OperatorSpectra {
                operator,
                spectra,
                seconds: start.elapsed().as_secs_f64(),
            })
        })
        .collect()
}

impl OperatorSpectra {
    /// The same spectra with every eigenvalue replaced by `|λ|` (order kept: by `|λ|`). The
    /// paper's default for applications (§7): the sign is informative but its order is
    /// unstable under perturbations of the geometry.
    pub fn magnitudes(&self) -> Self {
        Self {
            spectra: self
                .spectra
                .iter()
                .map(|s| s.iter().map(|v| v.abs()).collect())
                .collect(),
            ..self.clone()
        }
    }
}
