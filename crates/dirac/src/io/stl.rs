//! STL, ASCII and binary: a list of triangles, each with its own three corners and no
//! vertex shared by index. The corners are welded where their coordinates are equal (every
//! STL writer writes a corner shared by several triangles with the same numbers); corners that
//! are merely close stay apart, for [`crate::repair`] to merge if asked. The facet normals are
//! ignored: the corners' order gives the orientation.
//!
//! Binary: an 80-byte header, a little-endian `u32` triangle count, and per triangle a normal
//! and three corners as `f32` and a 2-byte attribute (50 bytes). ASCII: `solid [name]`, then per
//! triangle `facet normal nx ny nz`, `outer loop`, three `vertex x y z` lines, `endloop`,
//! `endfacet`, and `endsolid [name]`; a file may hold several solids. A file is binary when its
//! size is exactly what its count announces (binary headers may begin with `solid` too), else
//! ASCII when it is text beginning with `solid`, else binary if it holds at least the triangles
//! its count announces (bytes after them are ignored).

use std::collections::HashMap;

use super::{Lines, ParseError, RawMesh, coordinates};

/// Bytes of a binary header: 80 of text and the triangle count.
const BINARY_HEADER: usize = 84;
/// Bytes of a binary triangle: normal, three corners, attribute.
const BINARY_TRIANGLE: usize = 50;

/// Parses an STL file (ASCII or binary), welding corners with equal coordinates; vertices are
/// numbered in the order their first corner appears.
pub fn read_stl_from(bytes: &[u8]) -> Result<RawMesh, ParseError> {
    let size = bytes.len() as u128;
    let binary = binary_triangle_count(bytes).map(|count| (count, binary_size(count)));
    // Text never holds a NUL byte; a binary file nearly always does (its attribute bytes),
    // so a binary file whose header begins with `solid` and whose size is wrong (a truncated
    // download) is named as such rather than read as text.
    let text = bytes.trim_ascii_start().starts_with(b"solid") && !bytes.contains(&0);
    match binary {
        Some((count, needed)) if needed == size => Ok(read_binary(bytes, count)),
        _ if text => read_ascii(bytes),
        // Some writers pad a binary file after its triangles.
        Some((count, needed)) if needed < size => Ok(read_binary(bytes, count)),
        _ => Err(not_stl(bytes)),
    }
}

/// Bytes of a binary file of `count` triangles.
fn binary_size(count: usize) -> u128 {
    count as u128 * BINARY_TRIANGLE as u128 + BINARY_HEADER as u128
}

/// The triangle count a binary header announces.
fn binary_triangle_count(bytes: &[u8]) -> Option<usize> {
    let count = bytes.get(80..BINARY_HEADER)?.try_into().ok()?;
    usize::try_from(u32::from_le_bytes(count)).ok()
}

/// Why a file that is neither an ASCII STL nor a binary one with all its triangles was refused.
fn not_stl(bytes: &[u8]) -> ParseError {
    let message = match binary_triangle_count(bytes) {
        Some(count) => format!(
            "not an ASCII STL (text beginning with `solid`), and as a binary STL its count of \
             {count} triangles needs {} bytes, but the file has {} (truncated?)",
            binary_size(count),
            bytes.len()
        ),
        None => format!(
            "not an ASCII STL (text beginning with `solid`), and {} bytes are too few for the \
             {BINARY_HEADER}-byte header of a binary STL",
            bytes.len()
        ),
    };
    ParseError::BadHeader { line: 1, message }
}

/// The first `count` triangles after the binary header of `bytes`, which holds them.
fn read_binary(bytes: &[u8], count: usize) -> RawMesh {
    let mut welder = Welder::with_capacity(count);
    let body = &bytes[BINARY_HEADER..BINARY_HEADER + count * BINARY_TRIANGLE];
    for triangle in body.chunks_exact(BINARY_TRIANGLE) {
        let mut corners = [0; 3];
        // Bytes 0..12 are the facet normal, 48..50 the attribute.
        for (corner, point) in corners.iter_mut().zip(triangle[12..48].chunks_exact(12)) {
            let p: [f64; 3] = std::array::from_fn(|c| {
                let raw = point[4 * c..4 * c + 4].try_into().expect("four bytes");
                f64::from(f32::from_le_bytes(raw))
            });
            *corner = welder.vertex(p);
        }
        welder.mesh.faces.push(corners);
    }
    welder.mesh
}

/// An ASCII file, line by line: the keywords are checked where they carry the mesh (`facet`,
/// `vertex`, `endfacet`) and the others (`outer loop`, `endloop`, `solid`, `endsolid`)
/// accepted where they stand; a facet of more than three corners is fan-triangulated.
fn read_ascii(bytes: &[u8]) -> Result<RawMesh, ParseError> {
    let mut lines = Lines::new(bytes);
    let mut welder = Welder::with_capacity(bytes.len() / 256);
    let mut facet: Option<(usize, Vec<usize>)> = None;
    while lines.advance()? {
        let line = lines.line;
        let mut tokens = lines.content().split_ascii_whitespace();
        match (tokens.next(), facet.as_mut()) {
            (None | Some("solid" | "endsolid" | "outer" | "endloop"), _) => {}
            (Some("facet"), None) => facet = Some((line, Vec::with_capacity(3))),
            (Some("vertex"), Some((_, corners))) => {
                corners.push(welder.vertex(coordinates(tokens, line)?));
            }
            (Some("endfacet"), Some((start, corners))) => {
                if corners.len() < 3 {
                    return Err(ParseError::PolygonTooSmall {
                        line: *start,
                        found: corners.len(),
                    });
                }
                welder.mesh.push_polygon(corners);
                facet = None;
            }
            (Some(keyword), inside) => {
                return Err(ParseError::UnexpectedKeyword {
                    line,
                    found: keyword.to_string(),
                    expected: match inside {
                        Some(_) => "`vertex x y z` or `endfacet` inside a facet",
                        None => "`facet normal nx ny nz`, `solid` or `endsolid` between facets",
                    },
                });
            }
        }
    }
    match facet {
        Some((start, _)) => Err(ParseError::UnexpectedEnd {
            line: lines.line,
            expected: format!("`endfacet` of the facet of line {start}"),
        }),
        None => Ok(welder.mesh),
    }
}

/// Numbers corners by their coordinates: equal coordinates (`−0` equal to `0`), one vertex.
struct Welder {
    mesh: RawMesh,
    index: HashMap<[u64; 3], usize>,
}

impl Welder {
    /// Room for about `triangles` triangles (a closed mesh has half as many vertices), at most
    /// 2¹⁶ reserved: a count a file announces may lie.
    fn with_capacity(triangles: usize) -> Self {
        let triangles = triangles.min(1 << 16);
        Self {
            mesh: RawMesh {
                positions: Vec::with_capacity(triangles / 2),
                faces: Vec::with_capacity(triangles),
            },
            index: HashMap::with_capacity(triangles / 2),
        }
    }

    /// The vertex at `p`, new if no corner before was there.
    fn vertex(&mut self, p: [f64; 3]) -> usize {
        // `+ 0.0` turns −0 into +0, so that both have the same bits.
        let key = p.map(|x| (x + 0.0).to_bits());
        let positions = &mut self.mesh.positions;
        *self.index.entry(key).or_insert_with(|| {
            positions.push(p);
            positions.len() - 1
        })
    }
}
