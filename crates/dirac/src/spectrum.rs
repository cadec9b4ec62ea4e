//! Spectra of the paper's operators: one Hermitian-definite pencil per operator (DESIGN.md §3),
//! solved by `qeig` with any of its backends.
//!
//! | operator | pencil solved | reported `λ` |
//! |---|---|---|
//! | Laplace | `M x = μ (L + εM) x` (`L⊗I`), constants deflated | `1/μ − ε`; `0` for the constants |
//! | relative / extrinsic Dirac | `G x = μ (A + εM) x`; on a boundary `𝟙` and `S⁻¹G𝟙` deflated | `x*Ax / x*Gx` (signed) |
//! | family `L(τ)`, blended | `B_τ x = μ (A_τ + εM) x`, `S⁻¹B_τ𝟙` deflated | `x*A_τx / x*B_τx`; `0` for the constants |
//! | family, literal | `M x = μ (K(τ) + σM) x`, `K(τ) = (1−τ)L + τG` | `1/μ − σ` |
//! | squared `D_N* D_N` | `M x = μ (A + εM) x`, constants deflated | `1/μ − ε`; `0` for the constants |
//! | modified Dirichlet `Δ + U` | `M x = μ (L + M diag(U) + εM) x` (`⊗I`) | `1/μ − ε` |
//!
//! with `U = κ₁² + κ₂²` the Willmore potential ([`crate::curvature::willmore_potential`]),
//! `A = D* M_F D`, `G = sym(Bᵀ M_F D)`, `A_τ = τA + (1−τ)L`, `B_τ = τG + (1−τ)M`, and `ε`
//! a regularisation `10⁻¹⁰` times the largest diagonal ratio of the stiffness to `M`. The shifted
//! pencils are mapped back exactly. For the Rayleigh pencils `ε` changes the selection
//! (`|μ| = |x*Kx| / (x*Ax + ε x*Mx)`) and, to second order, the vectors, so after solving every
//! returned pair must have `ε x*Mx ≤ 10⁻⁸ x*Ax`; otherwise `ε` is set to `10⁻⁹` times the
//! smallest ratio `x*Ax / x*Mx` seen (at most `10⁻⁴` times the previous `ε`) and the pencil
//! solved again. For `k > 4` the first solve is a probe for 4 pairs that only sets `ε`
//! (statistics add up over all solves). Deflating `S⁻¹K𝟙` imposes the exact constraint
//! `𝟙*Kx = 0` that every eigenvector with `λ ≠ 0` satisfies when the stiffness annihilates the
//! constants; on closed meshes `S⁻¹B_τ𝟙 ∝ 𝟙` and `G𝟙 = 0`. `σ` is a Gershgorin bound that makes `K(τ) + σM` positive
//! definite; the literal family then collects eigenvalues from the bottom of the spectrum until
//! the `k` of smallest `|λ|` are certain.
//!
//! Results: the `k` eigenvalues of smallest `|λ|`, signed, sorted by `|λ|`, each as often as its
//! multiplicity; eigenvectors of unit mass norm `Σ_p Ā_p |φ_p|² = 1`, mass-orthonormal within
//! each eigenspace, in canonical phase ([`crate::phase`]). At `τ = 1` (relative Dirac) the
//! constants and the flat-region kernel are not eigenpairs of the pencil (`0/0`) and are not
//! reported. With a potential well the constants are not in the kernel and are not deflated.

use qeig::{
    ComplexAdjoint, EigError, Eigen, LanczosOptions, Native, Pencil, Progress, RealBlock,
    Statistics, Which,
};
use qscalar::{Quat, Scalar};
use qsparse::{CholeskyError, SparseCholesky, SparseMatrix, vector};
use thiserror::Error;

use crate::curvature::willmore_potential;
use crate::geometry::{barycentric_masses, cotan_laplacian};
use crate::operators::{DiracPencil, OperatorError, extrinsic_dirac, normal_dirac, quaternionic};
use crate::phase::orthonormalize_and_canonicalize;
use crate::well::{PotentialWell, WellError, dirac_with_well, laplacian_with_well};
use crate::{MeshError, TriMesh};

/// The operator whose spectrum is computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Operator {
    /// The cotangent Laplacian `Δ` (τ = 0).
    Laplace,
    /// The relative Dirac operator `D_N` (τ = 1), area-weighted vertex normals.
    RelativeDirac,
    /// The extrinsic Dirac operator `D_f`.
    ExtrinsicDirac,
    /// The family `L(τ)` as the blended pencil (default discretisation), `0 ≤ τ ≤ 1`.
    Family {
        /// Weight of `D_N` (0: Laplace, 1: relative Dirac).
        tau: f64,
    },
    /// The family `L(τ)` as the literal Galerkin operator `(1−τ)L + τG`, `0 ≤ τ ≤ 1`.
    FamilyLiteral {
        /// Weight of `D_N`.
        tau: f64,
    },
    /// The squared relative Dirac operator `D_N* D_N` (pencil `A x = ν M x`).
    Squared,
    /// The Hessian `Δ + (κ₁² + κ₂²)` of the modified Dirichlet energy (paper §4.1,
    /// Hildebrandt et al. 2012): pencil `(L + M diag(U)) x = λ M x` with the Willmore potential
    /// `U` of [`crate::curvature::willmore_potential`]. Real, so every eigenvalue comes as a
    /// quaternionic multiple of a real eigenvector; the constants are not in its kernel unless
    /// `U = 0` (a plane) and are never deflated.
    ModifiedDirichlet,
}

/// Which representation the eigensolver works in (`qeig` backends).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SolverBackend {
    /// Quaternion matrices and the native Cholesky.
    #[default]
    Native,
    /// The 4n×4n real-block expansion with faer's Cholesky.
    RealBlock,
    /// The 2n×2n complex adjoint with faer's Cholesky.
    ComplexAdjoint,
}

/// Scale normalisation applied to the mesh before assembly.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Normalization {
    /// Use the mesh as given.
    #[default]
    None,
    /// Scale positions by `s = 1/sqrt(total area)` (unit total area). Scaling a mesh by `s`
    /// multiplies the eigenvalues of `D_N`, `Δ`, `Δ + U` and the literal `L(τ)` by `1/s²`, of `D_f` by
    /// `1/s` and of `D_N* D_N` by `1/s⁴`. The blended `L(τ)` is not homogeneous: its values
    /// at scale `s` are those at scale 1 for `τ' = τ/(τ + (1−τ)s²)`, divided by `s²`.
    UnitArea,
}

/// Options of [`spectrum`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpectrumOptions {
    /// The operator.
    pub operator: Operator,
    /// Number of eigenvalues (of smallest `|λ|`).
    pub k: usize,
    /// Eigensolver representation.
    pub backend: SolverBackend,
    /// Scale normalisation.
    pub normalization: Normalization,
    /// Optional infinite potential well (paper §5.1).
    pub well: Option<PotentialWell>,
    /// Relative residual tolerance of the eigensolver.
    pub tolerance: f64,
    /// Seed of the eigensolver's start vectors.
    pub seed: u64,
    /// Largest number of thick restarts of each eigensolve before it reports non-convergence.
    pub max_restarts: usize,
}

impl SpectrumOptions {
    /// `k` eigenvalues of `operator`, native backend, no normalisation, no well, tolerance
    /// `1e−10`, at most 1000 restarts.
    pub fn new(operator: Operator, k: usize) -> Self {
        Self {
            operator,
            k,
            backend: SolverBackend::Native,
            normalization: Normalization::None,
            well: None,
            tolerance: 1e-10,
            seed: 0,
            max_restarts: 1000,
        }
    }
}

/// A computed spectrum.
#[derive(Debug, Clone)]
pub struct Spectrum {
    /// Eigenvalues `λ`, signed, sorted by `|λ|`.
    pub eigenvalues: Vec<f64>,
    /// Eigenvectors `φ` (one quaternion per vertex), unit mass norm, canonical phase.
    pub eigenvectors: Vec<Vec<Quat<f64>>>,
    /// Relative residual `‖P φ − λ Q φ‖ / (|λ| ‖Q φ‖)` of each pair in the operator's own
    /// eigenproblem (`A φ = λ G φ` for Dirac operators, `L φ = λ M φ` for Laplace, …; for
    /// `λ = 0`, `‖P φ‖ / ‖Q φ‖`), measured on the returned vectors.
    pub residuals: Vec<f64>,
    /// Eigensolver statistics (of the last solve for the literal family).
    pub statistics: Statistics,
    /// Factor applied to the positions (1 without normalisation).
    pub scale: f64,
}

/// Why a spectrum could not be computed.
#[derive(Debug, Clone, Error)]
#[non_exhaustive]
pub enum SpectrumError {
    /// `k` is zero or exceeds what the mesh has.
    #[error("cannot compute {k} eigenvalues on a mesh with {vertices} vertices")]
    InvalidCount {
        /// Requested count.
        k: usize,
        /// Vertices.
        vertices: usize,
    },
    /// `τ` outside `[0, 1]` (or not finite).
    #[error("tau = {0} is outside [0, 1]")]
    InvalidTau(f64),
    /// Scaling the mesh to unit area ([`Normalization::UnitArea`]) leaves floating-point
    /// range.
    #[error("normalising to unit area (scale {scale:e}) gives an invalid mesh: {source}")]
    Normalization {
        /// The scale factor `1/sqrt(total area)`.
        scale: f64,
        /// What the scaled mesh fails.
        source: MeshError,
    },
    /// The operator could not be assembled.
    #[error(transparent)]
    Operator(#[from] OperatorError),
    /// The potential well could not be computed.
    #[error(transparent)]
    Well(#[from] WellError),
    /// A factorisation needed to set up the pencil failed.
    #[error(transparent)]
    Factorization(#[from] CholeskyError),
    /// The eigensolver failed.
    #[error("eigensolver: {0}")]
    Eigen(String),
    /// The eigensolver stopped early; `partial` holds what converged, post-processed like a
    /// full result.
    #[error("the eigensolver converged {} of {wanted} eigenvalues", partial.eigenvalues.len())]
    NotConverged {
        /// Eigenvalues asked for.
        wanted: usize,
        /// The converged part.
        partial: Box<Spectrum>,
    },
}

/// A solved pencil before the eigenvalue map: `(μ, x, residual)` and statistics.
type Solved = (Vec<f64>, Vec<Vec<Quat<f64>>>, Vec<f64>, Statistics);

/// Outcome of one pencil solve: everything converged, or only part of it.
enum Outcome {
    Complete(Solved),
    Partial(Solved),
}

/// The spectrum of `options.operator` on `mesh`; see the module documentation for the pencils.
pub fn spectrum(mesh: &TriMesh, options: &SpectrumOptions) -> Result<Spectrum, SpectrumError> {
    spectrum_with_progress(mesh, options, None)
}

/// [`spectrum`] with a callback invoked after every restart of the eigensolver.
pub fn spectrum_with_progress(
    mesh: &TriMesh,
    options: &SpectrumOptions,
    mut progress: Option<&mut dyn FnMut(&Progress)>,
) -> Result<Spectrum, SpectrumError> {
    let n = mesh.vertex_count();
    if options.k == 0 || options.k > n {
        return Err(SpectrumError::InvalidCount {
            k: options.k,
            vertices: n,
        });
    }
    if let Operator::Family { tau } | Operator::FamilyLiteral { tau } = options.operator
        && !(0.0..=1.0).contains(&tau)
    {
        return Err(SpectrumError::InvalidTau(tau));
    }
    let (scale, scaled);
    let mesh = match options.normalization {
        Normalization::None => {
            scale = 1.0;
            mesh
        }
        Normalization::UnitArea => {
            let area: f64 = (0..mesh.face_count()).map(|t| mesh.face_area(t)).sum();
            scale = 1.0 / area.sqrt();
            // Fails when scaling leaves floating-point range (coordinates overflow, or a
            // face's area or angles degenerate).
            scaled = mesh
                .scaled(scale)
                .map_err(|source| SpectrumError::Normalization { scale, source })?;
            &scaled
        }
    };
    let masses = barycentric_masses(mesh);
    let potential = options.well.map(|w| w.potential(mesh)).transpose()?;
    // Without a well the constants are an exact zero mode of every stiffness matrix.
    let constant_mode = potential.is_none();
    let mass = quaternionic(&SparseMatrix::from_diagonal(&masses));
    let progress = &mut progress;

    let laplacian = || -> Result<SparseMatrix<f64>, SpectrumError> {
        let l = match options.operator {
            Operator::ModifiedDirichlet => modified_dirichlet(mesh)?,
            _ => cotan_laplacian(mesh),
        };
        Ok(match &potential {
            Some(u) => laplacian_with_well(mesh, &l, u)?,
            None => l,
        })
    };
    let dirac_pencil = |relative: bool| -> Result<DiracPencil, SpectrumError> {
        let d = if relative {
            normal_dirac(mesh)?
        } else {
            extrinsic_dirac(mesh)?
        };
        let d = match &potential {
            Some(u) => dirac_with_well(mesh, &d, u)?,
            None => d,
        };
        Ok(DiracPencil::new(mesh, &d)?)
    };

    // ε must reflect the operator's own scale, not the wall's (entries up to c² with a well).
    let natural_epsilon = match &potential {
        Some(_) => Some(natural_regularization(mesh, options.operator, &masses)?),
        None => None,
    };
    let regularize = |stiffness: &SparseMatrix<Quat<f64>>| {
        natural_epsilon.unwrap_or_else(|| regularization(stiffness, &masses))
    };

    // Each arm returns the solved pairs and the operator's own eigenproblem `P x = λ Q x`,
    // against which the reported residuals are measured.
    let (mapped, (p_matrix, q_matrix)) = match options.operator {
        Operator::Laplace
        | Operator::Family { tau: 0.0 }
        | Operator::Squared
        | Operator::ModifiedDirichlet => {
            let stiffness = match options.operator {
                Operator::Squared => dirac_pencil(true)?.stiffness,
                _ => quaternionic(&laplacian()?),
            };
            let epsilon = regularize(&stiffness);
            let mapped = shifted_spectrum(
                epsilon,
                options,
                &stiffness,
                &mass,
                &masses,
                constant_mode && options.operator != Operator::ModifiedDirichlet,
                progress,
            )?;
            (mapped, (stiffness, mass))
        }
        Operator::RelativeDirac | Operator::ExtrinsicDirac | Operator::Family { tau: 1.0 } => {
            let pencil = dirac_pencil(options.operator != Operator::ExtrinsicDirac)?;
            let epsilon = regularize(&pencil.stiffness);
            let (a, g) = (&pencil.stiffness, &pencil.coupling);
            let mapped = rayleigh_spectrum(
                epsilon,
                options,
                a,
                g,
                &mass,
                &masses,
                constant_mode,
                false,
                progress,
            )?;
            (mapped, (pencil.stiffness, pencil.coupling))
        }
        Operator::Family { tau } => {
            let pencil = dirac_pencil(true)?;
            let l = quaternionic(&laplacian()?);
            let stiffness = blend(tau, &pencil.stiffness, &l)?;
            let coupling = blend(tau, &pencil.coupling, &mass)?;
            let epsilon = regularize(&stiffness);
            let mapped = rayleigh_spectrum(
                epsilon,
                options,
                &stiffness,
                &coupling,
                &mass,
                &masses,
                constant_mode,
                true,
                progress,
            )?;
            (mapped, (stiffness, coupling))
        }
        Operator::FamilyLiteral { tau } => {
            let pencil = dirac_pencil(true)?;
            let l = quaternionic(&laplacian()?);
            let operator = blend(tau, &pencil.coupling, &l)?;
            let mapped = literal_spectrum(options, &operator, &mass, &masses, progress)?;
            (mapped, (operator, mass))
        }
    };
    let (values, vectors, _, statistics, complete) = mapped;
    let residuals = values
        .iter()
        .zip(&vectors)
        .map(|(&lambda, x)| operator_residual(&p_matrix, &q_matrix, lambda, x))
        .collect();
    let mut spectrum = finish(values, vectors, residuals, statistics, scale, &masses);
    spectrum.eigenvalues.truncate(options.k);
    spectrum.eigenvectors.truncate(options.k);
    spectrum.residuals.truncate(options.k);
    if complete {
        Ok(spectrum)
    } else {
        Err(SpectrumError::NotConverged {
            wanted: options.k,
            partial: Box::new(spectrum),
        })
    }
}

/// `τ X + (1 − τ) Y`.
fn blend(
    tau: f64,
    x: &SparseMatrix<Quat<f64>>,
    y: &SparseMatrix<Quat<f64>>,
) -> Result<SparseMatrix<Quat<f64>>, SpectrumError> {
    SparseMatrix::linear_combination(Quat::from_real(tau), x, Quat::from_real(1.0 - tau), y)
        .map_err(|e| SpectrumError::Operator(e.into()))
}

/// `L + M diag(U)`: the modified Dirichlet Hessian with the Willmore potential `U`.
fn modified_dirichlet(mesh: &TriMesh) -> Result<SparseMatrix<f64>, SpectrumError> {
    let weighted: Vec<f64> = barycentric_masses(mesh)
        .iter()
        .zip(willmore_potential(mesh))
        .map(|(m, u)| m * u)
        .collect();
    SparseMatrix::linear_combination(
        1.0,
        &cotan_laplacian(mesh),
        1.0,
        &SparseMatrix::from_diagonal(&weighted),
    )
    .map_err(|e| SpectrumError::Operator(e.into()))
}

/// `ε = 10⁻¹⁰ · max_p S_pp / M_pp` (or `10⁻¹⁰` if the stiffness vanishes). The ratio is about
/// the largest eigenvalue of the stiffness, so `ε` sits far below the wanted small ones; the
/// Rayleigh pencils check this after solving and reduce `ε` if needed.
fn regularization(stiffness: &SparseMatrix<Quat<f64>>, masses: &[f64]) -> f64 {
    let largest = (0..masses.len())
        .map(|p| stiffness.get(p, p).re() / masses[p])
        .filter(|r| r.is_finite())
        .fold(0.0, f64::max);
    1e-10 * if largest > 0.0 { largest } else { 1.0 }
}

/// `ε` of the operator without the potential well: the well's wall (entries up to `c`, or `c²`
/// in `A`) would otherwise set a shift that swamps the interior modes.
fn natural_regularization(
    mesh: &TriMesh,
    operator: Operator,
    masses: &[f64],
) -> Result<f64, SpectrumError> {
    let laplacian = || quaternionic(&cotan_laplacian(mesh));
    let stiffness = match operator {
        Operator::Laplace | Operator::FamilyLiteral { .. } => laplacian(),
        Operator::ModifiedDirichlet => quaternionic(&modified_dirichlet(mesh)?),
        Operator::ExtrinsicDirac => DiracPencil::new(mesh, &extrinsic_dirac(mesh)?)?.stiffness,
        Operator::RelativeDirac | Operator::Squared => {
            DiracPencil::new(mesh, &normal_dirac(mesh)?)?.stiffness
        }
        Operator::Family { tau } => blend(
            tau,
            &DiracPencil::new(mesh, &normal_dirac(mesh)?)?.stiffness,
            &laplacian(),
        )?,
    };
    Ok(regularization(&stiffness, masses))
}

/// `S + c M`.
fn plus_mass(
    s: &SparseMatrix<Quat<f64>>,
    c: f64,
    mass: &SparseMatrix<Quat<f64>>,
) -> Result<SparseMatrix<Quat<f64>>, SpectrumError> {
    SparseMatrix::linear_combination(Quat::from_real(1.0), s, Quat::from_real(c), mass)
        .map_err(|e| SpectrumError::Operator(e.into()))
}

/// Solves `K x = μ S x` for the `k` wanted pairs with the chosen backend.
fn solve_pencil(
    options: &SpectrumOptions,
    k_matrix: &SparseMatrix<Quat<f64>>,
    s_matrix: &SparseMatrix<Quat<f64>>,
    deflation: Vec<Vec<Quat<f64>>>,
    count: usize,
    which: Which,
    progress: &mut Option<&mut dyn FnMut(&Progress)>,
) -> Result<Outcome, SpectrumError> {
    let pencil = Pencil::new(k_matrix, s_matrix)
        .and_then(|p| p.with_deflation(deflation))
        .map_err(|e| SpectrumError::Eigen(e.to_string()))?;
    let mut lanczos = LanczosOptions::new(count, which);
    lanczos.tolerance = options.tolerance;
    lanczos.seed = options.seed;
    lanczos.max_restarts = options.max_restarts;
    let progress: Option<&mut dyn FnMut(&Progress)> = match progress {
        Some(callback) => Some(&mut **callback),
        None => None,
    };
    let result = match options.backend {
        SolverBackend::Native => pencil.solve_with_progress(&Native, &lanczos, progress),
        SolverBackend::RealBlock => pencil.solve_with_progress(&RealBlock, &lanczos, progress),
        SolverBackend::ComplexAdjoint => {
            pencil.solve_with_progress(&ComplexAdjoint, &lanczos, progress)
        }
    };
    let unpack = |e: Eigen<Quat<f64>>| (e.values, e.vectors, e.residuals, e.statistics);
    match result {
        Ok(e) => Ok(Outcome::Complete(unpack(e))),
        Err(EigError::NotConverged { partial, .. }) => Ok(Outcome::Partial(unpack(*partial))),
        Err(e) => Err(SpectrumError::Eigen(e.to_string())),
    }
}

type Mapped = (Vec<f64>, Vec<Vec<Quat<f64>>>, Vec<f64>, Statistics, bool);

fn split(outcome: Outcome) -> (Solved, bool) {
    match outcome {
        Outcome::Complete(s) => (s, true),
        Outcome::Partial(s) => (s, false),
    }
}

/// The constant mode `(0, 𝟙/‖𝟙‖_M)` prepended to a deflated result.
fn with_constant_mode(masses: &[f64], mapped: Mapped) -> Mapped {
    let (mut values, mut vectors, mut residuals, statistics, complete) = mapped;
    let total: f64 = masses.iter().sum();
    values.insert(0, 0.0);
    vectors.insert(0, vec![Quat::from_real(1.0 / total.sqrt()); masses.len()]);
    residuals.insert(0, 0.0);
    (values, vectors, residuals, statistics, complete)
}

/// Solves `K x = μ S x` for the wanted pairs, `S`-orthogonal to `deflation`, and maps them to
/// `λ` with `to_lambda(μ, x)`. With `constant_mode`, one pair fewer is computed and the exact
/// constant mode `λ = 0` is prepended.
#[allow(clippy::too_many_arguments)]
fn solve_mapped(
    options: &SpectrumOptions,
    k_matrix: &SparseMatrix<Quat<f64>>,
    s_matrix: &SparseMatrix<Quat<f64>>,
    masses: &[f64],
    deflation: Vec<Vec<Quat<f64>>>,
    constant_mode: bool,
    which: Which,
    progress: &mut Option<&mut dyn FnMut(&Progress)>,
    to_lambda: impl Fn(f64, &[Quat<f64>]) -> f64,
) -> Result<Mapped, SpectrumError> {
    let count = options.k - usize::from(constant_mode);
    let mapped = if count == 0 {
        (vec![], vec![], vec![], Statistics::default(), true)
    } else {
        let ((mu, vectors, residuals, statistics), complete) = split(solve_pencil(
            options, k_matrix, s_matrix, deflation, count, which, progress,
        )?);
        let values = mu
            .iter()
            .zip(&vectors)
            .map(|(&m, x)| to_lambda(m, x))
            .collect();
        (values, vectors, residuals, statistics, complete)
    };
    Ok(if constant_mode {
        with_constant_mode(masses, mapped)
    } else {
        mapped
    })
}

/// `K 𝟙`.
fn image_of_constants(k_matrix: &SparseMatrix<Quat<f64>>) -> Result<Vec<Quat<f64>>, SpectrumError> {
    let n = k_matrix.nrows();
    let mut image = vec![Quat::default(); n];
    k_matrix
        .mul_vec(&vec![Quat::from_real(1.0); n], &mut image)
        .map_err(OperatorError::from)?;
    Ok(image)
}

/// Pencils `M x = μ (S + εM) x` with `λ = 1/μ − ε` (Laplace, squared Dirac). The constants
/// (`S 𝟙 = 0`) are deflated directly: `S⁻¹ M 𝟙 = 𝟙/ε`.
fn shifted_spectrum(
    epsilon: f64,
    options: &SpectrumOptions,
    stiffness: &SparseMatrix<Quat<f64>>,
    mass: &SparseMatrix<Quat<f64>>,
    masses: &[f64],
    constant_mode: bool,
    progress: &mut Option<&mut dyn FnMut(&Progress)>,
) -> Result<Mapped, SpectrumError> {
    let s = plus_mass(stiffness, epsilon, mass)?;
    let deflation = if constant_mode {
        vec![vec![Quat::from_real(1.0); masses.len()]]
    } else {
        vec![]
    };
    let mut mapped = solve_mapped(
        options,
        mass,
        &s,
        masses,
        deflation,
        constant_mode,
        Which::LargestAlgebraic,
        progress,
        |mu, _| 1.0 / mu - epsilon,
    )?;
    if constant_mode {
        // The deflation keeps `𝟙* S x = ε 𝟙* M x + 𝟙* S₀ x = 0`, where rounding in `𝟙* S₀ x`
        // (`S₀ 𝟙 = 0`) leaves a constant component of relative size ~ 10⁻¹⁶ λ_max / ε ≈ 10⁻⁶
        // in the computed vectors; remove it exactly (the constant mode itself comes first).
        for x in &mut mapped.1[1..] {
            remove_mass_mean(masses, x);
        }
    }
    Ok(mapped)
}

/// Pencils `K x = μ (A + εM) x` with `λ = x*Ax / x*Kx`: `K = G` (Dirac operators) or
/// `K = B_τ` (blended family, `reports_constant`: the constants are an eigenpair with `λ = 0`).
///
/// When `A 𝟙 = 0` the other eigenvectors satisfy `𝟙* K x = 0`, imposed through
/// `S⁻¹ K 𝟙`. For `K = G` the constant itself is no eigenpair (`0/0`) and is deflated, which
/// fixes the otherwise arbitrary constant component of the eigenvectors; on a mesh with
/// boundary `G 𝟙 ≠ 0` and the pencil is defective at `λ = 0` (the regularisation would split it
/// into a spurious pair `±O(√ε)`), so `S⁻¹ G 𝟙` is deflated too.
#[allow(clippy::too_many_arguments)]
fn rayleigh_spectrum(
    epsilon: f64,
    options: &SpectrumOptions,
    stiffness: &SparseMatrix<Quat<f64>>,
    coupling: &SparseMatrix<Quat<f64>>,
    mass: &SparseMatrix<Quat<f64>>,
    masses: &[f64],
    constants_in_kernel: bool,
    reports_constant: bool,
    progress: &mut Option<&mut dyn FnMut(&Progress)>,
) -> Result<Mapped, SpectrumError> {
    // The pencil selects the largest |μ| = |x*Kx| / (x*Ax + ε x*Mx): ε must be negligible
    // against x*Ax for the wanted pairs, or it reorders them. ε starts far below the largest
    // diagonal ratio (≈ λ_max²) and is reduced while it is not negligible for a returned pair.
    let constant_mode = constants_in_kernel && reports_constant;
    // `G 𝟙` when it does not vanish (a boundary), for the Dirac pencils.
    let boundary_image = if constants_in_kernel && !reports_constant {
        let image = image_of_constants(coupling)?;
        let entry_scale = coupling
            .values()
            .iter()
            .map(|q| q.norm())
            .fold(0.0, f64::max);
        image
            .iter()
            .any(|q| q.norm() > 1e-10 * entry_scale)
            .then_some(image)
    } else {
        None
    };
    let mut epsilon = epsilon;
    let mut attempt = 0;
    let mut statistics = Statistics::default();
    // The first attempt is a cheap probe for the stiffness scale of the wanted pairs.
    let probe_count = options.k.min(PROBE_PAIRS + usize::from(constant_mode));
    loop {
        let probe = attempt == 0 && probe_count < options.k;
        let attempt_options = SpectrumOptions {
            k: if probe { probe_count } else { options.k },
            ..*options
        };
        let options = &attempt_options;
        let s = plus_mass(stiffness, epsilon, mass)?;
        let mut deflation = Vec::new();
        if constants_in_kernel {
            if reports_constant {
                // `S⁻¹ B_τ 𝟙` imposes `𝟙* B_τ x = 0` through qeig's `S`-orthogonal deflation.
                deflation
                    .push(SparseCholesky::factorize(&s)?.solve(&image_of_constants(coupling)?)?);
            } else {
                // `A 𝟙 = 0` and, on closed meshes, `G 𝟙 = 0`: eigenvectors are only defined
                // up to constants; deflating `𝟙` picks the mass-orthogonal one (as in the
                // continuum, ⟨𝟙, φ⟩ = ⟨D𝟙, φ⟩/λ = 0).
                deflation.push(vec![Quat::from_real(1.0); masses.len()]);
                if let Some(image) = &boundary_image {
                    // Boundary: `G 𝟙 ≠ 0`; impose `𝟙* G x = 0` as well.
                    deflation.push(SparseCholesky::factorize(&s)?.solve(image)?);
                }
            }
        }
        let mapped = solve_mapped(
            options,
            coupling,
            &s,
            masses,
            deflation,
            constant_mode,
            Which::LargestMagnitude,
            progress,
            |_, x| rayleigh_quotient(stiffness, x) / rayleigh_quotient(coupling, x),
        )?;
        let mut mapped = mapped;
        if constants_in_kernel && !reports_constant {
            for (x, &lambda) in mapped.1.iter_mut().zip(&mapped.0) {
                match &boundary_image {
                    // Closed mesh: x + 𝟙c is an eigenvector for every c; pick the
                    // mass-orthogonal one exactly (the deflation only fixes it to the accuracy
                    // of `S 𝟙 = ε M 𝟙 + A 𝟙`).
                    None => remove_mass_mean(masses, x),
                    // Boundary: the solve returned the part with 𝟙* M x = 0 of the eigenvector
                    // y = x + 𝟙c; c solves A x − λ G x = λ (G 𝟙) c (least squares).
                    Some(g) => restore_constant(stiffness, coupling, g, lambda, x),
                }
            }
        }
        accumulate(&mut statistics, &mapped.3);
        mapped.3 = statistics;
        // Smallest stiffness ratio x*Ax / x*Mx among the returned pairs.
        let first = usize::from(constant_mode);
        let smallest = mapped.1[first..]
            .iter()
            .map(|x| rayleigh_quotient(stiffness, x).abs() / rayleigh_quotient(mass, x))
            .fold(f64::INFINITY, f64::min);
        let negligible = epsilon <= 1e-8 * smallest;
        if !probe && (negligible || attempt == 3) {
            return Ok(mapped);
        }
        if !negligible {
            epsilon = (1e-9 * smallest).min(1e-4 * epsilon);
        }
        attempt += 1;
    }
}

/// Adds the counts and times of one solve to a running total.
fn accumulate(total: &mut Statistics, run: &Statistics) {
    total.iterations += run.iterations;
    total.restarts += run.restarts;
    total.rounds += run.rounds;
    total.operator_applications += run.operator_applications;
    total.solves += run.solves;
    total.locked += run.locked;
    total.factorization_time += run.factorization_time;
    total.solve_time += run.solve_time;
    total.orthogonalization_time += run.orthogonalization_time;
    total.total_time += run.total_time;
}

/// `‖P x − λ Q x‖ / (|λ| ‖Q x‖)` (Euclidean norms; `‖P x‖ / ‖Q x‖` for `λ = 0`): the residual
/// of the operator's own eigenproblem, not of the regularised pencil that was solved.
fn operator_residual(
    p: &SparseMatrix<Quat<f64>>,
    q: &SparseMatrix<Quat<f64>>,
    lambda: f64,
    x: &[Quat<f64>],
) -> f64 {
    let (mut px, mut qx) = (
        vec![Quat::default(); x.len()],
        vec![Quat::default(); x.len()],
    );
    p.mul_vec(x, &mut px)
        .expect("square operator of the vector's size");
    q.mul_vec(x, &mut qx)
        .expect("square operator of the vector's size");
    let difference: Vec<Quat<f64>> = px.iter().zip(&qx).map(|(&a, &b)| a - b * lambda).collect();
    let scale = if lambda == 0.0 { 1.0 } else { lambda.abs() };
    vector::norm(&difference) / (scale * vector::norm(&qx))
}

/// `x ← x + 𝟙 c` with `c = ⟨g, A x − λ G x⟩ / (λ ⟨g, g⟩)`, `g = G 𝟙`: the constant component
/// that makes `x` satisfy `A x = λ G x` when only its part orthogonal to the constants was
/// computed (least squares; exact when that part is exact).
fn restore_constant(
    a: &SparseMatrix<Quat<f64>>,
    g: &SparseMatrix<Quat<f64>>,
    g_one: &[Quat<f64>],
    lambda: f64,
    x: &mut [Quat<f64>],
) {
    let (mut ax, mut gx) = (
        vec![Quat::default(); x.len()],
        vec![Quat::default(); x.len()],
    );
    a.mul_vec(x, &mut ax)
        .expect("square operator of the vector's size");
    g.mul_vec(x, &mut gx)
        .expect("square operator of the vector's size");
    let residual: Vec<Quat<f64>> = ax.iter().zip(&gx).map(|(&p, &q)| p - q * lambda).collect();
    let c = vector::inner(g_one, &residual) / (lambda * vector::inner(g_one, g_one).re());
    x.iter_mut().for_each(|q| *q += c);
}

/// `x ← x − 𝟙 ⟨𝟙, x⟩_M / ⟨𝟙, 𝟙⟩_M`: the mass-orthogonal projection away from the constants.
fn remove_mass_mean(masses: &[f64], x: &mut [Quat<f64>]) {
    let total: f64 = masses.iter().sum();
    let mean = masses
        .iter()
        .zip(x.iter())
        .map(|(&m, &q)| q * m)
        .sum::<Quat<f64>>()
        / total;
    x.iter_mut().for_each(|q| *q -= mean);
}

/// Pairs computed by the probe that sets `ε` for the Rayleigh pencils.
const PROBE_PAIRS: usize = 4;

/// `Re(x* A x)`.
fn rayleigh_quotient(a: &SparseMatrix<Quat<f64>>, x: &[Quat<f64>]) -> f64 {
    let mut ax = vec![Quat::default(); x.len()];
    a.mul_vec(x, &mut ax)
        .expect("square operator of the vector's size");
    vector::inner(x, &ax).re()
}

/// The literal family `K x = λ M x` (`K` indefinite): `M x = μ (K + σM) x`, `λ = 1/μ − σ`,
/// collecting eigenvalues from the bottom until the `k` of smallest `|λ|` are certain.
fn literal_spectrum(
    options: &SpectrumOptions,
    operator: &SparseMatrix<Quat<f64>>,
    mass: &SparseMatrix<Quat<f64>>,
    masses: &[f64],
    progress: &mut Option<&mut dyn FnMut(&Progress)>,
) -> Result<Mapped, SpectrumError> {
    let n = masses.len();
    // Gershgorin on M^{-1/2} K M^{-1/2}: every λ ≥ min_p (K_pp/M_pp − Σ_{q≠p} |K_pq|/√(M_pp M_qq)).
    let mut lower = vec![0.0; n];
    let mut scale: f64 = 0.0;
    for (p, q, v) in operator.triplets() {
        let weighted = v.abs() / (masses[p] * masses[q]).sqrt();
        scale = scale.max(weighted);
        lower[p] += if p == q {
            v.re() / masses[p]
        } else {
            -weighted
        };
    }
    let bound = lower.iter().copied().fold(f64::INFINITY, f64::min);
    let sigma = 1.01 * (-bound).max(0.0) + 1e-8 * scale.max(f64::MIN_POSITIVE);
    let s = plus_mass(operator, sigma, mass)?;
    let mut count = (2 * options.k).min(n);
    loop {
        let ((mu, vectors, residuals, statistics), complete) = split(solve_pencil(
            options,
            mass,
            &s,
            Vec::new(),
            count,
            Which::LargestAlgebraic,
            progress,
        )?);
        let values: Vec<f64> = mu.iter().map(|m| 1.0 / m - sigma).collect();
        let highest = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mut magnitudes: Vec<f64> = values.iter().map(|v| v.abs()).collect();
        magnitudes.sort_by(f64::total_cmp);
        // Every λ below `highest` is known; the k smallest |λ| are certain once they lie below it.
        let certain = magnitudes.len() >= options.k && magnitudes[options.k - 1] <= highest;
        if certain || count == n || !complete {
            return Ok((values, vectors, residuals, statistics, complete));
        }
        count = (2 * count).min(n);
    }
}

/// Sorts by `|λ|`, mass-orthonormalises within eigenspaces and applies the canonical phase.
fn finish(
    values: Vec<f64>,
    vectors: Vec<Vec<Quat<f64>>>,
    residuals: Vec<f64>,
    statistics: Statistics,
    scale: f64,
    masses: &[f64],
) -> Spectrum {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| {
        values[a]
            .abs()
            .total_cmp(&values[b].abs())
            .then(values[a].total_cmp(&values[b]))
    });
    let eigenvalues: Vec<f64> = order.iter().map(|&i| values[i]).collect();
    let mut eigenvectors: Vec<Vec<Quat<f64>>> = order.iter().map(|&i| vectors[i].clone()).collect();
    let residuals = order.iter().map(|&i| residuals[i]).collect();
    orthonormalize_and_canonicalize(masses, &eigenvalues, &mut eigenvectors, 1e-8);
    Spectrum {
        eigenvalues,
        eigenvectors,
        residuals,
        statistics,
        scale,
    }
}
