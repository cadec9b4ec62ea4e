//! The command line shared by the examples:
//! `[INPUT] [--full] [--backend native|real-block|complex-adjoint] [--out DIR]`, with the
//! positional `INPUT` (a file or folder of data) only for the examples that read one.

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
    /// The positional input of the examples that read data ([`ExampleArgs::parse_with_input`]);
    /// `None` for the others.
    pub input: Option<PathBuf>,
}

/// The usage line of example `name`.
pub fn usage(name: &str) -> String {
    usage_with_input(name, None)
}

/// The usage line of example `name` with its positional input `INPUT` (when it reads one).
fn usage_with_input(name: &str, input: Option<&str>) -> String {
    let input = input.map(|i| format!("{i} ")).unwrap_or_default();
    format!(
        "usage: cargo run --release -p experiments --example {name} -- \
         {input}[--full] [--backend native|real-block|complex-adjoint] [--out DIR]"
    )
}

impl ExampleArgs {
    /// Parses the arguments after the program name; unknown flags and values and any
    /// positional argument are [`ExperimentError::Usage`] errors carrying the usage line.
    pub fn parse(
        name: &str,
        args: impl IntoIterator<Item = String>,
    ) -> Result<Self, ExperimentError> {
        Self::parse_inner(name, None, args)
    }

    /// [`ExampleArgs::parse`] for an example that reads data: exactly one positional argument,
    /// shown as `input` (e.g. `PSB_DIR`) in the usage line, is required and becomes
    /// [`ExampleArgs::input`].
    pub fn parse_with_input(
        name: &str,
        input: &str,
        args: impl IntoIterator<Item = String>,
    ) -> Result<Self, ExperimentError> {
        let parsed = Self::parse_inner(name, Some(input), args)?;
        if parsed.input.is_none() {
            return Err(ExperimentError::Usage(format!(
                "missing {input}\n{}",
                usage_with_input(name, Some(input))
            )));
        }
        Ok(parsed)
    }

    /// The parser of both: `input` names the one positional argument allowed, if any.
    fn parse_inner(
        name: &str,
        input: Option<&str>,
        args: impl IntoIterator<Item = String>,
    ) -> Result<Self, ExperimentError> {
        let mut parsed = Self {
            full: false,
            backend: SolverBackend::Native,
            out: PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("../../target/experiments")
                .join(name),
            input: None,
        };
        let fail = |message: String| {
            ExperimentError::Usage(format!("{message}\n{}", usage_with_input(name, input)))
        };
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
                "-h" | "--help" => {
                    return Err(ExperimentError::Usage(usage_with_input(name, input)));
                }
                positional
                    if input.is_some()
                        && parsed.input.is_none()
                        && !positional.starts_with('-') =>
                {
                    parsed.input = Some(PathBuf::from(positional));
                }
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
    finish(ExampleArgs::parse(name, std::env::args().skip(1)).and_then(|args| run(&args)))
}

/// [`run_example`] for an example that reads the positional `input`
/// ([`ExampleArgs::parse_with_input`]).
pub fn run_example_with_input(
    name: &str,
    input: &str,
    run: impl FnOnce(&ExampleArgs) -> Result<(), ExperimentError>,
) -> std::process::ExitCode {
    finish(
        ExampleArgs::parse_with_input(name, input, std::env::args().skip(1))
            .and_then(|args| run(&args)),
    )
}

/// Prints an error to stderr; the exit code (1 on any error).
fn finish(outcome: Result<(), ExperimentError>) -> std::process::ExitCode {
    match outcome {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("{error}");
            std::process::ExitCode::FAILURE
        }
    }
}
