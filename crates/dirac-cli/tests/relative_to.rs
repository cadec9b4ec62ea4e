//! `--relative-to B`: the relative Dirac operator `D_{A,B}` of two surfaces with one
//! triangulation from the command line — the library's `relative_spectrum`, checked where the
//! two surfaces are read, and refused with a message for other triangulations and for
//! operators that do not use the Gauss map.

mod support;

use std::path::PathBuf;

use dirac::TriMesh;
use dirac::spectrum::{Operator, SpectrumOptions, relative_spectrum};
use serde_json::Value;

use support::{assert_success, bumpy_sphere, dirac, scratch, stderr, text, write_off};

/// Two bumpy spheres of one triangulation (seeds `seed`, `seed + 1`), written as `a.off` and
/// `b.off` in a fresh directory `name`: the meshes and their files.
fn two_surfaces(name: &str, seed: u64) -> ([TriMesh; 2], [PathBuf; 2]) {
    let dir = scratch(name);
    let (a, b) = (bumpy_sphere(2, seed, 0.1), bumpy_sphere(2, seed + 1, 0.1));
    let paths = [
        write_off(&a, dir.join("a.off")),
        write_off(&b, dir.join("b.off")),
    ];
    ([a, b], paths)
}

#[test]
fn spectrum_relative_to_a_second_surface_is_the_librarys() {
    let ([a, b], [path_a, path_b]) = two_surfaces("relative-to-spectrum", 1);
    let output = dirac(&[
        "spectrum",
        text(&path_a),
        "--relative-to",
        text(&path_b),
        "-k",
        "6",
        "--json",
        "--quiet",
    ]);
    assert_success(&output);
    let json: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(json["relative_to"], text(&path_b));
    let want = relative_spectrum(&a, &b, &SpectrumOptions::new(Operator::RelativeDirac, 6))
        .unwrap()
        .eigenvalues;
    let got: Vec<f64> = (json["eigenvalues"].as_array().unwrap().iter())
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(got.len(), want.len());
    for (x, y) in got.iter().zip(&want) {
        assert!((x - y).abs() <= 1e-10 * y.abs(), "{x} vs {y}");
    }
    // Without --relative-to the same mesh gives D_N's spectrum, which differs.
    let plain = dirac(&["spectrum", text(&path_a), "-k", "6", "--json", "--quiet"]);
    let plain: Value = serde_json::from_slice(&plain.stdout).unwrap();
    assert!(plain.get("relative_to").is_none());
    assert_ne!(plain["eigenvalues"][0], json["eigenvalues"][0]);
}

#[test]
fn eigenfunctions_and_render_take_the_reference_too() {
    let (_, [path_a, path_b]) = two_surfaces("relative-to-outputs", 3);
    let dir = path_a.parent().expect("a file in a directory");
    let ply = dir.join("mode.ply");
    assert_success(&dirac(&[
        "eigenfunctions",
        text(&path_a),
        "--relative-to",
        text(&path_b),
        "-k",
        "4",
        "--out",
        text(&ply),
        "--quiet",
    ]));
    assert!(ply.exists());
    let png = dir.join("modes.png");
    assert_success(&dirac(&[
        "render",
        text(&path_a),
        "--relative-to",
        text(&path_b),
        "-k",
        "4",
        "--out",
        text(&png),
        "--quiet",
    ]));
    assert!(png.exists());
}

#[test]
fn another_triangulation_is_refused_naming_both_files() {
    let dir = scratch("relative-to-mismatch");
    let a = write_off(&bumpy_sphere(2, 5, 0.1), dir.join("a.off"));
    let finer = write_off(&bumpy_sphere(3, 5, 0.1), dir.join("finer.off"));
    let output = dirac(&[
        "spectrum",
        text(&a),
        "--relative-to",
        text(&finer),
        "-k",
        "4",
    ]);
    assert_eq!(output.status.code(), Some(1));
    let message = stderr(&output);
    assert!(message.contains("--relative-to"), "{message}");
    assert!(
        message.contains("finer.off") && message.contains("a.off"),
        "{message}"
    );
    assert!(message.contains("162 and 642 vertices"), "{message}");
}

#[test]
fn operators_without_the_gauss_map_are_a_usage_error() {
    let dir = scratch("relative-to-operator");
    let a = write_off(&bumpy_sphere(2, 6, 0.1), dir.join("a.off"));
    for operator in ["laplace", "extrinsic-dirac", "modified-dirichlet"] {
        let output = dirac(&[
            "spectrum",
            text(&a),
            "--relative-to",
            text(&a),
            "--operator",
            operator,
        ]);
        assert_eq!(output.status.code(), Some(2), "{operator}");
        let message = stderr(&output);
        assert!(message.contains("Gauss map"), "{message}");
    }
}
