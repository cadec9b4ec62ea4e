//! The anisotropic Laplacian `Δ_A = div(A grad)` (Andreux et al. 2014) against truths computed
//! independently of its assembly: a hand-computed triangle, the cotangent Laplacian for
//! `H = I`, the exact curvature of a cylinder and a sphere with exact normals, and the closed
//! spectra `ψ_α(1/r) l(l+1)/r²` (sphere) and `(πm/h)² + ψ_α(1/r)(n/r)²` (open cylinder,
//! Neumann ends).

use dirac::anisotropic::{anisotropic_laplacian, conductivity, tensor_laplacian};
use dirac::curvature::face_principal_curvatures;
use dirac::generators::{Torus, cylinder, cylinder_normals, icosphere};
use dirac::geometry::{cotan_laplacian, dot};
use dirac::operators::OperatorError;
use dirac::spectrum::{Operator, Parameter, SpectrumError, SpectrumOptions, spectrum};
use dirac::{ParseOperatorError, TriMesh};
use qscalar::random::SplitMix64;
use qsparse::SparseMatrix;

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// A bumpy, randomly tessellated torus: curvature of both signs, no symmetry.
fn torus() -> TriMesh {
    let mut torus = Torus::new(2.0, 0.7, 30, 14);
    torus.tessellation = Some(dirac::generators::RandomTessellation {
        jitter: 0.2,
        seed: 3,
    });
    torus.mesh().unwrap()
}

/// Largest `|a_ij − b_ij|` over the union of both patterns, relative to the largest `|b_ij|`.
fn relative_difference(a: &SparseMatrix<f64>, b: &SparseMatrix<f64>) -> f64 {
    let largest = b.triplets().map(|(_, _, v)| v.abs()).fold(0.0, f64::max);
    let difference = SparseMatrix::linear_combination(1.0, a, -1.0, b).unwrap();
    difference
        .triplets()
        .map(|(_, _, v)| v.abs())
        .fold(0.0, f64::max)
        / largest
}

#[test]
fn a_hand_computed_triangle() {
    // The right triangle (0,0), (1,0), (0,1): ∇φ = (−1,−1), (1,0), (0,1), area 1/2. With
    // H = diag(a, b) in (x, y), K = ½ [[a+b, −a, −b], [−a, a, 0], [−b, 0, b]].
    let mesh = TriMesh::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let (a, b) = (0.3, 2.0);
    let tensor = [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, 1.0]];
    let k = tensor_laplacian(&mesh, &[tensor]).unwrap();
    let expected = [[a + b, -a, -b], [-a, a, 0.0], [-b, 0.0, b]];
    for (i, row) in expected.iter().enumerate() {
        for (j, &value) in row.iter().enumerate() {
            assert!(
                (k.get(i, j) - 0.5 * value).abs() < 1e-15,
                "K[{i}][{j}] = {} instead of {}",
                k.get(i, j),
                0.5 * value
            );
        }
    }
    assert_eq!(
        tensor_laplacian(&mesh, &[]),
        Err(OperatorError::FaceValueCount {
            expected: 1,
            found: 0
        })
    );
}

#[test]
fn the_identity_tensor_and_no_anisotropy_give_the_cotangent_laplacian() {
    for mesh in [torus(), icosphere(2), cylinder(12, 5, 1.5).unwrap()] {
        let cotan = cotan_laplacian(&mesh);
        let identity = vec![IDENTITY; mesh.face_count()];
        let from_tensors = tensor_laplacian(&mesh, &identity).unwrap();
        let isotropic = anisotropic_laplacian(&mesh, 0.0).unwrap();
        // The same matrix up to rounding of the two formulas (cotangents against gradients).
        assert!(relative_difference(&from_tensors, &cotan) < 1e-13);
        assert!(relative_difference(&isotropic, &cotan) < 1e-13);
    }
}

#[test]
fn the_stiffness_is_symmetric_semidefinite_with_the_constants_in_its_kernel() {
    let mesh = torus();
    for alpha in [0.5, 10.0, 1e3] {
        let k = anisotropic_laplacian(&mesh, alpha).unwrap();
        let largest = k.triplets().map(|(_, _, v)| v.abs()).fold(0.0, f64::max);
        let mut row_sums = vec![0.0; mesh.vertex_count()];
        for (i, j, v) in k.triplets() {
            assert_eq!(v, k.get(j, i), "K not symmetric at ({i}, {j})");
            row_sums[i] += v;
        }
        assert!(row_sums.iter().all(|s| s.abs() < 1e-13 * largest));
        let mut rng = SplitMix64::new(7);
        for _ in 0..20 {
            let x: Vec<f64> = (0..mesh.vertex_count())
                .map(|_| rng.uniform(-1.0, 1.0))
                .collect();
            let mut kx = vec![0.0; x.len()];
            k.mul_vec(&x, &mut kx).unwrap();
            assert!(dot3(&x, &kx) >= -1e-13 * largest * dot3(&x, &x));
        }
        // The spectrum: one zero (the constants of the one component), the rest positive.
        let result = spectrum(
            &mesh,
            &SpectrumOptions::new(Operator::AnisotropicLaplace { anisotropy: alpha }, 6),
        )
        .unwrap();
        assert_eq!(result.kernel.dimension, 1);
        assert_eq!(result.eigenvalues[0], 0.0);
        assert!(result.eigenvalues[1..].iter().all(|&v| v > 0.0));
    }
}

fn dot3(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[test]
fn curvature_is_exact_with_exact_normals() {
    // Cylinder of radius 1 with radial normals: κ = (1, 0), the first direction around the
    // axis, the second along it.
    let (segments, rings) = (10, 4);
    let mesh = cylinder(segments, rings, 2.0).unwrap();
    for principal in face_principal_curvatures(&mesh, &cylinder_normals(segments, rings)) {
        let [k1, k2] = principal.curvatures;
        assert!(
            (k1 - 1.0).abs() < 1e-12 && k2.abs() < 1e-12,
            "{principal:?}"
        );
        assert!(principal.directions[0][2].abs() < 1e-12, "{principal:?}");
        assert!((principal.directions[1][2].abs() - 1.0).abs() < 1e-12);
        assert!(dot(principal.directions[0], principal.directions[1]).abs() < 1e-12);
    }
    // Sphere of radius 2 with normals p/2: an umbilic everywhere, κ = (1/2, 1/2).
    let sphere = icosphere(2).scaled(2.0).unwrap();
    let normals: Vec<_> = sphere
        .positions()
        .iter()
        .map(|p| p.map(|c| c / 2.0))
        .collect();
    for principal in face_principal_curvatures(&sphere, &normals) {
        for kappa in principal.curvatures {
            assert!((kappa - 0.5).abs() < 1e-12, "{principal:?}");
        }
    }
}

/// `c · l(l+1)` with multiplicity `2l+1`.
fn sphere_exact(c: f64, k: usize) -> Vec<f64> {
    (0..)
        .flat_map(|l: usize| std::iter::repeat_n(c * (l * (l + 1)) as f64, 2 * l + 1))
        .take(k)
        .collect()
}

fn eigenvalues(mesh: &TriMesh, operator: Operator, k: usize) -> Vec<f64> {
    spectrum(mesh, &SpectrumOptions::new(operator, k))
        .unwrap()
        .eigenvalues
}

#[test]
fn on_a_sphere_the_spectrum_is_laplace_times_the_conductivity() {
    // Radius 1: both principal curvatures 1, H = ψ_α(1) I, so λ = ψ_α(1) l(l+1).
    let alpha = 0.5;
    let psi = conductivity(alpha, 1.0);
    let mesh = icosphere(4);
    let computed = eigenvalues(
        &mesh,
        Operator::AnisotropicLaplace { anisotropy: alpha },
        16,
    );
    let exact = sphere_exact(psi, 16);
    let laplace = eigenvalues(&mesh, Operator::Laplace, 16);
    let worst = |reference: &[f64]| {
        computed
            .iter()
            .zip(reference)
            .map(|(c, r)| (c - r).abs() / r.max(psi))
            .fold(0.0, f64::max)
    };
    let scaled_laplace: Vec<f64> = laplace.iter().map(|l| psi * l).collect();
    println!(
        "largest relative error: {} against the closed form, {} against ψ · discrete Laplace",
        worst(&exact),
        worst(&scaled_laplace)
    );
    for ((c, e), l) in computed.iter().zip(&exact).zip(&laplace) {
        // Closed form within the discretisation error of Laplace itself (0.36% at level 4,
        // docs/MATH.md), plus that of the curvature from area-weighted normals.
        assert!(
            (c - e).abs() <= 0.006 * e.max(psi),
            "{computed:?} vs {exact:?}"
        );
        // Against ψ times the discrete Laplace spectrum, only the curvature estimate differs.
        assert!(
            (c - psi * l).abs() <= 1e-3 * (psi * l).max(psi),
            "{c} vs ψ·{l}"
        );
    }
}

/// `(π m / h)² + ψ (n / r)²` for `r = 1`, `n = 0` once and `n ≥ 1` twice (cos and sin).
fn cylinder_exact(psi: f64, height: f64, k: usize) -> Vec<f64> {
    let mut values = Vec::new();
    for m in 0..20 {
        for n in 0..20usize {
            let value = (std::f64::consts::PI * m as f64 / height).powi(2) + psi * (n * n) as f64;
            values.extend(std::iter::repeat_n(value, if n == 0 { 1 } else { 2 }));
        }
    }
    values.sort_by(f64::total_cmp);
    values.truncate(k);
    values
}

#[test]
fn on_a_cylinder_the_spectrum_separates_along_and_around_the_axis() {
    // Radius 1, height π: conductivity ψ_α(0) = 1 along the axis, ψ_α(1) = 1/(1+α) around.
    let (alpha, height, k) = (1.0, std::f64::consts::PI, 12);
    let psi = conductivity(alpha, 1.0);
    let exact = cylinder_exact(psi, height, k);
    let error = |segments: usize| {
        let rings = segments / 2 + 1;
        let mesh = cylinder(segments, rings, height).unwrap();
        let computed = eigenvalues(&mesh, Operator::AnisotropicLaplace { anisotropy: alpha }, k);
        println!("{segments} segments: {computed:?}\n  exact {exact:?}");
        computed
            .iter()
            .zip(&exact)
            .map(|(c, e)| (c - e).abs() / e.max(psi))
            .fold(0.0, f64::max)
    };
    let (coarse, fine) = (error(32), error(64));
    println!("errors {coarse} (32 segments), {fine} (64 segments)");
    assert!(fine < 0.01, "error {fine} at 64 segments");
    assert!(
        coarse / fine > 2.5,
        "errors {coarse} then {fine}: not converging"
    );
    // The separation is the anisotropy's: Laplace's second eigenvalue is 1 (n = 1 or m = 1).
    assert!(exact[1] < 0.6);
}

#[test]
fn scaling_rescales_the_anisotropy() {
    // Curvatures scale as 1/s: at scale s with α the pencil is the unscaled one with α/s,
    // eigenvalues divided by s².
    let mesh = torus();
    let (alpha, s) = (3.0, 2.5);
    let scaled = eigenvalues(
        &mesh.scaled(s).unwrap(),
        Operator::AnisotropicLaplace { anisotropy: alpha },
        8,
    );
    let reference = eigenvalues(
        &mesh,
        Operator::AnisotropicLaplace {
            anisotropy: alpha / s,
        },
        8,
    );
    for (a, b) in scaled.iter().zip(&reference) {
        assert!(
            (a - b / (s * s)).abs() <= 1e-8 * (b / (s * s)).max(1e-3),
            "{a} vs {b}/s²"
        );
    }
}

#[test]
fn the_anisotropy_must_be_finite_and_nonnegative() {
    let mesh = icosphere(0);
    for alpha in [-0.5, f64::NAN, f64::INFINITY] {
        let result = spectrum(
            &mesh,
            &SpectrumOptions::new(Operator::AnisotropicLaplace { anisotropy: alpha }, 2),
        );
        assert!(
            matches!(
                result,
                Err(SpectrumError::InvalidParameter {
                    operator: "anisotropic-laplace",
                    parameter: Parameter::Anisotropy,
                    value,
                }) if value.to_bits() == alpha.to_bits()
            ),
            "{alpha}: {result:?}"
        );
    }
    assert_eq!(
        "anisotropic-laplace:-1".parse::<Operator>(),
        Err(ParseOperatorError::ParameterOutOfRange {
            name: "anisotropic-laplace",
            parameter: Parameter::Anisotropy,
            value: -1.0
        })
    );
    let missing = "anisotropic-laplace".parse::<Operator>().unwrap_err();
    assert_eq!(
        missing.to_string(),
        "operator anisotropic-laplace needs the anisotropy α: anisotropic-laplace:A with A in \
         [0, ∞), e.g. anisotropic-laplace:10"
    );
    assert_eq!(
        "anisotropic-laplace:2.5".parse::<Operator>(),
        Ok(Operator::AnisotropicLaplace { anisotropy: 2.5 })
    );
    assert_eq!(
        Operator::AnisotropicLaplace { anisotropy: 2.5 }.to_string(),
        "anisotropic-laplace:2.5"
    );
}
