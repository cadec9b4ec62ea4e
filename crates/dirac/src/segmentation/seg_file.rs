//! The Princeton segmentation benchmark's `.seg` files: line `i` (0-based) holds the segment
//! number of face `i`, one non-negative decimal integer per line, as many lines as the mesh
//! has faces.
//!
//! What [`read_seg`] accepts, precisely:
//! - whitespace around a number (so `\r\n` line ends too) is ignored;
//! - blank lines at the end of the file are ignored; a blank line followed by further numbers
//!   is an error (face `i` would silently get the label of line `i + 1`);
//! - segment numbers need not be `0…S−1`. The benchmark's README asks for `0…S−1`, but every
//!   measure of [`evaluation`](super::evaluation) depends only on the partition the labels
//!   induce, so gaps or large numbers change nothing there and are kept as written; call
//!   [`relabel_by_first_appearance`] for the `0…S−1` convention. (The 95 human segmentations
//!   of the 19 models in `shared/meshes/psb/seg` all use exactly `0…S−1`.)
//!
//! [`write_seg`] writes labels as given, one per line; this crate writes segmentations
//! relabelled by [`relabel_by_first_appearance`] first.

use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::fs::File;
use std::hash::Hash;
use std::io::{self, BufRead, BufReader, Write};
use std::path::{Path, PathBuf};

use thiserror::Error;

/// Why a `.seg` file could not be read, naming the file (and the line, 1-based, where there
/// is one).
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SegFileError {
    /// The file could not be opened.
    #[error("{}: {source}", path.display())]
    Open {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// Reading failed (including text that is not UTF-8).
    #[error("{}: line {line}: read failed: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The line being read.
        line: usize,
        /// The I/O error.
        source: io::Error,
    },
    /// A line is not a single non-negative integer.
    #[error(
        "{}: line {line}: `{text}` is not a segment number (one non-negative integer per line)",
        path.display()
    )]
    NotAnInteger {
        /// The file.
        path: PathBuf,
        /// The line.
        line: usize,
        /// The line's text, trimmed.
        text: String,
    },
    /// A line holds a negative integer.
    #[error(
        "{}: line {line}: segment number {value} is negative (segment numbers are 0, 1, 2, …)",
        path.display()
    )]
    Negative {
        /// The file.
        path: PathBuf,
        /// The line.
        line: usize,
        /// The number as written.
        value: String,
    },
    /// A blank line before further segment numbers.
    #[error(
        "{}: line {line} is blank but more segment numbers follow: every face needs one, \
         on line i for face i",
        path.display()
    )]
    BlankLine {
        /// The file.
        path: PathBuf,
        /// The blank line.
        line: usize,
    },
    /// The file holds a different number of segment numbers than the mesh has faces.
    #[error(
        "{}: {labels} segment numbers for a mesh of {faces} faces (one line per face, in the \
         mesh file's face order; is it the segmentation of this mesh?)",
        path.display()
    )]
    FaceCount {
        /// The file.
        path: PathBuf,
        /// Number of segment numbers in the file.
        labels: usize,
        /// Number of faces of the mesh.
        faces: usize,
    },
}

/// Reads the per-face segment numbers of a `.seg` file (format and accepted variations in the
/// [module doc](self)) from `reader`, checking there is one per face of a mesh with
/// `face_count` faces; `path` names the file in errors.
pub fn read_seg(
    path: &Path,
    reader: impl BufRead,
    face_count: usize,
) -> Result<Vec<usize>, SegFileError> {
    let mut labels = Vec::with_capacity(face_count);
    // The first blank line not yet followed by a number: an error only if one follows.
    let mut pending_blank = None;
    for (index, text) in reader.lines().enumerate() {
        let line = index + 1;
        let text = text.map_err(|source| SegFileError::Io {
            path: path.to_path_buf(),
            line,
            source,
        })?;
        let text = text.trim();
        if text.is_empty() {
            pending_blank.get_or_insert(line);
            continue;
        }
        if let Some(blank) = pending_blank {
            return Err(SegFileError::BlankLine {
                path: path.to_path_buf(),
                line: blank,
            });
        }
        labels.push(parse_label(path, line, text)?);
    }
    if labels.len() != face_count {
        return Err(SegFileError::FaceCount {
            path: path.to_path_buf(),
            labels: labels.len(),
            faces: face_count,
        });
    }
    Ok(labels)
}

/// [`read_seg`] of the file at `path`.
pub fn read_seg_file(
    path: impl AsRef<Path>,
    face_count: usize,
) -> Result<Vec<usize>, SegFileError> {
    let path = path.as_ref();
    let file = File::open(path).map_err(|source| SegFileError::Open {
        path: path.to_path_buf(),
        source,
    })?;
    read_seg(path, BufReader::new(file), face_count)
}

/// One trimmed, non-empty line as a segment number.
fn parse_label(path: &Path, line: usize, text: &str) -> Result<usize, SegFileError> {
    if let Ok(label) = text.parse::<usize>() {
        return Ok(label);
    }
    let is_negative_integer = text
        .strip_prefix('-')
        .is_some_and(|digits| !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()));
    if is_negative_integer {
        return Err(SegFileError::Negative {
            path: path.to_path_buf(),
            line,
            value: text.to_string(),
        });
    }
    Err(SegFileError::NotAnInteger {
        path: path.to_path_buf(),
        line,
        text: text.to_string(),
    })
}

/// Writes `labels` as a `.seg` file: line `i` holds `labels[i]` in decimal, each line ended
/// by `\n`. Labels are written as given (relabel with [`relabel_by_first_appearance`] for the
/// `0…S−1` convention).
pub fn write_seg(labels: &[usize], writer: impl Write) -> io::Result<()> {
    let mut writer = io::BufWriter::new(writer);
    for label in labels {
        writeln!(writer, "{label}")?;
    }
    writer.flush()
}

/// The same partition with segments numbered `0…S−1` in order of first appearance: the
/// segment of `labels[0]` becomes 0, the next label not seen before 1, and so on. Two faces
/// share a label in the result exactly when they do in `labels`.
pub fn relabel_by_first_appearance<T: Eq + Hash>(labels: &[T]) -> Vec<usize> {
    let mut numbers: HashMap<&T, usize> = HashMap::new();
    labels
        .iter()
        .map(|label| {
            let next = numbers.len();
            match numbers.entry(label) {
                Entry::Occupied(entry) => *entry.get(),
                Entry::Vacant(entry) => *entry.insert(next),
            }
        })
        .collect()
}
