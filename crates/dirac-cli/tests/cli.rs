//! End-to-end tests of the `dirac` binary: JSON output against the library, closed-form
//! Laplace eigenvalues, and the exit codes of bad input.

use std::fs;
use std::path::PathBuf;
use std::process::{Command, Output};

use dirac::TriMesh;
use dirac::generators::icosphere;
use dirac::spectrum::{Operator, SpectrumOptions, spectrum};
use serde_json::Value;

/// Runs `dirac` with `args`.
fn dirac(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dirac"))
        .args(args)
        .output()
        .expect("the dirac binary runs")
}

/// Writes `mesh` as an OFF file (by hand, so the reader is exercised independently of any
/// writer) and returns its path.
fn write_off(mesh: &TriMesh, name: &str) -> PathBuf {
    let mut text = format!("OFF\n{} {} 0\n", mesh.vertex_count(), mesh.face_count());
    for [x, y, z] in mesh.positions() {
        text += &format!("{x} {y} {z}\n");
    }
    for [i, j, k] in mesh.faces() {
        text += &format!("3 {i} {j} {k}\n");
    }
    write_file(name, &text)
}

fn write_file(name: &str, contents: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    fs::write(&path, contents).expect("the temporary directory is writable");
    path
}

/// Parses stdout as the one JSON object of a successful run.
fn json(output: &Output) -> Value {
    assert!(
        output.status.success(),
        "exit {:?}, stderr: {}",
        output.status.code(),
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).expect("stdout is one JSON object")
}

fn numbers(value: &Value) -> Vec<f64> {
    value
        .as_array()
        .expect("an array")
        .iter()
        .map(|v| v.as_f64().expect("a number"))
        .collect()
}

#[test]
fn json_output_is_complete_and_agrees_with_the_library() {
    let mesh = icosphere(2);
    let path = write_off(&mesh, "icosphere2_dirac.off");
    let k = 6;
    let output = dirac(&[
        "spectrum",
        path.to_str().expect("UTF-8 path"),
        "--operator",
        "relative-dirac",
        "-k",
        &k.to_string(),
        "--json",
        "--quiet",
    ]);
    let report = json(&output);

    for key in [
        "mesh",
        "vertices",
        "faces",
        "operator",
        "tau",
        "k",
        "backend",
        "normalize",
        "eigenvalues",
        "residuals",
        "statistics",
        "timings",
        "converged",
    ] {
        assert!(report.get(key).is_some(), "missing key {key}: {report}");
    }
    for key in [
        "iterations",
        "restarts",
        "rounds",
        "operator_applications",
        "solves",
    ] {
        assert!(report["statistics"][key].is_u64(), "statistics.{key}");
    }
    for key in [
        "load",
        "assemble_and_solve",
        "factorization",
        "solves",
        "orthogonalization",
    ] {
        assert!(
            report["timings"][key].as_f64().is_some_and(|t| t >= 0.0),
            "timings.{key}"
        );
    }
    assert_eq!(report["mesh"], path.display().to_string());
    assert_eq!(report["vertices"], mesh.vertex_count());
    assert_eq!(report["faces"], mesh.face_count());
    assert_eq!(report["operator"], "relative-dirac");
    assert!(report["tau"].is_null());
    assert_eq!(report["k"], k);
    assert_eq!(report["backend"], "native");
    assert_eq!(report["normalize"], "none");
    assert_eq!(report["converged"], true);

    let eigenvalues = numbers(&report["eigenvalues"]);
    assert_eq!(eigenvalues.len(), k);
    assert_eq!(numbers(&report["residuals"]).len(), k);
    assert!(
        eigenvalues.windows(2).all(|w| w[0].abs() <= w[1].abs()),
        "not sorted by |λ|: {eigenvalues:?}"
    );

    let library = spectrum(&mesh, &SpectrumOptions::new(Operator::RelativeDirac, k))
        .expect("the library solves the same problem");
    for (binary, library) in eigenvalues.iter().zip(&library.eigenvalues) {
        assert!(
            (binary - library).abs() <= 1e-8 * library.abs().max(1.0),
            "binary {eigenvalues:?} vs library {:?}",
            library
        );
    }
}

#[test]
fn laplace_on_the_icosphere_matches_the_sphere() {
    let path = write_off(&icosphere(2), "icosphere2_laplace.off");
    let output = dirac(&[
        "spectrum",
        path.to_str().expect("UTF-8 path"),
        "--operator",
        "laplace",
        "-k",
        "4",
        "--json",
    ]);
    let eigenvalues = numbers(&json(&output)["eigenvalues"]);
    // Unit sphere: l(l+1) = 0, 2, 2, 2.
    assert!(eigenvalues[0].abs() < 1e-8, "{eigenvalues:?}");
    for &value in &eigenvalues[1..] {
        assert!((value - 2.0).abs() < 0.06 * 2.0, "{eigenvalues:?}");
    }
}

#[test]
fn family_reports_tau_and_human_output_has_a_table() {
    let path = write_off(&icosphere(1), "icosphere1_family.off");
    let path = path.to_str().expect("UTF-8 path");
    let args = [
        "spectrum",
        path,
        "--operator",
        "family",
        "--tau",
        "0.5",
        "-k",
        "3",
    ];
    let report = json(&dirac(&[&args[..], &["--json"]].concat()));
    assert_eq!(report["operator"], "family");
    assert_eq!(report["tau"], 0.5);

    let output = dirac(&args);
    assert!(output.status.success());
    let text = String::from_utf8_lossy(&output.stdout);
    for expected in [
        "42 vertices, 80 faces",
        "eigenvalue",
        "residual",
        "statistics",
        "timings",
    ] {
        assert!(text.contains(expected), "missing {expected:?} in\n{text}");
    }
}

#[test]
fn missing_file_exits_1_naming_it() {
    let output = dirac(&["spectrum", "/nonexistent/cow.obj", "--quiet"]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("/nonexistent/cow.obj"), "{stderr}");
    assert!(output.stdout.is_empty());
}

#[test]
fn malformed_file_exits_1_naming_file_and_line() {
    let path = write_file(
        "malformed.off",
        "OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n",
    );
    let output = dirac(&["spectrum", path.to_str().expect("UTF-8 path")]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("malformed.off"), "{stderr}");
    assert!(stderr.contains("line 4"), "{stderr}");
}

#[test]
fn family_without_tau_is_a_usage_error() {
    for operator in ["family", "family-literal"] {
        let output = dirac(&["spectrum", "--operator", operator]);
        assert_eq!(output.status.code(), Some(2));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains("needs --tau"), "{stderr}");
    }
    let output = dirac(&["spectrum", "--operator", "laplace", "--tau", "0.5"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("--tau applies only"));
}

#[test]
fn default_mesh_runs() {
    let report = json(&dirac(&["spectrum", "-k", "6", "--json"]));
    assert_eq!(report["mesh"], "spot (built-in)");
    assert_eq!(report["vertices"], 2930);
    assert_eq!(numbers(&report["eigenvalues"]).len(), 6);
}

#[test]
fn non_convergence_exits_3_with_the_partial_result() {
    let path = write_off(&icosphere(3), "icosphere3_tight.off");
    let output = dirac(&[
        "spectrum",
        path.to_str().expect("UTF-8 path"),
        "-k",
        "12",
        "--tolerance",
        "1e-14",
        "--max-restarts",
        "1",
        "--json",
    ]);
    assert_eq!(output.status.code(), Some(3));
    let report: Value = serde_json::from_slice(&output.stdout).expect("stdout is one JSON object");
    assert_eq!(report["converged"], false);
    let converged = numbers(&report["eigenvalues"]).len();
    assert!(converged < 12);
    assert_eq!(numbers(&report["residuals"]).len(), converged);
    assert!(String::from_utf8_lossy(&output.stderr).contains("converged only"));
}
