//! The top layer: the command line's definition ([`Cli`], [`Command`]) and [`dispatch`], which
//! runs a subcommand and gives its usage errors the subcommand's usage line.

use clap::{CommandFactory, Parser, Subcommand};

use crate::commands::batch::{self, BatchArgs};
use crate::commands::descriptor::{self, DescriptorArgs};
use crate::commands::eigenfunctions::{self, EigenfunctionsArgs};
use crate::commands::matrices::{self, MatricesArgs};
use crate::commands::plot::{self, PlotArgs, PlotCommand};
use crate::commands::render::{self, RenderArgs};
use crate::commands::repair::{self, RepairArgs};
use crate::commands::segment::{self, SegmentArgs};
use crate::commands::segment_eval::{self, SegmentEvalArgs};
use crate::commands::spectrum::{self, SpectrumArgs};
use crate::common::error::CliError;
use crate::common::solve_args::{ProblemArgs, SolveArgs};

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
  dirac spectrum bunny.obj --operator family:0.5 -k 20 --json";

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
    #[command(after_help = eigenfunctions::AFTER_HELP)]
    Eigenfunctions(EigenfunctionsArgs),
    /// The eigenproblem P x = λ Q x of an operator (the matrices `spectrum` solves) to Matrix
    /// Market files, to check a result with another solver.
    #[command(after_help = matrices::AFTER_HELP)]
    Matrices(MatricesArgs),
    /// Per-vertex descriptors (HKS, DKS, WKS, segmentation, eigenvectors) to .csv or .npy.
    #[command(after_help = descriptor::AFTER_HELP)]
    Descriptor(DescriptorArgs),
    /// Spectra of many meshes in parallel, resumable: one JSON per mesh and a summary.csv.
    #[command(after_help = batch::AFTER_HELP)]
    Batch(BatchArgs),
    /// A picture (PNG) of eigenfunction magnitudes |φ_I|, a descriptor (HKS, DKS, WKS) or the
    /// potential well on a mesh.
    Render(RenderArgs),
    /// Charts (PNG or SVG): `dirac plot spectra` draws several spectra in one chart.
    Plot(PlotArgs),
    /// Segment a mesh by consensus segmentation of the descriptor |φ_i|/√|λ_i| (paper §6.2),
    /// to a .seg, a .ply with a colour per face or a .png.
    #[command(after_help = segment::AFTER_HELP)]
    Segment(SegmentArgs),
    /// Repair a mesh (merge duplicate vertices, drop degenerate faces, split non-manifold
    /// edges and vertices, orient faces) and write it, reporting every change.
    #[command(after_help = repair::AFTER_HELP)]
    Repair(RepairArgs),
    /// Score a segmentation (.seg) against reference segmentations of the same mesh with the
    /// Princeton benchmark's measures: Cut Discrepancy, Hamming, Rand index, GCE, LCE.
    #[command(after_help = segment_eval::AFTER_HELP)]
    SegmentEval(SegmentEvalArgs),
}

impl Command {
    /// The names of the (sub)subcommand, from the top: `["plot", "spectra"]`.
    fn path(&self) -> &'static [&'static str] {
        match self {
            Command::Spectrum(_) => &["spectrum"],
            Command::Eigenfunctions(_) => &["eigenfunctions"],
            Command::Matrices(_) => &["matrices"],
            Command::Descriptor(_) => &["descriptor"],
            Command::Batch(_) => &["batch"],
            Command::Render(_) => &["render"],
            Command::Repair(_) => &["repair"],
            Command::Segment(_) => &["segment"],
            Command::SegmentEval(_) => &["segment-eval"],
            Command::Plot(PlotArgs {
                chart: PlotCommand::Spectra(_),
            }) => &["plot", "spectra"],
        }
    }

    /// The operator and eigensolver options of the command.
    fn solve_args(&self) -> Option<&SolveArgs> {
        match self {
            Command::Spectrum(args) => Some(&args.solve),
            Command::Eigenfunctions(args) => Some(&args.solve),
            Command::Descriptor(args) => Some(&args.solve),
            Command::Batch(args) => Some(&args.solve),
            Command::Render(args) => Some(&args.solve),
            Command::Segment(args) => Some(&args.solve),
            Command::Plot(PlotArgs {
                chart: PlotCommand::Spectra(args),
            }) => Some(&args.solve),
            Command::Matrices(_) | Command::Repair(_) | Command::SegmentEval(_) => None,
        }
    }

    /// The options that define the command's eigenproblem.
    fn problem_args(&self) -> Option<&ProblemArgs> {
        match self {
            Command::Matrices(args) => Some(&args.problem),
            other => other.solve_args().map(|solve| &solve.problem),
        }
    }
}

/// Runs the subcommand: applies the process-wide `--single-thread` first, and formats a usage
/// error of the command with its usage line, as clap formats its own.
pub fn dispatch(command: &Command) -> Result<(), CliError> {
    // What every solving command checks and sets before it runs.
    if let Some(solve) = command.solve_args() {
        solve.apply_thread_setting();
    }
    let prepared = command
        .problem_args()
        .map_or(Ok(()), |problem| problem.preparation.check());
    let outcome = prepared.and_then(|()| match command {
        Command::Spectrum(args) => spectrum::run(args),
        Command::Eigenfunctions(args) => eigenfunctions::run(args),
        Command::Matrices(args) => matrices::run(args),
        Command::Descriptor(args) => descriptor::run(args),
        Command::Batch(args) => batch::run(args),
        Command::Render(args) => render::run(args),
        Command::Plot(args) => plot::run(args),
        Command::Repair(args) => repair::run(args),
        Command::Segment(args) => segment::run(args),
        Command::SegmentEval(args) => segment_eval::run(args),
    });
    outcome.map_err(|error| match error {
        CliError::Usage(usage) => CliError::Usage(with_usage_line(usage, command.path())),
        other => other,
    })
}

/// `error` formatted with the usage line of the subcommand at `path`.
fn with_usage_line(error: clap::Error, path: &[&str]) -> clap::Error {
    let mut command = Cli::command();
    command.build();
    for name in path {
        let Some(sub) = command.find_subcommand(name).cloned() else {
            break;
        };
        command = sub;
    }
    error.format(&mut command)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
    }
}
