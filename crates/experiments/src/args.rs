//! The command line shared by the examples:
//! `[--full] [--backend native|real-block|complex-adjoint] [--out DIR]`.

use std::path::PathBuf;

use dirac::spectrum::SolverBackend;

use crate::ExperimentError;

/// Parsed example options.
#[derive(Debug, Clone, PartialEq)]
pub struct ExampleArgs {
    /// Run at the paper's sizes instead of the quick defaults.
    pub full: bool,
    /// Eigensolver backend for every spectrum.
    pub backend: SolverBackend,
    /// Directory the plots are written to: `--out`, default `target/experiments/<name>` in
    /// the workspace.
    pub out: PathBuf,
}

/// The usage line of example `name`.
pub fn usage(name: &str) -> String {
    format!(
        "usage: cargo run --release -p experiments --example {name} -- \
         [--full] [--backend native|real-block|complex-adjoint] [--out DIR]"
    )
}

impl ExampleArgs {
    /// Parses the arguments after the program name; unknown flags and values are
    /// [`ExperimentError::Usage`] errors carrying the usage line.
    pub fn parse(
        name: &str,
        args: impl IntoIterator<Item = String>,
    ) -> Result<Self, ExperimentError> {
        let mut parsed = Self {
            full: false,
            backend: SolverBackend::Native,
            out: PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("../../target/experiments")
                .join(name),
        };
        let fail = |message: String| ExperimentError::Usage(format!("{message}\n{}", usage(name)));
        let mut args = args.into_iter();
        while let Some(arg) = args.next() {
            match arg.as_str() {
                "--full" => parsed.full = true,
                "--backend" => {
                    parsed.backend = match args.next().as_deref() {
                        Some("native") => SolverBackend::Native,
                        Some("real-block") => SolverBackend::RealBlock,
                        Some("complex-adjoint") => SolverBackend::ComplexAdjoint,
                        other => return Err(fail(format!("invalid --backend value {other:?}"))),
                    }
                }
                "--out" => match args.next() {
                    Some(dir) => parsed.out = PathBuf::from(dir),
                    None => return Err(fail("--out needs a directory".into())),
                },
                "-h" | "--help" => return Err(ExperimentError::Usage(usage(name))),
                other => return Err(fail(format!("unexpected argument {other:?}"))),
            }
        }
        Ok(parsed)
    }
}

/// The `main` of every example: parses the arguments for the example `name`, runs `run`, prints
/// an error to stderr and turns the outcome into the exit code (1 on any error).
pub fn run_example(
    name: &str,
    run: impl FnOnce(&ExampleArgs) -> Result<(), ExperimentError>,
) -> std::process::ExitCode {
    match ExampleArgs::parse(name, std::env::args().skip(1)).and_then(|args| run(&args)) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("{error}");
            std::process::ExitCode::FAILURE
        }
    }
}
