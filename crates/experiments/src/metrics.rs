//! How well a set of descriptors (one vector per shape) separates known classes: leave-one-out
//! nearest-neighbour accuracy, the ratio of between-class to within-class distance, and the
//! purity of k-means clusterings ([`dirac::clustering`]) from many random starts (the paper's
//! §6.1 measure).
//!
//! Distances are Euclidean, `d(a, b) = ‖a − b‖₂`, over the common length of the two vectors.

use dirac::clustering::{Initialisation, KMeansOptions, Points, kmeans};
use qscalar::random::SplitMix64;

/// `‖a − b‖₂` over the first `min(|a|, |b|)` entries.
pub fn euclidean(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// The symmetric matrix `D_ij = ‖x_i − x_j‖₂`.
pub fn distance_matrix(points: &[Vec<f64>]) -> Vec<Vec<f64>> {
    points
        .iter()
        .map(|a| points.iter().map(|b| euclidean(a, b)).collect())
        .collect()
}

/// The item nearest to item `i` other than itself: smallest `D_ij`, `j ≠ i`, the lowest index
/// on ties; `None` without another item.
pub fn nearest_other(distances: &[Vec<f64>], i: usize) -> Option<usize> {
    (0..distances.len())
        .filter(|&j| j != i)
        .min_by(|&a, &b| distances[i][a].total_cmp(&distances[i][b]))
}

/// Leave-one-out 1-nearest-neighbour accuracy: the share of items `i` whose nearest other item
/// ([`nearest_other`]) has the same label. 0 for fewer than two items.
pub fn leave_one_out_accuracy(distances: &[Vec<f64>], labels: &[usize]) -> f64 {
    let n = labels.len();
    if n < 2 {
        return 0.0;
    }
    let correct = (0..n)
        .filter(|&i| nearest_other(distances, i).is_some_and(|j| labels[j] == labels[i]))
        .count();
    correct as f64 / n as f64
}

/// `mean_{i<j, ℓ_i ≠ ℓ_j} D_ij / mean_{i<j, ℓ_i = ℓ_j} D_ij`: above 1 when classes are farther
/// from each other than their members are from one another. `+∞` when every within-class
/// distance is 0 and some between-class distance is not; NaN without pairs of either kind.
pub fn separation_ratio(distances: &[Vec<f64>], labels: &[usize]) -> f64 {
    let (mut between, mut within) = ((0.0, 0usize), (0.0, 0usize));
    for i in 0..labels.len() {
        for j in i + 1..labels.len() {
            let sum = if labels[i] == labels[j] {
                &mut within
            } else {
                &mut between
            };
            sum.0 += distances[i][j];
            sum.1 += 1;
        }
    }
    (between.0 / between.1 as f64) / (within.0 / within.1 as f64)
}

/// Purity `(1/N) Σ_clusters max_class |cluster ∩ class|` (Manning, Raghavan, Schütze 2008,
/// p. 357): 1 when every cluster holds a single class.
pub fn purity(assignment: &[usize], labels: &[usize]) -> f64 {
    let clusters = assignment.iter().max().map_or(0, |m| m + 1);
    let classes = labels.iter().max().map_or(0, |m| m + 1);
    let mut counts = vec![vec![0usize; classes]; clusters];
    for (&c, &l) in assignment.iter().zip(labels) {
        counts[c][l] += 1;
    }
    let majority: usize = counts
        .iter()
        .map(|row| row.iter().copied().max().unwrap_or(0))
        .sum();
    majority as f64 / labels.len().max(1) as f64
}

/// The mean [`purity`] of `starts` runs of [`dirac::clustering::kmeans`] with `k` clusters
/// from uniformly random distinct points ([`Initialisation::Uniform`], at most 300 passes), the
/// random starts drawn from one [`SplitMix64`] seeded with `seed`. Points are compared over the
/// length of the shortest. `k` is clamped to `[1, |points|]`; 0 without points or starts, NaN
/// when the points have no coordinates or a non-finite one.
pub fn mean_kmeans_purity(
    points: &[Vec<f64>],
    labels: &[usize],
    k: usize,
    starts: usize,
    seed: u64,
) -> f64 {
    if points.is_empty() || starts == 0 {
        return 0.0;
    }
    let dimension = points.iter().map(Vec::len).min().unwrap_or(0);
    let rows: Vec<f64> = points
        .iter()
        .flat_map(|p| p[..dimension].iter().copied())
        .collect();
    let Ok(points) = Points::new(&rows, dimension) else {
        return f64::NAN;
    };
    let options = KMeansOptions {
        initialisation: Initialisation::Uniform,
        ..KMeansOptions::new(k.clamp(1, points.len()))
    };
    let mut rng = SplitMix64::new(seed);
    let mut total = 0.0;
    for _ in 0..starts {
        match kmeans(&points, &options, &mut rng) {
            Ok(clustering) => total += purity(&clustering.assignment, labels),
            Err(_) => return f64::NAN,
        }
    }
    total / starts as f64
}

/// The three separation scores of one operator's descriptors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scores {
    /// [`leave_one_out_accuracy`].
    pub nearest_neighbour: f64,
    /// [`separation_ratio`].
    pub ratio: f64,
    /// [`mean_kmeans_purity`] with as many clusters as classes.
    pub purity: f64,
}

impl Scores {
    /// All three scores of `points` with class `labels`; k-means uses `starts` random starts
    /// from `seed` and as many clusters as there are distinct labels.
    pub fn new(points: &[Vec<f64>], labels: &[usize], starts: usize, seed: u64) -> Self {
        let distances = distance_matrix(points);
        let mut distinct = labels.to_vec();
        distinct.sort_unstable();
        distinct.dedup();
        Self {
            nearest_neighbour: leave_one_out_accuracy(&distances, labels),
            ratio: separation_ratio(&distances, labels),
            purity: mean_kmeans_purity(points, labels, distinct.len(), starts, seed),
        }
    }
}
