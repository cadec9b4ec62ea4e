//! `dirac render`: a picture of eigenfunction magnitudes `|φ_I|`, of a kernel signature (HKS,
//! DKS, WKS from [`dirac::descriptors`]) or of the potential well `U` on the mesh.

use std::path::PathBuf;

use clap::error::ErrorKind;
use clap::{Args, ValueEnum};
use dirac::TriMesh;
use dirac::descriptors::{
    DescriptorError, Modes, WaveSampling, default_times, default_wave_sampling,
    dirac_kernel_signature, heat_kernel_signature, wave_kernel_signature,
};
use dirac::spectrum::{Normalization, Spectrum};
use dirac::well::PotentialWell;
use dirac_cli::render::{
    Field, MIN_PANEL, Projection, RenderOptions, View, format_value, max_panels, render_png,
};

use crate::common::error::{CliError, PICTURE_EXIT_CODES};
use crate::common::files::tell;
use crate::common::parsers::{
    finite, parse_size, picture_path, positive_count, positive_real, value_name,
};
use crate::common::preparation::PreparedMesh;
use crate::common::reference::ReferenceArgs;
use crate::common::solve::solve_converged;
use crate::common::solve_args::SolveArgs;

/// What `dirac render --help` shows after the exit codes.
const QUANTITIES_AND_EXAMPLES: &str = "
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
  dirac render --operator family:0.5 --mode 1 --view -60,10 --out side.png
  dirac render --quantity dks -k 50 --grid 3 --size 900x300 --out dks.png
  dirac render --quantity hks -k 50 --time 0.5 --out hks.png
  dirac render --quantity potential --normalize unit-area --well-radius 0.3 --out well.png";

/// Arguments of `dirac render`.
#[derive(Debug, Args)]
#[command(after_help = format!("{PICTURE_EXIT_CODES}{QUANTITIES_AND_EXAMPLES}"))]
pub struct RenderArgs {
    /// Mesh file (.obj, .off, .ply or .stl); without it, the built-in `spot` mesh.
    pub mesh: Option<PathBuf>,

    /// Operator and eigensolver (`--quantity hks` always uses the Laplacian).
    #[command(flatten)]
    pub solve: SolveArgs,

    /// The second surface of D_{f1,f2}.
    #[command(flatten)]
    pub reference: ReferenceArgs,

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
fn shading(args: &RenderArgs, well: Option<PotentialWell>) -> Result<Shading, CliError> {
    let error = |kind, message: String| Err(CliError::usage(kind, message));
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

/// Runs `dirac render`: writes the picture, or fails (a solve that did not converge draws
/// nothing: [`CliError::NotConverged`], exit code 3).
pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let mut options = args.solve.options();
    let shading = shading(args, options.well)?;
    let count = args.grid.unwrap_or(1);
    let (width, height) = args.size;
    if count > max_panels(width, height) {
        return Err(CliError::usage(
            ErrorKind::ValueValidation,
            format!(
                "--grid {count}: a {width}x{height} image holds at most {} panels of \
                 {MIN_PANEL}x{MIN_PANEL} pixels; use a smaller --grid or a larger --size",
                max_panels(width, height)
            ),
        ));
    }
    let (prepared, reference) = args.reference.load_with_mesh(
        &args.solve.problem.preparation,
        args.mesh.as_deref(),
        options.operator,
        args.quiet,
    )?;
    let PreparedMesh { mesh, name, .. } = prepared;

    let fields = match shading {
        Shading::Potential(well) => vec![potential(&mesh, &name, well, options.normalization)?],
        Shading::Modes(first) => {
            let wanted = first.saturating_add(count);
            if wanted > mesh.vertex_count() {
                return Err(CliError::usage(
                    ErrorKind::ValueValidation,
                    format!(
                        "--mode {first} with {count} panel(s) needs {wanted} eigenpairs, but \
                         {name} has only {} vertices",
                        mesh.vertex_count()
                    ),
                ));
            }
            options.k = options.k.max(wanted);
            let spectrum = solve_converged(&mesh, reference.as_ref(), &name, &options, args.quiet)?;
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
            let spectrum = solve_converged(&mesh, reference.as_ref(), &name, &options, args.quiet)?;
            signature_fields(kernel, at, count, &spectrum).map_err(|source| {
                CliError::Descriptor {
                    mesh: name.clone(),
                    source,
                }
            })?
        }
    };

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
        let operator = args.solve.problem.operator;
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
) -> Result<Field, CliError> {
    let scaled = match normalization {
        Normalization::None => None,
        Normalization::UnitArea => {
            let area: f64 = (0..mesh.face_count()).map(|t| mesh.face_area(t)).sum();
            Some(
                mesh.scaled(1.0 / area.sqrt())
                    .map_err(|source| CliError::Normalize {
                        mesh: name.to_string(),
                        source,
                    })?,
            )
        }
    };
    let values = well
        .potential(scaled.as_ref().unwrap_or(mesh))
        .map_err(|source| CliError::Well {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subscripts() {
        assert_eq!(subscript(0), "₀");
        assert_eq!(subscript(109), "₁₀₉");
    }
}
