//! The operator and eigensolver options every command that computes a spectrum flattens into
//! its arguments, and their translation into [`SpectrumOptions`].

use std::convert::Infallible;

use clap::{Args, ValueEnum};
use dirac::spectrum::{Normalization, Operator, SolverBackend, SpectrumOptions};
use dirac::well::PotentialWell;

use crate::common::parsers::{nonnegative_real, positive_count, positive_real, replaced_tau};
use crate::common::preparation::MeshPreparation;

/// The help of `--operator`: the forms it accepts.
fn operator_help() -> String {
    format!(
        "The operator: {} (T ∈ [0, 1] is the weight of D_N in the family L(T); A ≥ 0 the \
         anisotropy of the anisotropic Laplacian, conductivity 1/(1 + A|κ|) along each \
         principal direction)",
        Operator::forms().join(", ")
    )
}

/// The options that define the eigenproblem `P x = λ Q x` of a mesh: the operator, the
/// mesh's preparation and normalisation, the flat tolerance and the potential well (flattened
/// into every command that solves or writes one).
#[derive(Debug, Clone, Args)]
pub struct ProblemArgs {
    /// The operator (`Display` form of [`Operator`]: `relative-dirac`, `family:0.5`, …).
    #[arg(long, value_name = "OPERATOR", default_value_t = Operator::RelativeDirac,
          help = operator_help())]
    pub operator: Operator,

    /// The former `--tau T`: refused with a usage error that names `--operator family:T`.
    #[arg(long, value_name = "T", hide = true, num_args = 0..=1, default_missing_value = "",
          allow_hyphen_values = true, value_parser = replaced_tau)]
    pub tau: Option<Infallible>,

    /// Repair and component selection of the mesh.
    #[command(flatten)]
    pub preparation: MeshPreparation,

    /// Scale normalisation applied to the mesh first.
    #[arg(long, value_enum, default_value_t = NormalizeArg::None)]
    pub normalize: NormalizeArg,

    /// Faces whose Gauss map is flat within T are treated as exactly flat (D_N vanishes on
    /// them): along each edge |N_a − N_b| ≤ T |f_a − f_b| / √area. Exactly flat regions of
    /// real meshes give 1e-13 or less, curved ones 1e-4 or more.
    #[arg(long, value_name = "T", default_value_t = dirac::spectrum::DEFAULT_FLAT_TOLERANCE,
          value_parser = nonnegative_real)]
    pub flat_tolerance: f64,

    /// Potential well (paper §5.1): radius β in geodesic distance; enables the well.
    #[arg(long, value_name = "BETA", value_parser = nonnegative_real, help_heading = "Potential well")]
    pub well_radius: Option<f64>,

    /// Centre vertex of the well (0-based); default: the vertex nearest the area centroid.
    #[arg(
        long,
        value_name = "V",
        requires = "well_radius",
        help_heading = "Potential well"
    )]
    pub well_center: Option<usize>,

    /// Steepness γ of the well.
    #[arg(long, value_name = "GAMMA", default_value_t = PotentialWell::with_radius(0.0).steepness,
          value_parser = nonnegative_real, requires = "well_radius",
          help_heading = "Potential well")]
    pub well_steepness: f64,

    /// Height c of the well.
    #[arg(long, value_name = "C", default_value_t = PotentialWell::with_radius(0.0).height,
          value_parser = nonnegative_real, requires = "well_radius",
          help_heading = "Potential well")]
    pub well_height: f64,
}

/// The operator and eigensolver options shared by every command that computes a spectrum
/// (flattened into each command's arguments).
#[derive(Debug, Clone, Args)]
pub struct SolveArgs {
    /// The eigenproblem.
    #[command(flatten)]
    pub problem: ProblemArgs,

    /// Number of eigenvalues (those of smallest |λ|).
    #[arg(short, default_value_t = 10, value_parser = positive_count)]
    pub k: usize,

    /// Representation the eigensolver works in.
    #[arg(long, value_enum, default_value_t = BackendArg::Native)]
    pub backend: BackendArg,

    /// Relative residual tolerance of the eigensolver. A pair is reported as converged when its
    /// residual ‖Pφ − λQφ‖ / (|λ| ‖Qφ‖) is at most 100 times this, or its backward error is at
    /// the rounding floor (1000 ε).
    #[arg(long, default_value = "1e-10", value_parser = positive_real)]
    pub tolerance: f64,

    /// Seed of the eigensolver's start vectors.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,

    /// Largest number of thick restarts of the eigensolver before it stops and reports the
    /// pairs that converged (exit code 3).
    #[arg(long, default_value_t = 1000, value_name = "N")]
    pub max_restarts: usize,

    /// List the kernel's eigenvalue 0 (flat vertices and constants, with a mass-orthonormal
    /// basis) among the k of smallest |λ|. Default: listed for laplace, anisotropic-laplace,
    /// modified-dirichlet, family-literal and the family with τ < 1 (whose kernel is at most the
    /// constants), not for relative-dirac,
    /// extrinsic-dirac and squared (whose kernel holds every flat vertex). The kernel's
    /// dimension is always reported.
    #[arg(long, conflicts_with = "exclude_kernel")]
    pub include_kernel: bool,

    /// Never list the kernel's eigenvalue 0 (see --include-kernel).
    #[arg(long)]
    pub exclude_kernel: bool,

    /// Keep the eigensolver on one thread. By default the triangular solves and Gram–Schmidt
    /// passes of large problems use a second core (not inside `batch`, whose jobs already do).
    #[arg(long)]
    pub single_thread: bool,
}

/// `--backend` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BackendArg {
    /// The native Cholesky on quaternion matrices (real ones, in real arithmetic, for laplace,
    /// anisotropic-laplace and modified-dirichlet).
    Native,
    /// 4n×4n real-block expansion.
    RealBlock,
    /// 2n×2n complex adjoint.
    ComplexAdjoint,
}

/// `--normalize` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum NormalizeArg {
    /// Use the mesh as given.
    None,
    /// Scale to unit total area.
    UnitArea,
}

impl ProblemArgs {
    /// The library options of this eigenproblem for `operator` and `k` pairs, the
    /// eigensolver's settings at their defaults.
    pub fn options(&self, operator: Operator, k: usize) -> SpectrumOptions {
        let mut options = SpectrumOptions::new(operator, k);
        options.normalization = match self.normalize {
            NormalizeArg::None => Normalization::None,
            NormalizeArg::UnitArea => Normalization::UnitArea,
        };
        options.well = self.well_radius.map(|radius| PotentialWell {
            center: self.well_center,
            radius,
            steepness: self.well_steepness,
            height: self.well_height,
        });
        options.flat_tolerance = self.flat_tolerance;
        options
    }
}

impl SolveArgs {
    /// The library options these arguments ask for. Pure: `--single-thread`, a process-wide
    /// setting, is applied by the dispatcher ([`SolveArgs::apply_thread_setting`]).
    pub fn options(&self) -> SpectrumOptions {
        self.options_with(self.problem.operator)
    }

    /// The options of [`SolveArgs::options`] with another operator (`dirac plot spectra
    /// --operators`); the kernel is listed by that operator's default.
    pub fn options_with(&self, operator: Operator) -> SpectrumOptions {
        let mut options = self.problem.options(operator, self.k);
        options.backend = match self.backend {
            BackendArg::Native => SolverBackend::Native,
            BackendArg::RealBlock => SolverBackend::RealBlock,
            BackendArg::ComplexAdjoint => SolverBackend::ComplexAdjoint,
        };
        options.tolerance = self.tolerance;
        options.seed = self.seed;
        options.max_restarts = self.max_restarts;
        options.include_kernel = self.lists_kernel(operator);
        options
    }

    /// Applies `--single-thread`: a process-wide setting of the eigensolver
    /// ([`qeig::threads::set_second_thread_allowed`]).
    pub fn apply_thread_setting(&self) {
        if self.single_thread {
            qeig::threads::set_second_thread_allowed(false);
        }
    }

    /// Switches `options` to the Laplacian for the heat kernel signature (`what` names it in
    /// the note), which is defined for the Laplacian only; a note on stderr says so when
    /// `--operator` asked for another operator than the default.
    pub fn use_laplacian(&self, options: &mut SpectrumOptions, what: &str) {
        if !matches!(
            self.problem.operator,
            Operator::Laplace | Operator::RelativeDirac
        ) {
            eprintln!(
                "note: {what} uses the Laplace operator; --operator {} is ignored (the DKS uses it)",
                self.problem.operator
            );
        }
        options.operator = Operator::Laplace;
        options.include_kernel = self.lists_kernel(Operator::Laplace);
    }

    /// `--include-kernel`, `--exclude-kernel`, or else the operator's default.
    fn lists_kernel(&self, operator: Operator) -> bool {
        self.include_kernel || (!self.exclude_kernel && operator.lists_kernel_by_default())
    }
}
