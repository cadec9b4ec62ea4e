//! The `spmv` and `cholesky` cases of the `compare` harness: the same quaternionic matrix as
//! native `SparseMatrix<Quat<f64>>`, as its 4n×4n real-block expansion and as its 2n×2n complex
//! adjoint (both faer), timed in one run.

use faer::linalg::solvers::Solve;
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::cholesky::{SymmetricOrdering, factorize_symbolic_cholesky};
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::{Col, Side, c64};
use qscalar::{Quat, Scalar};
use qsparse::embedding::complex_adjoint_vector;
use qsparse::{FillOrdering, SparseCholesky, SparseMatrix, SymbolicCholesky};
use serde_json::{Value, json};
use std::sync::Arc;
use std::time::Instant;

use crate::{median, time_median};

/// A deterministic test vector with entries of size about one.
fn test_vector(n: usize) -> Vec<Quat<f64>> {
    (0..n)
        .map(|i| {
            let t = i as f64;
            Quat::new(
                (0.37 * t).sin(),
                (0.11 * t).cos(),
                (0.05 * t + 1.0).sin(),
                0.5,
            )
        })
        .collect()
}

/// Entries faer stores for the Cholesky factor of a matrix with this pattern.
fn faer_factor_entries(pattern: SymbolicSparseColMatRef<'_, usize>) -> usize {
    factorize_symbolic_cholesky(
        pattern,
        Side::Lower,
        SymmetricOrdering::Amd,
        Default::default(),
    )
    .expect("square pattern")
    .len_val()
}

fn ratio(numerator: f64, denominator: f64) -> f64 {
    numerator / denominator
}

/// Times `y = A x` natively (scattered by columns, `mul_vec`, and gathered from the columns
/// of the Hermitian `A` as `Aᴴ x`, `adjoint_mul_vec`, on one thread and on two) and on both
/// embeddings.
pub fn compare_spmv(a: &SparseMatrix<Quat<f64>>, repeats: usize) -> Value {
    let n = a.nrows();
    let x = test_vector(n);
    let mut y = vec![Quat::default(); n];
    let native = time_median(repeats, || a.mul_vec(&x, &mut y).expect("square matrix"));
    let scattered_one_thread = time_median(repeats, || {
        qsparse::threads::on_one_thread(|| a.mul_vec(&x, &mut y)).expect("square matrix")
    });
    let gathered = time_median(repeats, || {
        a.adjoint_mul_vec(&x, &mut y).expect("square matrix")
    });
    let gathered_one_thread = time_median(repeats, || {
        qsparse::threads::on_one_thread(|| a.adjoint_mul_vec(&x, &mut y)).expect("square matrix")
    });

    let real = a.to_real_block();
    let x_real = Col::<f64>::from_fn(4 * n, |i| Quat::as_reals(&x)[i]);
    let mut check = 0.0;
    let real_block = time_median(repeats, || {
        let y = &real * &x_real;
        check = y[0];
    });

    let complex = a.to_complex_adjoint();
    let xc = complex_adjoint_vector(&x);
    let x_complex = Col::<c64>::from_fn(2 * n, |i| xc[i]);
    let complex_adjoint = time_median(repeats, || {
        let y = &complex * &x_complex;
        check += y[0].re;
    });
    std::hint::black_box(check);
    json!({
        "case": "spmv",
        "quaternion_unknowns": n,
        "nnz": { "native": a.nnz(), "real_block": real.compute_nnz(), "complex_adjoint": complex.compute_nnz() },
        "median_seconds": {
            "native": native,
            "native_one_thread": scattered_one_thread,
            "native_hermitian_gathered": gathered,
            "native_hermitian_gathered_one_thread": gathered_one_thread,
            "real_block": real_block,
            "complex_adjoint": complex_adjoint,
        },
        "ratios": {
            "scattered_over_gathered": ratio(native, gathered),
            "real_block_over_native": ratio(real_block, native),
            "complex_adjoint_over_native": ratio(complex_adjoint, native),
        },
    })
}

/// Times the numeric Cholesky factorisation (symbolic analysis done once, outside the timing)
/// and one solve natively and on both embeddings; reports factor memory (stored values).
pub fn compare_cholesky(a: &SparseMatrix<Quat<f64>>, repeats: usize) -> Value {
    let n = a.nrows();
    let b = test_vector(n);

    let symbolic = Arc::new(SymbolicCholesky::analyze(a).expect("square matrix"));
    let mut native = SparseCholesky::factorize_with_symbolic(symbolic.clone(), a)
        .expect("the benchmark matrix is positive definite");
    let native_factor = time_median(repeats, || {
        native.refactorize(a).expect("positive definite")
    });
    let mut x = b.clone();
    let native_solve = time_median(repeats, || {
        x.copy_from_slice(&b);
        native.solve_in_place(&mut x).expect("matching length");
    });
    let native_stats = native.stats();

    let real = a.to_real_block();
    let real_symbolic = SymbolicLlt::try_new(real.symbolic(), Side::Lower).expect("square");
    let mut real_llt = None;
    let real_factor = time_median(repeats, || {
        real_llt = Some(
            Llt::try_new_with_symbolic(real_symbolic.clone(), real.as_ref(), Side::Lower)
                .expect("positive definite"),
        );
    });
    let real_llt = real_llt.expect("factored at least once");
    let b_real = Col::<f64>::from_fn(4 * n, |i| Quat::as_reals(&b)[i]);
    let real_solve = time_median(repeats, || {
        std::hint::black_box(real_llt.solve(&b_real));
    });

    let complex = a.to_complex_adjoint();
    let complex_symbolic = SymbolicLlt::try_new(complex.symbolic(), Side::Lower).expect("square");
    let mut complex_llt = None;
    let complex_factor = time_median(repeats, || {
        complex_llt = Some(
            Llt::try_new_with_symbolic(complex_symbolic.clone(), complex.as_ref(), Side::Lower)
                .expect("positive definite"),
        );
    });
    let complex_llt = complex_llt.expect("factored at least once");
    let bc = complex_adjoint_vector(&b);
    let b_complex = Col::<c64>::from_fn(2 * n, |i| bc[i]);
    let complex_solve = time_median(repeats, || {
        std::hint::black_box(complex_llt.solve(&b_complex));
    });

    // Stored factor values: native quaternions (32 bytes), real-block f64 (8), complex (16).
    // faer's high-level `SymbolicLlt` does not expose its size; the low-level analysis (same
    // AMD ordering and supernodes) does.
    let real_bytes = faer_factor_entries(real.symbolic()) * 8;
    let complex_bytes = faer_factor_entries(complex.symbolic()) * 16;
    json!({
        "case": "cholesky",
        "quaternion_unknowns": n,
        "nnz": a.nnz(),
        "median_seconds": {
            "native_factor": native_factor,
            "real_block_factor": real_factor,
            "complex_adjoint_factor": complex_factor,
            "native_solve": native_solve,
            "real_block_solve": real_solve,
            "complex_adjoint_solve": complex_solve,
        },
        "factor_bytes": { "native": native_stats.factor_bytes, "real_block": real_bytes, "complex_adjoint": complex_bytes },
        "native_supernodes": native_stats.supernodes,
        "native_max_supernode_width": native_stats.max_supernode_width,
        "ratios": {
            "real_block_factor_over_native": ratio(real_factor, native_factor),
            "complex_adjoint_factor_over_native": ratio(complex_factor, native_factor),
            "real_block_solve_over_native": ratio(real_solve, native_solve),
            "complex_adjoint_solve_over_native": ratio(complex_solve, native_solve),
            "native_memory_over_real_block": native_stats.factor_bytes as f64 / real_bytes as f64,
        },
    })
}

/// Relative residual `‖A x − b‖ / ‖b‖`.
fn relative_residual(a: &SparseMatrix<Quat<f64>>, x: &[Quat<f64>], b: &[Quat<f64>]) -> f64 {
    let mut ax = vec![Quat::default(); x.len()];
    a.mul_vec(x, &mut ax).expect("square matrix");
    let norm = |v: &mut dyn Iterator<Item = Quat<f64>>| v.map(|q| q.norm_sqr()).sum::<f64>().sqrt();
    norm(&mut ax.iter().zip(b).map(|(&p, &q)| p - q)) / norm(&mut b.iter().copied())
}

/// The native factorisation with each fill-reducing ordering ([`FillOrdering::Amd`] and
/// [`FillOrdering::NestedDissection`]) on the same matrix: fill (factor entries and bytes),
/// median seconds of the symbolic analysis, of the numeric factorisation (the first one
/// counts, so `repeats = 1` times each phase once) and of one solve, and the relative residual
/// of each solution and their relative distance.
pub fn compare_orderings(a: &SparseMatrix<Quat<f64>>, repeats: usize) -> Value {
    let n = a.nrows();
    let b = test_vector(n);
    let mut report = serde_json::Map::new();
    let mut solutions = Vec::new();
    for (name, ordering) in [
        ("amd", FillOrdering::Amd),
        ("nested_dissection", FillOrdering::NestedDissection),
    ] {
        let mut symbolic = None;
        let mut symbolic_seconds = Vec::new();
        for _ in 0..repeats.max(1) {
            let start = Instant::now();
            symbolic = Some(SymbolicCholesky::analyze_with_ordering(a, ordering).expect("square"));
            symbolic_seconds.push(start.elapsed().as_secs_f64());
        }
        let symbolic = Arc::new(symbolic.expect("analysed at least once"));
        let start = Instant::now();
        let mut factor = SparseCholesky::factorize_with_symbolic(symbolic, a)
            .expect("the benchmark matrix is positive definite");
        let mut factor_seconds = vec![start.elapsed().as_secs_f64()];
        for _ in 1..repeats.max(1) {
            let start = Instant::now();
            factor.refactorize(a).expect("positive definite");
            factor_seconds.push(start.elapsed().as_secs_f64());
        }
        let mut x = b.clone();
        let solve = time_median(repeats, || {
            x.copy_from_slice(&b);
            factor.solve_in_place(&mut x).expect("matching length");
        });
        let stats = factor.stats();
        report.insert(
            name.into(),
            json!({
                "factor_entries": stats.factor_entries,
                "factor_megabytes": stats.factor_bytes as f64 / 1e6,
                "supernodes": stats.supernodes,
                "max_supernode_width": stats.max_supernode_width,
                "median_seconds": {
                    "symbolic": median(&mut symbolic_seconds),
                    "factor": median(&mut factor_seconds),
                    "solve": solve,
                },
                "relative_residual": relative_residual(a, &x, &b),
            }),
        );
        solutions.push(x);
    }
    let difference = solutions[0]
        .iter()
        .zip(&solutions[1])
        .map(|(&p, &q)| (p - q).norm_sqr())
        .sum::<f64>()
        .sqrt()
        / solutions[0]
            .iter()
            .map(|q| q.norm_sqr())
            .sum::<f64>()
            .sqrt();
    report.insert("case".into(), json!("ordering"));
    report.insert("quaternion_unknowns".into(), json!(n));
    report.insert("nnz".into(), json!(a.nnz()));
    report.insert("solution_relative_difference".into(), json!(difference));
    Value::Object(report)
}
