//! Experiment 5, paper §6.1 and Fig. 9: man-made versus organic shapes of the Princeton
//! segmentation benchmark by the spectrum of the relative Dirac operator at unit area. The
//! paper's rule (mean `λ²` of the first 25 eigenvalues below a threshold) with the paper's
//! threshold and with one learnt leave-one-out, with and without the kernel's zeros; the
//! flat-vertex share as a baseline; 1-NN on `log |λ|`. See docs/EXPERIMENTS.md.
//!
//! `cargo run --release -p experiments --example man_made_vs_organic -- PSB_DIR [--backend B] [--out DIR]`
//! (`PSB_DIR` holds the meshes and `labels.csv`; `--full` is accepted and changes nothing).

use std::process::ExitCode;
use std::time::Instant;

use experiments::ExperimentError;
use experiments::args::{ExampleArgs, run_example_with_input};
use experiments::man_made::{
    ManMadeReport, PAPER_COUNT, SPECTRUM_LENGTH, compute_spectra, read_labels,
};

fn run(args: &ExampleArgs) -> Result<(), ExperimentError> {
    let start = Instant::now();
    let dir = args
        .input
        .as_deref()
        .expect("parse_with_input requires the input");
    let entries = read_labels(dir)?;
    println!(
        "{} meshes from {}; relative Dirac, unit area, {SPECTRUM_LENGTH} nonzero eigenvalues \
         each (the paper's score uses the first {PAPER_COUNT}), backend {:?}",
        entries.len(),
        dir.display(),
        args.backend
    );
    let shapes = compute_spectra(dir, &entries, args.backend, &mut |s| {
        println!(
            "  {} ({}, {}): {} vertices, dim ker {}, {:.1} s",
            s.entry.file,
            s.entry.category,
            s.entry.label,
            s.vertices,
            s.kernel.dimension,
            s.seconds
        );
    })?;
    let solving = start.elapsed().as_secs_f64();
    let report = ManMadeReport::new(shapes);
    println!("\n{}", report.shape_table());
    println!("{}", report.accuracy_table());
    print!("{}", report.class_medians());
    for path in report.write_plots(&args.out)? {
        println!("wrote {}", path.display());
    }
    println!(
        "spectra {solving:.1} s, total {:.1} s",
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn main() -> ExitCode {
    run_example_with_input("man_made_vs_organic", "PSB_DIR", run)
}
