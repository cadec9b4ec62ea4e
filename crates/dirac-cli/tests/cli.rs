//! End-to-end tests of the `dirac` binary: JSON output against the library, closed-form
//! Laplace eigenvalues, and the exit codes of bad input.

mod support;

use std::fs;
use std::process::Output;

use dirac::generators::icosphere;
use dirac::spectrum::Operator;
use serde_json::Value;

use support::{
    assert_success, assert_usage_errors, dirac, library, stderr, temporary, text, write_off,
};

/// Parses stdout as the one JSON object of a successful run.
fn json(output: &Output) -> Value {
    assert_success(output);
    serde_json::from_slice(&output.stdout).expect("stdout is one JSON object")
}

/// The numbers of a JSON array.
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
    let path = write_off(&mesh, temporary("icosphere2_dirac.off"));
    let k = 6;
    let output = dirac(&[
        "spectrum",
        text(&path),
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
        "backward_errors",
        "backward_error_floor",
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
        "basis_columns_read",
        "factor_bytes",
        "basis_bytes",
        "eigenvector_bytes",
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
    // Every reported pair passed the convergence rule of docs/MATH.md with its two numbers.
    let rule = numbers(&report["residuals"])
        .into_iter()
        .zip(numbers(&report["backward_errors"]))
        .all(|(relative, backward)| relative <= 100.0 * 1e-10 || backward <= 1e3 * f64::EPSILON);
    assert!(rule, "a reported pair fails the convergence rule: {report}");
    assert!(
        eigenvalues.windows(2).all(|w| w[0].abs() <= w[1].abs()),
        "not sorted by |λ|: {eigenvalues:?}"
    );

    let library = library(&mesh, Operator::RelativeDirac, k);
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
    let path = write_off(&icosphere(2), temporary("icosphere2_laplace.off"));
    let output = dirac(&[
        "spectrum",
        text(&path),
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
    let path = write_off(&icosphere(1), temporary("icosphere1_family.off"));
    let path = text(&path);
    let args = ["spectrum", path, "--operator", "family:0.5", "-k", "3"];
    let report = json(&dirac(&[&args[..], &["--json"]].concat()));
    assert_eq!(report["operator"], "family");
    assert_eq!(report["tau"], 0.5);

    let output = dirac(&args);
    assert!(output.status.success());
    let table = String::from_utf8_lossy(&output.stdout);
    for expected in [
        "42 vertices, 80 faces",
        "eigenvalue",
        "residual",
        "backward error",
        "statistics",
        "timings",
    ] {
        assert!(table.contains(expected), "missing {expected:?} in\n{table}");
    }
}

/// The family weighs D_N by scale: on a mesh in other units than the unit-area one (here an
/// icosphere of area 1.2e-3) the command warns, with the weight T amounts to at unit area, and
/// with --normalize unit-area it does not.
#[test]
fn the_family_warns_of_a_mesh_far_from_unit_area() {
    let small = icosphere(1).map_positions(|p| p.map(|c| 1e-2 * c)).unwrap();
    let path = write_off(&small, temporary("small_icosphere1_family.off"));
    let args = [
        "spectrum",
        text(&path),
        "--operator",
        "family:0.5",
        "-k",
        "3",
    ];
    let output = dirac(&args);
    assert_success(&output);
    let message = stderr(&output);
    assert!(message.contains("warning:"), "{message}");
    assert!(
        message.contains("the weight 0.5 of D_N acts as 9.99e-1"),
        "{message}"
    );
    assert!(message.contains("--normalize unit-area"), "{message}");
    let normalized = dirac(&[&args[..], &["--normalize", "unit-area"]].concat());
    assert_success(&normalized);
    assert!(
        !stderr(&normalized).contains("warning"),
        "{}",
        stderr(&normalized)
    );
}

#[test]
fn anisotropic_laplace_reports_its_anisotropy_and_scales_laplace_on_a_sphere() {
    let path = write_off(&icosphere(2), temporary("icosphere2_anisotropic.off"));
    let path = text(&path);
    let run = |operator: &str| {
        json(&dirac(&[
            "spectrum",
            path,
            "--operator",
            operator,
            "-k",
            "4",
            "--json",
        ]))
    };
    let report = run("anisotropic-laplace:1");
    assert_eq!(report["operator"], "anisotropic-laplace");
    assert_eq!(report["anisotropy"], 1.0);
    assert_eq!(report["tau"], Value::Null);
    assert_eq!(report["kernel_dimension"], 1);
    // Unit sphere: both curvatures 1, conductivity 1/(1 + 1·1) = 1/2 in every direction.
    let anisotropic = numbers(&report["eigenvalues"]);
    let laplace = numbers(&run("laplace")["eigenvalues"]);
    assert!(anisotropic[0].abs() < 1e-8, "{anisotropic:?}");
    for (a, l) in anisotropic.iter().zip(&laplace).skip(1) {
        assert!(
            (a - 0.5 * l).abs() < 0.02 * l,
            "{anisotropic:?} vs ½ {laplace:?}"
        );
    }
    let output = dirac(&[
        "spectrum",
        path,
        "--operator",
        "anisotropic-laplace:1",
        "-k",
        "2",
    ]);
    assert!(String::from_utf8_lossy(&output.stdout).contains("(anisotropy = 1)"));
}

#[test]
fn missing_file_exits_1_naming_it() {
    let output = dirac(&["spectrum", "/nonexistent/cow.obj", "--quiet"]);
    assert_eq!(output.status.code(), Some(1));
    let message = stderr(&output);
    assert!(message.contains("/nonexistent/cow.obj"), "{message}");
    assert!(output.stdout.is_empty());
}

#[test]
fn a_directory_given_as_a_mesh_exits_1_pointing_to_batch() {
    let directory = temporary("meshes.obj");
    fs::create_dir_all(&directory).expect("the temporary directory is writable");
    let output = dirac(&["spectrum", text(&directory), "--quiet"]);
    assert_eq!(output.status.code(), Some(1));
    let message = stderr(&output);
    assert!(
        message.contains("is a directory, not a mesh file"),
        "{message}"
    );
    assert!(message.contains("`dirac batch`"), "{message}");
}

/// A square with a flap glued to one edge whose apex is `1e-12` off it: a valid mesh with one
/// sliver face (height `1e-12` against a diagonal of `√2`). The spectrum is computed, with a
/// warning that names the face and `--repair`, and the JSON report counts it.
#[test]
fn a_sliver_is_warned_of_and_counted() {
    let path = temporary("flap.obj");
    fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 -1e-12 0\nf 1 2 3\nf 1 3 4\nf 2 1 5\n",
    )
    .expect("the temporary directory is writable");
    let laplace = |extra: &str| {
        dirac(&[
            "spectrum",
            text(&path),
            "--operator",
            "laplace",
            "-k",
            "2",
            extra,
        ])
    };
    let output = laplace("--json");
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let message = stderr(&output);
    assert!(
        message.contains("warning: ") && message.contains("1 sliver face (face 2)"),
        "{message}"
    );
    assert!(message.contains("--repair"), "{message}");
    let slivers = &json(&output)["preparation"]["slivers"];
    assert_eq!(slivers["count"], 1);
    assert_eq!(slivers["examples"][0], 2);
    // Repaired, the flap is gone and so is the warning.
    let output = laplace("--repair");
    assert!(!stderr(&output).contains("sliver"), "{}", stderr(&output));
}

#[test]
fn malformed_file_exits_1_naming_file_and_line() {
    let path = temporary("malformed.off");
    fs::write(&path, "OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n")
        .expect("the temporary directory is writable");
    let output = dirac(&["spectrum", text(&path)]);
    assert_eq!(output.status.code(), Some(1));
    let message = stderr(&output);
    assert!(message.contains("malformed.off"), "{message}");
    assert!(message.contains("line 4"), "{message}");
}

#[test]
fn badly_written_operators_and_the_former_tau_are_usage_errors() {
    assert_usage_errors(
        &["spectrum"],
        &[
            (&["--operator", "family"], "family:T"),
            (&["--operator", "family-literal"], "family-literal:T"),
            (&["--operator", "family:2"], "outside [0, 1]"),
            (&["--operator", "family:x"], "finite number"),
            (&["--operator", "laplace:0.5"], "takes no parameter"),
            (
                &["--operator", "anisotropic-laplace"],
                "anisotropic-laplace:A",
            ),
            (&["--operator", "anisotropic-laplace:-1"], "outside [0, ∞)"),
            (&["--operator", "dirac"], "relative-dirac"),
            // The old spelling: --operator is read first and says how to write the weight.
            (&["--operator", "family", "--tau", "0.5"], "family:0.5"),
            (
                &["--tau", "0.5"],
                "--tau was replaced by --operator family:T",
            ),
            (&["--tau"], "--tau was replaced by --operator family:T"),
        ],
    );
    let help = dirac(&["spectrum", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(
        help.contains("family:T") && help.contains("modified-dirichlet") && !help.contains("--tau"),
        "{help}"
    );
}

#[test]
fn default_mesh_runs() {
    let report = json(&dirac(&["spectrum", "-k", "6", "--json"]));
    assert_eq!(report["mesh"], "spot (built-in)");
    assert_eq!(report["vertices"], 2930);
    let eigenvalues = numbers(&report["eigenvalues"]);
    assert_eq!(eigenvalues.len(), 6);
    // `--single-thread` gives the same spectrum (by default large factors are solved on two).
    let single = numbers(
        &json(&dirac(&[
            "spectrum",
            "-k",
            "6",
            "--json",
            "--single-thread",
        ]))["eigenvalues"],
    );
    for (a, b) in eigenvalues.iter().zip(&single) {
        assert!(
            (a - b).abs() <= 1e-9 * a.abs(),
            "{eigenvalues:?} vs {single:?}"
        );
    }
}

#[test]
fn non_convergence_exits_3_with_the_partial_result() {
    let path = write_off(&icosphere(3), temporary("icosphere3_tight.off"));
    let output = dirac(&[
        "spectrum",
        text(&path),
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
    assert!(stderr(&output).contains("converged only"));
}

#[test]
fn the_kernel_is_reported_listed_on_request_and_a_plane_is_explained() {
    // The 5×5-per-side cube: 6 (5 − 3)² = 24 flat vertices and the constants.
    let cube = dirac::generators::subdivided_cube(5).unwrap();
    let path = write_off(&cube, temporary("cube5_kernel.off"));
    let plain = json(&dirac(&[
        "spectrum",
        text(&path),
        "-k",
        "3",
        "--json",
        "-q",
    ]));
    assert_eq!(plain["kernel_dimension"], 25);
    assert_eq!(plain["kernel"]["flat_vertices"], 24);
    assert_eq!(plain["include_kernel"], false);
    assert!(
        numbers(&plain["eigenvalues"])
            .iter()
            .all(|l| l.abs() > 1e-3)
    );
    let listed = json(&dirac(&[
        "spectrum",
        text(&path),
        "-k",
        "28",
        "--include-kernel",
        "--json",
        "-q",
    ]));
    let values = numbers(&listed["eigenvalues"]);
    assert!(values[..25].iter().all(|&l| l == 0.0));
    assert_eq!(values[25..], numbers(&plain["eigenvalues"])[..]);
    // Laplace lists its constant by default and drops it on request.
    let laplace = |extra: &[&str]| {
        let mut args = vec!["spectrum", text(&path), "--operator", "laplace", "-k", "2"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--json", "-q"]);
        numbers(&json(&dirac(&args))["eigenvalues"])
    };
    assert_eq!(laplace(&[])[0], 0.0);
    assert!(laplace(&["--exclude-kernel"])[0] > 0.0);

    let plane = dirac::generators::grid(6, 4, 1.5, 1.0).unwrap();
    let path = write_off(&plane, temporary("plane_kernel.off"));
    let output = dirac(&["spectrum", text(&path), "-k", "3"]);
    assert_eq!(output.status.code(), Some(1));
    let message = stderr(&output);
    assert!(
        message.contains("Gauss map is constant") && message.contains("--operator family:T"),
        "{message}"
    );
    // D_f on the plane annihilates a linear function besides the constant, and says so.
    let extrinsic = [
        "spectrum",
        text(&path),
        "--operator",
        "extrinsic-dirac",
        "-k",
        "3",
    ];
    let report = json(&dirac(&[&extrinsic[..], &["--json", "-q"]].concat()));
    assert_eq!(report["kernel_dimension"], 2);
    assert_eq!(report["kernel"]["linear_functions"], 1);
    let table = String::from_utf8(dirac(&extrinsic).stdout).unwrap();
    assert!(
        table.contains("+ 1 constant + 1 linear function;"),
        "{table}"
    );
}
