//! The crate root's one-call API: operator names, `dirac::eigenproblem` against
//! `dirac::spectrum`, the validation of solver options and stopping a solve from its progress
//! callback.

use std::ops::ControlFlow;

use dirac::spectrum::spectrum_with_progress;
use dirac::{
    Normalization, Operator, OperatorNameError, SpectrumError, SpectrumOptions, eigenproblem,
    spectrum,
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
    ];
    assert_eq!(Operator::names().len(), operators.len());
    for operator in operators {
        let tau = match operator {
            Operator::Family { tau } | Operator::FamilyLiteral { tau } => Some(tau),
            _ => None,
        };
        assert_eq!(Operator::from_name(operator.name(), tau), Ok(operator));
    }
    assert_eq!(
        Operator::from_name("family", None),
        Err(OperatorNameError::MissingTau { name: "family" })
    );
    assert_eq!(
        Operator::from_name("laplace", Some(0.5)),
        Err(OperatorNameError::UnexpectedTau { name: "laplace" })
    );
    let unknown = Operator::from_name("dirac", None).unwrap_err();
    assert!(unknown.to_string().contains("relative-dirac"), "{unknown}");
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
