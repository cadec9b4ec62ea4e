//! Polygon File Format, ASCII and binary, through `ply-rs-bw`: element `vertex` with scalar
//! `x`, `y`, `z` (any numeric type), element `face` with an integer list `vertex_indices` (or
//! `vertex_index`). Other elements and properties are ignored on reading.

use std::io::{Read, Write};
use std::path::Path;

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    Addable, DefaultElement, ElementDef, Encoding, Header, Ply, Property, PropertyAccess,
    PropertyAccessResult, PropertyDef, PropertyType, ScalarType,
};
use ply_rs_bw::writer::Writer;

use super::{ParseError, RawMesh, WriteError, create, with_path};
use crate::TriMesh;

/// Parses a PLY file (ASCII, binary little or big endian): positions in file order, polygons
/// fan-triangulated.
///
/// Before the payload is parsed, the element counts the header announces are checked against
/// the bytes that follow it ([`ParseError::PlyCountExceedsData`], [`ParseError::PlyEmptyElement`]),
/// so a lying header costs an error, not memory.
///
/// Memory is bounded by the file's size: each entry is parsed into a typed record that holds
/// only what the mesh needs (a vertex's `x, y, z`; a face's index list), and entries of other
/// elements into a record of size zero. Every entry consumes at least one byte of the file and
/// a face index at least one more, so the records and the mesh built from them take at most
/// about 40 bytes per byte of the file (a vertex of three one-byte coordinates: a 32-byte
/// record and a 24-byte position; a polygon of `n` one-byte indices: `8n + 24` bytes of list
/// and `24 (n − 2)` of triangles), besides the file's bytes themselves.
pub fn read_ply_from(mut reader: impl Read) -> Result<RawMesh, ParseError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(|source| ParseError::Io { line: None, source })?;
    replace_non_ascii_in_header(&mut bytes);
    let ply_error = |e: ply_rs_bw::parser::ParseError| ParseError::Ply {
        line: e.line(),
        message: e.to_string(),
    };
    let mut reader = Reader::new(&bytes[..]);
    let header = Parser::<Ignored>::new()
        .read_header(&mut reader)
        .map_err(ply_error)?;
    check_counts_against_data(&header, reader.get_ref().len())?;
    // Elements must be read in the order of the header, each with the parser of its record.
    let mut vertices = None;
    let mut faces = None;
    for element in header.elements.values() {
        match element.name.as_str() {
            "vertex" => {
                let parser = Parser::<VertexRecord>::new();
                vertices = Some(
                    parser
                        .read_payload_for_element(&mut reader, element, &header)
                        .map_err(ply_error)?,
                );
            }
            "face" => {
                let parser = Parser::<FaceRecord>::new();
                faces = Some(
                    parser
                        .read_payload_for_element(&mut reader, element, &header)
                        .map_err(ply_error)?,
                );
            }
            _ => {
                Parser::<Ignored>::new()
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(ply_error)?;
            }
        }
    }
    let missing = |name: &'static str| ParseError::PlyStructure {
        element: name,
        problem: "missing".into(),
    };
    let vertices = vertices.ok_or_else(|| missing("vertex"))?;
    let faces = faces.ok_or_else(|| missing("face"))?;

    let mut mesh = RawMesh {
        positions: Vec::with_capacity(vertices.len()),
        faces: Vec::with_capacity(faces.len()),
    };
    for (index, vertex) in vertices.into_iter().enumerate() {
        let mut p = [0.0; 3];
        for ((c, value), name) in p.iter_mut().zip(vertex.coordinates).zip(["x", "y", "z"]) {
            *c = value.ok_or_else(|| ParseError::PlyValue {
                element: "vertex",
                index,
                problem: format!("no numeric scalar property `{name}`"),
            })?;
        }
        mesh.positions.push(p);
    }
    let vertex_count = mesh.positions.len();
    let mut polygon = Vec::new();
    for (index, face) in faces.into_iter().enumerate() {
        let bad = |problem: String| ParseError::PlyValue {
            element: "face",
            index,
            problem,
        };
        let list = face
            .indices
            .ok_or_else(|| bad("no integer list property `vertex_indices`".into()))?;
        if list.len() < 3 {
            return Err(bad(format!(
                "a face needs at least 3 vertices, found {}",
                list.len()
            )));
        }
        polygon.clear();
        for &i in &list {
            let vertex = usize::try_from(i)
                .ok()
                .filter(|&v| v < vertex_count)
                .ok_or_else(|| {
                    bad(format!(
                        "vertex index {i} does not name one of the {vertex_count} vertices"
                    ))
                })?;
            polygon.push(vertex);
        }
        mesh.push_polygon(&polygon);
    }
    Ok(mesh)
}

/// What a `vertex` entry contributes: its `x`, `y`, `z` (any numeric scalar type), `None`
/// until read. Other properties are dropped as they are parsed.
struct VertexRecord {
    coordinates: [Option<f64>; 3],
}

impl VertexRecord {
    fn set(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        let axis = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return PropertyAccessResult::Ignored,
        };
        self.coordinates[axis] = Some(value);
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for VertexRecord {
    fn new() -> Self {
        Self {
            coordinates: [None; 3],
        }
    }
    fn set_char(&mut self, name: &str, value: i8) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_uchar(&mut self, name: &str, value: u8) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_short(&mut self, name: &str, value: i16) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_ushort(&mut self, name: &str, value: u16) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_int(&mut self, name: &str, value: i32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_uint(&mut self, name: &str, value: u32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        self.set(name, value)
    }
}

/// What a `face` entry contributes: its integer list `vertex_indices` (or `vertex_index`),
/// `None` until read. Other properties are dropped as they are parsed.
struct FaceRecord {
    indices: Option<Vec<i64>>,
}

impl FaceRecord {
    fn set<T: Copy + Into<i64>>(&mut self, name: &str, list: Vec<T>) -> PropertyAccessResult {
        if !matches!(name, "vertex_indices" | "vertex_index") {
            return PropertyAccessResult::Ignored;
        }
        self.indices = Some(list.into_iter().map(Into::into).collect());
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for FaceRecord {
    fn new() -> Self {
        Self { indices: None }
    }
    fn set_list_char(&mut self, name: &str, list: Vec<i8>) -> PropertyAccessResult {
        self.set(name, list)
    }
    fn set_list_uchar(&mut self, name: &str, list: Vec<u8>) -> PropertyAccessResult {
        self.set(name, list)
    }
    fn set_list_short(&mut self, name: &str, list: Vec<i16>) -> PropertyAccessResult {
        self.set(name, list)
    }
    fn set_list_ushort(&mut self, name: &str, list: Vec<u16>) -> PropertyAccessResult {
        self.set(name, list)
    }
    fn set_list_int(&mut self, name: &str, list: Vec<i32>) -> PropertyAccessResult {
        self.set(name, list)
    }
    fn set_list_uint(&mut self, name: &str, list: Vec<u32>) -> PropertyAccessResult {
        self.set(name, list)
    }
}

/// An entry of an element the mesh does not use: parsed (to reach the next element) and
/// dropped. Of size zero, so a vector of any count of them allocates nothing.
struct Ignored;

impl PropertyAccess for Ignored {
    fn new() -> Self {
        Ignored
    }
}

/// Replaces every byte above ASCII in the header's lines (up to the line `end_header`) by `?`:
/// the keywords are ASCII, and the comments and `obj_info` lines downloaded files write in
/// Latin-1 or other encodings would otherwise stop the header's parser, which reads UTF-8. One
/// byte for one, so the payload stays where it is.
fn replace_non_ascii_in_header(bytes: &mut [u8]) {
    let mut start = 0;
    while start < bytes.len() {
        let end =
            (bytes[start..].iter().position(|&b| b == b'\n')).map_or(bytes.len(), |i| start + i);
        let line = &mut bytes[start..end];
        if line.trim_ascii_end() == b"end_header" {
            return;
        }
        for byte in line.iter_mut().filter(|b| !b.is_ascii()) {
            *byte = b'?';
        }
        start = end + 1;
    }
}

/// Checks that the payload can hold what the header announces: every element with entries
/// has a property, and the entries need no more than the `available` bytes after the header.
///
/// The bound is a lower one (binary: the scalar sizes plus the list-length sizes, lists taken
/// empty; ASCII: one line end per entry), so no valid file is rejected. Without it, an element
/// without properties and a count of 10¹⁸ makes the parser build empty entries until memory
/// runs out, because reading them consumes no bytes.
fn check_counts_against_data(header: &Header, available: usize) -> Result<(), ParseError> {
    let mut needed: u128 = 0;
    for element in header.elements.values() {
        if element.count > 0 && element.properties.is_empty() {
            return Err(ParseError::PlyEmptyElement {
                element: element.name.clone(),
                count: element.count,
            });
        }
        let per_entry = match header.encoding {
            Encoding::Ascii => 1,
            Encoding::BinaryLittleEndian | Encoding::BinaryBigEndian => element
                .properties
                .values()
                .map(|p| match &p.data_type {
                    PropertyType::Scalar(t) | PropertyType::List(t, _) => scalar_size(t),
                })
                .sum(),
        };
        needed += element.count as u128 * per_entry as u128;
        if needed > available as u128 {
            return Err(ParseError::PlyCountExceedsData {
                element: element.name.clone(),
                count: element.count,
                needed,
                available,
            });
        }
    }
    Ok(())
}

/// Bytes of one binary scalar.
fn scalar_size(t: &ScalarType) -> usize {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// How [`write_ply_to`] encodes the payload.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PlyEncoding {
    /// Human-readable text.
    #[default]
    Ascii,
    /// Little-endian binary.
    BinaryLittleEndian,
}

/// What [`write_ply_to`] writes besides positions and faces.
#[derive(Debug, Clone, Copy, Default)]
pub struct PlyWriteOptions<'a> {
    /// The encoding.
    pub encoding: PlyEncoding,
    /// A per-vertex `double` property: its name and one value per vertex.
    pub scalar: Option<(&'a str, &'a [f64])>,
    /// Per-vertex colour, written as `uchar` properties `red`, `green`, `blue`.
    pub colors: Option<&'a [[u8; 3]]>,
    /// Per-face colour, written as `uchar` properties `red`, `green`, `blue` of the `face`
    /// element (flat colours, as MeshLab and Blender read them).
    pub face_colors: Option<&'a [[u8; 3]]>,
}

/// Writes `mesh` as PLY: `vertex` with `double x, y, z` (then the optional scalar and colour),
/// `face` with `list uchar uint vertex_indices` (then the optional colour).
pub fn write_ply_to(
    mesh: &TriMesh,
    out: &mut impl Write,
    options: &PlyWriteOptions,
) -> Result<(), WriteError> {
    let n = mesh.vertex_count();
    if u32::try_from(n).is_err() {
        return Err(WriteError::TooManyVertices(n));
    }
    let check_length = |attribute: &str, found: usize| {
        if found == n {
            Ok(())
        } else {
            Err(WriteError::AttributeLength {
                attribute: attribute.to_string(),
                expected: n,
                found,
            })
        }
    };
    let mut vertex_def = ElementDef::new("vertex".into());
    let scalar_property = |name: &str, t| PropertyDef::new(name.into(), PropertyType::Scalar(t));
    for name in ["x", "y", "z"] {
        vertex_def
            .properties
            .add(scalar_property(name, ScalarType::Double));
    }
    if let Some((name, values)) = options.scalar {
        let reserved = ["x", "y", "z", "red", "green", "blue"];
        if name.is_empty() || name.contains(char::is_whitespace) || reserved.contains(&name) {
            return Err(WriteError::BadPropertyName(name.into()));
        }
        check_length(name, values.len())?;
        vertex_def
            .properties
            .add(scalar_property(name, ScalarType::Double));
    }
    if let Some(colors) = options.colors {
        check_length("color", colors.len())?;
        for name in ["red", "green", "blue"] {
            vertex_def
                .properties
                .add(scalar_property(name, ScalarType::UChar));
        }
    }
    let mut face_def = ElementDef::new("face".into());
    face_def.properties.add(PropertyDef::new(
        "vertex_indices".into(),
        PropertyType::List(ScalarType::UChar, ScalarType::UInt),
    ));
    if let Some(colors) = options.face_colors {
        if colors.len() != mesh.face_count() {
            return Err(WriteError::FaceAttributeLength {
                attribute: "color".to_string(),
                expected: mesh.face_count(),
                found: colors.len(),
            });
        }
        for name in ["red", "green", "blue"] {
            face_def
                .properties
                .add(scalar_property(name, ScalarType::UChar));
        }
    }

    let vertices = (0..n)
        .map(|v| {
            let mut e = DefaultElement::new();
            for (name, c) in ["x", "y", "z"].iter().zip(mesh.positions()[v]) {
                e.insert(name.to_string(), Property::Double(c));
            }
            if let Some((name, values)) = options.scalar {
                e.insert(name.into(), Property::Double(values[v]));
            }
            if let Some(colors) = options.colors {
                for (name, c) in ["red", "green", "blue"].iter().zip(colors[v]) {
                    e.insert(name.to_string(), Property::UChar(c));
                }
            }
            e
        })
        .collect();
    let faces = mesh
        .faces()
        .iter()
        .enumerate()
        .map(|(t, f)| {
            let mut e = DefaultElement::new();
            let list = f.iter().map(|&v| v as u32).collect();
            e.insert("vertex_indices".into(), Property::ListUInt(list));
            if let Some(colors) = options.face_colors {
                for (name, c) in ["red", "green", "blue"].iter().zip(colors[t]) {
                    e.insert(name.to_string(), Property::UChar(c));
                }
            }
            e
        })
        .collect();

    let mut ply = Ply::<DefaultElement>::new();
    ply.header.encoding = match options.encoding {
        PlyEncoding::Ascii => Encoding::Ascii,
        PlyEncoding::BinaryLittleEndian => Encoding::BinaryLittleEndian,
    };
    ply.header.elements.add(vertex_def);
    ply.header.elements.add(face_def);
    ply.payload.insert("vertex".into(), vertices);
    ply.payload.insert("face".into(), faces);
    Writer::new()
        .write_ply(out, &mut ply)
        .map(|_| ())
        .map_err(|source| WriteError::Io { path: None, source })
}

/// Writes `mesh` to the PLY file `path` ([`write_ply_to`]).
pub fn write_ply(
    mesh: &TriMesh,
    path: impl AsRef<Path>,
    options: &PlyWriteOptions,
) -> Result<(), WriteError> {
    let path = path.as_ref();
    write_ply_to(mesh, &mut create(path)?, options).map_err(|e| with_path(path, e))
}
