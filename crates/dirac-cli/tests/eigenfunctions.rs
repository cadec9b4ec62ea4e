//! End-to-end tests of `dirac eigenfunctions`: the `.npy` files load back with the documented
//! shapes and hold the library's eigenpairs (mass-normalised), the `.ply` carries `|φ_I|`, and
//! bad arguments fail with the documented exit codes.

mod support;

use std::fs;

use dirac::generators::icosphere;
use dirac::geometry::barycentric_masses;
use dirac::spectrum::Operator;
use ndarray::{Array1, Array3};
use ndarray_npy::read_npy;

use support::{
    assert_success, assert_usage_errors, bumpy_sphere, dirac, library, scratch, stderr, text,
    write_off,
};

#[test]
fn npy_files_hold_the_library_eigenpairs() {
    let dir = scratch("eigenfunctions_npy");
    // No symmetry, so every eigenvector is unique up to its phase, which the canonical phase
    // fixes.
    let mesh = bumpy_sphere(1, 5, 0.15);
    let path = write_off(&mesh, dir.join("bumpy.off"));
    let k = 6;
    let output = dirac(&[
        "eigenfunctions",
        text(&path),
        "--operator",
        "relative-dirac",
        "-k",
        &k.to_string(),
        "--out",
        text(&dir.join("modes.npy")),
        "--quiet",
    ]);
    assert_success(&output);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("modes.eigenvalues.npy"), "{stdout}");
    assert!(!dir.join("modes.npy").exists());

    let values: Array1<f64> =
        read_npy(dir.join("modes.eigenvalues.npy")).expect("eigenvalues load");
    let vectors: Array3<f64> =
        read_npy(dir.join("modes.eigenvectors.npy")).expect("eigenvectors load");
    let n = mesh.vertex_count();
    assert_eq!(values.shape(), &[k]);
    assert_eq!(vectors.shape(), &[n, k, 4]);

    let expected = library(&mesh, Operator::RelativeDirac, k);
    let masses = barycentric_masses(&mesh);
    for i in 0..k {
        let lambda = expected.eigenvalues[i];
        assert!(
            (values[i] - lambda).abs() <= 1e-8 * lambda.abs(),
            "λ_{i}: {} vs {lambda}",
            values[i]
        );
        // Mass-normalised, from the file alone.
        let norm: f64 = (0..n)
            .map(|v| masses[v] * (0..4).map(|c| vectors[[v, i, c]].powi(2)).sum::<f64>())
            .sum();
        assert!((norm - 1.0).abs() < 1e-9, "mode {i}: mass norm² {norm}");
        // Component order (w, x, y, z) at [vertex, mode, component].
        for v in 0..n {
            let q = expected.eigenvectors[i][v];
            for (c, reference) in [q.w, q.x, q.y, q.z].into_iter().enumerate() {
                assert!(
                    (vectors[[v, i, c]] - reference).abs() < 1e-7,
                    "mode {i}, vertex {v}, component {c}: {} vs {reference}",
                    vectors[[v, i, c]]
                );
            }
        }
    }
}

#[test]
fn ply_output_carries_the_magnitude_of_the_chosen_mode() {
    let dir = scratch("eigenfunctions_ply");
    let mesh = bumpy_sphere(1, 5, 0.15);
    let path = write_off(&mesh, dir.join("bumpy.off"));
    let out = dir.join("mode2.ply");
    let output = dirac(&[
        "eigenfunctions",
        text(&path),
        "--operator",
        "laplace",
        "-k",
        "4",
        "--mode",
        "2",
        "--out",
        text(&out),
        "-q",
    ]);
    assert_success(&output);

    // The ASCII PLY: header, then `x y z phi_abs` per vertex.
    let ply = fs::read_to_string(&out).expect("the .ply exists");
    let (header, body) = ply.split_once("end_header\n").expect("a PLY header");
    let n = mesh.vertex_count();
    assert!(header.contains(&format!("element vertex {n}")), "{header}");
    assert!(header.contains("property double phi_abs"), "{header}");
    let expected = library(&mesh, Operator::Laplace, 4);
    for (v, line) in body.lines().take(n).enumerate() {
        let fields: Vec<f64> = line
            .split_whitespace()
            .map(|t| t.parse().expect("a number"))
            .collect();
        let position = mesh.positions()[v];
        for c in 0..3 {
            assert!((fields[c] - position[c]).abs() < 1e-12, "vertex {v}");
        }
        let magnitude = expected.eigenvectors[2][v].norm();
        assert!(
            (fields[3] - magnitude).abs() < 1e-7 * magnitude.max(1e-3),
            "vertex {v}: {} vs {magnitude}",
            fields[3]
        );
    }
}

#[test]
fn bad_arguments_exit_with_the_documented_codes() {
    let dir = scratch("eigenfunctions_errors");
    let path = write_off(&icosphere(1), dir.join("sphere.off"));
    let out = |name: &str| text(&dir.join(name)).to_string();
    let (txt, npy, ply) = (out("x.txt"), out("x.npy"), out("x.ply"));
    assert_usage_errors(
        &["eigenfunctions", text(&path)],
        &[
            (&["--out", &txt], "expected a .npy or .ply"),
            (&["--out", &npy, "--mode", "1"], "--mode applies only"),
            (&["-k", "3", "--out", &ply, "--mode", "3"], "--mode 3"),
        ],
    );

    let output = dirac(&["eigenfunctions", "/nonexistent/cow.obj", "--out", &npy]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("/nonexistent/cow.obj"));

    let missing = out("missing-dir/x.npy");
    let output = dirac(&["eigenfunctions", text(&path), "-k", "2", "--out", &missing]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("missing-dir/x.eigenvalues.npy"));
}
