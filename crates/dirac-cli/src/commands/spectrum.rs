//! `dirac spectrum`: load the mesh, compute the spectrum with a progress display, report.

use std::io::{self, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use dirac::io::ReadError;
use dirac::spectrum::{SpectrumError, spectrum_with_progress};
use thiserror::Error;

use crate::args::{SolveArgs, value_name};
use crate::commands::load_mesh;
use crate::output::{Report, StatisticsReport, Timings, WellReport, write_human, write_json};
use crate::progress::SolveProgress;

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

/// Exit code of a solve that did not converge (the converged part is still printed).
const NOT_CONVERGED: u8 = 3;

/// Why `dirac spectrum` failed (exit code 1).
#[derive(Debug, Error)]
pub enum CommandError {
    /// The mesh file cannot be read or is not a valid mesh (the message names the file).
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The spectrum cannot be computed on this mesh.
    #[error("{mesh}: {source}")]
    Spectrum {
        /// The mesh, as in the report.
        mesh: String,
        /// What failed.
        source: SpectrumError,
    },
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

    let mut report = Report {
        mesh: name,
        vertices: mesh.vertex_count(),
        faces: mesh.face_count(),
        topology: mesh.topology(),
        operator: value_name(&args.solve.operator),
        tau: args.solve.tau,
        k: args.solve.k,
        backend: value_name(&args.solve.backend),
        normalize: value_name(&args.solve.normalize),
        well: options.well.map(|w| WellReport {
            center: w.center,
            radius: w.radius,
            steepness: w.steepness,
            height: w.height,
        }),
        converged: true,
        eigenvalues: Vec::new(),
        residuals: Vec::new(),
        statistics: StatisticsReport::default(),
        timings: Timings {
            load: load_time.as_secs_f64(),
            ..Timings::default()
        },
    };

    let start = Instant::now();
    let display = SolveProgress::start(args.quiet);
    let result = spectrum_with_progress(&mesh, &options, Some(&mut |p| display.update(p)));
    drop(display);
    let elapsed = start.elapsed();

    let code = match result {
        Ok(spectrum) => {
            report.set_spectrum(&spectrum, elapsed);
            ExitCode::SUCCESS
        }
        Err(SpectrumError::NotConverged { wanted, partial }) => {
            report.set_spectrum(&partial, elapsed);
            report.converged = false;
            eprintln!(
                "error: {}: the eigensolver converged only {} of {wanted} eigenvalues; \
                 printing those (try a larger --tolerance or another --seed)",
                report.mesh,
                partial.eigenvalues.len()
            );
            ExitCode::from(NOT_CONVERGED)
        }
        Err(source) => {
            return Err(CommandError::Spectrum {
                mesh: report.mesh,
                source,
            });
        }
    };

    let mut out = io::stdout().lock();
    if args.json {
        write_json(&report, &mut out)?;
    } else {
        write_human(&report, &mut out)?;
    }
    out.flush()?;
    Ok(code)
}
