//! Locking when the true residuals lag behind the Lanczos estimates, as a pencil's do: the
//! residual of the mapped-back pair is the iteration space's residual seen through the
//! factor, larger by a factor (a constant one here).

use qeig::{HermitianOperator, LanczosOptions, Which, hermitian_eigs};

/// `A = diag(d)`, whose `relative_residual` reports `lag` times the true relative residual
/// `‖A y − θ y‖ / (|θ| ‖y‖)`.
struct Lagging {
    d: Vec<f64>,
    lag: f64,
}

impl HermitianOperator<f64> for Lagging {
    fn dim(&self) -> usize {
        self.d.len()
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        for ((y, x), d) in y.iter_mut().zip(x).zip(&self.d) {
            *y = d * x;
        }
    }

    fn relative_residual(&mut self, y: &[f64], theta: f64) -> f64 {
        let residual: f64 = (y.iter().zip(&self.d))
            .map(|(y, d)| (d * y - theta * y).powi(2))
            .sum();
        let norm: f64 = y.iter().map(|y| y * y).sum();
        self.lag * (residual / norm).sqrt() / theta.abs()
    }
}

/// Eigenvalues `1/(1 + j)` for `j < 800` (the spectrum of a shift-and-invert operator about
/// the bottom of a Laplacian): the 20 largest, with residuals lagging `lag` times.
fn solve(lag: f64) -> qeig::Eigen<f64> {
    let mut op = Lagging {
        d: (0..800).map(|j| 1.0 / (1.0 + j as f64)).collect(),
        lag,
    };
    // A lag beyond `√tol / (rounding level)` would make pairs lock at the rounding level with
    // residuals up to `√tol` (the module documentation of the Lanczos core); not here.
    let options = LanczosOptions::new(20, Which::LargestAlgebraic);
    let eig = hermitian_eigs(&mut op, &options, &[], None).expect("converges");
    for (j, (&value, &residual)) in eig.values.iter().zip(&eig.residuals).enumerate() {
        let want = 1.0 / (1.0 + j as f64);
        assert!(
            (value - want).abs() <= 1e-12 * want,
            "{j}: {value} vs {want}"
        );
        assert!(residual <= options.tolerance, "{j}: residual {residual:e}");
    }
    eig
}

/// A candidate refused by its true residual teaches how far below the tolerance estimates
/// must fall: the next check points wait for that instead of ten steps, so lagging
/// residuals cost a few more steps, not a restart and ten steps per refusal.
#[test]
fn lagging_residuals_cost_a_few_steps() {
    let prompt = solve(1.0).statistics;
    for lag in [10.0, 100.0] {
        let lagging = solve(lag).statistics;
        assert!(
            lagging.operator_applications < prompt.operator_applications + 6,
            "lag {lag}: {} applications against {} without lag",
            lagging.operator_applications,
            prompt.operator_applications
        );
    }
}
