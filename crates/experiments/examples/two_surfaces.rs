//! Paper Fig. 3: eigenfunctions of the relative Dirac operator `D_{f1,f2}` of a surface (spot)
//! and a copy whose head is shrunk concentrate where the two differ; those of the
//! extrinsic Dirac operator `D_f` of the surface alone do not. Prints each mode's
//! concentration in the deformed region, writes both surfaces as OBJ (for `dirac spectrum
//! spot.obj --relative-to spot-contracted.obj`) and a picture. See docs/EXPERIMENTS.md.
//!
//! `cargo run --release -p experiments --example two_surfaces -- [--out DIR]`

use std::process::ExitCode;
use std::time::Instant;

use dirac::geometry::{bounding_box, norm, sub};
use dirac::io::write_obj;
use dirac_cli::render::{Field, RenderOptions, View, format_value, render_png};
use experiments::ExperimentError;
use experiments::args::{ExampleArgs, run_example};
use experiments::two_surfaces::{Contraction, concentrations, run};

const K: usize = 8;

fn main_run(args: &ExampleArgs) -> Result<(), ExperimentError> {
    let start = Instant::now();
    let mesh = dirac::default_mesh();
    // Shrink the top of spot's head (around the vertex of largest y, within 0.3 of the
    // bounding-box diagonal) by 70%.
    let (low, high) = bounding_box(mesh.positions().iter().copied()).expect("spot has vertices");
    let top = (mesh.positions().iter())
        .copied()
        .max_by(|a, b| a[1].total_cmp(&b[1]))
        .expect("a mesh has vertices");
    let contraction = Contraction {
        center: top,
        radius: 0.3 * norm(sub(high, low)),
        amount: 0.7,
    };
    let result = run(&mesh, &contraction, K)?;
    let relative = concentrations(&mesh, &contraction, &result.relative);
    let extrinsic = concentrations(&mesh, &contraction, &result.extrinsic);
    println!(
        "spot, {} vertices; region: radius {:.3} around the top of the head, half of it scaled by {:.2}",
        mesh.vertex_count(),
        contraction.radius,
        1.0 - contraction.amount
    );
    println!("| mode | λ of D_(f1,f2) | concentration | λ of D_f | concentration |");
    println!("|---|---|---|---|---|");
    for i in 0..K {
        println!(
            "| {i} | {} | {:.2} | {} | {:.2} |",
            format_value(result.relative.eigenvalues[i]),
            relative[i],
            format_value(result.extrinsic.eigenvalues[i]),
            extrinsic[i]
        );
    }
    std::fs::create_dir_all(&args.out)?;
    for (name, surface) in [
        ("spot.obj", &mesh),
        ("spot-contracted.obj", &result.deformed),
    ] {
        let path = args.out.join(name);
        write_obj(surface, &path)?;
        println!("wrote {}", path.display());
    }
    let weight = Field {
        label: "contraction w".into(),
        values: (mesh.positions().iter())
            .map(|&p| contraction.weight(p))
            .collect(),
    };
    let mut fields = vec![weight.clone()];
    let modes = |label: &str, spectrum: &dirac::Spectrum| -> Vec<Field> {
        (0..3)
            .map(|i| Field {
                label: format!("{label} |φ{i}|"),
                values: spectrum.eigenvectors[i].iter().map(|q| q.norm()).collect(),
            })
            .collect()
    };
    fields.extend(modes("D(f1,f2)", &result.relative));
    fields.push(weight);
    fields.extend(modes("D_f", &result.extrinsic));
    let options = RenderOptions {
        width: 1040,
        height: 560,
        columns: Some(4),
        view: View {
            azimuth_degrees: 60.0,
            elevation_degrees: 25.0,
        },
        ..RenderOptions::default()
    };
    let path = args.out.join("two-surfaces.png");
    render_png(&mesh, &fields, &options, &path)?;
    println!("wrote {}", path.display());
    println!("total {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

fn main() -> ExitCode {
    run_example("two_surfaces", main_run)
}
