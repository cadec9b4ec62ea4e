//! The separation metrics and the 2-D embedding against hand-checkable configurations.

use dirac::clustering::{Initialisation, KMeansOptions, Points, kmeans};
use experiments::embedding::classical_mds;
use experiments::metrics::{
    Scores, distance_matrix, leave_one_out_accuracy, mean_kmeans_purity, purity, separation_ratio,
};
use qscalar::random::SplitMix64;

/// Three tight clusters of four points around far-apart centres in 3-D.
fn clusters() -> (Vec<Vec<f64>>, Vec<usize>) {
    let centres = [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 5.0]];
    let offsets = [
        [0.1, 0.0, 0.0],
        [-0.1, 0.0, 0.0],
        [0.0, 0.1, 0.0],
        [0.0, 0.0, -0.1],
    ];
    let mut points = Vec::new();
    let mut labels = Vec::new();
    for (class, c) in centres.iter().enumerate() {
        for o in offsets {
            points.push((0..3).map(|i| c[i] + o[i]).collect());
            labels.push(class);
        }
    }
    (points, labels)
}

#[test]
fn separated_clusters_score_perfectly() {
    let (points, labels) = clusters();
    let scores = Scores::new(&points, &labels, 50, 1);
    assert_eq!(scores.nearest_neighbour, 1.0);
    assert!(scores.ratio > 40.0, "ratio {}", scores.ratio);
    // Random starts can put two centres in one cluster; Lloyd then leaves a cluster split and
    // two classes merged, so the mean purity is at most 1 and each run is 1 or 2/3.
    let mut rng = SplitMix64::new(3);
    let rows: Vec<f64> = points.concat();
    let rows = Points::new(&rows, 3).expect("finite points");
    let options = KMeansOptions {
        initialisation: Initialisation::Uniform,
        ..KMeansOptions::new(3)
    };
    for _ in 0..20 {
        let assignment = kmeans(&rows, &options, &mut rng)
            .expect("3 ≤ 12")
            .assignment;
        let p = purity(&assignment, &labels);
        assert!(p == 1.0 || (p - 8.0 / 12.0).abs() < 1e-12, "purity {p}");
    }
    assert!(scores.purity > 0.6 && scores.purity <= 1.0);
}

#[test]
fn kmeans_with_one_centre_per_point_is_pure() {
    let (points, labels) = clusters();
    assert_eq!(
        mean_kmeans_purity(&points, &labels, points.len(), 5, 2),
        1.0
    );
    // One cluster: purity is the largest class share.
    assert!((mean_kmeans_purity(&points, &labels, 1, 5, 2) - 4.0 / 12.0).abs() < 1e-12);
}

#[test]
fn purity_counts_the_majority_class_per_cluster() {
    // Clusters {0,1,2} (labels a,a,b) and {3,4} (labels b,b): (2 + 2)/5.
    let assignment = [0, 0, 0, 1, 1];
    let labels = [0, 0, 1, 1, 1];
    assert!((purity(&assignment, &labels) - 0.8).abs() < 1e-12);
}

#[test]
fn leave_one_out_and_ratio_on_a_line() {
    // Points 0, 1, 3, 10 on a line with labels a, a, b, b: the nearest neighbour of 3 is 1
    // (label a, wrong); of 10 is 3 (right); of 0 is 1; of 1 is 0.
    let points: Vec<Vec<f64>> = [0.0, 1.0, 3.0, 10.0].iter().map(|&x| vec![x]).collect();
    let labels = [0, 0, 1, 1];
    let d = distance_matrix(&points);
    assert!((leave_one_out_accuracy(&d, &labels) - 0.75).abs() < 1e-12);
    // Within: |0−1| = 1, |3−10| = 7, mean 4. Between: 3, 10, 2, 9, mean 6.
    assert!((separation_ratio(&d, &labels) - 1.5).abs() < 1e-12);
}

#[test]
fn mds_recovers_a_planar_configuration() {
    let planar = [(0.0, 0.0), (3.0, 0.0), (0.0, 1.0), (2.0, 2.5), (-1.0, 0.5)];
    let points: Vec<Vec<f64>> = planar.iter().map(|&(x, y)| vec![x, y]).collect();
    let d = distance_matrix(&points);
    let embedded = classical_mds(&d).unwrap();
    let e: Vec<Vec<f64>> = embedded.iter().map(|&(x, y)| vec![x, y]).collect();
    let recovered = distance_matrix(&e);
    for i in 0..planar.len() {
        for j in 0..planar.len() {
            assert!(
                (recovered[i][j] - d[i][j]).abs() < 1e-9,
                "{i},{j}: {} vs {}",
                recovered[i][j],
                d[i][j]
            );
        }
    }
    // Centred: the embedding's mean is the origin.
    let mean_x: f64 = embedded.iter().map(|p| p.0).sum::<f64>() / 5.0;
    assert!(mean_x.abs() < 1e-9);
}

#[test]
fn mds_rejects_a_ragged_matrix() {
    assert!(classical_mds(&[vec![0.0, 1.0], vec![1.0]]).is_err());
}
