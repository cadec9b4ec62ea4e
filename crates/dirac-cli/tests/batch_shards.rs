//! End-to-end tests of `dirac batch` across runs: shards plus `--merge` equal one full run,
//! a merge names what is missing, and Ctrl-C leaves no partial file and a run that resumes.

mod support;

use std::fs;
use std::path::Path;
use std::process::{Command, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

use support::{bumpy_sphere, dirac, scratch, stderr, text, write_off};

/// `count` meshes `m0.off …` in `dir`, bumpy spheres of `level`.
fn meshes(dir: &Path, count: u64, level: u32) {
    fs::create_dir_all(dir).expect("the temporary directory is writable");
    for i in 0..count {
        write_off(&bumpy_sphere(level, i, 0.1), dir.join(format!("m{i}.off")));
    }
}

/// The rows of a summary as (mesh file name, status, eigenvalue fields).
fn rows(summary: &Path) -> Vec<(String, String, Vec<String>)> {
    let text = fs::read_to_string(summary).expect("the summary exists");
    text.lines()
        .skip(1)
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            let name = Path::new(fields[0])
                .file_name()
                .expect("a file name")
                .to_string_lossy()
                .into_owned();
            let lambdas = fields[7..].iter().map(|f| f.to_string()).collect();
            (name, fields[1].to_string(), lambdas)
        })
        .collect()
}

/// Files in `dir` whose names say they are unfinished.
fn partial_files(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .expect("the output directory exists")
        .map(|entry| {
            entry
                .expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .filter(|name| name.ends_with(".partial"))
        .collect()
}

#[test]
fn two_shards_and_a_merge_equal_one_full_run() {
    let dir = scratch("batch_shards");
    let input = dir.join("meshes");
    meshes(&input, 5, 1);
    let run = |out: &Path, extra: &[&str]| {
        let mut args = vec![
            "batch",
            text(&input),
            "-k",
            "4",
            "--jobs",
            "2",
            "--out",
            text(out),
        ];
        args.extend_from_slice(extra);
        dirac(&args)
    };
    let full = dir.join("full");
    assert_eq!(run(&full, &[]).status.code(), Some(0));

    let sharded = dir.join("sharded");
    assert_eq!(run(&sharded, &["--shard", "2/2"]).status.code(), Some(0));
    let second = rows(&sharded.join("summary-2-of-2.csv"));
    let names: Vec<&str> = second.iter().map(|(name, _, _)| name.as_str()).collect();
    assert_eq!(names, ["m1.off", "m3.off"]);

    // Before shard 1 ran, the merge names what is missing (exit 4).
    let early = run(&sharded, &["--merge"]);
    assert_eq!(early.status.code(), Some(4));
    assert!(
        stderr(&early).contains("no summary of shard 1/2"),
        "{}",
        stderr(&early)
    );
    let statuses: Vec<String> = rows(&sharded.join("summary.csv"))
        .into_iter()
        .map(|(_, status, _)| status)
        .collect();
    assert_eq!(statuses, ["missing", "ok", "missing", "ok", "missing"]);

    assert_eq!(run(&sharded, &["--shard", "1/2"]).status.code(), Some(0));
    let merged = run(&sharded, &["--merge"]);
    assert_eq!(merged.status.code(), Some(0), "{}", stderr(&merged));
    assert_eq!(
        rows(&sharded.join("summary.csv")),
        rows(&full.join("summary.csv"))
    );

    // A merge with other options than the shards ran with refuses their results.
    let other = dirac(&[
        "batch",
        text(&input),
        "-k",
        "5",
        "--out",
        text(&sharded),
        "--merge",
    ]);
    assert_eq!(other.status.code(), Some(4));
    assert!(
        stderr(&other).contains("not a complete result"),
        "{}",
        stderr(&other)
    );

    // Summaries of another shard count in the same directory are not of this batch.
    fs::copy(
        sharded.join("summary-1-of-2.csv"),
        sharded.join("summary-1-of-3.csv"),
    )
    .expect("copy");
    let mixed = run(&sharded, &["--merge"]);
    assert_eq!(mixed.status.code(), Some(1));
    assert!(
        stderr(&mixed).contains("of 2 and of 3 shards"),
        "{}",
        stderr(&mixed)
    );
    assert!(partial_files(&sharded).is_empty());
}

#[test]
fn bad_shards_are_usage_errors() {
    for shard in ["0/2", "3/2", "1/0", "two"] {
        let output = dirac(&["batch", ".", "--out", "x", "--shard", shard]);
        assert_eq!(output.status.code(), Some(2), "{shard}");
    }
}

#[test]
fn ctrl_c_leaves_no_partial_file_and_the_next_run_resumes() {
    let dir = scratch("batch_interrupt");
    let input = dir.join("meshes");
    let count = 6;
    meshes(&input, count, 4);
    let out = dir.join("out");
    let args = [
        "batch",
        text(&input),
        "-k",
        "30",
        "--jobs",
        "1",
        "--out",
        text(&out),
    ];
    let child = Command::new(env!("CARGO_BIN_EXE_dirac"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("dirac starts");
    // Interrupt once the first mesh is done, in the middle of the second.
    let start = Instant::now();
    while !out.join("m0.off.json").exists() {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no mesh finished"
        );
        sleep(Duration::from_millis(20));
    }
    sleep(Duration::from_millis(100));
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success());
    let output = child.wait_with_output().expect("dirac ends");
    let message = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(130), "{message}");
    assert!(partial_files(&out).is_empty());

    let first = rows(&out.join("summary.csv"));
    let done = first.iter().filter(|(_, status, _)| status == "ok").count();
    assert!(done >= 1 && done < count as usize, "{first:?}");
    assert!(
        first
            .iter()
            .all(|(_, s, _)| s == "ok" || s == "interrupted"),
        "{first:?}"
    );
    let jsons = fs::read_dir(&out)
        .expect("the output directory")
        .filter(|e| {
            e.as_ref()
                .is_ok_and(|e| e.file_name().to_string_lossy().ends_with(".json"))
        })
        .count();
    assert_eq!(jsons, done, "a JSON exactly for each finished mesh");

    let rerun = dirac(&args);
    assert_eq!(rerun.status.code(), Some(0), "{}", stderr(&rerun));
    for ((name, before, _), (_, after, _)) in first.iter().zip(rows(&out.join("summary.csv"))) {
        let expected = if before == "ok" { "skipped" } else { "ok" };
        assert_eq!(after, expected, "{name}");
    }
}

#[test]
fn saved_arrays_sit_beside_the_json_and_count_for_completeness() {
    use ndarray::{Array1, Array2, Array3};
    use ndarray_npy::read_npy;

    let dir = scratch("batch_save");
    let input = dir.join("meshes");
    meshes(&input, 2, 1);
    let out = dir.join("out");
    let run = |save: &str| {
        dirac(&[
            "batch",
            text(&input),
            "--operator",
            "laplace",
            "-k",
            "6",
            "--out",
            text(&out),
            "--save",
            save,
            "-q",
        ])
    };
    assert_eq!(run("eigenvectors").status.code(), Some(0));
    // The JSON of the first run lacks hks: the mesh is computed again, not skipped.
    let output = run("eigenvectors,hks");
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let summary = rows(&out.join("summary.csv"));
    assert!(
        summary.iter().all(|(_, status, _)| status == "ok"),
        "{summary:?}"
    );

    let report: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("m0.off.json")).expect("the JSON"))
            .expect("valid JSON");
    let lambda: Vec<f64> = report["eigenvalues"]
        .as_array()
        .expect("eigenvalues")
        .iter()
        .map(|v| v.as_f64().expect("a number"))
        .collect();
    let times: Vec<f64> = report["saved"]["hks"]["parameters"]
        .as_array()
        .expect("the times")
        .iter()
        .map(|v| v.as_f64().expect("a number"))
        .collect();
    let phi: Array3<f64> = read_npy(out.join("m0.off.eigenvectors.npy")).expect("the .npy");
    let hks: Array2<f64> = read_npy(out.join("m0.off.hks.npy")).expect("the .npy");
    let n = report["vertices"].as_u64().expect("vertices") as usize;
    assert_eq!(phi.shape(), [n, 6, 4]);
    assert_eq!(hks.shape(), [n, times.len()]);
    // HKS(v, t) = Σ_i e^{−tλ_i} |φ_i(v)|², from the saved eigenpairs.
    for v in [0, n / 2, n - 1] {
        for (j, &t) in times.iter().enumerate().step_by(17) {
            let squares =
                Array1::from_shape_fn(6, |i| (0..4).map(|c| phi[[v, i, c]].powi(2)).sum::<f64>());
            let expected: f64 = (0..6).map(|i| (-t * lambda[i]).exp() * squares[i]).sum();
            let got = hks[[v, j]];
            assert!(
                (got - expected).abs() <= 1e-10 * expected.abs(),
                "{got} vs {expected}"
            );
        }
    }

    // hks needs the Laplacian.
    let wrong = dirac(&["batch", text(&input), "--out", text(&out), "--save", "hks"]);
    assert_eq!(wrong.status.code(), Some(2));
    assert!(partial_files(&out).is_empty());
}

#[test]
fn a_merge_of_an_interrupted_shard_is_incomplete_not_interrupted() {
    let dir = scratch("batch_merge_interrupted");
    let input = dir.join("meshes");
    meshes(&input, 2, 1);
    let out = dir.join("out");
    let run = |extra: &str| {
        dirac(&[
            "batch",
            text(&input),
            "-k",
            "3",
            "--out",
            text(&out),
            "-q",
            extra,
        ])
    };
    assert_eq!(run("--shard=1/1").status.code(), Some(0));
    // As a shard stopped by Ctrl-C would have written it.
    let summary = out.join("summary-1-of-1.csv");
    let text = fs::read_to_string(&summary).expect("the shard summary");
    let stopped = text.replacen(",ok,", ",interrupted,", 1);
    assert_ne!(stopped, text);
    fs::write(&summary, stopped).expect("the summary is writable");
    let merged = run("--merge");
    assert_eq!(merged.status.code(), Some(4), "{}", stderr(&merged));
}
