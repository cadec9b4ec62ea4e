//! `dirac render`: a picture of eigenfunction magnitudes `|φ_I|`, of a kernel signature (HKS,
//! DKS, WKS from [`dirac::descriptors`]) or of the potential well `U` on the mesh. Also what
//! `dirac plot` shares: the errors and exit codes of the picture commands and a solve that must
//! converge.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::error::ErrorKind;
use clap::{Args, ValueEnum};
use dirac::descriptors::{
    DescriptorError, Modes, WaveSampling, default_times, default_wave_sampling,
    dirac_kernel_signature, heat_kernel_signature, wave_kernel_signature,
};
use dirac::spectrum::{Normalization, Spectrum, SpectrumOptions};
use dirac::well::{PotentialWell, WellError};
use dirac::{MeshError, TriMesh};
use dirac_cli::plot::PlotError;
use dirac_cli::render::{
    Field, MAX_SIDE, Projection, RenderError, RenderOptions, View, format_value, render_png,
};
use thiserror::Error;

use crate::args::{SolveArgs, finite, positive_count, positive_real, usage_error, value_name};
use crate::commands::{ComputeError, NOT_CONVERGED, load_mesh, solve, tell};

/// Exit codes of `dirac render` and `dirac plot` (a macro, so `concat!` can join it with each
/// command's examples).
macro_rules! picture_exit_codes {
    () => {
        "\
Exit codes:
  0  success
  1  a mesh cannot be read or is invalid, a spectrum, descriptor or the potential cannot be
     computed, or the picture cannot be written (the message names the file and the problem)
  2  usage error (bad or missing arguments)
  3  the eigensolver did not converge
"
    };
}
pub(crate) use picture_exit_codes;

const AFTER_HELP: &str = concat!(
    picture_exit_codes!(),
    "
Quantities (φ mass-normalised, |φ|² = w² + x² + y² + z²; see `dirac descriptor --help`):
  eigenfunction  |φ_I| of --operator                    --mode I, --grid N: modes I … I+N−1
  hks            Σ e^{−tλ} |φ|² of the Laplacian       --time T, --grid N: N default times
  dks            Σ e^{−t|λ|} |φ|² of --operator         --time T, --grid N: N default times
  wks            Σ g |φ|² / Σ g of --operator           --energy E, --grid N: N default energies
  potential      U of the well (needs --well-radius)
Without --time/--energy a descriptor is drawn at the middle of its default range (the
geometric mean of the default times, the mean of the default energies).

Examples:
  dirac render --mode 3 --out spot-mode3.png            # |φ_3| of D_N on the built-in spot
  dirac render bunny.obj --operator laplace --grid 4 --size 1000x300 --out bunny.png
  dirac render --operator family --tau 0.5 --mode 1 --view -60,10 --out side.png
  dirac render --quantity dks -k 50 --grid 3 --size 900x300 --out dks.png
  dirac render --quantity hks -k 50 --time 0.5 --out hks.png
  dirac render --quantity potential --normalize unit-area --well-radius 0.3 --out well.png"
);

/// Arguments of `dirac render`.
#[derive(Debug, Args)]
#[command(after_help = AFTER_HELP)]
pub struct RenderArgs {
    /// Mesh file (.obj, .off or .ply); without it, the built-in `spot` mesh.
    pub mesh: Option<PathBuf>,

    /// Operator and eigensolver (`--quantity hks` always uses the Laplacian).
    #[command(flatten)]
    pub solve: SolveArgs,

    /// The eigenfunction to draw, 0-based in the order of `dirac spectrum` (by |λ|) [default:
    /// 0]; the eigenpairs computed are the first max(k, I + N). Only for --quantity
    /// eigenfunction.
    #[arg(long, value_name = "I")]
    pub mode: Option<usize>,

    /// Draw N panels side by side: modes I, I+1, …, I+N−1, or for hks/dks/wks N times or
    /// energies spanning the default range.
    #[arg(long, value_name = "N", value_parser = positive_count)]
    pub grid: Option<usize>,

    /// What to shade the mesh by.
    #[arg(long, value_enum, default_value_t = Quantity::Eigenfunction)]
    pub quantity: Quantity,

    /// Time t > 0 of --quantity hks or dks [default: the middle of the default times,
    /// 4 ln10 / √(|λ|min |λ|max) over the nonzero |λ|].
    #[arg(long, value_name = "T", value_parser = positive_real)]
    pub time: Option<f64>,

    /// Log-energy e of --quantity wks [default: the middle of the default energies,
    /// (ln|λ|min + ln|λ|max) / 2]; the filter width σ is the default of `dirac descriptor`.
    #[arg(long, value_name = "E", value_parser = finite, allow_hyphen_values = true)]
    pub energy: Option<f64>,

    /// The PNG file to write.
    #[arg(short, long, value_name = "FILE.png", value_parser = picture_path(&["png"]))]
    pub out: PathBuf,

    /// Camera direction: azimuth about the up (+y) axis from +z towards +x, and elevation, in
    /// degrees.
    #[arg(long, value_name = "AZ,EL", default_value_t = View::default(), allow_hyphen_values = true)]
    pub view: View,

    /// Size of the whole image in pixels (all panels of a grid together).
    #[arg(long, value_name = "WxH", default_value = "800x600", value_parser = parse_size)]
    pub size: (u32, u32),

    /// Parallel instead of perspective projection.
    #[arg(long)]
    pub orthographic: bool,

    /// No progress display on stderr and no confirmation on stdout.
    #[arg(short, long)]
    pub quiet: bool,
}

/// `--quantity` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Quantity {
    /// The magnitude |φ_I| of the eigenfunction at each vertex.
    Eigenfunction,
    /// The potential U of the well (needs --well-radius; no eigenproblem is solved).
    Potential,
    /// Heat kernel signature Σ e^{−tλ}|φ|² of the Laplacian at time --time.
    Hks,
    /// Dirac kernel signature Σ e^{−t|λ|}|φ|² (paper §6.3) at time --time.
    Dks,
    /// Wave kernel signature (Aubry et al. 2011) at log-energy --energy.
    Wks,
}

/// Why `dirac render` or `dirac plot` failed.
#[derive(Debug, Error)]
pub enum CommandError {
    /// A mesh cannot be read, or its spectrum or a descriptor cannot be computed.
    #[error(transparent)]
    Compute(#[from] ComputeError),
    /// The eigensolver stopped before all wanted pairs converged (exit code 3).
    #[error(
        "{mesh}: the eigensolver converged only {converged} of {wanted} eigenpairs \
         (try a larger --tolerance, more --max-restarts or another --seed)"
    )]
    NotConverged {
        /// The mesh.
        mesh: String,
        /// Pairs that converged.
        converged: usize,
        /// Pairs wanted.
        wanted: usize,
    },
    /// The potential well cannot be computed on this mesh.
    #[error("{mesh}: potential well: {source}")]
    Well {
        /// The mesh.
        mesh: String,
        /// What failed.
        source: WellError,
    },
    /// Normalising the mesh failed.
    #[error("{mesh}: {source}")]
    Normalize {
        /// The mesh.
        mesh: String,
        /// What failed.
        source: MeshError,
    },
    /// The picture cannot be drawn or written (the message names the file).
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The chart cannot be drawn or written (the message names the file).
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// The exit code of a picture command: success, or 3 after reporting a solve that did not
/// converge; other errors are returned for `main` to report (exit code 1).
pub fn exit_code(outcome: Result<(), CommandError>) -> Result<ExitCode, CommandError> {
    match outcome {
        Ok(()) => Ok(ExitCode::SUCCESS),
        Err(error @ CommandError::NotConverged { .. }) => {
            eprintln!("error: {error}");
            Ok(ExitCode::from(NOT_CONVERGED))
        }
        Err(error) => Err(error),
    }
}

/// The spectrum of `mesh` (called `name` in messages) with the progress display; a solve that
/// stops early is an error here, since a picture of some other mode would mislead.
pub fn solve_converged(
    mesh: &TriMesh,
    name: &str,
    options: &SpectrumOptions,
    quiet: bool,
) -> Result<Spectrum, CommandError> {
    let solved = solve(mesh, name, options, quiet)?;
    if !solved.converged {
        return Err(CommandError::NotConverged {
            mesh: name.to_string(),
            converged: solved.spectrum.eigenvalues.len(),
            wanted: options.k,
        });
    }
    Ok(solved.spectrum)
}

/// Runs `dirac render`.
pub fn run(args: &RenderArgs) -> Result<ExitCode, CommandError> {
    exit_code(render(args))
}

/// What the panels show, from `--quantity` and the options that go with it.
#[derive(Debug, Clone, Copy)]
enum Shading {
    /// `|φ_i|` of the modes from this one on.
    Modes(usize),
    /// The well's potential.
    Potential(PotentialWell),
    /// A kernel signature (`Hks`, `Dks` or `Wks`) at this time or energy, or at default ones.
    Signature(Quantity, Option<f64>),
}

/// Checks the combinations of options that clap cannot express (usage errors, exit code 2)
/// and says what to draw; `well` is the potential well of the solver options.
fn shading(args: &RenderArgs, well: Option<PotentialWell>) -> Result<Shading, clap::Error> {
    let error = |kind, message: String| Err(usage_error("render", kind, message));
    let quantity = value_name(&args.quantity);
    if args.mode.is_some() && args.quantity != Quantity::Eigenfunction {
        return error(
            ErrorKind::ArgumentConflict,
            format!("--mode applies only to --quantity eigenfunction, not {quantity}"),
        );
    }
    if args.time.is_some() && !matches!(args.quantity, Quantity::Hks | Quantity::Dks) {
        return error(
            ErrorKind::ArgumentConflict,
            format!("--time applies only to --quantity hks or dks, not {quantity}"),
        );
    }
    if args.energy.is_some() && args.quantity != Quantity::Wks {
        return error(
            ErrorKind::ArgumentConflict,
            format!("--energy applies only to --quantity wks, not {quantity}"),
        );
    }
    let at = args.time.or(args.energy);
    if args.grid.is_some() && at.is_some() {
        return error(
            ErrorKind::ArgumentConflict,
            "--grid N draws N times or energies of the default range; it does not combine \
             with --time or --energy"
                .to_string(),
        );
    }
    match (args.quantity, well) {
        (Quantity::Eigenfunction, _) => Ok(Shading::Modes(args.mode.unwrap_or(0))),
        (Quantity::Potential, None) => error(
            ErrorKind::MissingRequiredArgument,
            "--quantity potential needs --well-radius <BETA>".to_string(),
        ),
        (Quantity::Potential, Some(_)) if args.grid.is_some() => error(
            ErrorKind::ArgumentConflict,
            "--grid does not apply to --quantity potential".to_string(),
        ),
        (Quantity::Potential, Some(well)) => Ok(Shading::Potential(well)),
        (kernel, _) => Ok(Shading::Signature(kernel, at)),
    }
}

fn render(args: &RenderArgs) -> Result<(), CommandError> {
    let mut options = args
        .solve
        .options("render")
        .unwrap_or_else(|error| error.exit());
    let shading = shading(args, options.well).unwrap_or_else(|error| error.exit());
    let count = args.grid.unwrap_or(1);
    let (mesh, name) = load_mesh(args.mesh.as_deref())?;

    let fields = match shading {
        Shading::Potential(well) => vec![potential(&mesh, &name, well, options.normalization)?],
        Shading::Modes(first) => {
            let wanted = first.saturating_add(count);
            if wanted > mesh.vertex_count() {
                usage_error(
                    "render",
                    ErrorKind::ValueValidation,
                    format!(
                        "--mode {first} with {count} panel(s) needs {wanted} eigenpairs, but \
                         {name} has only {} vertices",
                        mesh.vertex_count()
                    ),
                )
                .exit();
            }
            options.k = options.k.max(wanted);
            let spectrum = solve_converged(&mesh, &name, &options, args.quiet)?;
            (first..wanted)
                .map(|i| Field {
                    label: format!(
                        "|φ{}|  λ = {}",
                        subscript(i),
                        format_value(spectrum.eigenvalues[i])
                    ),
                    values: spectrum.eigenvectors[i].iter().map(|q| q.norm()).collect(),
                })
                .collect()
        }
        Shading::Signature(kernel, at) => {
            if kernel == Quantity::Hks {
                args.solve.use_laplacian(&mut options, "hks");
            }
            let spectrum = solve_converged(&mesh, &name, &options, args.quiet)?;
            signature_fields(kernel, at, count, &spectrum).map_err(|source| {
                ComputeError::Descriptor {
                    mesh: name.clone(),
                    source,
                }
            })?
        }
    };

    let (width, height) = args.size;
    let render_options = RenderOptions {
        width,
        height,
        view: args.view,
        columns: None,
        projection: if args.orthographic {
            Projection::Orthographic
        } else {
            Projection::Perspective
        },
        ..RenderOptions::default()
    };
    render_png(&mesh, &fields, &render_options, &args.out)?;
    if !args.quiet {
        let operator = value_name(&args.solve.operator);
        let what = match shading {
            Shading::Potential(_) => "the potential".to_string(),
            Shading::Modes(_) => format!("{count} eigenfunction(s) of {operator}"),
            Shading::Signature(Quantity::Hks, _) => format!("the HKS in {count} panel(s)"),
            Shading::Signature(kernel, _) => format!(
                "the {} of {operator} in {count} panel(s)",
                value_name(&kernel).to_uppercase()
            ),
        };
        tell(format_args!(
            "wrote {} ({width}x{height}): {what} on {name}",
            args.out.display()
        ));
    }
    Ok(())
}

/// The panels of a kernel signature (`Hks`, `Dks` or `Wks`) of `spectrum`: one at the time or
/// energy `at`, or else `count` spanning the default range of [`dirac::descriptors`] (one: the
/// middle of that range, the middle one of three default samples).
fn signature_fields(
    kernel: Quantity,
    at: Option<f64>,
    count: usize,
    spectrum: &Spectrum,
) -> Result<Vec<Field>, DescriptorError> {
    let modes = Modes::from_spectrum(spectrum)?;
    let samples = if count == 1 { 3 } else { count };
    let pick = |defaults: Vec<f64>| {
        if count == 1 {
            vec![defaults[1]]
        } else {
            defaults
        }
    };
    let (name, parameter, table) = if kernel == Quantity::Wks {
        let default = default_wave_sampling(&modes, samples)?;
        let sampling = WaveSampling {
            energies: at.map_or_else(|| pick(default.energies), |energy| vec![energy]),
            sigma: default.sigma,
        };
        ("WKS", "e", wave_kernel_signature(&modes, &sampling)?)
    } else {
        let times = match at {
            Some(time) => vec![time],
            None => pick(default_times(&modes, samples)?),
        };
        if kernel == Quantity::Hks {
            ("HKS", "t", heat_kernel_signature(&modes, &times)?)
        } else {
            ("DKS", "t", dirac_kernel_signature(&modes, &times)?)
        }
    };
    Ok(table
        .parameters()
        .iter()
        .enumerate()
        .map(|(j, &value)| Field {
            label: format!("{name}  {parameter} = {}", format_value(value)),
            values: table.column(j),
        })
        .collect())
}

/// The well's potential `U` on the mesh as the spectrum would see it: normalised first, since
/// the well's radius is a distance on the normalised mesh.
fn potential(
    mesh: &TriMesh,
    name: &str,
    well: PotentialWell,
    normalization: Normalization,
) -> Result<Field, CommandError> {
    let scaled = match normalization {
        Normalization::None => None,
        Normalization::UnitArea => {
            let area: f64 = (0..mesh.face_count()).map(|t| mesh.face_area(t)).sum();
            Some(
                mesh.scaled(1.0 / area.sqrt())
                    .map_err(|source| CommandError::Normalize {
                        mesh: name.to_string(),
                        source,
                    })?,
            )
        }
    };
    let values = well
        .potential(scaled.as_ref().unwrap_or(mesh))
        .map_err(|source| CommandError::Well {
            mesh: name.to_string(),
            source,
        })?;
    Ok(Field {
        label: format!("potential U, radius β = {}", well.radius),
        values,
    })
}

/// `i` in Unicode subscript digits (`12` → `₁₂`).
fn subscript(i: usize) -> String {
    i.to_string()
        .chars()
        .map(|d| char::from_u32(0x2080 + d.to_digit(10).unwrap_or(0)).unwrap_or(d))
        .collect()
}

/// Value parser of `--size`: `WIDTHxHEIGHT`, both sides positive and at most [`MAX_SIDE`].
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let error = || format!("`{text}` is not a size WIDTHxHEIGHT in pixels (for example 800x600)");
    let (width, height) = text.split_once(['x', 'X']).ok_or_else(error)?;
    let side = |s: &str| s.trim().parse::<u32>().map_err(|_| error());
    let (width, height) = (side(width)?, side(height)?);
    if width == 0 || height == 0 {
        return Err(format!("size {text}: width and height must be positive"));
    }
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(format!(
            "size {text}: the largest side allowed is {MAX_SIDE} pixels"
        ));
    }
    Ok((width, height))
}

/// A value parser of output files that accepts the given extensions (any case), so a wrong
/// one is a usage error before any work is done.
pub fn picture_path(
    extensions: &'static [&'static str],
) -> impl Fn(&str) -> Result<PathBuf, String> + Clone {
    move |text: &str| {
        let path = PathBuf::from(text);
        let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if extensions.iter().any(|e| e.eq_ignore_ascii_case(extension)) {
            Ok(path)
        } else {
            Err(format!(
                "{text}: the file name must end in .{}",
                extensions.join(" or .")
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_bad_ones_are_explained() {
        assert_eq!(parse_size("800x600"), Ok((800, 600)));
        assert_eq!(parse_size("64X48"), Ok((64, 48)));
        for bad in ["800", "800x", "x600", "-5x5", "axb", "800x600x2"] {
            let message = parse_size(bad).expect_err(bad);
            assert!(message.contains("WIDTHxHEIGHT"), "{bad}: {message}");
        }
        assert!(parse_size("0x10").expect_err("zero").contains("positive"));
        assert!(
            parse_size("99999x10")
                .expect_err("huge")
                .contains("largest")
        );
    }

    #[test]
    fn picture_paths_need_a_known_extension() {
        let parse = picture_path(&["png", "svg"]);
        assert_eq!(parse("a/b.SVG"), Ok(PathBuf::from("a/b.SVG")));
        assert!(
            parse("chart.gif")
                .expect_err("gif")
                .contains("chart.gif: the file name must end in .png or .svg")
        );
        assert!(parse("chart").is_err());
    }

    #[test]
    fn subscripts() {
        assert_eq!(subscript(0), "₀");
        assert_eq!(subscript(109), "₁₀₉");
    }
}
