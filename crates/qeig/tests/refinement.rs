//! `Pencil::refine`: a step of subspace iteration and a Rayleigh–Ritz step with the matrices
//! themselves, on perturbed pairs, against the dense solution of the same pencil.

mod common;

use common::{Rng, columns, dense_truth, distance_to_span, random_hermitian, random_hpd, s_inner};
use qeig::{Eigen, Pencil, Statistics};
use qscalar::{Quat, Scalar};
use qsparse::{SparseMatrix, TripletMatrix};

type Q = Quat<f64>;

/// `K = diag(60, 50, 40, 30, 20) ⊕ 0` plus a small random Hermitian part, `S` random positive
/// definite: five dominant eigenvalues `μ` well apart from the rest (`|μ_out / μ_in|` below
/// about 0.1), so that one step shrinks what lies outside the window tenfold.
fn dominant_pencil(n: usize) -> (SparseMatrix<Q>, SparseMatrix<Q>) {
    let mut rng = Rng::new(7);
    let noise = random_hermitian::<Q>(n, 2, 0.0, &mut rng);
    let mut t = TripletMatrix::new(n, n);
    for (i, j, v) in noise.triplets() {
        t.push(i, j, v.scale(0.1)).unwrap();
    }
    for (i, d) in [60.0, 50.0, 40.0, 30.0, 20.0].into_iter().enumerate() {
        t.push(i, i, Q::from_real(d)).unwrap();
    }
    (t.to_csc(), random_hpd(n, &mut rng))
}

/// The dominant eigenvector is deflated by the constraint `(S d)ᴴ x = 0`; the next four
/// eigenvectors, each perturbed by `10⁻⁶` in random directions (which break the constraint
/// too) and given the wrong eigenvalues, are refined twice: the eigenvalues come back to
/// `10⁻¹²`, the vectors to `10⁻⁷` of the dense eigenvectors, `S`-orthonormal, the constraint
/// holds to rounding, and the second step shrinks the residuals at least tenfold.
#[test]
fn refinement_restores_perturbed_pairs_under_a_constraint() {
    let n = 40;
    let (k, s) = dominant_pencil(n);
    let truth = dense_truth(&k, &s);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| truth.values[b].abs().total_cmp(&truth.values[a].abs()));
    assert!(truth.values[order[5]].abs() < 0.15 * truth.values[order[4]].abs());
    let dominant = columns(&truth.vectors, &order[..1]).remove(0);
    let mut constraint = vec![Q::default(); n];
    s.mul_vec(&dominant, &mut constraint).unwrap();
    let pencil = Pencil::new(&k, &s)
        .unwrap()
        .with_constraints(SparseMatrix::from_dense_columns(n, &[constraint.clone()]).unwrap())
        .unwrap();
    let wanted = &order[1..5];
    let mut rng = Rng::new(11);
    let start = Eigen {
        values: vec![1.0; wanted.len()],
        vectors: (columns(&truth.vectors, wanted).into_iter())
            .map(|x| {
                x.into_iter()
                    .map(|v| v + rng.scalar::<Q>().scale(1e-6))
                    .collect()
            })
            .collect(),
        residuals: vec![1.0; wanted.len()],
        statistics: Statistics::default(),
    };
    let once = pencil.refine(&start).unwrap();
    let refined = pencil.refine(&once).unwrap();
    assert_eq!(refined.values.len(), wanted.len());
    for (i, &j) in wanted.iter().enumerate() {
        let (got, want) = (refined.values[i], truth.values[j]);
        assert!(
            (got - want).abs() <= 1e-12 * want.abs(),
            "{i}: {got} against {want}"
        );
        let x = &refined.vectors[i];
        let eigenvector = columns(&truth.vectors, &[j]);
        assert!(distance_to_span(&s, x, &eigenvector) < 1e-7, "{i}");
        assert!((s_inner(&s, x, x).re() - 1.0).abs() < 1e-12, "{i}");
        let along: Q = (constraint.iter().zip(x)).map(|(c, v)| c.conj() * *v).sum();
        assert!(along.abs() < 1e-12, "{i}: {along:?}");
        // What lies outside the window shrinks by `|μ_out / μ_in|` per step.
        let (before, after) = (once.residuals[i], refined.residuals[i]);
        assert!(
            after < 1e-8 && after < 0.1 * before,
            "{i}: {before} then {after}"
        );
    }
}
