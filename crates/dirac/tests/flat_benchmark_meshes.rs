//! Man-made meshes of the Princeton segmentation benchmark with large exactly flat regions, from
//! `../shared/meshes/psb` when that directory is present (the repository does not carry them;
//! without it the test says so on stderr and checks nothing).
//!
//! Truths computed independently, with numpy and scipy on the 4n×4n real-block matrices
//! assembled from the paper's formulas: the flat vertices (all faces with corner normals equal
//! to `10⁻⁵`) and the smallest `|λ|` of `A x = λ G x` by shift-invert ARPACK with SuperLU on
//! the complement of the kernel.

use std::path::PathBuf;

use dirac::io::read_mesh;
use dirac::spectrum::{Normalization, Operator, SpectrumOptions, spectrum};
use qscalar::Quat;

/// File, quaternionic kernel dimension, and the four eigenvalues of smallest `|λ|` (signed, as
/// printed to five decimals) with the relative accuracy that leaves; on the table and the
/// mechanical part these eigenvalues are ill-conditioned (`λ ≪ λ_max`).
const CASES: [(&str, usize, [f64; 4], f64); 4] = [
    (
        "psb_105.off",
        1066,
        [-47.6424, 47.64386, 48.33915, -48.33916],
        1e-6,
    ),
    (
        "psb_150.off",
        5064,
        [0.40517, -0.40517, 0.48542, -0.48542],
        1e-4,
    ),
    (
        "psb_330.off",
        11608,
        [-0.53398, 0.53398, 0.58705, -0.58705],
        1e-4,
    ),
    (
        "psb_345.off",
        344,
        [50.4567, -51.1194, 59.23002, -59.2842],
        1e-6,
    ),
];

#[test]
fn flat_benchmark_meshes_have_their_exact_kernel_and_every_operator_converges() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes/psb");
    if !dir.is_dir() {
        eprintln!("{} is absent: nothing checked", dir.display());
        return;
    }
    for (file, kernel, smallest, accuracy) in CASES {
        let mesh = read_mesh(dir.join(file)).unwrap();
        let options = |operator| SpectrumOptions {
            normalization: Normalization::UnitArea,
            ..SpectrumOptions::new(operator, 16)
        };
        let dirac = spectrum(&mesh, &options(Operator::RelativeDirac)).unwrap();
        assert_eq!(dirac.kernel.dimension, kernel, "{file}");
        // ±λ pairs agree to ~10⁻⁸ in |λ|, so their order may differ: compare sorted values.
        let mut got = dirac.eigenvalues[..4].to_vec();
        got.sort_by(f64::total_cmp);
        let mut want = smallest.to_vec();
        want.sort_by(f64::total_cmp);
        for (got, want) in got.into_iter().zip(want) {
            assert!(
                (got - want).abs() <= accuracy * want.abs(),
                "{file}: {got} against {want}"
            );
        }
        let squared = spectrum(&mesh, &options(Operator::Squared)).unwrap();
        assert_eq!(squared.kernel.dimension, kernel, "{file}");
        let family = spectrum(&mesh, &options(Operator::Family { tau: 0.5 })).unwrap();
        assert_eq!(family.kernel.dimension, 1, "{file}");
        assert_eq!(family.eigenvalues[0], 0.0);
        // Rigid motions: the flat faces' normals then agree only to rounding.
        let moved = mesh
            .rotated(Quat::new(0.8, -0.3, 0.4, 0.2).normalize())
            .and_then(|m| m.translated([10.0, -4.0, 7.0]))
            .unwrap();
        let again = spectrum(&moved, &options(Operator::RelativeDirac)).unwrap();
        assert_eq!(again.kernel, dirac.kernel, "{file}");
        for (x, y) in again.eigenvalues.iter().zip(&dirac.eigenvalues) {
            assert!(
                (x.abs() - y.abs()).abs() <= accuracy * y.abs(),
                "{file}: {x} vs {y}"
            );
        }
    }
}

#[test]
fn every_benchmark_mesh_and_fandisk_converge_for_every_operator() {
    let shared = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes");
    let Ok(entries) = std::fs::read_dir(shared.join("psb")) else {
        eprintln!("{} is absent: nothing checked", shared.display());
        return;
    };
    let mut meshes: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "off"))
        .collect();
    meshes.sort();
    meshes.push(shared.join("fandisk.off"));
    assert!(meshes.len() >= 20, "{meshes:?}");
    for path in meshes {
        let mesh = read_mesh(&path).unwrap();
        for operator in [
            Operator::RelativeDirac,
            Operator::Family { tau: 0.5 },
            Operator::Squared,
        ] {
            let options = SpectrumOptions {
                normalization: Normalization::UnitArea,
                ..SpectrumOptions::new(operator, 16)
            };
            let result = spectrum(&mesh, &options);
            assert!(
                result.as_ref().is_ok_and(|s| s.eigenvalues.len() == 16),
                "{}, {operator:?}: {:?}",
                path.display(),
                result.err()
            );
        }
    }
}
