//! The operator cases of `compare eigs`: a spectrum of the paper's pencils (`dirac::spectrum`)
//! computed with every `qeig` backend in one run, on an icosphere or a mesh file.

use std::time::Instant;

use dirac::TriMesh;
use dirac::spectrum::{Operator, SolverBackend, SpectrumOptions, spectrum};
use serde_json::{Value, json};

use crate::median;

/// Times `k` eigenvalues of `operator` on `mesh` with the native, real-block and
/// complex-adjoint backends (median over `repeats` runs each) and reports the ratios and the
/// largest eigenvalue difference between backends.
pub fn compare_spectrum(
    mesh: &TriMesh,
    label: &str,
    operator: Operator,
    k: usize,
    repeats: usize,
) -> Value {
    let backends = [
        ("native", SolverBackend::Native),
        ("real-block", SolverBackend::RealBlock),
        ("complex-adjoint", SolverBackend::ComplexAdjoint),
    ];
    let mut report = serde_json::Map::new();
    let mut medians = Vec::new();
    let mut reference: Option<Vec<f64>> = None;
    let mut max_difference: f64 = 0.0;
    for (name, backend) in backends {
        let mut options = SpectrumOptions::new(operator, k);
        options.backend = backend;
        let mut samples = Vec::new();
        let mut last = None;
        for _ in 0..repeats.max(1) {
            let start = Instant::now();
            last = Some(spectrum(mesh, &options));
            samples.push(start.elapsed().as_secs_f64());
        }
        let seconds = median(&mut samples);
        medians.push(seconds);
        let entry = match last.expect("at least one run") {
            Ok(s) => {
                if let Some(r) = &reference {
                    for (a, b) in r.iter().zip(&s.eigenvalues) {
                        max_difference = max_difference.max((a - b).abs() / a.abs().max(1e-300));
                    }
                } else {
                    reference = Some(s.eigenvalues.clone());
                }
                json!({
                    "seconds": seconds,
                    "converged": s.eigenvalues.len(),
                    "operator_applications": s.statistics.operator_applications,
                    "rounds": s.statistics.rounds,
                    "factorization_seconds": s.statistics.factorization_time.as_secs_f64(),
                    "solve_seconds": s.statistics.solve_time.as_secs_f64(),
                    "orthogonalization_seconds": s.statistics.orthogonalization_time.as_secs_f64(),
                    "basis_columns_read": s.statistics.basis_columns_read,
                    "max_residual": s.residuals.iter().copied().fold(0.0, f64::max),
                })
            }
            Err(e) => json!({ "seconds": seconds, "error": e.to_string() }),
        };
        report.insert(name.into(), entry);
    }
    report.insert("case".into(), json!("eigs"));
    report.insert("mesh".into(), json!(label));
    report.insert("vertices".into(), json!(mesh.vertex_count()));
    report.insert("operator".into(), json!(format!("{operator:?}")));
    report.insert("k".into(), json!(k));
    report.insert("repeats".into(), json!(repeats));
    report.insert(
        "max_relative_eigenvalue_difference".into(),
        json!(max_difference),
    );
    report.insert(
        "ratios".into(),
        json!({
            "real_block_over_native": medians[1] / medians[0],
            "complex_adjoint_over_native": medians[2] / medians[0],
        }),
    );
    Value::Object(report)
}
