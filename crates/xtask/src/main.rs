//! `cargo xtask test`: every test of the project, Rust and Python, in one command.
//!
//! 1. `cargo test --workspace`;
//! 2. `cargo build --release -p dirac-cli` (the Python tests compare with the command line);
//! 3. a virtual environment in `target/python-env` with numpy, scipy, pytest and matplotlib
//!    (the walk-through of docs/PYTHON.md draws with it), and the
//!    package installed from `crates/dirac-py` by `pip install` (maturin is fetched as its
//!    build backend), exactly as a user installs it;
//! 4. `pytest crates/dirac-py/tests`.
//!
//! `PYTHON` selects the interpreter that creates the environment (default `python3`, which
//! must be CPython 3.11 or later).

use std::env;
use std::ffi::OsStr;
use std::fmt;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

/// A step that failed, and how to see why.
#[derive(Debug)]
enum TaskError {
    /// A command could not be started.
    Start { program: String, error: String },
    /// A command ran and failed.
    Failed { step: &'static str, status: String },
    /// The arguments are not a known task.
    Usage(String),
}

impl fmt::Display for TaskError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TaskError::Start { program, error } => write!(
                f,
                "cannot run {program}: {error} (the Python steps need CPython 3.11 or later with venv \
                 and pip; set PYTHON to choose the interpreter)"
            ),
            TaskError::Failed { step, status } => write!(f, "{step} failed ({status})"),
            TaskError::Usage(message) => write!(f, "{message}\nusage: cargo xtask test"),
        }
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = env::args().skip(1).collect();
    let result = match args
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>()
        .as_slice()
    {
        ["test"] => test(),
        other => Err(TaskError::Usage(format!("unknown task {other:?}"))),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("xtask: {error}");
            ExitCode::FAILURE
        }
    }
}

/// The workspace root (this crate lives in `crates/xtask`).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .expect("crates/xtask lies two levels below the workspace root")
        .to_path_buf()
}

/// Runs `program args…` in the workspace root, as `step`.
fn run<I, S>(step: &'static str, program: impl AsRef<OsStr>, args: I) -> Result<(), TaskError>
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    run_with(step, Command::new(program).args(args))
}

/// Runs `command` in the workspace root, as `step`.
fn run_with(step: &'static str, command: &mut Command) -> Result<(), TaskError> {
    println!("\n=== {step}");
    let status = command
        .current_dir(root())
        .status()
        .map_err(|e| TaskError::Start {
            program: command.get_program().to_string_lossy().into_owned(),
            error: e.to_string(),
        })?;
    if status.success() {
        Ok(())
    } else {
        Err(TaskError::Failed {
            step,
            status: status.to_string(),
        })
    }
}

fn test() -> Result<(), TaskError> {
    let cargo = env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let root = root();
    run(
        "Rust tests (cargo test --workspace)",
        &cargo,
        ["test", "--workspace"],
    )?;
    run(
        "the command line, for the Python tests (cargo build --release -p dirac-cli)",
        &cargo,
        ["build", "--release", "-p", "dirac-cli"],
    )?;
    let environment = root.join("target").join("python-env");
    let python = environment.join("bin").join("python");
    if !python.is_file() {
        let interpreter = env::var_os("PYTHON").unwrap_or_else(|| "python3".into());
        run(
            "Python environment (target/python-env)",
            interpreter,
            [
                OsStr::new("-m"),
                OsStr::new("venv"),
                environment.as_os_str(),
            ],
        )?;
    }
    let pip = |step, packages: &[&str]| {
        let options = [
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
        ];
        run(step, &python, options.iter().chain(packages))
    };
    pip(
        "Python test dependencies",
        &["numpy", "scipy", "pytest", "matplotlib"],
    )?;
    pip(
        "the Python package (pip install crates/dirac-py)",
        &["--force-reinstall", "--no-deps", "crates/dirac-py"],
    )?;
    let binary = target_directory(&root).join("release").join("dirac");
    run_with(
        "Python tests (pytest crates/dirac-py/tests)",
        Command::new(&python)
            .args(["-m", "pytest", "-q", "crates/dirac-py/tests"])
            .env("DIRAC_BIN", binary),
    )
}

/// Where cargo puts what it builds: `CARGO_TARGET_DIR` (relative to the workspace when
/// relative), else `target/` of the workspace, so the tests find the binary cargo just built.
fn target_directory(root: &Path) -> PathBuf {
    env::var_os("CARGO_TARGET_DIR")
        .map(|dir| root.join(dir))
        .unwrap_or_else(|| root.join("target"))
}
