//! The fixed costs of a spectrum before the eigensolver, each phase timed once in a fresh
//! process (as the command line pays them, first-touch page faults included): reading the
//! file, parsing it, validating the mesh, finding its topology, assembling the cotangent
//! Laplacian and masses, the symbolic analysis of `L + M` (fill-reducing ordering,
//! supernodes, the two-thread split) and its numeric factorisation. Prints one line of
//! milliseconds; run it several times for medians: `load_timing MESH`.

use std::sync::Arc;
use std::time::Instant;

use dirac::geometry::{barycentric_masses, cotan_laplacian};
use qsparse::{SparseCholesky, SparseMatrix, SymbolicCholesky};

fn main() {
    let path = std::env::args().nth(1).expect("usage: load_timing MESH");
    let path = std::path::Path::new(&path);
    let mut phases = Vec::new();
    let mut clock = Instant::now();
    let mut lap = |name: &'static str| {
        phases.push((name, clock.elapsed().as_secs_f64() * 1e3));
        clock = Instant::now();
    };
    let bytes = std::fs::read(path).expect("readable file");
    lap("read");
    let raw = dirac::io::parse_raw(path, &bytes).expect("a mesh file");
    lap("parse");
    let mesh = raw.into_mesh().expect("a valid mesh");
    lap("validate");
    std::hint::black_box(mesh.topology());
    lap("topology");
    let laplacian = cotan_laplacian(&mesh);
    let mass = barycentric_masses(&mesh);
    let masses = SparseMatrix::from_diagonal(&mass);
    let pencil = SparseMatrix::linear_combination(1.0, &laplacian, 1.0, &masses).expect("n × n");
    lap("assemble");
    let symbolic = Arc::new(SymbolicCholesky::analyze(&pencil).expect("square"));
    lap("analyse");
    std::hint::black_box(SparseCholesky::factorize_with_symbolic(symbolic, &pencil).expect("HPD"));
    lap("factorise");
    let line: Vec<String> = (phases.iter())
        .map(|(name, ms)| format!("{name} {ms:.3}"))
        .collect();
    println!("{}", line.join("  "));
}
