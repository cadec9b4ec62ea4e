//! Real operators in real arithmetic: with the native backend, Laplace, modified Dirichlet and
//! anisotropic Laplace are solved over `f64`, and must give what the quaternionic path (`L⊗I`,
//! kept by the embedded backends) gives — the same eigenvalues and eigenspaces — and what a
//! dense solve of the same pencil gives, on spot, generated meshes and a mesh of two
//! components.

use dirac::TriMesh;
use dirac::generators::{RandomTessellation, Torus, icosphere};
use dirac::io::read_mesh;
use dirac::phase::{mass_inner, mass_norm};
use dirac::spectrum::{Operator, SolverBackend, Spectrum, SpectrumOptions, eigenproblem, spectrum};
use qeig::dense::generalized_hermitian_eigen;
use qscalar::Quat;
use qsparse::vector::axpy;
use qsparse::{DenseMatrix, SparseMatrix};

/// The three real operators.
const REAL_OPERATORS: [Operator; 3] = [
    Operator::Laplace,
    Operator::ModifiedDirichlet,
    Operator::AnisotropicLaplace { anisotropy: 2.0 },
];

fn solve(mesh: &TriMesh, operator: Operator, k: usize, backend: SolverBackend) -> Spectrum {
    let mut options = SpectrumOptions::new(operator, k);
    options.backend = backend;
    spectrum(mesh, &options).unwrap_or_else(|e| panic!("{operator} with {backend:?}: {e}"))
}

/// A torus with a random tessellation: no symmetry, so every eigenvalue is simple.
fn irregular_torus(major_radius: f64, seed: u64) -> TriMesh {
    let mut torus = Torus::new(major_radius, 0.4, 14, 9);
    torus.tessellation = Some(RandomTessellation { jitter: 0.2, seed });
    torus.mesh().unwrap()
}

/// Two irregular tori of different sizes, one moved away from the other: one mesh, two
/// components, simple eigenvalues (so that no eigenspace is cut at `k`).
fn two_components() -> TriMesh {
    let (first, second) = (irregular_torus(1.0, 7), irregular_torus(1.3, 8));
    let offset = first.vertex_count();
    let mut positions = first.positions().to_vec();
    positions.extend(second.positions().iter().map(|p| [p[0] + 5.0, p[1], p[2]]));
    let mut faces = first.faces().to_vec();
    faces.extend((second.faces().iter()).map(|f| [f[0] + offset, f[1] + offset, f[2] + offset]));
    TriMesh::new(positions, faces).unwrap()
}

/// `|a − b| ≤ tolerance · max(|b|, scale)`: relative, and absolute for the kernel's zeros
/// against the size `scale` of the spectrum.
fn assert_close(a: &[f64], b: &[f64], tolerance: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: counts");
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= tolerance * y.abs().max(1e-3 * scale),
            "{what}: eigenvalue {i}: {x} against {y}"
        );
    }
}

/// Every vector of `b` lies in the quaternionic span of the vectors of `a` whose eigenvalue
/// equals its own (mass-orthonormal within eigenspaces, so the projection is
/// `v − Σ u ⟨u, v⟩_M`).
fn assert_same_eigenspaces(a: &Spectrum, b: &Spectrum, what: &str) {
    let masses = &a.masses;
    for (j, (mu, v)) in b.eigenvalues.iter().zip(&b.eigenvectors).enumerate() {
        let mut rest = v.clone();
        for (lambda, u) in a.eigenvalues.iter().zip(&a.eigenvectors) {
            if (lambda - mu).abs() <= 1e-6 * mu.abs().max(1.0) {
                let c = mass_inner(masses, u, &rest);
                axpy(&mut rest, u, -c);
            }
        }
        let left = mass_norm(masses, &rest);
        assert!(
            left < 1e-6,
            "{what}: vector {j} (λ = {mu}) leaves {left} outside"
        );
    }
}

/// The real path ran: its eigenvectors are quaternions of exactly zero imaginary part (the
/// quaternionic path's are real only up to rounding), of unit mass norm.
fn assert_real_vectors(s: &Spectrum, what: &str) {
    for (j, x) in s.eigenvectors.iter().enumerate() {
        assert!(
            x.iter().all(|q| q.x == 0.0 && q.y == 0.0 && q.z == 0.0),
            "{what}: vector {j} has an imaginary part"
        );
        assert!(
            (mass_norm(&s.masses, x) - 1.0).abs() < 1e-12,
            "{what}: vector {j}"
        );
    }
}

/// The `k` smallest eigenvalues of the real pencil `P x = λ Q x` of `operator` on `mesh`, by a
/// dense solve of the matrices [`eigenproblem`] assembles (their imaginary parts checked to be
/// zero).
fn dense_eigenvalues(mesh: &TriMesh, operator: Operator, k: usize) -> Vec<f64> {
    let problem = eigenproblem(mesh, &SpectrumOptions::new(operator, k)).unwrap();
    let real = |m: &SparseMatrix<Quat<f64>>| -> DenseMatrix<f64> {
        assert!(
            m.values()
                .iter()
                .all(|q| q.x == 0.0 && q.y == 0.0 && q.z == 0.0)
        );
        m.map(|q| q.w).to_dense()
    };
    let eigen =
        generalized_hermitian_eigen(&real(&problem.stiffness), &real(&problem.coupling)).unwrap();
    eigen.values[..k].to_vec()
}

#[test]
fn real_path_matches_the_quaternionic_path_on_spot() {
    let mesh = read_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/data/spot.obj")).unwrap();
    for operator in REAL_OPERATORS {
        let real = solve(&mesh, operator, 12, SolverBackend::Native);
        let quaternionic = solve(&mesh, operator, 12, SolverBackend::ComplexAdjoint);
        let what = format!("spot, {operator}");
        assert_real_vectors(&real, &what);
        assert_close(&real.eigenvalues, &quaternionic.eigenvalues, 1e-10, &what);
        assert_same_eigenspaces(&real, &quaternionic, &what);
        assert_same_eigenspaces(&quaternionic, &real, &what);
        assert_eq!(real.kernel, quaternionic.kernel, "{what}");
        assert!(
            real.residuals.iter().all(|&r| r <= 1e-8),
            "{what}: {:?}",
            real.residuals
        );
        assert!(real.statistics.operator_applications > 0, "{what}");
    }
}

#[test]
fn real_path_matches_dense_solves_and_the_quaternionic_path_on_generated_meshes() {
    let torus = irregular_torus(1.0, 7);
    // The icosphere's eigenvalues are multiple (1, 3, 5, 7 for l = 0..3 of the sphere):
    // k = 16 takes whole eigenspaces.
    let sphere = icosphere(2);
    for (name, mesh, k) in [("torus", &torus, 14), ("icosphere", &sphere, 16)] {
        for operator in REAL_OPERATORS {
            let what = format!("{name}, {operator}");
            let real = solve(mesh, operator, k, SolverBackend::Native);
            assert_real_vectors(&real, &what);
            assert_close(
                &real.eigenvalues,
                &dense_eigenvalues(mesh, operator, k),
                1e-9,
                &what,
            );
            let quaternionic = solve(mesh, operator, k, SolverBackend::RealBlock);
            assert_close(&real.eigenvalues, &quaternionic.eigenvalues, 1e-10, &what);
            assert_same_eigenspaces(&real, &quaternionic, &what);
            assert_same_eigenspaces(&quaternionic, &real, &what);
        }
    }
}

#[test]
fn sphere_multiplicities_come_out_in_real_arithmetic() {
    let real = solve(&icosphere(2), Operator::Laplace, 16, SolverBackend::Native);
    // Clusters of sizes 1, 3, 5, 7 around l(l+1), separated by gaps.
    let mut sizes = Vec::new();
    let mut start = 0;
    for i in 1..=real.eigenvalues.len() {
        let end = i == real.eigenvalues.len();
        if end
            || real.eigenvalues[i] - real.eigenvalues[start]
                > 0.2 * real.eigenvalues[start].max(1.0)
        {
            sizes.push(i - start);
            start = i;
        }
    }
    assert_eq!(sizes, [1, 3, 5, 7], "{:?}", real.eigenvalues);
}

#[test]
fn two_components_give_a_kernel_of_dimension_two() {
    let mesh = two_components();
    let k = 12;
    for operator in REAL_OPERATORS {
        let what = format!("two components, {operator}");
        let real = solve(&mesh, operator, k, SolverBackend::Native);
        assert_real_vectors(&real, &what);
        // The constants of each component; the Willmore potential of the modified Dirichlet
        // operator is positive on both, so it has none.
        let kernel = if operator == Operator::ModifiedDirichlet {
            0
        } else {
            2
        };
        assert_eq!(real.kernel.dimension, kernel, "{what}");
        assert!(
            real.eigenvalues[..kernel].iter().all(|&v| v == 0.0),
            "{what}"
        );
        assert_close(
            &real.eigenvalues,
            &dense_eigenvalues(&mesh, operator, k),
            1e-9,
            &what,
        );
        let quaternionic = solve(&mesh, operator, k, SolverBackend::ComplexAdjoint);
        assert_close(&real.eigenvalues, &quaternionic.eigenvalues, 1e-10, &what);
        assert_same_eigenspaces(&real, &quaternionic, &what);
        assert_same_eigenspaces(&quaternionic, &real, &what);
    }
}
