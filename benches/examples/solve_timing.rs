//! Times the two triangular solves of one Lanczos operator application (`C⁻ᴴ` then `C⁻¹`) with
//! the native Cholesky: quaternion connection Laplacian versus the real Laplacian of the same
//! icosphere, each on one and on two threads ([`SolveThreads`]), alternating so that all see
//! the same machine load: `solve_timing LEVEL REPEATS`.

use std::time::Instant;

use dirac::generators::icosphere;
use dirac::geometry::{barycentric_masses, cotan_laplacian};
use qscalar::{Quat, Scalar};
use qsparse::{SolveThreads, SparseCholesky, SparseMatrix};

/// A factor and a right-hand side to solve with repeatedly.
struct Case<T> {
    chol: SparseCholesky<T>,
    x: Vec<T>,
}

impl<T: Scalar<Real = f64>> Case<T> {
    fn new(a: &SparseMatrix<T>) -> Self {
        let chol = SparseCholesky::factorize(a).expect("HPD");
        let x = (0..a.nrows())
            .map(|i| T::from_real(1.0 + (i % 7) as f64))
            .collect();
        Self { chol, x }
    }

    /// Seconds for `C⁻¹ C⁻ᴴ x` with `threads`, then `x` normalised.
    fn time(&mut self, threads: SolveThreads) -> f64 {
        self.chol.set_solve_threads(threads);
        let start = Instant::now();
        self.chol.solve_upper_in_place(&mut self.x).expect("length");
        self.chol.solve_lower_in_place(&mut self.x).expect("length");
        let seconds = start.elapsed().as_secs_f64();
        let norm = self.x.iter().map(|v| v.abs2()).sum::<f64>().sqrt();
        self.x.iter_mut().for_each(|v| *v = v.scale(1.0 / norm));
        seconds
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let level: u32 = args.next().and_then(|s| s.parse().ok()).unwrap_or(5);
    let repeats: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(100);
    let mesh = icosphere(level);
    let laplacian = cotan_laplacian(&mesh);
    let mass = barycentric_masses(&mesh);
    let masses = SparseMatrix::from_diagonal(&mass);
    let pencil = SparseMatrix::linear_combination(1.0, &laplacian, 1.0, &masses).expect("n × n");
    let mut real = Case::<f64>::new(&pencil);
    let mut quaternion = Case::<Quat<f64>>::new(&dirac_bench::connection_laplacian(level));
    // [quaternion one, quaternion two, real one, real two]
    let mut samples: [Vec<f64>; 4] = Default::default();
    let mut ratio = Vec::new();
    for _ in 0..repeats {
        for (i, threads) in [SolveThreads::One, SolveThreads::Two]
            .into_iter()
            .enumerate()
        {
            samples[i].push(quaternion.time(threads));
            samples[2 + i].push(real.time(threads));
        }
        ratio.push(samples[1].last().expect("pushed") / samples[3].last().expect("pushed"));
    }
    let [q1, q2, r1, r2] = samples.map(|mut s| dirac_bench::median(&mut s) * 1e3);
    let stats = quaternion.chol.stats();
    println!(
        "level {level}: n {}, {} supernodes (widest {}), {} factor entries, split {:?}; per pair of \
         solves (median, one / two threads): quaternion {q1:.3} / {q2:.3} ms, real {r1:.3} / \
         {r2:.3} ms, quaternion ÷ real on two threads {:.2}",
        stats.n,
        stats.supernodes,
        stats.max_supernode_width,
        stats.factor_entries,
        stats.split_columns,
        dirac_bench::median(&mut ratio)
    );
}
