//! End-to-end tests of `--repair`, `--component` and `dirac repair`: a triangle soup repaired
//! has the clean mesh's spectrum, invalid meshes name the defect and the hint, batches record
//! the repair in their settings.

mod support;

use std::fs;
use std::path::{Path, PathBuf};

use dirac::TriMesh;
use dirac::spectrum::Operator;
use serde_json::Value;

use support::{bumpy_sphere, dirac, library, scratch, stderr, text, write_off};

/// `mesh` as a triangle soup: every face with its own three vertices.
fn write_soup(mesh: &TriMesh, path: PathBuf) -> PathBuf {
    let mut obj = String::new();
    for face in mesh.faces() {
        for &v in face {
            let p = mesh.positions()[v];
            obj.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
        }
    }
    for f in 0..mesh.face_count() {
        obj.push_str(&format!("f {} {} {}\n", 3 * f + 1, 3 * f + 2, 3 * f + 3));
    }
    fs::write(&path, obj).expect("the temporary directory is writable");
    path
}

/// `mesh` with a third face on the edge of its first face: a non-manifold fin.
fn write_fin(mesh: &TriMesh, path: PathBuf) -> PathBuf {
    let mut obj = String::new();
    for p in mesh.positions() {
        obj.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
    }
    obj.push_str("v 5 5 5\n");
    for f in mesh.faces() {
        obj.push_str(&format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1));
    }
    let [a, b, _] = mesh.faces()[0];
    obj.push_str(&format!(
        "f {} {} {}\n",
        b + 1,
        a + 1,
        mesh.vertex_count() + 1
    ));
    fs::write(&path, obj).expect("the temporary directory is writable");
    path
}

fn json(output: &std::process::Output) -> Value {
    serde_json::from_slice(&output.stdout).expect("one JSON object on stdout")
}

fn eigenvalues(report: &Value) -> Vec<f64> {
    report["eigenvalues"]
        .as_array()
        .expect("eigenvalues")
        .iter()
        .map(|v| v.as_f64().expect("a number"))
        .collect()
}

#[test]
fn a_repaired_soup_has_the_spectrum_of_the_clean_mesh() {
    let dir = scratch("repair_soup");
    let mesh = bumpy_sphere(2, 3, 0.1);
    let soup = write_soup(&mesh, dir.join("soup.obj"));

    // Without --repair the soup is valid but falls apart; the note says what to do.
    let plain = dirac(&["spectrum", text(&soup), "-k", "4", "--operator", "laplace"]);
    assert!(
        stderr(&plain).contains("triangle soup"),
        "{}",
        stderr(&plain)
    );

    let output = dirac(&[
        "spectrum",
        text(&soup),
        "-k",
        "6",
        "--operator",
        "laplace",
        "--repair",
        "--json",
        "-q",
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let report = json(&output);
    assert_eq!(report["vertices"], mesh.vertex_count());
    let merged = &report["preparation"]["repair"]["merged_vertices"]["count"];
    assert_eq!(merged, 3 * mesh.face_count() - mesh.vertex_count());
    assert_eq!(report["repair"], 1e-9);
    let expected = library(&mesh, Operator::Laplace, 6);
    for (got, want) in eigenvalues(&report).iter().zip(&expected.eigenvalues) {
        assert!(
            (got - want).abs() <= 1e-10 * want.abs().max(1.0),
            "{got} vs {want}"
        );
    }
}

#[test]
fn invalid_meshes_name_the_defect_and_the_repair() {
    let dir = scratch("repair_fin");
    let mesh = bumpy_sphere(1, 1, 0.1);
    let fin = write_fin(&mesh, dir.join("fin.obj"));
    let plain = dirac(&["spectrum", text(&fin), "-k", "3"]);
    assert_eq!(plain.status.code(), Some(1));
    let message = stderr(&plain);
    assert!(
        message.contains("shared by 3 faces") && message.contains("--repair"),
        "{message}"
    );

    // Repaired, the fin is a component of its own; --component largest drops it.
    let output = dirac(&[
        "spectrum",
        text(&fin),
        "-k",
        "3",
        "--repair",
        "--component",
        "largest",
        "--json",
        "-q",
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let report = json(&output);
    assert_eq!(report["preparation"]["components"], 2);
    assert_eq!(report["vertices"], mesh.vertex_count());
    assert_eq!(report["preparation"]["repair"]["split_edges"]["count"], 1);

    let missing = dirac(&["spectrum", text(&fin), "--repair", "--component", "7"]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(
        stderr(&missing).contains("component 7 does not exist"),
        "{}",
        stderr(&missing)
    );
    let alone = dirac(&["spectrum", text(&fin), "--merge-distance", "1e-6"]);
    assert_eq!(alone.status.code(), Some(2));
    // Also in a batch, which prepares each mesh itself.
    let out = dir.join("out");
    let batch = dirac(&[
        "batch",
        text(&dir),
        "--merge-distance",
        "1e-6",
        "--out",
        text(&out),
    ]);
    assert_eq!(batch.status.code(), Some(2), "{}", stderr(&batch));
}

#[test]
fn a_mobius_strip_is_named_non_orientable_without_pointing_to_repair() {
    // A strip of 8 quads glued with a half twist: no repair can orient it, so the error says
    // what to do instead of suggesting --repair (which would only say "not orientable").
    let dir = scratch("repair_mobius");
    let n = 8;
    let mut obj = String::new();
    for i in 0..n {
        let u = std::f64::consts::TAU * i as f64 / n as f64;
        for w in [-0.3_f64, 0.3] {
            let (r, z) = (1.0 + w * (u / 2.0).cos(), w * (u / 2.0).sin());
            obj.push_str(&format!("v {} {} {}\n", r * u.cos(), r * u.sin(), z));
        }
    }
    for i in 0..n {
        let (a, b) = (2 * i + 1, 2 * i + 2);
        let (c, d) = if i + 1 < n {
            (2 * i + 3, 2 * i + 4)
        } else {
            (2, 1)
        };
        obj.push_str(&format!("f {a} {c} {d}\nf {a} {d} {b}\n"));
    }
    let path = dir.join("mobius.obj");
    fs::write(&path, obj).expect("the temporary directory is writable");
    let plain = dirac(&["spectrum", text(&path), "-k", "3"]);
    assert_eq!(plain.status.code(), Some(1));
    let message = stderr(&plain);
    assert!(
        message.contains("not orientable") && message.contains("cut the surface"),
        "{message}"
    );
    assert!(!message.contains("--repair"), "{message}");
}

#[test]
fn dirac_repair_writes_a_mesh_that_needs_no_repair() {
    let dir = scratch("repair_command");
    let mesh = bumpy_sphere(1, 2, 0.1);
    let soup = write_soup(&mesh, dir.join("soup.obj"));
    let fixed = dir.join("fixed.ply");
    let output = dirac(&["repair", text(&soup), "--out", text(&fixed), "--json"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let report = json(&output);
    assert_eq!(report["input_vertices"], 3 * mesh.face_count());
    assert_eq!(report["vertices"], mesh.vertex_count());
    assert_eq!(report["faces"], mesh.face_count());

    let again = dirac(&[
        "repair",
        text(&fixed),
        "--out",
        text(&dir.join("again.obj")),
    ]);
    assert_eq!(again.status.code(), Some(0));
    assert!(
        stderr(&again).contains("changed nothing"),
        "{}",
        stderr(&again)
    );
    let off = dirac(&["repair", text(&soup), "--out", text(&dir.join("x.off"))]);
    assert_eq!(off.status.code(), Some(2));
}

#[test]
fn a_batch_with_repair_completes_and_records_it() {
    let dir = scratch("repair_batch");
    let input = dir.join("meshes");
    fs::create_dir_all(&input).expect("the temporary directory is writable");
    let mesh = bumpy_sphere(1, 4, 0.1);
    write_off(&mesh, input.join("clean.off"));
    write_soup(&mesh, input.join("soup.obj"));
    write_fin(&mesh, input.join("fin.obj"));
    let out = dir.join("out");
    let run = |extra: &[&str]| {
        let mut args = vec!["batch", text(&input), "-k", "3", "--out", text(&out), "-q"];
        args.extend_from_slice(extra);
        dirac(&args)
    };
    let repaired = run(&["--repair"]);
    assert_eq!(repaired.status.code(), Some(0), "{}", stderr(&repaired));
    let report = |name: &str| -> Value {
        serde_json::from_str(&fs::read_to_string(out.join(name)).expect("the JSON"))
            .expect("valid JSON")
    };
    assert_eq!(report("soup.obj.json")["repair"], 1e-9);
    // The repaired soup numbers its vertices otherwise: equal up to rounding.
    let clean = eigenvalues(&report("clean.off.json"));
    for (got, want) in eigenvalues(&report("soup.obj.json")).iter().zip(&clean) {
        assert!((got - want).abs() <= 1e-10 * want.abs(), "{got} vs {want}");
    }

    // Without --repair the results of the repaired run are not reused, and the fin fails
    // with the hint.
    let plain = run(&[]);
    assert_eq!(plain.status.code(), Some(4));
    assert!(
        stderr(&plain).contains("--repair fixes"),
        "{}",
        stderr(&plain)
    );
    let summary = fs::read_to_string(out.join("summary.csv")).expect("the summary");
    let status = |name: &str| {
        summary
            .lines()
            .find(|line| Path::new(line.split(',').next().unwrap_or("")).ends_with(name))
            .and_then(|line| line.split(',').nth(1))
            .map(String::from)
    };
    assert_eq!(status("clean.off").as_deref(), Some("ok"));
    assert_eq!(status("fin.obj").as_deref(), Some("failed"));
}
