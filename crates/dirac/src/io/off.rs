//! Object File Format: an `OFF` header (also `COFF`, `NOFF`, `CNOFF`, `STOFF`, …), a counts
//! line `V F [E]` (possibly on the header line), `V` vertex lines and `F` face lines
//! `n i_1 … i_n [colour…]` with 0-based indices. `#` starts a comment; blank lines are skipped.

use std::io::BufRead;

use super::{ParseError, RawMesh, coordinates, numbered_lines, parse_number};

/// Upper bound on memory reserved from counts a file announces (they may lie).
const MAX_RESERVE: usize = 1 << 16;

/// Parses an OFF file: positions in file order, polygons fan-triangulated, extra columns
/// (vertex normals or colours, face colours) ignored.
pub fn read_off_from(reader: impl BufRead) -> Result<RawMesh, ParseError> {
    let mut lines = numbered_lines(reader);
    let mut last_line = 0;
    // The next line with content, or an error naming what was expected.
    let mut next = |expected: &dyn Fn() -> String| -> Result<(usize, String), ParseError> {
        for item in lines.by_ref() {
            let (line, text) = item?;
            last_line = line;
            if !text.trim().is_empty() {
                return Ok((line, text));
            }
        }
        Err(ParseError::UnexpectedEnd {
            line: last_line,
            expected: expected(),
        })
    };

    let (line, header) = next(&|| "the OFF header".into())?;
    let mut tokens = header.split_whitespace();
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
        (counts_line, counts_text) = next(&|| "the counts line `V F E`".into())?;
    }
    let counts: Vec<&str> = counts_text.split_whitespace().collect();
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
        let (line, text) = next(&|| format!("vertex {k} of {vertex_count}"))?;
        mesh.positions
            .push(coordinates(text.split_whitespace(), line)?);
    }
    let mut polygon = Vec::new();
    for k in 0..face_count {
        let (line, text) = next(&|| format!("face {k} of {face_count}"))?;
        let tokens: Vec<&str> = text.split_whitespace().collect();
        let n: usize = parse_number(tokens[0], line, "polygon size")?;
        if n < 3 {
            return Err(ParseError::PolygonTooSmall { line, found: n });
        }
        if tokens.len() - 1 < n {
            return Err(ParseError::MissingValues {
                line,
                expected: n.saturating_add(1),
                found: tokens.len(),
            });
        }
        polygon.clear();
        for token in &tokens[1..=n] {
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
