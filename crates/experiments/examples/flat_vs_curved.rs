//! Experiment 4, paper Fig. 5 and Fig. 9: kernel dimension and small-eigenvalue counts of the
//! relative Dirac operator on subdivided cubes versus icospheres (unit area), and the first
//! eigenfunctions of the family `L(τ)` on a cube for τ = 0, 0.5, 1. See docs/EXPERIMENTS.md.
//!
//! `cargo run --release -p experiments --example flat_vs_curved -- [--full] [--out DIR]`
//! (`--backend` is accepted and ignored: the counts use a dense solver).

use std::process::ExitCode;
use std::time::Instant;

use dirac::generators::{icosphere, subdivided_cube};
use dirac::spectrum::Operator;
use dirac_cli::render::{Field, RenderOptions, render_png};
use experiments::ExperimentError;
use experiments::args::{ExampleArgs, run_example};
use experiments::flat_vs_curved::{SMALL, eigenfunction_magnitudes, kernel_counts};

fn run(args: &ExampleArgs) -> Result<(), ExperimentError> {
    let start = Instant::now();
    let (cubes, levels): (&[usize], &[u32]) = if args.full {
        (&[4, 8, 12], &[2, 3])
    } else {
        (&[4, 8], &[1, 2])
    };
    println!(
        "| mesh | vertices | dim ker D_N | flat-neighbourhood bound | nonzero |λ| < {SMALL} | \
         all |λ| < {SMALL} | smallest nonzero |λ| |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for &n in cubes {
        rows.push((format!("cube n = {n}"), subdivided_cube(n)?));
    }
    for &level in levels {
        rows.push((format!("icosphere level {level}"), icosphere(level)));
    }
    for (name, mesh) in &rows {
        let counts = kernel_counts(mesh)?;
        println!(
            "| {name} | {} | {} | {} | {} | {} | {:.3} |",
            counts.vertices,
            counts.kernel,
            counts.flat_bound,
            counts.small,
            counts.kernel + counts.small,
            counts.smallest_nonzero
        );
    }
    // Fig. 5: the first nonconstant eigenfunctions |φ| of L(τ) on a cube.
    let cube = subdivided_cube(if args.full { 16 } else { 10 })?;
    std::fs::create_dir_all(&args.out)?;
    for tau in [0.0, 0.5, 1.0] {
        let modes = eigenfunction_magnitudes(&cube, Operator::Family { tau }, 4)?;
        let fields: Vec<Field> = modes
            .iter()
            .map(|(lambda, values)| Field {
                label: format!("τ = {tau}, λ = {lambda:.3}"),
                values: values.clone(),
            })
            .collect();
        let path = args.out.join(format!("cube-tau-{tau}.png"));
        let options = RenderOptions {
            width: 1200,
            height: 320,
            columns: Some(4),
            ..RenderOptions::default()
        };
        render_png(&cube, &fields, &options, &path)?;
        let values: Vec<String> = modes.iter().map(|(l, _)| format!("{l:.3}")).collect();
        println!(
            "τ = {tau}: first nonzero λ {} → {}",
            values.join(", "),
            path.display()
        );
    }
    println!("\ntotal {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

fn main() -> ExitCode {
    run_example("flat_vs_curved", run)
}
