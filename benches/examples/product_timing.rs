//! Times the sparse product `y = Aᴴ x` (`SparseMatrix::adjoint_mul_vec`, the product of
//! every Lanczos step of the relative Dirac operator and of every residual) with the stiffness
//! `A = D* M_F D` of the relative Dirac operator of a mesh, on one and on two threads,
//! alternating: `product_timing MESH REPEATS`. Prints the median milliseconds of each.

use std::time::Instant;

use dirac::io::read_mesh;
use dirac::operators::{DiracPencil, normal_dirac};
use qscalar::Quat;
use qsparse::threads;

fn main() {
    let mut args = std::env::args().skip(1);
    let (Some(path), Some(repeats)) = (args.next(), args.next()) else {
        eprintln!("usage: product_timing MESH REPEATS");
        std::process::exit(2);
    };
    let repeats: usize = repeats.parse().expect("REPEATS is a count");
    let mesh = read_mesh(&path).expect("a readable mesh");
    let d = normal_dirac(&mesh).expect("the Dirac operator");
    let a = DiracPencil::new(&mesh, &d)
        .expect("the Dirac pencil")
        .stiffness;
    let n = a.ncols();
    let x: Vec<Quat<f64>> = (0..n)
        .map(|i| Quat::new(1.0 + (i % 7) as f64, 0.5, -0.25, 0.125))
        .collect();
    let mut y = vec![Quat::new(0.0, 0.0, 0.0, 0.0); n];
    let mut times = [Vec::new(), Vec::new()];
    for _ in 0..repeats {
        for (two, seconds) in times.iter_mut().enumerate() {
            threads::set_second_thread_allowed(two == 1);
            let start = Instant::now();
            a.adjoint_mul_vec(&x, &mut y).expect("square");
            seconds.push(start.elapsed().as_secs_f64());
        }
    }
    let [one, two] = times.map(|mut seconds| dirac_bench::median(&mut seconds));
    println!(
        "{n} unknowns, {} entries: one thread {:.3} ms, two threads {:.3} ms",
        a.nnz(),
        one * 1e3,
        two * 1e3
    );
}
