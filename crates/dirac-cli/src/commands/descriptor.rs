//! `dirac descriptor`: per-vertex spectral descriptors ([`dirac::descriptors`]) written as a
//! table with one row per vertex (mesh order) and one column per time, energy or mode.
//!
//! | kind | operator | columns (CSV header) |
//! |---|---|---|
//! | `hks` | always the Laplacian | one per time, `t=<t>` |
//! | `dks` | `--operator` (default relative Dirac) | one per time, `t=<t>` |
//! | `wks` | `--operator` | one per energy, `e=<e>` |
//! | `segmentation` | `--operator` | one per nonzero mode, `lambda=<λ>` |
//! | `eigvec` | `--operator` | `phi<i>_w, phi<i>_x, phi<i>_y, phi<i>_z` per eigenvector |
//!
//! `.csv` output has that header line and full-precision values; `.npy` output is a `float64`
//! array of shape `(n, columns)` (no header: pass `--times`/`--energies` to know them, or read
//! them from a CSV run).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use clap::error::ErrorKind;
use clap::{Args, ValueEnum};
use dirac::descriptors::{
    DEFAULT_SAMPLES, DescriptorError, Modes, WaveSampling, default_times, default_wave_sampling,
    dirac_kernel_signature, heat_kernel_signature, segmentation_descriptor, wave_kernel_signature,
};
use dirac::spectrum::Spectrum;
use ndarray::Array2;

use crate::common::error::CliError;
use crate::common::files::{has_extension, write_array};
use crate::common::parsers::{finite, positive_count, positive_real, value_name};
use crate::common::preparation::PreparedMesh;
use crate::common::reference::ReferenceArgs;
use crate::common::solve::solve;
use crate::common::solve_args::SolveArgs;

/// Exit codes and examples shown by `dirac descriptor --help`.
pub const AFTER_HELP: &str = "\
Descriptors (rows: vertices; φ mass-normalised, |φ|² = w² + x² + y² + z²):
  hks           Σ e^{−tλ} |φ|² of the Laplacian (--operator is not used)
  dks           Σ e^{−t|λ|} |φ|² of --operator (default relative-dirac)
  wks           Σ g |φ|² / Σ g,  g = exp(−(e − ln|λ|)² / 2σ²), zero modes excluded
  segmentation  |φ_i| / √|λ_i| over the nonzero modes
  eigvec        the components w, x, y, z of every eigenvector

Exit codes:
  0  success
  1  the mesh cannot be read or is invalid, the spectrum or the descriptor cannot be
     computed, or the output cannot be written (the message names the file and the problem)
  2  usage error (bad or missing arguments, options of another descriptor)
  3  the eigensolver did not converge; the descriptor of the converged pairs is written

Examples:
  dirac descriptor hks bunny.obj -k 100 --out hks.csv
  dirac descriptor dks bunny.obj -k 100 --times 0.01,0.1,1 --out dks.npy
  dirac descriptor wks bunny.obj --operator laplace -k 100 --samples 50 --out wks.csv";

/// Arguments of `dirac descriptor`.
#[derive(Debug, Args)]
pub struct DescriptorArgs {
    /// The descriptor.
    #[arg(value_enum)]
    pub kind: DescriptorKind,

    /// Mesh file (.obj, .off, .ply or .stl); without it, the built-in `spot` mesh.
    pub mesh: Option<PathBuf>,

    /// Operator and eigensolver (`hks` always uses the Laplacian).
    #[command(flatten)]
    pub solve: SolveArgs,

    /// The second surface of D_{f1,f2}.
    #[command(flatten)]
    pub reference: ReferenceArgs,

    /// Times t > 0 of hks/dks, comma-separated; default: --samples times log-spaced over
    /// [4 ln10/|λ|max, 4 ln10/|λ|min] (nonzero |λ|).
    #[arg(long, value_name = "T,…", value_delimiter = ',', value_parser = positive_real)]
    pub times: Option<Vec<f64>>,

    /// Log-energies e of wks, comma-separated; default: --samples evenly over
    /// [ln|λ|min + 2σ, ln|λ|max − 2σ] (nonzero |λ|).
    #[arg(long, value_name = "E,…", value_delimiter = ',', value_parser = finite,
          allow_hyphen_values = true)]
    pub energies: Option<Vec<f64>>,

    /// Width σ of the wks energy filter; default 7 (ln|λ|max − ln|λ|min)/100.
    #[arg(long, value_name = "SIGMA", value_parser = positive_real)]
    pub sigma: Option<f64>,

    /// Number of default times or energies.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_SAMPLES, value_parser = positive_count)]
    pub samples: usize,

    /// Output table: .csv (with a header) or .npy (float64, n × columns).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,

    /// No progress display on stderr.
    #[arg(short, long)]
    pub quiet: bool,
}

/// The descriptors.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DescriptorKind {
    /// Heat kernel signature Σ e^{−tλ}|φ|² of the Laplacian.
    Hks,
    /// Dirac kernel signature Σ e^{−t|λ|}|φ|² (paper §6.3).
    Dks,
    /// Wave kernel signature (Aubry et al. 2011), normalised per energy.
    Wks,
    /// |φ_i|/√|λ_i| over the nonzero modes (paper §6.2).
    Segmentation,
    /// The eigenvector components (w, x, y, z) themselves.
    Eigvec,
}

/// A computed table: column names and row-major values.
struct Table {
    header: Vec<String>,
    values: Vec<f64>,
}

/// Checks the options clap cannot relate (usage errors, exit code 2).
fn check(args: &DescriptorArgs) -> Result<(), CliError> {
    let error = |kind, message: String| Err(CliError::usage(kind, message));
    let kind = value_name(&args.kind);
    let kernel = matches!(args.kind, DescriptorKind::Hks | DescriptorKind::Dks);
    if args.times.is_some() && !kernel {
        return error(
            ErrorKind::ArgumentConflict,
            format!("--times applies only to hks and dks, not {kind}"),
        );
    }
    if (args.energies.is_some() || args.sigma.is_some()) && args.kind != DescriptorKind::Wks {
        return error(
            ErrorKind::ArgumentConflict,
            format!("--energies and --sigma apply only to wks, not {kind}"),
        );
    }
    if !(has_extension(&args.out, "csv") || has_extension(&args.out, "npy")) {
        return error(
            ErrorKind::ValueValidation,
            format!(
                "--out {}: expected a .csv or .npy file name",
                args.out.display()
            ),
        );
    }
    Ok(())
}

/// Most values of a descriptor table: 2²⁸ (2 GiB of `float64`; a million vertices × 268
/// columns), so that a mistyped `--samples` fails at once instead of after the solve.
const MAX_VALUES: usize = 1 << 28;

/// Checks, before the solve, that the table of `vertices` rows fits [`MAX_VALUES`].
fn check_size(args: &DescriptorArgs, vertices: usize, k: usize) -> Result<(), CliError> {
    let columns = match args.kind {
        DescriptorKind::Hks | DescriptorKind::Dks => {
            args.times.as_ref().map_or(args.samples, Vec::len)
        }
        DescriptorKind::Wks => args.energies.as_ref().map_or(args.samples, Vec::len),
        DescriptorKind::Segmentation => k,
        DescriptorKind::Eigvec => k.saturating_mul(4),
    };
    match vertices.checked_mul(columns) {
        Some(values) if values <= MAX_VALUES => Ok(()),
        _ => Err(CliError::usage(
            ErrorKind::ValueValidation,
            format!(
                "a table of {vertices} vertices × {columns} columns exceeds {MAX_VALUES} values \
                 (2 GiB); use fewer --samples, --times or --energies"
            ),
        )),
    }
}

/// The descriptor table of `spectrum`.
fn table(args: &DescriptorArgs, spectrum: &Spectrum) -> Result<Table, DescriptorError> {
    let modes = Modes::from_spectrum(spectrum)?;
    let named = |prefix: &str, parameters: &[f64]| -> Vec<String> {
        parameters.iter().map(|p| format!("{prefix}={p}")).collect()
    };
    let times = || match &args.times {
        Some(times) => Ok(times.clone()),
        None => default_times(&modes, args.samples),
    };
    let descriptor = match args.kind {
        DescriptorKind::Hks => heat_kernel_signature(&modes, &times()?)?,
        DescriptorKind::Dks => dirac_kernel_signature(&modes, &times()?)?,
        DescriptorKind::Wks => {
            let sampling = match (&args.energies, args.sigma) {
                (Some(energies), Some(sigma)) => WaveSampling {
                    energies: energies.clone(),
                    sigma,
                },
                (energies, sigma) => {
                    let default = default_wave_sampling(&modes, args.samples)?;
                    WaveSampling {
                        energies: energies.clone().unwrap_or(default.energies),
                        sigma: sigma.unwrap_or(default.sigma),
                    }
                }
            };
            wave_kernel_signature(&modes, &sampling)?
        }
        DescriptorKind::Segmentation => segmentation_descriptor(&modes)?,
        DescriptorKind::Eigvec => {
            let header = (0..modes.len())
                .flat_map(|i| ["w", "x", "y", "z"].map(|c| format!("phi{i}_{c}")))
                .collect();
            let values = (0..modes.vertex_count())
                .flat_map(|v| {
                    spectrum
                        .eigenvectors
                        .iter()
                        .flat_map(move |phi| phi[v].to_array())
                })
                .collect();
            return Ok(Table { header, values });
        }
    };
    let prefix = match args.kind {
        DescriptorKind::Wks => "e",
        DescriptorKind::Segmentation => "lambda",
        _ => "t",
    };
    Ok(Table {
        header: named(prefix, descriptor.parameters()),
        values: descriptor.values().to_vec(),
    })
}

/// Writes the table as CSV: the header, then one line per vertex.
fn write_csv(table: &Table, out: &mut impl Write) -> io::Result<()> {
    writeln!(out, "{}", table.header.join(","))?;
    for row in table.values.chunks(table.header.len().max(1)) {
        let line: Vec<String> = row.iter().map(f64::to_string).collect();
        writeln!(out, "{}", line.join(","))?;
    }
    out.flush()
}

/// Runs `dirac descriptor`: writes the table, then fails with [`CliError::NotConverged`] (exit
/// code 3) when the eigensolver did not converge (the descriptor of the converged pairs is
/// written).
pub fn run(args: &DescriptorArgs) -> Result<(), CliError> {
    let mut options = args.solve.options();
    check(args)?;
    if args.kind == DescriptorKind::Hks {
        args.solve.use_laplacian(&mut options, "hks");
    }
    let (prepared, reference) = args.reference.load_with_mesh(
        &args.solve.problem.preparation,
        args.mesh.as_deref(),
        options.operator,
        args.quiet,
    )?;
    let PreparedMesh { mesh, name, .. } = prepared;
    check_size(args, mesh.vertex_count(), options.k)?;
    let solved = solve(&mesh, reference.as_ref(), &name, &options, args.quiet)?;
    let table = table(args, &solved.spectrum).map_err(|source| CliError::Descriptor {
        mesh: name.clone(),
        source,
    })?;

    let path = &args.out;
    if has_extension(path, "csv") {
        File::create(path)
            .and_then(|file| write_csv(&table, &mut BufWriter::new(file)))
            .map_err(|source| CliError::Io {
                path: path.clone(),
                source,
            })?;
    } else {
        let shape = (mesh.vertex_count(), table.header.len());
        let array =
            Array2::from_shape_vec(shape, table.values).expect("one value per vertex and column");
        write_array(path, &array)?;
    }
    solved.check_converged(&name, options.k, "writing the descriptor of those")
}
