//! End-to-end tests of `dirac batch`: per-mesh JSON equal to the library's spectra, a broken
//! mesh reported without stopping the others (exit code 4), resuming that skips complete
//! outputs and recomputes missing, truncated or differently configured ones, and list input.

mod support;

use std::fs;
use std::path::{Path, PathBuf};

use dirac::TriMesh;
use dirac::spectrum::Operator;
use serde_json::Value;

use support::{bumpy_sphere, dirac, library, scratch, stderr, text, write_off};

/// A fresh scratch directory `name` and, inside it, an empty folder `meshes` for the inputs.
fn scratch_with_input(name: &str) -> (PathBuf, PathBuf) {
    let dir = scratch(name);
    let input = dir.join("meshes");
    fs::create_dir_all(&input).expect("the temporary directory is writable");
    (dir, input)
}

/// A directory with two valid meshes and one malformed file, and the valid meshes.
fn inputs(dir: &Path) -> Vec<(String, TriMesh)> {
    let meshes = vec![
        ("a.off".to_string(), bumpy_sphere(1, 1, 0.1)),
        ("c.off".to_string(), bumpy_sphere(2, 2, 0.1)),
    ];
    for (name, mesh) in &meshes {
        write_off(mesh, dir.join(name));
    }
    fs::write(
        dir.join("b.off"),
        "OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n",
    )
    .expect("the temporary directory is writable");
    fs::write(dir.join("notes.txt"), "not a mesh").expect("the temporary directory is writable");
    meshes
}

/// The summary rows as (mesh file name, status, all fields).
fn summary(out: &Path) -> Vec<(String, String, Vec<String>)> {
    let text = fs::read_to_string(out.join("summary.csv")).expect("the summary exists");
    let mut lines = text.lines();
    let header = lines.next().expect("a header");
    assert!(
        header.starts_with("mesh,status,vertices,faces,converged,seconds,error,slivers,lambda_0"),
        "{header}"
    );
    lines
        .map(|line| {
            let fields: Vec<String> = line.split(',').map(String::from).collect();
            let name = Path::new(&fields[0])
                .file_name()
                .expect("a file name")
                .to_string_lossy()
                .into_owned();
            (name, fields[1].clone(), fields)
        })
        .collect()
}

fn statuses(out: &Path) -> Vec<(String, String)> {
    summary(out)
        .into_iter()
        .map(|(name, status, _)| (name, status))
        .collect()
}

fn pairs(list: &[(&str, &str)]) -> Vec<(String, String)> {
    list.iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect()
}

#[test]
fn batch_computes_reports_failures_and_resumes() {
    let (dir, input) = scratch_with_input("batch_dir");
    let meshes = inputs(&input);
    let out = dir.join("out");
    let k = 5;
    let args = [
        "batch",
        text(&input),
        "--operator",
        "relative-dirac",
        "-k",
        "5",
        "--jobs",
        "2",
        "--out",
        text(&out),
    ];

    // First run: the malformed mesh fails (exit 4, named on stderr), the others complete.
    let output = dirac(&args);
    assert_eq!(output.status.code(), Some(4));
    let message = stderr(&output);
    assert!(
        message.contains("b.off") && message.contains("line 4"),
        "{message}"
    );
    assert_eq!(
        statuses(&out),
        pairs(&[("a.off", "ok"), ("b.off", "failed"), ("c.off", "ok")])
    );
    for (name, mesh) in &meshes {
        let json: Value = serde_json::from_str(
            &fs::read_to_string(out.join(format!("{name}.json"))).expect("the JSON exists"),
        )
        .expect("valid JSON");
        assert_eq!(json["converged"], true);
        assert_eq!(json["vertices"], mesh.vertex_count());
        assert_eq!(json["operator"], "relative-dirac");
        let expected = library(mesh, Operator::RelativeDirac, k);
        let values: Vec<f64> = json["eigenvalues"]
            .as_array()
            .expect("an array")
            .iter()
            .map(|v| v.as_f64().expect("a number"))
            .collect();
        assert_eq!(values.len(), k);
        for (value, lambda) in values.iter().zip(&expected.eigenvalues) {
            assert!((value - lambda).abs() <= 1e-8 * lambda.abs(), "{name}");
        }
        // The summary row carries the same eigenvalues.
        let row = summary(&out)
            .into_iter()
            .find(|(n, _, _)| n == name)
            .expect("a row");
        assert_eq!(row.2[7], "0", "{name}: no sliver faces");
        let listed: f64 = row.2[8].parse().expect("lambda_0");
        assert!((listed - values[0]).abs() <= 1e-12 * values[0].abs());
    }
    assert!(!out.join("b.off.json").exists());

    // Second run: the complete outputs are skipped (not rewritten), the failure persists.
    let a_json = out.join("a.off.json");
    let before = fs::metadata(&a_json)
        .and_then(|m| m.modified())
        .expect("mtime");
    let eigenvalue_fields = |out: &Path| -> Vec<Vec<String>> {
        summary(out)
            .into_iter()
            .map(|(_, _, fields)| fields[8..].to_vec())
            .collect()
    };
    let computed = eigenvalue_fields(&out);
    let output = dirac(&args);
    assert_eq!(output.status.code(), Some(4));
    assert_eq!(
        statuses(&out),
        pairs(&[
            ("a.off", "skipped"),
            ("b.off", "failed"),
            ("c.off", "skipped")
        ])
    );
    let after = fs::metadata(&a_json)
        .and_then(|m| m.modified())
        .expect("mtime");
    assert_eq!(before, after);
    // Read back from the JSON, the skipped meshes' eigenvalues are the computed ones exactly.
    assert_eq!(eigenvalue_fields(&out), computed);

    // Fix the broken mesh, truncate one JSON and delete another: only those are computed.
    write_off(&bumpy_sphere(1, 3, 0.1), input.join("b.off"));
    let truncated = fs::read_to_string(&a_json).expect("the JSON exists");
    fs::write(&a_json, &truncated[..truncated.len() / 2]).expect("writable");
    fs::remove_file(out.join("c.off.json")).expect("removable");
    let output = dirac(&args);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(
        statuses(&out),
        pairs(&[("a.off", "ok"), ("b.off", "ok"), ("c.off", "ok")])
    );

    // Other settings (k) make the earlier outputs incomplete; --force recomputes regardless.
    let mut other_k = args;
    other_k[5] = "4";
    assert_eq!(dirac(&other_k).status.code(), Some(0));
    assert!(statuses(&out).iter().all(|(_, status)| status == "ok"));
    assert_eq!(dirac(&other_k).status.code(), Some(0));
    assert!(statuses(&out).iter().all(|(_, status)| status == "skipped"));
    assert_eq!(
        dirac(&[&other_k[..], &["--force"]].concat()).status.code(),
        Some(0)
    );
    assert!(statuses(&out).iter().all(|(_, status)| status == "ok"));
}

/// A mesh with a sliver face (a square with a flap whose apex is `1e-12` off its edge) is
/// computed, counted in the summary's `slivers` column (also when a later run skips it) and
/// warned of at the end.
#[test]
fn sliver_faces_are_counted_in_the_summary() {
    let (dir, input) = scratch_with_input("batch_slivers");
    fs::write(
        input.join("flap.obj"),
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 -1e-12 0\nf 1 2 3\nf 1 3 4\nf 2 1 5\n",
    )
    .expect("the temporary directory is writable");
    write_off(&bumpy_sphere(1, 1, 0.1), input.join("sphere.off"));
    let out = dir.join("out");
    let args = [
        "batch",
        text(&input),
        "--operator",
        "laplace",
        "-k",
        "2",
        "--out",
        text(&out),
    ];
    for expected in ["ok", "skipped"] {
        let output = dirac(&args);
        assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
        let message = stderr(&output);
        assert!(
            message.contains("warning: 1 mesh has sliver faces") && message.contains("--repair"),
            "{message}"
        );
        let rows = summary(&out);
        let slivers: Vec<(&str, &str, &str)> = rows
            .iter()
            .map(|(name, status, fields)| (name.as_str(), status.as_str(), fields[7].as_str()))
            .collect();
        assert_eq!(
            slivers,
            [("flap.obj", expected, "1"), ("sphere.off", expected, "0")]
        );
    }
}

#[test]
fn a_mesh_past_the_time_limit_is_stopped_and_computed_again_by_a_rerun() {
    let (dir, input) = scratch_with_input("batch_time_limit");
    write_off(&bumpy_sphere(2, 1, 0.2), input.join("sphere.off"));
    let out = dir.join("out");
    let run = |extra: &[&str]| {
        let args = [
            &["batch", text(&input), "-k", "10", "--out", text(&out)],
            extra,
        ]
        .concat();
        dirac(&args)
    };
    // The limit has passed at the eigensolver's first restart, which stops it there.
    let stopped = run(&["--time-limit", "1e-9"]);
    assert_eq!(stopped.status.code(), Some(4), "{}", stderr(&stopped));
    let rows = summary(&out);
    assert_eq!(rows[0].1, "not-converged");
    let error = &rows[0].2[6];
    assert!(
        error.contains("stopped at the time limit of 0.000000001 s (--time-limit)"),
        "{error}"
    );
    let json: Value = serde_json::from_str(
        &fs::read_to_string(out.join("sphere.off.json")).expect("the JSON of the stopped mesh"),
    )
    .expect("JSON");
    assert_eq!(json["converged"], false);
    // A rerun with room to finish computes it rather than skipping it; a limit beyond what a
    // clock holds is no limit (it panicked converting to a duration).
    let finished = run(&["--time-limit", "1e300"]);
    assert_eq!(finished.status.code(), Some(0), "{}", stderr(&finished));
    assert_eq!(statuses(&out), pairs(&[("sphere.off", "ok")]));
}

#[test]
fn a_result_is_reused_only_for_the_same_file_contents_and_settings() {
    let dir = scratch("batch_identity");
    let (first, second, out) = (dir.join("a"), dir.join("b"), dir.join("out"));
    for (input, mesh) in [
        (&first, bumpy_sphere(1, 1, 0.1)),
        (&second, bumpy_sphere(2, 1, 0.2)),
    ] {
        fs::create_dir_all(input).expect("the temporary directory is writable");
        write_off(&mesh, input.join("x.off"));
    }
    let run = |input: &Path, extra: &[&str]| {
        let args = [
            &["batch", text(input), "-k", "4", "--out", text(&out)],
            extra,
        ]
        .concat();
        let output = dirac(&args);
        assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
        let json: Value = serde_json::from_str(
            &fs::read_to_string(out.join("x.off.json")).expect("the JSON exists"),
        )
        .expect("valid JSON");
        (statuses(&out), json)
    };
    let (status, from_first) = run(&first, &[]);
    assert_eq!(status, pairs(&[("x.off", "ok")]));
    assert_eq!(from_first["mesh_sha256"].as_str().map(str::len), Some(64));
    // Same file name, other contents: computed again, with the other mesh's eigenvalues.
    let (status, from_second) = run(&second, &[]);
    assert_eq!(status, pairs(&[("x.off", "ok")]));
    assert_ne!(from_second["mesh_sha256"], from_first["mesh_sha256"]);
    assert_ne!(from_second["eigenvalues"], from_first["eigenvalues"]);
    assert_eq!(run(&second, &[]).0, pairs(&[("x.off", "skipped")]));
    // Every setting that changes the result is part of the identity.
    for extra in [
        &["--seed", "3"][..],
        &["--tolerance", "1e-9"],
        &["--max-restarts", "50"],
    ] {
        assert_eq!(
            run(&second, extra).0,
            pairs(&[("x.off", "ok")]),
            "{extra:?}"
        );
        assert_eq!(
            run(&second, extra).0,
            pairs(&[("x.off", "skipped")]),
            "{extra:?}"
        );
    }
}

#[test]
fn a_count_beyond_every_mesh_fails_each_mesh_and_writes_the_summary() {
    let (dir, input) = scratch_with_input("batch_huge_k");
    write_off(&bumpy_sphere(1, 1, 0.1), input.join("x.off"));
    let out = dir.join("out");
    let output = dirac(&[
        "batch",
        text(&input),
        "-k",
        "18446744073709551615",
        "--out",
        text(&out),
    ]);
    assert_eq!(output.status.code(), Some(4), "{}", stderr(&output));
    assert!(stderr(&output).contains("cannot compute 18446744073709551615 eigenvalues"));
    assert_eq!(statuses(&out), pairs(&[("x.off", "failed")]));
}

#[test]
fn list_input_with_comments_and_relative_paths() {
    let (dir, input) = scratch_with_input("batch_list");
    inputs(&input);
    let list = dir.join("list.txt");
    fs::write(
        &list,
        "# meshes for the test\nmeshes/c.off\n\n  meshes/a.off  # trailing comment\n",
    )
    .expect("writable");
    let out = dir.join("out");
    let output = dirac(&[
        "batch",
        text(&list),
        "--operator",
        "laplace",
        "-k",
        "3",
        "--out",
        text(&out),
        "--quiet",
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    // In list order, not sorted.
    assert_eq!(statuses(&out), pairs(&[("c.off", "ok"), ("a.off", "ok")]));
}

#[test]
fn inputs_that_cannot_run_exit_1() {
    let dir = scratch("batch_errors");
    let empty = dir.join("empty");
    fs::create_dir_all(&empty).expect("writable");
    let out = dir.join("out");
    let output = dirac(&["batch", text(&empty), "--out", text(&out)]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("no .obj, .off, .ply or .stl"));

    let list = dir.join("same-names.txt");
    fs::write(&list, "x/m.off\ny/m.off\n").expect("writable");
    let output = dirac(&["batch", text(&list), "--out", text(&out)]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("same file name"));

    let output = dirac(&["batch", "/nonexistent/list.txt", "--out", text(&out)]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("/nonexistent/list.txt"));
}

/// The family weighs D_N by each mesh's scale: a batch of meshes that are not normalised is
/// warned of once (its solves run quiet); normalised, or another operator, it is not.
#[test]
fn a_batch_of_the_family_without_normalisation_is_warned_of() {
    let (dir, input) = scratch_with_input("batch_family_scale");
    write_off(&bumpy_sphere(1, 3, 0.05), input.join("a.off"));
    let run = |extra: &[&str]| {
        let out = dir.join(format!("out{}", extra.len()));
        let args = ["batch", text(&input), "-k", "3", "--out", text(&out)];
        let output = dirac(&[&args[..], extra].concat());
        assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
        stderr(&output)
    };
    let warned = run(&["--operator", "family:0.5"]);
    assert!(
        warned.contains("warning: the family weighs D_N"),
        "{warned}"
    );
    assert!(warned.contains("--normalize unit-area"), "{warned}");
    let normalized = run(&["--operator", "family:0.5", "--normalize", "unit-area"]);
    assert!(!normalized.contains("weighs D_N"), "{normalized}");
    assert!(!run(&[]).contains("weighs D_N"));
}
