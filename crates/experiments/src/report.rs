//! Scores of every operator's spectra and the table the examples print.

use crate::metrics::Scores;
use crate::spectra::OperatorSpectra;

/// One operator's row: scores and cost.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScoreRow {
    /// Operator name.
    pub operator: &'static str,
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
            operator: table.operator.name,
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
