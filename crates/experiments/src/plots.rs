//! The charts the examples write (through `dirac_cli::plot`): mean spectrum per class and the
//! 2-D embedding of the spectral distances, one file per operator; a score per shape against
//! its thresholds (Fig. 9).

use std::fs;
use std::path::{Path, PathBuf};

use dirac::spectrum::Operator;
use dirac_cli::plot::{
    Axes, Corner, Level, PointGroup, Series, plot_points, plot_points_with_levels, plot_spectra,
};
use dirac_cli::render::format_value;

use crate::ExperimentError;
use crate::embedding::{TsneOptions, tsne};
use crate::metrics::distance_matrix;
use crate::spectra::OperatorSpectra;

/// `dir/<prefix>-<operator>.png` with the operator as the command line writes it, its `:` as
/// `-` (`family:0.5` → `family-0.5`).
pub fn plot_path(dir: &Path, prefix: &str, operator: Operator) -> PathBuf {
    let slug = operator.to_string().replace(':', "-");
    dir.join(format!("{prefix}-{slug}.png"))
}

/// The mean spectrum of each class (entrywise over its members), labelled by class name.
pub fn class_means(spectra: &[Vec<f64>], labels: &[usize], names: &[String]) -> Vec<Series> {
    names
        .iter()
        .enumerate()
        .filter_map(|(class, name)| {
            let members: Vec<&Vec<f64>> = spectra
                .iter()
                .zip(labels)
                .filter(|(_, l)| **l == class)
                .map(|(s, _)| s)
                .collect();
            let length = members.iter().map(|s| s.len()).min()?;
            let values = (0..length)
                .map(|i| members.iter().map(|s| s[i]).sum::<f64>() / members.len() as f64)
                .collect();
            Some(Series {
                label: name.clone(),
                values,
            })
        })
        .collect()
}

/// Writes, for every operator, `spectra-<operator>.png` (mean spectrum per class) into `dir`
/// (created if needed); returns the files written.
pub fn write_spectra_plots(
    tables: &[OperatorSpectra],
    labels: &[usize],
    names: &[String],
    dir: &Path,
) -> Result<Vec<PathBuf>, ExperimentError> {
    for_each_operator(tables, dir, "spectra", |table, path| {
        plot_spectra(
            &class_means(&table.spectra, labels, names),
            &format!("{}: mean spectrum per class", table.operator),
            path,
        )?;
        Ok(())
    })
}

/// Writes, for every operator, `embedding-<operator>.png` (t-SNE of the Euclidean distances
/// between spectra with [`TsneOptions::for_points`], one colour per class, as in paper Fig. 10)
/// into `dir`; returns the files written.
pub fn write_embedding_plots(
    tables: &[OperatorSpectra],
    labels: &[usize],
    names: &[String],
    dir: &Path,
) -> Result<Vec<PathBuf>, ExperimentError> {
    for_each_operator(tables, dir, "embedding", |table, path| {
        let embedded = tsne(
            &distance_matrix(&table.spectra),
            &TsneOptions::for_points(table.spectra.len()),
        )?;
        let groups: Vec<PointGroup> = names
            .iter()
            .enumerate()
            .map(|(class, name)| PointGroup {
                label: name.clone(),
                points: embedded
                    .iter()
                    .zip(labels)
                    .filter(|(_, l)| **l == class)
                    .map(|(p, _)| *p)
                    .collect(),
            })
            .collect();
        plot_points(
            &groups,
            &format!("{}: t-SNE of spectral distances", table.operator),
            path,
        )?;
        Ok(())
    })
}

/// One score per shape on a logarithmic axis against the shape's rank (1 = smallest score,
/// ties in the given order), one colour per class (`labels[i]` indexes `names`), with the
/// horizontal `levels` (thresholds), into `path`. A logarithmic axis cannot show 0: zero
/// scores are drawn at a floor a tenth of the smallest positive score or level, and the
/// class's legend entry says how many. Scores must be finite and nonnegative.
pub fn write_score_plot(
    scores: &[f64],
    labels: &[usize],
    names: &[String],
    levels: &[Level],
    (title, y_description): (&str, &str),
    path: &Path,
) -> Result<(), ExperimentError> {
    let mut order: Vec<usize> = (0..scores.len()).collect();
    order.sort_by(|&a, &b| scores[a].total_cmp(&scores[b]));
    let smallest = (scores.iter().chain(levels.iter().map(|l| &l.value)))
        .copied()
        .filter(|&v| v > 0.0)
        .fold(f64::INFINITY, f64::min);
    let floor = if smallest.is_finite() {
        smallest / 10.0
    } else {
        1.0
    };
    let groups: Vec<PointGroup> = (names.iter().enumerate())
        .map(|(class, name)| {
            let members = || (order.iter().enumerate()).filter(|&(_, &i)| labels[i] == class);
            let zeros = members().filter(|&(_, &i)| scores[i] == 0.0).count();
            let label = match zeros {
                0 => name.clone(),
                _ => format!(
                    "{name} ({zeros} with score 0, drawn at {})",
                    format_value(floor)
                ),
            };
            let points = members()
                .map(|(rank, &i)| {
                    let y = if scores[i] == 0.0 { floor } else { scores[i] };
                    ((rank + 1) as f64, y)
                })
                .collect();
            PointGroup { label, points }
        })
        .collect();
    let axes = Axes {
        x: "shape, by increasing score",
        y: y_description,
        log_y: true,
        // Sorted ascending, the points leave the lower right free.
        legend: Corner::LowerRight,
    };
    if let Some(dir) = path.parent() {
        fs::create_dir_all(dir)?;
    }
    plot_points_with_levels(&groups, levels, axes, title, path)?;
    Ok(())
}

/// Creates `dir` and calls `draw` with every operator's table and its file
/// `<prefix>-<operator>.png`; returns the files.
fn for_each_operator(
    tables: &[OperatorSpectra],
    dir: &Path,
    prefix: &str,
    mut draw: impl FnMut(&OperatorSpectra, &Path) -> Result<(), ExperimentError>,
) -> Result<Vec<PathBuf>, ExperimentError> {
    fs::create_dir_all(dir)?;
    tables
        .iter()
        .map(|table| {
            let path = plot_path(dir, prefix, table.operator);
            draw(table, &path)?;
            Ok(path)
        })
        .collect()
}
