//! End-to-end tests of `dirac segment-eval`: the measures of hand-computed cases on a small
//! generated mesh, as JSON and as a table; malformed and mismatched `.seg` files name both
//! files (exit 1); usage errors (exit 2).

mod support;

use std::fs;
use std::path::{Path, PathBuf};

use dirac::generators::grid;
use serde_json::Value;

use support::{assert_success, dirac, scratch, stderr, text, write_off};

/// Three unit squares in a row (`[−1.5, 1.5] × [−0.5, 0.5]`), faces `2i, 2i + 1` in square `i`,
/// written as OFF in a fresh directory.
fn strip(dir: &Path) -> PathBuf {
    write_off(&grid(3, 1, 3.0, 1.0).unwrap(), dir.join("strip.off"))
}

fn write_seg(dir: &Path, name: &str, contents: &str) -> PathBuf {
    let path = dir.join(name);
    fs::write(&path, contents).expect("the temporary directory is writable");
    path
}

fn close(value: &Value, expected: f64) -> bool {
    value.as_f64().is_some_and(|v| (v - expected).abs() < 1e-12)
}

#[test]
fn json_holds_the_hand_computed_measures_their_mean_and_each_reference() {
    let dir = scratch("segment_eval_json");
    let mesh = strip(&dir);
    // Squares {0, 1} | {2} scored against {0} | {1, 2}, against itself, and against one
    // segment (hand computations in crates/dirac/tests/segmentation_evaluation.rs).
    let result = write_seg(&dir, "result.seg", "0\n0\n0\n0\n1\n1\n");
    let other = write_seg(&dir, "other.seg", "0\n0\n1\n1\n1\n1\n");
    let one = write_seg(&dir, "one.seg", "4\n4\n4\n4\n4\n4\n");
    let output = dirac(&[
        "segment-eval",
        text(&mesh),
        text(&result),
        text(&other),
        text(&result),
        text(&one),
        "--json",
    ]);
    assert_success(&output);
    let json: Value = serde_json::from_slice(&output.stdout).expect("one JSON object");
    assert_eq!(json["faces"], 6);
    assert_eq!(json["result_segments"], 2);
    let references = json["references"].as_array().unwrap();
    assert_eq!(references.len(), 3);
    assert_eq!(references[0]["file"], text(&other));
    assert_eq!(references[2]["segments"], 1);
    let first = &references[0]["scores"];
    assert!(close(&first["rand_index_error"], 8.0 / 15.0), "{first}");
    assert!(close(&first["consistency"]["global"], 1.0 / 3.0), "{first}");
    assert!(close(&first["consistency"]["local"], 1.0 / 6.0), "{first}");
    assert!(close(&first["hamming"]["distance"], 1.0 / 3.0), "{first}");
    let cut = 18.0 / (26f64.sqrt() + 50f64.sqrt() + 2f64.sqrt());
    assert!(close(&first["cut_discrepancy"], cut), "{first}");
    assert!(close(&references[1]["scores"]["rand_index_error"], 0.0));
    // Against one segment: Rm = (3 − 2)/3 (the larger computed segment covers 2 of the 3
    // area units), Rf = 0; no cut.
    let third = &references[2]["scores"];
    assert!(
        close(&third["hamming"]["missing_rate"], 1.0 / 3.0),
        "{third}"
    );
    assert!(close(&third["hamming"]["false_alarm_rate"], 0.0), "{third}");
    assert!(third["cut_discrepancy"].is_null(), "{third}");
    // Means: Rand (8/15 + 0 + 8/15)/3; CD over the two references with a cut.
    let mean = &json["mean"];
    assert!(close(&mean["rand_index_error"], 16.0 / 45.0), "{mean}");
    assert_eq!(json["cut_discrepancy_references"], 2);
    assert!(close(&mean["cut_discrepancy"], cut / 2.0), "{mean}");
}

#[test]
fn the_table_shows_the_mean_and_one_row_per_reference() {
    let dir = scratch("segment_eval_table");
    let mesh = strip(&dir);
    let result = write_seg(&dir, "result.seg", "0\n0\n0\n0\n1\n1\n");
    let other = write_seg(&dir, "other.seg", "0\n0\n1\n1\n1\n1\n");
    let output = dirac(&["segment-eval", text(&mesh), text(&result), text(&other)]);
    assert_success(&output);
    let table = String::from_utf8(output.stdout).unwrap();
    let lines: Vec<&str> = table.lines().collect();
    assert!(lines[0].contains("(6 faces)"), "{table}");
    assert!(lines[1].contains("(2 segments)"), "{table}");
    let header = lines
        .iter()
        .position(|l| l.starts_with("reference"))
        .unwrap();
    for column in ["CD", "Hamming", "Rm", "Rf", "Rand", "GCE", "LCE"] {
        assert!(lines[header].contains(column), "{table}");
    }
    // 1 − RI = 8/15 = 0.5333, GCE = 1/3, LCE = 1/6 in both the mean and the row.
    let mean = lines[header + 1];
    assert!(mean.starts_with("mean of 1 (CD of 1)"), "{table}");
    let row = lines[header + 2];
    assert!(row.contains(text(&other)), "{table}");
    for line in [mean, row] {
        for value in ["0.5333", "0.3333", "0.1667"] {
            assert!(line.contains(value), "{value}: {table}");
        }
    }
}

#[test]
fn a_seg_file_of_the_wrong_length_names_both_files_and_both_numbers() {
    let dir = scratch("segment_eval_mismatch");
    let mesh = strip(&dir);
    let result = write_seg(&dir, "result.seg", "0\n0\n0\n0\n1\n1\n");
    let short = write_seg(&dir, "short.seg", "0\n0\n1\n1\n1\n");
    let output = dirac(&["segment-eval", text(&mesh), text(&result), text(&short)]);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    let message = stderr(&output);
    assert!(message.contains(text(&mesh)), "{message}");
    assert!(message.contains(text(&short)), "{message}");
    assert!(
        message.contains("5 segment numbers for a mesh of 6 faces"),
        "{message}"
    );
}

#[test]
fn malformed_seg_files_are_errors_naming_the_line() {
    let dir = scratch("segment_eval_malformed");
    let mesh = strip(&dir);
    let reference = write_seg(&dir, "reference.seg", "0\n0\n1\n1\n1\n1\n");
    for (contents, expected) in [
        ("0\n0\nx\n1\n1\n1\n", "line 3: `x` is not a segment number"),
        (
            "0\n0\n-1\n1\n1\n1\n",
            "line 3: segment number -1 is negative",
        ),
    ] {
        let result = write_seg(&dir, "result.seg", contents);
        let output = dirac(&["segment-eval", text(&mesh), text(&result), text(&reference)]);
        assert_eq!(output.status.code(), Some(1));
        let message = stderr(&output);
        assert!(message.contains(text(&result)), "{message}");
        assert!(message.contains(expected), "{message}");
    }
    let missing = dir.join("missing.seg");
    let output = dirac(&[
        "segment-eval",
        text(&mesh),
        text(&missing),
        text(&reference),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains(text(&missing)));
}

#[test]
fn usage_errors_exit_with_two() {
    let dir = scratch("segment_eval_usage");
    let mesh = strip(&dir);
    let result = write_seg(&dir, "result.seg", "0\n0\n0\n0\n1\n1\n");
    // No reference.
    let output = dirac(&["segment-eval", text(&mesh), text(&result)]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    // Repair would renumber the faces the .seg files refer to: not offered.
    let output = dirac(&[
        "segment-eval",
        text(&mesh),
        text(&result),
        text(&result),
        "--repair",
    ]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
}
