//! The one-call use of the library: the spectrum of the relative Dirac operator of a mesh file
//! (or of the built-in `spot`), and a descriptor built on it.
//!
//! ```text
//! cargo run --release -p dirac --example spectrum -- [MESH.obj|.off|.ply] [K]
//! ```

use std::error::Error;

use dirac::descriptors::{Modes, default_times, dirac_kernel_signature};
use dirac::{Normalization, Operator, SpectrumOptions};

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let mesh = match args.next() {
        Some(path) => dirac::io::read_mesh(path)?,
        None => dirac::default_mesh(),
    };
    let k = args.next().map_or(Ok(10), |k| k.parse())?;

    let mut options = SpectrumOptions::new(Operator::RelativeDirac, k);
    options.normalization = Normalization::UnitArea;
    let spectrum = dirac::spectrum(&mesh, &options)?;

    println!(
        "{} vertices, kernel of dimension {}",
        mesh.vertex_count(),
        spectrum.kernel.dimension
    );
    for (lambda, residual) in spectrum.eigenvalues.iter().zip(&spectrum.residuals) {
        println!("λ = {lambda:>12.6}   residual {residual:.1e}");
    }

    // The Dirac kernel signature at 16 times, one row per vertex.
    let modes = Modes::from_spectrum(&spectrum)?;
    let signature = dirac_kernel_signature(&modes, &default_times(&modes, 16)?)?;
    println!("DKS at vertex 0: {:.3?}", &signature.row(0)[..4]);
    Ok(())
}
