//! `dirac eigenfunctions`: the eigenpairs of an operator written to `.npy` files, or the
//! pointwise magnitude `|φ_I|` of one eigenvector on the mesh as a `.ply`.
//!
//! `--out NAME.npy` writes two files next to each other:
//!
//! - `NAME.eigenvalues.npy`: `float64`, shape `(k,)`, signed, sorted by `|λ|`;
//! - `NAME.eigenvectors.npy`: `float64`, shape `(n, k, 4)`: entry `[v, i, c]` is component `c`
//!   (`w, x, y, z` of `φ = w + x i + y j + z k`) of eigenvector `i` at vertex `v` — mass
//!   normalised (`Σ_v Ā_v |φ_i(v)|² = 1`, barycentric areas `Ā_v`), in canonical phase.
//!
//! `--out NAME.ply` writes the mesh (ASCII PLY) with a per-vertex `double` property `phi_abs`
//! holding `|φ_I(v)|` for `--mode I` (default 0).

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use clap::Args;
use clap::error::ErrorKind;
use dirac::io::{PlyWriteOptions, write_ply};
use ndarray::Array1;

use crate::common::error::CliError;
use crate::common::files::{eigenvector_array, has_extension, write_array};
use crate::common::preparation::PreparedMesh;
use crate::common::reference::ReferenceArgs;
use crate::common::solve::solve;
use crate::common::solve_args::SolveArgs;

/// Exit codes and examples shown by `dirac eigenfunctions --help`.
pub const AFTER_HELP: &str = "\
Output:
  NAME.npy  writes NAME.eigenvalues.npy (float64, shape (k,), signed, sorted by |λ|) and
            NAME.eigenvectors.npy (float64, shape (n, k, 4): [vertex, mode, (w, x, y, z)],
            mass-normalised, canonical phase)
  NAME.ply  writes the mesh with the per-vertex property phi_abs = |φ_I| (--mode I)

Exit codes:
  0  success
  1  the mesh cannot be read or is invalid, the spectrum cannot be computed, or an output
     file cannot be written (the message names the file and the problem)
  2  usage error (bad or missing arguments, an --out that is neither .npy nor .ply)
  3  the eigensolver did not converge; the converged pairs are written

Examples:
  dirac eigenfunctions bunny.obj -k 20 --out bunny.npy
  dirac eigenfunctions bunny.obj --operator laplace -k 10 --mode 3 --out mode3.ply";

/// Arguments of `dirac eigenfunctions`.
#[derive(Debug, Args)]
pub struct EigenfunctionsArgs {
    /// Mesh file (.obj, .off, .ply or .stl); without it, the built-in `spot` mesh.
    pub mesh: Option<PathBuf>,

    /// Operator and eigensolver.
    #[command(flatten)]
    pub solve: SolveArgs,

    /// The second surface of D_{f1,f2}.
    #[command(flatten)]
    pub reference: ReferenceArgs,

    /// Output: NAME.npy writes NAME.eigenvalues.npy (k) and NAME.eigenvectors.npy (n × k × 4,
    /// components w, x, y, z); NAME.ply writes the mesh with |φ_I| per vertex (`phi_abs`).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,

    /// The eigenvector written to a .ply (0-based, in order of |λ|; default 0).
    #[arg(long, value_name = "I")]
    pub mode: Option<usize>,

    /// No progress display on stderr.
    #[arg(short, long)]
    pub quiet: bool,
}

/// What `--out` asks for.
enum Output {
    /// The two `.npy` files.
    Npy {
        eigenvalues: PathBuf,
        eigenvectors: PathBuf,
    },
    /// The mesh with `|φ_mode|`.
    Ply { path: PathBuf, mode: usize },
}

/// `NAME.npy` → `NAME.<suffix>.npy`.
fn npy_sibling(path: &Path, suffix: &str) -> PathBuf {
    path.with_extension(format!("{suffix}.npy"))
}

/// Reads `--out` and `--mode`; usage errors (exit code 2) for an unknown extension, `--mode`
/// with `.npy` output, or a mode beyond `k`.
fn output(args: &EigenfunctionsArgs) -> Result<Output, CliError> {
    if has_extension(&args.out, "npy") {
        if args.mode.is_some() {
            return Err(CliError::usage(
                ErrorKind::ArgumentConflict,
                "--mode applies only to .ply output (.npy holds every eigenvector)",
            ));
        }
        Ok(Output::Npy {
            eigenvalues: npy_sibling(&args.out, "eigenvalues"),
            eigenvectors: npy_sibling(&args.out, "eigenvectors"),
        })
    } else if has_extension(&args.out, "ply") {
        let mode = args.mode.unwrap_or(0);
        if mode >= args.solve.k {
            return Err(CliError::usage(
                ErrorKind::ValueValidation,
                format!(
                    "--mode {mode} is not among the k = {} eigenvectors (0-based)",
                    args.solve.k
                ),
            ));
        }
        Ok(Output::Ply {
            path: args.out.clone(),
            mode,
        })
    } else {
        Err(CliError::usage(
            ErrorKind::ValueValidation,
            format!(
                "--out {}: expected a .npy or .ply file name",
                args.out.display()
            ),
        ))
    }
}

/// Runs `dirac eigenfunctions`: writes the pairs, then fails with [`CliError::NotConverged`]
/// (exit code 3) when the eigensolver did not converge (the converged pairs are written; for
/// `.ply` only if mode `I` is among them).
pub fn run(args: &EigenfunctionsArgs) -> Result<(), CliError> {
    let options = args.solve.options();
    let output = output(args)?;
    let (prepared, reference) = args.reference.load_with_mesh(
        &args.solve.problem.preparation,
        args.mesh.as_deref(),
        options.operator,
        args.quiet,
    )?;
    let PreparedMesh { mesh, name, .. } = prepared;
    let solved = solve(&mesh, reference.as_ref(), &name, &options, args.quiet)?;
    let spectrum = &solved.spectrum;
    let converged = spectrum.eigenvalues.len();

    let doing = match output {
        Output::Npy {
            eigenvalues,
            eigenvectors,
        } => {
            let vectors = eigenvector_array(spectrum, mesh.vertex_count());
            write_array(&eigenvalues, &Array1::from(spectrum.eigenvalues.clone()))?;
            write_array(&eigenvectors, &vectors)?;
            print_lines(&[
                format!("{} ({converged})", eigenvalues.display()),
                format!(
                    "{} ({} × {converged} × 4)",
                    eigenvectors.display(),
                    mesh.vertex_count()
                ),
            ])?;
            "writing those".to_string()
        }
        Output::Ply { path, mode } => match spectrum.eigenvectors.get(mode) {
            None => format!("mode {mode} is not among them, nothing written"),
            Some(phi) => {
                let magnitudes: Vec<f64> = phi.iter().map(|q| q.norm()).collect();
                let ply_options = PlyWriteOptions {
                    scalar: Some(("phi_abs", &magnitudes)),
                    ..PlyWriteOptions::default()
                };
                write_ply(&mesh, &path, &ply_options)?;
                print_lines(&[format!(
                    "{} (|phi_{mode}|, eigenvalue {})",
                    path.display(),
                    spectrum.eigenvalues[mode]
                )])?;
                format!("writing mode {mode}")
            }
        },
    };
    solved.check_converged(&name, options.k, &doing)
}

/// Prints the names of the written files on stdout.
fn print_lines(lines: &[String]) -> Result<(), CliError> {
    let mut out = io::stdout().lock();
    lines
        .iter()
        .try_for_each(|line| writeln!(out, "{line}"))
        .and_then(|()| out.flush())
        .map_err(CliError::Stdout)
}
