//! Fuzz target: small meshes with arbitrary geometry (perturbed icosphere or grid, faces
//! possibly dropped, or arbitrary triangles) → mesh validation → every operator's spectrum
//! with arbitrary `k`, `τ`, tolerance, restart limit, normalisation and potential well, alone
//! or relative to a flattened or sheared copy →
//! the descriptors of whatever converged. Every step must return a value or a typed error,
//! never panic: this is the path a user's mesh file and command-line options take.

#![no_main]

use dirac::descriptors::{
    Modes, default_times, default_wave_sampling, dirac_kernel_signature, heat_kernel_signature,
    wave_kernel_signature,
};
use dirac::generators::{grid, icosphere};
use dirac::spectrum::{
    Normalization, Operator, SpectrumError, SpectrumOptions, relative_spectrum, spectrum,
};
use dirac::well::PotentialWell;
use dirac::{TriMesh, operators};
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;

/// A real number: mostly moderate, sometimes tiny, huge, zero or arbitrary bits (NaN, ±∞).
fn real(u: &mut Unstructured) -> Result<f64> {
    Ok(match u.int_in_range(0..=15u8)? {
        0 => f64::from_bits(u.arbitrary()?),
        1 => f64::from(u.arbitrary::<i16>()?) * 1e-12,
        2 => f64::from(u.arbitrary::<i16>()?) * 1e12,
        3 => 0.0,
        _ => f64::from(u.arbitrary::<i16>()?) / 4096.0,
    })
}

/// Positions and faces, not yet validated.
type MeshData = (Vec<[f64; 3]>, Vec<[usize; 3]>);

/// Positions and faces: a small generated mesh with perturbed vertices and possibly some
/// faces dropped, or arbitrary triangles on at most 8 vertices.
fn mesh_data(u: &mut Unstructured) -> Result<MeshData> {
    let base = match u.int_in_range(0..=2u8)? {
        0 => Some(icosphere(0)),
        1 => grid(u.int_in_range(1..=3)?, u.int_in_range(1..=3)?, 1.0, 1.0).ok(),
        _ => None,
    };
    let (mut positions, mut faces) = match base {
        Some(mesh) => (mesh.positions().to_vec(), mesh.faces().to_vec()),
        None => {
            let n = u.int_in_range(3..=8usize)?;
            let mut faces = Vec::new();
            for _ in 0..u.int_in_range(1..=10)? {
                let mut f = [0; 3];
                for i in &mut f {
                    *i = u.int_in_range(0..=n)?;
                }
                faces.push(f);
            }
            (vec![[0.0; 3]; n], faces)
        }
    };
    let perturbation = real(u)?;
    for p in &mut positions {
        for c in p {
            if u.arbitrary()? {
                *c += perturbation * f64::from(u.arbitrary::<i8>()?);
            }
        }
    }
    if u.ratio(1, 4)? {
        let keep: u64 = u.arbitrary()?;
        let mut index = 0;
        faces.retain(|_| {
            index += 1;
            keep >> (index % 64) & 1 == 1
        });
    }
    Ok((positions, faces))
}

fn operator(u: &mut Unstructured) -> Result<Operator> {
    Ok(match u.int_in_range(0..=6u8)? {
        0 => Operator::Laplace,
        1 => Operator::RelativeDirac,
        2 => Operator::ExtrinsicDirac,
        3 => Operator::Family { tau: real(u)? },
        4 => Operator::FamilyLiteral { tau: real(u)? },
        5 => Operator::Squared,
        _ => Operator::ModifiedDirichlet,
    })
}

fn descriptors(u: &mut Unstructured, modes: &Modes) -> Result<()> {
    let count = u.int_in_range(0..=4)?;
    if let Ok(times) = default_times(modes, count) {
        let _ = heat_kernel_signature(modes, &times);
        let _ = dirac_kernel_signature(modes, &times);
    }
    let mut arbitrary_times = Vec::new();
    for _ in 0..u.int_in_range(0..=3)? {
        arbitrary_times.push(real(u)?);
    }
    let _ = heat_kernel_signature(modes, &arbitrary_times);
    let _ = dirac_kernel_signature(modes, &arbitrary_times);
    if let Ok(sampling) = default_wave_sampling(modes, count) {
        let _ = wave_kernel_signature(modes, &sampling);
    }
    Ok(())
}

fn run(u: &mut Unstructured) -> Result<()> {
    let (positions, faces) = mesh_data(u)?;
    let Ok((mesh, _)) = TriMesh::with_unreferenced_removed(positions, faces) else {
        return Ok(());
    };
    let values: Vec<[f64; 3]> = (0..mesh.vertex_count())
        .map(|_| Ok([real(u)?, real(u)?, real(u)?]))
        .collect::<Result<_>>()?;
    let _ = operators::relative_dirac(&mesh, &values);

    let mut options =
        SpectrumOptions::new(operator(u)?, u.int_in_range(0..=mesh.vertex_count() + 1)?);
    options.tolerance = if u.arbitrary()? { real(u)? } else { 1e-8 };
    options.max_restarts = u.int_in_range(0..=30)?;
    options.seed = u.arbitrary()?;
    if u.arbitrary()? {
        options.normalization = Normalization::UnitArea;
    }
    if u.ratio(1, 4)? {
        options.well = Some(PotentialWell {
            center: if u.arbitrary()? {
                Some(u.int_in_range(0..=mesh.vertex_count())?)
            } else {
                None
            },
            radius: real(u)?,
            steepness: real(u)?,
            height: real(u)?,
        });
    }
    // Sometimes relative to a second surface of the same faces: the mesh flattened onto a
    // coordinate plane (a planar reference: a linear function in the kernel) or moved.
    // (Zero bytes, the end of the input, mean no reference: older inputs keep their meaning.)
    let reference = match u.int_in_range(0..=3u8)? {
        2 => mesh.map_positions(|[x, y, _]| [x, y, 0.0]).ok(),
        3 => {
            let shift = real(u)?;
            mesh.map_positions(|[x, y, z]| [x + shift * y, y, z * shift])
                .ok()
        }
        _ => None,
    };
    let solved = match &reference {
        Some(reference) => relative_spectrum(&mesh, reference, &options),
        None => spectrum(&mesh, &options),
    };
    let result = match solved {
        Ok(spectrum) => spectrum,
        Err(SpectrumError::NotConverged { partial, .. }) => *partial,
        Err(_) => return Ok(()),
    };
    if let Ok(modes) = Modes::from_spectrum(&result) {
        descriptors(u, &modes)?;
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
