//! Writing a mesh as OBJ or PLY (ASCII, binary) and reading it back gives the same positions
//! (bit for bit) and faces; PLY per-vertex scalars and colours are written as declared
//! (checked with `ply-rs-bw` directly).

use dirac::TriMesh;
use dirac::generators::{Detail, RandomTessellation, Torus, icosphere};
use dirac::io::{
    PlyEncoding, PlyWriteOptions, WriteError, read_mesh, read_obj_from, read_ply_from, write_obj,
    write_obj_to, write_ply, write_ply_to,
};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};
use proptest::prelude::*;

/// A torus with awkward coordinates (noise and jitter) so decimal round trips are tested.
fn awkward_mesh(seed: u64) -> TriMesh {
    let mut t = Torus::new(2.5, 0.9, 14, 9);
    t.detail = Detail::Noise {
        amplitude: 0.2,
        seed,
    };
    t.tessellation = Some(RandomTessellation { jitter: 0.2, seed });
    t.mesh().unwrap()
}

fn via_obj(mesh: &TriMesh) -> TriMesh {
    let mut bytes = Vec::new();
    write_obj_to(mesh, &mut bytes).unwrap();
    read_obj_from(&bytes[..]).unwrap().into_mesh().unwrap()
}

fn via_ply(mesh: &TriMesh, encoding: PlyEncoding) -> TriMesh {
    let mut bytes = Vec::new();
    let options = PlyWriteOptions {
        encoding,
        ..Default::default()
    };
    write_ply_to(mesh, &mut bytes, &options).unwrap();
    read_ply_from(&bytes[..]).unwrap().into_mesh().unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn round_trips_preserve_the_mesh(seed in any::<u64>()) {
        let mesh = awkward_mesh(seed);
        prop_assert_eq!(&via_obj(&mesh), &mesh);
        prop_assert_eq!(&via_ply(&mesh, PlyEncoding::Ascii), &mesh);
        prop_assert_eq!(&via_ply(&mesh, PlyEncoding::BinaryLittleEndian), &mesh);
    }
}

#[test]
fn ply_scalar_and_colour_are_written_per_vertex() {
    let mesh = icosphere(1);
    let n = mesh.vertex_count();
    let values: Vec<f64> = (0..n).map(|v| (v as f64).sqrt() - 2.5).collect();
    let colors: Vec<[u8; 3]> = (0..n).map(|v| [v as u8, 255 - v as u8, 7]).collect();
    for encoding in [PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian] {
        let mut bytes = Vec::new();
        let options = PlyWriteOptions {
            encoding,
            scalar: Some(("quality", &values)),
            colors: Some(&colors),
            face_colors: None,
        };
        write_ply_to(&mesh, &mut bytes, &options).unwrap();
        let ply = Parser::<DefaultElement>::new()
            .read_ply(&mut &bytes[..])
            .unwrap();
        let vertices = &ply.payload["vertex"];
        assert_eq!(vertices.len(), n);
        for (v, e) in vertices.iter().enumerate() {
            assert_eq!(e["quality"], Property::Double(values[v]));
            assert_eq!(e["red"], Property::UChar(colors[v][0]));
            assert_eq!(e["green"], Property::UChar(colors[v][1]));
            assert_eq!(e["blue"], Property::UChar(colors[v][2]));
        }
        // Our reader ignores the extra properties.
        assert_eq!(
            read_ply_from(&bytes[..]).unwrap().into_mesh().unwrap(),
            mesh
        );
    }
}

#[test]
fn ply_face_colours_are_written_per_face() {
    let mesh = icosphere(1);
    let colors: Vec<[u8; 3]> = (0..mesh.face_count())
        .map(|t| [t as u8, 3 * t as u8, 200])
        .collect();
    for encoding in [PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian] {
        let mut bytes = Vec::new();
        let options = PlyWriteOptions {
            encoding,
            face_colors: Some(&colors),
            ..Default::default()
        };
        write_ply_to(&mesh, &mut bytes, &options).unwrap();
        let ply = Parser::<DefaultElement>::new()
            .read_ply(&mut &bytes[..])
            .unwrap();
        let faces = &ply.payload["face"];
        assert_eq!(faces.len(), mesh.face_count());
        for (t, e) in faces.iter().enumerate() {
            assert_eq!(e["red"], Property::UChar(colors[t][0]));
            assert_eq!(e["green"], Property::UChar(colors[t][1]));
            assert_eq!(e["blue"], Property::UChar(colors[t][2]));
        }
        assert_eq!(
            read_ply_from(&bytes[..]).unwrap().into_mesh().unwrap(),
            mesh
        );
    }
    let short = &colors[1..];
    let options = PlyWriteOptions {
        face_colors: Some(short),
        ..Default::default()
    };
    assert!(matches!(
        write_ply_to(&mesh, &mut Vec::new(), &options),
        Err(WriteError::FaceAttributeLength {
            expected: 80,
            found: 79,
            ..
        })
    ));
}

#[test]
fn ply_attributes_of_the_wrong_length_or_name_are_rejected() {
    let mesh = icosphere(0);
    let short = vec![0.0; 11];
    let options = PlyWriteOptions {
        scalar: Some(("value", &short)),
        ..Default::default()
    };
    assert!(matches!(
        write_ply_to(&mesh, &mut Vec::new(), &options),
        Err(WriteError::AttributeLength {
            expected: 12,
            found: 11,
            ..
        })
    ));
    let values = vec![0.0; 12];
    for name in ["", "two words", "x", "red"] {
        let options = PlyWriteOptions {
            scalar: Some((name, &values)),
            ..Default::default()
        };
        assert!(matches!(
            write_ply_to(&mesh, &mut Vec::new(), &options),
            Err(WriteError::BadPropertyName(_))
        ));
    }
    let colors = vec![[0u8; 3]; 13];
    let options = PlyWriteOptions {
        colors: Some(&colors),
        ..Default::default()
    };
    assert!(matches!(
        write_ply_to(&mesh, &mut Vec::new(), &options),
        Err(WriteError::AttributeLength { found: 13, .. })
    ));
}

#[test]
fn files_round_trip_through_read_mesh() {
    let dir = std::env::temp_dir().join(format!("dirac-io-roundtrip-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mesh = awkward_mesh(42);
    write_obj(&mesh, dir.join("m.obj")).unwrap();
    assert_eq!(read_mesh(dir.join("m.obj")).unwrap(), mesh);
    for (name, encoding) in [
        ("a.ply", PlyEncoding::Ascii),
        ("b.ply", PlyEncoding::BinaryLittleEndian),
    ] {
        let options = PlyWriteOptions {
            encoding,
            ..Default::default()
        };
        write_ply(&mesh, dir.join(name), &options).unwrap();
        assert_eq!(read_mesh(dir.join(name)).unwrap(), mesh);
    }
    let err = write_obj(&mesh, dir.join("no/such/dir/m.obj")).unwrap_err();
    assert!(matches!(err, WriteError::Io { path: Some(_), .. }));
    assert!(err.to_string().contains("m.obj"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
