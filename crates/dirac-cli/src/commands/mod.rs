//! One module per subcommand: its arguments and a `run` function that returns `Ok(())` or the
//! [`CliError`](crate::common::error::CliError) `main` reports. A command imports only
//! [`crate::common`] and the library crates, never another command.

pub mod batch;
pub mod descriptor;
pub mod eigenfunctions;
pub mod matrices;
pub mod plot;
pub mod render;
pub mod repair;
pub mod segment;
pub mod segment_eval;
pub mod spectrum;
