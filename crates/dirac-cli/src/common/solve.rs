//! Solving with the progress display.

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use dirac::TriMesh;
use dirac::spectrum::{
    Spectrum, SpectrumError, SpectrumOptions, Unaccepted, relative_spectrum_with_progress,
    scale_warning, spectrum_with_progress,
};
use qeig::Progress;

use crate::common::error::CliError;
use crate::common::progress::SolveProgress;

/// A spectrum computed by [`solve`].
pub struct Solved {
    /// The eigenpairs: all `k`, or those that converged.
    pub spectrum: Spectrum,
    /// Whether all `k` converged.
    pub converged: bool,
    /// The pairs found but not accepted (none when all converged).
    pub unaccepted: Unaccepted,
    /// Assembly and eigensolve together.
    pub elapsed: Duration,
}

impl Solved {
    /// `Ok`, or [`CliError::NotConverged`] (exit code 3) saying how many of the `wanted` pairs
    /// of the mesh `name` converged and what was done with them (`doing`, e.g. "writing
    /// those"). Called after the converged part is printed or written.
    pub fn check_converged(&self, name: &str, wanted: usize, doing: &str) -> Result<(), CliError> {
        self.check_converged_unless_stopped(name, wanted, doing, None)
    }

    /// [`Self::check_converged`] for a solve that may have been stopped: `stopped` says why
    /// (a time limit), and replaces the advice when given.
    pub fn check_converged_unless_stopped(
        &self,
        name: &str,
        wanted: usize,
        doing: &str,
        stopped: Option<String>,
    ) -> Result<(), CliError> {
        if self.converged {
            return Ok(());
        }
        let advice = stopped
            .or_else(|| self.unaccepted.explanation(&self.spectrum.eigenvalues))
            .unwrap_or_else(|| {
                "try a larger --tolerance, more --max-restarts or another --seed".to_string()
            });
        Err(CliError::NotConverged {
            mesh: name.to_string(),
            converged: self.spectrum.eigenvalues.len(),
            wanted,
            doing: doing.to_string(),
            advice,
        })
    }
}

/// The spectrum of `mesh` (called `name` in messages), relative to the `reference` surface when
/// given (`--relative-to`), with the progress display on stderr (hidden with `quiet`). A solve that stops early is not an error here: it returns what
/// converged with `converged: false`, and the caller reports it ([`Solved::check_converged`]).
pub fn solve(
    mesh: &TriMesh,
    reference: Option<&TriMesh>,
    name: &str,
    options: &SpectrumOptions,
    quiet: bool,
) -> Result<Solved, CliError> {
    solve_until(mesh, reference, name, options, quiet, || false)
}

/// [`solve`], stopped within about 0.1 s once `stop()` is true (it is asked whenever the
/// eigensolver reports progress); it then returns what converged by then, with
/// `converged: false`. Unless `quiet`, first warns on stderr of options whose meaning depends
/// on the mesh's scale ([`scale_warning`]).
pub fn solve_until(
    mesh: &TriMesh,
    reference: Option<&TriMesh>,
    name: &str,
    options: &SpectrumOptions,
    quiet: bool,
    stop: impl Fn() -> bool,
) -> Result<Solved, CliError> {
    if let Some(warning) = scale_warning(mesh, options).filter(|_| !quiet) {
        eprintln!("warning: {name}: {warning}");
    }
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
    let result = match reference {
        Some(reference) => {
            relative_spectrum_with_progress(mesh, reference, options, Some(&mut show))
        }
        None => spectrum_with_progress(mesh, options, Some(&mut show)),
    };
    drop(display);
    let elapsed = start.elapsed();
    match result {
        Ok(spectrum) => Ok(Solved {
            spectrum,
            converged: true,
            unaccepted: Unaccepted::default(),
            elapsed,
        }),
        Err(SpectrumError::NotConverged {
            partial,
            unaccepted,
            ..
        }) => Ok(Solved {
            spectrum: *partial,
            converged: false,
            unaccepted,
            elapsed,
        }),
        Err(source) => Err(CliError::Spectrum {
            mesh: name.to_string(),
            source,
        }),
    }
}

/// The spectrum of `mesh` (called `name` in messages) with the progress display; a solve that
/// stops early is an error here (nothing is drawn), since a picture of some other mode would
/// mislead.
pub fn solve_converged(
    mesh: &TriMesh,
    reference: Option<&TriMesh>,
    name: &str,
    options: &SpectrumOptions,
    quiet: bool,
) -> Result<Spectrum, CliError> {
    let solved = solve(mesh, reference, name, options, quiet)?;
    solved.check_converged(name, options.k, "nothing drawn")?;
    Ok(solved.spectrum)
}
