//! Experiment 1, paper Fig. 8: textured tori. One base torus with bumps, ridges and noise at
//! two amplitudes, several random tessellations each; the first 60 eigenvalues of Laplace,
//! `L(0.5)`, relative Dirac, Dirac, the modified Dirichlet Hessian and the anisotropic
//! Laplacian (`α = 10`) at unit area; how well
//! each operator's spectra separate the textures. See docs/EXPERIMENTS.md.
//!
//! `cargo run --release -p experiments --example textured_tori -- [--full] [--backend B] [--out DIR]`

use std::process::ExitCode;
use std::time::Instant;

use dirac::spectrum::Normalization;
use experiments::ExperimentError;
use experiments::args::{ExampleArgs, run_example};
use experiments::report::report_classification;
use experiments::spectra::{
    ANISOTROPIC_LAPLACE, DIRAC, HALF_WAY, LAPLACE, MODIFIED_DIRICHLET, RELATIVE_DIRAC,
    compute_spectra,
};
use experiments::tori::{ToriConfig, meshes, texture_classes};

/// k-means random starts.
const STARTS: usize = 500;
/// Seed of the k-means starts.
const SEED: u64 = 8;

fn run(args: &ExampleArgs) -> Result<(), ExperimentError> {
    let start = Instant::now();
    let config = if args.full {
        ToriConfig::FULL
    } else {
        ToriConfig::DEFAULT
    };
    let classes = texture_classes();
    let meshes = meshes(&config, &classes)?;
    println!(
        "{} tori ({} classes × {} tessellations, {} vertices each), k = {}, unit area, backend {:?}",
        meshes.len(),
        classes.len(),
        config.tessellations,
        meshes[0].mesh.vertex_count(),
        config.k,
        args.backend
    );
    let labels: Vec<usize> = meshes.iter().map(|m| m.class).collect();
    let surfaces: Vec<_> = meshes.into_iter().map(|m| m.mesh).collect();
    let operators = [
        LAPLACE,
        HALF_WAY,
        RELATIVE_DIRAC,
        DIRAC,
        MODIFIED_DIRICHLET,
        ANISOTROPIC_LAPLACE,
    ];
    let tables = compute_spectra(
        &surfaces,
        &operators,
        config.k,
        args.backend,
        Normalization::UnitArea,
        &|_| None,
    )?;
    let names: Vec<String> = classes.iter().map(|c| c.name.clone()).collect();
    report_classification(&tables, &labels, &names, (STARTS, SEED), &args.out)?;
    println!("total {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

fn main() -> ExitCode {
    run_example("textured_tori", run)
}
