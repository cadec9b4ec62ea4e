//! Factorises the level-L connection Laplacian and solves with it repeatedly (for profiling the
//! native Cholesky): `profile_cholesky LEVEL SOLVES`.
fn main() {
    let mut args = std::env::args().skip(1);
    let level: u32 = args.next().and_then(|s| s.parse().ok()).unwrap_or(6);
    let solves: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(0);
    let a = dirac_bench::connection_laplacian(level);
    let chol = qsparse::SparseCholesky::factorize(&a).expect("HPD");
    let mut x = vec![qscalar::Quat::new(1.0, 0.5, -0.25, 2.0); a.nrows()];
    for _ in 0..solves {
        chol.solve_in_place(&mut x).expect("matching length");
    }
    std::hint::black_box(x);
}
