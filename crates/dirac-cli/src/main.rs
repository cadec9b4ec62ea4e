//! `dirac`: spectra of the operators of "A Dirac Operator for Extrinsic Shape Analysis"
//! (Liu, Jacobson, Crane 2017) from the command line. See `dirac --help`.
//!
//! Layers, from the top (docs/ARCHITECTURE.md): `main` → [`cli`] (definition and dispatch) →
//! [`commands`] (one module per subcommand) → [`common`] (what they share, [`CliError`]).

mod cli;
mod commands;
mod common;

use std::process::ExitCode;

use clap::Parser;

use crate::cli::Cli;
use crate::common::error::CliError;

fn main() -> ExitCode {
    let outcome = Cli::try_parse()
        .map_err(CliError::Usage)
        .and_then(|cli| cli::dispatch(&cli.command));
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            match &error {
                // clap's own rendering: `error: …`, the usage line, colours; `--help` on stdout.
                CliError::Usage(usage) => {
                    let _ = usage.print();
                }
                other => eprintln!("error: {other}"),
            }
            ExitCode::from(error.exit_code())
        }
    }
}
