//! The spectra of a collection of meshes under several operators, with the time each operator
//! took: the data of the texture experiments. A spectrum is the vector of the `k` eigenvalues
//! of smallest `|λ|`, signed, in the order [`dirac::spectrum::spectrum`] returns them (by
//! `|λ|`); the distance between two shapes is the Euclidean distance of these vectors (paper
//! §6.1).

use std::time::Instant;

use dirac::TriMesh;
use dirac::spectrum::{Normalization, Operator, SolverBackend, SpectrumOptions, spectrum};
use dirac::well::PotentialWell;

use crate::ExperimentError;

/// An operator with the name the tables and plots print.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NamedOperator {
    /// Short name (`Laplace`, `L(0.5)`, …).
    pub name: &'static str,
    /// The operator.
    pub operator: Operator,
}

/// The cotangent Laplacian `Δ`.
pub const LAPLACE: NamedOperator = NamedOperator {
    name: "Laplace",
    operator: Operator::Laplace,
};
/// The family half way, `L(0.5)` (blended pencil).
pub const HALF_WAY: NamedOperator = NamedOperator {
    name: "L(0.5)",
    operator: Operator::Family { tau: 0.5 },
};
/// The relative Dirac operator `D_N`.
pub const RELATIVE_DIRAC: NamedOperator = NamedOperator {
    name: "relative Dirac",
    operator: Operator::RelativeDirac,
};
/// The extrinsic Dirac operator `D_f` (the paper's "Dirac").
pub const DIRAC: NamedOperator = NamedOperator {
    name: "Dirac",
    operator: Operator::ExtrinsicDirac,
};
/// The modified Dirichlet energy Hessian `Δ + κ₁² + κ₂²`.
pub const MODIFIED_DIRICHLET: NamedOperator = NamedOperator {
    name: "modified Dirichlet",
    operator: Operator::ModifiedDirichlet,
};

/// Relative residual tolerance of every eigensolve (eigenvalues to about 8 digits, far below
/// the differences the experiments measure).
pub const TOLERANCE: f64 = 1e-8;

/// One operator's spectra of every mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct OperatorSpectra {
    /// The operator.
    pub operator: NamedOperator,
    /// One spectrum per mesh, in the order of the meshes.
    pub spectra: Vec<Vec<f64>>,
    /// Wall-clock seconds of all of this operator's solves (well and assembly included).
    pub seconds: f64,
}

/// The first `k` eigenvalues of every mesh under every operator with `backend` and
/// `normalization`; `well(i)` gives
/// the potential well of mesh `i` (or none).
pub fn compute_spectra(
    meshes: &[TriMesh],
    operators: &[NamedOperator],
    k: usize,
    backend: SolverBackend,
    normalization: Normalization,
    well: &dyn Fn(usize) -> Option<PotentialWell>,
) -> Result<Vec<OperatorSpectra>, ExperimentError> {
    operators
        .iter()
        .map(|&named| {
            let start = Instant::now();
            let spectra = meshes
                .iter()
                .enumerate()
                .map(|(index, mesh)| {
                    let mut options = SpectrumOptions::new(named.operator, k);
                    options.backend = backend;
                    options.normalization = normalization;
                    options.tolerance = TOLERANCE;
                    options.well = well(index);
                    spectrum(mesh, &options)
                        .map(|s| s.eigenvalues)
                        .map_err(|source| ExperimentError::Spectrum {
                            operator: named.name.to_string(),
                            mesh: index,
                            source,
                        })
                })
                .collect::<Result<Vec<_>, _>>()?;
            Ok(OperatorSpectra {
                operator: named,
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
