//! Experiment 5, paper §6.2 and Fig. 11: consensus segmentation of the Princeton segmentation
//! benchmark's models under four operators with identical parameters, scored against the human
//! segmentations (Cut Discrepancy, GCE, Hamming distance, Rand Index error) beside the paper's
//! numbers; writes every `.seg` and pictures of four models per operator. See
//! docs/EXPERIMENTS.md.
//!
//! `cargo run --release -p experiments --example segmentation -- PSB_DIR [--out DIR]`
//! (`PSB_DIR` holds `psb_<id>.off` and `seg/psb_<id>_<j>.seg`).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use dirac::segmentation::consensus::ConsensusOptions;
use dirac::segmentation::seg_file::write_seg;
use dirac::spectrum::Operator;
use dirac_cli::render::{RenderOptions, render_segments_png};
use experiments::ExperimentError;
use experiments::args::{ExampleArgs, usage};
use experiments::segmentation::{MeanScores, PAPER, benchmark_models, run_operator};
use experiments::spectra::{DIRAC, HALF_WAY, LAPLACE, RELATIVE_DIRAC};

/// Eigenpairs per model (the descriptor has one column per nonzero mode).
const K: usize = 20;
/// Models drawn per operator (the first four).
const PICTURES: usize = 4;

fn run(dir: &Path, args: &ExampleArgs) -> Result<(), ExperimentError> {
    let start = Instant::now();
    let models = benchmark_models(dir)?;
    let options = ConsensusOptions::default();
    println!(
        "{} models from {}, k = {K}, {} trials of k-means with {}–{} clusters, segments under \
         {} of the area absorbed, seed {}",
        models.len(),
        dir.display(),
        options.trials,
        options.min_clusters,
        options.max_clusters,
        options.min_area_fraction,
        options.seed
    );
    let operators: [Operator; 4] = [RELATIVE_DIRAC, DIRAC, HALF_WAY, LAPLACE];
    let mut rows = Vec::new();
    for operator in operators {
        let results = run_operator(&models, operator, K, &options)?;
        let folder = args.out.join(operator.to_string().replace(':', "-"));
        fs::create_dir_all(&folder)?;
        for (model, result) in models.iter().zip(&results) {
            let file = fs::File::create(folder.join(format!("psb_{}.seg", model.id)))?;
            write_seg(&result.segmentation.labels, file)?;
        }
        for (model, result) in models.iter().zip(&results).take(PICTURES) {
            let picture = folder.join(format!("psb_{}.png", model.id));
            let options = RenderOptions {
                width: 320,
                height: 320,
                ..RenderOptions::default()
            };
            let title = format!(
                "psb_{}: {} segments, {operator}",
                model.id,
                result.segmentation.segment_count()
            );
            render_segments_png(
                &model.mesh,
                &result.segmentation.labels,
                &title,
                &options,
                &picture,
            )?;
        }
        let segments: Vec<usize> = results
            .iter()
            .map(|r| r.segmentation.segment_count())
            .collect();
        let seconds: f64 = results.iter().map(|r| r.seconds).sum();
        println!(
            "{operator}: segments per model {segments:?}, {seconds:.1} s (spectra and segmentations)"
        );
        let mean_segments = segments.iter().sum::<usize>() as f64 / segments.len().max(1) as f64;
        rows.push((
            operator.to_string(),
            mean_segments,
            MeanScores::of(&results),
        ));
    }
    println!();
    println!("| operator | mean segments | CD | GCE | Hamming | Rand (1 − RI) |");
    println!("|---|---|---|---|---|---|");
    for (name, segments, s) in &rows {
        println!(
            "| {name} | {segments:.1} | {:.3} | {:.3} | {:.3} | {:.3} |",
            s.cut_discrepancy, s.consistency, s.hamming, s.rand
        );
    }
    for (name, s) in PAPER {
        println!(
            "| {name} | | {:.2} | {:.2} | {:.2} | {:.2} |",
            s.cut_discrepancy, s.consistency, s.hamming, s.rand
        );
    }
    println!();
    println!(
        "wrote the .seg files and pictures under {}; total {:.1} s",
        args.out.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn main() -> ExitCode {
    let name = "segmentation";
    let mut rest: Vec<String> = std::env::args().skip(1).collect();
    if rest.first().is_none_or(|a| a.starts_with('-')) {
        eprintln!(
            "the first argument must be PSB_DIR\n{} (PSB_DIR first)",
            usage(name)
        );
        return ExitCode::FAILURE;
    }
    let dir = PathBuf::from(rest.remove(0));
    match ExampleArgs::parse(name, rest).and_then(|args| run(&dir, &args)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("{error}");
            ExitCode::FAILURE
        }
    }
}
