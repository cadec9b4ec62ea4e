//! Experiment 3, paper Fig. 12: bumps in and out. Two tessellations of a flat sheet with an
//! outward and an inward bump; point-to-point correspondence by nearest HKS (Laplace) versus
//! nearest DKS (extrinsic Dirac); mean geodesic error and share matched within a radius.
//! See docs/EXPERIMENTS.md.
//!
//! `cargo run --release -p experiments --example bumps -- [--full] [--backend B] [--out DIR]`

use std::process::ExitCode;
use std::time::Instant;

use dirac_cli::render::{Field, RenderOptions, View, render_png};
use experiments::ExperimentError;
use experiments::args::{ExampleArgs, run_example};
use experiments::bumps::{BumpsConfig, RADIUS, run};

fn main_run(args: &ExampleArgs) -> Result<(), ExperimentError> {
    let start = Instant::now();
    let config = if args.full {
        BumpsConfig::FULL
    } else {
        BumpsConfig::DEFAULT
    };
    let (source, target, results) = run(&config, args.backend)?;
    println!(
        "source {} vertices, target {} vertices, k = {}, {} samples, backend {:?}",
        source.vertex_count(),
        target.vertex_count(),
        config.k,
        results[0].errors.len(),
        args.backend
    );
    println!(
        "| descriptor | mean geodesic error | on the bumps | matched within {RADIUS} | bump samples swapped in ↔ out |"
    );
    println!("|---|---|---|---|---|");
    for r in &results {
        println!(
            "| {} | {:.3} | {:.3} | {:.1}% | {:.1}% |",
            r.descriptor,
            r.mean(false),
            r.mean(true),
            100.0 * r.within_radius(),
            100.0 * r.swapped()
        );
    }
    // The surface, shaded by height, for orientation.
    std::fs::create_dir_all(&args.out)?;
    let path = args.out.join("surface.png");
    let field = Field {
        label: "height z".into(),
        values: source.positions().iter().map(|p| p[2]).collect(),
    };
    let options = RenderOptions {
        width: 640,
        height: 400,
        view: View {
            azimuth_degrees: 20.0,
            elevation_degrees: 35.0,
        },
        ..RenderOptions::default()
    };
    render_png(&source, &[field], &options, &path)?;
    println!("wrote {}", path.display());
    println!("total {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

fn main() -> ExitCode {
    run_example("bumps", main_run)
}
