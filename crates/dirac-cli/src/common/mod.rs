//! What the commands share: the bottom layer of the command line. Nothing here imports from
//! `commands` or `cli`; usage errors are built without the `Cli` definition
//! ([`error::CliError::usage`]) and get their usage line from the dispatcher.

pub mod error;
pub mod files;
pub mod matrix_market;
pub mod parsers;
pub mod preparation;
pub mod progress;
pub mod reference;
pub mod report;
pub mod solve;
pub mod solve_args;
