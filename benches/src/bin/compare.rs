//! `compare`: times the quaternion-native path against the real-block (faer, 4n×4n) and
//! complex-adjoint (faer, 2n×2n) paths in one run, on the same matrix, and prints one JSON
//! object.
//!
//! ```text
//! compare spmv|cholesky [--level L | --size N] [--repeats R] [--single-thread]
//! compare ordering [--level L | --size N | --mesh FILE] [--repeats R] [--single-thread]
//! compare eigs [--level L | --mesh FILE] [-k K] [--repeats R] [--single-thread]
//!              [--operator laplace-quaternionic|OPERATOR] [--cases CASE,CASE,…]
//! ```
//!
//! `spmv` and `cholesky` use `dirac_bench::connection_laplacian` on the unit icosphere:
//! `--level L` gives `10·4^L + 2` quaternion unknowns, `--size N` picks the smallest level with
//! at least `N`. `eigs` computes `K` quaternionic pairs of the quaternionic Laplacian pencil on
//! the icosphere with every backend and the real scalar Laplacian (`dirac_bench::eigs`; `--cases`
//! keeps some of `dirac_bench::eigs::EIGS_CASES`, for example `native,real-scalar`), or,
//! with `--operator OPERATOR` written as for `dirac` (`relative-dirac`, `family:0.5`, …), the
//! spectrum of that operator on the icosphere or `--mesh FILE` with every backend
//! (`dirac_bench::spectra`). `ordering` factors the same matrix (on the icosphere, or on
//! `--mesh FILE` with `dirac_bench::connection_laplacian_on`) with AMD and with nested
//! dissection and reports fill and times of each phase (`dirac_bench::linear::compare_orderings`).
//! Defaults: `cholesky --level 4 --repeats 5` (2,562 unknowns, a few seconds), `-k 60`.
//! faer always runs on one thread; our solver uses a second core where it pays
//! (`qsparse::threads`) unless `--single-thread` is given, which makes every path sequential.

use std::process::ExitCode;

use dirac::generators::icosphere;
use dirac::io::read_mesh;
use dirac::spectrum::Operator;
use dirac_bench::eigs::{EIGS_CASES, compare_eigs_cases};
use dirac_bench::linear::{compare_cholesky, compare_orderings, compare_spmv};
use dirac_bench::spectra::compare_spectrum;
use dirac_bench::{connection_laplacian, connection_laplacian_on, icosphere_level_for};

const USAGE: &str = "usage: compare [spmv|cholesky|ordering|eigs] [--level L | --size N | --mesh FILE] \
                     [-k K] [--repeats R] [--operator laplace-quaternionic|relative-dirac|family:T|…] \
                     [--cases CASE,CASE,…] [--single-thread]";

struct Options {
    case: String,
    level: u32,
    k: usize,
    repeats: usize,
    mesh: Option<String>,
    operator: String,
    cases: Vec<String>,
    single_thread: bool,
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut options = Options {
        case: "cholesky".into(),
        level: 4,
        k: 60,
        repeats: 5,
        mesh: None,
        operator: "laplace-quaternionic".into(),
        cases: EIGS_CASES.iter().map(|c| c.to_string()).collect(),
        single_thread: false,
    };
    let mut i = 0;
    while i < args.len() {
        let value = |i: usize| args.get(i + 1).ok_or(format!("{} needs a value", args[i]));
        match args[i].as_str() {
            "--level" => {
                options.level = value(i)?.parse().map_err(|e| format!("--level: {e}"))?;
                i += 1;
            }
            "--size" => {
                let size: usize = value(i)?.parse().map_err(|e| format!("--size: {e}"))?;
                options.level = icosphere_level_for(size);
                i += 1;
            }
            "--mesh" => {
                options.mesh = Some(value(i)?.clone());
                i += 1;
            }
            "--operator" => {
                options.operator = value(i)?.clone();
                i += 1;
            }
            "-k" => {
                options.k = value(i)?.parse().map_err(|e| format!("-k: {e}"))?;
                i += 1;
            }
            "--repeats" => {
                options.repeats = value(i)?.parse().map_err(|e| format!("--repeats: {e}"))?;
                i += 1;
            }
            "--cases" => {
                options.cases = value(i)?.split(',').map(str::to_string).collect();
                if let Some(unknown) = options
                    .cases
                    .iter()
                    .find(|c| !EIGS_CASES.contains(&c.as_str()))
                {
                    return Err(format!(
                        "--cases: unknown case {unknown} (known: {})",
                        EIGS_CASES.join(", ")
                    ));
                }
                i += 1;
            }
            "--single-thread" => options.single_thread = true,
            "-h" | "--help" => return Err(USAGE.into()),
            case if !case.starts_with('-') => options.case = case.into(),
            other => return Err(format!("unknown option {other}\n{USAGE}")),
        }
        i += 1;
    }
    if options.level > 8 {
        return Err(format!(
            "--level {} is too large (at most 8)",
            options.level
        ));
    }
    Ok(options)
}

/// `compare eigs --operator OPERATOR` on `--mesh FILE` or the icosphere.
fn operator_spectrum(options: &Options) -> Result<serde_json::Value, String> {
    let operator: Operator = options
        .operator
        .parse()
        .map_err(|e| format!("--operator: {e}\n{USAGE}"))?;
    let (mesh, label) = match &options.mesh {
        Some(path) => (read_mesh(path).map_err(|e| e.to_string())?, path.clone()),
        None => (
            icosphere(options.level),
            format!("icosphere level {}", options.level),
        ),
    };
    Ok(compare_spectrum(
        &mesh,
        &label,
        operator,
        options.k,
        options.repeats,
    ))
}

/// The matrix of `compare ordering`: the connection Laplacian of `--mesh FILE` or of the
/// icosphere.
fn ordering_matrix(options: &Options) -> Result<qsparse::SparseMatrix<qscalar::Quat<f64>>, String> {
    Ok(match &options.mesh {
        Some(path) => connection_laplacian_on(&read_mesh(path).map_err(|e| e.to_string())?),
        None => connection_laplacian(options.level),
    })
}

fn main() -> ExitCode {
    faer::set_global_parallelism(faer::Par::Seq);
    let args: Vec<String> = std::env::args().skip(1).collect();
    let options = match parse(&args) {
        Ok(o) => o,
        Err(message) => {
            eprintln!("{message}");
            return ExitCode::from(2);
        }
    };
    qsparse::threads::set_second_thread_allowed(!options.single_thread);
    let report = match options.case.as_str() {
        "spmv" => compare_spmv(&connection_laplacian(options.level), options.repeats),
        "cholesky" => compare_cholesky(&connection_laplacian(options.level), options.repeats),
        "ordering" => match ordering_matrix(&options) {
            Ok(a) => compare_orderings(&a, options.repeats),
            Err(message) => {
                eprintln!("{message}");
                return ExitCode::FAILURE;
            }
        },
        "eigs" if options.operator == "laplace-quaternionic" => {
            let cases: Vec<&str> = options.cases.iter().map(String::as_str).collect();
            compare_eigs_cases(options.level, options.k, options.repeats, &cases)
        }
        "eigs" => match operator_spectrum(&options) {
            Ok(report) => report,
            Err(message) => {
                eprintln!("{message}");
                return ExitCode::FAILURE;
            }
        },
        other => {
            eprintln!("unknown case {other}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    println!("{report}");
    ExitCode::SUCCESS
}
