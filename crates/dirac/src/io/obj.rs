//! Wavefront OBJ: `v x y z` vertices and `f` polygons (`i`, `i/t`, `i//n`, `i/t/n` corners,
//! 1-based or negative = relative). Every other statement is ignored.

use std::io::{BufRead, Write};
use std::path::Path;

use super::{Lines, ParseError, RawMesh, WriteError, coordinates, create, parse_number, with_path};
use crate::TriMesh;

/// Parses an OBJ file: positions in file order, polygons fan-triangulated. A face may only
/// refer to vertices defined before it (as relative indices require).
pub fn read_obj_from(reader: impl BufRead) -> Result<RawMesh, ParseError> {
    let mut mesh = RawMesh::default();
    let mut polygon = Vec::new();
    let mut lines = Lines::new(reader);
    while lines.advance()? {
        let (line, text) = (lines.line, lines.content());
        let mut tokens = text.split_ascii_whitespace();
        match tokens.next() {
            Some("v") => mesh.positions.push(coordinates(tokens, line)?),
            Some("f") => {
                polygon.clear();
                for corner in tokens {
                    polygon.push(vertex_index(corner, line, mesh.positions.len())?);
                }
                if polygon.len() < 3 {
                    return Err(ParseError::PolygonTooSmall {
                        line,
                        found: polygon.len(),
                    });
                }
                mesh.push_polygon(&polygon);
            }
            _ => {}
        }
    }
    Ok(mesh)
}

/// The 0-based vertex of a face corner `i[/t[/n]]`, given `vertex_count` vertices so far.
fn vertex_index(corner: &str, line: usize, vertex_count: usize) -> Result<usize, ParseError> {
    let token = corner.split('/').next().unwrap_or(corner);
    let index: i64 = parse_number(token, line, "vertex index")?;
    let magnitude = usize::try_from(index.unsigned_abs()).unwrap_or(usize::MAX);
    let resolved = match index.signum() {
        1 => Some(magnitude - 1).filter(|&v| v < vertex_count),
        -1 => vertex_count.checked_sub(magnitude),
        _ => None,
    };
    resolved.ok_or(ParseError::BadIndex {
        line,
        index,
        vertex_count,
    })
}

/// Writes `v x y z` lines (shortest decimal that reads back to the same `f64`) and 1-based
/// `f i j k` lines.
pub fn write_obj_to(mesh: &TriMesh, out: &mut impl Write) -> Result<(), WriteError> {
    write_lines(mesh.positions(), mesh.faces(), out)
}

impl RawMesh {
    /// Writes the positions and triangles as they are, valid or not, in the format of
    /// [`write_obj_to`] (e.g. broken test meshes).
    pub fn write_obj_to(&self, out: &mut impl Write) -> Result<(), WriteError> {
        write_lines(&self.positions, &self.faces, out)
    }
}

fn write_lines(
    positions: &[[f64; 3]],
    faces: &[[usize; 3]],
    out: &mut impl Write,
) -> Result<(), WriteError> {
    let io = |source| WriteError::Io { path: None, source };
    for p in positions {
        writeln!(out, "v {} {} {}", p[0], p[1], p[2]).map_err(io)?;
    }
    for f in faces {
        writeln!(out, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1).map_err(io)?;
    }
    out.flush().map_err(io)
}

/// Writes `mesh` to the OBJ file `path` ([`write_obj_to`]).
pub fn write_obj(mesh: &TriMesh, path: impl AsRef<Path>) -> Result<(), WriteError> {
    let path = path.as_ref();
    write_obj_to(mesh, &mut create(path)?).map_err(|e| with_path(path, e))
}
