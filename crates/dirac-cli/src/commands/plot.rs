//! `dirac plot`: charts. `dirac plot spectra` draws the spectra of several meshes and/or
//! several operators in one chart, one line per (mesh, operator) pair.

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use dirac::spectrum::Operator;
use dirac_cli::plot::{Series, plot_spectra};

use crate::common::error::{CliError, PICTURE_EXIT_CODES};
use crate::common::files::tell;
use crate::common::parsers::picture_path;
use crate::common::preparation::PreparedMesh;
use crate::common::solve::solve_converged;
use crate::common::solve_args::SolveArgs;

/// What `dirac plot spectra --help` shows after the exit codes.
const SPECTRA_HELP: &str = "
Several meshes give one line each; `--operators` gives one line per operator (on every mesh).

Examples:
  dirac plot spectra torus-bumps.obj torus-noise.obj -k 30 --out tori.svg
  dirac plot spectra --operators laplace,relative-dirac,family:0.5 -k 20 --out spot.png";

/// Arguments of `dirac plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// The kind of chart.
    #[command(subcommand)]
    pub chart: PlotCommand,
}

/// The charts `dirac plot` draws.
#[derive(Debug, Subcommand)]
pub enum PlotCommand {
    /// Eigenvalue index against eigenvalue for several meshes and/or operators in one chart.
    #[command(after_help = format!("{PICTURE_EXIT_CODES}{SPECTRA_HELP}"))]
    Spectra(SpectraArgs),
}

/// Arguments of `dirac plot spectra`.
#[derive(Debug, Args)]
pub struct SpectraArgs {
    /// Mesh files (.obj, .off, .ply or .stl); without any, the built-in `spot` mesh.
    pub meshes: Vec<PathBuf>,

    /// Operator and eigensolver (for all meshes).
    #[command(flatten)]
    pub solve: SolveArgs,

    /// Several operators, comma-separated, each drawn on every mesh, e.g.
    /// `laplace,relative-dirac,family:0.5` (written as for --operator, which this replaces).
    #[arg(
        long,
        value_name = "LIST",
        value_delimiter = ',',
        conflicts_with = "operator"
    )]
    pub operators: Vec<Operator>,

    /// The picture to write: .png or .svg.
    #[arg(short, long, value_name = "FILE", value_parser = picture_path(&["png", "svg"]))]
    pub out: PathBuf,

    /// Title of the chart (default: the operator and the mesh when there is only one).
    #[arg(long)]
    pub title: Option<String>,

    /// No progress display on stderr and no confirmation on stdout.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `dirac plot`.
pub fn run(args: &PlotArgs) -> Result<(), CliError> {
    match &args.chart {
        PlotCommand::Spectra(spectra) => plot(spectra),
    }
}

fn plot(args: &SpectraArgs) -> Result<(), CliError> {
    let choices = if args.operators.is_empty() {
        vec![args.solve.problem.operator]
    } else {
        args.operators.clone()
    };
    let options: Vec<_> = choices
        .iter()
        .map(|&operator| args.solve.options_with(operator))
        .collect();
    let paths: Vec<Option<&Path>> = if args.meshes.is_empty() {
        vec![None]
    } else {
        args.meshes.iter().map(|p| Some(p.as_path())).collect()
    };

    let mut series = Vec::new();
    let mut mesh_names = Vec::new();
    for path in paths {
        let PreparedMesh { mesh, name, .. } =
            args.solve.problem.preparation.load(path, args.quiet)?;
        // Legends and titles name a file by its name alone; directories make them too long.
        let name = path
            .and_then(|p| p.file_name())
            .map_or(name, |file| file.to_string_lossy().into_owned());
        for (choice, options) in choices.iter().zip(&options) {
            let spectrum = solve_converged(&mesh, None, &name, options, args.quiet)?;
            // Label by what varies: the mesh, the operator, or both.
            let label = match (args.meshes.len() > 1, choices.len() > 1) {
                (true, true) => format!("{name}, {choice}"),
                (true, false) => name.clone(),
                (false, _) => choice.to_string(),
            };
            series.push(Series {
                label,
                values: spectrum.eigenvalues,
            });
        }
        mesh_names.push(name);
    }

    let title = args.title.clone().unwrap_or_else(|| {
        let mut title = "eigenvalues of smallest |λ|".to_string();
        if let [choice] = choices.as_slice() {
            title += &format!(" of {choice}");
        }
        if let [name] = mesh_names.as_slice() {
            title += &format!(" on {name}");
        }
        title
    });
    plot_spectra(&series, &title, &args.out)?;
    if !args.quiet {
        tell(format_args!(
            "wrote {}: {} spectra",
            args.out.display(),
            series.len()
        ));
    }
    Ok(())
}
