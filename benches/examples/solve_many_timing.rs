//! Times the many-column half-solves of the native Cholesky against one column at a time:
//! `C⁻ᴴ` then `C⁻¹` on `ncols` columns at once (`solve_upper_many_in_place_with`,
//! `solve_lower_many_in_place_with`), per column, for `ncols` in 1, 2, 4, 8 and 16, on the
//! quaternion connection Laplacian of an icosphere: `solve_many_timing LEVEL REPEATS` (median
//! of the repeats; defaults 6 and 7).

use std::time::Instant;

use qscalar::{Quat, Scalar};
use qsparse::SparseCholesky;

fn main() {
    let mut args = std::env::args().skip(1);
    let level: u32 = args.next().map_or(6, |a| a.parse().expect("LEVEL"));
    let repeats: usize = args.next().map_or(7, |a| a.parse().expect("REPEATS"));
    let a = dirac_bench::connection_laplacian(level);
    let n = a.nrows();
    let chol = SparseCholesky::factorize(&a).expect("HPD");
    println!(
        "level {level}: {n} quaternion unknowns, factor {:.1} MB",
        chol.stats().factor_bytes as f64 / 1e6
    );
    let mut work = Vec::new();
    let mut single = f64::NAN;
    for ncols in [1usize, 2, 4, 8, 16] {
        let mut x: Vec<Quat<f64>> = (0..n * ncols)
            .map(|i| Quat::from_real(1.0 + (i % 7) as f64))
            .collect();
        let mut times: Vec<f64> = (0..repeats)
            .map(|_| {
                let start = Instant::now();
                chol.solve_upper_many_in_place_with(&mut x, ncols, &mut work)
                    .expect("length");
                chol.solve_lower_many_in_place_with(&mut x, ncols, &mut work)
                    .expect("length");
                let seconds = start.elapsed().as_secs_f64() / ncols as f64;
                let norm = x.iter().map(|v| v.abs2()).sum::<f64>().sqrt();
                x.iter_mut().for_each(|v| *v = v.scale(1.0 / norm));
                seconds
            })
            .collect();
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        if ncols == 1 {
            single = median;
        }
        println!(
            "ncols {ncols:>2}: {:.3} ms per column for both halves ({:.2}x one column)",
            median * 1e3,
            single / median
        );
    }
}
