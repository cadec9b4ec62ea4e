//! The `eigs` case of the `compare` harness: `k` quaternionic eigenpairs of the quaternionic
//! Laplacian pencil `M x = μ (L + εM) x` (`L⊗I`, `M⊗I`, constants deflated) on an icosphere,
//! with the native quaternion Lanczos, the same Lanczos on the real-block and complex-adjoint
//! embeddings, faer's `partial_self_adjoint_eigen` on the real-block operator `C⁻¹ K C⁻ᵀ`, and
//! the same code on the real scalar Laplacian (`real-scalar`), in one run.

use std::sync::Mutex;
use std::time::Instant;

use dirac::generators::icosphere;
use dirac::geometry::{barycentric_masses, cotan_laplacian};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::matrix_free::LinOp;
use faer::matrix_free::eigen::{
    PartialEigenParams, partial_self_adjoint_eigen, partial_self_adjoint_eigen_scratch,
};
use faer::{Col, Mat, MatMut, MatRef, Par};
use qeig::{
    Backend, ComplexAdjoint, Eigen, HermitianOperator, LanczosOptions, Native, Pencil, RealBlock,
    RealBlockOperator, Which,
};
use qscalar::{Quat, Scalar};
use qsparse::{SparseMatrix, TripletMatrix};
use serde_json::{Value, json};

use crate::median;

/// Regularisation `ε` of the Laplacian pencil (unit sphere: eigenvalues `l(l+1)`).
const EPSILON: f64 = 1e-3;
/// Relative residual tolerance of every solver.
const TOLERANCE: f64 = 1e-8;

/// `K = M`, `S = L + εM` over `T` (real entries), from the real cotan Laplacian and masses.
fn laplacian_pencil<T: Scalar<Real = f64>>(
    laplacian: &SparseMatrix<f64>,
    mass: &[f64],
) -> (SparseMatrix<T>, SparseMatrix<T>) {
    let n = mass.len();
    let k = SparseMatrix::from_diagonal(&mass.iter().map(|&m| T::from_real(m)).collect::<Vec<_>>());
    let mut t = TripletMatrix::with_capacity(n, n, laplacian.nnz() + n);
    for (i, j, v) in laplacian.triplets() {
        t.push(i, j, T::from_real(v)).expect("valid entry");
    }
    for (i, &m) in mass.iter().enumerate() {
        t.push(i, i, T::from_real(EPSILON * m))
            .expect("valid entry");
    }
    (k, t.to_csc())
}

/// Median seconds over `repeats` runs and the result of the last run.
fn timed<R>(repeats: usize, mut f: impl FnMut() -> R) -> (f64, R) {
    let mut samples = Vec::new();
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        last = Some(f());
        samples.push(start.elapsed().as_secs_f64());
    }
    (median(&mut samples), last.expect("at least one run"))
}

fn summary<T>(seconds: f64, result: &Result<Eigen<T>, qeig::EigError<T>>) -> Value {
    match result {
        Ok(e) => {
            let s = &e.statistics;
            json!({
                "seconds": seconds,
                "converged": e.values.len(),
                "max_residual": e.residuals.iter().fold(0.0f64, |m, &r| m.max(r)),
                "operator_applications": s.operator_applications,
                "restarts": s.restarts,
                "rounds": s.rounds,
                "factorization_seconds": s.factorization_time.as_secs_f64(),
                "solve_seconds": s.solve_time.as_secs_f64(),
                "orthogonalization_seconds": s.orthogonalization_time.as_secs_f64(),
                "basis_columns_read": s.basis_columns_read,
                "eigenvalues": e.values,
            })
        }
        Err(e) => json!({ "seconds": seconds, "converged": 0, "error": e.to_string() }),
    }
}

fn solve<T: Scalar<Real = f64>, B: Backend<T>>(
    backend: &B,
    k_mat: &SparseMatrix<T>,
    s_mat: &SparseMatrix<T>,
    k: usize,
    repeats: usize,
) -> Value {
    let n = k_mat.nrows();
    let options = LanczosOptions {
        tolerance: TOLERANCE,
        ..LanczosOptions::new(k, Which::LargestMagnitude)
    };
    let (seconds, result) = timed(repeats, || {
        Pencil::new(k_mat, s_mat)
            // `S`-orthogonality to the constants: the constraint `(S 𝟙)ᴴ x = 0`.
            .and_then(|p| {
                let constant = image(s_mat, &vec![T::one(); n]);
                p.with_constraints(
                    SparseMatrix::from_dense_columns(n, &[constant]).expect("a finite column"),
                )
            })
            .and_then(|p| p.solve(backend, &options))
    });
    summary(seconds, &result)
}

/// The real-block operator `C⁻¹ K C⁻ᵀ` as a faer `LinOp` (the deflation of the constants is
/// not available there; faer is asked for `4k + 4` values to include the constant's copies).
#[derive(Debug)]
struct FaerOperator(Mutex<RealBlockOperator>, usize);

impl LinOp<f64> for FaerOperator {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }
    fn nrows(&self) -> usize {
        self.1
    }
    fn ncols(&self) -> usize {
        self.1
    }
    fn apply(
        &self,
        mut out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        _par: Par,
        _stack: &mut MemStack,
    ) {
        let mut op = self.0.lock().expect("not poisoned");
        let (mut x, mut y) = (vec![0.0; self.1], vec![0.0; self.1]);
        for c in 0..rhs.ncols() {
            for i in 0..self.1 {
                x[i] = rhs[(i, c)];
            }
            op.apply(&x, &mut y);
            for i in 0..self.1 {
                out[(i, c)] = y[i];
            }
        }
    }
    fn conj_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        self.apply(out, rhs, par, stack);
    }
}

fn faer_partial(
    k_mat: &SparseMatrix<Quat<f64>>,
    s_mat: &SparseMatrix<Quat<f64>>,
    k: usize,
    repeats: usize,
) -> Value {
    let wanted = 4 * k + 4;
    let (seconds, converged) = timed(repeats, || {
        let op = <RealBlock as Backend<Quat<f64>>>::prepare(&RealBlock, k_mat, s_mat)
            .expect("S is positive definite");
        let n = op.dim();
        let op = FaerOperator(Mutex::new(op), n);
        let params = PartialEigenParams {
            max_dim: 2 * wanted,
            max_restarts: 1000,
            ..Default::default()
        };
        let mut mem = MemBuffer::new(partial_self_adjoint_eigen_scratch::<f64>(
            &op,
            wanted,
            Par::Seq,
            params,
        ));
        let mut vecs = Mat::<f64>::zeros(n, wanted);
        let mut vals = vec![0.0; wanted];
        let v0 = Col::<f64>::from_fn(n, |i| ((i as f64) * 0.618).sin() + 0.1);
        let info = partial_self_adjoint_eigen(
            vecs.as_mut(),
            &mut vals,
            &op,
            v0.as_ref(),
            TOLERANCE,
            Par::Seq,
            MemStack::new(&mut mem),
            params,
        );
        info.n_converged_eigen
    });
    json!({ "seconds": seconds, "converged_real": converged, "wanted_real": wanted })
}

/// Every case of [`compare_eigs_cases`].
pub const EIGS_CASES: [&str; 5] = [
    "native",
    "real-scalar",
    "real-block",
    "complex-adjoint",
    "faer-partial-real-block",
];

/// `compare eigs --level L -k K [--cases …]`: one JSON object with each case's median seconds
/// over `repeats` runs, converged counts, solver statistics, the eigenvalues `μ` of the last
/// run, and the ratios of the issue (those whose cases ran).
pub fn compare_eigs_cases(level: u32, k: usize, repeats: usize, cases: &[&str]) -> Value {
    let mesh = icosphere(level);
    let laplacian = cotan_laplacian(&mesh);
    let mass = barycentric_masses(&mesh);
    let (kq, sq) = laplacian_pencil::<Quat<f64>>(&laplacian, &mass);
    let (kr, sr) = laplacian_pencil::<f64>(&laplacian, &mass);
    let mut report = json!({
        "case": "eigs",
        "level": level,
        "vertices": mesh.vertex_count(),
        "k": k,
        "repeats": repeats,
        "tolerance": TOLERANCE,
        "epsilon": EPSILON,
    });
    for &case in cases {
        let value = match case {
            "native" => solve(&Native, &kq, &sq, k, repeats),
            "real-scalar" => solve(&Native, &kr, &sr, k, repeats),
            "real-block" => solve(&RealBlock, &kq, &sq, k, repeats),
            "complex-adjoint" => solve(&ComplexAdjoint, &kq, &sq, k, repeats),
            "faer-partial-real-block" => faer_partial(&kq, &sq, k, repeats),
            other => json!({ "error": format!("unknown case {other}") }),
        };
        report[case] = value;
    }
    let secs = |case: &str| report[case]["seconds"].as_f64().unwrap_or(f64::NAN);
    let best_embedded = ["real-block", "complex-adjoint", "faer-partial-real-block"]
        .iter()
        .map(|c| secs(c))
        .filter(|s| s.is_finite())
        .fold(f64::INFINITY, f64::min);
    report["ratios"] = json!({
        "best_embedded_over_native": best_embedded / secs("native"),
        "native_over_real_scalar": secs("native") / secs("real-scalar"),
    });
    report
}

/// `S x`.
fn image<T: Scalar<Real = f64>>(s: &SparseMatrix<T>, x: &[T]) -> Vec<T> {
    let mut y = vec![T::zero(); x.len()];
    s.mul_vec(x, &mut y)
        .expect("square matrix of the vector's size");
    y
}
