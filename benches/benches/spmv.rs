//! Criterion bench: `y = A x` for the quaternionic connection Laplacian, natively
//! (`SparseMatrix<Quat<f64>>::mul_vec`) against faer's sparse × dense product on its
//! `4n × 4n` real-block expansion and on its `2n × 2n` complex adjoint. All three write into a
//! preallocated output and run sequentially.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use dirac_bench::connection_laplacian;
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::{Accum, Col, Par, c64};
use qscalar::{Quat, Scalar};
use qsparse::embedding::complex_adjoint_vector;

/// Icosphere level of the benchmark matrix (`10·4^5 + 2 = 10242` quaternion unknowns).
const LEVEL: u32 = 5;

fn spmv(c: &mut Criterion) {
    faer::set_global_parallelism(Par::Seq);
    let a = connection_laplacian(LEVEL);
    let n = a.nrows();
    let x: Vec<Quat<f64>> = (0..n)
        .map(|i| Quat::new(1.0, (i as f64).sin(), (i as f64).cos(), 0.5))
        .collect();
    let mut group = c.benchmark_group(format!("spmv/n={n}"));

    let mut y = vec![Quat::default(); n];
    group.bench_function("native", |b| {
        b.iter(|| a.mul_vec(black_box(&x), &mut y).expect("square matrix"))
    });

    let real = a.to_real_block();
    let x_real = Col::<f64>::from_fn(4 * n, |i| Quat::as_reals(&x)[i]);
    let mut y_real = Col::<f64>::zeros(4 * n);
    group.bench_function("real_block", |b| {
        b.iter(|| {
            sparse_dense_matmul(
                y_real.as_mat_mut(),
                Accum::Replace,
                real.as_ref(),
                black_box(&x_real).as_mat(),
                1.0,
                Par::Seq,
            )
        })
    });

    let complex = a.to_complex_adjoint();
    let xc = complex_adjoint_vector(&x);
    let x_complex = Col::<c64>::from_fn(2 * n, |i| xc[i]);
    let mut y_complex = Col::<c64>::zeros(2 * n);
    group.bench_function("complex_adjoint", |b| {
        b.iter(|| {
            sparse_dense_matmul(
                y_complex.as_mat_mut(),
                Accum::Replace,
                complex.as_ref(),
                black_box(&x_complex).as_mat(),
                c64::new(1.0, 0.0),
                Par::Seq,
            )
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    targets = spmv
}
criterion_main!(benches);
