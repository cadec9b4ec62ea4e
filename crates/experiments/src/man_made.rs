//! Experiment 5 (paper §6.1, Fig. 9): man-made versus organic shapes from the spectrum of the
//! relative Dirac operator `D_N` at unit area.
//!
//! **The data.** Every mesh of a folder listed in its `labels.csv` (columns `file`, `category`,
//! `label`; label `man-made` or `organic`), scaled to total area 1. For each, one solve gives
//! the [`SPECTRUM_LENGTH`] eigenvalues of smallest `|λ|` *outside* the exact kernel (flat
//! vertices and constants, docs/MATH.md "The exact kernel") and the kernel's dimension `d`.
//! The first `k` eigenvalues *with* the kernel listed are then `min(d, k)` zeros followed by
//! the first `k − min(d, k)` nonzero ones ([`with_kernel_zeros`]): exactly what
//! [`dirac::spectrum()`] returns with `include_kernel: true` (it lists the kernel, then solves
//! for the rest), so one solve per mesh serves both lists.
//!
//! **The classifiers**, all evaluated leave-one-out (LOO) where they have a parameter:
//! * the paper's rule: score `s = (1/k) Σ_{i<k} λ_i²` over the first `k = 25` eigenvalues
//!   ([`mean_square`]), man-made when `s` is *below* a threshold (man-made shapes have many
//!   small eigenvalues, Fig. 9). The paper's threshold 1 is applied as is, and a threshold is
//!   learnt by [`crate::threshold::leave_one_out_threshold`]; both with and without the kernel's zeros;
//! * the baseline: the share of flat vertices, man-made when *above* a learnt threshold;
//! * nearest neighbour on `log |λ_i|` over the first [`SPECTRUM_LENGTH`] nonzero eigenvalues
//!   ([`log_magnitudes`], LOO 1-NN of [`crate::metrics`]): the mean of squares is dominated by
//!   the largest of its eigenvalues, while the logarithm weighs the growth of the whole
//!   spectrum, where flat faces and sharp edges show as a spread of small and large `|λ|`,
//!   equally at every index, and is blind to the overall scale that the unit-area
//!   normalisation fixes anyway.

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::Instant;

use dirac::io::read_mesh;
use dirac::spectrum::{KernelSummary, Normalization, SolverBackend};
use dirac_cli::plot::Level;

use crate::ExperimentError;
use crate::metrics::{distance_matrix, leave_one_out_accuracy, nearest_other};
use crate::plots::write_score_plot;
use crate::spectra::{RELATIVE_DIRAC, experiment_options, solve};
use crate::threshold::{
    LeaveOneOut, Side, best_threshold, leave_one_out_threshold, threshold_accuracy,
};

/// Eigenvalues in the paper's score (§6.1: "the first 25 eigenvalues").
pub const PAPER_COUNT: usize = 25;

/// The paper's threshold on the score (§6.1: "thresholding at a value of 1").
pub const PAPER_THRESHOLD: f64 = 1.0;

/// Nonzero eigenvalues computed per mesh (as in the paper's other whole-shape experiments,
/// Fig. 8): the input of the nearest-neighbour classifier; the first [`PAPER_COUNT`] of them
/// are the paper's.
pub const SPECTRUM_LENGTH: usize = 60;

/// The name of the label file in a data folder.
pub const LABELS_FILE: &str = "labels.csv";

/// The two classes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Label {
    /// Made by people (flat pieces, sharp edges).
    ManMade,
    /// Natural shapes (curved everywhere).
    Organic,
}

impl Label {
    /// Both labels, in the order of the reports.
    pub const ALL: [Label; 2] = [Label::ManMade, Label::Organic];

    /// The label as `labels.csv` writes it.
    pub fn name(self) -> &'static str {
        match self {
            Label::ManMade => "man-made",
            Label::Organic => "organic",
        }
    }
}

impl fmt::Display for Label {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Label {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        Label::ALL
            .into_iter()
            .find(|l| l.name() == text)
            .ok_or_else(|| format!("unknown label {text:?} (expected man-made or organic)"))
    }
}

/// One row of `labels.csv`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LabelledFile {
    /// The mesh's file name, relative to the folder.
    pub file: String,
    /// The benchmark's category (Cup, Human, …).
    pub category: String,
    /// Man-made or organic.
    pub label: Label,
}

/// The rows of `dir/labels.csv` (a header `file,category,label`, then one row per mesh), in
/// file order.
pub fn read_labels(dir: &Path) -> Result<Vec<LabelledFile>, ExperimentError> {
    let path = dir.join(LABELS_FILE);
    let error = |line: u64, message: String| ExperimentError::Labels {
        path: path.clone(),
        line,
        message,
    };
    let file = std::fs::File::open(&path).map_err(|e| ExperimentError::InFile {
        path: path.clone(),
        source: Box::new(e.into()),
    })?;
    let mut reader = csv::Reader::from_reader(file);
    let headers = reader
        .headers()
        .map_err(|e| error(1, e.to_string()))?
        .clone();
    let column = |name: &str| {
        headers.iter().position(|h| h == name).ok_or_else(|| {
            error(
                1,
                format!("no column {name:?} (the header must name file, category and label)"),
            )
        })
    };
    let (file, category, label) = (column("file")?, column("category")?, column("label")?);
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            error(line, e.to_string())
        })?;
        let line = record.position().map_or(0, |p| p.line());
        let field = |index: usize| record.get(index).unwrap_or("").trim().to_string();
        rows.push(LabelledFile {
            file: field(file),
            category: field(category),
            label: field(label)
                .parse()
                .map_err(|message| error(line, message))?,
        });
    }
    if rows.is_empty() {
        return Err(error(1, "no meshes listed".into()));
    }
    Ok(rows)
}

/// What one solve tells about one mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeSpectrum {
    /// The labels file's row.
    pub entry: LabelledFile,
    /// Vertices of the mesh.
    pub vertices: usize,
    /// Total area of the mesh as stored (before the unit-area scaling).
    pub area: f64,
    /// The exact kernel of `D_N`: its dimension, flat vertices and constants.
    pub kernel: KernelSummary,
    /// The eigenvalues of smallest `|λ|` outside the kernel, signed, ordered by `|λ|`, at unit
    /// area.
    pub nonzero: Vec<f64>,
    /// Wall-clock seconds of reading and solving.
    pub seconds: f64,
}

impl ShapeSpectrum {
    /// The first `k` eigenvalues with the kernel's zeros listed ([`with_kernel_zeros`]).
    pub fn with_kernel(&self, k: usize) -> Vec<f64> {
        with_kernel_zeros(&self.nonzero, self.kernel.dimension, k)
    }

    /// The first `k` eigenvalues outside the kernel (fewer if fewer were computed).
    pub fn without_kernel(&self, k: usize) -> &[f64] {
        &self.nonzero[..k.min(self.nonzero.len())]
    }

    /// A score `mean λ²` at unit area converted to the mesh's stored scale: scaling positions
    /// by `s` multiplies the eigenvalues of `D_N` by `1/s²`, so `λ_stored = λ_unit / area` and
    /// the score is divided by `area²`.
    pub fn at_stored_scale(&self, unit_area_score: f64) -> f64 {
        unit_area_score / (self.area * self.area)
    }

    /// Flat vertices as a share of all vertices.
    pub fn flat_fraction(&self) -> f64 {
        self.kernel.flat_vertices as f64 / self.vertices as f64
    }
}

/// The first `k` eigenvalues of smallest `|λ|` of an operator whose kernel has dimension
/// `kernel_dimension`, from its eigenvalues outside the kernel (`nonzero`, by `|λ|`):
/// `min(d, k)` zeros, then `nonzero[..k − min(d, k)]`. Shorter than `k` only when `nonzero`
/// is.
pub fn with_kernel_zeros(nonzero: &[f64], kernel_dimension: usize, k: usize) -> Vec<f64> {
    let zeros = kernel_dimension.min(k);
    let mut values = vec![0.0; zeros];
    values.extend(nonzero.iter().take(k - zeros));
    values
}

/// Reads every mesh of `entries` from `dir` and computes its [`SPECTRUM_LENGTH`] nonzero
/// eigenvalues of `D_N` (unit area, kernel not listed) with `backend`; `progress` is called
/// after each mesh.
pub fn compute_spectra(
    dir: &Path,
    entries: &[LabelledFile],
    backend: SolverBackend,
    progress: &mut dyn FnMut(&ShapeSpectrum),
) -> Result<Vec<ShapeSpectrum>, ExperimentError> {
    let mut options = experiment_options(
        RELATIVE_DIRAC,
        SPECTRUM_LENGTH,
        backend,
        Normalization::UnitArea,
    );
    options.include_kernel = false;
    entries
        .iter()
        .enumerate()
        .map(|(index, entry)| {
            let start = Instant::now();
            let path: PathBuf = dir.join(&entry.file);
            // A read error names its file already; a failed solve is named by it here.
            let mesh = read_mesh(&path)?;
            let result = solve(&mesh, &options, index).map_err(|e| ExperimentError::InFile {
                path,
                source: Box::new(e),
            })?;
            let shape = ShapeSpectrum {
                entry: entry.clone(),
                vertices: mesh.vertex_count(),
                // Positions were scaled by 1/√area.
                area: result.scale.powi(-2),
                kernel: result.kernel,
                nonzero: result.eigenvalues,
                seconds: start.elapsed().as_secs_f64(),
            };
            progress(&shape);
            Ok(shape)
        })
        .collect()
}

/// The paper's score `(1/k) Σ λ_i²` of the `k` given eigenvalues (NaN for none).
pub fn mean_square(values: &[f64]) -> f64 {
    values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64
}

/// `log |λ_i|` of every eigenvalue (the nearest-neighbour features; `−∞` for a zero, so pass
/// eigenvalues outside the kernel).
pub fn log_magnitudes(values: &[f64]) -> Vec<f64> {
    values.iter().map(|v| v.abs().ln()).collect()
}

/// Leave-one-out 1-nearest-neighbour classification on the features `log |λ_i|` over the
/// first `k` nonzero eigenvalues of every shape (Euclidean distance, [`crate::metrics`]).
#[derive(Debug, Clone, PartialEq)]
pub struct NearestNeighbour {
    /// Eigenvalues per shape.
    pub k: usize,
    /// For each shape, the index of its nearest other shape.
    pub nearest: Vec<usize>,
    /// Share of shapes whose nearest other shape has their label.
    pub accuracy: f64,
}

impl NearestNeighbour {
    /// Classifies `shapes` by their first `k` nonzero eigenvalues (at least two shapes).
    pub fn new(shapes: &[ShapeSpectrum], k: usize) -> Self {
        let features: Vec<Vec<f64>> = shapes
            .iter()
            .map(|s| log_magnitudes(s.without_kernel(k)))
            .collect();
        let labels: Vec<usize> = shapes.iter().map(|s| s.entry.label as usize).collect();
        let distances = distance_matrix(&features);
        Self {
            k,
            nearest: (0..shapes.len())
                .map(|i| nearest_other(&distances, i).unwrap_or(i))
                .collect(),
            accuracy: leave_one_out_accuracy(&distances, &labels),
        }
    }
}

/// One score of every shape, classified by a threshold: the paper's fixed one (where it
/// applies) and one learnt leave-one-out.
#[derive(Debug, Clone, PartialEq)]
pub struct ThresholdClassifier {
    /// What the score is.
    pub name: String,
    /// The score of each shape.
    pub scores: Vec<f64>,
    /// Man-made below or above the threshold.
    pub side: Side,
    /// The accuracy of [`PAPER_THRESHOLD`], for the paper's score.
    pub paper_threshold_accuracy: Option<f64>,
    /// The accuracy of [`PAPER_THRESHOLD`] on the score at the meshes' stored scale
    /// ([`ShapeSpectrum::at_stored_scale`]), for the paper's score.
    pub stored_scale_accuracy: Option<f64>,
    /// The leave-one-out evaluation.
    pub leave_one_out: LeaveOneOut,
    /// The threshold learnt from all shapes.
    pub all_data_threshold: f64,
}

impl ThresholdClassifier {
    /// Evaluates `scores` (one per shape) against the shapes' labels.
    pub fn new(
        name: &str,
        shapes: &[ShapeSpectrum],
        scores: Vec<f64>,
        side: Side,
        paper_threshold: bool,
    ) -> Self {
        let positive: Vec<bool> = shapes
            .iter()
            .map(|s| s.entry.label == Label::ManMade)
            .collect();
        let stored: Vec<f64> = (shapes.iter().zip(&scores))
            .map(|(shape, &score)| shape.at_stored_scale(score))
            .collect();
        Self {
            name: name.to_string(),
            paper_threshold_accuracy: paper_threshold
                .then(|| threshold_accuracy(&scores, &positive, PAPER_THRESHOLD, side)),
            stored_scale_accuracy: paper_threshold
                .then(|| threshold_accuracy(&stored, &positive, PAPER_THRESHOLD, side)),
            leave_one_out: leave_one_out_threshold(&scores, &positive, side),
            all_data_threshold: best_threshold(&scores, &positive, side),
            side,
            scores,
        }
    }
}

/// Everything the experiment measures.
#[derive(Debug, Clone, PartialEq)]
pub struct ManMadeReport {
    /// The shapes and their spectra.
    pub shapes: Vec<ShapeSpectrum>,
    /// The paper's score without the kernel's zeros.
    pub without_kernel: ThresholdClassifier,
    /// The paper's score with the kernel's zeros.
    pub with_kernel: ThresholdClassifier,
    /// The flat-vertex share baseline.
    pub flat_fraction: ThresholdClassifier,
    /// LOO 1-NN on `log |λ|` for `k` = [`PAPER_COUNT`] and [`SPECTRUM_LENGTH`].
    pub nearest_neighbour: Vec<NearestNeighbour>,
}

impl ManMadeReport {
    /// Evaluates every classifier on `shapes`.
    pub fn new(shapes: Vec<ShapeSpectrum>) -> Self {
        let score = |values: &dyn Fn(&ShapeSpectrum) -> Vec<f64>| -> Vec<f64> {
            shapes.iter().map(|s| mean_square(&values(s))).collect()
        };
        let without = score(&|s| s.without_kernel(PAPER_COUNT).to_vec());
        let with = score(&|s| s.with_kernel(PAPER_COUNT));
        let flat = shapes.iter().map(ShapeSpectrum::flat_fraction).collect();
        Self {
            without_kernel: ThresholdClassifier::new(
                "mean λ², kernel excluded",
                &shapes,
                without,
                Side::Below,
                true,
            ),
            with_kernel: ThresholdClassifier::new(
                "mean λ², kernel included",
                &shapes,
                with,
                Side::Below,
                true,
            ),
            flat_fraction: ThresholdClassifier::new(
                "flat-vertex share",
                &shapes,
                flat,
                Side::Above,
                false,
            ),
            nearest_neighbour: [PAPER_COUNT, SPECTRUM_LENGTH]
                .into_iter()
                .map(|k| NearestNeighbour::new(&shapes, k))
                .collect(),
            shapes,
        }
    }

    /// The per-shape table (Markdown): file, category, label, vertices, stored area, kernel dimension and
    /// flat share, both scores, whether each threshold classifier got the shape right
    /// leave-one-out (✓/✗), the nearest other shape by `log |λ|` over [`SPECTRUM_LENGTH`]
    /// eigenvalues, seconds.
    pub fn shape_table(&self) -> String {
        let mut out = String::from(
            "| mesh | category | label | vertices | stored area | dim ker | flat share | \
             score, kernel excluded | score, kernel included | LOO right? excl. / incl. / flat \
             share | 1-NN (60) | seconds |\n\
             |---|---|---|---|---|---|---|---|---|---|---|---|\n",
        );
        let is_man_made = |i: usize| self.shapes[i].entry.label == Label::ManMade;
        let mark = |right: bool| if right { "✓" } else { "✗" };
        let verdict = |c: &ThresholdClassifier, i: usize| {
            mark(c.leave_one_out.predicted[i] == is_man_made(i))
        };
        let longest = self.nearest_neighbour.last();
        for (i, s) in self.shapes.iter().enumerate() {
            let nearest = longest.map_or(String::from("—"), |nn| {
                let j = nn.nearest[i];
                let right = self.shapes[j].entry.label == s.entry.label;
                format!("{} {}", self.shapes[j].entry.category, mark(right))
            });
            out.push_str(&format!(
                "| {} | {} | {} | {} | {:.3} | {} | {:.2}% | {:.1} | {:.1} | {} / {} / {} | {nearest} | {:.1} |\n",
                s.entry.file,
                s.entry.category,
                s.entry.label,
                s.vertices,
                s.area,
                s.kernel.dimension,
                100.0 * s.flat_fraction(),
                self.without_kernel.scores[i],
                self.with_kernel.scores[i],
                verdict(&self.without_kernel, i),
                verdict(&self.with_kernel, i),
                verdict(&self.flat_fraction, i),
                s.seconds,
            ));
        }
        out
    }

    /// The accuracy table (Markdown), with the paper's figures beside ours.
    pub fn accuracy_table(&self) -> String {
        let percent = |a: f64| {
            format!(
                "{:.1}% ({}/{})",
                100.0 * a,
                (a * self.shapes.len() as f64).round(),
                self.shapes.len()
            )
        };
        let mut out = String::from(
            "| classifier | accuracy | learnt threshold (all data; LOO range) |\n|---|---|---|\n",
        );
        for c in [&self.without_kernel, &self.with_kernel] {
            if let Some(a) = c.paper_threshold_accuracy {
                out.push_str(&format!(
                    "| {}, paper's threshold {PAPER_THRESHOLD} | {} | — |\n",
                    c.name,
                    percent(a)
                ));
            }
            if let Some(a) = c.stored_scale_accuracy {
                out.push_str(&format!(
                    "| {}, paper's threshold {PAPER_THRESHOLD} at the stored scale | {} | — |\n",
                    c.name,
                    percent(a)
                ));
            }
        }
        for c in [&self.without_kernel, &self.with_kernel, &self.flat_fraction] {
            let finite = c
                .leave_one_out
                .thresholds
                .iter()
                .copied()
                .filter(|t| t.is_finite());
            let (low, high) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), t| {
                (l.min(t), h.max(t))
            });
            out.push_str(&format!(
                "| {}, LOO threshold (man-made {}) | {} | {:.4} ({:.4} – {:.4}) |\n",
                c.name,
                match c.side {
                    Side::Below => "below",
                    Side::Above => "above",
                },
                percent(c.leave_one_out.accuracy),
                c.all_data_threshold,
                low,
                high
            ));
        }
        for nn in &self.nearest_neighbour {
            out.push_str(&format!(
                "| 1-NN on log \\|λ\\|, first {} nonzero (LOO) | {} | — |\n",
                nn.k,
                percent(nn.accuracy)
            ));
        }
        out.push_str("| paper: mean λ² of the first 25, threshold 1 | 95% | 1 |\n");
        out.push_str("| paper: D2 shape distribution + SVM | 88% | — |\n");
        out
    }

    /// The median of each score within each class (which side man-made is on).
    pub fn class_medians(&self) -> String {
        let mut out = String::new();
        for c in [&self.without_kernel, &self.with_kernel, &self.flat_fraction] {
            let medians: Vec<String> = Label::ALL
                .iter()
                .map(|&label| {
                    let mut members: Vec<f64> = (self.shapes.iter().zip(&c.scores))
                        .filter(|(s, _)| s.entry.label == label)
                        .map(|(_, &v)| v)
                        .collect();
                    members.sort_by(f64::total_cmp);
                    format!("{label} {:.4}", median(&members))
                })
                .collect();
            out.push_str(&format!("{}: median {}\n", c.name, medians.join(", ")));
        }
        out
    }
}

impl ThresholdClassifier {
    /// The horizontal lines of its chart: every distinct finite LOO threshold (with the number
    /// of folds that chose it) and, for the paper's score, [`PAPER_THRESHOLD`]. Infinite LOO
    /// thresholds (a fold that called everything one class) are named in the legend of none:
    /// the table reports them.
    pub fn levels(&self) -> Vec<Level> {
        let mut distinct: Vec<(f64, usize)> = Vec::new();
        for &t in self
            .leave_one_out
            .thresholds
            .iter()
            .filter(|t| t.is_finite())
        {
            match distinct.iter_mut().find(|(v, _)| *v == t) {
                Some((_, count)) => *count += 1,
                None => distinct.push((t, 1)),
            }
        }
        distinct.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut levels: Vec<Level> = distinct
            .into_iter()
            .map(|(value, folds)| Level {
                label: format!(
                    "LOO threshold {value:.1} ({folds} fold{})",
                    if folds == 1 { "" } else { "s" }
                ),
                value,
            })
            .collect();
        if self.paper_threshold_accuracy.is_some() {
            levels.push(Level {
                label: format!("paper's threshold {PAPER_THRESHOLD}"),
                value: PAPER_THRESHOLD,
            });
        }
        levels
    }
}

impl ManMadeReport {
    /// Writes the charts of both paper scores (Fig. 9: score per shape, log axis, coloured by
    /// label, thresholds marked) into `dir`: `man-made-vs-organic.png` (kernel excluded) and
    /// `man-made-vs-organic-with-kernel.png`; returns the files.
    pub fn write_plots(&self, dir: &Path) -> Result<Vec<PathBuf>, ExperimentError> {
        let labels: Vec<usize> = self.shapes.iter().map(|s| s.entry.label as usize).collect();
        let names: Vec<String> = Label::ALL.iter().map(|l| l.to_string()).collect();
        [
            (&self.without_kernel, "man-made-vs-organic.png"),
            (&self.with_kernel, "man-made-vs-organic-with-kernel.png"),
        ]
        .into_iter()
        .map(|(classifier, file)| {
            let path = dir.join(file);
            write_score_plot(
                &classifier.scores,
                &labels,
                &names,
                &classifier.levels(),
                (
                    &format!("relative Dirac, unit area: {}", classifier.name),
                    "mean of λ² over the first 25 eigenvalues",
                ),
                &path,
            )?;
            Ok(path)
        })
        .collect()
    }
}

/// The median of sorted values (NaN for none).
fn median(sorted: &[f64]) -> f64 {
    match sorted.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => sorted[n / 2],
        n => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
    }
}
