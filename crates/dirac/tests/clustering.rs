//! k-means (`dirac::clustering`) against hand-computed clusterings and the fixed-point property
//! of Lloyd's iteration, checked by brute force.

use dirac::clustering::{ClusteringError, Initialisation, KMeansOptions, Points, kmeans};
use qscalar::random::SplitMix64;

fn options(clusters: usize, initialisation: Initialisation) -> KMeansOptions {
    KMeansOptions {
        initialisation,
        ..KMeansOptions::new(clusters)
    }
}

#[test]
fn two_pairs_on_a_line_give_their_means() {
    let values = [0.0, 1.0, 10.0, 11.0];
    let points = Points::new(&values, 1).unwrap();
    for initialisation in [Initialisation::Uniform, Initialisation::PlusPlus] {
        let mut rng = SplitMix64::new(7);
        for _ in 0..20 {
            let c = kmeans(&points, &options(2, initialisation), &mut rng).unwrap();
            let a = &c.assignment;
            if initialisation == Initialisation::PlusPlus || a[0] != a[2] {
                // k-means++ always starts in both pairs; a uniform start may pick one pair
                // twice, and Lloyd still separates the pairs from there.
                assert_eq!(a[0], a[1]);
                assert_eq!(a[2], a[3]);
                assert_ne!(a[0], a[2]);
                assert_eq!(c.centres[a[0]], 0.5);
                assert_eq!(c.centres[a[2]], 10.5);
            }
            assert!(c.converged);
        }
    }
}

#[test]
fn a_converged_clustering_is_a_fixed_point_of_lloyd() {
    let mut rng = SplitMix64::new(11);
    let values: Vec<f64> = (0..200).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let points = Points::new(&values, 2).unwrap();
    for initialisation in [Initialisation::Uniform, Initialisation::PlusPlus] {
        let c = kmeans(&points, &options(5, initialisation), &mut rng).unwrap();
        assert!(c.converged, "{} passes", c.iterations);
        let centre = |k: usize| &c.centres[2 * k..2 * k + 2];
        let d2 = |p: &[f64], q: &[f64]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
        for p in 0..points.len() {
            let own = d2(points.point(p), centre(c.assignment[p]));
            for k in 0..5 {
                assert!(
                    own <= d2(points.point(p), centre(k)),
                    "point {p} nearer to {k}"
                );
            }
        }
        for k in 0..5 {
            let members: Vec<usize> = (0..100).filter(|&p| c.assignment[p] == k).collect();
            assert!(!members.is_empty(), "cluster {k} is empty");
            for axis in 0..2 {
                let mean = members.iter().map(|&p| values[2 * p + axis]).sum::<f64>()
                    / members.len() as f64;
                assert!((centre(k)[axis] - mean).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn one_cluster_per_point_reproduces_the_points() {
    let values = [3.0, -1.0, 0.5, 2.0, 7.0, 7.5];
    let points = Points::new(&values, 2).unwrap();
    let c = kmeans(
        &points,
        &options(3, Initialisation::Uniform),
        &mut SplitMix64::new(1),
    )
    .unwrap();
    let mut seen = c.assignment.clone();
    seen.sort_unstable();
    assert_eq!(seen, [0, 1, 2]);
    for p in 0..3 {
        let k = c.assignment[p];
        assert_eq!(&c.centres[2 * k..2 * k + 2], points.point(p));
    }
}

#[test]
fn plus_plus_never_starts_twice_in_a_location() {
    // Three locations, each repeated four times: once a location holds a centre its copies
    // have weight D² = 0, so the three centres start in the three locations every time.
    let values: Vec<f64> = [0.0, 5.0, 9.0].iter().flat_map(|&x| [x; 4]).collect();
    let points = Points::new(&values, 1).unwrap();
    let mut rng = SplitMix64::new(5);
    for _ in 0..50 {
        let c = kmeans(&points, &options(3, Initialisation::PlusPlus), &mut rng).unwrap();
        assert_eq!(c.iterations, 2, "the start is already the answer");
        let mut centres = c.centres.clone();
        centres.sort_by(f64::total_cmp);
        assert_eq!(centres, [0.0, 5.0, 9.0]);
    }
}

#[test]
fn the_same_seed_gives_the_same_clustering() {
    let mut rng = SplitMix64::new(2);
    let values: Vec<f64> = (0..300).map(|_| rng.next_f64()).collect();
    let points = Points::new(&values, 3).unwrap();
    let run = |seed| kmeans(&points, &KMeansOptions::new(6), &mut SplitMix64::new(seed)).unwrap();
    assert_eq!(run(9), run(9));
}

#[test]
fn bad_points_and_counts_are_named() {
    assert_eq!(
        Points::new(&[1.0], 0).unwrap_err(),
        ClusteringError::ZeroDimension
    );
    assert_eq!(
        Points::new(&[1.0, 2.0, 3.0], 2).unwrap_err(),
        ClusteringError::RaggedRows {
            values: 3,
            dimension: 2
        }
    );
    assert_eq!(Points::new(&[], 2).unwrap_err(), ClusteringError::NoPoints);
    let error = Points::new(&[0.0, 1.0, f64::NAN, 2.0], 2).unwrap_err();
    assert!(
        matches!(error, ClusteringError::NonFinite { point: 1, coordinate: 0, value } if value.is_nan()),
        "{error:?}"
    );
    let points = Points::new(&[0.0, 1.0], 1).unwrap();
    for clusters in [0, 3] {
        assert_eq!(
            kmeans(
                &points,
                &KMeansOptions::new(clusters),
                &mut SplitMix64::new(0)
            )
            .unwrap_err(),
            ClusteringError::ClusterCount {
                clusters,
                points: 2
            }
        );
    }
}
