//! Spectral descriptors against independent truth: rigid-motion invariance of HKS and DKS, the
//! constant DKS of the round sphere under subdivision, the unit-sphere heat kernel in closed
//! form, the dense heat-kernel diagonal, mass identities, the documented samplings and the
//! typed errors of bad input.

use dirac::TriMesh;
use dirac::descriptors::{
    DescriptorError, DescriptorTable, Modes, WaveSampling, default_times, default_wave_sampling,
    dirac_kernel_signature, heat_kernel_signature, segmentation_descriptor, wave_kernel_signature,
};
use dirac::generators::icosphere;
use dirac::geometry::{barycentric_masses, cotan_laplacian};
use dirac::spectrum::{Operator, Spectrum, SpectrumOptions, spectrum};
use qscalar::Quat;
use qscalar::random::SplitMix64;

/// The level-`level` icosphere with each vertex moved radially by a random factor in
/// `[1 − a, 1 + a]` (seeded), so that no eigenvalue is degenerate.
fn bumpy_sphere(level: u32, amplitude: f64, seed: u64) -> TriMesh {
    let mut rng = SplitMix64::new(seed);
    icosphere(level)
        .map_positions(|p| p.map(|c| c * (1.0 + rng.uniform(-amplitude, amplitude))))
        .expect("a mildly perturbed sphere is valid")
}

fn solve(mesh: &TriMesh, operator: Operator, k: usize) -> Spectrum {
    let mut options = SpectrumOptions::new(operator, k);
    options.tolerance = 1e-12;
    spectrum(mesh, &options).expect("the spectrum converges")
}

fn assert_close(a: &[f64], b: &[f64], relative: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= relative * x.abs().max(y.abs()),
            "{what}: entry {i}: {x} vs {y}"
        );
    }
}

#[test]
fn hks_and_dks_are_invariant_under_a_rigid_motion() {
    let mesh = bumpy_sphere(2, 0.15, 7);
    let mut rng = SplitMix64::new(11);
    let rotation = Quat::new(
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
    )
    .normalize();
    let translation = [
        rng.uniform(-3.0, 3.0),
        rng.uniform(-3.0, 3.0),
        rng.uniform(-3.0, 3.0),
    ];
    let moved = mesh
        .rotated(rotation)
        .and_then(|m| m.translated(translation))
        .expect("a rigid motion keeps the mesh valid");

    for (operator, k) in [(Operator::Laplace, 10), (Operator::RelativeDirac, 10)] {
        let (before, after) = (solve(&mesh, operator, k), solve(&moved, operator, k));
        let (before, after) = (
            Modes::from_spectrum(&before).expect("valid modes"),
            Modes::from_spectrum(&after).expect("valid modes"),
        );
        // The same times for both, so only the eigenpairs can differ.
        let times = default_times(&before, 6).expect("nonzero eigenvalues");
        let signature = |modes| match operator {
            Operator::Laplace => heat_kernel_signature(modes, &times),
            _ => dirac_kernel_signature(modes, &times),
        };
        let (a, b) = (
            signature(&before).expect("valid times"),
            signature(&after).expect("valid times"),
        );
        assert_close(a.values(), b.values(), 1e-8, &format!("{operator:?}"));
    }
}

/// Relative deviations of each column from its mean over the vertices: the largest
/// `(max − min)/mean` and the largest area-weighted RMS deviation `‖x − x̄‖_M / x̄`.
fn relative_spreads(table: &DescriptorTable, masses: &[f64]) -> (f64, f64) {
    let total: f64 = masses.iter().sum();
    (0..table.column_count())
        .map(|j| {
            let column = table.column(j);
            let max = column.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let min = column.iter().copied().fold(f64::INFINITY, f64::min);
            let mean = column.iter().zip(masses).map(|(x, m)| x * m).sum::<f64>() / total;
            let variance = column
                .iter()
                .zip(masses)
                .map(|(x, m)| m * (x - mean).powi(2))
                .sum::<f64>()
                / total;
            ((max - min) / mean, variance.sqrt() / mean)
        })
        .fold((0.0, 0.0), |(a, b), (c, d)| {
            (f64::max(a, c), f64::max(b, d))
        })
}

#[test]
fn dks_of_the_sphere_becomes_constant_under_subdivision() {
    // The round sphere is homogeneous, so its DKS over complete eigenspaces is constant. The
    // first 12 Dirac modes are the complete eigenspaces |λ| = 1, 2, 3 (2 + 4 + 6 modes).
    let times = [0.1, 0.3, 1.0, 3.0];
    let spreads: Vec<(f64, f64)> = (1..=3)
        .map(|level| {
            let mesh = icosphere(level);
            let s = solve(&mesh, Operator::RelativeDirac, 12);
            let modes = Modes::from_spectrum(&s).expect("valid modes");
            let dks = dirac_kernel_signature(&modes, &times).expect("valid times");
            relative_spreads(&dks, &barycentric_masses(&mesh))
        })
        .collect();
    // The RMS deviation falls with every level (≈ 0.015, 0.0085, 0.0063). The extremes converge
    // irregularly (≈ 0.035, 0.019, 0.023): the icosphere's vertex areas grow less uniform with
    // each level, so only the overall trend is asserted for them.
    for pair in spreads.windows(2) {
        assert!(
            pair[1].1 < 0.8 * pair[0].1,
            "(range, rms) by level: {spreads:?}"
        );
    }
    assert!(spreads[2].1 < 0.5 * spreads[0].1, "{spreads:?}");
    assert!(spreads[2].0 < 0.75 * spreads[0].0, "{spreads:?}");
}

#[test]
fn hks_of_the_unit_sphere_matches_the_closed_form() {
    // Unit sphere: Σ_{l ≤ 3} (2l+1)/(4π) e^{−t l(l+1)} from the 16 modes l = 0..3 (addition
    // theorem: Σ_m |Y_lm|² = (2l+1)/(4π) at every point).
    let s = solve(&icosphere(3), Operator::Laplace, 16);
    let modes = Modes::from_spectrum(&s).expect("valid modes");
    let times = [0.05, 0.2, 1.0];
    let hks = heat_kernel_signature(&modes, &times).expect("valid times");
    for (j, &t) in times.iter().enumerate() {
        let exact: f64 = (0..=3)
            .map(|l| {
                (2 * l + 1) as f64 / (4.0 * std::f64::consts::PI)
                    * (-t * (l * (l + 1)) as f64).exp()
            })
            .sum();
        for (v, value) in hks.column(j).into_iter().enumerate() {
            assert!(
                (value - exact).abs() < 0.03 * exact,
                "t = {t}, vertex {v}: {value} vs {exact}"
            );
        }
    }
}

/// `exp(a)` of a small dense symmetric matrix by scaling and squaring with a Taylor series.
fn dense_exp(a: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = a.len();
    let norm = a
        .iter()
        .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let squarings = norm.log2().ceil().max(0.0) as i32 + 4;
    let scale = 0.5f64.powi(squarings);
    let multiply = |x: &[Vec<f64>], y: &[Vec<f64>]| -> Vec<Vec<f64>> {
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| (0..n).map(|l| x[i][l] * y[l][j]).sum())
                    .collect()
            })
            .collect()
    };
    let identity: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    let scaled: Vec<Vec<f64>> = a
        .iter()
        .map(|row| row.iter().map(|x| x * scale).collect())
        .collect();
    let (mut sum, mut term) = (identity.clone(), identity);
    for order in 1..=20 {
        term = multiply(&term, &scaled);
        term.iter_mut()
            .flatten()
            .for_each(|x| *x /= f64::from(order));
        for (s, t) in sum.iter_mut().flatten().zip(term.iter().flatten()) {
            *s += t;
        }
    }
    for _ in 0..squarings {
        sum = multiply(&sum, &sum);
    }
    sum
}

#[test]
fn hks_with_every_mode_is_the_diagonal_of_the_heat_kernel() {
    // All n modes: HKS_t(v) = [e^{−t M⁻¹L} M⁻¹]_vv = [M^{-1/2} e^{−t S} M^{-1/2}]_vv with the
    // symmetric S = M^{-1/2} L M^{-1/2}, exponentiated densely.
    let mesh = bumpy_sphere(0, 0.2, 3);
    let n = mesh.vertex_count();
    let s = solve(&mesh, Operator::Laplace, n);
    let modes = Modes::from_spectrum(&s).expect("valid modes");
    let masses = barycentric_masses(&mesh);
    let laplacian = cotan_laplacian(&mesh);
    let times = [0.02, 0.2, 1.0];
    let hks = heat_kernel_signature(&modes, &times).expect("valid times");
    for (j, &t) in times.iter().enumerate() {
        let minus_t_s: Vec<Vec<f64>> = (0..n)
            .map(|p| {
                (0..n)
                    .map(|q| -t * laplacian.get(p, q) / (masses[p] * masses[q]).sqrt())
                    .collect()
            })
            .collect();
        let kernel = dense_exp(&minus_t_s);
        let diagonal: Vec<f64> = (0..n).map(|v| kernel[v][v] / masses[v]).collect();
        assert_close(&hks.column(j), &diagonal, 1e-9, &format!("t = {t}"));
    }
}

#[test]
fn mass_integrals_of_the_descriptors() {
    let mesh = bumpy_sphere(2, 0.1, 5);
    let masses = barycentric_masses(&mesh);
    let integral = |column: Vec<f64>, power: i32| -> f64 {
        column
            .iter()
            .zip(&masses)
            .map(|(x, m)| m * x.powi(power))
            .sum()
    };

    // Laplace: Σ_v Ā_v HKS_t(v) = Σ_i e^{−tλ_i} (the heat trace of the modes given).
    let laplace = solve(&mesh, Operator::Laplace, 8);
    let modes = Modes::from_spectrum(&laplace).expect("valid modes");
    let times = [0.01, 0.1, 1.0];
    let hks = heat_kernel_signature(&modes, &times).expect("valid times");
    for (j, t) in times.iter().enumerate() {
        let trace: f64 = laplace.eigenvalues.iter().map(|l| (-t * l).exp()).sum();
        assert!((integral(hks.column(j), 1) - trace).abs() < 1e-9 * trace);
    }
    // The segmentation descriptor skips the constant mode; Σ_v Ā_v value² = 1/|λ|.
    let segmentation = segmentation_descriptor(&modes).expect("nonzero modes");
    assert_eq!(segmentation.column_count(), 7);
    assert_eq!(segmentation.parameters(), &laplace.eigenvalues[1..]);
    for (j, lambda) in laplace.eigenvalues[1..].iter().enumerate() {
        let value = integral(segmentation.column(j), 2);
        assert!((value * lambda - 1.0).abs() < 1e-9, "mode {j}: {value}");
    }

    // Dirac (signed): the WKS integrates to 1 at every energy; no mode is skipped.
    let dirac = solve(&mesh, Operator::RelativeDirac, 8);
    assert!(dirac.eigenvalues.iter().any(|&l| l < 0.0));
    let modes = Modes::from_spectrum(&dirac).expect("valid modes");
    let sampling = default_wave_sampling(&modes, 20).expect("two distinct |λ|");
    let wks = wave_kernel_signature(&modes, &sampling).expect("valid sampling");
    assert_eq!(wks.column_count(), 20);
    for j in 0..20 {
        assert!(
            (integral(wks.column(j), 1) - 1.0).abs() < 1e-9,
            "energy {j}"
        );
    }
    assert_eq!(
        segmentation_descriptor(&modes)
            .expect("nonzero modes")
            .column_count(),
        8
    );
    assert!(matches!(
        heat_kernel_signature(&modes, &times),
        Err(DescriptorError::NegativeEigenvalue { .. })
    ));
}

/// A flat mode per vertex pair, for the sampling tests (only the eigenvalues matter).
fn unit_vectors(k: usize) -> Vec<Vec<Quat<f64>>> {
    vec![vec![Quat::from_real(1.0); 3]; k]
}

#[test]
fn default_samplings_follow_the_published_rules() {
    let eigenvalues = [0.0, -2.0, 6.0, 12.0];
    let vectors = unit_vectors(4);
    let modes = Modes::new(&eigenvalues, &vectors).expect("valid modes");

    // Sun–Ovsjanikov–Guibas: 4 ln 10/|λ|_max .. 4 ln 10/|λ|_min (nonzero), geometric steps.
    let times = default_times(&modes, 5).expect("nonzero eigenvalues");
    let c = 4.0 * 10f64.ln();
    assert!((times[0] - c / 12.0).abs() < 1e-12);
    assert!((times[4] - c / 2.0).abs() < 1e-12);
    let ratio = (6.0f64).powf(0.25);
    for pair in times.windows(2) {
        assert!((pair[1] / pair[0] - ratio).abs() < 1e-12, "{times:?}");
    }
    assert_eq!(default_times(&modes, 1).expect("one time"), vec![c / 12.0]);

    // Aubry–Schlickewei–Cremers: σ = 7 (ln 12 − ln 2)/100, energies ln 2 + 2σ .. ln 12 − 2σ.
    let WaveSampling { energies, sigma } = default_wave_sampling(&modes, 3).expect("two scales");
    let expected_sigma = 0.07 * 6f64.ln();
    assert!((sigma - expected_sigma).abs() < 1e-14);
    let (first, last) = (
        2f64.ln() + 2.0 * expected_sigma,
        12f64.ln() - 2.0 * expected_sigma,
    );
    assert_close(
        &energies,
        &[first, (first + last) / 2.0, last],
        1e-13,
        "energies",
    );
}

#[test]
fn bad_input_fails_with_typed_errors() {
    let vectors = unit_vectors(2);
    assert_eq!(
        Modes::new(&[], &[]).err(),
        Some(DescriptorError::EmptySpectrum)
    );
    assert_eq!(
        Modes::new(&[1.0], &vectors).err(),
        Some(DescriptorError::CountMismatch {
            eigenvalues: 1,
            eigenvectors: 2
        })
    );
    let ragged = vec![vec![Quat::from_real(1.0); 3], vec![Quat::from_real(1.0); 2]];
    assert_eq!(
        Modes::new(&[1.0, 2.0], &ragged).err(),
        Some(DescriptorError::VectorLength {
            index: 1,
            expected: 3,
            found: 2
        })
    );
    assert!(matches!(
        Modes::new(&[1.0, f64::NAN], &vectors),
        Err(DescriptorError::NonFiniteEigenvalue { index: 1, .. })
    ));
    let mut bad = unit_vectors(2);
    bad[1][2] = Quat::new(0.0, f64::INFINITY, 0.0, 0.0);
    assert_eq!(
        Modes::new(&[1.0, 2.0], &bad).err(),
        Some(DescriptorError::NonFiniteEigenvector {
            index: 1,
            vertex: 2
        })
    );

    let modes = Modes::new(&[0.0, 1.0], &vectors).expect("valid modes");
    for time in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            heat_kernel_signature(&modes, &[1.0, time]),
            Err(DescriptorError::BadTime { index: 1, .. })
        ));
        assert!(matches!(
            dirac_kernel_signature(&modes, &[time]),
            Err(DescriptorError::BadTime { index: 0, .. })
        ));
    }
    assert_eq!(
        dirac_kernel_signature(&modes, &[]).err(),
        Some(DescriptorError::NoSamples)
    );
    assert_eq!(
        default_times(&modes, 0).err(),
        Some(DescriptorError::NoSamples)
    );
    // A single nonzero |λ| spans no range of energies.
    assert!(matches!(
        default_wave_sampling(&modes, 10),
        Err(DescriptorError::SingleScale(_))
    ));
    for sigma in [0.0, -1.0, f64::NAN] {
        let sampling = WaveSampling {
            energies: vec![0.0],
            sigma,
        };
        assert!(matches!(
            wave_kernel_signature(&modes, &sampling),
            Err(DescriptorError::BadSigma(_))
        ));
    }
    let far = WaveSampling {
        energies: vec![0.0, 1e3],
        sigma: 1.0,
    };
    assert!(matches!(
        wave_kernel_signature(&modes, &far),
        Err(DescriptorError::EmptyBand { index: 1, .. })
    ));

    let zeros = Modes::new(&[0.0, 0.0], &vectors).expect("valid modes");
    assert_eq!(
        default_times(&zeros, 4).err(),
        Some(DescriptorError::NoNonzeroEigenvalue)
    );
    assert_eq!(
        segmentation_descriptor(&zeros).err(),
        Some(DescriptorError::NoNonzeroEigenvalue)
    );
}
