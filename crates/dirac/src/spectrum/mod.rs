//! Spectra of the paper's operators: each operator's eigenproblem `P x = λ Q x` (docs/MATH.md,
//! "Pencils") solved by `qeig` with any of its backends, on the complement of its exactly known
//! kernel (docs/MATH.md, "The exact kernel").
//!
//! | operator | `P x = λ Q x` | solved as | kernel (`ker P`, exact) | listed by default |
//! |---|---|---|---|---|
//! | Laplace | `L x = λ M x` (`L⊗I`) | `M x = μ (L + εM) x`, `λ = 1/μ − ε` | constants of each component | yes |
//! | modified Dirichlet `Δ + U` | `(L + M diag(U)) x = λ M x` | as Laplace | constants where `U = 0` | yes |
//! | anisotropic Laplace `Δ_A`, `α ≥ 0` | `K_α x = λ M x` | as Laplace | constants of each component | yes |
//! | squared `D_N* D_N` | `A x = ν M x` | as Laplace | flat vertices, constants, linear functions of parallel pieces | no |
//! | relative / extrinsic Dirac | `A x = λ G x` | `G y = μ A y` (pinned), `λ = x*Ax / x*Gx` | flat vertices, constants, linear functions of parallel pieces | no |
//! | family `L(τ)`, blended, `0 < τ < 1` | `A_τ x = λ B_τ x` | as Dirac | constants | yes |
//! | family, literal | `K(τ) x = λ M x`, `K(τ) = (1−τ)L + τG` | `M x = μ (K + σM) x`, `λ = 1/μ − σ` | constants that `K(τ)` annihilates (closed pieces) | yes |
//!
//! with `U = κ₁² + κ₂²` the Willmore potential ([`crate::curvature::willmore_potential`]),
//! `K_α` the anisotropic stiffness `Σ_t A_t ∇φ_i · H_t ∇φ_j` with the per-face conductivity
//! `H_t = diag(1/(1 + α|κ₁|), 1/(1 + α|κ₂|))` in the principal frame
//! ([`crate::anisotropic::anisotropic_laplacian`]; `α = 0` is Laplace),
//! `A = D* M_F D`, `G = sym(Bᵀ M_F D)`, `A_τ = τA + (1−τ)L`, `B_τ = τG + (1−τ)M` (τ = 0 is
//! Laplace, τ = 1 relative Dirac), `ε` a shift `10⁻¹⁰` times the mean diagonal ratio of `P`
//! to `M`, `Σ P_pp / Σ M_pp` (mapped back exactly), and `σ` the smallest shift, within a
//! factor of 2, that makes `K(τ) + σM` positive definite (found by trial factorisations; the
//! literal family is collected from the bottom of its spectrum, so a strongly indefinite
//! `K(τ)` is [`SpectrumError::IndefiniteLiteralFamily`]).
//!
//! **Arithmetic.** Laplace, modified Dirichlet and anisotropic Laplace are real operators:
//! their quaternionic form `P⊗I` has the real spectrum of `P` with every eigenvector a real one
//! times a quaternion. They are assembled and, with [`SolverBackend::Native`], solved in real
//! arithmetic (the same reduction, Lanczos and native Cholesky over `f64`, a quarter of the
//! data), and their eigenvectors returned as quaternions of zero imaginary part; the embedded
//! backends solve `P⊗I` as before. Every other operator is quaternionic.
//!
//! The operators built on `D_N = D_{f,N}` (relative Dirac, squared, the family) can take a
//! second surface `f2` of the same triangulation in place of the Gauss map `N`:
//! [`relative_spectrum`] solves them with `D_{f1,f2}`.
//!
//! **The kernel.** A face is flat when its corner normals agree within
//! [`SpectrumOptions::flat_tolerance`] relative to its edges; its row of `D_N` is then treated
//! as exactly zero. A
//! vertex whose faces are all flat spans a kernel dimension (`D_N δ_p = 0`, `G δ_p = 0`), and so
//! does the constant of every connected piece of the remaining vertices whose constant `P`
//! annihilates. These are removed before solving, exactly: flat vertices are dropped (every
//! other eigenvector vanishes there), each constant is pinned at one vertex of its piece
//! (Rayleigh form; `P` is then positive definite, no regularisation) or constrained away by
//! `(M 𝟙_S)* x = 0` (shifted form), and where `Q 𝟙_S ≠ 0` (a boundary, or the mass term of the
//! blend) the eigenvectors satisfy `(Q 𝟙_S)* x = 0`, imposed as a constraint, with the
//! constant component restored afterwards. On a piece where every triangle of the second surface
//! `f2` is parallel to one direction `u` (a plane or an open prism for `D_f`), the linear
//! function `u f2` is in the kernel too and is removed the same way (a second pin). Where two
//! corners of a triangle of `f2` coincide (normals along a crease from boundary to boundary,
//! or on the rulings of a cylinder) its row asks only equal values there, so the pieces are
//! finer than the connected ones, each with its constant; where such rulings tie proper
//! triangles together at single vertices the kernel can be larger, and it is computed on the
//! rulings and removed (functions of rulings; [`SpectrumError::RuledKernel`] beyond the size
//! computed). Where some triangles are segments of three distinct points the kernel can be
//! larger too: [`SpectrumError::ParallelFaces`]. A row with a corner that no other row
//! involves is *freed*: it holds for exactly one value there whatever the others are, so the
//! structure is read without it and every kernel vector extended to that corner (rows on
//! jagged open boundaries, ribbons freed from end to end). [`Spectrum::kernel`] reports what was found;
//! [`SpectrumOptions::include_kernel`] lists its eigenvalue `0` among the `k` of smallest `|λ|`,
//! with a mass-orthonormal basis (by piece: its constant and its linear function if it has
//! one, or its functions of rulings; then `δ_p / √Ā_p`).
//!
//! **Results.** The `k` eigenvalues of smallest `|λ|`, signed, sorted by `|λ|`, then by `λ`
//! among magnitudes equal to within `max(100 tol, 10⁻⁸)` relative (so `−a` before `a`,
//! whatever the last bits of the two), each as often as its multiplicity; eigenvectors of unit
//! mass norm `Σ_p Ā_p |φ_p|² = 1`, mass-orthonormal within each eigenspace, in canonical
//! phase ([`crate::phase`]), and mass-orthogonal to the kernel except on coupled pieces. A
//! pair counts as converged when the relative residual of the operator's own eigenproblem
//! (matrices as assembled, dual and mass norms) is at most [`CONVERGED_RESIDUAL_FACTOR`] times
//! the tolerance, or when its normwise backward error
//! `‖P x − λ Q x‖ / ((‖P‖ + |λ| ‖Q‖) ‖x‖_M)` is at the rounding floor
//! [`ROUNDING_BACKWARD_ERROR`] (unless `|λ| ‖Q‖` exceeds `‖P‖` by more than its inverse: there
//! every `x` with `Q x` at rounding level passes, an eigenvalue at infinity). Pairs the
//! eigensolver accepted at its rounding level that fail this test (Lanczos vectors less
//! accurate than rounding allows, where the reduced `P` is ill-conditioned and the smallest
//! eigenvalues cluster, as on finely faceted cylinders) are refined by up to two steps of
//! subspace iteration with the matrices themselves (`qeig::Pencil::refine`); what still fails
//! makes [`SpectrumError::NotConverged`], which carries the pairs that pass and says what the
//! others tell ([`Unaccepted`]).

mod determined;
mod first_order;
mod flatness;
mod kernel;
mod pencil;
mod solve;

use std::any::Any;
use std::borrow::Cow;
use std::fmt;
use std::str::FromStr;

use qeig::{ProgressCallback, Statistics};
use qscalar::{Quat, Scalar};
use qsparse::{CholeskyError, SparseMatrix, threads, vector};
use thiserror::Error;

use first_order::Unremoved;
use flatness::{NEARLY_FLAT, flatness_around};
pub use kernel::KernelSummary;
use kernel::{ExactKernel, KernelStructure};
use pencil::{Matrices, OperatorPencil, PencilSpec};
use solve::{Pairs, SolveError, Solved, products};

use crate::geometry::barycentric_masses;
use crate::operators::OperatorError;
use crate::phase::{mass_norm, orthonormalize_and_canonicalize};
use crate::well::{PotentialWell, WellError};
use crate::{ConnectivityMismatch, MeshError, TriMesh, geometry};

/// Default [`SpectrumOptions::flat_tolerance`] `10⁻⁵`: a face is flat when along each edge
/// `|N_a − N_b| ≤ 10⁻⁵ |f_a − f_b| / L` (`L = √area`: a curvature below `10⁻⁵/L`). Exactly
/// flat regions of real meshes give `≤ 10⁻¹³` (rounding of the normals), curved regions
/// `≥ 10⁻⁴`; the 19 Princeton benchmark meshes have no face in between.
pub const DEFAULT_FLAT_TOLERANCE: f64 = 1e-5;

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
    /// The anisotropic Laplacian `Δ_A = div(A grad)` of Andreux et al. 2014 (paper §2, §4.1),
    /// conductivity `ψ_α(κ) = 1/(1 + α|κ|)` along each principal direction
    /// ([`crate::anisotropic`]): pencil `K_α x = λ M x`, real and positive semidefinite, kernel
    /// the constants of each component.
    AnisotropicLaplace {
        /// `α ≥ 0`, in units of length (0: Laplace).
        anisotropy: f64,
    },
}

/// The one real parameter an operator may take, with its meaning and range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Parameter {
    /// The family's weight `τ ∈ [0, 1]` of `D_N` (0: Laplace, 1: relative Dirac).
    Weight,
    /// The anisotropic Laplacian's anisotropy `α ∈ [0, ∞)` (0: Laplace), a length: curvatures
    /// enter as `α|κ|`.
    Anisotropy,
}

impl Parameter {
    /// What it is, for messages: `the weight τ of D_N`, `the anisotropy α`.
    pub fn description(self) -> &'static str {
        match self {
            Parameter::Weight => "the weight τ of D_N",
            Parameter::Anisotropy => "the anisotropy α",
        }
    }

    /// Its name as a keyword: `tau`, `anisotropy` (the JSON reports' keys, the Python
    /// package's keyword arguments).
    pub fn keyword(self) -> &'static str {
        match self {
            Parameter::Weight => "tau",
            Parameter::Anisotropy => "anisotropy",
        }
    }

    /// Its symbol: `τ`, `α`.
    pub fn symbol(self) -> &'static str {
        match self {
            Parameter::Weight => "τ",
            Parameter::Anisotropy => "α",
        }
    }

    /// The placeholder of the written form ([`Operator::forms`]): `T` in `family:T`, `A` in
    /// `anisotropic-laplace:A`.
    pub fn placeholder(self) -> &'static str {
        match self {
            Parameter::Weight => "T",
            Parameter::Anisotropy => "A",
        }
    }

    /// Its range, as messages write it: `[0, 1]`, `[0, ∞)`.
    pub fn range(self) -> &'static str {
        match self {
            Parameter::Weight => "[0, 1]",
            Parameter::Anisotropy => "[0, ∞)",
        }
    }

    /// Whether `value` is in range (finite).
    pub fn contains(self, value: f64) -> bool {
        match self {
            Parameter::Weight => (0.0..=1.0).contains(&value),
            Parameter::Anisotropy => value >= 0.0 && value.is_finite(),
        }
    }

    /// A typical value, for messages.
    pub fn example(self) -> f64 {
        match self {
            Parameter::Weight => 0.5,
            Parameter::Anisotropy => DEFAULT_ANISOTROPY,
        }
    }
}

/// The anisotropy `α = 10` the experiments use for [`Operator::AnisotropicLaplace`] on unit-area
/// meshes (see docs/MATH.md, "The anisotropic Laplacian", for why this value).
pub const DEFAULT_ANISOTROPY: f64 = 10.0;

/// Every operator, those with a parameter at an arbitrary value: what [`Operator::from_name`]
/// looks names up in.
const OPERATORS: [Operator; 8] = [
    Operator::Laplace,
    Operator::RelativeDirac,
    Operator::ExtrinsicDirac,
    Operator::Family { tau: 0.5 },
    Operator::FamilyLiteral { tau: 0.5 },
    Operator::Squared,
    Operator::ModifiedDirichlet,
    Operator::AnisotropicLaplace {
        anisotropy: DEFAULT_ANISOTROPY,
    },
];

/// Why [`Operator::from_name`] failed.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum OperatorNameError {
    /// No operator has this name.
    #[error("unknown operator {name:?}; expected one of {}", Operator::names().join(", "))]
    Unknown {
        /// The name given.
        name: String,
    },
    /// The operator needs its parameter (the family `τ`, the anisotropic Laplacian `α`).
    #[error("operator {name:?} needs {} (in {})", parameter.description(), parameter.range())]
    MissingParameter {
        /// The operator's name.
        name: &'static str,
        /// The parameter it needs.
        parameter: Parameter,
    },
    /// The operator takes no parameter.
    #[error("operator {name:?} takes no parameter (only {} do)", Operator::parametrized().join(", "))]
    UnexpectedParameter {
        /// The operator's name.
        name: &'static str,
    },
}

/// Why parsing an operator from its written form ([`Operator`]'s `FromStr`: `laplace`,
/// `family:0.5`, …) failed.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ParseOperatorError {
    /// No operator has this name.
    #[error("unknown operator {name:?}; expected one of {}", Operator::forms().join(", "))]
    Unknown {
        /// The name given (before any `:`).
        name: String,
    },
    /// An operator with a parameter was written without it.
    #[error(
        "operator {name} needs {}: {name}:{p} with {p} in {}, e.g. {name}:{}",
        parameter.description(), parameter.range(), parameter.example(), p = parameter.placeholder()
    )]
    MissingParameter {
        /// The operator's name.
        name: &'static str,
        /// The parameter it needs.
        parameter: Parameter,
    },
    /// An operator without a parameter was written with one.
    #[error("operator {name} takes no parameter (only {} do)", Operator::parametrized_forms().join(", "))]
    UnexpectedParameter {
        /// The operator's name.
        name: &'static str,
    },
    /// The text after `:` is not a finite number.
    #[error("{name}:{text}: {} must be a finite number in {}", parameter.description(), parameter.range())]
    InvalidParameter {
        /// The operator's name.
        name: &'static str,
        /// Its parameter.
        parameter: Parameter,
        /// The text after `:`.
        text: String,
    },
    /// The parameter is out of its range.
    #[error(
        "{name}:{value}: {} = {value} is outside {}", parameter.description(), parameter.range()
    )]
    ParameterOutOfRange {
        /// The operator's name.
        name: &'static str,
        /// Its parameter.
        parameter: Parameter,
        /// The value given.
        value: f64,
    },
}

/// `laplace`, `relative-dirac`, …, and for an operator with a parameter its value after a
/// colon: `family:0.5`, `family-literal:0.25`, `anisotropic-laplace:10` (written as the
/// shortest decimal that reads back exactly). What `FromStr` reads back.
impl fmt::Display for Operator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.parameter() {
            Some((_, value)) => write!(f, "{}:{value}", self.name()),
            None => f.write_str(self.name()),
        }
    }
}

/// Reads exactly what [`Operator`]'s `Display` writes: a name of [`Operator::names`], an
/// operator with a parameter followed by `:` and its value, a finite number in the
/// parameter's range ([`Parameter::range`]).
impl FromStr for Operator {
    type Err = ParseOperatorError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let (name, value) = match text.split_once(':') {
            Some((name, value)) => (name, Some(value)),
            None => (text, None),
        };
        let prototype = Operator::prototype(name).ok_or_else(|| ParseOperatorError::Unknown {
            name: name.to_string(),
        })?;
        let name = prototype.name();
        let value = match (value, prototype.parameter()) {
            (None, _) => None,
            (Some(_), None) => return Err(ParseOperatorError::UnexpectedParameter { name }),
            (Some(text), Some((parameter, _))) => {
                match text.parse::<f64>().ok().filter(|v| v.is_finite()) {
                    None => {
                        return Err(ParseOperatorError::InvalidParameter {
                            name,
                            parameter,
                            text: text.to_string(),
                        });
                    }
                    Some(value) if !parameter.contains(value) => {
                        return Err(ParseOperatorError::ParameterOutOfRange {
                            name,
                            parameter,
                            value,
                        });
                    }
                    value => value,
                }
            }
        };
        Operator::from_name(name, value).map_err(|error| match error {
            OperatorNameError::MissingParameter { name, parameter } => {
                ParseOperatorError::MissingParameter { name, parameter }
            }
            OperatorNameError::UnexpectedParameter { name } => {
                ParseOperatorError::UnexpectedParameter { name }
            }
            OperatorNameError::Unknown { name } => ParseOperatorError::Unknown { name },
        })
    }
}

impl Operator {
    /// The names [`Operator::from_name`] accepts, in the order of the enum.
    pub fn names() -> Vec<&'static str> {
        OPERATORS.iter().map(|o| o.name()).collect()
    }

    /// How each operator is written for `FromStr`, in the order of the enum: its name, one
    /// with a parameter followed by `:` and the parameter's placeholder (`family:T`,
    /// `anisotropic-laplace:A`).
    pub fn forms() -> Vec<String> {
        OPERATORS.iter().map(|o| o.form()).collect()
    }

    /// [`Operator::forms`] of the operators that take a parameter.
    fn parametrized_forms() -> Vec<String> {
        OPERATORS
            .iter()
            .filter(|o| o.parameter().is_some())
            .map(|o| o.form())
            .collect()
    }

    /// The names of the operators that take a parameter.
    fn parametrized() -> Vec<&'static str> {
        OPERATORS
            .iter()
            .filter(|o| o.parameter().is_some())
            .map(|o| o.name())
            .collect()
    }

    /// How this operator is written for `FromStr`, with the placeholder of its parameter.
    fn form(self) -> String {
        match self.parameter() {
            Some((parameter, _)) => format!("{}:{}", self.name(), parameter.placeholder()),
            None => self.name().to_string(),
        }
    }

    /// The operator called `name` ([`Operator::name`]), its parameter at an arbitrary value.
    fn prototype(name: &str) -> Option<Operator> {
        OPERATORS.into_iter().find(|o| o.name() == name)
    }

    /// The operator's parameter and its value: the family's weight `τ`
    /// ([`Parameter::Weight`]), the anisotropic Laplacian's `α` ([`Parameter::Anisotropy`]);
    /// `None` for the other operators.
    pub fn parameter(self) -> Option<(Parameter, f64)> {
        match self {
            Operator::Family { tau } | Operator::FamilyLiteral { tau } => {
                Some((Parameter::Weight, tau))
            }
            Operator::AnisotropicLaplace { anisotropy } => {
                Some((Parameter::Anisotropy, anisotropy))
            }
            Operator::Laplace
            | Operator::RelativeDirac
            | Operator::ExtrinsicDirac
            | Operator::Squared
            | Operator::ModifiedDirichlet => None,
        }
    }

    /// The same operator with its parameter set to `value` (unchanged without one).
    fn with_parameter(self, value: f64) -> Self {
        match self {
            Operator::Family { .. } => Operator::Family { tau: value },
            Operator::FamilyLiteral { .. } => Operator::FamilyLiteral { tau: value },
            Operator::AnisotropicLaplace { .. } => {
                Operator::AnisotropicLaplace { anisotropy: value }
            }
            other => other,
        }
    }

    /// The family's weight `τ`; `None` for the other operators.
    pub fn tau(self) -> Option<f64> {
        self.parameter()
            .filter(|(parameter, _)| *parameter == Parameter::Weight)
            .map(|(_, tau)| tau)
    }

    /// The anisotropic Laplacian's anisotropy `α`; `None` for the other operators.
    pub fn anisotropy(self) -> Option<f64> {
        self.parameter()
            .filter(|(parameter, _)| *parameter == Parameter::Anisotropy)
            .map(|(_, alpha)| alpha)
    }

    /// The operator's name, as the command line and the Python package spell it.
    pub fn name(self) -> &'static str {
        match self {
            Operator::Laplace => "laplace",
            Operator::RelativeDirac => "relative-dirac",
            Operator::ExtrinsicDirac => "extrinsic-dirac",
            Operator::Family { .. } => "family",
            Operator::FamilyLiteral { .. } => "family-literal",
            Operator::Squared => "squared",
            Operator::ModifiedDirichlet => "modified-dirichlet",
            Operator::AnisotropicLaplace { .. } => "anisotropic-laplace",
        }
    }

    /// The operator called `name` ([`Operator::name`]) with its parameter `value`: required
    /// by the operators that take one (`family`, `family-literal`: `τ`;
    /// `anisotropic-laplace`: `α`) and refused by every other operator. The range is checked
    /// by [`spectrum`].
    pub fn from_name(name: &str, value: Option<f64>) -> Result<Self, OperatorNameError> {
        let prototype = Operator::prototype(name).ok_or_else(|| OperatorNameError::Unknown {
            name: name.to_string(),
        })?;
        let name = prototype.name();
        match (prototype.parameter(), value) {
            (Some(_), Some(value)) => Ok(prototype.with_parameter(value)),
            (Some((parameter, _)), None) => {
                Err(OperatorNameError::MissingParameter { name, parameter })
            }
            (None, Some(_)) => Err(OperatorNameError::UnexpectedParameter { name }),
            (None, None) => Ok(prototype),
        }
    }

    /// Whether the operator is built on `D_N = D_{f,N}`, whose Gauss map
    /// [`relative_spectrum`] replaces by another surface: relative Dirac, squared and the
    /// family.
    pub fn uses_gauss_map(self) -> bool {
        matches!(
            self,
            Operator::RelativeDirac
                | Operator::Squared
                | Operator::Family { .. }
                | Operator::FamilyLiteral { .. }
        )
    }

    /// Whether the kernel's eigenvalue `0` is listed unless asked otherwise: yes for the
    /// operators whose kernel is at most the constants and whose zero eigenvalue is an
    /// ordinary one (Laplace, anisotropic Laplace, modified Dirichlet, the literal family, the
    /// blended family for `τ < 1`),
    /// no for `D_N`, `D_f`
    /// and `D_N* D_N`, whose kernel holds every flat vertex (hundreds to thousands on man-made
    /// shapes) and where the pencil is singular.
    pub fn lists_kernel_by_default(self) -> bool {
        match self {
            Operator::Laplace
            | Operator::AnisotropicLaplace { .. }
            | Operator::ModifiedDirichlet
            | Operator::FamilyLiteral { .. } => true,
            Operator::Family { tau } => tau < 1.0,
            Operator::RelativeDirac | Operator::ExtrinsicDirac | Operator::Squared => false,
        }
    }
}

/// Which representation the eigensolver works in (`qeig` backends).
///
/// For a real operator (Laplace, anisotropic Laplace, modified Dirichlet) `Native` solves the
/// real pencil in real arithmetic: the same Lanczos and native Cholesky over `f64`, a quarter
/// of the data of `L⊗I`, with the results returned as quaternions of zero imaginary part. The
/// embedded backends solve such an operator as before, as the quaternionic `L⊗I` embedded in
/// their representation, so that the representations can still be compared on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SolverBackend {
    /// The operator's own scalar with the native Cholesky: quaternion matrices, or real ones
    /// for a real operator.
    #[default]
    Native,
    /// The 4n×4n real-block expansion of the quaternionic pencil with faer's Cholesky.
    RealBlock,
    /// The 2n×2n complex adjoint of the quaternionic pencil with faer's Cholesky.
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
    /// at scale `s` are those at scale 1 for `τ' = τ/(τ + (1−τ)s²)`, divided by `s²`. Nor is
    /// the anisotropic Laplacian (curvatures scale as `1/s`, so `ψ_α(κ/s) = ψ_{αs⁻¹}(κ)`): its
    /// values at scale `s` are those at scale 1 for `α' = α/s`, divided by `s²`.
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
    /// Relative residual tolerance of the eigensolver; pairs are reported as converged by the
    /// test of the module documentation.
    pub tolerance: f64,
    /// Seed of the eigensolver's start vectors.
    pub seed: u64,
    /// Largest number of thick restarts of each eigensolve before it reports non-convergence.
    pub max_restarts: usize,
    /// List the kernel's eigenvalue `0` (with a mass-orthonormal kernel basis) among the `k`
    /// of smallest `|λ|`. Default: [`Operator::lists_kernel_by_default`].
    pub include_kernel: bool,
    /// Faces whose Gauss map is flat within this (along each edge `|N_a − N_b| ≤ T |f_a −
    /// f_b| / √area`) are flat: their row of `D_N` is taken as exactly zero
    /// ([`DEFAULT_FLAT_TOLERANCE`]; `0` keeps only exactly equal normals).
    pub flat_tolerance: f64,
}

impl SpectrumOptions {
    /// The family's weight `τ` when what it means depends on the mesh's scale: the blended
    /// family with `0 < τ < 1` on meshes that are not normalised (it mixes `τA ∝ 1/s²` with
    /// `(1−τ)L ∝ 1`; docs/MATH.md, "Scaling and rigid motions"). `None` otherwise.
    pub fn weight_by_scale(&self) -> Option<f64> {
        match self.operator {
            Operator::Family { tau } if tau > 0.0 && tau < 1.0 => {
                (self.normalization == Normalization::None).then_some(tau)
            }
            _ => None,
        }
    }

    /// `k` eigenvalues of `operator`, native backend, no normalisation, no well, tolerance
    /// `1e−10`, at most 1000 restarts, the operator's default kernel listing and flat
    /// tolerance [`DEFAULT_FLAT_TOLERANCE`].
    pub fn new(operator: Operator, k: usize) -> Self {
        Self {
            include_kernel: operator.lists_kernel_by_default(),
            flat_tolerance: DEFAULT_FLAT_TOLERANCE,
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
    /// `λ = 0`, `‖P φ‖ / (max_p (P_pp/Ā_p) ‖φ‖_M)`), in the dual norm `‖r‖² = Σ_p |r_p|²/Ā_p`,
    /// measured on the returned vectors with the matrices as assembled (flat faces not zeroed).
    pub residuals: Vec<f64>,
    /// Normwise backward error `‖P φ − λ Q φ‖ / ((‖P‖ + |λ| ‖Q‖) ‖φ‖_M)` of each pair (the
    /// smallest relative change of `P` and `Q` for which it is exact), in the norms of
    /// [`Spectrum::residuals`], with `‖X‖ = max_p Σ_q |X_pq| / √(Ā_p Ā_q)`. A pair is returned
    /// as converged when its relative residual is at most [`CONVERGED_RESIDUAL_FACTOR`] times
    /// the tolerance **or** its backward error is at most [`ROUNDING_BACKWARD_ERROR`]: an
    /// ill-conditioned eigenvalue (a small `|λ|` of a pencil with a large `‖P‖`) can have a
    /// relative residual far above the tolerance while being as accurate as double precision
    /// allows, and this number is what says so.
    pub backward_errors: Vec<f64>,
    /// Eigensolver statistics, summed over all solves.
    pub statistics: Statistics,
    /// Factor applied to the positions (1 without normalisation).
    pub scale: f64,
    /// The barycentric vertex masses `Ā_p` of the mesh as solved (after normalisation): the
    /// weights of the eigenvectors' mass norm.
    pub masses: Vec<f64>,
    /// The exactly known kernel: its dimension and how it was found.
    pub kernel: KernelSummary,
    /// The backward error at which a pair counts as converged whatever its relative residual:
    /// [`ROUNDING_BACKWARD_ERROR`], or, for positions stored in single precision
    /// ([`TriMesh::single_precision_rounding`]), the relative change of `P` and `Q` that the
    /// rounding of the positions alone makes, if larger (measured by assembling them again at
    /// positions moved by up to that rounding; docs/MATH.md, "Coordinates in single precision").
    pub backward_error_floor: f64,
}

/// The second surface `f2` of a first-order operator `D_{f,f2}`, as an error names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SecondSurface {
    /// The Gauss map `N` (the vertex normals): `D_N`.
    GaussMap,
    /// The mesh's own positions: `D_f`.
    Mesh,
    /// The reference surface `B` of a relative spectrum: `D_{f,B}`.
    Reference,
}

impl SecondSurface {
    /// How it is written in formulas.
    fn symbol(self) -> &'static str {
        match self {
            Self::GaussMap => "N",
            Self::Mesh => "f",
            Self::Reference => "B",
        }
    }

    /// The first-order operator built on it.
    fn operator(self) -> &'static str {
        match self {
            Self::GaussMap => "D_N",
            Self::Mesh => "D_f",
            Self::Reference => "D_{f,B}",
        }
    }

    /// What is parallel to `direction` on the piece (`None`: every triangle is a segment).
    fn describe(self, direction: Option<[f64; 3]>) -> String {
        let triangles = match self {
            Self::GaussMap => "the triangles of the vertex normals N",
            Self::Mesh => "the faces of the mesh",
            Self::Reference => "the faces of the reference surface",
        };
        match direction {
            Some([x, y, z]) => format!(
                "{triangles} are all parallel to the direction ({x:.6}, {y:.6}, {z:.6}) and some \
                 are segments (three distinct points on a line, within 10⁻¹⁰ of their size)"
            ),
            None => format!(
                "{triangles} are all segments (three distinct points on a line, within 10⁻¹⁰ \
                 of their size)"
            ),
        }
    }
}

/// Why a spectrum could not be computed.
#[derive(Debug, Clone, Error)]
#[non_exhaustive]
pub enum SpectrumError {
    /// `k` is zero or exceeds what the mesh has.
    #[error(
        "cannot compute {k} eigenvalues on a mesh with {vertices} vertices: ask for between 1 \
         and {vertices}"
    )]
    InvalidCount {
        /// Requested count.
        k: usize,
        /// Vertices.
        vertices: usize,
    },
    /// The operator's parameter (`τ` of the family, `α` of the anisotropic Laplacian) is
    /// outside its range or not finite.
    #[error(
        "{operator}: {} = {value} is outside {} ({})",
        parameter.keyword(), parameter.range(), parameter.description()
    )]
    InvalidParameter {
        /// The operator's name.
        operator: &'static str,
        /// Its parameter.
        parameter: Parameter,
        /// The value given.
        value: f64,
    },
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
    /// The eigensolver failed (other than by not converging, which is
    /// [`SpectrumError::NotConverged`]). The source is the solver's typed error,
    /// `qeig::EigError<f64>` for real operators and `qeig::EigError<Quat<f64>>` for the others
    /// (`downcast_ref` recovers it); its variants say what to change, for example
    /// `BasisTooLarge` names the memory the Krylov basis needs.
    #[error("eigensolver: {0}")]
    Eigen(#[source] std::sync::Arc<dyn std::error::Error + Send + Sync>),
    /// The eigensolver's tolerance is not in `(0, 1)`.
    #[error("tolerance {0} must lie strictly between 0 and 1")]
    InvalidTolerance(f64),
    /// No restart allowed: the eigensolver needs at least one.
    #[error("max_restarts must be at least 1")]
    InvalidMaxRestarts,
    /// The flat tolerance is negative or not a number.
    #[error("flat tolerance {0} must be a finite number ≥ 0")]
    InvalidFlatTolerance(f64),
    /// The operator's entries leave floating-point range when weighted by the vertex masses.
    #[error(
        "the operator's entries leave floating-point range when weighted by the vertex masses: \
         the mesh mixes extremely large and extremely small elements; scale it (--normalize \
         unit-area) or remove its degenerate faces"
    )]
    ScaleOutOfRange,
    /// The operator vanishes identically on the mesh: its Gauss map is constant on every
    /// component (each is planar, or every face is flat), so every function is in its kernel.
    #[error(
        "the {operator} operator vanishes on this mesh: the mesh's Gauss map is constant (every \
         face is flat), so all {vertices} vertices are in its kernel and it has no nonzero \
         eigenvalue; {}list the kernel with --include-kernel, or use --operator family:T \
         (0 < T < 1), which sees the flat geometry through the Laplacian",
        weld_advice(*components, "flat ")
    )]
    VanishingOperator {
        /// The operator asked for (relative Dirac, its square, the family at `τ = 1`).
        operator: Operator,
        /// Vertices (all in the kernel).
        vertices: usize,
        /// Connected components of the mesh (all flat).
        components: usize,
    },
    /// A Dirac pencil on `D_{f,f2}` whose second surface `f2` (the Gauss map for `D_N`, the
    /// mesh itself for `D_f`, else the reference surface) has a piece on which every triangle
    /// is parallel to one direction `u` and some triangles are segments of three distinct
    /// points (degenerate triangles, such as a reference squashed onto a line): there the row
    /// of each segment annihilates the functions linear along it, and `D_{f,f2}` possibly more
    /// than the constants and `u f2`, a kernel the solver does not remove. (Triangles with two
    /// coinciding corners, the normals along a crease or the rulings of a cylinder, and proper
    /// triangles leave a kernel that is known and removed.)
    #[error(
        "the {operator} operator is not solved here: on the piece of vertex {vertex}, {}, where \
         {} annihilates {} and possibly more (functions linear along each segment) besides the \
         constants, a kernel the solver does not remove; use --operator family:T (0 < T < 1), \
         whose blend with the Laplacian has only the constants in its kernel{}",
        surface.describe(*direction),
        surface.operator(),
        match direction {
            Some(_) => format!("the linear function u·{}", surface.symbol()),
            None => format!("{} itself", surface.symbol()),
        },
        if *surface == SecondSurface::Mesh { ", or --operator laplace for a flat domain" } else { "" }
    )]
    ParallelFaces {
        /// The operator asked for.
        operator: Operator,
        /// Which surface `f2` is.
        surface: SecondSurface,
        /// The smallest vertex of the piece.
        vertex: usize,
        /// A unit direction `u` every triangle of the piece is parallel to (`None`: every
        /// triangle is a segment, parallel to every direction).
        direction: Option<[f64; 3]>,
    },
    /// A Dirac pencil on `D_{f,f2}` with a piece where corners of the triangles of `f2`
    /// coincide along rulings (a crease between flat panels, a cylinder of straight rulings)
    /// whose kernel may be larger than its constant and `u f2` but is not computed: its rigid
    /// parts have more parameters than a dense count takes.
    #[error(
        "the {operator} operator is not solved here: on the piece of vertex {vertex}, corners of \
         the triangles of {} coincide along rulings (a crease between flat panels, or a \
         cylinder of straight rulings) tied together at single vertices, where the kernel of \
         {} may be larger than the constant and the linear function, and is computed for at \
         most {} parameters of rigid parts; use --operator family:T (0 < T < 1), whose blend \
         with the Laplacian has only the constants in its kernel",
        surface.symbol(),
        surface.operator(),
        first_order::PARAMETERS_COMPUTED
    )]
    RuledKernel {
        /// The operator asked for.
        operator: Operator,
        /// Which surface `f2` is.
        surface: SecondSurface,
        /// The smallest vertex of the piece.
        vertex: usize,
    },
    /// Fewer nonzero eigenvalues exist than were asked for.
    #[error(
        "asked for {wanted} nonzero eigenvalues, but outside its kernel of dimension \
         {kernel_dimension} the operator has only {available}; {}ask for fewer, or list the \
         kernel too (--include-kernel)",
        weld_advice(*components, "")
    )]
    TooFewNonzero {
        /// Nonzero eigenvalues wanted.
        wanted: usize,
        /// Nonzero eigenvalues the mesh has.
        available: usize,
        /// Quaternionic dimension of the kernel.
        kernel_dimension: usize,
        /// Connected components of the mesh: each carries its own kernel, so a triangle soup
        /// (one component per face) has a kernel of about the whole space.
        components: usize,
    },
    /// The matrix the eigensolver factorises is numerically singular: the operator nearly
    /// vanishes somewhere without vanishing exactly (almost but not exactly flat faces), so its
    /// smallest eigenvalues there are below what double precision resolves against the rest
    /// of the mesh.
    #[error(
        "{}",
        nearly_singular_message(*.vertex, *.flatness, *.flat_tolerance, *.sliver, *.remedy)
    )]
    NearlySingular {
        /// Where the factorisation failed (native backend), original numbering.
        vertex: Option<usize>,
        /// A face around that vertex whose height is at most `10⁻⁹` of the mesh's size (a
        /// sliver, its corners collinear to rounding), which `--repair` removes: the likely
        /// cause.
        sliver: Option<usize>,
        /// The flatness `|N_a − N_b| √area / |f_a − f_b|` of the faces around it (relative
        /// Dirac), which the flat tolerance bounds: the largest of the nearly flat ones (at most
        /// `10⁻²`), or the smallest when all are more curved.
        flatness: Option<f64>,
        /// The flat tolerance in force.
        flat_tolerance: f64,
        /// What the operator's options can change.
        remedy: Remedy,
    },
    /// The literal family is solved from the bottom of its spectrum (its matrix `(1−τ)L + τG`
    /// is indefinite, and the eigensolver factorises positive definite matrices only), and on
    /// this mesh so many of its eigenvalues are negative that all of them would have to be
    /// computed before the wanted ones.
    #[error(
        "the literal family is strongly indefinite on this mesh: it is solved from the bottom of \
         its spectrum, and at least {negative} of its eigenvalues are negative (the lowest \
         {lowest:.3e}), below the {wanted} nonzero ones of smallest |λ|; use --operator family:T, the \
         blended pencil, which is definite, or a smaller T"
    )]
    IndefiniteLiteralFamily {
        /// Nonzero eigenvalues wanted.
        wanted: usize,
        /// Negative eigenvalues computed before giving up (a lower bound on their number).
        negative: usize,
        /// The lowest eigenvalue.
        lowest: f64,
    },
    /// [`relative_spectrum`] was given a reference surface with another triangulation.
    #[error(
        "the reference surface must be the same triangulation as the mesh (same vertices in \
         the same order, same faces): {0}"
    )]
    ReferenceConnectivity(#[from] ConnectivityMismatch),
    /// [`relative_spectrum`] was asked for an operator that does not use the Gauss map, so a
    /// reference surface has nothing to replace.
    #[error(
        "operator {operator} does not use the Gauss map, so a reference surface would change \
         nothing; use relative-dirac (D_{{f1,f2}}), squared or family:T"
    )]
    ReferenceUnused {
        /// The operator asked for.
        operator: Operator,
    },
    /// The eigensolver stopped early; `partial` holds what converged, post-processed like a
    /// full result.
    #[error(
        "the eigensolver converged {} of {wanted} eigenvalues{}",
        partial.eigenvalues.len(),
        unaccepted.explanation(&partial.eigenvalues).map_or(String::new(), |e| format!("; {e}"))
    )]
    NotConverged {
        /// Eigenvalues asked for.
        wanted: usize,
        /// The converged part.
        partial: Box<Spectrum>,
        /// The pairs the eigensolver found that are not in `partial`, and why.
        unaccepted: Unaccepted,
    },
}

/// The pairs an eigensolve found that did not pass the convergence test of the operator's own
/// eigenproblem (module documentation, "Results"), so that [`SpectrumError::NotConverged`]
/// does not list them: what they tell is said in its message.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Unaccepted {
    /// Pairs whose eigenvalue is at infinity (`|λ| ‖Q‖` beyond `‖P‖ /`
    /// [`ROUNDING_BACKWARD_ERROR`]: `Q` vanishes on them to rounding); when there are any,
    /// the operator has no further finite nonzero eigenvalues to find.
    pub at_infinity: usize,
    /// Pairs of finite eigenvalue whose residual is above what the tolerance accepts.
    pub inaccurate: usize,
    /// The smallest `|λ|` among the inaccurate pairs (`None` without any): where it is below
    /// the largest converged `|λ|`, the converged list has a gap.
    pub smallest_inaccurate: Option<f64>,
    /// The largest relative residual of the inaccurate pairs (`0` without any).
    pub largest_residual: f64,
    /// What the operator's options can change, when the inaccurate pairs show that it is
    /// singular to rounding.
    pub remedy: Remedy,
}

/// What a user can change when the operator nearly vanishes on some functions without
/// vanishing exactly, so that its smallest eigenvalues are below what double precision
/// resolves: the advice that ends [`SpectrumError::NearlySingular`]'s message and
/// [`Unaccepted::explanation`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Remedy {
    /// Nothing the options change (the Laplace-type operators and the literal family).
    #[default]
    None,
    /// The blended family `L(τ)` instead of an operator built on `D_N` or `D_f` alone.
    Family,
    /// The family with less weight on `D_N`: a smaller `τ`, or, for a mesh whose area is far
    /// below 1 and not normalised, unit area. The family mixes `τA ∝ 1/s²` with
    /// `(1−τ)L ∝ 1` (docs/MATH.md, "Scaling and rigid motions"), so at area `a` its `τ` weighs
    /// `D_N` as `effective_tau = τ / (τ + (1−τ) a)` does at unit area.
    LessDirac {
        /// The mesh's area as solved.
        area: f64,
        /// The `τ` of the unit-area mesh that the pencil equals.
        effective_tau: f64,
    },
}

impl Remedy {
    /// The remedy for `operator` on a mesh of total area `area` (as solved, after any
    /// normalisation).
    pub fn of(operator: Operator, area: f64) -> Self {
        match operator {
            Operator::RelativeDirac | Operator::ExtrinsicDirac | Operator::Squared => {
                Remedy::Family
            }
            Operator::Family { tau } => Remedy::LessDirac {
                area,
                effective_tau: effective_tau(tau, area),
            },
            Operator::Laplace
            | Operator::FamilyLiteral { .. }
            | Operator::ModifiedDirichlet
            | Operator::AnisotropicLaplace { .. } => Remedy::None,
        }
    }

    /// The advice, as a clause (`None` for [`Remedy::None`]).
    fn advice(self) -> Option<String> {
        match self {
            Remedy::None => None,
            Remedy::Family => Some("use --operator family:T (0 < T < 1)".to_string()),
            // An area within a factor 10 of 1 changes the weight little.
            Remedy::LessDirac {
                area,
                effective_tau,
            } if area < 0.1 => Some(format!(
                "use --normalize unit-area: the family's balance of D_N and the Laplacian \
                 depends on the scale, and at this mesh's area {area:.1e} its T weighs D_N as \
                 T = {} does at unit area (or use a smaller T)",
                if effective_tau > 0.999 {
                    format!("1 − {:.1e}", 1.0 - effective_tau)
                } else {
                    format!("{effective_tau:.3}")
                }
            )),
            Remedy::LessDirac { .. } => {
                Some("use a smaller T in --operator family:T (T = 0 is the Laplacian)".to_string())
            }
        }
    }
}

/// The `τ` at which the family on the unit-area version of a mesh equals the family at weight
/// `tau` on the mesh of area `area` (docs/MATH.md, "Scaling and rigid motions": `τA ∝ 1/s²`
/// against `(1−τ)L ∝ 1`; eigenvalues are divided by the area besides).
fn effective_tau(tau: f64, area: f64) -> f64 {
    tau / (tau + (1.0 - tau) * area)
}

/// Areas outside `[1/RANGE, RANGE]` (lengths beyond a factor 10 of unit area's) are far enough
/// from 1 for [`scale_warning`].
const UNIT_AREA_RANGE: f64 = 100.0;

/// A warning for options whose meaning depends on the mesh's scale, or `None`: the blended
/// family with `0 < τ < 1` on a mesh that is not normalised and whose area is outside
/// `[0.01, 100]` weighs `D_N` as another `τ` does at unit area, so the same `family:τ` means
/// different operators for a mesh in millimetres and in metres ([`Remedy::LessDirac`]). The
/// command line prints it and the Python package warns with it.
pub fn scale_warning(mesh: &TriMesh, options: &SpectrumOptions) -> Option<String> {
    let tau = options.weight_by_scale()?;
    let area: f64 = (0..mesh.face_count()).map(|t| mesh.face_area(t)).sum();
    let far = !(1.0 / UNIT_AREA_RANGE..=UNIT_AREA_RANGE).contains(&area);
    far.then(|| {
        format!(
            "the family weighs D_N and the Laplacian by the mesh's scale: at its area {area:.1e} \
             (not normalised) the weight {tau} of D_N acts as {:.2e} does on the mesh scaled to \
             unit area; --normalize unit-area makes the weight mean the same on every mesh",
            effective_tau(tau, area)
        )
    })
}

impl Unaccepted {
    /// A suggestion of tolerance is made only up to this: a pair whose relative residual is
    /// `100 ×` this or more is not an accurate pair short of a tight tolerance.
    pub const LARGEST_SUGGESTED_TOLERANCE: f64 = 1e-6;

    /// The pairs not converged among `measured` (`converged` flags those that are), and what
    /// to do if they show that the operator is singular to rounding.
    fn of(eigenvalues: &[f64], measured: &[Residual], converged: &[bool], remedy: Remedy) -> Self {
        let mut unaccepted = Self {
            remedy,
            ..Self::default()
        };
        for ((lambda, r), _) in
            (eigenvalues.iter().zip(measured).zip(converged)).filter(|(_, converged)| !**converged)
        {
            if r.beyond_floor {
                unaccepted.at_infinity += 1;
                continue;
            }
            unaccepted.inaccurate += 1;
            unaccepted.largest_residual = unaccepted.largest_residual.max(r.relative);
            let smallest = unaccepted.smallest_inaccurate.get_or_insert(lambda.abs());
            *smallest = smallest.min(lambda.abs());
        }
        unaccepted
    }

    /// The tolerance at which every inaccurate pair counts as converged (its largest relative
    /// residual over [`CONVERGED_RESIDUAL_FACTOR`], rounded up to one significant digit), when
    /// it is at most [`Self::LARGEST_SUGGESTED_TOLERANCE`].
    pub fn accepting_tolerance(&self) -> Option<f64> {
        if self.inaccurate == 0 {
            return None;
        }
        let needed = self.largest_residual / CONVERGED_RESIDUAL_FACTOR;
        let unit = 10f64.powf(needed.log10().floor());
        // Less a rounding's worth, so that `3e-11 / 1e-11 = 3.0000000000000004` stays 3.
        let rounded = (needed / unit - 1e-9).ceil() * unit;
        (rounded <= Self::LARGEST_SUGGESTED_TOLERANCE * (1.0 + 1e-9)).then_some(rounded)
    }

    /// What these pairs tell a reader of the `converged` eigenvalues, with what to do, for a
    /// message (`None` when there are none).
    pub fn explanation(&self, converged: &[f64]) -> Option<String> {
        let mut sentences = Vec::new();
        if let Some(smallest) = self.smallest_inaccurate {
            let count = self.inaccurate;
            let below = converged.iter().any(|l| l.abs() > smallest);
            let them = if count == 1 { "it" } else { "them" };
            let verdict = if let Some(tolerance) = self.accepting_tolerance() {
                format!("short of the tolerance: --tolerance {tolerance:.0e} accepts {them}")
            } else if self.largest_residual
                > CONVERGED_RESIDUAL_FACTOR * Self::LARGEST_SUGGESTED_TOLERANCE
            {
                // Pairs the Lanczos accepted that fail the operator's own test by this much
                // come from applying an operator that is singular to rounding.
                let fact = "far beyond any tolerance: the operator nearly vanishes on some \
                            functions without vanishing exactly (as D_N does on developable \
                            parts such as thin cylinders and cones), so its smallest eigenvalues \
                            are below what double precision resolves";
                match self.remedy.advice() {
                    Some(advice) => format!("{fact}; {advice}"),
                    None => fact.to_string(),
                }
            } else {
                String::from("short of the tolerance")
            };
            let sentence = format!(
                "{count} other pair{} with |λ| from {smallest:.4e}{} {} computed to relative \
                 residuals up to {:.1e}, {verdict}",
                plural(count),
                if below {
                    ", below some of those listed,"
                } else {
                    ""
                },
                if count == 1 { "was" } else { "were" },
                self.largest_residual,
            );
            sentences.push(sentence);
        }
        if self.at_infinity > 0 {
            let count = self.at_infinity;
            sentences.push(format!(
                "{count} other pair{} found {} eigenvalue{} at infinity (the coupling \
                 vanishes on {} to rounding), so outside its kernel the operator has only \
                 {} finite nonzero eigenvalue{} to find: ask for fewer, or use \
                 --operator family:T (0 < T < 1)",
                plural(count),
                if count == 1 { "is an" } else { "are" },
                plural(count),
                if count == 1 { "it" } else { "them" },
                converged.len(),
                plural(converged.len()),
            ));
        }
        (!sentences.is_empty()).then(|| sentences.join("; "))
    }
}

/// `"s"` unless `count` is one.
fn plural(count: usize) -> &'static str {
    if count == 1 { "" } else { "s" }
}

/// The message of [`SpectrumError::NearlySingular`].
fn nearly_singular_message(
    vertex: Option<usize>,
    flatness: Option<f64>,
    tolerance: f64,
    sliver: Option<usize>,
    remedy: Remedy,
) -> String {
    let place = vertex.map_or(String::new(), |v| format!(" near vertex {v}"));
    if let Some(face) = sliver {
        return format!(
            "the operator is numerically singular{place}: face {face} there is a sliver (its \
             height is at most 10⁻⁹ of the mesh's size, its corners collinear to rounding), \
             whose cotangent weights are beyond what double precision resolves; remove such \
             faces with --repair"
        );
    }
    let or_remedy = remedy
        .advice()
        .map_or(String::new(), |a| format!(", or {a}"));
    let then_remedy = remedy.advice().map_or(String::new(), |a| format!("; {a}"));
    let (how, remedy) = match flatness {
        Some(s) if s > NEARLY_FLAT => (
            format!(
                " (every face around it has flatness {s:.1e} or more, |N_a − N_b| √area / \
                 |f_a − f_b|: curved, not nearly flat)"
            ),
            format!(
                "a flat tolerance would not help: D_N nearly vanishes on functions constant \
                 along straight lines of the surface (developable parts such as thin cylinders \
                 and cones){then_remedy}"
            ),
        ),
        Some(s) if s > tolerance => (
            format!(
                " (its nearly flat faces have flatness up to {s:.1e}, |N_a − N_b| √area / \
                 |f_a − f_b|, above the flat tolerance {tolerance:.0e})"
            ),
            format!(
                "treat such faces as flat with --flat-tolerance {:.0e}{or_remedy}",
                10f64.powf((10.0 * s).log10().ceil())
            ),
        ),
        Some(_) => {
            return format!(
                "the operator is numerically singular{place} (the nearly flat faces around it \
                 are flat already, within the flat tolerance {tolerance:.0e}): it vanishes \
                 there, or nearly, on functions that the exact kernel does not remove (neither \
                 flat vertices nor modes of the pieces its rows join){then_remedy}"
            );
        }
        None => (
            String::new(),
            format!("treat such faces as flat with --flat-tolerance a larger value{or_remedy}"),
        ),
    };
    format!(
        "the operator is numerically singular{place}{how}: it nearly vanishes there without \
         vanishing exactly, so its smallest eigenvalues are below what double precision \
         resolves against the rest of the mesh; {remedy}"
    )
}

/// The eigenproblem `P x = λ Q x` of an operator, with the matrices as assembled (flat faces
/// not zeroed; for positions stored in single precision, with the Gauss map's noisy planes
/// given their planes' normals, docs/MATH.md): what [`spectrum`] solves and measures its
/// residuals against, for checking a result or feeding another solver. Quaternionic matrices
/// of size `n × n`; [`SparseMatrix::to_real_block`] and [`SparseMatrix::to_complex_adjoint`]
/// give the `4n × 4n` real and `2n × 2n` complex forms.
#[derive(Debug, Clone)]
pub struct Eigenproblem {
    /// `P`: `L` (Laplace), `K_α` (anisotropic Laplace), `L + M diag(U)` (modified Dirichlet), `A = D* M_F D` (relative and
    /// extrinsic Dirac, squared), `τA + (1−τ)L` (family), `(1−τ)L + τG` (literal family).
    pub stiffness: SparseMatrix<Quat<f64>>,
    /// `Q`: `M` (Laplace, anisotropic Laplace, modified Dirichlet, squared, literal family), `G = sym(Bᵀ M_F D)`
    /// (relative and extrinsic Dirac), `τG + (1−τ)M` (family).
    pub coupling: SparseMatrix<Quat<f64>>,
    /// The barycentric vertex masses `Ā_p`, the diagonal of `M`.
    pub masses: Vec<f64>,
    /// Factor applied to the positions ([`Normalization`]; 1 without normalisation).
    pub scale: f64,
}

/// The eigenproblem of `options.operator` on `mesh`, after `options.normalization` and with
/// `options.well`; `options.k`, the backend and the solver settings are not used.
pub fn eigenproblem(
    mesh: &TriMesh,
    options: &SpectrumOptions,
) -> Result<Eigenproblem, SpectrumError> {
    assembled_eigenproblem(mesh, None, options)
}

/// The eigenproblem [`relative_spectrum`] solves: `options.operator` built on `D_{f1,f2}` with
/// `f2` the positions of `reference` in place of the Gauss map, as [`eigenproblem`] gives it.
pub fn relative_eigenproblem(
    mesh: &TriMesh,
    reference: &TriMesh,
    options: &SpectrumOptions,
) -> Result<Eigenproblem, SpectrumError> {
    check_reference(mesh, reference, options)?;
    assembled_eigenproblem(mesh, Some(reference), options)
}

/// [`eigenproblem`] relative to `reference` if given.
fn assembled_eigenproblem(
    mesh: &TriMesh,
    reference: Option<&TriMesh>,
    options: &SpectrumOptions,
) -> Result<Eigenproblem, SpectrumError> {
    validate_operator(options)?;
    let Assembled {
        scale,
        mesh,
        pencil,
    } = assemble(mesh, reference, options)?;
    let operator = pencil.into_quaternionic().operator;
    Ok(Eigenproblem {
        stiffness: operator.stiffness,
        coupling: operator.coupling,
        masses: barycentric_masses(&mesh),
        scale,
    })
}

/// The mesh as solved and the operator's pencil on it.
struct Assembled<'a> {
    /// Factor applied to the positions.
    scale: f64,
    /// The mesh after normalisation.
    mesh: Cow<'a, TriMesh>,
    /// The pencil, with the well when there is one.
    pencil: OperatorPencil,
}

/// Normalises `mesh` (and the `reference` surface by the same factor) and assembles the
/// pencil of `options.operator` on it.
fn assemble<'a>(
    mesh: &'a TriMesh,
    reference: Option<&TriMesh>,
    options: &SpectrumOptions,
) -> Result<Assembled<'a>, SpectrumError> {
    let (scale, scaled) = normalized(mesh, options.normalization)?;
    let mesh = scaled.map_or(Cow::Borrowed(mesh), Cow::Owned);
    let potential = options.well.map(|w| w.potential(&mesh)).transpose()?;
    let reference: Option<Vec<[f64; 3]>> = reference.map(|r| {
        r.positions()
            .iter()
            .map(|&p| geometry::scale(p, scale))
            .collect()
    });
    let pencil = OperatorPencil::for_operator(
        options.operator,
        &mesh,
        reference.as_deref(),
        potential.as_deref(),
        options.flat_tolerance,
    )?;
    Ok(Assembled {
        scale,
        mesh,
        pencil,
    })
}

/// The spectrum of `options.operator` on `mesh`; see the module documentation for the pencils.
pub fn spectrum(mesh: &TriMesh, options: &SpectrumOptions) -> Result<Spectrum, SpectrumError> {
    spectrum_with_progress(mesh, options, None)
}

/// [`spectrum`] with a callback invoked whenever the eigensolver reports (after every restart,
/// and between restarts at least every 0.1 s: [`qeig::ProgressCallback`]). When it returns
/// [`std::ops::ControlFlow::Break`], the solve stops and the result is
/// [`SpectrumError::NotConverged`] with the pairs converged so far.
pub fn spectrum_with_progress(
    mesh: &TriMesh,
    options: &SpectrumOptions,
    progress: Option<ProgressCallback>,
) -> Result<Spectrum, SpectrumError> {
    compute(mesh, None, options, progress)
}

/// The spectrum of the relative Dirac operator `D_{f1,f2}` of two immersions of one
/// triangulation (paper §4, Fig. 3): `f1` the positions of `mesh`, `f2` those of `reference`,
/// which must have the same faces ([`TriMesh::check_same_connectivity`]). Every operator built
/// on `D_N = D_{f,N}` is built on `D_{f1,f2}` instead: `relative-dirac` (pencil
/// `A x = λ G x`, `A = D* M_F D`, `G = sym(Bᵀ M_F D)`, areas and masses of `f1`), `squared`
/// and the family `L(τ)` (blended with the Laplacian of `f1`). The kernel is the constants of
/// each component (no row of `D_{f1,f2}` vanishes: the faces of `f2` have positive area).
/// With [`Normalization::UnitArea`] both surfaces are scaled by `f1`'s factor, so
/// `reference = mesh` gives exactly the spectrum of the extrinsic Dirac operator `D_f`.
pub fn relative_spectrum(
    mesh: &TriMesh,
    reference: &TriMesh,
    options: &SpectrumOptions,
) -> Result<Spectrum, SpectrumError> {
    relative_spectrum_with_progress(mesh, reference, options, None)
}

/// [`relative_spectrum`] with the progress callback of [`spectrum_with_progress`].
pub fn relative_spectrum_with_progress(
    mesh: &TriMesh,
    reference: &TriMesh,
    options: &SpectrumOptions,
    progress: Option<ProgressCallback>,
) -> Result<Spectrum, SpectrumError> {
    check_reference(mesh, reference, options)?;
    compute(mesh, Some(reference), options, progress)
}

/// `options.operator` takes a second surface in place of the Gauss map, and `reference` has
/// `mesh`'s triangulation.
fn check_reference(
    mesh: &TriMesh,
    reference: &TriMesh,
    options: &SpectrumOptions,
) -> Result<(), SpectrumError> {
    if !options.operator.uses_gauss_map() {
        return Err(SpectrumError::ReferenceUnused {
            operator: options.operator,
        });
    }
    Ok(mesh.check_same_connectivity(reference)?)
}

/// The spectrum of `options.operator` on `mesh`, relative to `reference` when given: a real
/// operator in real arithmetic with the native backend, over the quaternions otherwise
/// ([`SolverBackend`]).
fn compute(
    mesh: &TriMesh,
    reference: Option<&TriMesh>,
    options: &SpectrumOptions,
    progress: Option<ProgressCallback>,
) -> Result<Spectrum, SpectrumError> {
    validate(mesh, options)?;
    let stored = mesh;
    let Assembled {
        scale,
        mesh,
        pencil,
    } = assemble(mesh, reference, options)?;
    let mesh = mesh.as_ref();
    let floor = data_floor(stored, reference, options, &pencil, mesh)?.max(ROUNDING_BACKWARD_ERROR);
    match (pencil, options.backend) {
        (OperatorPencil::Real(spec), SolverBackend::Native) => {
            solve_pencil(spec, mesh, scale, floor, options, progress)
        }
        (pencil, _) => {
            let spec = pencil.into_quaternionic();
            solve_pencil(spec, mesh, scale, floor, options, progress)
        }
    }
}

/// For positions stored in single precision, the relative change of the operator's matrices
/// that their rounding alone makes: `max(‖P' − P‖ / ‖P‖, ‖Q' − Q‖ / ‖Q‖)` in the norms of the
/// backward error, `P'`, `Q'` assembled again at positions each moved by a seeded random
/// amount up to its rounding (`2⁻²⁴ |x|`). The matrices are known no better than that, so a
/// pair exact for a change that small is as accurate as the data (docs/MATH.md, "Coordinates
/// in single precision"). `0` for positions of double precision, or if the moved mesh is
/// invalid.
fn data_floor(
    stored: &TriMesh,
    reference: Option<&TriMesh>,
    options: &SpectrumOptions,
    pencil: &OperatorPencil,
    solved: &TriMesh,
) -> Result<f64, SpectrumError> {
    if stored.single_precision_rounding().is_none() {
        return Ok(0.0);
    }
    let mut random = qscalar::random::SplitMix64::new(options.seed);
    let relative = f64::from(f32::EPSILON) / 2.0;
    let Ok(moved) =
        stored.map_positions(|p| p.map(|x| x + x * relative * random.uniform(-1.0, 1.0)))
    else {
        return Ok(0.0);
    };
    let Ok(again) = assemble(&moved, reference, options) else {
        return Ok(0.0);
    };
    pencil.relative_change(&again.pencil, &barycentric_masses(solved))
}

/// The spectrum of the pencil `spec` over its scalar `T` on `mesh` (as solved, positions
/// multiplied by `scale`).
fn solve_pencil<T: Scalar<Real = f64>>(
    mut spec: PencilSpec<T>,
    mesh: &TriMesh,
    scale: f64,
    floor: f64,
    options: &SpectrumOptions,
    mut progress: Option<ProgressCallback>,
) -> Result<Spectrum, SpectrumError> {
    let masses = barycentric_masses(mesh);
    // Taken: the kernel's pieces are consumed by its search, before the solve's peak of memory.
    let first_order = spec.first_order.take();
    // A kernel that may be larger than what is removed is an error: the pinned form needs `P`
    // definite once the known kernel is out, and the shifted form would list the rest as
    // eigenvalues `0` among the nonzero ones.
    if let Some(first_order) = &first_order
        && let Some(unremoved) = first_order.unremoved
    {
        let (operator, surface) = (options.operator, first_order.surface);
        return Err(match unremoved {
            Unremoved::Segments { vertex, direction } => SpectrumError::ParallelFaces {
                operator,
                surface,
                vertex,
                direction,
            },
            Unremoved::Rulings { vertex } => SpectrumError::RuledKernel {
                operator,
                surface,
                vertex,
            },
        });
    }
    let structure = match first_order {
        Some(k) => k.structure,
        None => KernelStructure::of_pieces(kernel::pieces(mesh, &spec.flat)),
    };
    // The zeroed part of the coupling (as large as the coupling) only judges the modes: it is
    // dropped before the solve.
    let kernel = ExactKernel::find(
        mesh,
        &masses,
        &spec.flat,
        structure,
        &spec.solved().stiffness,
        &spec.solved().coupling,
        spec.zeroed_coupling()?.as_ref(),
    );
    let listed = if options.include_kernel {
        kernel.summary().dimension.min(options.k)
    } else {
        0
    };
    let wanted = options.k - listed;
    let report = |mut pairs: Pairs<T>| {
        pairs.values.splice(0..0, vec![0.0; listed]);
        pairs.vectors.splice(0..0, kernel.basis(&masses, listed));
        finish(
            pairs,
            &spec.operator,
            &masses,
            options,
            scale,
            floor,
            kernel.summary(),
        )
    };
    if wanted == 0 {
        return report(Pairs::none());
    }
    let reduced = solve::reduce(spec.form, spec.solved(), &kernel, &masses)?;
    check_available(&kernel, wanted, reduced.available(), mesh, options.operator)?;
    let problem = solve::Problem {
        reduced: &reduced,
        form: spec.form,
        matrices: spec.solved(),
        kernel: &kernel,
        masses: &masses,
    };
    let area: f64 = masses.iter().sum();
    let singular = |e| singular_error(e, &spec, mesh, options, area);
    let Solved { pairs, mut reduced } = problem
        .solve(wanted, options, &mut progress)
        .map_err(singular)?;
    let complete = pairs.complete;
    let mut result = report(pairs);
    // Pairs the eigensolver accepted that fail the operator's own test: refined by steps of
    // subspace iteration (module documentation, "Results"); a result replaces the one before
    // only if more pairs converge.
    for _ in 0..REFINEMENT_STEPS {
        let (Some(eigen), Err(SpectrumError::NotConverged { unaccepted, .. })) =
            (&reduced, &result)
        else {
            break;
        };
        if unaccepted.inaccurate == 0 {
            break;
        }
        let refined = problem.refine(eigen, complete).map_err(singular)?;
        reduced = refined.reduced;
        let candidate = report(refined.pairs);
        if converged_count(&candidate, options.k) > converged_count(&result, options.k) {
            result = candidate;
        }
    }
    result
}

/// At most this many steps of [`solve::Problem::refine`] for pairs the eigensolver accepted
/// that fail the operator's own convergence test: each shrinks what lies outside the wanted
/// pairs' span by the ratio of the largest eigenvalue outside to the smallest inside.
const REFINEMENT_STEPS: usize = 2;

/// How many of `k` pairs a result lists as converged.
fn converged_count(result: &Result<Spectrum, SpectrumError>, k: usize) -> usize {
    match result {
        Ok(_) => k,
        Err(SpectrumError::NotConverged { partial, .. }) => partial.eigenvalues.len(),
        Err(_) => 0,
    }
}

/// `k` and the operator's parameter in range, flat tolerance valid.
fn validate(mesh: &TriMesh, options: &SpectrumOptions) -> Result<(), SpectrumError> {
    let n = mesh.vertex_count();
    if options.k == 0 || options.k > n {
        return Err(SpectrumError::InvalidCount {
            k: options.k,
            vertices: n,
        });
    }
    if !(options.tolerance > 0.0 && options.tolerance < 1.0) {
        return Err(SpectrumError::InvalidTolerance(options.tolerance));
    }
    if options.max_restarts == 0 {
        return Err(SpectrumError::InvalidMaxRestarts);
    }
    validate_operator(options)
}

/// The operator's parameter in range, flat tolerance valid.
fn validate_operator(options: &SpectrumOptions) -> Result<(), SpectrumError> {
    if let Some((parameter, value)) = options.operator.parameter()
        && !parameter.contains(value)
    {
        return Err(SpectrumError::InvalidParameter {
            operator: options.operator.name(),
            parameter,
            value,
        });
    }
    if !(options.flat_tolerance >= 0.0 && options.flat_tolerance.is_finite()) {
        return Err(SpectrumError::InvalidFlatTolerance(options.flat_tolerance));
    }
    Ok(())
}

/// The scale factor and, unless it is 1, the scaled mesh.
fn normalized(
    mesh: &TriMesh,
    normalization: Normalization,
) -> Result<(f64, Option<TriMesh>), SpectrumError> {
    match normalization {
        Normalization::None => Ok((1.0, None)),
        Normalization::UnitArea => {
            let area: f64 = (0..mesh.face_count()).map(|t| mesh.face_area(t)).sum();
            let scale = 1.0 / area.sqrt();
            // Fails when scaling leaves floating-point range (coordinates overflow, or a
            // face's area or angles degenerate).
            let scaled = mesh
                .scaled(scale)
                .map_err(|source| SpectrumError::Normalization { scale, source })?;
            Ok((scale, Some(scaled)))
        }
    }
}

/// The advice, for an error about the kernel, that a mesh in several pieces may be an
/// unwelded triangle soup (empty for one piece); `kind` qualifies the pieces ("flat ").
fn weld_advice(components: usize, kind: &str) -> String {
    if components > 1 {
        format!(
            "the mesh is {components} separate {kind}pieces (an unwelded triangle soup, if there \
             is one piece per face): weld its coincident vertices with --repair, or "
        )
    } else {
        String::new()
    }
}

/// Fails unless `wanted` nonzero pairs exist outside the kernel (`available` of them do).
fn check_available<T: Scalar<Real = f64>>(
    kernel: &ExactKernel<T>,
    wanted: usize,
    available: usize,
    mesh: &TriMesh,
    operator: Operator,
) -> Result<(), SpectrumError> {
    if wanted <= available {
        return Ok(());
    }
    let summary = kernel.summary();
    let vertices = mesh.vertex_count();
    let components = mesh.topology().components.len();
    Err(if available == 0 && summary.flat_vertices == vertices {
        SpectrumError::VanishingOperator {
            operator,
            vertices,
            components,
        }
    } else {
        SpectrumError::TooFewNonzero {
            wanted,
            available,
            kernel_dimension: summary.dimension,
            components,
        }
    })
}

/// A solve error in the user's terms.
fn singular_error<T>(
    error: SolveError,
    spec: &PencilSpec<T>,
    mesh: &TriMesh,
    options: &SpectrumOptions,
    area: f64,
) -> SpectrumError {
    match error {
        SolveError::Other(e) => e,
        SolveError::Singular(vertex) => SpectrumError::NearlySingular {
            vertex,
            sliver: vertex.and_then(|v| crate::repair::sliver_around(mesh, v)),
            flatness: vertex
                .zip(spec.normals.as_ref())
                .map(|(v, normals)| flatness_around(mesh, normals, v)),
            flat_tolerance: options.flat_tolerance,
            remedy: Remedy::of(options.operator, area),
        },
    }
}

/// The indices of `values` by increasing `|λ|`, then by increasing `λ` among magnitudes equal
/// to within `relative` (consecutive magnitudes `a ≤ b` with `b − a ≤ relative · b` chain into
/// one run, sorted by `λ`).
///
/// A pair `±a` of opposite eigenvalues (symmetric shapes, flat and man-made ones above all)
/// is computed as `−a(1 + δ₁)` and `a(1 + δ₂)` with `δ` at rounding level, so sorting by `|λ|`
/// alone put it in either order depending on the last bits, which change with the CPU's
/// kernels and the solver's path; with the tie broken by sign the order is `−a, a` in every
/// run.
fn magnitude_order(values: &[f64], relative: f64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].abs().total_cmp(&values[b].abs()));
    let mut start = 0;
    while start < order.len() {
        let mut end = start + 1;
        while end < order.len() {
            let (previous, next) = (values[order[end - 1]].abs(), values[order[end]].abs());
            if next - previous > relative * next {
                break;
            }
            end += 1;
        }
        order[start..end].sort_by(|&a, &b| values[a].total_cmp(&values[b]));
        start = end;
    }
    order
}

/// Sorts by `|λ|` ([`magnitude_order`], ties within the pencil's cluster width
/// [`qeig::relative_cluster_width`]), keeps `k`, mass-orthonormalises within eigenspaces,
/// applies the canonical phase, measures residuals and splits off the pairs that are not
/// converged; the eigenvectors leave as quaternions.
fn finish<T: Scalar<Real = f64>>(
    pairs: Pairs<T>,
    operator: &Matrices<T>,
    masses: &[f64],
    options: &SpectrumOptions,
    scale: f64,
    floor: f64,
    kernel: KernelSummary,
) -> Result<Spectrum, SpectrumError> {
    let values = &pairs.values;
    let cluster_width = qeig::relative_cluster_width(options.tolerance);
    let mut order = magnitude_order(values, cluster_width);
    order.truncate(options.k);
    let eigenvalues: Vec<f64> = order.iter().map(|&i| values[i]).collect();
    // Moved, not copied: at a million vertices each copy of k eigenvectors is gigabytes.
    let mut slots: Vec<Option<Vec<T>>> = pairs.vectors.into_iter().map(Some).collect();
    let mut eigenvectors: Vec<Vec<T>> = (order.iter())
        .map(|&i| slots[i].take().expect("the order lists each pair once"))
        .collect();
    drop(slots);
    orthonormalize_and_canonicalize(masses, &eigenvalues, &mut eigenvectors, cluster_width);
    let norms = (
        scaled_norm(&operator.stiffness, masses),
        scaled_norm(&operator.coupling, masses),
    );
    let each = eigenvalues.iter().zip(&eigenvectors).collect();
    let measured: Vec<Residual> =
        threads::map_on_two_threads(each, |(&lambda, x): (&f64, &Vec<T>)| {
            Residual::of(operator, norms, masses, lambda, x, floor)
        });
    let converged: Vec<bool> = measured
        .iter()
        .map(|r| r.is_converged(options.tolerance, floor))
        .collect();
    let remedy = Remedy::of(options.operator, masses.iter().sum());
    let unaccepted = Unaccepted::of(&eigenvalues, &measured, &converged, remedy);
    let residuals = measured.iter().map(|r| r.relative).collect();
    let backward_errors = measured.iter().map(|r| r.backward_error).collect();
    let all = pairs.complete && eigenvalues.len() == options.k && converged.iter().all(|&c| c);
    let eigenvectors = eigenvectors.into_iter().map(quaternions).collect();
    let spectrum = Spectrum {
        eigenvalues: retain(eigenvalues, &converged),
        eigenvectors: retain(eigenvectors, &converged),
        residuals: retain(residuals, &converged),
        backward_errors: retain(backward_errors, &converged),
        statistics: pairs.statistics,
        scale,
        masses: masses.to_vec(),
        kernel,
        backward_error_floor: floor,
    };
    if all {
        Ok(spectrum)
    } else {
        Err(SpectrumError::NotConverged {
            wanted: options.k,
            partial: Box::new(spectrum),
            unaccepted,
        })
    }
}

/// `x` as quaternions: the `REAL_DIM` real components of each entry as `(w, x, y, z)` in
/// order, the others zero (a real vector has zero imaginary part). A quaternion vector is
/// returned as it is, without a copy.
fn quaternions<T: Scalar<Real = f64>>(mut x: Vec<T>) -> Vec<Quat<f64>> {
    if let Some(q) = (&mut x as &mut dyn Any).downcast_mut::<Vec<Quat<f64>>>() {
        return std::mem::take(q);
    }
    T::as_reals(&x)
        .chunks_exact(T::REAL_DIM)
        .map(|c| {
            let mut q = [0.0; 4];
            q[..c.len()].copy_from_slice(c);
            Quat::new(q[0], q[1], q[2], q[3])
        })
        .collect()
}

/// The items whose flag is set.
fn retain<T>(items: Vec<T>, flags: &[bool]) -> Vec<T> {
    items
        .into_iter()
        .zip(flags)
        .filter(|(_, f)| **f)
        .map(|(x, _)| x)
        .collect()
}

/// How well a pair `(λ, x)` satisfies `P x = λ Q x`, in the dual norm `‖r‖² = Σ_p |r_p|²/Ā_p`
/// of integrated quantities (Euclidean norms would be dominated by sliver triangles, whose rows
/// of `P` are large and whose masses are tiny) and the mass norm `‖x‖_M` of vectors.
struct Residual {
    /// `‖P x − λ Q x‖ / (|λ| ‖Q x‖)`; for `λ = 0`, `‖P x‖ / (‖P‖ ‖x‖_M)`.
    relative: f64,
    /// The normwise backward error `‖P x − λ Q x‖ / ((‖P‖ + |λ| ‖Q‖) ‖x‖_M)`: the smallest
    /// relative change of `P` and `Q` for which the pair is exact.
    backward_error: f64,
    /// `|λ| ‖Q‖ ‖P‖⁻¹` is beyond the inverse of the backward-error floor: every `x` with `Q x`
    /// at that level has a backward error at the floor, so it says nothing (an eigenvalue at
    /// infinity, as where `Q` vanishes on the complement of the kernel of `P`).
    beyond_floor: bool,
}

/// A pair whose backward error is at most this is at the rounding floor of its problem: no
/// computation in double precision does better, however ill-conditioned the eigenvalue.
pub const ROUNDING_BACKWARD_ERROR: f64 = 1e3 * f64::EPSILON;

/// A pair is converged when its relative residual is at most this factor times the tolerance
/// (the eigensolver's tolerance bounds the residual of the reduced pencil it solves, which
/// differs from the operator's by a factor of order one).
pub const CONVERGED_RESIDUAL_FACTOR: f64 = 100.0;

impl Residual {
    /// Converged: relative residual at most [`CONVERGED_RESIDUAL_FACTOR`]` · tolerance`, or
    /// backward error at most `floor` ([`Spectrum::backward_error_floor`]: the rounding floor,
    /// or the precision of positions stored in single precision) for an eigenvalue that is
    /// not beyond the floor itself.
    fn is_converged(&self, tolerance: f64, floor: f64) -> bool {
        self.relative <= CONVERGED_RESIDUAL_FACTOR * tolerance
            || (self.backward_error <= floor && !self.beyond_floor)
    }

    /// The residual of the operator's own eigenproblem (matrices as assembled), with
    /// `norms = (‖P‖, ‖Q‖)` from [`scaled_norm`] and the backward-error `floor`.
    fn of<T: Scalar<Real = f64>>(
        m: &Matrices<T>,
        norms: (f64, f64),
        masses: &[f64],
        lambda: f64,
        x: &[T],
        floor: f64,
    ) -> Self {
        let dual = |r: &[T]| -> f64 {
            r.iter()
                .zip(masses)
                .map(|(q, a)| q.abs2() / a)
                .sum::<f64>()
                .sqrt()
        };
        // `P x` and `Q x` once: the difference and the scale both need `Q x`.
        let (mut residual, qx) = products(m, x);
        vector::axpy_real(&mut residual, &qx, -lambda);
        let difference = dual(&residual);
        let x_norm = mass_norm(masses, x);
        // An exact pair (`P x = λ Q x` to the last bit, as for the kernel of an operator that
        // vanishes identically, `P = Q = 0`) has no error, whatever the norms.
        let ratio = |scale: f64| {
            if difference == 0.0 {
                0.0
            } else {
                difference / scale
            }
        };
        let relative = if lambda == 0.0 {
            ratio(norms.0 * x_norm)
        } else {
            ratio(lambda.abs() * dual(&qx))
        };
        Self {
            relative,
            backward_error: ratio((norms.0 + lambda.abs() * norms.1) * x_norm),
            beyond_floor: lambda.abs() * norms.1 * floor > norms.0,
        }
    }
}

/// `max_p Σ_q |X_pq| / √(Ā_p Ā_q)`: a bound on `‖M^{-1/2} X M^{-1/2}‖₂`, the norm of `X` from
/// the mass norm to its dual.
fn scaled_norm<T: Scalar<Real = f64>>(x: &SparseMatrix<T>, masses: &[f64]) -> f64 {
    let mut rows = vec![0.0; masses.len()];
    for (p, q, v) in x.triplets() {
        rows[p] += v.abs() / (masses[p] * masses[q]).sqrt();
    }
    rows.into_iter().fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn opposite_eigenvalues_equal_in_magnitude_come_negative_first() {
        let a = 1.5e-4;
        // `+a` computed a hair smaller in magnitude than `−a`, and the other way round.
        for (plus, minus) in [(a * (1.0 - 1e-13), -a), (a, -a * (1.0 - 1e-13))] {
            let values = [2.0, plus, -3.0, minus, 1e-3];
            let sorted: Vec<f64> = (magnitude_order(&values, 1e-8).iter())
                .map(|&i| values[i])
                .collect();
            assert_eq!(sorted, [minus, plus, 1e-3, 2.0, -3.0]);
        }
        // Magnitudes farther apart than the tie keep their order by magnitude.
        let values = [-1.0 - 1e-6, 1.0];
        assert_eq!(magnitude_order(&values, 1e-8), [1, 0]);
    }

    proptest! {
        /// Any perturbation of a spectrum by rounding-level relative errors gives the same
        /// order of its (well separated) eigenvalues, and the order is a permutation sorted
        /// by magnitude up to ties.
        #[test]
        fn the_order_does_not_depend_on_the_last_bits(
            magnitudes in prop::collection::vec(1e-6f64..1e3, 1..12),
            signs in prop::collection::vec(any::<bool>(), 12),
            noise in prop::collection::vec(-1e-13f64..1e-13, 24),
        ) {
            // Each magnitude as a ± pair or a single value: well separated, or a tie.
            let mut exact = Vec::new();
            for (i, &m) in magnitudes.iter().enumerate() {
                let m = m * (1.0 + i as f64);
                exact.push(if signs[i] { m } else { -m });
                if signs[(i + 5) % 12] {
                    exact.push(-exact[exact.len() - 1]);
                }
            }
            let perturbed: Vec<f64> = (exact.iter().zip(&noise))
                .map(|(v, e)| v * (1.0 + e))
                .collect();
            let order = magnitude_order(&perturbed, 1e-8);
            let mut seen = order.clone();
            seen.sort_unstable();
            prop_assert_eq!(seen, (0..exact.len()).collect::<Vec<_>>());
            let signs_in_order = |values: &[f64]| -> Vec<bool> {
                magnitude_order(values, 1e-8).iter().map(|&i| values[i] < 0.0).collect()
            };
            prop_assert_eq!(signs_in_order(&perturbed), signs_in_order(&exact));
            for pair in order.windows(2) {
                let (a, b) = (perturbed[pair[0]].abs(), perturbed[pair[1]].abs());
                prop_assert!(a <= b * (1.0 + 1e-8), "{} before {}", a, b);
            }
        }
    }
}
