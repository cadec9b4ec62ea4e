//! End-to-end tests of `dirac descriptor`: every kind written as CSV or `.npy`, with the
//! documented shape and header, against the library's descriptors of the library's spectrum
//! (HKS always from the Laplacian), and usage errors for options of another kind.

mod support;

use std::fs;
use std::path::{Path, PathBuf};

use dirac::TriMesh;
use dirac::descriptors::{
    Modes, default_times, default_wave_sampling, dirac_kernel_signature, heat_kernel_signature,
    segmentation_descriptor, wave_kernel_signature,
};
use dirac::generators::icosphere;
use dirac::spectrum::Operator;
use ndarray::Array2;
use ndarray_npy::read_npy;

use support::{
    assert_success, assert_usage_errors, bumpy_sphere, dirac, library, scratch, stderr, text,
    write_off,
};

/// The level-1 icosphere with radial bumps (no degenerate eigenvalues), written as an OFF
/// file in a fresh directory; returns the mesh, the directory and the file.
fn bumpy_input(test: &str) -> (TriMesh, PathBuf, String) {
    let dir = scratch(test);
    let mesh = bumpy_sphere(1, 9, 0.15);
    let path = text(&write_off(&mesh, dir.join("bumpy.off"))).to_string();
    (mesh, dir, path)
}

/// Runs `dirac descriptor KIND MESH OPTIONS… --out OUT --quiet` and checks that it succeeded.
fn run(kind: &str, mesh: &str, options: &[&str], out: &Path) {
    let fixed = ["--out", text(out), "--quiet"];
    assert_success(&dirac(
        &[&["descriptor", kind, mesh], options, &fixed].concat(),
    ));
}

/// A CSV file: its header and its rows of numbers.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = fs::read_to_string(path).expect("the CSV exists");
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("a header")
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|line| {
            line.split(',')
                .map(|t| t.parse().expect("a number"))
                .collect()
        })
        .collect();
    (header, rows)
}

/// `rows[v][j]` against `expected(v, j)` to a relative `1e-7`.
fn assert_table(rows: &[Vec<f64>], columns: usize, expected: impl Fn(usize, usize) -> f64) {
    for (v, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), columns, "row {v}");
        for (j, &value) in row.iter().enumerate() {
            let reference = expected(v, j);
            assert!(
                (value - reference).abs() <= 1e-7 * reference.abs().max(1e-6),
                "vertex {v}, column {j}: {value} vs {reference}"
            );
        }
    }
}

#[test]
fn hks_uses_the_laplacian_and_the_given_times() {
    let (mesh, dir, path) = bumpy_input("descriptor_hks");
    let out = dir.join("hks.csv");
    // The default --operator (relative Dirac) does not apply to the HKS.
    run("hks", &path, &["-k", "8", "--times", "0.05,0.5,2"], &out);
    let (header, rows) = read_csv(&out);
    assert_eq!(header, ["t=0.05", "t=0.5", "t=2"]);
    assert_eq!(rows.len(), mesh.vertex_count());
    let s = library(&mesh, Operator::Laplace, 8);
    let modes = Modes::from_spectrum(&s).expect("valid modes");
    let hks = heat_kernel_signature(&modes, &[0.05, 0.5, 2.0]).expect("valid times");
    assert_table(&rows, 3, |v, j| hks.row(v)[j]);
}

#[test]
fn dks_npy_uses_the_default_times() {
    let (mesh, dir, path) = bumpy_input("descriptor_dks");
    let out = dir.join("dks.npy");
    run("dks", &path, &["-k", "6", "--samples", "7"], &out);
    let table: Array2<f64> = read_npy(&out).expect("the .npy loads");
    assert_eq!(table.shape(), &[mesh.vertex_count(), 7]);
    let s = library(&mesh, Operator::RelativeDirac, 6);
    let modes = Modes::from_spectrum(&s).expect("valid modes");
    let times = default_times(&modes, 7).expect("nonzero eigenvalues");
    let dks = dirac_kernel_signature(&modes, &times).expect("valid times");
    let rows: Vec<Vec<f64>> = table.rows().into_iter().map(|r| r.to_vec()).collect();
    assert_table(&rows, 7, |v, j| dks.row(v)[j]);
}

#[test]
fn wks_segmentation_and_eigvec_tables() {
    let (mesh, dir, path) = bumpy_input("descriptor_other");
    let n = mesh.vertex_count();
    let k = 6;
    let laplace = library(&mesh, Operator::Laplace, k);
    let modes = Modes::from_spectrum(&laplace).expect("valid modes");
    let options = ["--operator", "laplace", "-k", "6"];

    run(
        "wks",
        &path,
        &[&options[..], &["--samples", "5"]].concat(),
        &dir.join("wks.csv"),
    );
    let (header, rows) = read_csv(&dir.join("wks.csv"));
    let sampling = default_wave_sampling(&modes, 5).expect("two scales");
    let wks = wave_kernel_signature(&modes, &sampling).expect("valid sampling");
    assert_eq!(header.len(), 5);
    assert!(header.iter().all(|h| h.starts_with("e=")), "{header:?}");
    assert_eq!(rows.len(), n);
    assert_table(&rows, 5, |v, j| wks.row(v)[j]);

    // Segmentation skips the constant mode: k − 1 columns.
    run(
        "segmentation",
        &path,
        &options,
        &dir.join("segmentation.csv"),
    );
    let (header, rows) = read_csv(&dir.join("segmentation.csv"));
    assert_eq!(header.len(), k - 1);
    assert!(header[0].starts_with("lambda="), "{header:?}");
    let segmentation = segmentation_descriptor(&modes).expect("nonzero modes");
    assert_table(&rows, k - 1, |v, j| segmentation.row(v)[j]);

    run("eigvec", &path, &options, &dir.join("eigvec.npy"));
    let table: Array2<f64> = read_npy(dir.join("eigvec.npy")).expect("the .npy loads");
    assert_eq!(table.shape(), &[n, 4 * k]);
    for v in 0..n {
        for i in 0..k {
            let q = laplace.eigenvectors[i][v];
            for (c, reference) in [q.w, q.x, q.y, q.z].into_iter().enumerate() {
                assert!((table[[v, 4 * i + c]] - reference).abs() < 1e-7);
            }
        }
    }
}

#[test]
fn options_of_another_descriptor_are_usage_errors() {
    let dir = scratch("descriptor_errors");
    let path = write_off(&icosphere(1), dir.join("sphere.off"));
    let path = text(&path);
    let csv = dir.join("a.csv");
    let csv = text(&csv);
    let txt = dir.join("a.txt");
    assert_usage_errors(
        &["descriptor"],
        &[
            (
                &["wks", path, "--times", "1", "--out", csv],
                "--times applies only",
            ),
            (
                &["dks", path, "--sigma", "1", "--out", csv],
                "apply only to wks",
            ),
            (
                &["dks", path, "--out", text(&txt)],
                "expected a .csv or .npy",
            ),
            (
                &["hks", path, "--times", "0,1", "--out", csv],
                "not positive",
            ),
        ],
    );
    // A descriptor the spectrum cannot give: with k = 1 there is a single nonzero |λ|, so
    // the default WKS energies span no range (exit code 1, naming the mesh).
    let output = dirac(&["descriptor", "wks", path, "-k", "1", "--out", csv]);
    assert_eq!(output.status.code(), Some(1));
    let message = stderr(&output);
    assert!(
        message.contains("sphere.off") && message.contains("two distinct"),
        "{message}"
    );
}
