//! One module per subcommand; each defines its arguments and a `run` function returning the
//! process exit code. Shared here: loading the mesh named on the command line, solving with
//! the progress display, reporting a solve that stopped early, and writing `.npy` files.

pub mod batch;
pub mod descriptor;
pub mod eigenfunctions;
pub mod plot;
pub mod render;
pub mod spectrum;

use std::ffi::OsStr;
use std::io::{self, Write};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use dirac::descriptors::DescriptorError;
use dirac::io::{ReadError, read_mesh};
use dirac::spectrum::{Spectrum, SpectrumError, SpectrumOptions, spectrum_with_progress};
use dirac::{TriMesh, default_mesh};
use ndarray::{Array, Dimension};
use ndarray_npy::{WriteNpyError, write_npy};
use qeig::Progress;
use thiserror::Error;

use crate::progress::SolveProgress;

/// Name of the built-in mesh in reports.
pub const DEFAULT_MESH_NAME: &str = "spot (built-in)";

/// Exit code of a solve that did not converge (what converged is still reported or written).
pub const NOT_CONVERGED: u8 = 3;

/// Why the spectrum of a mesh, or a descriptor from it, could not be computed (exit code 1).
#[derive(Debug, Error)]
pub enum ComputeError {
    /// The mesh file cannot be read or is not a valid mesh (the message names the file).
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The spectrum cannot be computed on this mesh.
    #[error("{mesh}: {source}")]
    Spectrum {
        /// The mesh, as in reports.
        mesh: String,
        /// What failed.
        source: SpectrumError,
    },
    /// A descriptor cannot be computed from the spectrum.
    #[error("{mesh}: {source}")]
    Descriptor {
        /// The mesh, as in reports.
        mesh: String,
        /// What failed.
        source: DescriptorError,
    },
}

/// The mesh at `path`, or the built-in one without a path, with its name for reports.
pub fn load_mesh(path: Option<&Path>) -> Result<(TriMesh, String), ComputeError> {
    match path {
        Some(path) => Ok((read_mesh(path)?, path.display().to_string())),
        None => Ok((default_mesh(), DEFAULT_MESH_NAME.to_string())),
    }
}

/// What follows the message of a mesh that cannot be read: for an invalid mesh (not for an
/// unreadable file), that `--repair` exists.
pub fn mesh_error_hint(error: &ReadError) -> &'static str {
    match error {
        ReadError::Mesh { .. } => "; --repair fixes such defects (see `dirac repair --help`)",
        _ => "",
    }
}

/// A spectrum computed by [`solve`].
pub struct Solved {
    /// The eigenpairs: all `k`, or those that converged.
    pub spectrum: Spectrum,
    /// Whether all `k` converged.
    pub converged: bool,
    /// Assembly and eigensolve together.
    pub elapsed: Duration,
}

impl Solved {
    /// The exit code of a command that reports or writes what converged: 0, or
    /// [`NOT_CONVERGED`] after saying on stderr how many of the `wanted` pairs of the mesh
    /// `name` converged and what is done with them (`doing`, e.g. "writing those").
    pub fn exit_code(&self, name: &str, wanted: usize, doing: &str) -> ExitCode {
        if self.converged {
            return ExitCode::SUCCESS;
        }
        eprintln!(
            "error: {name}: the eigensolver converged only {} of {wanted} eigenpairs; \
             {doing} (try a larger --tolerance, more --max-restarts or another --seed)",
            self.spectrum.eigenvalues.len()
        );
        ExitCode::from(NOT_CONVERGED)
    }
}

/// The spectrum of `mesh` (called `name` in messages) with the progress display on stderr
/// (hidden with `quiet`). A solve that stops early is not an error here: it returns what
/// converged with `converged: false`, and the caller reports it (exit code 3).
pub fn solve(
    mesh: &TriMesh,
    name: &str,
    options: &SpectrumOptions,
    quiet: bool,
) -> Result<Solved, ComputeError> {
    solve_until(mesh, name, options, quiet, || false)
}

/// [`solve`], stopped within one restart of the eigensolver once `stop()` is true (then it
/// returns what converged by then, with `converged: false`).
pub fn solve_until(
    mesh: &TriMesh,
    name: &str,
    options: &SpectrumOptions,
    quiet: bool,
    stop: impl Fn() -> bool,
) -> Result<Solved, ComputeError> {
    let start = Instant::now();
    let display = SolveProgress::start(quiet);
    let mut show = |p: &Progress| {
        display.update(p);
        if stop() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    let result = spectrum_with_progress(mesh, options, Some(&mut show));
    drop(display);
    let elapsed = start.elapsed();
    match result {
        Ok(spectrum) => Ok(Solved {
            spectrum,
            converged: true,
            elapsed,
        }),
        Err(SpectrumError::NotConverged { partial, .. }) => Ok(Solved {
            spectrum: *partial,
            converged: false,
            elapsed,
        }),
        Err(source) => Err(ComputeError::Spectrum {
            mesh: name.to_string(),
            source,
        }),
    }
}

/// An `.npy` file that cannot be written.
#[derive(Debug, Error)]
#[error("{}: {source}", path.display())]
pub struct NpyError {
    /// The file.
    pub path: PathBuf,
    /// What failed.
    pub source: WriteNpyError,
}

/// Writes `array` as `.npy` (`float64`) to `path`.
pub fn write_array<D: Dimension>(path: &Path, array: &Array<f64, D>) -> Result<(), NpyError> {
    write_npy(path, array).map_err(|source| NpyError {
        path: path.to_path_buf(),
        source,
    })
}

/// Prints an informational line (what was written where) on stdout. The files are written by
/// then, so a reader that has gone away (`dirac render … | head -0`) is not an error.
pub fn tell(line: std::fmt::Arguments) {
    let _ = writeln!(io::stdout().lock(), "{line}");
}

/// Whether `path` has the extension `ext` (case-insensitive).
pub fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension()
        .and_then(OsStr::to_str)
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}
