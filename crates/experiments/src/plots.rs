//! The charts the examples write (through `dirac_cli::plot`): mean spectrum per class and the
//! 2-D embedding of the spectral distances, one file per operator.

use std::fs;
use std::path::{Path, PathBuf};

use dirac::spectrum::Operator;
use dirac_cli::plot::{PointGroup, Series, plot_points, plot_spectra};

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
