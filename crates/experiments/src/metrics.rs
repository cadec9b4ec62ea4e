//! How well a set of descriptors (one vector per shape) separates known classes: leave-one-out
//! nearest-neighbour accuracy, the ratio of between-class to within-class distance, and the
//! purity of k-means clusterings from many random starts (the paper's §6.1 measure).
//!
//! Distances are Euclidean, `d(a, b) = ‖a − b‖₂`, over the common length of the two vectors.

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

/// One run of Lloyd's k-means from `k` distinct points drawn uniformly at random as the
/// initial centres; stops when no assignment changes (at most 300 iterations). A cluster that
/// empties keeps its centre. Returns the cluster of every point. Requires `1 ≤ k ≤ |points|`
/// (the caller checks).
pub fn kmeans(points: &[Vec<f64>], k: usize, rng: &mut SplitMix64) -> Vec<usize> {
    let n = points.len();
    let dimension = points.first().map_or(0, Vec::len);
    // Partial Fisher–Yates: the first k entries are a uniform random k-subset.
    let mut order: Vec<usize> = (0..n).collect();
    for i in 0..k {
        let j = i + (rng.next_u64() % (n - i) as u64) as usize;
        order.swap(i, j);
    }
    let mut centres: Vec<Vec<f64>> = order[..k].iter().map(|&i| points[i].clone()).collect();
    let mut assignment = vec![usize::MAX; n];
    for _ in 0..300 {
        let mut changed = false;
        for (p, point) in points.iter().enumerate() {
            let nearest = (0..k)
                .min_by(|&a, &b| {
                    euclidean(point, &centres[a]).total_cmp(&euclidean(point, &centres[b]))
                })
                .expect("k ≥ 1");
            changed |= assignment[p] != nearest;
            assignment[p] = nearest;
        }
        if !changed {
            break;
        }
        let mut sums = vec![vec![0.0; dimension]; k];
        let mut counts = vec![0usize; k];
        for (point, &c) in points.iter().zip(&assignment) {
            counts[c] += 1;
            sums[c].iter_mut().zip(point).for_each(|(s, x)| *s += x);
        }
        for c in (0..k).filter(|&c| counts[c] > 0) {
            centres[c] = sums[c].iter().map(|s| s / counts[c] as f64).collect();
        }
    }
    assignment
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

/// The mean [`purity`] of `starts` [`kmeans`] runs with `k` clusters, the random starts drawn
/// from one [`SplitMix64`] seeded with `seed`. `k` is clamped to `[1, |points|]`; 0 without
/// points or starts.
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
    let k = k.clamp(1, points.len());
    let mut rng = SplitMix64::new(seed);
    (0..starts)
        .map(|_| purity(&kmeans(points, k, &mut rng), labels))
        .sum::<f64>()
        / starts as f64
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
