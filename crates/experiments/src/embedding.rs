//! Two-dimensional embeddings of a distance matrix for plotting: t-SNE (van der Maaten and
//! Hinton 2008), as the paper uses for Fig. 10, through the `bhtsne` crate; and classical
//! multidimensional scaling, deterministic and exact for planar data.

use bhtsne::tSNE;
use faer::{Mat, Side};
use qscalar::random::SplitMix64;

use crate::ExperimentError;

/// Settings of [`tsne`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TsneOptions {
    /// Perplexity, the effective number of neighbours of each point (`≤ (n − 1)/3`).
    pub perplexity: f64,
    /// Gradient-descent iterations (the first 250 with early exaggeration 12).
    pub epochs: usize,
    /// Seed of the initial positions.
    pub seed: u64,
}

impl TsneOptions {
    /// Perplexity 10 (this experiment's class size), 1000 iterations, seed 1.
    pub const DEFAULT: Self = Self {
        perplexity: 10.0,
        epochs: 1000,
        seed: 1,
    };

    /// [`TsneOptions::DEFAULT`] with the perplexity lowered, if needed, to the largest that `n`
    /// points support, `(n − 1)/3` (the tori experiment has 24 shapes).
    pub fn for_points(n: usize) -> Self {
        Self {
            perplexity: Self::DEFAULT
                .perplexity
                .min(n.saturating_sub(1) as f64 / 3.0),
            ..Self::DEFAULT
        }
    }
}

/// Exact t-SNE of the points whose Euclidean distances are `distances` into the plane:
/// `p_{j|i} ∝ exp(−β_i D_ij²)` with `β_i` set so that the perplexity `2^{H(p_{·|i})}` is
/// `options.perplexity`, `P = (p_{j|i} + p_{i|j}) / 2n`, and the plane points minimise
/// `KL(P ‖ Q)` for the Student-t kernel `q_ij ∝ (1 + ‖y_i − y_j‖²)^{−1}` (`bhtsne`'s exact
/// gradient descent with momentum and gains). The initial positions are uniform in
/// `[−10⁻⁴, 10⁻⁴]²` from `options.seed`, and the descent runs on one thread, so the result is
/// a function of the inputs. The distances are divided by their mean first (the
/// perplexity calibration makes `P` independent of their scale; this keeps the calibration's
/// first trial in range).
pub fn tsne(
    distances: &[Vec<f64>],
    options: &TsneOptions,
) -> Result<Vec<(f64, f64)>, ExperimentError> {
    let n = distances.len();
    if distances.iter().any(|row| row.len() != n) {
        return Err(ExperimentError::NotSquare);
    }
    let needed = (3.0 * options.perplexity).max(0.0).ceil() as usize + 1;
    if options.perplexity.is_nan() || options.perplexity <= 0.0 || n < needed {
        return Err(ExperimentError::Perplexity {
            perplexity: options.perplexity,
            needed,
            points: n,
        });
    }
    let mean = distances.iter().flatten().sum::<f64>() / (n * n) as f64;
    let unit = if mean > 0.0 { 1.0 / mean } else { 1.0 };
    let mut rng = SplitMix64::new(options.seed);
    let start: Vec<f64> = (0..2 * n).map(|_| rng.uniform(-1e-4, 1e-4)).collect();
    let indices: Vec<usize> = (0..n).collect();
    // bhtsne sums over rayon's adaptive splits; one thread makes the sums, hence the picture,
    // reproducible. n ≈ 100 makes the exact O(n²) iterations cheap.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| ExperimentError::Embedding(e.to_string()))?;
    let embedding = pool.install(|| {
        let mut fit: tSNE<f64, usize> = tSNE::new(&indices);
        fit.perplexity(options.perplexity)
            .epochs(options.epochs)
            .initial_embedding(start)
            .exact(|&i, &j| distances[i][j] * unit);
        fit.embedding()
    });
    Ok(embedding.chunks_exact(2).map(|p| (p[0], p[1])).collect())
}

/// Classical (Torgerson) multidimensional scaling into the plane: with `J = I − 𝟙𝟙ᵀ/n` and
/// `B = −½ J D⁽²⁾ J` (`D⁽²⁾` the entrywise squared distances), the coordinates of point `i`
/// are `(√λ₁ u₁ᵢ, √λ₂ u₂ᵢ)` for the two largest eigenpairs of `B` (negative eigenvalues count
/// as 0). Recovers a planar configuration up to a rigid motion when `D` is Euclidean in the
/// plane. Signs of the axes are fixed so that the first entry of largest magnitude of each
/// `u` is positive.
pub fn classical_mds(distances: &[Vec<f64>]) -> Result<Vec<(f64, f64)>, ExperimentError> {
    let n = distances.len();
    if distances.iter().any(|row| row.len() != n) {
        return Err(ExperimentError::NotSquare);
    }
    if n == 0 {
        return Ok(Vec::new());
    }
    let squared = Mat::<f64>::from_fn(n, n, |i, j| distances[i][j] * distances[i][j]);
    let row_mean: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| squared[(i, j)]).sum::<f64>() / n as f64)
        .collect();
    let total_mean = row_mean.iter().sum::<f64>() / n as f64;
    let b = Mat::<f64>::from_fn(n, n, |i, j| {
        -0.5 * (squared[(i, j)] - row_mean[i] - row_mean[j] + total_mean)
    });
    let eigen = b
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| ExperimentError::Eigen(format!("{e:?}")))?;
    let (u, s) = (eigen.U(), eigen.S());
    let axis = |rank: usize| -> Vec<f64> {
        if rank >= n {
            return vec![0.0; n];
        }
        let column = n - 1 - rank;
        let scale = s[column].max(0.0).sqrt();
        let values: Vec<f64> = (0..n).map(|i| u[(i, column)] * scale).collect();
        let sign = values
            .iter()
            .copied()
            .max_by(|a, b| a.abs().total_cmp(&b.abs()))
            .map_or(1.0, f64::signum);
        values.iter().map(|v| v * sign).collect()
    };
    let (x, y) = (axis(0), axis(1));
    Ok(x.into_iter().zip(y).collect())
}
