//! Unit-sphere spectra of every pencil against the closed forms of docs/MATH.md, "What the
//! tests check against", with the
//! O(h²) convergence under subdivision, and agreement of the three eigensolver backends.

use dirac::generators::icosphere;
use dirac::spectrum::{Operator, SolverBackend, SpectrumOptions, spectrum};

/// `l(l+1)` with multiplicity `2l+1`.
fn laplace_exact(k: usize) -> Vec<f64> {
    (0..)
        .flat_map(|l: usize| std::iter::repeat_n((l * (l + 1)) as f64, 2 * l + 1))
        .take(k)
        .collect()
}

/// `D_f = D_N` on the unit sphere: `+l` (mult `l+1`, `l ≥ 1` here: τ = 1 drops the constants)
/// and `−(l+1)` (mult `l`), ordered by `|λ|`, negative first on ties.
fn dirac_exact(k: usize) -> Vec<f64> {
    let mut values = Vec::new();
    for l in 1..10usize {
        values.extend(std::iter::repeat_n(l as f64, l + 1));
        values.extend(std::iter::repeat_n(-((l + 1) as f64), l));
    }
    values.sort_by(|a, b| a.abs().total_cmp(&b.abs()).then(a.total_cmp(b)));
    values.truncate(k);
    values
}

/// Blended pencil: `[τλ² + (1−τ)l(l+1)] / [τλ + (1−τ)]` for `λ ∈ {l, −(l+1)}`, plus the constant.
fn blend_exact(tau: f64, k: usize) -> Vec<f64> {
    let mut values = vec![0.0];
    for l in 1..10usize {
        let lap = (l * (l + 1)) as f64;
        for (lambda, mult) in [(l as f64, l + 1), (-((l + 1) as f64), l)] {
            let v = (tau * lambda * lambda + (1.0 - tau) * lap) / (tau * lambda + 1.0 - tau);
            values.extend(std::iter::repeat_n(v, mult));
        }
    }
    values.sort_by(|a, b| a.abs().total_cmp(&b.abs()).then(a.total_cmp(b)));
    values.truncate(k);
    values
}

/// Literal family: `(1−τ)l(l+1) + τl` (mult `l+1`) and `(1−τ)l(l+1) − τ(l+1)` (mult `l`).
fn literal_exact(tau: f64, k: usize) -> Vec<f64> {
    let mut values = Vec::new();
    for l in 0..10usize {
        let lap = (1.0 - tau) * (l * (l + 1)) as f64;
        values.extend(std::iter::repeat_n(lap + tau * l as f64, l + 1));
        values.extend(std::iter::repeat_n(lap - tau * (l + 1) as f64, l));
    }
    values.sort_by(|a, b| a.abs().total_cmp(&b.abs()).then(a.total_cmp(b)));
    values.truncate(k);
    values
}

/// `n²` with multiplicity `2n`, and 0 once.
fn squared_exact(k: usize) -> Vec<f64> {
    // ν = 0 (the constants) is the kernel, which the squared operator does not list by
    // default (docs/MATH.md, "The exact kernel").
    (1..)
        .flat_map(|n: usize| std::iter::repeat_n((n * n) as f64, 2 * n))
        .take(k)
        .collect()
}

/// Largest error relative to `max(|exact|, 1)`.
fn max_error(computed: &[f64], exact: &[f64]) -> f64 {
    assert_eq!(computed.len(), exact.len());
    computed
        .iter()
        .zip(exact)
        .map(|(c, e)| (c - e).abs() / e.abs().max(1.0))
        .fold(0.0, f64::max)
}

fn eigenvalues(level: u32, operator: Operator, k: usize) -> Vec<f64> {
    spectrum(&icosphere(level), &SpectrumOptions::new(operator, k))
        .unwrap()
        .eigenvalues
}

/// Errors at levels 2, 3, 4; asserts the finest is below `bound` and that refinement divides
/// the error by about 4 (O(h²)) each time.
fn assert_converges(operator: Operator, exact: &[f64], bound: f64) {
    let errors: Vec<f64> = (2..=4)
        .map(|level| max_error(&eigenvalues(level, operator, exact.len()), exact))
        .collect();
    println!("{operator:?}: errors at levels 2, 3, 4 = {errors:?}");
    assert!(
        errors[2] < bound,
        "{operator:?}: level-4 error {}",
        errors[2]
    );
    for pair in errors.windows(2) {
        let ratio = pair[0] / pair[1];
        assert!(
            (3.0..5.5).contains(&ratio),
            "{operator:?}: error ratio {ratio} per subdivision"
        );
    }
}

#[test]
fn laplace_converges_to_l_times_l_plus_one() {
    // docs/MATH.md quotes 5.6%, 1.4%, 0.36% for the first 15 non-zero eigenvalues.
    assert_converges(Operator::Laplace, &laplace_exact(16), 0.004);
}

#[test]
fn extrinsic_dirac_converges_to_signed_integers() {
    // On the unit sphere N = f, so D_f = D_N with exact normals; docs/MATH.md: 9.9%, 2.4%, 0.6%.
    assert_converges(Operator::ExtrinsicDirac, &dirac_exact(12), 0.007);
}

#[test]
fn relative_dirac_with_area_weighted_normals_is_close() {
    let computed = eigenvalues(4, Operator::RelativeDirac, 12);
    assert!(
        max_error(&computed, &dirac_exact(12)) < 0.01,
        "{computed:?}"
    );
}

#[test]
fn squared_dirac_converges_to_squares() {
    assert_converges(Operator::Squared, &squared_exact(7), 0.004);
}

#[test]
fn blended_family_matches_the_rational_formula() {
    for tau in [0.25, 0.5, 0.9] {
        let exact = blend_exact(tau, 8);
        let computed = eigenvalues(4, Operator::Family { tau }, 8);
        println!("tau {tau}: {computed:?} vs {exact:?}");
        assert!(
            max_error(&computed, &exact) < 0.01,
            "tau {tau}: {computed:?} vs {exact:?}"
        );
    }
}

#[test]
fn literal_family_matches_its_closed_form() {
    let exact = literal_exact(0.5, 8);
    let computed = eigenvalues(3, Operator::FamilyLiteral { tau: 0.5 }, 8);
    assert!(
        max_error(&computed, &exact) < 0.02,
        "{computed:?} vs {exact:?}"
    );
}

#[test]
fn family_endpoints_are_laplace_and_relative_dirac() {
    let mesh = icosphere(2);
    let at = |operator| {
        spectrum(&mesh, &SpectrumOptions::new(operator, 8))
            .unwrap()
            .eigenvalues
    };
    let close = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= 1e-8 * y.abs().max(1.0))
    };
    assert!(close(
        &at(Operator::Family { tau: 0.0 }),
        &at(Operator::Laplace)
    ));
    assert!(close(
        &at(Operator::Family { tau: 1.0 }),
        &at(Operator::RelativeDirac)
    ));
}

#[test]
fn backends_agree() {
    let mesh = icosphere(2);
    for operator in [
        Operator::RelativeDirac,
        Operator::Family { tau: 0.5 },
        Operator::Laplace,
    ] {
        let mut options = SpectrumOptions::new(operator, 10);
        let native = spectrum(&mesh, &options).unwrap().eigenvalues;
        for backend in [SolverBackend::RealBlock, SolverBackend::ComplexAdjoint] {
            options.backend = backend;
            let other = spectrum(&mesh, &options).unwrap().eigenvalues;
            for (a, b) in native.iter().zip(&other) {
                assert!(
                    (a - b).abs() <= 1e-9 * a.abs().max(1.0),
                    "{operator:?} {backend:?}: {a} vs {b}"
                );
            }
        }
    }
}
