//! The modified Dirichlet Hessian `Δ + (κ₁² + κ₂²)` (paper §4.1): the Willmore potential on the
//! unit sphere and the plane, the sphere spectrum `l(l+1) + 2` converging under subdivision,
//! and equality with the Laplacian on a flat grid (with and without a potential well).

use dirac::curvature::{gaussian_curvature, mean_curvature, willmore_potential};
use dirac::generators::{grid, icosphere};
use dirac::geometry::barycentric_masses;
use dirac::spectrum::{Operator, SpectrumOptions, spectrum};
use dirac::well::PotentialWell;

/// `l(l+1) + 2` with multiplicity `2l+1`.
fn sphere_exact(k: usize) -> Vec<f64> {
    (0..)
        .flat_map(|l: usize| std::iter::repeat_n((l * (l + 1) + 2) as f64, 2 * l + 1))
        .take(k)
        .collect()
}

fn largest_relative_error(computed: &[f64], exact: &[f64]) -> f64 {
    computed
        .iter()
        .zip(exact)
        .map(|(c, e)| (c - e).abs() / e.abs())
        .fold(0.0, f64::max)
}

/// `Σ_p Ā_p |v_p − exact| / Σ_p Ā_p`.
fn mean_error(values: &[f64], masses: &[f64], exact: f64) -> f64 {
    let weighted: f64 = values
        .iter()
        .zip(masses)
        .map(|(v, m)| m * (v - exact).abs())
        .sum();
    weighted / masses.iter().sum::<f64>()
}

#[test]
fn sphere_curvatures_converge_in_the_mean() {
    let mut previous = f64::INFINITY;
    for level in 2..=5 {
        let mesh = icosphere(level);
        let masses = barycentric_masses(&mesh);
        let k = gaussian_curvature(&mesh);
        let errors = [
            mean_error(&mean_curvature(&mesh), &masses, 1.0),
            mean_error(&k, &masses, 1.0),
            mean_error(&willmore_potential(&mesh), &masses, 2.0),
        ];
        println!("level {level}: mean |H − 1|, |K − 1|, |U − 2| = {errors:.3?}");
        // The angle defects of a closed genus-0 surface sum to 4π (Gauss–Bonnet, exact).
        let total: f64 = k.iter().zip(&masses).map(|(k, m)| k * m).sum();
        assert!((total - 4.0 * std::f64::consts::PI).abs() < 1e-9);
        assert!(errors[2] < previous, "level {level}: {errors:?}");
        previous = errors[2];
    }
    assert!(previous < 0.01, "level 5 mean |U − 2| = {previous}");
}

#[test]
fn plane_has_zero_potential_boundary_included() {
    let mesh = grid(6, 4, 2.0, 1.5).unwrap();
    let u = willmore_potential(&mesh);
    assert!(u.iter().all(|&v| v.abs() < 1e-12), "{u:?}");
}

#[test]
fn sphere_spectrum_is_laplace_plus_two_and_converges() {
    let k = 16;
    let exact = sphere_exact(k);
    let errors: Vec<f64> = (2..=4)
        .map(|level| {
            let values = spectrum(
                &icosphere(level),
                &SpectrumOptions::new(Operator::ModifiedDirichlet, k),
            )
            .unwrap()
            .eigenvalues;
            let error = largest_relative_error(&values, &exact);
            println!("level {level}: {values:?}\n  largest relative error {error:.3e}");
            error
        })
        .collect();
    assert!(errors[2] < 0.01, "level 4 error {}", errors[2]);
    for pair in errors.windows(2) {
        assert!(pair[1] < 0.5 * pair[0], "no convergence: {errors:?}");
    }
}

#[test]
fn flat_grid_spectrum_equals_the_laplacian() {
    let mesh = grid(12, 10, 1.2, 1.0).unwrap();
    let well = PotentialWell::with_radius(0.45);
    for with_well in [false, true] {
        let solve = |operator| {
            let mut options = SpectrumOptions::new(operator, 8);
            options.well = with_well.then_some(well);
            spectrum(&mesh, &options).unwrap().eigenvalues
        };
        let (laplace, modified) = (solve(Operator::Laplace), solve(Operator::ModifiedDirichlet));
        println!("well {with_well}: Laplace {laplace:?}\n  modified {modified:?}");
        let scale = laplace.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in laplace.iter().zip(&modified) {
            assert!((a - b).abs() <= 1e-8 * scale, "{a} vs {b}");
        }
    }
}
