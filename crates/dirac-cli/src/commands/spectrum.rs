//! `dirac spectrum`: load the mesh, compute the spectrum with a progress display, report.

use std::io::{self, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use thiserror::Error;

use crate::args::SolveArgs;
use crate::commands::{ComputeError, load_mesh, solve};
use crate::output::{Report, RunSettings, write_human, write_json};

/// Arguments of `dirac spectrum`.
#[derive(Debug, Args)]
pub struct SpectrumArgs {
    /// Mesh file (.obj, .off or .ply); without it, the built-in `spot` mesh.
    pub mesh: Option<PathBuf>,

    /// Operator and eigensolver.
    #[command(flatten)]
    pub solve: SolveArgs,

    /// Print exactly one JSON object on stdout instead of tables.
    #[arg(long)]
    pub json: bool,

    /// No progress display on stderr.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Why `dirac spectrum` failed (exit code 1).
#[derive(Debug, Error)]
pub enum CommandError {
    /// The mesh cannot be read or its spectrum cannot be computed.
    #[error(transparent)]
    Compute(#[from] ComputeError),
    /// Writing the result failed.
    #[error("cannot write the result: {0}")]
    Output(#[from] io::Error),
}

/// Runs `dirac spectrum`; returns the exit code to use after printing the result (0, 2 for a
/// usage error clap cannot detect, or 3 when the eigensolver did not converge).
pub fn run(args: &SpectrumArgs) -> Result<ExitCode, CommandError> {
    let options = args
        .solve
        .options("spectrum")
        .unwrap_or_else(|error| error.exit());
    let start = Instant::now();
    let (mesh, name) = load_mesh(args.mesh.as_deref())?;
    let load_time = start.elapsed();

    let mut report = Report::new(
        name,
        &mesh,
        RunSettings::new(&args.solve, &options),
        load_time,
    );

    let solved = solve(&mesh, &report.mesh, &options, args.quiet)?;
    report.set_spectrum(&solved.spectrum, solved.elapsed);
    report.converged = solved.converged;
    let code = solved.exit_code(&report.mesh, options.k, "printing those");

    let mut out = io::stdout().lock();
    if args.json {
        write_json(&report, &mut out)?;
    } else {
        write_human(&report, &mut out)?;
    }
    out.flush()?;
    Ok(code)
}
