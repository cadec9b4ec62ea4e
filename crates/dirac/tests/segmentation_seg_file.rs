//! `.seg` files: reading what the benchmark writes, every malformed input as a typed error
//! naming file and line, writing and relabelling; and, when `../shared/meshes/psb` is present
//! (the repository does not carry it; without it the test says so on stderr and checks
//! nothing), the benchmark's 95 human segmentations against their meshes.

use std::path::{Path, PathBuf};

use dirac::io::read_mesh;
use dirac::segmentation::seg_file::{
    SegFileError, read_seg, read_seg_file, relabel_by_first_appearance, write_seg,
};

fn read(text: &str, faces: usize) -> Result<Vec<usize>, SegFileError> {
    read_seg(Path::new("model.seg"), text.as_bytes(), faces)
}

#[test]
fn reads_one_label_per_line_ignoring_surrounding_whitespace_and_trailing_blank_lines() {
    assert_eq!(read("0\n1\n1\n0\n", 4).unwrap(), [0, 1, 1, 0]);
    assert_eq!(read("0\n1", 2).unwrap(), [0, 1], "no final newline");
    assert_eq!(
        read("2\r\n 0 \r\n\t7\r\n", 3).unwrap(),
        [2, 0, 7],
        "CRLF, spaces, tab"
    );
    assert_eq!(
        read("3\n4\n\n  \n", 2).unwrap(),
        [3, 4],
        "blank lines at the end"
    );
    // Not `0…S−1`: kept as written (module doc).
    assert_eq!(read("5\n9\n5\n", 3).unwrap(), [5, 9, 5]);
}

#[test]
fn a_count_that_differs_from_the_face_count_names_both_numbers() {
    let error = read("0\n1\n2\n", 4).unwrap_err();
    assert!(
        matches!(
            error,
            SegFileError::FaceCount {
                labels: 3,
                faces: 4,
                ..
            }
        ),
        "{error:?}"
    );
    let message = error.to_string();
    assert!(message.starts_with("model.seg: "), "{message}");
    assert!(
        message.contains("3 segment numbers for a mesh of 4 faces"),
        "{message}"
    );
    let error = read("0\n1\n2\n0\n1\n", 4).unwrap_err();
    assert!(matches!(
        error,
        SegFileError::FaceCount {
            labels: 5,
            faces: 4,
            ..
        }
    ));
    let error = read("", 1).unwrap_err();
    assert!(matches!(
        error,
        SegFileError::FaceCount {
            labels: 0,
            faces: 1,
            ..
        }
    ));
}

#[test]
fn malformed_lines_are_errors_naming_the_line() {
    let cases: [(&str, usize, &str); 6] = [
        ("0\n1.5\n0\n", 2, "`1.5` is not a segment number"),
        ("0\n0\nabc\n", 3, "`abc` is not a segment number"),
        ("0 1\n0\n", 1, "`0 1` is not a segment number"),
        ("0\n99999999999999999999999\n", 2, "is not a segment number"),
        ("0\n-3\n", 2, "segment number -3 is negative"),
        (
            "0\n\n1\n",
            2,
            "line 2 is blank but more segment numbers follow",
        ),
    ];
    for (text, line, expected) in cases {
        let error = read(text, 3).unwrap_err();
        let found_line = match &error {
            SegFileError::NotAnInteger { line, .. }
            | SegFileError::Negative { line, .. }
            | SegFileError::BlankLine { line, .. } => *line,
            other => panic!("{text:?}: unexpected {other:?}"),
        };
        assert_eq!(found_line, line, "{text:?}");
        let message = error.to_string();
        assert!(message.starts_with("model.seg: line "), "{message}");
        assert!(message.contains(expected), "{text:?}: {message}");
    }
}

#[test]
fn bytes_that_are_not_utf8_are_a_read_error_naming_the_line() {
    let bytes: &[u8] = b"0\n\xff\xfe\n";
    let error = read_seg(Path::new("model.seg"), bytes, 2).unwrap_err();
    assert!(
        matches!(error, SegFileError::Io { line: 2, .. }),
        "{error:?}"
    );
}

#[test]
fn a_missing_file_is_an_open_error_naming_it() {
    let path = Path::new("/nonexistent/directory/model.seg");
    let error = read_seg_file(path, 1).unwrap_err();
    assert!(matches!(error, SegFileError::Open { .. }), "{error:?}");
    assert!(
        error
            .to_string()
            .starts_with("/nonexistent/directory/model.seg: ")
    );
}

#[test]
fn written_files_read_back_to_the_same_labels() {
    let labels = [3, 0, 0, 12, 3, 1];
    let mut bytes = Vec::new();
    write_seg(&labels, &mut bytes).unwrap();
    assert_eq!(
        String::from_utf8(bytes.clone()).unwrap(),
        "3\n0\n0\n12\n3\n1\n"
    );
    assert_eq!(read_seg(Path::new("x.seg"), &bytes[..], 6).unwrap(), labels);
}

#[test]
fn relabelling_numbers_segments_in_order_of_first_appearance() {
    assert_eq!(
        relabel_by_first_appearance(&[7, 7, 2, 9, 2, 7, 0]),
        [0, 0, 1, 2, 1, 0, 3]
    );
    assert_eq!(relabel_by_first_appearance(&["b", "a", "b"]), [0, 1, 0]);
    assert_eq!(
        relabel_by_first_appearance::<usize>(&[]),
        Vec::<usize>::new()
    );
    // Already in the convention: unchanged.
    assert_eq!(relabel_by_first_appearance(&[0, 1, 0, 2]), [0, 1, 0, 2]);
}

#[test]
fn the_benchmark_human_segmentations_match_their_meshes_and_use_zero_to_s_minus_one() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes/psb");
    if !dir.is_dir() {
        eprintln!("{} is absent: nothing checked", dir.display());
        return;
    }
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let mesh_path = entry.unwrap().path();
        if mesh_path.extension().is_none_or(|e| e != "off") {
            continue;
        }
        let mesh = read_mesh(&mesh_path).unwrap();
        let stem = mesh_path.file_stem().unwrap().to_str().unwrap();
        for j in 0.. {
            let seg = dir.join("seg").join(format!("{stem}_{j}.seg"));
            if !seg.is_file() {
                break;
            }
            let labels = read_seg_file(&seg, mesh.face_count()).unwrap();
            let segments = labels.iter().max().unwrap() + 1;
            let mut used = vec![false; segments];
            labels.iter().for_each(|&l| used[l] = true);
            assert!(
                used.iter().all(|&u| u),
                "{}: a number in 0…S−1 is unused",
                seg.display()
            );
            files += 1;
        }
    }
    assert_eq!(files, 95, "19 models with 5 human segmentations each");
}
