//! `dirac segment`: the `.seg` labels are the library's consensus segmentation of the library's
//! segmentation descriptor, `--segments` and `--seed` are honoured, the `.ply` carries each
//! face's segment colour, the `.png` shows the segments, the `--json` summary agrees with the
//! labels, and bad options are usage errors.

mod support;

use std::fs;
use std::path::Path;

use dirac::descriptors::{Modes, segmentation_descriptor};
use dirac::segmentation::consensus::{ConsensusOptions, segment_by_descriptor};
use dirac::spectrum::Operator;
use dirac_cli::render::segment_colour;

use support::{
    Picture, assert_success, assert_usage_errors, bumpy_sphere, dirac, library, scratch, stderr,
    text, write_off,
};

/// The labels of a `.seg` file.
fn read_labels(path: &Path) -> Vec<usize> {
    fs::read_to_string(path)
        .expect("the .seg exists")
        .lines()
        .map(|line| line.parse().expect("one integer per line"))
        .collect()
}

#[test]
fn seg_output_is_the_librarys_consensus_segmentation() {
    let dir = scratch("segment-seg");
    let mesh = bumpy_sphere(2, 3, 0.15);
    let input = write_off(&mesh, dir.join("sphere.off"));
    let out = dir.join("sphere.seg");
    let output = dirac(&[
        "segment",
        text(&input),
        "-k",
        "12",
        "--json",
        "--out",
        text(&out),
    ]);
    assert_success(&output);
    let labels = read_labels(&out);

    let spectrum = library(&mesh, Operator::RelativeDirac, 12);
    let table = segmentation_descriptor(&Modes::from_spectrum(&spectrum).unwrap()).unwrap();
    let expected = segment_by_descriptor(&mesh, &table, &ConsensusOptions::default()).unwrap();
    assert_eq!(labels, expected.labels);

    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let s = expected.segment_count();
    assert_eq!(summary["segments"], s);
    assert_eq!(summary["faces"], mesh.face_count());
    assert_eq!(summary["operator"], "relative-dirac");
    assert_eq!(summary["levels"].as_array().unwrap().len(), 40);
    let fractions: f64 = summary["area_fractions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_f64().unwrap())
        .sum();
    assert!((fractions - 1.0).abs() < 1e-12);
    let total: f64 = (0..mesh.face_count()).map(|t| mesh.face_area(t)).sum();
    let first: f64 = (0..mesh.face_count())
        .filter(|&t| labels[t] == 0)
        .map(|t| mesh.face_area(t))
        .sum();
    let reported = summary["area_fractions"][0].as_f64().unwrap();
    assert!((reported - first / total).abs() < 1e-12);
}

#[test]
fn a_forced_count_and_the_seed_are_honoured() {
    let dir = scratch("segment-forced");
    let input = write_off(&bumpy_sphere(2, 5, 0.15), dir.join("sphere.off"));
    let run = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let args = [&["segment", text(&input), "-q", "--out", text(&out)], extra].concat();
        assert_success(&dirac(&args));
        read_labels(&out)
    };
    for n in [2, 5] {
        let labels = run("forced.seg", &["--segments", &n.to_string()]);
        let mut distinct = labels.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct, (0..n).collect::<Vec<_>>());
    }
    let a = run("a.seg", &["--seed", "7", "--segments", "4"]);
    let b = run("b.seg", &["--seed", "7", "--segments", "4"]);
    assert_eq!(a, b);
}

#[test]
fn ply_faces_carry_their_segment_colour() {
    let dir = scratch("segment-ply");
    let mesh = bumpy_sphere(2, 8, 0.15);
    let input = write_off(&mesh, dir.join("sphere.off"));
    let (seg, ply) = (dir.join("s.seg"), dir.join("s.ply"));
    for out in [&seg, &ply] {
        let args = [
            "segment",
            text(&input),
            "-q",
            "--segments",
            "3",
            "--out",
            text(out),
        ];
        assert_success(&dirac(&args));
    }
    let labels = read_labels(&seg);
    let contents = fs::read_to_string(&ply).unwrap();
    let (header, body) = contents.split_once("end_header\n").unwrap();
    let face_part = header.split("element face").nth(1).unwrap();
    assert!(face_part.contains("property uchar red"), "{header}");
    let faces: Vec<&str> = body.lines().skip(mesh.vertex_count()).collect();
    assert_eq!(faces.len(), mesh.face_count());
    for (t, line) in faces.iter().enumerate() {
        let numbers: Vec<u32> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        let colour = segment_colour(labels[t]).map(u32::from);
        assert_eq!(numbers[4..], colour, "face {t}");
    }
}

#[test]
fn png_shows_the_segments_with_boundaries() {
    let dir = scratch("segment-png");
    let input = write_off(&bumpy_sphere(2, 9, 0.15), dir.join("sphere.off"));
    let out = dir.join("s.png");
    let args = [
        "segment",
        text(&input),
        "-q",
        "--segments",
        "4",
        "--size",
        "200x160",
    ];
    assert_success(&dirac(&[&args[..], &["--out", text(&out)]].concat()));
    let picture = Picture::read(&out);
    assert_eq!((picture.width, picture.height), (200, 160));
    // Pixels whose hue is that of each segment colour (the light only scales it).
    let hue_of = |[r, g, b]: [u8; 3]| {
        let total = (u32::from(r) + u32::from(g) + u32::from(b)).max(1) as f64;
        [f64::from(r) / total, f64::from(g) / total]
    };
    // A sphere shows about half of itself: at least two of the four segments are in view.
    let mut visible = 0;
    for segment in 0..4 {
        let target = hue_of(segment_colour(segment));
        let matching = (0..picture.height)
            .flat_map(|y| (0..picture.width).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let [r, g, b] = picture.pixel(x, y);
                let h = hue_of([r, g, b]);
                u32::from(r) + u32::from(g) + u32::from(b) > 120
                    && (h[0] - target[0]).abs() < 0.02
                    && (h[1] - target[1]).abs() < 0.02
            })
            .count();
        visible += usize::from(matching > 20);
    }
    assert!(visible >= 2, "{visible} segments in view");
    // Dark boundary pixels.
    let dark = picture
        .rgb
        .chunks(3)
        .filter(|p| p.iter().all(|&c| c < 60))
        .count();
    assert!(dark > 20, "{dark} dark pixels");
}

#[test]
fn bad_options_are_usage_errors_and_impossible_counts_failures() {
    assert_usage_errors(
        &["segment", "-q"],
        &[
            (&["--out", "x.txt"], "expected a .seg, .ply or .png"),
            (
                &["--out", "x.seg", "--min-clusters", "1"],
                "need 2 ≤ min ≤ max",
            ),
            (
                &["--out", "x.seg", "--min-area", "1.5"],
                "not a fraction in [0, 1)",
            ),
            (&["--out", "x.seg", "--segments", "0"], "--segments"),
        ],
    );
    let dir = scratch("segment-too-many");
    let input = write_off(&bumpy_sphere(1, 2, 0.1), dir.join("sphere.off"));
    let out = dir.join("s.seg");
    let output = dirac(&[
        "segment",
        text(&input),
        "-q",
        "--segments",
        "1000",
        "--out",
        text(&out),
    ]);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(stderr(&output).contains("at most"), "{}", stderr(&output));
    assert!(!out.exists(), "nothing written");
}
