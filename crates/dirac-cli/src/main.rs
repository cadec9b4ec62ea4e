//! `dirac`: spectra of the operators of "A Dirac Operator for Extrinsic Shape Analysis"
//! (Liu, Jacobson, Crane 2017) from the command line. See `dirac --help`.

mod args;
mod commands;
mod output;
mod progress;

use std::process::ExitCode;

use clap::Parser;

use crate::args::{Cli, Command};

fn main() -> ExitCode {
    let outcome = match Cli::parse().command {
        Command::Spectrum(args) => commands::spectrum::run(&args).map_err(|e| e.to_string()),
        Command::Eigenfunctions(args) => {
            commands::eigenfunctions::run(&args).map_err(|e| e.to_string())
        }
        Command::Descriptor(args) => commands::descriptor::run(&args).map_err(|e| e.to_string()),
        Command::Batch(args) => commands::batch::run(&args).map_err(|e| e.to_string()),
        Command::Render(args) => commands::render::run(&args).map_err(|e| e.to_string()),
        Command::Plot(args) => commands::plot::run(&args).map_err(|e| e.to_string()),
    };
    outcome.unwrap_or_else(|error| {
        eprintln!("error: {error}");
        ExitCode::FAILURE
    })
}
