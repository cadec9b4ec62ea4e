//! The relative Dirac operator `D_{f1,f2}` of two immersions of one triangulation
//! ([`dirac::relative_spectrum`]) against identities it must satisfy: `f2 = f1` is the
//! extrinsic Dirac operator `D_f`; moving `f2` rigidly leaves the spectrum unchanged (`D`
//! changes by a unit quaternion conjugation, translations cancel in the edge differences);
//! scaling `f2` by `c` scales `D`, `A = D* M_F D` by `c²` and `G` by `c`, so every eigenvalue of
//! `A x = λ G x` by `c`.

use dirac::generators::icosphere;
use dirac::{
    ConnectivityMismatch, Normalization, Operator, SpectrumError, SpectrumOptions, TriMesh,
    eigenproblem, relative_eigenproblem, relative_spectrum, spectrum,
};
use qscalar::Quat;

const K: usize = 12;

/// An icosphere squashed into an ellipsoid with a bump: a surface with curvature of both
/// signs and no symmetry, so that eigenvalues are simple.
fn surface() -> TriMesh {
    icosphere(2)
        .map_positions(|[x, y, z]| {
            let bump = 0.3 * (-((x - 0.6).powi(2) + (y - 0.5).powi(2)) * 8.0).exp();
            [
                1.3 * x * (1.0 + bump),
                0.9 * y * (1.0 + bump),
                0.7 * z + 0.1 * x * y,
            ]
        })
        .unwrap()
}

/// Another immersion of the same triangulation: the unit icosphere with a wave.
fn other_surface() -> TriMesh {
    icosphere(2)
        .map_positions(|[x, y, z]| {
            let s = 1.0 + 0.15 * (3.0 * z).sin();
            [s * x, s * y, z]
        })
        .unwrap()
}

fn options(operator: Operator) -> SpectrumOptions {
    SpectrumOptions::new(operator, K)
}

fn assert_close(a: &[f64], b: &[f64], tolerance: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= tolerance * y.abs().max(1.0),
            "{what}: λ_{i} = {x} vs {y}"
        );
    }
}

#[test]
fn relative_to_itself_is_the_extrinsic_dirac_operator() {
    let mesh = surface();
    for normalization in [Normalization::None, Normalization::UnitArea] {
        let mut relative = options(Operator::RelativeDirac);
        relative.normalization = normalization;
        let mut extrinsic = options(Operator::ExtrinsicDirac);
        extrinsic.normalization = normalization;
        let got = relative_spectrum(&mesh, &mesh, &relative).unwrap();
        let want = spectrum(&mesh, &extrinsic).unwrap();
        assert_close(&got.eigenvalues, &want.eigenvalues, 1e-9, "D_{f,f} = D_f");
        assert_eq!(got.kernel.dimension, 1, "constants only");
        // The matrices of the two eigenproblems are the same too (entries assembled alike).
        let got = relative_eigenproblem(&mesh, &mesh, &relative).unwrap();
        let want = eigenproblem(&mesh, &extrinsic).unwrap();
        assert_eq!(got.stiffness.values(), want.stiffness.values());
        assert_eq!(got.coupling.values(), want.coupling.values());
        assert_eq!(got.scale, want.scale);
    }
}

#[test]
fn rigid_motions_of_the_reference_leave_the_spectrum_unchanged() {
    let (mesh, reference) = (surface(), other_surface());
    let base = relative_spectrum(&mesh, &reference, &options(Operator::RelativeDirac)).unwrap();
    let rotation = Quat::new(0.3, -0.5, 0.7, 0.2);
    let rotation = rotation * (1.0 / rotation.norm());
    let moved = reference
        .rotated(rotation)
        .unwrap()
        .translated([2.0, -1.0, 0.5])
        .unwrap();
    let got = relative_spectrum(&mesh, &moved, &options(Operator::RelativeDirac)).unwrap();
    assert_close(
        &got.eigenvalues,
        &base.eigenvalues,
        1e-8,
        "rigid motion of f2",
    );
    // A different reference really is a different operator.
    let itself = relative_spectrum(&mesh, &mesh, &options(Operator::RelativeDirac)).unwrap();
    let gap = (itself.eigenvalues[0] - base.eigenvalues[0]).abs();
    assert!(
        gap > 1e-3 * base.eigenvalues[0].abs(),
        "D_(f1,f2) ≠ D_(f1,f1)"
    );
}

#[test]
fn scaling_the_reference_scales_the_eigenvalues() {
    let (mesh, reference) = (surface(), other_surface());
    let base = relative_spectrum(&mesh, &reference, &options(Operator::RelativeDirac)).unwrap();
    let scaled = reference.scaled(2.5).unwrap();
    let got = relative_spectrum(&mesh, &scaled, &options(Operator::RelativeDirac)).unwrap();
    let want: Vec<f64> = base.eigenvalues.iter().map(|l| 2.5 * l).collect();
    assert_close(&got.eigenvalues, &want, 1e-8, "f2 → 2.5 f2");
}

#[test]
fn the_family_blends_the_relative_operator_with_the_laplacian() {
    // τ = 0 is the Laplacian of f1 whatever the reference.
    let (mesh, reference) = (surface(), other_surface());
    let got =
        relative_spectrum(&mesh, &reference, &options(Operator::Family { tau: 0.0 })).unwrap();
    let want = spectrum(&mesh, &options(Operator::Laplace)).unwrap();
    assert_close(
        &got.eigenvalues,
        &want.eigenvalues,
        1e-8,
        "family:0 = Laplace",
    );
    let blended =
        relative_spectrum(&mesh, &reference, &options(Operator::Family { tau: 0.5 })).unwrap();
    assert!(blended.residuals.iter().all(|r| *r < 1e-6));
}

#[test]
fn another_triangulation_is_refused_with_the_first_difference() {
    let mesh = surface();
    let finer = icosphere(3);
    let error = relative_spectrum(&mesh, &finer, &options(Operator::RelativeDirac)).unwrap_err();
    assert!(matches!(
        error,
        SpectrumError::ReferenceConnectivity(ConnectivityMismatch::VertexCount {
            this: 162,
            other: 642
        })
    ));
    let flipped = mesh.reverse_orientation();
    let error = relative_spectrum(&mesh, &flipped, &options(Operator::RelativeDirac)).unwrap_err();
    match error {
        SpectrumError::ReferenceConnectivity(ConnectivityMismatch::Face {
            face: 0,
            this,
            other,
        }) => {
            assert_eq!(this, mesh.faces()[0]);
            assert_eq!(other, flipped.faces()[0]);
        }
        other => panic!("expected a face mismatch, got {other:?}"),
    }
    assert!(error_text(&mesh, &flipped).contains("face 0 is"));
}

fn error_text(mesh: &TriMesh, reference: &TriMesh) -> String {
    relative_spectrum(mesh, reference, &options(Operator::RelativeDirac))
        .unwrap_err()
        .to_string()
}

#[test]
fn operators_without_the_gauss_map_refuse_a_reference() {
    let mesh = surface();
    for operator in [
        Operator::Laplace,
        Operator::ExtrinsicDirac,
        Operator::ModifiedDirichlet,
    ] {
        let error = relative_spectrum(&mesh, &mesh, &options(operator)).unwrap_err();
        assert!(
            matches!(error, SpectrumError::ReferenceUnused { operator: o } if o == operator),
            "{operator}: {error}"
        );
        assert!(error.to_string().contains("relative-dirac"));
        let error = relative_eigenproblem(&mesh, &mesh, &options(operator)).unwrap_err();
        assert!(matches!(error, SpectrumError::ReferenceUnused { .. }));
    }
}
