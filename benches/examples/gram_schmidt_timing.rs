//! Times one thread's Gram–Schmidt sweep (`qsparse::vector::axpy_two_then_inner_two`, the
//! kernel of every Lanczos step's orthogonalisation) over `COLUMNS` unit columns of
//! `LENGTH` quaternions, and over the same number of real columns of `4 LENGTH` reals:
//! `gram_schmidt_timing LENGTH COLUMNS REPEATS` (`LENGTH` a multiple of four: whole blocks of
//! the blocked layout the kernel works on; the columns are random, so reading them as blocked
//! vectors changes nothing in the timing). Prints the median time per quaternion (four reals)
//! and column, and the rate at which the sweep streams the columns.
//!
//! With the default 21,600 quaternions (half of the armadillo's 43,243 rows: one thread's
//! share of a two-thread pass) and 400 columns the basis (276 MB) is far out of cache, as in
//! the Lanczos runs of docs/PERFORMANCE.md; `2000 40` keeps it in the second-level cache.

use std::time::Instant;

use qscalar::random::SplitMix64;
use qscalar::{Quat, Scalar};
use qsparse::vector;

/// Unit columns and a vector to sweep, of scalar `T`.
struct Sweep<T> {
    columns: Vec<Vec<T>>,
    w: Vec<T>,
}

impl<T: Scalar<Real = f64>> Sweep<T> {
    fn new(length: usize, count: usize, rng: &mut SplitMix64) -> Self {
        let mut unit = || {
            let mut v = vec![T::zero(); length];
            rng.fill_symmetric(&mut v);
            let norm = vector::norm(&v);
            vector::scale(&mut v, 1.0 / norm);
            v
        };
        let columns = (0..count).map(|_| unit()).collect();
        let w = unit();
        Self { columns, w }
    }

    /// Seconds for one modified Gram–Schmidt sweep of `w` against every column, two at a time.
    fn time(&mut self) -> f64 {
        let columns = &self.columns;
        let start = Instant::now();
        let (a, b) = vector::inner_two(&columns[0], &columns[1], &self.w);
        let mut c = [a, b];
        for pair in 0..columns.len() / 2 - 1 {
            let (v, next) = (2 * pair, 2 * pair + 2);
            c = vector::axpy_two_then_inner_two(
                &mut self.w,
                [&columns[v], &columns[v + 1]],
                [T::zero() - c[0], T::zero() - c[1]],
                [&columns[next], &columns[next + 1]],
            );
        }
        let seconds = start.elapsed().as_secs_f64();
        // Keep `w` of unit norm, so that repeated sweeps neither vanish nor grow.
        let norm = vector::norm(&self.w);
        vector::scale(&mut self.w, 1.0 / norm);
        seconds
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let length: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(21_600);
    let count: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(400);
    let repeats: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(9);
    if length == 0 || repeats == 0 || count < 4 || !count.is_multiple_of(2) {
        eprintln!(
            "usage: gram_schmidt_timing LENGTH COLUMNS REPEATS (LENGTH, REPEATS ≥ 1; COLUMNS even and ≥ 4)"
        );
        std::process::exit(2);
    }
    let mut rng = SplitMix64::new(7);
    let mut quaternion = Sweep::<Quat<f64>>::new(length, count, &mut rng);
    let mut real = Sweep::<f64>::new(4 * length, count, &mut rng);
    let (mut q, mut r) = (Vec::new(), Vec::new());
    for _ in 0..repeats {
        q.push(quaternion.time());
        r.push(real.time());
    }
    // The sweep reads every column but the first two once.
    let column_reads = ((count - 2) * length) as f64;
    for (name, seconds) in [
        ("quaternion", dirac_bench::median(&mut q)),
        ("real (4 per quaternion)", dirac_bench::median(&mut r)),
    ] {
        println!(
            "{name}: {:.3} ms per sweep, {:.3} ns per quaternion and column, {:.1} GB/s of columns",
            1e3 * seconds,
            1e9 * seconds / column_reads,
            column_reads * 32.0 / seconds / 1e9,
        );
    }
}
