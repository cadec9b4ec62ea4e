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
    keep_freed_memory();
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

/// glibc's `malloc` serves blocks from 128 KiB up with fresh memory mappings, returns them to
/// the system on `free`, and raises that threshold only as it sees large blocks freed (at
/// most to 32 MiB). A spectrum allocates and frees many such blocks (mesh tables, matrices,
/// work vectors), and each fresh mapping is paid again in page faults: starting at the
/// threshold glibc would reach anyway, and keeping up to 64 MiB of freed memory per
/// allocator arena (about one per thread), cut the page faults of a small Laplace spectrum by
/// a quarter to a third and its time by 4–7 %, for 0.5–1.5 MB more peak memory (a `batch`
/// of relative Dirac spectra on two threads: 10 % more; docs/PERFORMANCE.md). Blocks above
/// 32 MiB (the bases and factors of large meshes) are still mapped and returned one by one.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_freed_memory() {
    const MIB: libc::c_int = 1 << 20;
    // SAFETY: `mallopt` only sets parameters of the allocator, which takes its own lock;
    // called first thing, before any other thread exists.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 * MIB);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 64 * MIB);
    }
}

/// Other allocators keep their own policy.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_freed_memory() {}
