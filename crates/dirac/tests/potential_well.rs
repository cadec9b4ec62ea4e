//! The infinite potential well (paper §5.1, Fig. 7): sphere patches with the same interior and
//! different ragged boundaries have matching low spectra once the well confines the modes,
//! while without the well their spectra differ.

use dirac::TriMesh;
use dirac::generators::SpherePatch;
use dirac::spectrum::{Operator, SpectrumOptions, spectrum};
use dirac::well::PotentialWell;

const CENTER: [f64; 3] = [0.0, 0.0, 1.0];

fn patch(seed: u64) -> TriMesh {
    SpherePatch {
        level: 4,
        center: CENTER,
        radius: 0.9,
        raggedness: 0.5,
        bump_amplitude: 0.08,
        seed,
    }
    .mesh()
    .unwrap()
}

/// The vertex nearest the patch centre, so every patch puts its well at the same point.
fn center_vertex(mesh: &TriMesh) -> usize {
    let distance = |p: &[f64; 3]| (0..3).map(|c| (p[c] - CENTER[c]).powi(2)).sum::<f64>();
    (0..mesh.vertex_count())
        .min_by(|&a, &b| distance(&mesh.positions()[a]).total_cmp(&distance(&mesh.positions()[b])))
        .unwrap()
}

fn low_spectrum(mesh: &TriMesh, operator: Operator, well: bool) -> Vec<f64> {
    let mut options = SpectrumOptions::new(operator, 6);
    if well {
        options.well = Some(PotentialWell {
            center: Some(center_vertex(mesh)),
            ..PotentialWell::with_radius(0.55)
        });
    }
    spectrum(mesh, &options).unwrap().eigenvalues
}

fn max_relative_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()))
        .fold(0.0, f64::max)
}

#[test]
fn ragged_boundaries_do_not_change_the_confined_spectrum() {
    let patches: Vec<TriMesh> = (1..=3).map(patch).collect();
    assert!(
        patches
            .windows(2)
            .all(|w| w[0].face_count() != w[1].face_count()),
        "boundaries differ"
    );
    for operator in [Operator::RelativeDirac, Operator::Laplace] {
        let with_well: Vec<Vec<f64>> = patches
            .iter()
            .map(|m| low_spectrum(m, operator, true))
            .collect();
        let without: Vec<Vec<f64>> = patches
            .iter()
            .map(|m| low_spectrum(m, operator, false))
            .collect();
        println!("{operator:?} with well: {with_well:?}\nwithout: {without:?}");
        let confined = (1..3)
            .map(|i| max_relative_difference(&with_well[0], &with_well[i]))
            .fold(0.0, f64::max);
        let free = (1..3)
            .map(|i| max_relative_difference(&without[0], &without[i]))
            .fold(0.0, f64::max);
        println!("{operator:?}: spread with well {confined:.2e}, without {free:.2e}");
        assert!(
            confined < 0.01,
            "{operator:?}: confined spectra differ by {confined}"
        );
        assert!(
            free > 5.0 * confined,
            "{operator:?}: the boundary should matter without the well"
        );
    }
}
