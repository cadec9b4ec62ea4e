//! `dirac segment`: the consensus segmentation of paper §6.2
//! ([`dirac::segmentation::consensus`]) of the segmentation descriptor `|φ_i|/√|λ_i|`, written
//! as labels (`.seg`), a mesh with a colour per face (`.ply`) or a picture (`.png`).

use std::fs::File;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use clap::Args;
use clap::error::ErrorKind;
use dirac::TriMesh;
use dirac::descriptors::{Modes, segmentation_descriptor};
use dirac::io::{PlyWriteOptions, write_ply};
use dirac::segmentation::consensus::{
    ConsensusOptions, ConsensusSegmentation, Level, Run, segment_by_descriptor,
};
use dirac::segmentation::seg_file::write_seg;
use dirac_cli::render::{Projection, RenderOptions, View, render_segments_png, segment_colour};
use serde::Serialize;

use crate::common::error::CliError;
use crate::common::files::{has_extension, tell};
use crate::common::parsers::{parse_size, positive_count};
use crate::common::preparation::{PreparationReport, PreparedMesh};
use crate::common::report::RunSettings;
use crate::common::solve::solve;
use crate::common::solve_args::SolveArgs;

/// Exit codes and examples shown by `dirac segment --help`.
pub const AFTER_HELP: &str = "\
Method (docs/MATH.md, \"Consensus segmentation\"): the descriptor |φ_i|/√|λ_i| of the k
eigenpairs (nonzero modes), averaged over each face's corners; --trials k-means runs with a
random number of clusters in [--min-clusters, --max-clusters]; for every pair of adjacent faces
the fraction of runs that put them together; faces joined where that fraction is at least a
threshold θ, segments under --min-area of the surface absorbed by their strongest neighbour;
the number of segments is the one that persists over the widest range of θ (or --segments N).
--seed seeds both the eigensolver and the k-means runs.

Output (faces in the order of the mesh used: with --repair or --component, the repaired or
selected mesh, whose faces may be renumbered or dropped):
  FILE.seg  one label 0…S−1 per line, one line per face (the Princeton benchmark's format)
  FILE.ply  the mesh with a colour per face (red, green, blue of the face element)
  FILE.png  a picture: a flat colour per segment, dark lines along segment boundaries

Exit codes:
  0  success
  1  the mesh cannot be read or is invalid, the spectrum, descriptor or segmentation cannot
     be computed, or the output cannot be written (the message names the file and the problem)
  2  usage error (bad or missing arguments)
  3  the eigensolver did not converge; nothing is written

Examples:
  dirac segment bunny.off --out bunny.seg
  dirac segment bunny.off --operator laplace -k 20 --segments 6 --out bunny.png
  dirac segment bunny.off --json --out bunny.ply";

/// Arguments of `dirac segment`.
#[derive(Debug, Args)]
pub struct SegmentArgs {
    /// Mesh file (.obj, .off, .ply or .stl); without it, the built-in `spot` mesh.
    pub mesh: Option<PathBuf>,

    /// Operator and eigensolver (default relative Dirac, as in the paper).
    #[command(flatten)]
    pub solve: SolveArgs,

    /// Number of segments, instead of the one chosen by persistence.
    #[arg(long, value_name = "N", value_parser = positive_count, help_heading = "Segmentation")]
    pub segments: Option<usize>,

    /// Number of k-means runs.
    #[arg(long, value_name = "T", default_value_t = ConsensusOptions::default().trials,
          value_parser = positive_count, help_heading = "Segmentation")]
    pub trials: usize,

    /// Fewest clusters of a k-means run (at least 2).
    #[arg(long, value_name = "K", default_value_t = ConsensusOptions::default().min_clusters,
          help_heading = "Segmentation")]
    pub min_clusters: usize,

    /// Most clusters of a k-means run.
    #[arg(long, value_name = "K", default_value_t = ConsensusOptions::default().max_clusters,
          help_heading = "Segmentation")]
    pub max_clusters: usize,

    /// Segments with less than this fraction of the surface area are absorbed, in [0, 1).
    #[arg(long, value_name = "FRACTION",
          default_value_t = ConsensusOptions::default().min_area_fraction,
          value_parser = area_fraction, help_heading = "Segmentation")]
    pub min_area: f64,

    /// Output: FILE.seg (labels), FILE.ply (colour per face) or FILE.png (picture).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,

    /// With .png: camera direction AZ,EL in degrees (as `dirac render`).
    #[arg(long, value_name = "AZ,EL", default_value_t = View::default(), allow_hyphen_values = true)]
    pub view: View,

    /// With .png: size of the picture in pixels.
    #[arg(long, value_name = "WxH", default_value = "600x600", value_parser = parse_size)]
    pub size: (u32, u32),

    /// Print a JSON summary on stdout (segments, areas, the persistence of every count).
    #[arg(long)]
    pub json: bool,

    /// No progress display on stderr and no confirmation on stdout.
    #[arg(short, long)]
    pub quiet: bool,
}

/// `--min-area`: a number in `[0, 1)`.
fn area_fraction(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if (0.0..1.0).contains(&x) => Ok(x),
        _ => Err(format!("`{text}` is not a fraction in [0, 1)")),
    }
}

/// The kinds of `--out`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Output {
    Seg,
    Ply,
    Png,
}

/// `--out`'s kind, or a usage error (exit code 2) for another extension.
fn output(args: &SegmentArgs) -> Result<Output, CliError> {
    [
        ("seg", Output::Seg),
        ("ply", Output::Ply),
        ("png", Output::Png),
    ]
    .into_iter()
    .find(|(extension, _)| has_extension(&args.out, extension))
    .map(|(_, kind)| kind)
    .ok_or_else(|| {
        CliError::usage(
            ErrorKind::ValueValidation,
            format!(
                "--out {}: expected a .seg, .ply or .png file name",
                args.out.display()
            ),
        )
    })
}

/// The consensus options of the command line, checked (usage errors, exit code 2).
fn consensus_options(args: &SegmentArgs) -> Result<ConsensusOptions, CliError> {
    if args.min_clusters < 2 || args.max_clusters < args.min_clusters {
        return Err(CliError::usage(
            ErrorKind::ValueValidation,
            format!(
                "--min-clusters {} --max-clusters {}: need 2 ≤ min ≤ max",
                args.min_clusters, args.max_clusters
            ),
        ));
    }
    Ok(ConsensusOptions {
        trials: args.trials,
        min_clusters: args.min_clusters,
        max_clusters: args.max_clusters,
        min_area_fraction: args.min_area,
        segments: args.segments,
        seed: args.solve.seed,
        ..ConsensusOptions::default()
    })
}

/// The `--json` summary.
#[derive(Debug, Serialize)]
struct Summary<'a> {
    mesh: &'a str,
    /// The operator and solver options, under the keys of `dirac spectrum --json` (`seed`
    /// is also the k-means trials' seed).
    #[serde(flatten)]
    settings: RunSettings,
    faces: usize,
    segments: usize,
    /// Area of every segment, and as a fraction of the surface.
    areas: Vec<f64>,
    area_fractions: Vec<f64>,
    forced: bool,
    /// The threshold of the level used and the run of levels it lies in.
    threshold: f64,
    run: RunSummary,
    runs: Vec<RunSummary>,
    levels: Vec<LevelSummary>,
    trials: usize,
    min_clusters: usize,
    max_clusters: usize,
    min_area: f64,
    out: String,
    preparation: &'a PreparationReport,
}

#[derive(Debug, Serialize)]
struct RunSummary {
    segments: usize,
    lowest: f64,
    highest: f64,
    persistence: f64,
}

impl From<Run> for RunSummary {
    fn from(run: Run) -> Self {
        Self {
            segments: run.segments,
            lowest: run.lowest,
            highest: run.highest,
            persistence: run.persistence(),
        }
    }
}

#[derive(Debug, Serialize)]
struct LevelSummary {
    threshold: f64,
    segments: usize,
}

impl From<&Level> for LevelSummary {
    fn from(level: &Level) -> Self {
        Self {
            threshold: level.threshold,
            segments: level.segments,
        }
    }
}

/// Runs `dirac segment`: solves, segments, writes `--out`; a solve that did not converge
/// writes nothing ([`CliError::NotConverged`], exit code 3).
pub fn run(args: &SegmentArgs) -> Result<(), CliError> {
    let options = args.solve.options();
    let kind = output(args)?;
    let consensus = consensus_options(args)?;
    let PreparedMesh {
        mesh, name, report, ..
    } = args
        .solve
        .problem
        .preparation
        .load(args.mesh.as_deref(), args.quiet)?;
    let solved = solve(&mesh, None, &name, &options, args.quiet)?;
    solved.check_converged(&name, options.k, "nothing written")?;
    let modes = Modes::from_spectrum(&solved.spectrum);
    let table = modes
        .and_then(|modes| segmentation_descriptor(&modes))
        .map_err(|source| CliError::Descriptor {
            mesh: name.clone(),
            source,
        })?;
    let segmentation = segment_by_descriptor(&mesh, &table, &consensus).map_err(|source| {
        CliError::Segmentation {
            mesh: name.clone(),
            source,
        }
    })?;

    write_output(args, kind, &mesh, &name, &segmentation)?;
    let s = segmentation.segment_count();
    if args.json {
        let total: f64 = segmentation.areas.iter().sum();
        let summary = Summary {
            mesh: &name,
            settings: RunSettings::new(&args.solve, &options),
            faces: mesh.face_count(),
            segments: s,
            areas: segmentation.areas.clone(),
            area_fractions: segmentation.areas.iter().map(|a| a / total).collect(),
            forced: segmentation.forced,
            threshold: segmentation.threshold,
            run: segmentation.run().into(),
            runs: segmentation.runs.iter().map(|&r| r.into()).collect(),
            levels: segmentation.levels.iter().map(Into::into).collect(),
            trials: consensus.trials,
            min_clusters: consensus.min_clusters,
            max_clusters: consensus.max_clusters,
            min_area: consensus.min_area_fraction,
            out: args.out.display().to_string(),
            preparation: &report,
        };
        let mut out = io::stdout().lock();
        serde_json::to_writer_pretty(&mut out, &summary)
            .map_err(io::Error::from)
            .and_then(|()| writeln!(out))
            .and_then(|()| out.flush())
            .map_err(CliError::Stdout)?;
    } else if !args.quiet {
        let run = segmentation.run();
        let how = if segmentation.forced {
            format!("forced, from the level θ = {}", segmentation.threshold)
        } else {
            format!(
                "θ = {}, the count of {} levels θ ∈ ({}, {}]",
                segmentation.threshold,
                (run.persistence() * consensus.trials as f64).round(),
                run.lowest,
                run.highest
            )
        };
        tell(format_args!(
            "wrote {}: {s} segment(s) of {name} ({how})",
            args.out.display()
        ));
    }
    Ok(())
}

/// Writes the segmentation as `--out` asks.
fn write_output(
    args: &SegmentArgs,
    kind: Output,
    mesh: &TriMesh,
    name: &str,
    segmentation: &ConsensusSegmentation,
) -> Result<(), CliError> {
    let labels = &segmentation.labels;
    match kind {
        Output::Seg => {
            let path = &args.out;
            File::create(path)
                .and_then(|file| write_seg(labels, file))
                .map_err(|source| CliError::Io {
                    path: path.clone(),
                    source,
                })?;
        }
        Output::Ply => {
            let colours: Vec<[u8; 3]> = labels.iter().map(|&l| segment_colour(l)).collect();
            let options = PlyWriteOptions {
                face_colors: Some(&colours),
                ..PlyWriteOptions::default()
            };
            write_ply(mesh, &args.out, &options)?;
        }
        Output::Png => {
            let (width, height) = args.size;
            let options = RenderOptions {
                width,
                height,
                view: args.view,
                projection: Projection::Perspective,
                ..RenderOptions::default()
            };
            // The file name, not the whole path, fits a small picture.
            let short = Path::new(name)
                .file_name()
                .map_or(name.into(), |file| file.to_string_lossy());
            let title = format!(
                "{short}: {} segments, {}",
                segmentation.segment_count(),
                args.solve.problem.operator
            );
            render_segments_png(mesh, labels, &title, &options, &args.out)?;
        }
    }
    Ok(())
}
