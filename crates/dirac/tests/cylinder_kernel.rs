//! The kernel of `D_N` on the unit cylinder (docs/MATH.md, "What the tests check against"): with
//! the exact radial normals every function of the angle alone is in the kernel and the quaternionic
//! nullity is exactly the number of segments; with area-weighted normals the kernel collapses.

use dirac::generators::{cylinder, cylinder_normals};
use dirac::geometry::barycentric_masses;
use dirac::operators::{DiracPencil, normal_dirac, quaternionic, relative_dirac};
use proptest::prelude::*;
use qeig::dense::generalized_hermitian_eigen;
use qscalar::Quat;
use qscalar::blocks::left_block;
use qscalar::strategies::quat;
use qsparse::{DenseMatrix, SparseMatrix, vector};

const SEGMENTS: usize = 24;
const RINGS: usize = 10;
const HEIGHT: f64 = 2.0;

fn max_abs(m: &SparseMatrix<Quat<f64>>) -> f64 {
    m.values().iter().map(|q| q.norm()).fold(0.0, f64::max)
}

/// Eigenvalues (ascending) of the dense pencil `A x = ν M x`.
fn stiffness_spectrum(a: &SparseMatrix<Quat<f64>>, masses: &[f64]) -> Vec<f64> {
    let m = quaternionic(&SparseMatrix::from_diagonal(masses));
    generalized_hermitian_eigen(&a.to_dense(), &m.to_dense())
        .unwrap()
        .values
}

/// The same pencil in the real-block representation (docs/MATH.md, "The real-block
/// representation"), `4n × 4n`.
fn real_block_spectrum(a: &SparseMatrix<Quat<f64>>, masses: &[f64]) -> Vec<f64> {
    let n = masses.len();
    let mut block = DenseMatrix::<f64>::zeros(4 * n, 4 * n);
    for (i, j, q) in a.triplets() {
        let l = left_block(q);
        for r in 0..4 {
            for c in 0..4 {
                block[(4 * i + r, 4 * j + c)] = l[r][c];
            }
        }
    }
    let mass = DenseMatrix::from_fn(
        4 * n,
        4 * n,
        |i, j| {
            if i == j { masses[i / 4] } else { 0.0 }
        },
    );
    generalized_hermitian_eigen(&block, &mass).unwrap().values
}

/// Number of eigenvalues below `1e-10 · max`, and the smallest eigenvalue above it relative to
/// the largest (to show the count is not a threshold artefact).
fn nullity(values: &[f64]) -> (usize, f64) {
    let top = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let count = values.iter().filter(|v| v.abs() <= 1e-10 * top).count();
    let next = values
        .iter()
        .filter(|v| v.abs() > 1e-10 * top)
        .fold(f64::INFINITY, |m, v| m.min(v.abs()));
    (count, next / top)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// `D_N ψ = 0` for every `ψ` that depends only on the angle index (continuum:
    /// `D_N ψ = −N_θ ψ_z`), with quaternion values drawn per angle.
    #[test]
    fn angle_only_functions_are_in_the_kernel(values in prop::collection::vec(quat(1.0), SEGMENTS)) {
        let mesh = cylinder(SEGMENTS, RINGS, HEIGHT).unwrap();
        let d = relative_dirac(&mesh, &cylinder_normals(SEGMENTS, RINGS)).unwrap();
        let psi: Vec<Quat<f64>> = (0..mesh.vertex_count()).map(|v| values[v % SEGMENTS]).collect();
        let mut y = vec![Quat::default(); mesh.face_count()];
        d.mul_vec(&psi, &mut y).unwrap();
        let bound = 1e-13 * max_abs(&d) * vector::norm(&psi);
        prop_assert!(vector::norm(&y) <= bound, "|D ψ| = {:e}", vector::norm(&y));
    }
}

#[test]
fn exact_normals_give_quaternionic_nullity_equal_to_the_segment_count() {
    let mesh = cylinder(SEGMENTS, RINGS, HEIGHT).unwrap();
    let masses = barycentric_masses(&mesh);
    let d = relative_dirac(&mesh, &cylinder_normals(SEGMENTS, RINGS)).unwrap();
    let a = DiracPencil::new(&mesh, &d).unwrap().stiffness;

    let (count, gap) = nullity(&stiffness_spectrum(&a, &masses));
    assert_eq!(count, SEGMENTS, "quaternionic nullity of A = D* M_F D");
    assert!(
        gap > 1e-6,
        "the kernel is separated from the rest (next/max = {gap:e})"
    );

    let (real_count, real_gap) = nullity(&real_block_spectrum(&a, &masses));
    assert_eq!(real_count, 4 * SEGMENTS, "real nullity of the real block");
    assert!(real_gap > 1e-6, "next/max = {real_gap:e}");
}

#[test]
fn area_weighted_normals_shrink_the_kernel() {
    let mesh = cylinder(SEGMENTS, RINGS, HEIGHT).unwrap();
    let masses = barycentric_masses(&mesh);
    let a = DiracPencil::new(&mesh, &normal_dirac(&mesh).unwrap())
        .unwrap()
        .stiffness;
    let (count, gap) = nullity(&stiffness_spectrum(&a, &masses));
    // The constants are always in the kernel; an independent computation on this cylinder
    // found 2 quaternionic dimensions (8 real).
    assert!(
        (1..SEGMENTS).contains(&count),
        "nullity {count} with area-weighted normals"
    );
    assert!(gap > 1e-6, "next/max = {gap:e}");
    eprintln!("area-weighted normals: quaternionic nullity {count}");
}
