//! `dirac spectrum`: load the mesh, compute the spectrum with a progress display, report.

use std::io::{self, Write};
use std::process::ExitCode;
use std::time::Instant;

use dirac::io::{ReadError, read_mesh};
use dirac::spectrum::{SpectrumError, SpectrumOptions, spectrum_with_progress};
use dirac::{TriMesh, default_mesh};
use thiserror::Error;

use crate::args::{SpectrumArgs, value_name};
use crate::output::{Report, StatisticsReport, Timings, WellReport, write_human, write_json};
use crate::progress::SolveProgress;

/// Name of the built-in mesh in reports.
const DEFAULT_MESH_NAME: &str = "spot (built-in)";

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

/// Runs `dirac spectrum` with validated `options`; returns the exit code to use after
/// printing the result (0, or 3 when the eigensolver did not converge).
pub fn spectrum(args: &SpectrumArgs, options: &SpectrumOptions) -> Result<ExitCode, CommandError> {
    let start = Instant::now();
    let (mesh, name) = load(args)?;
    let load_time = start.elapsed();

    let mut report = Report {
        mesh: name,
        vertices: mesh.vertex_count(),
        faces: mesh.face_count(),
        topology: mesh.topology(),
        operator: value_name(&args.operator),
        tau: args.tau,
        k: args.k,
        backend: value_name(&args.backend),
        normalize: value_name(&args.normalize),
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
    let result = spectrum_with_progress(&mesh, options, Some(&mut |p| display.update(p)));
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

/// The mesh named on the command line, or the built-in one, with its name for the report.
fn load(args: &SpectrumArgs) -> Result<(TriMesh, String), ReadError> {
    match &args.mesh {
        Some(path) => Ok((read_mesh(path)?, path.display().to_string())),
        None => Ok((default_mesh(), DEFAULT_MESH_NAME.to_string())),
    }
}
