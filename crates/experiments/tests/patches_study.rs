//! The pieces of the patch study: distance variants against hand-computed values, the
//! homogeneous textures' statistics against their definition, and the one-factor-at-a-time
//! design of the settings and variants.

use experiments::ExperimentError;
use experiments::patches::{NoiseProfile, PatchConfig, Texture, TextureSet};
use experiments::patches_study::{PATCH_MARGIN, StudySetting, feature_variants, settings};
use experiments::spectral_features::{EigenvalueTransform, FeatureScaling, SpectralFeatures};
use qscalar::random::SplitMix64;

fn features(
    count: usize,
    transform: EigenvalueTransform,
    scaling: FeatureScaling,
) -> SpectralFeatures {
    SpectralFeatures {
        count,
        transform,
        scaling,
    }
}

fn assert_close(a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() < 1e-12, "{a:?} vs {b:?}");
    }
}

#[test]
fn transforms_and_per_shape_scaling_match_hand_values() {
    let spectra = vec![vec![0.0, -2.0, 4.0, -8.0], vec![1.0, -1.0, 3.0, 5.0]];
    use EigenvalueTransform::*;
    use FeatureScaling::{FirstNonzero, None};
    let v = |f: SpectralFeatures| f.vectors(&spectra).unwrap();
    assert_close(&v(features(3, Magnitude, None))[0], &[0.0, 2.0, 4.0]);
    assert_close(&v(features(3, Signed, None))[0], &[0.0, -2.0, 4.0]);
    assert_close(&v(features(4, Squared, None))[1], &[1.0, 1.0, 9.0, 25.0]);
    let logs = |f: SpectralFeatures| f.vectors(&spectra[1..]).unwrap();
    assert_close(
        &logs(features(3, LogMagnitude, None))[0],
        &[0.0, 0.0, 3f64.ln()],
    );
    // The first nonzero eigenvalue of shape 0 is −2 (its 0 is skipped), of shape 1 it is 1.
    assert_close(
        &v(features(4, Signed, FirstNonzero))[0],
        &[0.0, -1.0, 2.0, -4.0],
    );
    assert_close(
        &v(features(4, Squared, FirstNonzero))[1],
        &[1.0, 1.0, 9.0, 25.0],
    );
    assert_close(
        &logs(features(4, LogMagnitude, FirstNonzero))[0],
        &[0.0, 0.0, 3f64.ln(), 5f64.ln()],
    );
}

#[test]
fn standardised_coordinates_have_unit_spread_and_constants_stay() {
    let spectra = vec![
        vec![1.0, 7.0, 10.0],
        vec![3.0, 7.0, 30.0],
        vec![5.0, 7.0, 20.0],
    ];
    let vectors = features(
        3,
        EigenvalueTransform::Magnitude,
        FeatureScaling::Standardised,
    )
    .vectors(&spectra)
    .unwrap();
    // Column 0: 1, 3, 5 has population variance 8/3; column 2: 10, 30, 20 has 200/3.
    let sd0 = (8.0f64 / 3.0).sqrt();
    let sd2 = (200.0f64 / 3.0).sqrt();
    assert_close(&vectors[1], &[3.0 / sd0, 7.0, 30.0 / sd2]);
}

#[test]
fn log_distance_is_twice_the_relative_distance_for_close_spectra() {
    let a = vec![1.0, 4.0, 9.0, 16.0];
    let b: Vec<f64> = a
        .iter()
        .enumerate()
        .map(|(i, x)| x * (1.0 + 1e-4 * (i as f64 + 1.0)))
        .collect();
    let logs = features(4, EigenvalueTransform::LogMagnitude, FeatureScaling::None)
        .vectors(&[a.clone(), b.clone()])
        .unwrap();
    let log_distance = experiments::metrics::euclidean(&logs[0], &logs[1]);
    let relative: f64 = a
        .iter()
        .zip(&b)
        .map(|(x, y)| ((x - y) / (x + y)).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(
        (log_distance / relative - 2.0).abs() < 1e-3,
        "{log_distance} vs {relative}"
    );
}

#[test]
fn feature_errors_name_the_shape() {
    let spectra = vec![vec![1.0, 2.0, 3.0], vec![0.0, 2.0]];
    let magnitude = |count, scaling| features(count, EigenvalueTransform::Magnitude, scaling);
    assert!(matches!(
        magnitude(3, FeatureScaling::None).vectors(&spectra),
        Err(ExperimentError::TooFewEigenvalues {
            shape: 1,
            available: 2,
            wanted: 3
        })
    ));
    assert!(matches!(
        features(2, EigenvalueTransform::LogMagnitude, FeatureScaling::None).vectors(&spectra),
        Err(ExperimentError::ZeroEigenvalue { shape: 1, index: 0 })
    ));
    assert!(matches!(
        magnitude(1, FeatureScaling::FirstNonzero).vectors(&spectra),
        Err(ExperimentError::NoNonzeroEigenvalue { shape: 1 })
    ));
}

/// Uniform points on the unit sphere within angle `radius` of `center`.
fn cap_points(center: [f64; 3], radius: f64, count: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut rng = SplitMix64::new(seed);
    let mut points = Vec::new();
    while points.len() < count {
        let z = rng.uniform(-1.0, 1.0);
        let azimuth = rng.uniform(0.0, std::f64::consts::TAU);
        let s = (1.0 - z * z).sqrt();
        let p = [s * azimuth.cos(), s * azimuth.sin(), z];
        let cos = p[0] * center[0] + p[1] * center[1] + p[2] * center[2];
        if cos >= radius.cos() {
            points.push(p);
        }
    }
    points
}

/// Root mean square of the tangential gradient of `f` over the points (central differences
/// along two tangent directions, step 10⁻⁵): the local frequency times the local RMS.
fn gradient_rms(f: &dyn Fn([f64; 3]) -> f64, points: &[[f64; 3]]) -> f64 {
    let h = 1e-5;
    let normalize = |v: [f64; 3]| {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        [v[0] / n, v[1] / n, v[2] / n]
    };
    let sum: f64 = points
        .iter()
        .map(|&p| {
            let helper = if p[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            let d = helper[0] * p[0] + helper[1] * p[1] + helper[2] * p[2];
            let t1 = normalize([
                helper[0] - d * p[0],
                helper[1] - d * p[1],
                helper[2] - d * p[2],
            ]);
            let t2 = [
                p[1] * t1[2] - p[2] * t1[1],
                p[2] * t1[0] - p[0] * t1[2],
                p[0] * t1[1] - p[1] * t1[0],
            ];
            [t1, t2]
                .iter()
                .map(|t| {
                    let step =
                        |s: f64| normalize([p[0] + s * t[0], p[1] + s * t[1], p[2] + s * t[2]]);
                    ((f(step(h)) - f(step(-h))) / (2.0 * h)).powi(2)
                })
                .sum::<f64>()
        })
        .sum();
    (sum / points.len() as f64).sqrt()
}

#[test]
fn noise_profiles_have_zero_mean_and_unit_variance_over_the_sphere() {
    // Mean and variance over the draws: a single realisation's spatial variance differs from
    // 1 by O(1/√n) for n plane waves, so average the spatial moments over eight seeds.
    let points = cap_points([0.0, 0.0, 1.0], std::f64::consts::PI, 2000, 9);
    for profile in [
        NoiseProfile::Smooth,
        NoiseProfile::Ridged,
        NoiseProfile::Pitted,
    ] {
        let (mut mean, mut variance) = (0.0, 0.0);
        for seed in 1..=8 {
            let f = Texture::Noise {
                frequency: 14.0,
                profile,
                seed,
            }
            .function();
            let values: Vec<f64> = points.iter().map(|&p| f(p)).collect();
            let m = values.iter().sum::<f64>() / values.len() as f64;
            mean += m / 8.0;
            variance +=
                values.iter().map(|v| (v - m).powi(2)).sum::<f64>() / values.len() as f64 / 8.0;
        }
        assert!(mean.abs() < 0.05, "{profile:?}: mean {mean}");
        assert!(
            (variance - 1.0).abs() < 0.08,
            "{profile:?}: variance {variance}"
        );
    }
    // Ridged is the negative of pitted, and its crests (|g| → 0) are its maxima √(2/π)/√(1−2/π).
    assert_eq!(
        NoiseProfile::Ridged.apply(0.3),
        -NoiseProfile::Pitted.apply(0.3)
    );
    let crest = (2.0 / std::f64::consts::PI).sqrt() / (1.0 - 2.0 / std::f64::consts::PI).sqrt();
    assert!((NoiseProfile::Ridged.apply(0.0) - crest).abs() < 1e-12);
}

#[test]
fn noise_is_homogeneous_where_one_direction_is_not() {
    // Gradient RMS in caps of the well's effective radius around the axis of the ridges and
    // around a point of their equator: the local frequency a sin θ of a texture along one
    // axis is near 0 at the pole, a at the equator. The noise looks alike in both caps.
    let axis = [0.0, 0.0, 1.0];
    let equator = [1.0, 0.0, 0.0];
    let ridges = Texture::Ridges { frequency: 14.0 };
    let noise = Texture::Noise {
        frequency: 14.0,
        profile: NoiseProfile::Smooth,
        seed: 3,
    };
    let f = ridges.function();
    // The ridges' fixed axis ∝ (0.3, 0.5, 0.8) and a unit vector orthogonal to it.
    let length = (0.3f64 * 0.3 + 0.5 * 0.5 + 0.8 * 0.8).sqrt();
    let direction = [0.3 / length, 0.5 / length, 0.8 / length];
    let away = {
        let length = (0.5f64 * 0.5 + 0.3 * 0.3).sqrt();
        [0.5 / length, -0.3 / length, 0.0]
    };
    let ratio = |f: &dyn Fn([f64; 3]) -> f64, pole: [f64; 3], side: [f64; 3]| {
        gradient_rms(f, &cap_points(pole, 0.65, 400, 2))
            / gradient_rms(f, &cap_points(side, 0.65, 400, 3))
    };
    let wave_ratio = ratio(&f, direction, away);
    assert!(
        wave_ratio < 0.65,
        "ridges: pole/equator gradient ratio {wave_ratio}"
    );
    let g = noise.function();
    for (pole, side) in [(axis, equator), (direction, away)] {
        let noise_ratio = ratio(&g, pole, side);
        println!("noise ratio {noise_ratio}, ridges ratio {wave_ratio}");
        assert!(
            noise_ratio > 0.8 && noise_ratio < 1.25,
            "noise: gradient ratio {noise_ratio} between two caps"
        );
    }
}

#[test]
fn texture_sets_have_ten_classes_that_differ_as_named() {
    for set in [
        TextureSet::Original,
        TextureSet::Homogeneous,
        TextureSet::AmplitudeOnly,
        TextureSet::FrequencyOnly,
    ] {
        let classes = set.classes();
        assert_eq!(classes.len(), 10, "{set:?}");
        let mut names: Vec<&str> = classes.iter().map(|c| c.name.as_str()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), 10, "{set:?}: repeated class names");
    }
    let amplitude = TextureSet::AmplitudeOnly.classes();
    assert!(amplitude.iter().all(|c| c.texture == amplitude[0].texture));
    assert!(
        amplitude
            .windows(2)
            .all(|w| w[1].amplitude > w[0].amplitude)
    );
    let frequency = TextureSet::FrequencyOnly.classes();
    assert!(
        frequency
            .iter()
            .all(|c| c.amplitude == frequency[0].amplitude)
    );
    assert!(frequency.windows(2).all(|w| w[0].texture != w[1].texture));
}

#[test]
fn the_study_changes_one_factor_at_a_time() {
    let default = StudySetting::default_setting();
    assert_eq!(default.textures, TextureSet::Original);
    assert_eq!(
        PatchConfig {
            k: PatchConfig::DEFAULT.k,
            ..default.config
        },
        PatchConfig::DEFAULT
    );
    let level_5 = StudySetting::with_level(5);
    for setting in settings(true).into_iter().skip(1) {
        // The combined setting joins two single changes; the doubled frequency is a change
        // from the level-5 setting.
        if setting.factor == "texture + well radius" {
            assert_eq!(setting.textures, TextureSet::Homogeneous);
            assert_eq!(setting.config, StudySetting::with_well_radius(1.45).config);
            continue;
        }
        if setting.frequency_scale != 1.0 {
            assert_eq!(
                (setting.textures, setting.config),
                (level_5.textures, level_5.config)
            );
            continue;
        }
        let changed_textures = setting.textures != default.textures;
        let changed_well = setting.config.well_radius != default.config.well_radius;
        let changed_level = setting.config.level != default.config.level;
        assert_eq!(
            [changed_textures, changed_well, changed_level]
                .iter()
                .filter(|&&c| c)
                .count(),
            1,
            "{setting:?}"
        );
        // A larger well comes with a larger patch: no boundary inside the region of interest.
        assert!((setting.config.radius - setting.config.well_radius - PATCH_MARGIN).abs() < 1e-12);
    }
    let paper = SpectralFeatures::PAPER;
    for (factor, variant) in feature_variants().into_iter().skip(1) {
        let changes = [
            variant.count != paper.count,
            variant.transform != paper.transform,
            variant.scaling != paper.scaling,
        ];
        assert_eq!(
            changes.iter().filter(|&&c| c).count(),
            1,
            "{factor}: {variant:?}"
        );
    }
}

#[test]
fn frequency_scale_multiplies_every_texture_frequency() {
    assert_eq!(
        Texture::Ridges { frequency: 14.0 }.with_frequency_scale(2.0),
        Texture::Ridges { frequency: 28.0 }
    );
    let noise = Texture::Noise {
        frequency: 10.0,
        profile: NoiseProfile::Ridged,
        seed: 4,
    };
    // Same directions and phases, doubled frequency: equal to the noise defined at 20.
    assert_eq!(noise.with_frequency_scale(1.0), noise);
    let doubled = noise.with_frequency_scale(2.0).function();
    let reference = Texture::Noise {
        frequency: 20.0,
        profile: NoiseProfile::Ridged,
        seed: 4,
    }
    .function();
    for p in cap_points([0.0, 1.0, 0.0], 1.0, 50, 8) {
        assert_eq!(doubled(p), reference(p));
    }
    let scaled_set: Vec<Texture> = StudySetting {
        frequency_scale: 2.0,
        ..StudySetting::default_setting()
    }
    .classes()
    .iter()
    .map(|c| c.texture)
    .collect();
    let original: Vec<Texture> = TextureSet::Original
        .classes()
        .iter()
        .map(|c| c.texture.with_frequency_scale(2.0))
        .collect();
    assert_eq!(scaled_set, original);
    assert!(matches!(
        scaled_set[0],
        Texture::Waves { frequency, .. } if frequency == 20.0
    ));
}

#[test]
fn kmeans_ceiling_of_point_classes_is_their_own_purity_and_below_one() {
    use experiments::metrics::mean_kmeans_purity;
    use experiments::patches_study::{Protocol, kmeans_ceiling, simplex_ceiling};
    let protocol = Protocol {
        starts: 200,
        seed: 10,
    };
    let labels: Vec<usize> = (0..100).map(|i| i / 10).collect();
    // Classes already single points (the unit vectors): their centroids are themselves.
    let points: Vec<Vec<f64>> = labels
        .iter()
        .map(|&l| (0..10).map(|c| if c == l { 1.0 } else { 0.0 }).collect())
        .collect();
    let ceiling = simplex_ceiling(&labels, protocol);
    assert_eq!(ceiling, mean_kmeans_purity(&points, &labels, 10, 200, 10));
    // Spread around those points, the centroids are the points again (spread ±0.1, mean 0 by
    // symmetry of the offsets).
    let spread: Vec<Vec<f64>> = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let offset = if i % 2 == 0 { 0.1 } else { -0.1 };
            p.iter().map(|x| x + offset).collect()
        })
        .collect();
    assert!((kmeans_ceiling(&spread, &labels, protocol) - ceiling).abs() < 1e-12);
    // Ten random initial points fall in ten distinct classes with probability
    // 10¹⁰ / C(100, 10) ≈ 6·10⁻⁴; otherwise Lloyd's iteration keeps two classes in one
    // cluster: the protocol stays well below 1 on perfectly separated classes.
    assert!(ceiling > 0.5 && ceiling < 0.9, "ceiling {ceiling}");
}

#[test]
fn study_table_escapes_the_bars_of_the_magnitude() {
    use experiments::patches_study::{StudyRow, format_study};
    let table = format_study(&[StudyRow {
        factor: "transform",
        setting: "default".into(),
        features: features(20, EigenvalueTransform::LogMagnitude, FeatureScaling::None),
        relative_dirac: 0.477,
        laplace: 0.353,
    }]);
    let row = table.lines().nth(2).unwrap();
    assert_eq!(
        row,
        "| transform | default | 20 × log\\|λ\\|, none | 47.7 | 35.3 |"
    );
    // Six unescaped bars: five cells.
    let unescaped = row
        .match_indices('|')
        .filter(|&(i, _)| !row[..i].ends_with('\\'))
        .count();
    assert_eq!(unescaped, 6);
}
