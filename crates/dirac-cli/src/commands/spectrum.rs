//! `dirac spectrum`: load the mesh, compute the spectrum with a progress display, report.

use std::io::{self, Write};
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::common::error::CliError;
use crate::common::preparation::PreparedMesh;
use crate::common::reference::ReferenceArgs;
use crate::common::report::{Report, RunSettings, write_human, write_json};
use crate::common::solve::solve;
use crate::common::solve_args::SolveArgs;

/// Arguments of `dirac spectrum`.
#[derive(Debug, Args)]
pub struct SpectrumArgs {
    /// Mesh file (.obj, .off, .ply or .stl); without it, the built-in `spot` mesh.
    pub mesh: Option<PathBuf>,

    /// Operator and eigensolver.
    #[command(flatten)]
    pub solve: SolveArgs,

    /// The second surface of D_{f1,f2}.
    #[command(flatten)]
    pub reference: ReferenceArgs,

    /// Print exactly one JSON object on stdout instead of tables.
    #[arg(long)]
    pub json: bool,

    /// No progress display on stderr.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `dirac spectrum`: prints the report, then fails with [`CliError::NotConverged`] (exit
/// code 3) when the eigensolver did not converge (the report holds what did).
pub fn run(args: &SpectrumArgs) -> Result<(), CliError> {
    let options = args.solve.options();
    let start = Instant::now();
    let (prepared, reference) = args.reference.load_with_mesh(
        &args.solve.problem.preparation,
        args.mesh.as_deref(),
        options.operator,
        args.quiet,
    )?;
    let PreparedMesh {
        mesh,
        name,
        topology,
        report: preparation,
    } = prepared;
    let load_time = start.elapsed();

    let mut settings = RunSettings::new(&args.solve, &options);
    settings.relative_to = (args.reference.relative_to.as_ref()).map(|p| p.display().to_string());
    let mut report = Report::new(name, &mesh, topology, settings, load_time);
    report.preparation = Some(preparation);

    let solved = solve(
        &mesh,
        reference.as_ref(),
        &report.mesh,
        &options,
        args.quiet,
    )?;
    report.set_spectrum(&solved.spectrum, solved.elapsed);
    report.converged = solved.converged;

    // Standard output flushes at every newline; the report is written in one go.
    let mut out = io::BufWriter::new(io::stdout().lock());
    if args.json {
        write_json(&report, &mut out)
    } else {
        write_human(&report, &mut out)
    }
    .and_then(|()| out.flush())
    .map_err(CliError::Stdout)?;
    solved.check_converged(&report.mesh, options.k, "printing those")
}
