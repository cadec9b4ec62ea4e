//! k-means clustering by Lloyd's algorithm, for points stored as flat row-major rows (the layout
//! of [`crate::descriptors::DescriptorTable::values`]).
//!
//! Lloyd's algorithm alternates two steps until no point changes cluster (or
//! [`KMeansOptions::max_iterations`] assignment passes have run):
//!
//! 1. *assign* every point `x_p` to its nearest centre, `a_p = argmin_c ‖x_p − m_c‖²` (the
//!    lowest index on ties);
//! 2. *update* every centre to the mean of its points, `m_c = mean{x_p : a_p = c}`; a cluster
//!    that empties keeps its centre.
//!
//! The result depends on the initial centres ([`Initialisation`]): uniformly random distinct
//! points (the classical start, used by the patch-purity experiment of paper §6.1) or
//! k-means++ (Arthur and Vassilvitskii 2007), which spreads them out.

use qscalar::random::SplitMix64;
use thiserror::Error;

/// Why points could not be clustered. Each variant names the offending element.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ClusteringError {
    /// The dimension is zero.
    #[error("points of dimension 0 cannot be clustered: each point needs a coordinate")]
    ZeroDimension,
    /// The number of values is not a multiple of the dimension.
    #[error(
        "{values} values do not form rows of dimension {dimension} (not a multiple): \
         give one row of {dimension} values per point"
    )]
    RaggedRows {
        /// Number of values given.
        values: usize,
        /// The dimension.
        dimension: usize,
    },
    /// There are no points.
    #[error("there are no points to cluster")]
    NoPoints,
    /// A coordinate is NaN or infinite.
    #[error("point {point} has the non-finite coordinate {value} at position {coordinate}")]
    NonFinite {
        /// The point (row, 0-based).
        point: usize,
        /// The coordinate (column, 0-based).
        coordinate: usize,
        /// Its value.
        value: f64,
    },
    /// The number of clusters is zero or exceeds the number of points.
    #[error(
        "{clusters} clusters asked for {points} points: the number of clusters must be \
         between 1 and the number of points"
    )]
    ClusterCount {
        /// Clusters asked for.
        clusters: usize,
        /// Number of points.
        points: usize,
    },
}

/// Points of `R^d` as validated flat row-major rows: point `p` is
/// `values[p·d .. (p+1)·d]`, every coordinate finite.
#[derive(Debug, Clone, Copy)]
pub struct Points<'a> {
    values: &'a [f64],
    dimension: usize,
}

impl<'a> Points<'a> {
    /// Checks that `dimension > 0`, that `values` holds a whole, non-zero number of rows and
    /// that every value is finite.
    pub fn new(values: &'a [f64], dimension: usize) -> Result<Self, ClusteringError> {
        if dimension == 0 {
            return Err(ClusteringError::ZeroDimension);
        }
        if !values.len().is_multiple_of(dimension) {
            return Err(ClusteringError::RaggedRows {
                values: values.len(),
                dimension,
            });
        }
        if values.is_empty() {
            return Err(ClusteringError::NoPoints);
        }
        if let Some(i) = values.iter().position(|x| !x.is_finite()) {
            return Err(ClusteringError::NonFinite {
                point: i / dimension,
                coordinate: i % dimension,
                value: values[i],
            });
        }
        Ok(Self { values, dimension })
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.values.len() / self.dimension
    }

    /// Always `false`: [`Points::new`] rejects an empty set.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The dimension `d`.
    pub fn dimension(&self) -> usize {
        self.dimension
    }

    /// Point `p`. Panics if `p` is out of range.
    pub fn point(&self, p: usize) -> &'a [f64] {
        &self.values[p * self.dimension..(p + 1) * self.dimension]
    }
}

/// How the initial centres are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Initialisation {
    /// `k` distinct points drawn uniformly at random (a partial Fisher–Yates shuffle of the
    /// point indices with [`SplitMix64::next_u64`] modulo the remaining count).
    Uniform,
    /// k-means++ (Arthur and Vassilvitskii 2007): the first centre a uniformly random point,
    /// each further one a point drawn with probability proportional to its squared distance
    /// `D(x)²` to the nearest centre chosen so far (uniformly when every `D(x)` is 0).
    #[default]
    PlusPlus,
}

/// Parameters of [`kmeans`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KMeansOptions {
    /// Number of clusters `k`, `1 ≤ k ≤` number of points.
    pub clusters: usize,
    /// The initial centres.
    pub initialisation: Initialisation,
    /// Most assignment passes (default 300); the result of the last one is returned.
    pub max_iterations: usize,
}

impl KMeansOptions {
    /// `clusters` clusters from a k-means++ start, at most 300 passes.
    pub fn new(clusters: usize) -> Self {
        Self {
            clusters,
            initialisation: Initialisation::default(),
            max_iterations: 300,
        }
    }
}

/// The outcome of [`kmeans`].
#[derive(Debug, Clone, PartialEq)]
pub struct Clustering {
    /// The cluster (`0..k`) of every point.
    pub assignment: Vec<usize>,
    /// The centres, `k` flat rows of the points' dimension. A centre is the mean of its
    /// points after the last update; the clustering is then a fixed point of Lloyd's
    /// iteration if [`Clustering::converged`].
    pub centres: Vec<f64>,
    /// Assignment passes run.
    pub iterations: usize,
    /// Whether the last pass changed no assignment (`false`: stopped by `max_iterations`).
    pub converged: bool,
}

/// `‖a − b‖²`.
fn squared_distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

/// The index of the centre nearest to `point` (the lowest on ties) and its squared distance.
fn nearest(point: &[f64], centres: &[f64], dimension: usize) -> (usize, f64) {
    centres
        .chunks_exact(dimension)
        .map(|centre| squared_distance(point, centre))
        .enumerate()
        .fold(
            (0, f64::INFINITY),
            |best, (c, d)| {
                if d < best.1 { (c, d) } else { best }
            },
        )
}

/// The initial centres, `k` flat rows.
fn initial_centres(
    points: &Points,
    k: usize,
    initialisation: Initialisation,
    rng: &mut SplitMix64,
) -> Vec<f64> {
    let n = points.len();
    let mut centres = Vec::with_capacity(k * points.dimension());
    match initialisation {
        Initialisation::Uniform => {
            // Partial Fisher–Yates: the first k entries are a uniform random k-subset.
            let mut order: Vec<usize> = (0..n).collect();
            for i in 0..k {
                let j = i + (rng.next_u64() % (n - i) as u64) as usize;
                order.swap(i, j);
            }
            for &p in &order[..k] {
                centres.extend_from_slice(points.point(p));
            }
        }
        Initialisation::PlusPlus => {
            let first = (rng.next_u64() % n as u64) as usize;
            centres.extend_from_slice(points.point(first));
            let mut distance: Vec<f64> = (0..n)
                .map(|p| squared_distance(points.point(p), points.point(first)))
                .collect();
            for _ in 1..k {
                let total: f64 = distance.iter().sum();
                let chosen = if total > 0.0 {
                    let target = rng.next_f64() * total;
                    let mut sum = 0.0;
                    // The last point with positive weight if rounding leaves `target` above
                    // every partial sum.
                    let mut chosen = distance.iter().rposition(|&d| d > 0.0).unwrap_or(0);
                    for (p, &d) in distance.iter().enumerate() {
                        sum += d;
                        if sum > target && d > 0.0 {
                            chosen = p;
                            break;
                        }
                    }
                    chosen
                } else {
                    (rng.next_u64() % n as u64) as usize
                };
                let centre = points.point(chosen);
                centres.extend_from_slice(centre);
                for (p, d) in distance.iter_mut().enumerate() {
                    *d = d.min(squared_distance(points.point(p), centre));
                }
            }
        }
    }
    centres
}

/// Lloyd's k-means (see the module documentation) with the start drawn from `rng`.
///
/// Errors: [`ClusteringError::ClusterCount`] unless `1 ≤ k ≤ points.len()`.
pub fn kmeans(
    points: &Points,
    options: &KMeansOptions,
    rng: &mut SplitMix64,
) -> Result<Clustering, ClusteringError> {
    let (n, d, k) = (points.len(), points.dimension(), options.clusters);
    if k == 0 || k > n {
        return Err(ClusteringError::ClusterCount {
            clusters: k,
            points: n,
        });
    }
    let mut centres = initial_centres(points, k, options.initialisation, rng);
    let mut assignment = vec![usize::MAX; n];
    let mut iterations = 0;
    let mut converged = false;
    let mut sums = vec![0.0; k * d];
    let mut counts = vec![0usize; k];
    while iterations < options.max_iterations {
        iterations += 1;
        let mut changed = false;
        for (p, a) in assignment.iter_mut().enumerate() {
            let (c, _) = nearest(points.point(p), &centres, d);
            changed |= *a != c;
            *a = c;
        }
        if !changed {
            converged = true;
            break;
        }
        sums.fill(0.0);
        counts.fill(0);
        for (p, &c) in assignment.iter().enumerate() {
            counts[c] += 1;
            for (s, x) in sums[c * d..(c + 1) * d].iter_mut().zip(points.point(p)) {
                *s += x;
            }
        }
        for c in (0..k).filter(|&c| counts[c] > 0) {
            for (m, s) in centres[c * d..(c + 1) * d]
                .iter_mut()
                .zip(&sums[c * d..(c + 1) * d])
            {
                *m = s / counts[c] as f64;
            }
        }
    }
    Ok(Clustering {
        assignment,
        centres,
        iterations,
        converged,
    })
}
