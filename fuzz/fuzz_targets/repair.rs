//! Fuzz target: a small raw mesh built from the bytes (up to 12 vertices with moderate, tiny,
//! huge, coincident or non-finite coordinates; up to 24 faces with arbitrary indices, some out
//! of range), optionally with an arbitrary merge distance → `dirac::repair::repair` never
//! panics; when it succeeds the mesh validates again and repairing it reports nothing.

#![no_main]

use dirac::TriMesh;
use dirac::io::RawMesh;
use dirac::repair::{RepairOptions, repair};
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;

/// A coordinate: mostly one of a few grid values (so vertices coincide and faces share edges),
/// sometimes nudged by a tiny amount, sometimes arbitrary bits (NaN, ±∞, subnormal).
fn coordinate(u: &mut Unstructured) -> Result<f64> {
    Ok(match u.int_in_range(0..=7u8)? {
        0 => f64::from_bits(u.arbitrary()?),
        1 => f64::from(u.int_in_range(0..=3u8)?) + f64::from(u.arbitrary::<i8>()?) * 1e-12,
        2 => f64::from(u.arbitrary::<i16>()?) * 1e150,
        _ => f64::from(u.int_in_range(0..=3u8)?),
    })
}

fn raw_mesh(u: &mut Unstructured) -> Result<RawMesh> {
    let n = u.int_in_range(0..=12usize)?;
    let mut positions = Vec::with_capacity(n);
    for _ in 0..n {
        positions.push([coordinate(u)?, coordinate(u)?, coordinate(u)?]);
    }
    let mut faces = Vec::new();
    for _ in 0..u.int_in_range(0..=24usize)? {
        let mut f = [0; 3];
        for i in &mut f {
            // Mostly in range; `n + 2` and `usize::MAX` are out of range.
            *i = match u.int_in_range(0..=15u8)? {
                0 => usize::MAX,
                _ => u.int_in_range(0..=n + 2)?,
            };
        }
        faces.push(f);
    }
    Ok(RawMesh { positions, faces })
}

fn run(u: &mut Unstructured) -> Result<()> {
    let raw = raw_mesh(u)?;
    let mut options = RepairOptions::default();
    if u.ratio(1, 4)? {
        options.merge_distance = match u.int_in_range(0..=2u8)? {
            0 => 0.0,
            1 => f64::from_bits(u.arbitrary()?),
            _ => f64::from(u.int_in_range(0..=1000u16)?) * 1e-4,
        };
    }
    let Ok(repaired) = repair(raw, &options) else {
        return Ok(());
    };
    let mesh = &repaired.mesh;
    let again = TriMesh::new(mesh.positions().to_vec(), mesh.faces().to_vec());
    assert!(
        again.is_ok(),
        "the repaired mesh does not validate: {again:?}"
    );
    let raw = RawMesh {
        positions: mesh.positions().to_vec(),
        faces: mesh.faces().to_vec(),
    };
    match repair(raw, &options) {
        Ok(twice) => {
            assert!(
                twice.report.is_empty(),
                "repairing again reported:\n{}",
                twice.report
            );
            assert_eq!(&twice.mesh, mesh);
        }
        Err(error) => panic!("repairing a repaired mesh failed: {error}"),
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
