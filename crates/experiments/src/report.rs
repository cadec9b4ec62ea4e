//! Scores of every operator's spectra and the table the examples print.

use std::path::Path;

use dirac::spectrum::Operator;

use crate::ExperimentError;
use crate::metrics::Scores;
use crate::plots::{write_embedding_plots, write_spectra_plots};
use crate::spectra::OperatorSpectra;

/// One operator's row: scores and cost.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScoreRow {
    /// The operator.
    pub operator: Operator,
    /// Separation scores of its spectra.
    pub scores: Scores,
    /// Seconds spent computing its spectra.
    pub seconds: f64,
}

/// Scores every operator's spectra against the class `labels`, k-means with `starts` random
/// starts seeded by `seed`.
pub fn score_rows(
    tables: &[OperatorSpectra],
    labels: &[usize],
    starts: usize,
    seed: u64,
) -> Vec<ScoreRow> {
    tables
        .iter()
        .map(|table| ScoreRow {
            operator: table.operator,
            scores: Scores::new(&table.spectra, labels, starts, seed),
            seconds: table.seconds,
        })
        .collect()
}

/// A Markdown table: operator, leave-one-out 1-NN accuracy (%), between/within distance
/// ratio, mean k-means purity (%), seconds.
pub fn format_rows(rows: &[ScoreRow]) -> String {
    let mut out = String::from(
        "| operator | 1-NN accuracy (LOO) | between/within ratio | k-means purity | seconds |\n\
         |---|---|---|---|---|\n",
    );
    for row in rows {
        out.push_str(&format!(
            "| {} | {:.1}% | {:.2} | {:.1}% | {:.1} |\n",
            row.operator,
            100.0 * row.scores.nearest_neighbour,
            row.scores.ratio,
            100.0 * row.scores.purity,
            row.seconds
        ));
    }
    out
}

/// What the classification experiments (tori, patches) print and draw: the score table of the
/// `|λ|` spectra (the paper's default, §7) and of the signed ones, then the mean-spectrum and
/// embedding plots of the `|λ|` spectra per operator, written into `out`. k-means uses
/// `starts` random starts seeded by `seed`.
pub fn report_classification(
    tables: &[OperatorSpectra],
    labels: &[usize],
    names: &[String],
    (starts, seed): (usize, u64),
    out: &Path,
) -> Result<(), ExperimentError> {
    let magnitudes: Vec<OperatorSpectra> = tables.iter().map(OperatorSpectra::magnitudes).collect();
    println!("\nspectra of |λ| (the paper's default, §7):");
    println!(
        "{}",
        format_rows(&score_rows(&magnitudes, labels, starts, seed))
    );
    println!("signed spectra (λ ordered by |λ|):");
    println!("{}", format_rows(&score_rows(tables, labels, starts, seed)));
    let mut written = write_spectra_plots(&magnitudes, labels, names, out)?;
    written.extend(write_embedding_plots(&magnitudes, labels, names, out)?);
    for path in written {
        println!("wrote {}", path.display());
    }
    Ok(())
}
