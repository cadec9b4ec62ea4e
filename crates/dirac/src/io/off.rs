//! Object File Format: an `OFF` header (also `COFF`, `NOFF`, `CNOFF`, `STOFF`, …), a counts
//! line `V F [E]` (possibly on the header line), `V` vertex lines and `F` face lines
//! `n i_1 … i_n [colour…]` with 0-based indices. `#` starts a comment; blank lines are skipped.

use std::io::BufRead;

use super::{Lines, ParseError, RawMesh, coordinates, parse_number};

/// Upper bound on memory reserved from counts a file announces (they may lie).
const MAX_RESERVE: usize = 1 << 16;

/// Parses an OFF file: positions in file order, polygons fan-triangulated, extra columns
/// (vertex normals or colours, face colours) ignored.
pub fn read_off_from(reader: impl BufRead) -> Result<RawMesh, ParseError> {
    let mut lines = Lines::new(reader);
    let (line, header) = next_content(&mut lines, &|| "the OFF header".into())?;
    let mut tokens = header.split_ascii_whitespace();
    let keyword = tokens.next().unwrap_or_default();
    match keyword.strip_suffix("OFF") {
        Some(prefix) if prefix.chars().all(|c| "STCN".contains(c)) => {}
        _ => {
            return Err(ParseError::BadHeader {
                line,
                message: format!("expected an OFF header, found `{keyword}`"),
            });
        }
    }
    let mut counts_text = tokens.collect::<Vec<_>>().join(" ");
    let mut counts_line = line;
    if counts_text.is_empty() {
        let (line, text) = next_content(&mut lines, &|| "the counts line `V F E`".into())?;
        (counts_line, counts_text) = (line, text.to_string());
    }
    let counts: Vec<&str> = counts_text.split_ascii_whitespace().collect();
    if counts.len() < 2 {
        return Err(ParseError::MissingValues {
            line: counts_line,
            expected: 2,
            found: counts.len(),
        });
    }
    let vertex_count: usize = parse_number(counts[0], counts_line, "vertex count")?;
    let face_count: usize = parse_number(counts[1], counts_line, "face count")?;

    let mut mesh = RawMesh {
        positions: Vec::with_capacity(vertex_count.min(MAX_RESERVE)),
        faces: Vec::with_capacity(face_count.min(MAX_RESERVE)),
    };
    for k in 0..vertex_count {
        let (line, text) = next_content(&mut lines, &|| format!("vertex {k} of {vertex_count}"))?;
        mesh.positions
            .push(coordinates(text.split_ascii_whitespace(), line)?);
    }
    let mut polygon = Vec::new();
    for k in 0..face_count {
        let (line, text) = next_content(&mut lines, &|| format!("face {k} of {face_count}"))?;
        let mut tokens = text.split_ascii_whitespace();
        let n: usize = parse_number(tokens.next().unwrap_or_default(), line, "polygon size")?;
        if n < 3 {
            return Err(ParseError::PolygonTooSmall { line, found: n });
        }
        let indices = tokens.clone().count();
        if indices < n {
            return Err(ParseError::MissingValues {
                line,
                expected: n.saturating_add(1),
                found: indices + 1,
            });
        }
        polygon.clear();
        for token in tokens.take(n) {
            let index: i64 = parse_number(token, line, "vertex index")?;
            match usize::try_from(index) {
                Ok(v) if v < vertex_count => polygon.push(v),
                _ => {
                    return Err(ParseError::BadIndex {
                        line,
                        index,
                        vertex_count,
                    });
                }
            }
        }
        mesh.push_polygon(&polygon);
    }
    Ok(mesh)
}

/// The next line with content (blank and comment lines skipped), or an error naming what was
/// `expected` there.
fn next_content<'a, R: BufRead>(
    lines: &'a mut Lines<R>,
    expected: &dyn Fn() -> String,
) -> Result<(usize, &'a str), ParseError> {
    loop {
        if !lines.advance()? {
            return Err(ParseError::UnexpectedEnd {
                line: lines.line,
                expected: expected(),
            });
        }
        if !lines.content().trim_ascii().is_empty() {
            return Ok((lines.line, lines.content()));
        }
    }
}
