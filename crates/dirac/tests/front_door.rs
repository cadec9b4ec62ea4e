//! The crate root's one-call API: operator names and their written form (`family:0.5`), `dirac::eigenproblem` against
//! `dirac::spectrum`, the validation of solver options and stopping a solve from its progress
//! callback.

use std::ops::ControlFlow;

use dirac::spectrum::spectrum_with_progress;
use dirac::{
    Normalization, Operator, OperatorNameError, Parameter, ParseOperatorError, SpectrumError,
    SpectrumOptions, eigenproblem, spectrum,
};
use qscalar::Quat;

#[test]
fn every_operator_round_trips_through_its_name() {
    let operators = [
        Operator::Laplace,
        Operator::RelativeDirac,
        Operator::ExtrinsicDirac,
        Operator::Family { tau: 0.25 },
        Operator::FamilyLiteral { tau: 0.75 },
        Operator::Squared,
        Operator::ModifiedDirichlet,
        Operator::AnisotropicLaplace { anisotropy: 4.0 },
    ];
    assert_eq!(Operator::names().len(), operators.len());
    for operator in operators {
        let value = match operator {
            Operator::Family { tau } | Operator::FamilyLiteral { tau } => Some(tau),
            Operator::AnisotropicLaplace { anisotropy } => Some(anisotropy),
            _ => None,
        };
        assert_eq!(operator.parameter().map(|(_, v)| v), value);
        assert_eq!(Operator::from_name(operator.name(), value), Ok(operator));
    }
    assert_eq!(
        Operator::from_name("family", None),
        Err(OperatorNameError::MissingParameter {
            name: "family",
            parameter: Parameter::Weight
        })
    );
    assert_eq!(
        Operator::from_name("anisotropic-laplace", None),
        Err(OperatorNameError::MissingParameter {
            name: "anisotropic-laplace",
            parameter: Parameter::Anisotropy
        })
    );
    assert_eq!(
        Operator::from_name("laplace", Some(0.5)),
        Err(OperatorNameError::UnexpectedParameter { name: "laplace" })
    );
    let unknown = Operator::from_name("dirac", None).unwrap_err();
    assert!(unknown.to_string().contains("relative-dirac"), "{unknown}");
}

#[test]
fn every_operator_round_trips_through_its_written_form() {
    // Weights whose shortest decimal is not their binary value must read back exactly too.
    let family = [0.0, 0.1, 0.5, 1.0 / 3.0, 1.0].map(|tau| Operator::Family { tau });
    let literal = [0.25, 0.7].map(|tau| Operator::FamilyLiteral { tau });
    let anisotropic =
        [0.0, 0.1, 10.0, 1e6].map(|anisotropy| Operator::AnisotropicLaplace { anisotropy });
    let others = Operator::names()
        .into_iter()
        .filter_map(|name| Operator::from_name(name, None).ok());
    for operator in family
        .into_iter()
        .chain(literal)
        .chain(anisotropic)
        .chain(others)
    {
        let written = operator.to_string();
        assert_eq!(written.parse::<Operator>(), Ok(operator), "{written}");
    }
    assert_eq!(Operator::Family { tau: 0.5 }.to_string(), "family:0.5");
    assert_eq!(
        Operator::FamilyLiteral { tau: 0.25 }.to_string(),
        "family-literal:0.25"
    );
    assert_eq!(Operator::Family { tau: 0.1 }.to_string(), "family:0.1");
    assert_eq!(Operator::RelativeDirac.to_string(), "relative-dirac");
    assert_eq!(Operator::forms().len(), Operator::names().len());
    assert!(Operator::forms().contains(&"anisotropic-laplace:A".to_string()));
}

#[test]
fn badly_written_operators_say_what_is_wrong() {
    let parse = |text: &str| text.parse::<Operator>().unwrap_err();
    assert_eq!(
        parse("family"),
        ParseOperatorError::MissingParameter {
            name: "family",
            parameter: Parameter::Weight
        }
    );
    assert_eq!(
        parse("family:x"),
        ParseOperatorError::InvalidParameter {
            name: "family",
            parameter: Parameter::Weight,
            text: "x".to_string()
        }
    );
    assert_eq!(
        parse("family-literal:inf"),
        ParseOperatorError::InvalidParameter {
            name: "family-literal",
            parameter: Parameter::Weight,
            text: "inf".to_string()
        }
    );
    assert_eq!(
        parse("family:2"),
        ParseOperatorError::ParameterOutOfRange {
            name: "family",
            parameter: Parameter::Weight,
            value: 2.0
        }
    );
    assert_eq!(
        parse("anisotropic-laplace:x"),
        ParseOperatorError::InvalidParameter {
            name: "anisotropic-laplace",
            parameter: Parameter::Anisotropy,
            text: "x".to_string()
        }
    );
    assert_eq!(
        parse("laplace:0.5"),
        ParseOperatorError::UnexpectedParameter { name: "laplace" }
    );
    assert_eq!(
        parse("family").to_string(),
        "operator family needs the weight τ of D_N: family:T with T in [0, 1], e.g. family:0.5"
    );
    assert!(
        parse("laplace:0.5")
            .to_string()
            .contains("family:T, family-literal:T, anisotropic-laplace:A"),
        "{}",
        parse("laplace:0.5")
    );
    assert_eq!(
        parse("dirac"),
        ParseOperatorError::Unknown {
            name: "dirac".to_string()
        }
    );
    assert!(parse("family:2").to_string().contains("[0, 1]"));
    let unknown = parse("Laplace").to_string();
    assert!(
        unknown.contains("family:T") && unknown.contains("relative-dirac"),
        "{unknown}"
    );
    assert!(parse("family").to_string().contains("family:0.5"));
}

#[test]
fn the_eigenproblem_is_the_one_the_spectrum_satisfies() {
    let mesh = dirac::default_mesh();
    let mut options = SpectrumOptions::new(Operator::RelativeDirac, 6);
    options.normalization = Normalization::UnitArea;
    let result = spectrum(&mesh, &options).unwrap();
    let problem = eigenproblem(&mesh, &options).unwrap();
    assert_eq!(problem.scale, result.scale);
    let n = mesh.vertex_count();
    for (&lambda, x) in result.eigenvalues.iter().zip(&result.eigenvectors) {
        let (mut px, mut qx) = (vec![Quat::default(); n], vec![Quat::default(); n]);
        problem.stiffness.mul_vec(x, &mut px).unwrap();
        problem.coupling.mul_vec(x, &mut qx).unwrap();
        let residual: f64 = px
            .iter()
            .zip(&qx)
            .map(|(p, q)| (*p - *q * lambda).norm_sqr())
            .sum::<f64>()
            .sqrt();
        let scale: f64 = qx.iter().map(|q| q.norm_sqr()).sum::<f64>().sqrt() * lambda.abs();
        assert!(
            residual <= 1e-8 * scale,
            "λ = {lambda}: {residual:e} / {scale:e}"
        );
    }
    // Masses are those of the scaled mesh: they sum to its area, 1.
    assert!((problem.masses.iter().sum::<f64>() - 1.0).abs() < 1e-12);
}

#[test]
fn solver_options_are_validated_before_solving() {
    let mesh = dirac::default_mesh();
    let mut options = SpectrumOptions::new(Operator::Laplace, 4);
    options.tolerance = 0.0;
    assert!(matches!(
        spectrum(&mesh, &options),
        Err(SpectrumError::InvalidTolerance(t)) if t == 0.0
    ));
    options.tolerance = 1e-10;
    options.max_restarts = 0;
    assert!(matches!(
        spectrum(&mesh, &options),
        Err(SpectrumError::InvalidMaxRestarts)
    ));
}

#[test]
fn a_progress_callback_can_stop_the_solve_and_keep_what_converged() {
    let mesh = dirac::default_mesh();
    let options = SpectrumOptions::new(Operator::RelativeDirac, 30);
    let mut calls = 0;
    let mut stop_at_second = |_: &qeig::Progress| {
        calls += 1;
        if calls == 2 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    let stopped = spectrum_with_progress(&mesh, &options, Some(&mut stop_at_second));
    assert_eq!(calls, 2, "no call after the stop");
    let Err(SpectrumError::NotConverged {
        wanted: 30,
        partial,
        ..
    }) = stopped
    else {
        panic!("expected NotConverged, got {stopped:?}");
    };
    assert!(partial.eigenvalues.len() < 30);
    let full = spectrum(&mesh, &options).unwrap();
    for lambda in &partial.eigenvalues {
        assert!(
            full.eigenvalues
                .iter()
                .any(|l| (l - lambda).abs() <= 1e-8 * lambda.abs())
        );
    }
}
