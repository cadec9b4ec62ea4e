//! `dirac plot`: charts. `dirac plot spectra` draws the spectra of several meshes and/or
//! several operators in one chart, one line per (mesh, operator) pair.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::builder::PossibleValue;
use clap::{Args, Subcommand, ValueEnum};
use dirac_cli::plot::{Series, plot_spectra};

use crate::args::{OperatorArg, SolveArgs, unit_interval, value_name};
use crate::commands::render::{
    CommandError, exit_code, picture_exit_codes, picture_path, solve_converged,
};
use crate::commands::{load_mesh, tell};

const SPECTRA_HELP: &str = concat!(
    picture_exit_codes!(),
    "
Several meshes give one line each; `--operators` gives one line per operator (on every mesh).

Examples:
  dirac plot spectra torus-bumps.obj torus-noise.obj -k 30 --out tori.svg
  dirac plot spectra --operators laplace,relative-dirac,family:0.5 -k 20 --out spot.png"
);

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
    #[command(after_help = SPECTRA_HELP)]
    Spectra(SpectraArgs),
}

/// Arguments of `dirac plot spectra`.
#[derive(Debug, Args)]
pub struct SpectraArgs {
    /// Mesh files (.obj, .off or .ply); without any, the built-in `spot` mesh.
    pub meshes: Vec<PathBuf>,

    /// Operator and eigensolver (for all meshes).
    #[command(flatten)]
    pub solve: SolveArgs,

    /// Several operators, comma-separated, each drawn on every mesh, e.g.
    /// `laplace,relative-dirac,family:0.5` (the family operators take `:TAU`); replaces
    /// --operator and --tau.
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = parse_operator,
          conflicts_with_all = ["operator", "tau"])]
    pub operators: Vec<OperatorChoice>,

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

/// One entry of `--operators`: an operator and, for the family, its τ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OperatorChoice {
    /// The operator.
    pub operator: OperatorArg,
    /// τ for the family operators.
    pub tau: Option<f64>,
}

impl OperatorChoice {
    /// `relative-dirac`, `family τ=0.5`.
    fn label(&self) -> String {
        match self.tau {
            Some(tau) => format!("{} τ={tau}", value_name(&self.operator)),
            None => value_name(&self.operator),
        }
    }
}

/// Value parser of `--operators` entries: `NAME` or `NAME:TAU`.
fn parse_operator(text: &str) -> Result<OperatorChoice, String> {
    let (name, tau) = match text.split_once(':') {
        Some((name, tau)) => (name, Some(unit_interval(tau)?)),
        None => (text, None),
    };
    let operator = OperatorArg::from_str(name.trim(), true).map_err(|_| {
        let names: Vec<String> = OperatorArg::value_variants()
            .iter()
            .filter_map(|v| {
                v.to_possible_value()
                    .as_ref()
                    .map(PossibleValue::get_name)
                    .map(str::to_string)
            })
            .collect();
        format!("`{name}` is not an operator (one of {})", names.join(", "))
    })?;
    Ok(OperatorChoice { operator, tau })
}

/// Runs `dirac plot`.
pub fn run(args: &PlotArgs) -> Result<ExitCode, CommandError> {
    match &args.chart {
        PlotCommand::Spectra(spectra) => exit_code(plot(spectra)),
    }
}

fn plot(args: &SpectraArgs) -> Result<(), CommandError> {
    let choices = if args.operators.is_empty() {
        vec![OperatorChoice {
            operator: args.solve.operator,
            tau: args.solve.tau,
        }]
    } else {
        args.operators.clone()
    };
    // Every operator's options first, so a usage error comes before any solve.
    let options: Vec<_> = choices
        .iter()
        .map(|choice| {
            let solve = SolveArgs {
                operator: choice.operator,
                tau: choice.tau,
                ..args.solve.clone()
            };
            solve.options("plot").unwrap_or_else(|error| error.exit())
        })
        .collect();
    let paths: Vec<Option<&std::path::Path>> = if args.meshes.is_empty() {
        vec![None]
    } else {
        args.meshes.iter().map(|p| Some(p.as_path())).collect()
    };

    let mut series = Vec::new();
    let mut mesh_names = Vec::new();
    for path in paths {
        let (mesh, name) = load_mesh(path)?;
        // Legends and titles name a file by its name alone; directories make them too long.
        let name = path
            .and_then(|p| p.file_name())
            .map_or(name, |file| file.to_string_lossy().into_owned());
        for (choice, options) in choices.iter().zip(&options) {
            let spectrum = solve_converged(&mesh, &name, options, args.quiet)?;
            // Label by what varies: the mesh, the operator, or both.
            let label = match (args.meshes.len() > 1, choices.len() > 1) {
                (true, true) => format!("{name}, {}", choice.label()),
                (true, false) => name.clone(),
                (false, _) => choice.label(),
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
            title += &format!(" of {}", choice.label());
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn operator_lists_parse() {
        assert_eq!(
            parse_operator("family:0.5"),
            Ok(OperatorChoice {
                operator: OperatorArg::Family,
                tau: Some(0.5)
            })
        );
        assert_eq!(
            parse_operator("Laplace").map(|c| c.operator),
            Ok(OperatorArg::Laplace)
        );
        assert!(
            parse_operator("dirac")
                .expect_err("unknown")
                .contains("relative-dirac")
        );
        assert!(
            parse_operator("family:2")
                .expect_err("tau")
                .contains("outside")
        );
    }
}
