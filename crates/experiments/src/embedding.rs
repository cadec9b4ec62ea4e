//! Two-dimensional embeddings of a distance matrix for plotting (the paper uses t-SNE for
//! Fig. 10; classical multidimensional scaling is deterministic and exact for planar data).

use faer::{Mat, Side};

use crate::ExperimentError;

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
