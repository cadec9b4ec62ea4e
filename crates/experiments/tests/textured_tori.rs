//! Experiment 1 at reduced size: the relative Dirac spectra (|λ|, unit area) separate torus
//! textures better than the Laplace spectra — larger between/within distance ratio and at
//! least the same leave-one-out accuracy.

use dirac::spectrum::{Normalization, SolverBackend};
use experiments::metrics::Scores;
use experiments::spectra::{LAPLACE, RELATIVE_DIRAC, compute_spectra};
use experiments::tori::{ToriConfig, meshes, texture_classes};

#[test]
fn relative_dirac_separates_textures_better_than_laplace() {
    let config = ToriConfig {
        major_segments: 40,
        tessellations: 3,
        k: 30,
    };
    let meshes = meshes(&config, &texture_classes()).unwrap();
    let labels: Vec<usize> = meshes.iter().map(|m| m.class).collect();
    let surfaces: Vec<_> = meshes.into_iter().map(|m| m.mesh).collect();
    let tables = compute_spectra(
        &surfaces,
        &[LAPLACE, RELATIVE_DIRAC],
        config.k,
        SolverBackend::Native,
        Normalization::UnitArea,
        &|_| None,
    )
    .unwrap();
    let scores: Vec<Scores> = tables
        .iter()
        .map(|t| Scores::new(&t.magnitudes().spectra, &labels, 20, 1))
        .collect();
    println!("Laplace {:?}\nrelative Dirac {:?}", scores[0], scores[1]);
    assert!(
        scores[1].ratio > 1.5 * scores[0].ratio,
        "ratio: relative Dirac {} vs Laplace {}",
        scores[1].ratio,
        scores[0].ratio
    );
    assert!(scores[1].nearest_neighbour >= scores[0].nearest_neighbour);
}
