//! Experiment 5, paper §6.2 and Fig. 11: consensus segmentation
//! ([`dirac::segmentation::consensus`]) of the segmentation descriptor `|φ_i|/√|λ_i|` under
//! several operators with identical parameters, scored against the human segmentations of the
//! Princeton segmentation benchmark ([`dirac::segmentation::evaluation`]).
//!
//! The models are `psb_<id>.off` in a directory with their human segmentations
//! `seg/psb_<id>_<j>.seg` (`j = 0, 1, …`), read as they are (no repair: a repair could renumber
//! faces, and the `.seg` files refer to the file's faces).

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use dirac::TriMesh;
use dirac::descriptors::{Modes, segmentation_descriptor};
use dirac::io::read_mesh;
use dirac::segmentation::consensus::{
    ConsensusOptions, ConsensusSegmentation, segment_by_descriptor,
};
use dirac::segmentation::evaluation::{Scores, SegmentationEvaluator};
use dirac::segmentation::seg_file::read_seg_file;
use dirac::spectrum::{Operator, SpectrumOptions, spectrum};

use crate::ExperimentError;
use crate::spectra::TOLERANCE;

/// A benchmark model: its mesh and human segmentations.
#[derive(Debug, Clone)]
pub struct BenchmarkModel {
    /// The model's number (`psb_<id>.off`).
    pub id: u32,
    /// The mesh file.
    pub path: PathBuf,
    /// The mesh.
    pub mesh: TriMesh,
    /// The human segmentations, one label per face each.
    pub references: Vec<Vec<usize>>,
}

/// Every `psb_<id>.off` in `dir` (by increasing id) with its human segmentations
/// `seg/psb_<id>_<j>.seg` for `j = 0, 1, …` until one is missing. A model without any is an
/// error, as is a mesh that does not read as valid.
pub fn benchmark_models(dir: &Path) -> Result<Vec<BenchmarkModel>, ExperimentError> {
    let mut ids: Vec<u32> = fs::read_dir(dir)?
        .filter_map(|entry| {
            let name = entry.ok()?.file_name().into_string().ok()?;
            name.strip_prefix("psb_")?
                .strip_suffix(".off")?
                .parse()
                .ok()
        })
        .collect();
    ids.sort_unstable();
    ids.into_iter()
        .map(|id| {
            let path = dir.join(format!("psb_{id}.off"));
            let mesh = read_mesh(&path)?;
            let references: Vec<Vec<usize>> = (0..)
                .map(|j| dir.join("seg").join(format!("psb_{id}_{j}.seg")))
                .take_while(|seg| seg.exists())
                .map(|seg| read_seg_file(&seg, mesh.face_count()))
                .collect::<Result<_, _>>()?;
            if references.is_empty() {
                return Err(ExperimentError::Usage(format!(
                    "{}: no human segmentation seg/psb_{id}_0.seg",
                    dir.display()
                )));
            }
            Ok(BenchmarkModel {
                id,
                path,
                mesh,
                references,
            })
        })
        .collect()
}

/// The consensus segmentation of `mesh` (called `index` in errors) from the `k` eigenpairs of
/// `operator`.
pub fn segment(
    mesh: &TriMesh,
    index: usize,
    operator: Operator,
    k: usize,
    options: &ConsensusOptions,
) -> Result<ConsensusSegmentation, ExperimentError> {
    let mut spectrum_options = SpectrumOptions::new(operator, k);
    spectrum_options.tolerance = TOLERANCE;
    let spectrum =
        spectrum(mesh, &spectrum_options).map_err(|source| ExperimentError::Spectrum {
            operator,
            mesh: index,
            source,
        })?;
    let table = segmentation_descriptor(&Modes::from_spectrum(&spectrum)?)?;
    Ok(segment_by_descriptor(mesh, &table, options)?)
}

/// One model's result under one operator.
#[derive(Debug, Clone)]
pub struct ModelResult {
    /// The model's number.
    pub id: u32,
    /// The segmentation.
    pub segmentation: ConsensusSegmentation,
    /// Its mean scores over the model's human segmentations.
    pub scores: Scores,
    /// Seconds for the spectrum and the segmentation.
    pub seconds: f64,
}

/// Segments every model with `operator` and scores it against its humans.
pub fn run_operator(
    models: &[BenchmarkModel],
    operator: Operator,
    k: usize,
    options: &ConsensusOptions,
) -> Result<Vec<ModelResult>, ExperimentError> {
    models
        .iter()
        .map(|model| {
            let start = Instant::now();
            let segmentation = segment(&model.mesh, model.id as usize, operator, k, options)?;
            let seconds = start.elapsed().as_secs_f64();
            let evaluator = SegmentationEvaluator::new(&model.mesh)?;
            let scores = evaluator
                .scores_against_references(&segmentation.labels, &model.references)?
                .mean;
            Ok(ModelResult {
                id: model.id,
                segmentation,
                scores,
                seconds,
            })
        })
        .collect()
}

/// The benchmark's four summary numbers, means over models: Cut Discrepancy (over the models
/// where it is defined), GCE, Hamming distance and `1 − RI`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeanScores {
    /// Cut Discrepancy.
    pub cut_discrepancy: f64,
    /// Global Consistency Error.
    pub consistency: f64,
    /// Hamming distance.
    pub hamming: f64,
    /// Rand Index error `1 − RI`.
    pub rand: f64,
}

impl MeanScores {
    /// The means of `results`.
    pub fn of(results: &[ModelResult]) -> Self {
        let mean = |values: Vec<f64>| values.iter().sum::<f64>() / values.len().max(1) as f64;
        Self {
            cut_discrepancy: mean(
                results
                    .iter()
                    .filter_map(|r| r.scores.cut_discrepancy)
                    .collect(),
            ),
            consistency: mean(
                results
                    .iter()
                    .map(|r| r.scores.consistency.global)
                    .collect(),
            ),
            hamming: mean(results.iter().map(|r| r.scores.hamming.distance).collect()),
            rand: mean(results.iter().map(|r| r.scores.rand_index_error).collect()),
        }
    }
}

/// The paper's numbers (§6.2), in the order Cut Discrepancy, GCE, Hamming, Rand: human
/// segmentations against each other, the paper's Dirac, and RandCut (the benchmark's best).
pub const PAPER: [(&str, MeanScores); 3] = [
    (
        "paper: Human",
        MeanScores {
            cut_discrepancy: 0.17,
            consistency: 0.07,
            hamming: 0.10,
            rand: 0.10,
        },
    ),
    (
        "paper: Dirac",
        MeanScores {
            cut_discrepancy: 0.40,
            consistency: 0.19,
            hamming: 0.23,
            rand: 0.24,
        },
    ),
    (
        "paper: RandCut",
        MeanScores {
            cut_discrepancy: 0.26,
            consistency: 0.13,
            hamming: 0.14,
            rand: 0.15,
        },
    ),
];
