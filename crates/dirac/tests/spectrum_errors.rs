//! What `spectrum` returns for options or meshes it cannot work with: typed errors naming the
//! bad value, never a panic.

use dirac::generators::{grid, icosphere};
use dirac::operators::relative_dirac;
use dirac::spectrum::{
    Normalization, Operator, Parameter, Remedy, SecondSurface, SpectrumError, SpectrumOptions,
    relative_spectrum, scale_warning, spectrum,
};
use dirac::well::{PotentialWell, WellError};
use dirac::{MeshError, TriMesh};
use qscalar::{Quat, Scalar};
use qsparse::SparseMatrix;

#[test]
fn counts_outside_one_to_vertex_count_are_rejected() {
    let mesh = icosphere(0);
    for k in [0, 13] {
        let options = SpectrumOptions::new(Operator::Laplace, k);
        assert!(matches!(
            spectrum(&mesh, &options),
            Err(SpectrumError::InvalidCount { k: bad, vertices: 12 }) if bad == k
        ));
    }
}

#[test]
fn tau_outside_the_unit_interval_is_rejected() {
    let mesh = icosphere(0);
    for tau in [-0.1, 1.5, f64::NAN] {
        for operator in [Operator::Family { tau }, Operator::FamilyLiteral { tau }] {
            let result = spectrum(&mesh, &SpectrumOptions::new(operator, 2));
            assert!(
                matches!(
                    result,
                    Err(SpectrumError::InvalidParameter { parameter: Parameter::Weight, value, .. })
                        if value.to_bits() == tau.to_bits()
                ),
                "{operator:?}"
            );
        }
    }
}

#[test]
fn unit_area_normalisation_that_overflows_is_an_error() {
    // A valid triangle of area 5·10⁻²¹ at x = 10³⁰⁰: scaling by 1/sqrt(area) ≈ 1.4·10¹⁰ takes
    // x past the largest double. This used to panic.
    let p = vec![[1e300, 0.0, 0.0], [1e300, 1e-10, 0.0], [1e300, 0.0, 1e-10]];
    let mesh = TriMesh::new(p, vec![[0, 1, 2]]).unwrap();
    let mut options = SpectrumOptions::new(Operator::Laplace, 1);
    options.normalization = Normalization::UnitArea;
    match spectrum(&mesh, &options) {
        Err(SpectrumError::Normalization { scale, source }) => {
            assert!((scale - 1.0 / 5e-21f64.sqrt()).abs() < 1e-6 * scale);
            assert_eq!(source, MeshError::NonFiniteCoordinate { vertex: 0 });
        }
        other => panic!("{other:?}"),
    }
    // Without normalisation the same mesh has a spectrum.
    options.normalization = Normalization::None;
    assert!(spectrum(&mesh, &options).is_ok());
}

#[test]
fn invalid_well_parameters_name_the_parameter() {
    let mesh = icosphere(1);
    for (radius, steepness, height, name) in [
        (f64::NAN, 100.0, 1e10, "radius"),
        (0.5, -1.0, 1e10, "steepness"),
        (0.5, 100.0, f64::INFINITY, "height"),
    ] {
        let mut options = SpectrumOptions::new(Operator::RelativeDirac, 4);
        options.well = Some(PotentialWell {
            center: None,
            radius,
            steepness,
            height,
        });
        assert!(matches!(
            spectrum(&mesh, &options),
            Err(SpectrumError::Well(WellError::InvalidParameter { name: n, .. })) if n == name
        ));
    }
}

/// The literal family at `τ = 1` is `G` against `M`, whose spectrum on a curved mesh is
/// negative down to thousands: solved from the bottom it would need them all. The error says
/// so (a lower bound on the negative eigenvalues and the lowest one) instead of running for
/// minutes and reporting no converged pair, as before it had a limit.
#[test]
fn a_strongly_indefinite_literal_family_is_an_error_that_names_the_blended_one() {
    let mesh = dirac::io::default_mesh();
    let options = SpectrumOptions::new(Operator::FamilyLiteral { tau: 1.0 }, 8);
    match spectrum(&mesh, &options) {
        Err(
            // The constants' eigenvalue 0 is listed: seven nonzero ones are wanted.
            error @ SpectrumError::IndefiniteLiteralFamily {
                wanted: 7,
                negative,
                lowest,
            },
        ) => {
            assert!(negative >= 32 && lowest < -100.0, "{negative} {lowest}");
            assert!(error.to_string().contains("family:T"), "{error}");
        }
        other => panic!("{other:?}"),
    }
}

/// `|D u f| / (|D| |u f|)` for the linear function `u f`: zero when every face is parallel to
/// `u` (`df(X) u df(Y) = df(Y) u df(X)` for three vectors of one plane, or two on one line).
fn relative_image_of_linear_function(
    d: &SparseMatrix<Quat<f64>>,
    f: &[[f64; 3]],
    u: [f64; 3],
) -> f64 {
    let linear: Vec<Quat<f64>> = f
        .iter()
        .map(|&p| Quat::from_vector(u) * Quat::from_vector(p))
        .collect();
    let mut image = vec![Quat::from_real(0.0); d.nrows()];
    d.mul_vec(&linear, &mut image).unwrap();
    let size = |v: &[Quat<f64>]| v.iter().map(|q| q.abs()).fold(0.0, f64::max);
    let operator = d.values().iter().map(|q| q.abs()).fold(0.0, f64::max);
    size(&image) / (operator * size(&linear))
}

/// A short open cylinder (200 segments, height 10⁻³): with exact vertex normals every triangle
/// of normals lies in the plane of the circle, so `D_N` annihilates `u N` for `u` in that
/// plane, a kernel removed like the constants, and the spectrum is solved. With the radius
/// changed by `10⁻¹³` unevenly that kernel is only nearly there, and the factorisation fails.
/// The faces are far from flat, so the error must not advise a flat tolerance (following that
/// advice made the whole mesh "flat" and the operator vanish); it points to the family
/// instead, which is solved.
#[test]
fn a_nearly_developable_mesh_is_not_told_to_raise_the_flat_tolerance() {
    let exact = dirac::generators::cylinder(200, 2, 1e-3).unwrap();
    let options = SpectrumOptions::new(Operator::RelativeDirac, 6);
    let solved = spectrum(&exact, &options).unwrap();
    assert_eq!(solved.kernel.linear_functions, 1);
    // The radius grows by up to 10⁻¹³ from one ring to the other, unevenly around: the rulings
    // stay straight but the surface is no longer developable.
    let bent = exact
        .map_positions(|[x, y, z]| {
            let s = 1.0 + 1e-13 * (5.0 * y.atan2(x)).sin() * z / 1e-3;
            [s * x, s * y, z]
        })
        .unwrap();
    match spectrum(&bent, &options) {
        Err(
            error @ SpectrumError::NearlySingular {
                vertex: Some(_),
                flatness: Some(flatness),
                sliver: None,
                ..
            },
        ) => {
            let message = error.to_string();
            assert!(flatness > 1e-2, "{message}");
            assert!(!message.contains("--flat-tolerance"), "{message}");
            assert!(message.contains("family:T"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let family = SpectrumOptions::new(Operator::Family { tau: 0.5 }, 6);
    assert!(spectrum(&exact, &family).is_ok());
    assert!(spectrum(&bent, &family).is_ok());
}

/// Where the faces around the vertex the factorisation stops at are flat already, raising the
/// flat tolerance cannot help: the message said they were "above the flat tolerance" with
/// flatness 0.0e0 and advised raising it; it names the cause and the family instead.
#[test]
fn a_kernel_the_exact_search_misses_is_not_blamed_on_near_flatness() {
    let error = SpectrumError::NearlySingular {
        vertex: Some(15),
        sliver: None,
        flatness: Some(0.0),
        flat_tolerance: 1e-5,
        remedy: Remedy::Family,
    };
    let message = error.to_string();
    assert!(message.contains("near vertex 15"), "{message}");
    assert!(message.contains("flat already"), "{message}");
    assert!(!message.contains("--flat-tolerance"), "{message}");
    assert!(message.contains("family:T"), "{message}");
}

/// Relative to a reference squashed onto a line (up to `10⁻¹²`), every triangle of `B` is a
/// segment of three distinct points, whose row of `D_{f,B}` annihilates the functions linear
/// along it as well as the constants: `D_{f,B}` annihilates `B` itself (checked here), and
/// possibly more, a kernel the pinned form does not remove. Relative Dirac stops with the typed
/// error, which names the reference and points to the family; the family is solved.
#[test]
fn a_reference_of_segments_is_an_error_for_relative_dirac() {
    let mesh = grid(6, 4, 2.0, 1.0)
        .unwrap()
        .map_positions(|[x, y, _]| [x, y, 0.2 * (2.0 * x).sin() * (3.0 * y).cos()])
        .unwrap();
    let squashed = mesh
        .map_positions(|[x, y, _]| {
            [
                x + std::f64::consts::SQRT_2 * y,
                0.0,
                1e-12 * (x * x + 2.0 * y * y),
            ]
        })
        .unwrap();
    let options = SpectrumOptions::new(Operator::RelativeDirac, 4);
    match relative_spectrum(&mesh, &squashed, &options) {
        Err(
            error @ SpectrumError::ParallelFaces {
                surface: SecondSurface::Reference,
                direction: None,
                ..
            },
        ) => {
            let message = error.to_string();
            assert!(message.contains("segments"), "{message}");
            assert!(message.contains("family:T"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let d = relative_dirac(&mesh, squashed.positions()).unwrap();
    let residue = relative_image_of_linear_function(&d, squashed.positions(), [0.0, 0.0, 1.0]);
    assert!(residue < 1e-12, "|D (k B)| / |D| |k B| = {residue:e}");
    let family = SpectrumOptions::new(Operator::Family { tau: 0.5 }, 4);
    assert!(relative_spectrum(&mesh, &squashed, &family).is_ok());
}

/// The literal family's shift is found by bisecting the exponent between `ε` and Gershgorin's
/// shift. A well of height `5·10⁻³²²` on a mesh whose coordinates reach `4·10¹⁷` makes `ε`
/// underflow to zero, and the bisection's geometric mean stayed at zero forever. Found by the
/// `spectrum` fuzz target as a timeout; the call must return, here within seconds.
#[test]
fn the_literal_family_returns_when_its_regularization_underflows() {
    let positions = vec![
        [-0.5, -0.5, 0.0],
        [0.5, 1.59752e17, 4.28808e17],
        [4.28808e17, 4.28808e17, 0.0],
        [4.28808e17, 4.28808e17, 4.28808e17],
    ];
    let mesh = TriMesh::new(positions, vec![[0, 1, 3], [0, 3, 2]]).unwrap();
    let mut options = SpectrumOptions::new(Operator::FamilyLiteral { tau: 1.0 }, 1);
    options.well = Some(PotentialWell {
        center: None,
        radius: 4.115482555109136e-107,
        steepness: 0.0,
        height: 5.04e-322,
    });
    options.seed = 750448400297870899;
    let (sender, receiver) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let values = spectrum(&mesh, &options).map(|s| s.eigenvalues);
        let _ = sender.send(values.map_err(|e| e.to_string()));
    });
    let values = receiver
        .recv_timeout(std::time::Duration::from_secs(20))
        .expect("spectrum did not return within 20 s");
    if let Ok(values) = values {
        assert!(values.iter().all(|v| v.is_finite()), "{values:?}");
    }
}

/// A well centred on a vertex the mesh does not have is named as the well's centre, with the
/// range to choose from (it was "source vertex", the heat method's word).
#[test]
fn a_well_centre_out_of_range_is_named_as_such() {
    let mesh = icosphere(1);
    let mut options = SpectrumOptions::new(Operator::RelativeDirac, 4);
    options.well = Some(PotentialWell {
        center: Some(42),
        ..PotentialWell::with_radius(0.3)
    });
    match spectrum(&mesh, &options) {
        Err(
            error @ SpectrumError::Well(WellError::CenterOutOfRange {
                vertex: 42,
                vertex_count: 42,
            }),
        ) => {
            let message = error.to_string();
            assert!(message.contains("give one from 0 to 41"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

/// The family weighs `D_N` by scale, so an unnormalised mesh far from unit area is warned of,
/// with the weight its `τ` amounts to at unit area (`τ/(τ + (1−τ)a)` at area `a`); normalised
/// meshes, areas near 1 and other operators are not.
#[test]
fn the_family_on_a_mesh_far_from_unit_area_is_warned_of() {
    let sphere = icosphere(2);
    let area: f64 = (0..sphere.face_count()).map(|t| sphere.face_area(t)).sum();
    let family = SpectrumOptions::new(Operator::Family { tau: 0.5 }, 4);
    let scaled = |s: f64| sphere.map_positions(|p| p.map(|c| s * c)).unwrap();
    for s in [1e-2, 1e2] {
        let warning = scale_warning(&scaled(s), &family).expect("warned");
        let amounts_to = 0.5 / (0.5 + 0.5 * s * s * area);
        assert!(warning.contains(&format!("{amounts_to:.2e}")), "{warning}");
        assert!(warning.contains("--normalize unit-area"), "{warning}");
    }
    assert_eq!(scale_warning(&scaled(1.0), &family), None);
    let mut normalized = family;
    normalized.normalization = Normalization::UnitArea;
    assert_eq!(scale_warning(&scaled(1e-2), &normalized), None);
    let laplace = SpectrumOptions::new(Operator::Laplace, 4);
    assert_eq!(scale_warning(&scaled(1e-2), &laplace), None);
}
