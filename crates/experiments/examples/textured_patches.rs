//! Experiment 2, paper Fig. 7 and Fig. 10: textured patches with ragged boundaries inside the
//! infinite potential well; distance between patches = Euclidean distance of spectra; mean
//! purity of k-means (k = 10, 500 random starts) per operator, and a 2-D embedding plot.
//! See docs/EXPERIMENTS.md.
//!
//! `cargo run --release -p experiments --example textured_patches -- [--full] [--backend B] [--out DIR]`

use std::process::ExitCode;
use std::time::Instant;

use dirac::spectrum::Normalization;
use experiments::ExperimentError;
use experiments::args::{ExampleArgs, run_example};
use experiments::patches::{PatchConfig, patch_classes, patches, well};
use experiments::report::report_classification;
use experiments::spectra::{
    ANISOTROPIC_LAPLACE, DIRAC, HALF_WAY, LAPLACE, MODIFIED_DIRICHLET, RELATIVE_DIRAC,
    compute_spectra,
};

/// k-means random starts (the paper's 500).
const STARTS: usize = 500;
/// Seed of the k-means starts.
const SEED: u64 = 10;

fn run(args: &ExampleArgs) -> Result<(), ExperimentError> {
    let start = Instant::now();
    let config = if args.full {
        PatchConfig::FULL
    } else {
        PatchConfig::DEFAULT
    };
    let classes = patch_classes();
    let patches = patches(&config, &classes)?;
    let sizes: Vec<usize> = patches.iter().map(|p| p.mesh.vertex_count()).collect();
    println!(
        "{} patches ({} classes × {}), {}–{} vertices, k = {}, well radius {}, backend {:?}",
        patches.len(),
        classes.len(),
        config.per_class,
        sizes.iter().min().unwrap_or(&0),
        sizes.iter().max().unwrap_or(&0),
        config.k,
        config.well_radius,
        args.backend
    );
    let labels: Vec<usize> = patches.iter().map(|p| p.class).collect();
    let meshes: Vec<_> = patches.iter().map(|p| p.mesh.clone()).collect();
    let operators = [
        RELATIVE_DIRAC,
        DIRAC,
        LAPLACE,
        MODIFIED_DIRICHLET,
        HALF_WAY,
        ANISOTROPIC_LAPLACE,
    ];
    let tables = compute_spectra(
        &meshes,
        &operators,
        config.k,
        args.backend,
        Normalization::None,
        &|i| Some(well(&config, &patches[i])),
    )?;
    let names: Vec<String> = classes.iter().map(|c| c.name.clone()).collect();
    report_classification(&tables, &labels, &names, (STARTS, SEED), &args.out)?;
    println!("total {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

fn main() -> ExitCode {
    run_example("textured_patches", run)
}
