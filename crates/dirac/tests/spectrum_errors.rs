//! What `spectrum` returns for options or meshes it cannot work with: typed errors naming the
//! bad value, never a panic.

use dirac::generators::icosphere;
use dirac::spectrum::{
    Normalization, Operator, Parameter, SpectrumError, SpectrumOptions, spectrum,
};
use dirac::well::{PotentialWell, WellError};
use dirac::{MeshError, TriMesh};

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
