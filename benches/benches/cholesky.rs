//! Criterion bench: numeric sparse Cholesky factorisation and solve of the quaternionic
//! connection Laplacian. Native: `SparseCholesky::<Quat<f64>>::refactorize` with a prebuilt
//! symbolic analysis (storage reused). faer: `Llt::try_new_with_symbolic` with a prebuilt
//! `SymbolicLlt` on the `4n × 4n` real-block expansion and on the `2n × 2n` complex adjoint.
//! Solves are one right-hand side, in place. Everything runs sequentially (`Par::Seq`).

use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use dirac_bench::connection_laplacian;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::{Col, Par, Side, c64};
use qscalar::{Quat, Scalar};
use qsparse::embedding::complex_adjoint_vector;
use qsparse::{SparseCholesky, SymbolicCholesky};

/// Icosphere level of the benchmark matrix (`10·4^5 + 2 = 10242` quaternion unknowns).
const LEVEL: u32 = 5;

fn cholesky(c: &mut Criterion) {
    faer::set_global_parallelism(Par::Seq);
    let a = connection_laplacian(LEVEL);
    let n = a.nrows();
    let b: Vec<Quat<f64>> = (0..n)
        .map(|i| Quat::new(1.0, (i as f64).sin(), (i as f64).cos(), 0.5))
        .collect();

    let symbolic = Arc::new(SymbolicCholesky::analyze(&a).expect("square matrix"));
    let mut native = SparseCholesky::factorize_with_symbolic(symbolic, &a)
        .expect("the benchmark matrix is positive definite");
    let real = a.to_real_block();
    let real_symbolic = SymbolicLlt::try_new(real.symbolic(), Side::Lower).expect("square");
    let complex = a.to_complex_adjoint();
    let complex_symbolic = SymbolicLlt::try_new(complex.symbolic(), Side::Lower).expect("square");

    let mut group = c.benchmark_group(format!("cholesky_factor/n={n}"));
    group.bench_function("native", |bench| {
        bench.iter(|| {
            native
                .refactorize(black_box(&a))
                .expect("positive definite")
        })
    });
    group.bench_function("real_block", |bench| {
        bench.iter(|| {
            Llt::try_new_with_symbolic(
                real_symbolic.clone(),
                black_box(&real).as_ref(),
                Side::Lower,
            )
            .expect("positive definite")
        })
    });
    group.bench_function("complex_adjoint", |bench| {
        bench.iter(|| {
            Llt::try_new_with_symbolic(
                complex_symbolic.clone(),
                black_box(&complex).as_ref(),
                Side::Lower,
            )
            .expect("positive definite")
        })
    });
    group.finish();

    let real_llt = Llt::try_new_with_symbolic(real_symbolic, real.as_ref(), Side::Lower)
        .expect("positive definite");
    let complex_llt = Llt::try_new_with_symbolic(complex_symbolic, complex.as_ref(), Side::Lower)
        .expect("positive definite");
    let mut group = c.benchmark_group(format!("cholesky_solve/n={n}"));
    let mut x = b.clone();
    group.bench_function("native", |bench| {
        bench.iter(|| {
            x.copy_from_slice(black_box(&b));
            native.solve_in_place(&mut x).expect("matching length");
        })
    });
    let b_real = Col::<f64>::from_fn(4 * n, |i| Quat::as_reals(&b)[i]);
    let mut x_real = b_real.clone();
    group.bench_function("real_block", |bench| {
        bench.iter(|| {
            x_real.copy_from(black_box(&b_real));
            real_llt.solve_in_place(x_real.as_mut());
        })
    });
    let bc = complex_adjoint_vector(&b);
    let b_complex = Col::<c64>::from_fn(2 * n, |i| bc[i]);
    let mut x_complex = b_complex.clone();
    group.bench_function("complex_adjoint", |bench| {
        bench.iter(|| {
            x_complex.copy_from(black_box(&b_complex));
            complex_llt.solve_in_place(x_complex.as_mut());
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    targets = cholesky
}
criterion_main!(benches);
