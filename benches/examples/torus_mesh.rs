//! Writes the million-vertex torus of issue 15 as an OBJ file: `dirac::generators::Torus` with
//! `R = 3`, `r = 1` on a `MAJOR × MINOR` grid (default 2000 × 500) with a small ripple
//! (`Detail::Bumps`, amplitude 0.02, 24 × 6 bumps):
//! `cargo run --release -p dirac-bench --example torus_mesh -- OUT.obj [MAJOR MINOR]`.

use std::process::ExitCode;

use dirac::generators::{Detail, Torus};
use dirac::io::write_obj;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: torus_mesh OUT.obj [MAJOR MINOR]";
    let Some(path) = args.first() else {
        eprintln!("{usage}");
        return ExitCode::from(2);
    };
    let segment = |k: usize, default: usize| -> Result<usize, String> {
        args.get(k)
            .map_or(Ok(default), |s| s.parse().map_err(|e| format!("{s}: {e}")))
    };
    let (major, minor) = match (segment(1, 2000), segment(2, 500)) {
        (Ok(major), Ok(minor)) => (major, minor),
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("{e}\n{usage}");
            return ExitCode::from(2);
        }
    };
    let mut torus = Torus::new(3.0, 1.0, major, minor);
    torus.detail = Detail::Bumps {
        amplitude: 0.02,
        frequency: [24, 6],
    };
    let result = torus
        .mesh()
        .map_err(|e| e.to_string())
        .and_then(|mesh| write_obj(&mesh, path).map_err(|e| e.to_string()));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}
