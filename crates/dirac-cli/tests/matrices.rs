//! `dirac matrices`: the files hold the library's eigenproblem entry for entry, in the
//! documented Matrix Market layout, and bad output names are usage errors. (The Python tests
//! read the same files with scipy and solve them.)

mod support;

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

use dirac::generators::icosphere;
use dirac::spectrum::{Operator, SpectrumOptions, eigenproblem};

use support::{assert_success, assert_usage_errors, dirac, temporary, text, write_off};

/// The header line, the size line and the entries `(row, column) → numbers` of a file.
struct MarketFile {
    header: String,
    size: Vec<usize>,
    entries: BTreeMap<(usize, usize), Vec<f64>>,
}

/// Reads a `coordinate` file by splitting its lines (no Matrix Market library).
fn read_coordinate(path: &Path) -> MarketFile {
    let contents = fs::read_to_string(path).expect("the file was written");
    let mut lines = contents
        .lines()
        .filter(|l| !l.starts_with('%') || l.starts_with("%%"));
    let header = lines.next().expect("a header").to_string();
    let size = (lines.next().expect("a size line").split_whitespace())
        .map(|n| n.parse().expect("a count"))
        .collect();
    let entries = lines
        .map(|line| {
            let mut fields = line.split_whitespace();
            let mut index = || fields.next().unwrap().parse::<usize>().unwrap();
            let at = (index(), index());
            (at, fields.map(|x| x.parse::<f64>().unwrap()).collect())
        })
        .collect();
    MarketFile {
        header,
        size,
        entries,
    }
}

#[test]
fn the_files_hold_the_lower_triangle_of_the_real_form_bit_for_bit() {
    let mesh = icosphere(2);
    let path = write_off(&mesh, temporary("matrices_icosphere2.off"));
    let out = temporary("matrices_icosphere2.mtx");
    let output = dirac(&[
        "matrices",
        text(&path),
        "--operator",
        "family:0.5",
        "--out",
        text(&out),
    ]);
    assert_success(&output);

    let options = SpectrumOptions::new(Operator::Family { tau: 0.5 }, 1);
    let problem = eigenproblem(&mesh, &options).unwrap();
    let n = 4 * mesh.vertex_count();
    for (part, matrix) in [
        ("stiffness", &problem.stiffness),
        ("coupling", &problem.coupling),
    ] {
        let file = read_coordinate(&out.with_extension(format!("{part}.mtx")));
        assert_eq!(
            file.header,
            "%%MatrixMarket matrix coordinate real symmetric"
        );
        let expected: BTreeMap<(usize, usize), Vec<f64>> = (matrix.to_real_block().triplet_iter())
            .filter(|t| t.row >= t.col)
            .map(|t| ((t.row + 1, t.col + 1), vec![*t.val]))
            .collect();
        assert_eq!(file.size, [n, n, expected.len()], "{part}");
        assert_eq!(file.entries, expected, "{part}");
    }
    let masses = fs::read_to_string(out.with_extension("mass.mtx")).unwrap();
    let values: Vec<f64> = (masses.lines().filter(|l| !l.starts_with('%')).skip(1))
        .map(|l| l.parse().unwrap())
        .collect();
    assert_eq!(values, problem.masses);
}

#[test]
fn bad_output_names_and_options_are_usage_errors() {
    assert_usage_errors(
        &["matrices"],
        &[
            (&["--out", "pencil.npy"], "expected a .mtx file name"),
            (&["--out", "p.mtx", "--form", "quaternion"], "--form"),
            (
                &[
                    "--out",
                    "p.mtx",
                    "--operator",
                    "laplace",
                    "--relative-to",
                    "b.obj",
                ],
                "--relative-to replaces the Gauss map",
            ),
        ],
    );
}
