//! `dirac segment-eval MESH RESULT.seg HUMAN.seg…`: the Princeton segmentation benchmark's
//! error measures of a segmentation against reference segmentations of the same mesh
//! (`dirac::segmentation::evaluation`), their mean (the benchmark's per-model score) and each.

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use clap::Args;
use dirac::io::read_mesh;
use dirac::segmentation::evaluation::{Scores, SegmentationEvaluator};
use dirac::segmentation::seg_file::read_seg_file;
use serde::Serialize;

use crate::common::error::CliError;

/// What `dirac segment-eval --help` shows after the options.
pub const AFTER_HELP: &str = "\
Measures (Chen, Golovinskiy, Funkhouser 2009, as the benchmark's segEval computes them; all
are errors, 0 for identical segmentations; docs/MATH.md, \"Segmentation benchmark measures\"):
  CD       Cut Discrepancy: mean edge-path distance between the two segmentations' cut
           vertices over the mean radius of the surface (undefined if one has no cut)
  Hamming  area-weighted Hamming distance (Rm + Rf)/2, Rm the missing rate, Rf the false
           alarm rate, with the references as ground truth
  Rand     1 − Rand index over pairs of faces
  GCE/LCE  Global and Local Consistency Error over faces

The mesh is read as it is: there is no --repair or --component, because both renumber or
drop faces, and line i of a .seg file names the segment of face i of the mesh file. A mesh
that needs repair was segmented as repaired; evaluate on the repaired file (`dirac repair`).

Exit codes:
  0  success
  1  the mesh or a .seg file cannot be read, is malformed, or has a number of lines other
     than the mesh's number of faces (the message names both files and both numbers)
  2  usage error (bad or missing arguments)

Examples:
  dirac segment-eval psb_5.off psb_5.seg human/psb_5_*.seg
  dirac segment-eval chair.off chair.seg chair_human.seg --json";

/// Arguments of `dirac segment-eval`.
#[derive(Debug, Args)]
pub struct SegmentEvalArgs {
    /// Mesh file (.obj, .off, .ply or .stl), read without repair.
    pub mesh: PathBuf,

    /// The segmentation to score: a .seg file, one segment number per face.
    pub result: PathBuf,

    /// Reference segmentations (.seg files) of the same mesh, e.g. the benchmark's human ones.
    #[arg(required = true, num_args = 1.., value_name = "REFERENCE")]
    pub references: Vec<PathBuf>,

    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// What `dirac segment-eval --json` prints.
#[derive(Serialize)]
struct EvaluationOutput {
    mesh: String,
    faces: usize,
    result: String,
    result_segments: usize,
    /// The mean over the references (`cut_discrepancy` over `cut_discrepancy_references`).
    mean: Scores,
    cut_discrepancy_references: usize,
    references: Vec<ReferenceOutput>,
}

/// One reference's line of the output.
#[derive(Serialize)]
struct ReferenceOutput {
    file: String,
    segments: usize,
    scores: Scores,
}

/// Runs `dirac segment-eval`.
pub fn run(args: &SegmentEvalArgs) -> Result<(), CliError> {
    let mesh = read_mesh(&args.mesh)?;
    let mesh_name = args.mesh.display().to_string();
    let faces = mesh.face_count();
    let read = |path: &Path| {
        read_seg_file(path, faces).map_err(|source| CliError::SegFile {
            mesh: mesh_name.clone(),
            source,
        })
    };
    let result = read(&args.result)?;
    let references = args
        .references
        .iter()
        .map(|path| read(path))
        .collect::<Result<Vec<_>, _>>()?;
    let evaluation = |source| CliError::Evaluation {
        mesh: mesh_name.clone(),
        source,
    };
    let evaluator = SegmentationEvaluator::new(&mesh).map_err(evaluation)?;
    let model = evaluator
        .scores_against_references(&result, &references)
        .map_err(evaluation)?;
    let output = EvaluationOutput {
        mesh: mesh_name.clone(),
        faces,
        result: args.result.display().to_string(),
        result_segments: segment_count(&result),
        mean: model.mean,
        cut_discrepancy_references: model.cut_discrepancy_references,
        references: args
            .references
            .iter()
            .zip(&references)
            .zip(model.per_reference)
            .map(|((path, labels), scores)| ReferenceOutput {
                file: path.display().to_string(),
                segments: segment_count(labels),
                scores,
            })
            .collect(),
    };
    let mut out = io::stdout().lock();
    if args.json {
        serde_json::to_writer_pretty(&mut out, &output)
            .map_err(io::Error::from)
            .and_then(|()| writeln!(out))
    } else {
        write_table(&output, &mut out)
    }
    .and_then(|()| out.flush())
    .map_err(CliError::Stdout)
}

/// The number of distinct segment numbers.
fn segment_count(labels: &[usize]) -> usize {
    let mut sorted = labels.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    sorted.len()
}

/// The human-readable table: the mean first, then one row per reference.
fn write_table(output: &EvaluationOutput, out: &mut impl Write) -> io::Result<()> {
    writeln!(out, "mesh:   {} ({} faces)", output.mesh, output.faces)?;
    writeln!(
        out,
        "result: {} ({} segments)",
        output.result, output.result_segments
    )?;
    writeln!(out)?;
    let mut rows = vec![(
        format!(
            "mean of {} (CD of {})",
            output.references.len(),
            output.cut_discrepancy_references
        ),
        &output.mean,
    )];
    rows.extend(output.references.iter().map(|reference| {
        (
            format!("{} ({} segments)", reference.file, reference.segments),
            &reference.scores,
        )
    }));
    let width = rows
        .iter()
        .map(|(label, _)| label.chars().count())
        .max()
        .unwrap_or(0);
    writeln!(
        out,
        "{:<width$}  {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8}",
        "reference", "CD", "Hamming", "Rm", "Rf", "Rand", "GCE", "LCE"
    )?;
    for (label, scores) in rows {
        write_row(out, &label, scores, width)?;
    }
    Ok(())
}

fn write_row(out: &mut impl Write, label: &str, scores: &Scores, width: usize) -> io::Result<()> {
    let cut_discrepancy = match scores.cut_discrepancy {
        Some(value) => format!("{value:.4}"),
        None => "undef.".to_string(),
    };
    writeln!(
        out,
        "{label:<width$}  {cut_discrepancy:>8} {:>8.4} {:>8.4} {:>8.4} {:>8.4} {:>8.4} {:>8.4}",
        scores.hamming.distance,
        scores.hamming.missing_rate,
        scores.hamming.false_alarm_rate,
        scores.rand_index_error,
        scores.consistency.global,
        scores.consistency.local,
    )
}
