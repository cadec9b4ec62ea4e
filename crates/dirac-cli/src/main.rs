//! `dirac`: spectra of the operators of "A Dirac Operator for Extrinsic Shape Analysis"
//! (Liu, Jacobson, Crane 2017) from the command line. See `dirac --help`.

mod args;
mod command;
mod output;
mod progress;

use std::process::ExitCode;

use clap::Parser;

use crate::args::{Cli, Command};

fn main() -> ExitCode {
    match Cli::parse().command {
        Command::Spectrum(args) => {
            let options = args.options().unwrap_or_else(|error| error.exit());
            command::spectrum(&args, &options).unwrap_or_else(|error| {
                eprintln!("error: {error}");
                ExitCode::FAILURE
            })
        }
    }
}
