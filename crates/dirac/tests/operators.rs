//! Property tests of the discrete operators against the exact identities of docs/MATH.md,
//! "The operators" and "What the tests check against".

mod common;

use std::collections::HashMap;

use common::perturbed_sphere;
use dirac::TriMesh;
use dirac::generators::icosphere;
use dirac::geometry::{barycentric_masses, cotan_laplacian, vertex_normals};
use dirac::operators::{DiracPencil, extrinsic_dirac, normal_dirac, relative_dirac};
use proptest::prelude::*;
use qscalar::strategies::quat;
use qscalar::{Quat, Scalar};
use qsparse::SparseMatrix;

/// A flat `side × side` grid in the plane z = 0.
fn plane(side: usize) -> TriMesh {
    let positions = (0..side * side)
        .map(|v| [(v % side) as f64, (v / side) as f64, 0.0])
        .collect();
    let mut faces = Vec::new();
    for r in 0..side - 1 {
        for c in 0..side - 1 {
            let v = r * side + c;
            faces.push([v, v + 1, v + side + 1]);
            faces.push([v, v + side + 1, v + side]);
        }
    }
    TriMesh::new(positions, faces).expect("a grid is valid")
}

fn max_abs(m: &SparseMatrix<Quat<f64>>) -> f64 {
    m.values().iter().map(|q| q.norm()).fold(0.0, f64::max)
}

fn apply(m: &SparseMatrix<Quat<f64>>, x: &[Quat<f64>]) -> Vec<Quat<f64>> {
    let mut y = vec![Quat::default(); m.nrows()];
    m.mul_vec(x, &mut y).expect("matching dimensions");
    y
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn dirac_operators_annihilate_constants(mesh in perturbed_sphere(1, 0.2), c in quat(2.0)) {
        for d in [normal_dirac(&mesh).unwrap(), extrinsic_dirac(&mesh).unwrap()] {
            let y = apply(&d, &vec![c; mesh.vertex_count()]);
            let scale = max_abs(&d) * c.norm();
            prop_assert!(y.iter().all(|q| q.norm() <= 1e-12 * scale));
        }
    }

    #[test]
    fn coupling_is_hermitian_imaginary_with_zero_diagonal(mesh in perturbed_sphere(1, 0.2)) {
        let d = normal_dirac(&mesh).unwrap();
        let g = DiracPencil::new(&mesh, &d).unwrap().coupling;
        let scale = max_abs(&g);
        prop_assert!(g.hermitian_defect() <= 1e-14 * scale);
        for (i, j, v) in g.triplets() {
            prop_assert!(v.w.abs() <= 1e-14 * scale, "real part at ({i}, {j})");
            if i == j {
                prop_assert!(v.norm() <= 1e-14 * scale, "diagonal at {i}");
            }
        }
        // G 𝟙 = 0.
        let y = apply(&g, &vec![Quat::from_real(1.0); mesh.vertex_count()]);
        prop_assert!(y.iter().all(|q| q.norm() <= 1e-13 * scale));
    }

    #[test]
    fn coupling_entry_formula(mesh in perturbed_sphere(1, 0.2)) {
        // G_ij = −(N_l − N_k)/6 for the edge ij with k opposite in face (i,j,k), l in (j,i,l).
        let normals = vertex_normals(&mesh).unwrap();
        let g = DiracPencil::new(&mesh, &relative_dirac(&mesh, &normals).unwrap()).unwrap().coupling;
        let mut opposite = HashMap::new();
        for &[a, b, c] in mesh.faces() {
            for (i, j, k) in [(a, b, c), (b, c, a), (c, a, b)] {
                opposite.insert((i, j), k);
            }
        }
        for (&(i, j), &k) in &opposite {
            let l = opposite[&(j, i)];
            let expected = Quat::from_vector([0, 1, 2].map(|c| -(normals[l][c] - normals[k][c]) / 6.0));
            prop_assert!((g.get(i, j) - expected).norm() <= 1e-14);
        }
    }

    #[test]
    fn stiffness_is_hermitian_positive_semidefinite(
        mesh in perturbed_sphere(1, 0.2),
        x in prop::collection::vec(quat(1.0), 42),
    ) {
        let a = DiracPencil::new(&mesh, &normal_dirac(&mesh).unwrap()).unwrap().stiffness;
        let scale = max_abs(&a);
        prop_assert!(a.hermitian_defect() <= 1e-13 * scale);
        let ax = apply(&a, &x);
        let energy = qsparse::vector::inner(&x, &ax);
        prop_assert!(energy.w >= -1e-12 * scale);
        prop_assert!(Quat::from_vector(energy.vector_part()).norm() <= 1e-12 * scale * 42.0);
    }

    #[test]
    fn real_part_of_extrinsic_stiffness_is_cotan_laplacian(mesh in perturbed_sphere(1, 0.2)) {
        let a = DiracPencil::new(&mesh, &extrinsic_dirac(&mesh).unwrap()).unwrap().stiffness;
        let l = cotan_laplacian(&mesh);
        let scale = l.values().iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (i, j, v) in a.triplets() {
            prop_assert!((v.re() - l.get(i, j)).abs() <= 1e-12 * scale, "entry ({i}, {j})");
        }
        for (i, j, v) in l.triplets() {
            prop_assert!((a.get(i, j).re() - v).abs() <= 1e-12 * scale, "entry ({i}, {j})");
        }
    }

    #[test]
    fn relative_dirac_with_positions_is_extrinsic_dirac(mesh in perturbed_sphere(1, 0.2)) {
        prop_assert_eq!(relative_dirac(&mesh, mesh.positions()).unwrap(), extrinsic_dirac(&mesh).unwrap());
    }

    #[test]
    fn flipping_orientation_with_fixed_normals_negates_the_operator(mesh in perturbed_sphere(1, 0.2)) {
        let normals = vertex_normals(&mesh).unwrap();
        let flipped_faces = mesh.faces().iter().map(|&[i, j, k]| [i, k, j]).collect();
        let flipped = TriMesh::new(mesh.positions().to_vec(), flipped_faces).unwrap();
        let d = relative_dirac(&mesh, &normals).unwrap();
        let e = relative_dirac(&flipped, &normals).unwrap();
        for (i, j, v) in d.triplets() {
            prop_assert!((e.get(i, j) + v).norm() <= 1e-14 * v.norm().max(1.0));
        }
    }
}

#[test]
fn plane_has_vanishing_normal_dirac_operator() {
    let d = normal_dirac(&plane(6)).unwrap();
    assert_eq!(d.nnz(), 3 * 2 * 25);
    assert!(d.values().iter().all(|q| q.norm() == 0.0));
}

#[test]
fn masses_sum_to_total_area() {
    let mesh = icosphere(3);
    let total: f64 = barycentric_masses(&mesh).iter().sum();
    // The inscribed polyhedron's area approaches 4π from below.
    assert!(total < 4.0 * std::f64::consts::PI && total > 0.99 * 4.0 * std::f64::consts::PI);
}

#[test]
fn operators_reject_bad_vertex_values() {
    let mesh = icosphere(0);
    assert!(matches!(
        relative_dirac(&mesh, &[[0.0; 3]; 5]),
        Err(dirac::operators::OperatorError::VertexValueCount {
            expected: 12,
            found: 5
        })
    ));
    let mut values = mesh.positions().to_vec();
    values[7][1] = f64::NAN;
    assert!(matches!(
        relative_dirac(&mesh, &values),
        Err(dirac::operators::OperatorError::NonFiniteValue { vertex: 7 })
    ));
}
