//! OBJ, OFF, PLY and STL readers on small hand-written files: the accepted syntax (corner
//! forms, relative indices, polygons fan-triangulated, comments, extra columns and properties,
//! binary encodings, STL corners welded), and malformed inputs, each of which is a typed error naming the line or
//! element, never a panic.

use dirac::io::{
    ParseError, RawMesh, ReadError, read_mesh, read_obj_from, read_off_from, read_ply_from,
    read_stl_from,
};
use dirac::{MeshError, TriMesh};

fn obj(text: &str) -> Result<dirac::io::RawMesh, ParseError> {
    read_obj_from(text.as_bytes())
}

fn off(text: &str) -> Result<dirac::io::RawMesh, ParseError> {
    read_off_from(text.as_bytes())
}

fn ply(bytes: &[u8]) -> Result<dirac::io::RawMesh, ParseError> {
    read_ply_from(bytes)
}

const SQUARE: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
];

// ---------------------------------------------------------------- OBJ

#[test]
fn obj_corner_forms_and_quad_fan() {
    let text = "# a square\nmtllib x.mtl\no square\n\
                v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n\
                g top\nusemtl red\ns off\n\
                f 1/1/1 2/2/1 3/3/1\n\
                g other\n\
                f 1//1 3//1 4//1 # trailing comment\n\
                f 1/1 2/2 3/3 4/3\n";
    let raw = obj(text).unwrap();
    assert_eq!(raw.positions, SQUARE);
    assert_eq!(raw.faces, vec![[0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 2, 3]]);
}

#[test]
fn obj_polygons_are_fan_triangulated_and_groups_share_vertices() {
    let text = "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\ng a\nf 1 2 3 4 5\n";
    let raw = obj(text).unwrap();
    assert_eq!(raw.faces, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    // Groups do not split vertices: two groups sharing an edge form one component.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ng a\nf 1 2 3\ng b\nf 1 3 4\n";
    let mesh = obj(text).unwrap().into_mesh().unwrap();
    assert_eq!(mesh.topology().components.len(), 1);
}

#[test]
fn obj_relative_indices_count_back_from_the_last_vertex() {
    let raw = obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nv 0 1 0\nf -4 -2 -1\n").unwrap();
    assert_eq!(raw.faces, vec![[0, 1, 2], [0, 2, 3]]);
}

#[test]
fn obj_extra_vertex_columns_are_ignored() {
    let raw = obj("v 0 0 0 1 0.5 0.5 0.5\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert_eq!(raw.positions[0], [0.0, 0.0, 0.0]);
}

#[test]
fn obj_malformed_inputs_name_the_line() {
    let head = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let case = |tail: &str| obj(&format!("{head}{tail}")).unwrap_err();
    assert!(matches!(
        case("v 1 x 3\n"),
        ParseError::BadNumber { line: 4, ref token, .. } if token == "x"
    ));
    assert!(matches!(
        case("\n# c\nv 1 2\n"),
        ParseError::MissingValues {
            line: 6,
            expected: 3,
            found: 2
        }
    ));
    assert!(matches!(
        case("f 1 2\n"),
        ParseError::PolygonTooSmall { line: 4, found: 2 }
    ));
    assert!(matches!(
        case("f 1 2 4\n"),
        ParseError::BadIndex {
            line: 4,
            index: 4,
            vertex_count: 3
        }
    ));
    assert!(matches!(
        case("f 0 1 2\n"),
        ParseError::BadIndex { index: 0, .. }
    ));
    assert!(matches!(
        case("f -4 1 2\n"),
        ParseError::BadIndex { index: -4, .. }
    ));
    assert!(matches!(
        case(&format!("f {} 1 2\n", i64::MIN)),
        ParseError::BadIndex { .. }
    ));
    assert!(matches!(
        case("f 1 2 99999999999999999999999\n"),
        ParseError::BadNumber { line: 4, .. }
    ));
    assert!(matches!(
        case("f 1/a 2 x/1\n"),
        ParseError::BadNumber { line: 4, ref token, .. } if token == "x"
    ));
    // A face may not refer forward to a vertex defined later.
    assert!(matches!(
        obj("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap_err(),
        ParseError::BadIndex {
            line: 1,
            vertex_count: 0,
            ..
        }
    ));
    // A byte that is not UTF-8 where a number belongs.
    let mut bytes = head.as_bytes().to_vec();
    bytes.extend_from_slice(b"v \xff 0 0\n");
    assert!(matches!(
        read_obj_from(&bytes[..]).unwrap_err(),
        ParseError::BadNumber { line: 4, ref token, .. } if token == "\u{fffd}"
    ));
}

/// Names and comments in Latin-1 (`Cr\xe9\xe9` for "Créé"), as downloaded files write them, are
/// ignored as any name is: OBJ, OFF, ASCII STL and PLY files read as their UTF-8 twins.
#[test]
fn names_and_comments_that_are_not_utf8_are_ignored() {
    let latin1 = |text: &str| -> Vec<u8> {
        text.chars()
            .map(|c| u8::try_from(u32::from(c)).expect("Latin-1"))
            .collect()
    };
    let obj_text =
        "# Créé par l'exportateur\no pièce\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 # façade\n";
    let off_text = "OFF # créé\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 # façade\n";
    let stl_text = "solid pièce\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                    vertex 0 1 0\nendloop\nendfacet\nendsolid pièce\n";
    let ply_text = "ply\nformat ascii 1.0\ncomment créé\nobj_info pièce\nelement vertex 3\n\
                    property float x\nproperty float y\nproperty float z\nelement face 1\n\
                    property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n\
                    3 0 1 2\n";
    type Reader = fn(&[u8]) -> Result<RawMesh, ParseError>;
    let readers: [(&str, Reader, &str); 4] = [
        ("obj", |bytes| read_obj_from(bytes), obj_text),
        ("off", |bytes| read_off_from(bytes), off_text),
        ("stl", read_stl_from, stl_text),
        ("ply", |bytes| read_ply_from(bytes), ply_text),
    ];
    for (name, read, text) in readers {
        let utf8 = read(text.as_bytes()).unwrap();
        let other = read(&latin1(text)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(other.positions, utf8.positions, "{name}");
        assert_eq!(other.faces, vec![[0, 1, 2]], "{name}");
    }
}

#[test]
fn obj_nan_coordinates_fail_validation() {
    let raw = obj("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert_eq!(
        raw.into_mesh(),
        Err(MeshError::NonFiniteCoordinate { vertex: 1 })
    );
    let raw = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    assert!(matches!(
        raw.into_mesh(),
        Err(MeshError::Empty { faces: 0, .. })
    ));
}

// ---------------------------------------------------------------- OFF

#[test]
fn off_with_comments_colours_and_a_quad() {
    let text = "OFF\n# comment\n\n4 2 5\n0 0 0\n1 0 0 # x\n1 1 0 255 0 0\n0 1 0\n\
                4 0 1 2 3 255 255 255\n3 0 2 1\n";
    let raw = off(text).unwrap();
    assert_eq!(raw.positions, SQUARE);
    assert_eq!(raw.faces, vec![[0, 1, 2], [0, 2, 3], [0, 2, 1]]);
}

#[test]
fn off_counts_may_share_the_header_line_and_variants_are_accepted() {
    let body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    for header in ["OFF 3 1 0\n", "COFF\n3 1\n", "NOFF\n3 1 3\n"] {
        let raw = off(&format!("{header}{body}")).unwrap();
        assert_eq!(raw.faces, vec![[0, 1, 2]], "{header}");
    }
}

#[test]
fn off_malformed_inputs_name_the_line() {
    assert!(matches!(
        off("").unwrap_err(),
        ParseError::UnexpectedEnd { line: 0, .. }
    ));
    assert!(matches!(
        off("PLY\n3 1 0\n").unwrap_err(),
        ParseError::BadHeader { line: 1, .. }
    ));
    assert!(matches!(
        off("4OFF\n3 1 0\n").unwrap_err(),
        ParseError::BadHeader { line: 1, .. }
    ));
    assert!(matches!(
        off("OFF\nx 1 0\n").unwrap_err(),
        ParseError::BadNumber { line: 2, .. }
    ));
    assert!(matches!(
        off("OFF\n3\n").unwrap_err(),
        ParseError::MissingValues {
            line: 2,
            expected: 2,
            found: 1
        }
    ));
    assert!(matches!(
        off("OFF\n3 1 0\n0 0 0\n1 0 0\n").unwrap_err(),
        ParseError::UnexpectedEnd { line: 4, ref expected } if expected == "vertex 2 of 3"
    ));
    // Counts that lie about huge sizes fail at the end of the file, without allocating them.
    assert!(matches!(
        off("OFF\n18446744073709551615 18446744073709551615 0\n0 0 0\n").unwrap_err(),
        ParseError::UnexpectedEnd { .. }
    ));
    let head = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
    let case = |tail: &str| off(&format!("{head}{tail}")).unwrap_err();
    assert!(matches!(
        case(""),
        ParseError::UnexpectedEnd { line: 5, .. }
    ));
    assert!(matches!(
        case("3 0 1 3\n"),
        ParseError::BadIndex {
            line: 6,
            index: 3,
            vertex_count: 3
        }
    ));
    assert!(matches!(
        case("3 0 -1 2\n"),
        ParseError::BadIndex { index: -1, .. }
    ));
    assert!(matches!(
        case("2 0 1\n"),
        ParseError::PolygonTooSmall { line: 6, found: 2 }
    ));
    assert!(matches!(
        case("5 0 1 2\n"),
        ParseError::MissingValues {
            line: 6,
            expected: 6,
            found: 4
        }
    ));
    // Too few indices is reported before what is wrong with them.
    assert!(matches!(
        case("5 0 x 2\n"),
        ParseError::MissingValues {
            line: 6,
            expected: 6,
            found: 4
        }
    ));
    assert!(matches!(
        case("99999999999999999999999 0 1 2\n"),
        ParseError::BadNumber { line: 6, .. }
    ));
    assert!(matches!(
        case("3 0 1 2.5\n"),
        ParseError::BadNumber { line: 6, .. }
    ));
    assert!(matches!(
        off("OFF\n3 1 0\n0 0\n").unwrap_err(),
        ParseError::MissingValues { line: 3, .. }
    ));
}

/// Lines end at `\n` or `\r\n` (the last one may end the file without either), tokens are
/// separated by spaces or tabs, a comment may follow the content of any line, and a
/// byte-order mark may start the file.
#[test]
fn line_endings_tabs_and_comments() {
    let square = dirac::io::RawMesh {
        positions: SQUARE.to_vec(),
        faces: vec![[0, 1, 2], [0, 2, 3]],
    };
    let text_obj = "v 0 0 0\r\nv 1 0 0 # x\r\nv\t1 1 0\r\nv 0 1 0\r\n#\r\nf 1 2 3\r\nf 1 3 4";
    assert_eq!(obj(text_obj).unwrap(), square);
    let text = "OFF\r\n4 2 0\r\n\r\n0 0 0\r\n1\t0 0\r\n1 1 0 # x\r\n0 1 0\r\n3 0 1 2\r\n3 0 2 3";
    assert_eq!(off(text).unwrap(), square);
    // A byte-order mark does not hide the first vertex or the OFF header.
    assert_eq!(
        obj(&format!("\u{feff}{text_obj}")).unwrap(),
        square,
        "OBJ with a BOM"
    );
    assert_eq!(
        off(&format!("\u{feff}{text}")).unwrap(),
        square,
        "OFF with a BOM"
    );
    // The line numbers count `\r\n` lines.
    assert!(matches!(
        obj("v 0 0 0\r\nv 1 0 0\r\nv 0 x 0\r\n").unwrap_err(),
        ParseError::BadNumber { line: 3, ref token, .. } if token == "x"
    ));
}

// ---------------------------------------------------------------- PLY

const PLY_ASCII: &str = "ply\nformat ascii 1.0\ncomment hand-written\n\
    element vertex 4\nproperty float x\nproperty float y\nproperty double z\n\
    property uchar red\nproperty float nx\n\
    element face 1\nproperty list uchar int vertex_indices\nproperty uchar flags\n\
    element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
    0 0 0 1 0.5\n1 0 0 2 0.5\n1 1 0 3 0.5\n0 1 0 4 0.5\n4 0 1 2 3 7\n0 1\n";

#[test]
fn ply_ascii_with_extra_properties_and_elements() {
    let raw = ply(PLY_ASCII.as_bytes()).unwrap();
    assert_eq!(raw.positions, SQUARE);
    assert_eq!(raw.faces, vec![[0, 1, 2], [0, 2, 3]]);
}

#[test]
fn ply_vertex_index_name_and_other_integer_widths() {
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty int x\nproperty short y\n\
                property uchar z\nelement face 1\nproperty list ushort uint vertex_index\n\
                end_header\n0 0 0\n1 0 0\n0 1 0\n3 2 0 1\n";
    let raw = ply(text.as_bytes()).unwrap();
    assert_eq!(raw.faces, vec![[2, 0, 1]]);
}

/// A binary PLY of the unit square as one quad: `double` positions and a
/// `list uchar ushort` face, in the given byte order.
fn binary_square(little_endian: bool) -> Vec<u8> {
    let format = if little_endian {
        "binary_little_endian"
    } else {
        "binary_big_endian"
    };
    let mut bytes = format!(
        "ply\nformat {format} 1.0\nelement vertex 4\nproperty double x\nproperty double y\n\
         property double z\nelement face 1\nproperty list uchar ushort vertex_indices\nend_header\n"
    )
    .into_bytes();
    for p in SQUARE {
        for c in p {
            bytes.extend(if little_endian {
                c.to_le_bytes()
            } else {
                c.to_be_bytes()
            });
        }
    }
    bytes.push(4);
    for i in 0u16..4 {
        bytes.extend(if little_endian {
            i.to_le_bytes()
        } else {
            i.to_be_bytes()
        });
    }
    bytes
}

#[test]
fn ply_binary_both_byte_orders() {
    for little_endian in [true, false] {
        let raw = ply(&binary_square(little_endian)).unwrap();
        assert_eq!(raw.positions, SQUARE);
        assert_eq!(raw.faces, vec![[0, 1, 2], [0, 2, 3]]);
    }
}

#[test]
fn ply_malformed_inputs_are_typed_errors() {
    assert!(matches!(ply(b"").unwrap_err(), ParseError::Ply { .. }));
    assert!(matches!(
        ply(b"OFF\n3 1 0\n").unwrap_err(),
        ParseError::Ply { .. }
    ));
    // Truncated binary payload: 4 vertices of 24 bytes and one face of at least 1 byte need
    // 97 bytes; the whole payload is 105. Cuts the count check cannot see reach the parser.
    let full = binary_square(true);
    let payload = 4 * 24 + 1 + 4 * 2;
    assert!(matches!(
        ply(&full[..full.len() - 1]).unwrap_err(),
        ParseError::Ply { .. }
    ));
    for (cut, element) in [(9, "face"), (40, "vertex")] {
        match ply(&full[..full.len() - cut]).unwrap_err() {
            ParseError::PlyCountExceedsData {
                element: e,
                needed,
                available,
                ..
            } => {
                assert_eq!(e, element);
                assert_eq!(available, payload - cut);
                assert!(needed > available as u128);
            }
            other => panic!("cut {cut}: {other}"),
        }
    }
    // A vertex count that lies: 4·10⁹ ASCII lines cannot fit in a few dozen bytes.
    let lying = PLY_ASCII.replace("element vertex 4", "element vertex 4000000000");
    assert!(matches!(
        ply(lying.as_bytes()).unwrap_err(),
        ParseError::PlyCountExceedsData { element, count: 4_000_000_000, .. } if element == "vertex"
    ));
    // An element without properties consumes no bytes per entry, so its count cannot be checked
    // against the data; a huge one used to exhaust memory (found by the fuzzer).
    for format in ["ascii", "binary_little_endian"] {
        let empty = format!(
            "ply\nformat {format} 1.0\nelement vertex 2222222222222444444\nelement face 1\n\
             property list uchar int vertex_indices\nend_header\n"
        );
        assert!(matches!(
            ply(empty.as_bytes()).unwrap_err(),
            ParseError::PlyEmptyElement { element, count: 2_222_222_222_222_444_444 }
                if element == "vertex"
        ));
    }
    let header = |vertex_props: &str, face_prop: &str, body: &str| {
        format!(
            "ply\nformat ascii 1.0\nelement vertex 3\n{vertex_props}element face 1\n\
             {face_prop}end_header\n{body}"
        )
    };
    let xyz = "property float x\nproperty float y\nproperty float z\n";
    let list = "property list uchar int vertex_indices\n";
    let verts = "0 0 0\n1 0 0\n0 1 0\n";
    let err = |text: String| ply(text.as_bytes()).unwrap_err();
    assert!(matches!(
        err(header(xyz, list, &format!("{verts}3 0 1 3\n"))),
        ParseError::PlyValue {
            element: "face",
            index: 0,
            ..
        }
    ));
    assert!(matches!(
        err(header(xyz, list, &format!("{verts}3 0 -1 2\n"))),
        ParseError::PlyValue {
            element: "face",
            ..
        }
    ));
    assert!(matches!(
        err(header(xyz, list, &format!("{verts}2 0 1\n"))),
        ParseError::PlyValue {
            element: "face",
            ..
        }
    ));
    assert!(matches!(
        err(header(
            xyz,
            "property list uchar float vertex_indices\n",
            &format!("{verts}3 0 1 2\n")
        )),
        ParseError::PlyValue {
            element: "face",
            ..
        }
    ));
    assert!(matches!(
        err(header(
            "property float x\nproperty float y\n",
            list,
            "0 0\n1 0\n0 1\n3 0 1 2\n"
        )),
        ParseError::PlyValue {
            element: "vertex",
            index: 0,
            ..
        }
    ));
    assert!(matches!(
        err(header(xyz, list, &format!("{verts}3 0 1 x\n"))),
        ParseError::Ply { .. }
    ));
    let no_faces = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                    property float z\nend_header\n0 0 0\n";
    assert!(matches!(
        ply(no_faces.as_bytes()).unwrap_err(),
        ParseError::PlyStructure {
            element: "face",
            ..
        }
    ));
}

// ---------------------------------------------------------------- STL

/// The four faces of a tetrahedron, outward, each as its three corners.
const TETRAHEDRON: [[[f64; 3]; 3]; 4] = [
    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
];

fn ascii_stl(triangles: &[[[f64; 3]; 3]]) -> String {
    let mut text = String::from("solid tetra\n");
    for corners in triangles {
        text += "  facet normal 0 0 0\n    outer loop\n";
        for [x, y, z] in corners {
            text += &format!("      vertex {x:e} {y:e} {z:e}\n");
        }
        text += "    endloop\n  endfacet\n";
    }
    text + "endsolid tetra\n"
}

/// A binary STL whose 80-byte header begins with `header` (which may say `solid`).
fn binary_stl(triangles: &[[[f64; 3]; 3]], header: [u8; 16]) -> Vec<u8> {
    let mut bytes = header.to_vec();
    bytes.resize(80, b' ');
    bytes.extend((triangles.len() as u32).to_le_bytes());
    for corners in triangles {
        bytes.extend([0u8; 12]);
        for c in corners.iter().flatten() {
            bytes.extend((*c as f32).to_le_bytes());
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

#[test]
fn stl_ascii_and_binary_weld_equal_corners_into_one_mesh() {
    let ascii = read_stl_from(ascii_stl(&TETRAHEDRON).as_bytes()).unwrap();
    // Vertices numbered as their first corner appears.
    let positions = vec![
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    assert_eq!(ascii.positions, positions);
    assert_eq!(
        ascii.faces,
        vec![[0, 1, 2], [0, 2, 3], [0, 3, 1], [2, 1, 3]]
    );
    let mesh = ascii.clone().into_mesh().unwrap();
    assert!(mesh.topology().is_closed());
    for header in [*b"binary tetra    ", *b"solid tetra     "] {
        let mut binary = binary_stl(&TETRAHEDRON, header);
        assert_eq!(read_stl_from(&binary).unwrap(), ascii);
        // Bytes after the triangles (some writers pad) are not read.
        binary.extend([0xff; 10]);
        assert_eq!(read_stl_from(&binary).unwrap(), ascii);
    }
    // −0 is the same point as 0; a corner off by one unit in the last place is not.
    let mut moved = TETRAHEDRON;
    moved[1][0] = [-0.0, 0.0, -0.0];
    moved[3][2][2] = f64::from_bits(1.0f64.to_bits() + 1);
    let raw = read_stl_from(ascii_stl(&moved).as_bytes()).unwrap();
    assert_eq!(raw.positions.len(), 5);
    assert_eq!(raw.faces[1][0], 0);
}

#[test]
fn a_mesh_written_as_stl_reads_back_as_the_same_mesh() {
    // Each face written with its own corners, in single precision: welding must find every
    // shared vertex again, and nothing else.
    let spot = dirac::io::default_mesh();
    let triangles: Vec<[[f64; 3]; 3]> = (spot.faces().iter())
        .map(|f| f.map(|v| spot.positions()[v]))
        .collect();
    let raw = read_stl_from(&binary_stl(&triangles, *b"spot            ")).unwrap();
    let mesh = raw.into_mesh().unwrap();
    assert_eq!(mesh.vertex_count(), spot.vertex_count());
    assert_eq!(mesh.face_count(), spot.face_count());
    assert_eq!(mesh.topology().genus(), spot.topology().genus());
    for (read, written) in mesh.faces().iter().zip(&triangles) {
        for (&v, p) in read.iter().zip(written) {
            assert_eq!(mesh.positions()[v], p.map(|x| f64::from(x as f32)));
        }
    }
}

#[test]
fn stl_facets_of_more_corners_are_fan_triangulated_and_solids_may_repeat() {
    let text = "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                vertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid a\n\
                solid b\r\nfacet normal 0 0 1\r\n outer loop\r\n\tvertex 0 0 0\r\n\
                vertex 1 1 0\r\nvertex 2 0 0\r\nendloop\r\nendfacet\r\nendsolid\r\n";
    let raw = read_stl_from(text.as_bytes()).unwrap();
    assert_eq!(raw.positions[..4], SQUARE);
    assert_eq!(raw.faces, vec![[0, 1, 2], [0, 2, 3], [0, 2, 4]]);
}

#[test]
fn stl_malformed_inputs_are_typed_errors() {
    let facet = |body: &str| {
        let text = format!("solid x\nfacet normal 0 0 1\nouter loop\n{body}");
        read_stl_from(text.as_bytes()).unwrap_err()
    };
    assert!(matches!(
        facet("vertex 0 0 0\nvertex 1 0\n"),
        ParseError::MissingValues {
            line: 5,
            expected: 3,
            found: 2
        }
    ));
    assert!(matches!(
        facet("vertex 0 0 0\nvertex 1 x 0\n"),
        ParseError::BadNumber { line: 5, .. }
    ));
    assert!(matches!(
        facet("vertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n"),
        ParseError::PolygonTooSmall { line: 2, found: 2 }
    ));
    assert!(matches!(
        facet("vertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n"),
        ParseError::UnexpectedEnd { line: 6, .. }
    ));
    assert!(matches!(
        facet("vertex 0 0 0\nfacet normal 0 0 1\n"),
        ParseError::UnexpectedKeyword { line: 5, .. }
    ));
    assert!(matches!(
        read_stl_from(b"solid x\nvertex 0 0 0\n").unwrap_err(),
        ParseError::UnexpectedKeyword { line: 2, .. }
    ));
    assert!(matches!(
        read_stl_from(b"OFF\n").unwrap_err(),
        ParseError::BadHeader { line: 1, .. }
    ));
    // A binary file cut short, even one whose header says `solid`, is named as such.
    let mut truncated = binary_stl(&TETRAHEDRON, *b"solid tetra     ");
    truncated.truncate(truncated.len() - 7);
    let error = read_stl_from(&truncated).unwrap_err();
    assert!(
        error.to_string().contains("4 triangles needs 284 bytes"),
        "{error}"
    );
    assert!(error.to_string().contains("has 277"), "{error}");
    assert!(read_stl_from(&[]).is_err());
}

// ---------------------------------------------------------------- files

#[test]
fn read_mesh_names_the_file() {
    let dir = std::env::temp_dir().join(format!("dirac-io-readers-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();

    let path = dir.join("square.OFF");
    std::fs::write(
        &path,
        "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n",
    )
    .unwrap();
    let mesh = read_mesh(&path).unwrap();
    assert_eq!(
        mesh,
        TriMesh::new(SQUARE.to_vec(), vec![[0, 1, 2], [0, 2, 3]]).unwrap()
    );

    let path = dir.join("bad.obj");
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nf 1 2 3\n").unwrap();
    let err = read_mesh(&path).unwrap_err();
    assert!(matches!(
        err,
        ReadError::Parse {
            source: ParseError::BadIndex { line: 3, .. },
            ..
        }
    ));
    assert!(err.to_string().contains("bad.obj: line 3"), "{err}");

    let path = dir.join("unused.obj");
    std::fs::write(&path, "v 0 0 0\nv 5 5 5\nv 1 0 0\nv 0 1 0\nf 1 3 4\n").unwrap();
    let err = read_mesh(&path).unwrap_err();
    assert!(matches!(
        err,
        ReadError::Mesh {
            source: MeshError::UnreferencedVertex { vertex: 1 },
            ..
        }
    ));
    assert!(err.to_string().contains("unused.obj"), "{err}");
    let (mesh, old_to_new) = dirac::io::read_mesh_removing_unreferenced(&path).unwrap();
    assert_eq!(mesh.vertex_count(), 3);
    assert_eq!(old_to_new, vec![Some(0), None, Some(1), Some(2)]);

    assert!(matches!(
        read_mesh(dir.join("mesh.3ds")).unwrap_err(),
        ReadError::UnknownFormat { .. }
    ));
    // A directory, with or without a mesh extension, is named as one.
    let folder = dir.join("folder.obj");
    std::fs::create_dir_all(&folder).unwrap();
    for path in [&dir, &folder] {
        let err = read_mesh(path).unwrap_err();
        assert!(matches!(err, ReadError::Directory { .. }), "{err}");
        assert!(
            err.to_string().contains("is a directory, not a mesh file"),
            "{err}"
        );
    }
    let path = dir.join("tetrahedron.STL");
    std::fs::write(&path, binary_stl(&TETRAHEDRON, *b"solid but binary")).unwrap();
    assert_eq!(read_mesh(&path).unwrap().face_count(), 4);
    assert!(matches!(
        read_mesh(dir.join("missing.ply")).unwrap_err(),
        ReadError::Open { .. }
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}
