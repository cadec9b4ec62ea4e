//! t-SNE of the 2-D pictures: separated clusters stay separated, the seed fixes the result,
//! and impossible perplexities are errors, not panics.

use experiments::ExperimentError;
use experiments::embedding::{TsneOptions, tsne};
use experiments::metrics::distance_matrix;
use qscalar::random::SplitMix64;

/// Two blobs of 20 points in 5-D: coordinates uniform in `[−0.5, 0.5]` around the origin and
/// around `(20, 0, 0, 0, 0)`.
fn two_blobs() -> Vec<Vec<f64>> {
    let mut rng = SplitMix64::new(7);
    (0..40)
        .map(|i| {
            let mut p: Vec<f64> = (0..5).map(|_| rng.uniform(-0.5, 0.5)).collect();
            if i >= 20 {
                p[0] += 20.0;
            }
            p
        })
        .collect()
}

fn options() -> TsneOptions {
    TsneOptions {
        perplexity: 5.0,
        epochs: 500,
        seed: 3,
    }
}

#[test]
fn tsne_keeps_two_separated_blobs_apart() {
    let embedded = tsne(&distance_matrix(&two_blobs()), &options()).unwrap();
    assert_eq!(embedded.len(), 40);
    let plane: Vec<Vec<f64>> = embedded.iter().map(|&(x, y)| vec![x, y]).collect();
    let d = distance_matrix(&plane);
    let blob = |i: usize| i / 20;
    // Every point is closer to every member of its blob than to any point of the other blob.
    for i in 0..40 {
        let farthest_within = (0..40)
            .filter(|&j| blob(j) == blob(i))
            .map(|j| d[i][j])
            .fold(0.0f64, f64::max);
        let nearest_between = (0..40)
            .filter(|&j| blob(j) != blob(i))
            .map(|j| d[i][j])
            .fold(f64::INFINITY, f64::min);
        assert!(
            farthest_within < nearest_between,
            "point {i}: within {farthest_within}, between {nearest_between}"
        );
    }
}

#[test]
fn tsne_is_a_function_of_its_seed() {
    let d = distance_matrix(&two_blobs());
    let first = tsne(&d, &options()).unwrap();
    assert_eq!(first, tsne(&d, &options()).unwrap());
    let other = tsne(
        &d,
        &TsneOptions {
            seed: 4,
            ..options()
        },
    )
    .unwrap();
    assert_ne!(first, other);
}

#[test]
fn tsne_rejects_a_perplexity_too_large_for_the_points() {
    let d = distance_matrix(&two_blobs()[..10]);
    // 10 points support a perplexity of at most (10 − 1)/3 = 3.
    match tsne(&d, &options()) {
        Err(ExperimentError::Perplexity { needed, points, .. }) => {
            assert_eq!((needed, points), (16, 10));
        }
        other => panic!("expected a perplexity error, got {other:?}"),
    }
    assert!(
        tsne(
            &d,
            &TsneOptions {
                perplexity: 3.0,
                ..options()
            }
        )
        .is_ok()
    );
    for perplexity in [0.0, f64::NAN] {
        assert!(matches!(
            tsne(
                &d,
                &TsneOptions {
                    perplexity,
                    ..options()
                }
            ),
            Err(ExperimentError::Perplexity { .. })
        ));
    }
    assert_eq!(TsneOptions::for_points(10).perplexity, 3.0);
    assert_eq!(TsneOptions::for_points(100).perplexity, 10.0);
    assert!(matches!(
        tsne(&[vec![0.0, 1.0], vec![1.0]], &options()),
        Err(ExperimentError::NotSquare)
    ));
}
