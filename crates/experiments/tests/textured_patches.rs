//! Experiment 2 at reduced size: inside the potential well, k-means on the relative Dirac
//! spectra (|λ|) of textured patches is purer than on the Laplace spectra.

use dirac::spectrum::{Normalization, SolverBackend};
use experiments::metrics::mean_kmeans_purity;
use experiments::patches::{PatchConfig, patch_classes, patches, well};
use experiments::spectra::{LAPLACE, RELATIVE_DIRAC, compute_spectra};

#[test]
fn relative_dirac_clusters_patches_better_than_laplace() {
    let config = PatchConfig {
        per_class: 4,
        ..PatchConfig::DEFAULT
    };
    let classes = patch_classes();
    let patches = patches(&config, &classes).unwrap();
    let labels: Vec<usize> = patches.iter().map(|p| p.class).collect();
    let meshes: Vec<_> = patches.iter().map(|p| p.mesh.clone()).collect();
    let tables = compute_spectra(
        &meshes,
        &[LAPLACE, RELATIVE_DIRAC],
        config.k,
        SolverBackend::Native,
        Normalization::None,
        &|i| Some(well(&config, &patches[i])),
    )
    .unwrap();
    let purity: Vec<f64> = tables
        .iter()
        .map(|t| mean_kmeans_purity(&t.magnitudes().spectra, &labels, classes.len(), 100, 4))
        .collect();
    println!(
        "purity: Laplace {:.3}, relative Dirac {:.3}",
        purity[0], purity[1]
    );
    assert!(
        purity[1] > purity[0] + 0.05,
        "relative Dirac {} vs Laplace {}",
        purity[1],
        purity[0]
    );
}
