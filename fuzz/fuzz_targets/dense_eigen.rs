//! Fuzz target: small arbitrary dense quaternion matrices (n ≤ 8, occasionally not square or
//! of different sizes), Hermitian or not, with NaN, ∞, raw-bit (huge and tiny) and moderate
//! values, optionally scaled by a power of two far from 1 → `qeig::dense::hermitian_eigen` and
//! `qeig::dense::generalized_hermitian_eigen`. Neither may panic: `NotSquare` only for a
//! non-square operand, `NonFinite` only (and always) for a non-finite value, `DimensionMismatch`
//! only for operands of different orders. A result has ascending eigenvalues, finite
//! eigenvectors, and — checked on copies divided by the largest component, so that the check
//! itself neither overflows nor underflows — orthonormal eigenvectors with residuals at
//! rounding level (`hermitian_eigen`, of the Hermitian matrix its lower triangle defines); a
//! diagonally dominant `S` of moderate values is accepted, with `S`-orthonormal eigenvectors
//! of small residual.

#![no_main]

use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use qeig::EigError;
use qeig::dense::{DenseEigen, generalized_hermitian_eigen, hermitian_eigen};
use qscalar::{Quat, Scalar};
use qsparse::DenseMatrix;

#[path = "quaternion_matrices.rs"]
#[allow(dead_code)] // The values only; the sparse assembly helpers serve the other targets.
mod quaternion_matrices;
use quaternion_matrices::{Q, quat};

/// A generated operand and what is known about it by construction.
struct Operand {
    m: DenseMatrix<Q>,
    /// Hermitian (lower triangle), moderate values, strictly diagonally dominant with a margin
    /// of 1: certainly positive definite.
    dominant: bool,
}

/// An `nrows × ncols` matrix. A non-finite value stays with probability 1/8 (otherwise it
/// becomes 0, so that most inputs reach the solvers); with probability `dominant` (out of 4)
/// a square one gets `1 + Σⱼ |aᵢⱼ|` added to its diagonal; with probability 1/8 everything is
/// scaled by a power of two between `2⁻¹⁰⁰⁰` and `2¹⁰⁰⁰`.
fn operand(u: &mut Unstructured, nrows: usize, ncols: usize, dominant: u8) -> Result<Operand> {
    let mut moderate = true;
    let mut values = Vec::with_capacity(nrows * ncols);
    for _ in 0..nrows * ncols {
        let v = quat(u, &mut moderate)?;
        let keep = v.is_finite() || u.ratio(1, 8)?;
        values.push(if keep { v } else { Q::default() });
    }
    let moderate = values.iter().all(|v| {
        v.to_array()
            .iter()
            .all(|c| c.is_finite() && c.abs() <= 2048.0)
    });
    let mut m = DenseMatrix::from_fn(nrows, ncols, |i, j| values[i + nrows * j]);
    let square = nrows == ncols;
    let dominated = square && moderate && dominant > 0 && u.ratio(dominant, 4)?;
    if dominated {
        for i in 0..nrows {
            // Only the lower triangle is read: that is the Hermitian matrix solved.
            let row: f64 = (0..ncols)
                .filter(|&j| j != i)
                .map(|j| if i > j { m[(i, j)] } else { m[(j, i)] }.norm())
                .sum();
            m[(i, i)] = Quat::from_real(m[(i, i)].w.abs() + 1.0 + row);
        }
    }
    if u.ratio(1, 8)? {
        let power = u.int_in_range(-1000..=1000i32)?;
        let factor = 2f64.powi(power);
        m = DenseMatrix::from_fn(nrows, ncols, |i, j| m[(i, j)].scale(factor));
    }
    Ok(Operand {
        m,
        dominant: dominated,
    })
}

fn largest_component(m: &DenseMatrix<Q>) -> f64 {
    (m.as_slice().iter())
        .flat_map(|v| v.to_array())
        .fold(0.0f64, |a, c| a.max(c.abs()))
}

/// The Hermitian matrix the lower triangle of `m` defines, divided by `scale`.
fn hermitian_part(m: &DenseMatrix<Q>, scale: f64) -> DenseMatrix<Q> {
    let n = m.nrows();
    DenseMatrix::from_fn(n, n, |i, j| {
        let v = if i > j {
            m[(i, j)]
        } else if i < j {
            m[(j, i)].conj()
        } else {
            Quat::from_real(m[(i, i)].w)
        };
        v.scale(1.0 / scale)
    })
}

fn check_shape(eigen: &DenseEigen<Q>, n: usize) {
    assert_eq!(eigen.values.len(), n);
    assert_eq!((eigen.vectors.nrows(), eigen.vectors.ncols()), (n, n));
    assert!(
        eigen.vectors.as_slice().iter().all(|v| v.is_finite()),
        "non-finite eigenvector"
    );
    assert!(
        eigen.values.windows(2).all(|w| w[0] <= w[1]),
        "eigenvalues not ascending: {:?}",
        eigen.values
    );
}

/// `maxᵢ ‖A xᵢ − B xᵢ μᵢ‖` and `max |Xᴴ B X − I|` with `B` the identity when `None`.
fn defects(
    a: &DenseMatrix<Q>,
    b: Option<&DenseMatrix<Q>>,
    values: &[f64],
    x: &DenseMatrix<Q>,
) -> (f64, f64) {
    let n = a.nrows();
    let bx = match b {
        Some(b) => b.matmul(x).expect("square"),
        None => x.clone(),
    };
    let ax = a.matmul(x).expect("square");
    let mut residual = 0.0f64;
    for (j, &mu) in values.iter().enumerate() {
        let r = (0..n)
            .map(|i| (ax[(i, j)] - bx[(i, j)].scale(mu)).abs2())
            .sum::<f64>()
            .sqrt();
        residual = residual.max(r);
    }
    let gram = x.adjoint().matmul(&bx).expect("square");
    let identity = DenseMatrix::<Q>::identity(n);
    let orthonormality = (gram.as_slice().iter().zip(identity.as_slice()))
        .map(|(g, e)| (*g - *e).norm())
        .fold(0.0f64, f64::max);
    (residual, orthonormality)
}

fn run(u: &mut Unstructured) -> Result<()> {
    let n = u.int_in_range(0..=8usize)?;
    let a_cols = if u.ratio(1, 16)? { n + 1 } else { n };
    let a = operand(u, n, a_cols, 0)?.m;
    let a_finite = a.as_slice().iter().all(|v| v.is_finite());

    match hermitian_eigen(&a) {
        Ok(eigen) => {
            assert!(a_cols == n && a_finite);
            check_shape(&eigen, n);
            let scale = largest_component(&a);
            // An eigenvalue beyond the range of f64 can only be ±∞.
            if scale > 0.0 && scale < 1e300 {
                assert!(eigen.values.iter().all(|v| v.is_finite()));
                let values: Vec<f64> = eigen.values.iter().map(|v| v / scale).collect();
                let h = hermitian_part(&a, scale);
                let (residual, orthonormality) = defects(&h, None, &values, &eigen.vectors);
                assert!(
                    residual < 1e-12,
                    "residual {residual:e} (relative to the largest entry)"
                );
                assert!(
                    orthonormality < 1e-12,
                    "orthonormality defect {orthonormality:e}"
                );
            }
        }
        Err(EigError::NotSquare {
            which,
            nrows,
            ncols,
        }) => {
            assert!(which == "A" && (nrows, ncols) == (n, a_cols) && nrows != ncols)
        }
        Err(EigError::NonFinite(which)) => assert!(which == "A" && a_cols == n && !a_finite),
        Err(EigError::DenseEigen(_)) => {}
        Err(e) => panic!("unexpected error from hermitian_eigen: {e}"),
    }

    let s_order = if u.ratio(1, 16)? { n + 1 } else { n };
    let s = operand(u, s_order, s_order, 3)?;
    let k = a;
    let k_square = k.nrows() == k.ncols();
    let s_finite = s.m.as_slice().iter().all(|v| v.is_finite());
    match generalized_hermitian_eigen(&k, &s.m) {
        Ok(eigen) => {
            assert!(k_square && a_finite && s_finite && s_order == n);
            check_shape(&eigen, n);
            let (k_scale, s_scale) = (largest_component(&k), largest_component(&s.m));
            // `S` is dominant with a margin of 1 before any power-of-two scaling, so its smallest
            // eigenvalue is at least `s_scale / 10⁵` and `|μ| ≤ 10⁶ k_scale / s_scale`: finite
            // when the two scales are less than `10²⁹⁰` apart.
            let ratio = k_scale / s_scale;
            if s.dominant && k_scale > 0.0 && s_scale > 0.0 && ratio < 1e290 && ratio > 1e-290 {
                assert!(
                    eigen.values.iter().all(|v| v.is_finite()),
                    "{:?}",
                    eigen.values
                );
                // K x = μ S x ⇔ (K/a) x = (μ b/a) (S/b) x; the vectors are S-orthonormal, so
                // √b x is (S/b)-orthonormal. `b/a` is normal by the guard above; `μ b` alone
                // can overflow (μ = 1.5e254, b = 1.3e54).
                let (kh, sh) = (hermitian_part(&k, k_scale), hermitian_part(&s.m, s_scale));
                let values: Vec<f64> = eigen.values.iter().map(|v| v * ratio.recip()).collect();
                let x =
                    DenseMatrix::from_fn(n, n, |i, j| eigen.vectors[(i, j)].scale(s_scale.sqrt()));
                let (residual, orthonormality) = defects(&kh, Some(&sh), &values, &x);
                assert!(residual < 1e-9, "pencil residual {residual:e}");
                assert!(
                    orthonormality < 1e-9,
                    "S-orthonormality defect {orthonormality:e}"
                );
            }
        }
        Err(EigError::NotSquare { which, .. }) => assert!(which == "K" && !k_square),
        Err(EigError::NonFinite(which)) => {
            assert!(
                (which == "K" && !a_finite) || (which == "S" && !s_finite),
                "NonFinite({which}), K finite {a_finite}, S finite {s_finite}, n {n}, S order {s_order}"
            )
        }
        Err(EigError::DimensionMismatch {
            expected, found, ..
        }) => {
            assert!(k_square && expected == s_order && found == n && s_order != n)
        }
        Err(EigError::EmbeddedFactorization(e)) => {
            assert!(!s.dominant, "a diagonally dominant S was refused: {e}")
        }
        Err(EigError::DenseEigen(_)) => {}
        Err(e) => panic!("unexpected error from generalized_hermitian_eigen: {e}"),
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
