//! Command-line arguments (clap derive) and their translation into library options.

use clap::error::ErrorKind;
use clap::{Args, CommandFactory, Parser, Subcommand, ValueEnum};
use dirac::spectrum::{Normalization, Operator, SolverBackend, SpectrumOptions};
use dirac::well::PotentialWell;

use crate::commands::batch::BatchArgs;
use crate::commands::descriptor::DescriptorArgs;
use crate::commands::eigenfunctions::EigenfunctionsArgs;
use crate::commands::plot::PlotArgs;
use crate::commands::render::RenderArgs;
use crate::commands::spectrum::SpectrumArgs;

const AFTER_HELP: &str = "\
Exit codes:
  0  success
  1  the mesh cannot be read or is invalid (the message names the file and the problem),
     or the spectrum cannot be computed
  2  usage error (bad or missing arguments)
  3  the eigensolver did not converge; what did converge is printed
     (with --json as the usual object with \"converged\": false)

Examples:
  dirac spectrum -k 10                       # built-in `spot` mesh, relative Dirac
  dirac spectrum bunny.obj --operator family --tau 0.5 -k 20 --json";

/// Spectra of the operators of \"A Dirac Operator for Extrinsic Shape Analysis\" (Liu,
/// Jacobson, Crane 2017) on triangle meshes.
#[derive(Debug, Parser)]
#[command(name = "dirac", version, about, after_help = AFTER_HELP)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// The k eigenvalues of smallest |λ| of an operator on a mesh.
    #[command(after_help = AFTER_HELP)]
    Spectrum(SpectrumArgs),
    /// Eigenvalues and eigenvectors to .npy files, or |φ_I| on the mesh to a .ply.
    #[command(after_help = crate::commands::eigenfunctions::AFTER_HELP)]
    Eigenfunctions(EigenfunctionsArgs),
    /// Per-vertex descriptors (HKS, DKS, WKS, segmentation, eigenvectors) to .csv or .npy.
    #[command(after_help = crate::commands::descriptor::AFTER_HELP)]
    Descriptor(DescriptorArgs),
    /// Spectra of many meshes in parallel, resumable: one JSON per mesh and a summary.csv.
    #[command(after_help = crate::commands::batch::AFTER_HELP)]
    Batch(BatchArgs),
    /// A picture (PNG) of eigenfunction magnitudes |φ_I|, a descriptor (HKS, DKS, WKS) or the
    /// potential well on a mesh.
    Render(RenderArgs),
    /// Charts (PNG or SVG): `dirac plot spectra` draws several spectra in one chart.
    Plot(PlotArgs),
}

/// The operator and eigensolver options shared by every command that computes a spectrum
/// (flattened into each command's arguments).
#[derive(Debug, Clone, Args)]
pub struct SolveArgs {
    /// The operator.
    #[arg(long, value_enum, default_value_t = OperatorArg::RelativeDirac)]
    pub operator: OperatorArg,

    /// Weight τ ∈ [0, 1] of D_N in the family L(τ); required for `family` and
    /// `family-literal`, rejected for the other operators.
    #[arg(long, value_name = "T", value_parser = unit_interval)]
    pub tau: Option<f64>,

    /// Number of eigenvalues (those of smallest |λ|).
    #[arg(short, default_value_t = 10, value_parser = positive_count)]
    pub k: usize,

    /// Representation the eigensolver works in.
    #[arg(long, value_enum, default_value_t = BackendArg::Native)]
    pub backend: BackendArg,

    /// Scale normalisation applied to the mesh first.
    #[arg(long, value_enum, default_value_t = NormalizeArg::None)]
    pub normalize: NormalizeArg,

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
    /// basis) among the k of smallest |λ|. Default: listed for laplace, modified-dirichlet and
    /// the family with τ < 1 (whose kernel is the constants), not for relative-dirac,
    /// extrinsic-dirac and squared (whose kernel holds every flat vertex). The kernel's
    /// dimension is always reported.
    #[arg(long, conflicts_with = "exclude_kernel")]
    pub include_kernel: bool,

    /// Never list the kernel's eigenvalue 0 (see --include-kernel).
    #[arg(long)]
    pub exclude_kernel: bool,

    /// Faces whose Gauss map is flat within T are treated as exactly flat (D_N vanishes on
    /// them): along each edge |N_a − N_b| ≤ T |f_a − f_b| / √area. Exactly flat regions of
    /// real meshes give 1e-13 or less, curved ones 1e-4 or more.
    #[arg(long, value_name = "T", default_value_t = dirac::spectrum::DEFAULT_FLAT_TOLERANCE,
          value_parser = nonnegative_real)]
    pub flat_tolerance: f64,

    /// Keep the eigensolver on one thread. By default the triangular solves and Gram–Schmidt
    /// passes of large problems use a second core (not inside `batch`, whose jobs already do).
    #[arg(long)]
    pub single_thread: bool,

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

/// `--operator` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OperatorArg {
    /// Cotangent Laplacian Δ.
    Laplace,
    /// Relative Dirac operator D_N.
    RelativeDirac,
    /// Extrinsic Dirac operator D_f.
    ExtrinsicDirac,
    /// The family L(τ), blended pencil (needs --tau).
    Family,
    /// The family L(τ), literal Galerkin operator (needs --tau).
    FamilyLiteral,
    /// Squared relative Dirac operator D_N* D_N.
    Squared,
    /// Modified Dirichlet energy Hessian Δ + (κ₁² + κ₂²).
    ModifiedDirichlet,
}

/// `--backend` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BackendArg {
    /// Quaternion matrices and the native Cholesky.
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

/// The command-line name of a value (`relative-dirac`, `unit-area`, …).
pub fn value_name(value: &impl ValueEnum) -> String {
    value
        .to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_default()
}

impl SolveArgs {
    /// Checks what clap cannot express (`--tau` only with the family) and builds the options;
    /// `subcommand` names the command in the error message. Errors are clap usage errors
    /// (exit code 2). Also applies `--single-thread`, a process-wide setting
    /// ([`qeig::threads::set_second_thread_allowed`]).
    pub fn options(&self, subcommand: &str) -> Result<SpectrumOptions, clap::Error> {
        if self.single_thread {
            qeig::threads::set_second_thread_allowed(false);
        }
        let operator = match (self.operator, self.tau) {
            (OperatorArg::Family, Some(tau)) => Operator::Family { tau },
            (OperatorArg::FamilyLiteral, Some(tau)) => Operator::FamilyLiteral { tau },
            (OperatorArg::Family | OperatorArg::FamilyLiteral, None) => {
                return Err(usage_error(
                    subcommand,
                    ErrorKind::MissingRequiredArgument,
                    format!(
                        "--operator {} needs --tau <T> (the weight of D_N, in [0, 1])",
                        value_name(&self.operator)
                    ),
                ));
            }
            (_, Some(_)) => {
                return Err(usage_error(
                    subcommand,
                    ErrorKind::ArgumentConflict,
                    format!(
                        "--tau applies only to --operator family or family-literal, not {}",
                        value_name(&self.operator)
                    ),
                ));
            }
            (OperatorArg::Laplace, None) => Operator::Laplace,
            (OperatorArg::RelativeDirac, None) => Operator::RelativeDirac,
            (OperatorArg::ExtrinsicDirac, None) => Operator::ExtrinsicDirac,
            (OperatorArg::Squared, None) => Operator::Squared,
            (OperatorArg::ModifiedDirichlet, None) => Operator::ModifiedDirichlet,
        };
        let mut options = SpectrumOptions::new(operator, self.k);
        options.backend = match self.backend {
            BackendArg::Native => SolverBackend::Native,
            BackendArg::RealBlock => SolverBackend::RealBlock,
            BackendArg::ComplexAdjoint => SolverBackend::ComplexAdjoint,
        };
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
        options.tolerance = self.tolerance;
        options.seed = self.seed;
        options.max_restarts = self.max_restarts;
        options.flat_tolerance = self.flat_tolerance;
        options.include_kernel = self.lists_kernel(operator);
        Ok(options)
    }

    /// Switches `options` to the Laplacian for the heat kernel signature (`what` names it in
    /// the note), which is defined for the Laplacian only; a note on stderr says so when
    /// `--operator` asked for another operator than the default.
    pub fn use_laplacian(&self, options: &mut SpectrumOptions, what: &str) {
        if !matches!(
            self.operator,
            OperatorArg::Laplace | OperatorArg::RelativeDirac
        ) {
            eprintln!(
                "note: {what} uses the Laplace operator; --operator {} is ignored (the DKS uses it)",
                value_name(&self.operator)
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

/// A usage error of `dirac <subcommand>` in the style of clap's own (exit code 2).
pub fn usage_error(subcommand: &str, kind: ErrorKind, message: String) -> clap::Error {
    let mut command = Cli::command();
    command.build();
    match command.find_subcommand_mut(subcommand) {
        Some(found) => found.error(kind, message),
        None => command.error(kind, message),
    }
}

/// Value parser (clap `value_parser`).
pub fn finite(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("`{text}` is not a finite number")),
    }
}

/// Value parser (clap `value_parser`).
pub fn unit_interval(text: &str) -> Result<f64, String> {
    let x = finite(text)?;
    if (0.0..=1.0).contains(&x) {
        Ok(x)
    } else {
        Err(format!("{x} is outside [0, 1]"))
    }
}

/// Value parser (clap `value_parser`).
pub fn positive_real(text: &str) -> Result<f64, String> {
    let x = finite(text)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("{x} is not positive"))
    }
}

/// Value parser (clap `value_parser`).
pub fn nonnegative_real(text: &str) -> Result<f64, String> {
    let x = finite(text)?;
    if x >= 0.0 {
        Ok(x)
    } else {
        Err(format!("{x} is negative"))
    }
}

/// Value parser (clap `value_parser`).
pub fn positive_count(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(k) if k > 0 => Ok(k),
        _ => Err(format!("`{text}` is not a positive integer")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
    }
}
