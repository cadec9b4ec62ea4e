//! Reading and writing meshes: OBJ, OFF, PLY (ASCII and binary) and STL (ASCII and binary) in,
//! OBJ and PLY out.
//!
//! Readers parse into a [`RawMesh`] (positions and fan-triangulated faces, not yet validated),
//! so malformed files fail with a [`ParseError`] naming the line (OBJ, OFF, ASCII STL) or
//! element (PLY), and a parsed but invalid mesh fails with the [`MeshError`] of
//! [`TriMesh::new`]. No input makes a reader panic. [`read_mesh`] does both steps for a file
//! chosen by extension.
//!
//! OBJ, OFF and ASCII STL files are read line by line: a line ends at `\n` or `\r\n` (a
//! byte-order mark at the start of the file is skipped), `#` starts a comment to the end of the
//! line, and tokens are separated by ASCII whitespace (spaces and tabs). Bytes that are not
//! UTF-8 read as `U+FFFD`: the names and comments downloaded files write in Latin-1 or other
//! encodings are ignored as any name is, and such a byte where a number belongs is a
//! [`ParseError::BadNumber`].

mod obj;
mod off;
mod ply;
mod stl;

use std::fs::File;
use std::io::{self, BufRead};
use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::{MeshError, TriMesh};

pub use obj::{read_obj_from, write_obj, write_obj_to};
pub use off::read_off_from;
pub use ply::{PlyEncoding, PlyWriteOptions, read_ply_from, write_ply, write_ply_to};
pub use stl::read_stl_from;

/// Positions and triangles as read from a file: polygons are fan-triangulated
/// (`v0 v1 … vk ↦ (v0, v_i, v_{i+1})`), vertex order is the file's, nothing is validated yet.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RawMesh {
    /// Vertex positions in file order.
    pub positions: Vec<[f64; 3]>,
    /// Triangles (0-based vertex indices).
    pub faces: Vec<[usize; 3]>,
}

impl RawMesh {
    /// Validates into a [`TriMesh`] ([`TriMesh::new`]).
    pub fn into_mesh(self) -> Result<TriMesh, MeshError> {
        TriMesh::new(self.positions, self.faces)
    }

    /// Validates into a [`TriMesh`], as read from the file `path`: an invalid mesh is the
    /// [`ReadError::Mesh`] naming it.
    pub fn into_mesh_of(self, path: &Path) -> Result<TriMesh, ReadError> {
        self.into_mesh().map_err(|source| ReadError::Mesh {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Validates into a [`TriMesh`], dropping vertices no face uses
    /// ([`TriMesh::with_unreferenced_removed`]; returns the renumbering too).
    pub fn into_mesh_removing_unreferenced(
        self,
    ) -> Result<(TriMesh, Vec<Option<usize>>), MeshError> {
        TriMesh::with_unreferenced_removed(self.positions, self.faces)
    }

    /// Appends the fan triangulation of `polygon` (nothing for fewer than 3 vertices).
    fn push_polygon(&mut self, polygon: &[usize]) {
        for i in 1..polygon.len().saturating_sub(1) {
            self.faces.push([polygon[0], polygon[i], polygon[i + 1]]);
        }
    }
}

/// What is wrong with a file's contents.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ParseError {
    /// Reading failed (including text that is not UTF-8).
    #[error("read failed{}: {source}", at_line(*line))]
    Io {
        /// The line being read (OBJ, OFF), if known.
        line: Option<usize>,
        /// The I/O error.
        source: io::Error,
    },
    /// A token that should be a number is not one.
    #[error("line {line}: `{token}` is not a valid {expected}")]
    BadNumber {
        /// The line (1-based).
        line: usize,
        /// The offending token.
        token: String,
        /// What was expected, e.g. "coordinate" or "vertex index".
        expected: &'static str,
    },
    /// A line has fewer values than its kind needs.
    #[error("line {line}: expected {expected} values, found {found}")]
    MissingValues {
        /// The line (1-based).
        line: usize,
        /// How many values were needed.
        expected: usize,
        /// How many there were.
        found: usize,
    },
    /// A face refers to a vertex that does not exist (OBJ: not defined before the face).
    #[error("line {line}: vertex index {index} does not name one of the {vertex_count} vertices")]
    BadIndex {
        /// The line (1-based).
        line: usize,
        /// The index as written in the file.
        index: i64,
        /// Number of vertices available.
        vertex_count: usize,
    },
    /// A face lists fewer than three vertices.
    #[error("line {line}: a face needs at least 3 vertices, found {found}")]
    PolygonTooSmall {
        /// The line (1-based).
        line: usize,
        /// Number of vertices given.
        found: usize,
    },
    /// The file ended before everything its header announced.
    #[error("unexpected end of file after line {line}: expected {expected}")]
    UnexpectedEnd {
        /// The last line read.
        line: usize,
        /// What was still expected.
        expected: String,
    },
    /// A malformed header (OFF), or a file that is no STL of either kind.
    #[error("line {line}: {message}")]
    BadHeader {
        /// The line (1-based).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A line begins with a keyword that cannot stand there (ASCII STL).
    #[error("line {line}: found `{found}`, expected {expected}")]
    UnexpectedKeyword {
        /// The line (1-based).
        line: usize,
        /// The keyword found.
        found: String,
        /// What may stand there.
        expected: &'static str,
    },
    /// The PLY parser rejected the file.
    #[error("PLY{}: {message}", at_line(*line))]
    Ply {
        /// The line (ASCII PLY and header), if the parser reports one.
        line: Option<usize>,
        /// The parser's message.
        message: String,
    },
    /// A PLY file lacks an element or property the mesh needs, or has it with the wrong type.
    #[error("PLY element `{element}`: {problem}")]
    PlyStructure {
        /// The element (`vertex` or `face`).
        element: &'static str,
        /// What is missing or wrong.
        problem: String,
    },
    /// A PLY header announces more entries than the bytes after it can hold.
    #[error(
        "PLY element `{element}` announces {count} entries; with the elements before it they \
         need at least {needed} bytes, but {available} bytes follow the header"
    )]
    PlyCountExceedsData {
        /// The element whose count does not fit.
        element: String,
        /// The count its header line announces.
        count: usize,
        /// Bytes needed by this element and those before it, at the least.
        needed: u128,
        /// Bytes after `end_header`.
        available: usize,
    },
    /// A PLY element announces entries but declares no property to read them from.
    #[error("PLY element `{element}` announces {count} entries but declares no property")]
    PlyEmptyElement {
        /// The element.
        element: String,
        /// The count its header line announces.
        count: usize,
    },
    /// A PLY element holds a bad value.
    #[error("PLY {element} {index}: {problem}")]
    PlyValue {
        /// The element (`vertex` or `face`).
        element: &'static str,
        /// Which one (0-based).
        index: usize,
        /// What is wrong.
        problem: String,
    },
}

fn at_line(line: Option<usize>) -> String {
    line.map(|l| format!(" at line {l}")).unwrap_or_default()
}

/// The lines of a reader, one at a time, with their 1-based numbers and their comments (`#` to
/// the end of the line) removed. One buffer serves every line: a `String` per line was a third
/// of the time of parsing an OBJ file.
struct Lines<R> {
    reader: R,
    /// The current line as read (its end of line and comment included).
    buffer: String,
    /// Where the current line's content starts and ends in `buffer`.
    start: usize,
    end: usize,
    /// The number of the current line (lines read so far).
    line: usize,
}

impl<R: BufRead> Lines<R> {
    fn new(reader: R) -> Self {
        Self {
            reader,
            buffer: String::new(),
            start: 0,
            end: 0,
            line: 0,
        }
    }

    /// Reads the next line; `false` at the end of the input. Bytes that are not UTF-8 become
    /// `U+FFFD` (module documentation).
    fn advance(&mut self) -> Result<bool, ParseError> {
        // The buffer's allocation serves every line: moved to bytes and back, not copied.
        let mut bytes = std::mem::take(&mut self.buffer).into_bytes();
        bytes.clear();
        let line = self.line + 1;
        let read =
            (self.reader.read_until(b'\n', &mut bytes)).map_err(|source| ParseError::Io {
                line: Some(line),
                source,
            })?;
        self.buffer = match String::from_utf8(bytes) {
            Ok(text) => text,
            Err(error) => String::from_utf8_lossy(error.as_bytes()).into_owned(),
        };
        if read == 0 {
            return Ok(false);
        }
        self.line = line;
        // A byte-order mark (some Windows tools write one) is not part of the first line: read
        // as text it would hide the first statement, e.g. an OBJ file's first vertex.
        self.start = if line == 1 && self.buffer.starts_with('\u{feff}') {
            '\u{feff}'.len_utf8()
        } else {
            0
        };
        let text = &self.buffer[self.start..];
        let text = text.strip_suffix('\n').unwrap_or(text);
        let text = text.strip_suffix('\r').unwrap_or(text);
        self.end = self.start + text.find('#').unwrap_or(text.len());
        Ok(true)
    }

    /// The current line without its end of line and comment.
    fn content(&self) -> &str {
        &self.buffer[self.start..self.end]
    }
}

/// The first three tokens as coordinates (further tokens, such as colours, are ignored).
fn coordinates<'a>(
    mut tokens: impl Iterator<Item = &'a str>,
    line: usize,
) -> Result<[f64; 3], ParseError> {
    let mut p = [0.0; 3];
    for (found, c) in p.iter_mut().enumerate() {
        let token = tokens.next().ok_or(ParseError::MissingValues {
            line,
            expected: 3,
            found,
        })?;
        *c = parse_number(token, line, "coordinate")?;
    }
    Ok(p)
}

/// `token` parsed as a `T`, or [`ParseError::BadNumber`].
fn parse_number<T: std::str::FromStr>(
    token: &str,
    line: usize,
    expected: &'static str,
) -> Result<T, ParseError> {
    token.parse().map_err(|_| ParseError::BadNumber {
        line,
        token: token.to_string(),
        expected,
    })
}

/// Why [`read_mesh`] failed, naming the file.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ReadError {
    /// The file could not be opened.
    #[error("{}: {source}", path.display())]
    Open {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// The path is a directory.
    #[error(
        "{}: is a directory, not a mesh file: name a .obj, .off, .ply or .stl file in it",
        path.display()
    )]
    Directory {
        /// The directory.
        path: PathBuf,
    },
    /// The extension is not `.obj`, `.off`, `.ply` or `.stl` (any case).
    #[error("{}: unknown mesh format (expected a .obj, .off, .ply or .stl file)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The contents are malformed.
    #[error("{}: {source}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        source: ParseError,
    },
    /// The contents parse but do not form a valid mesh.
    #[error("{}: invalid mesh: {source}", path.display())]
    Mesh {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        source: MeshError,
    },
}

/// Why writing a mesh failed.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum WriteError {
    /// Creating or writing the output failed.
    #[error("{}: {source}", path.as_deref().unwrap_or(Path::new("<output>")).display())]
    Io {
        /// The file, when writing to a path.
        path: Option<PathBuf>,
        /// The I/O error.
        source: io::Error,
    },
    /// A per-vertex attribute does not have one value per vertex.
    #[error("per-vertex `{attribute}` has {found} values for {expected} vertices")]
    AttributeLength {
        /// The attribute.
        attribute: String,
        /// Number of vertices.
        expected: usize,
        /// Number of values given.
        found: usize,
    },
    /// A per-face attribute does not have one value per face.
    #[error("per-face `{attribute}` has {found} values for {expected} faces")]
    FaceAttributeLength {
        /// The attribute.
        attribute: String,
        /// Number of faces.
        expected: usize,
        /// Number of values given.
        found: usize,
    },
    /// An attribute name that PLY cannot hold (empty, or containing whitespace) or that
    /// collides with a position or colour property.
    #[error("`{0}` is not a usable PLY property name")]
    BadPropertyName(String),
    /// PLY output stores vertex indices as 32-bit unsigned integers.
    #[error("{0} vertices do not fit 32-bit PLY vertex indices")]
    TooManyVertices(usize),
}

/// A mesh file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ.
    Obj,
    /// Object File Format.
    Off,
    /// Polygon File Format (ASCII or binary).
    Ply,
    /// Stereolithography (ASCII or binary): triangles with their own corners, welded where
    /// their coordinates are equal.
    Stl,
}

impl Format {
    /// The format of a path's extension (case-insensitive), if known.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Self::Obj),
            "off" => Some(Self::Off),
            "ply" => Some(Self::Ply),
            "stl" => Some(Self::Stl),
            _ => None,
        }
    }
}

/// Reads the positions and triangles of a mesh file, the format chosen by extension, without
/// validating them.
pub fn read_raw(path: impl AsRef<Path>) -> Result<RawMesh, ReadError> {
    let path = path.as_ref();
    parse_raw(path, &read_bytes(path)?)
}

/// Reads and validates a mesh file (`.obj`, `.off`, `.ply` or `.stl`, chosen by extension).
pub fn read_mesh(path: impl AsRef<Path>) -> Result<TriMesh, ReadError> {
    let path = path.as_ref();
    parse_mesh(path, &read_bytes(path)?)
}

/// Parses the contents of the mesh file `path` (format chosen by its extension; errors name
/// the file) without validating them: [`read_raw`] for bytes already in memory, e.g. read
/// once to be hashed too.
pub fn parse_raw(path: &Path, bytes: &[u8]) -> Result<RawMesh, ReadError> {
    let format = Format::from_path(path).ok_or_else(|| ReadError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    match format {
        Format::Obj => read_obj_from(bytes),
        Format::Off => read_off_from(bytes),
        Format::Ply => read_ply_from(bytes),
        Format::Stl => read_stl_from(bytes),
    }
    .map_err(|source| ReadError::Parse {
        path: path.to_path_buf(),
        source,
    })
}

/// Parses and validates the contents of the mesh file `path`: [`read_mesh`] for bytes
/// already in memory.
pub fn parse_mesh(path: &Path, bytes: &[u8]) -> Result<TriMesh, ReadError> {
    parse_raw(path, bytes)?.into_mesh_of(path)
}

/// The bytes of `path`; a directory or an unknown extension fails before anything is read.
fn read_bytes(path: &Path) -> Result<Vec<u8>, ReadError> {
    if path.is_dir() {
        return Err(ReadError::Directory {
            path: path.to_path_buf(),
        });
    }
    if Format::from_path(path).is_none() {
        return Err(ReadError::UnknownFormat {
            path: path.to_path_buf(),
        });
    }
    std::fs::read(path).map_err(|source| ReadError::Open {
        path: path.to_path_buf(),
        source,
    })
}

/// Like [`read_mesh`], but vertices no face uses are dropped; returns the renumbering
/// (`old_to_new[i]` for file vertex `i`) too.
pub fn read_mesh_removing_unreferenced(
    path: impl AsRef<Path>,
) -> Result<(TriMesh, Vec<Option<usize>>), ReadError> {
    let path = path.as_ref();
    read_raw(path)?
        .into_mesh_removing_unreferenced()
        .map_err(|source| ReadError::Mesh {
            path: path.to_path_buf(),
            source,
        })
}

/// Creates `path` for writing, buffered.
fn create(path: &Path) -> Result<io::BufWriter<File>, WriteError> {
    File::create(path)
        .map(io::BufWriter::new)
        .map_err(|source| WriteError::Io {
            path: Some(path.to_path_buf()),
            source,
        })
}

/// Names `path` in an error from writing to it.
fn with_path(path: &Path, error: WriteError) -> WriteError {
    match error {
        WriteError::Io { path: None, source } => WriteError::Io {
            path: Some(path.to_path_buf()),
            source,
        },
        other => other,
    }
}

/// The built-in default mesh: Keenan Crane's `spot` (2930 vertices, 5856 faces, closed,
/// genus 0; public domain, see `crates/dirac/data/README.md`), embedded in the binary.
pub fn default_mesh() -> TriMesh {
    read_obj_from(include_str!("../../data/spot.obj").as_bytes())
        .ok()
        .and_then(|raw| raw.into_mesh().ok())
        .expect("the embedded spot.obj is a valid mesh")
}
