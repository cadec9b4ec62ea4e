//! Experiment 2's purity gap (issue 13, part 5): relative Dirac and Laplace purity of the
//! textured patches with one factor changed at a time — texture classes, well radius, mesh
//! resolution (`--full` adds level 5), eigenvalue count, transform and normalisation of the
//! distance. Same protocol as `textured_patches` (100 patches, 10 classes, k-means with
//! k = 10, 500 random starts). See docs/EXPERIMENTS.md §2.
//!
//! `cargo run --release -p experiments --example patches_study -- [--full] [--backend B]`

use std::process::ExitCode;
use std::time::Instant;

use experiments::ExperimentError;
use experiments::args::{ExampleArgs, run_example};
use experiments::patches_study::{
    Protocol, StudyRow, feature_variants, format_study, setting_spectra, settings, simplex_ceiling,
};
use experiments::spectral_features::SpectralFeatures;

/// The paper's 500 k-means starts, seeded as in `textured_patches`.
const PROTOCOL: Protocol = Protocol {
    starts: 500,
    seed: 10,
};

fn run(args: &ExampleArgs) -> Result<(), ExperimentError> {
    let start = Instant::now();
    let mut one_factor = Vec::new();
    let mut best: Option<StudyRow> = None;
    for setting in settings(args.full) {
        let spectra = setting_spectra(&setting, args.backend)?;
        let scoring = Instant::now();
        let rows = feature_variants()
            .into_iter()
            .map(|(factor, features)| spectra.score(factor, features, PROTOCOL))
            .collect::<Result<Vec<_>, _>>()?;
        println!(
            "\n{}: {} ({}–{} vertices): spectra {:.1} s (relative Dirac {:.1} s, Laplace {:.1} s), \
             scores {:.1} s",
            setting.factor,
            setting.value,
            spectra.vertices.0,
            spectra.vertices.1,
            spectra.seconds,
            spectra.tables[0].seconds,
            spectra.tables[1].seconds,
            scoring.elapsed().as_secs_f64()
        );
        println!("{}", format_study(&rows));
        let [dirac_ceiling, laplace_ceiling] =
            spectra.ceilings(SpectralFeatures::PAPER, PROTOCOL)?;
        println!(
            "k-means ceiling (every patch at its class centroid, {}): relative Dirac {:.1}, \
             Laplace {:.1}; equidistant classes {:.1}",
            SpectralFeatures::PAPER.describe(),
            100.0 * dirac_ceiling,
            100.0 * laplace_ceiling,
            100.0 * simplex_ceiling(&spectra.labels, PROTOCOL)
        );
        for row in &rows {
            if best
                .as_ref()
                .is_none_or(|b| row.relative_dirac > b.relative_dirac)
            {
                best = Some(row.clone());
            }
        }
        // The one-factor-at-a-time table: every distance variant of the default setting, the
        // default distance of every other setting.
        if setting.factor == "default" {
            one_factor.extend(rows);
        } else {
            one_factor.extend(rows.into_iter().take(1).map(|row| StudyRow {
                factor: setting.factor,
                ..row
            }));
        }
    }
    println!("\none factor at a time:\n{}", format_study(&one_factor));
    if let Some(best) = best {
        println!("best relative Dirac:\n{}", format_study(&[best]));
    }
    println!("total {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

fn main() -> ExitCode {
    run_example("patches_study", run)
}
