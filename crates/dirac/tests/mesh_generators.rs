//! Generators produce valid meshes with the documented counts, on the documented surfaces,
//! oriented outward, deterministically for a seed; invalid parameters are typed errors.

use std::collections::HashSet;
use std::f64::consts::PI;

use dirac::TriMesh;
use dirac::generators::{
    Detail, GeneratorError, RandomTessellation, SpherePatch, Torus, cylinder, cylinder_normals,
    grid, icosphere, subdivided_cube,
};
use proptest::prelude::*;

/// `Σ_t p_i · (p_j × p_k) / 6`: the enclosed volume of a closed mesh, positive when the faces
/// are counter-clockwise seen from outside.
fn signed_volume(mesh: &TriMesh) -> f64 {
    let p = mesh.positions();
    mesh.faces()
        .iter()
        .map(|&[i, j, k]| {
            let (a, b, c) = (p[i], p[j], p[k]);
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum()
}

/// Unnormalized normal `(p_j − p_i) × (p_k − p_i)` and centroid of each face.
fn normals_and_centroids(mesh: &TriMesh) -> Vec<([f64; 3], [f64; 3])> {
    let p = mesh.positions();
    mesh.faces()
        .iter()
        .map(|&[i, j, k]| {
            let (a, b, c) = (p[i], p[j], p[k]);
            let (u, v) = (
                [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
            );
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let centroid = [0, 1, 2].map(|d| (a[d] + b[d] + c[d]) / 3.0);
            (n, centroid)
        })
        .collect()
}

fn total_area(mesh: &TriMesh) -> f64 {
    (0..mesh.face_count()).map(|t| mesh.face_area(t)).sum()
}

#[test]
fn icosphere_counts_and_radius() {
    for level in 0..4 {
        let mesh = icosphere(level);
        assert_eq!(mesh.vertex_count(), 10 * 4usize.pow(level) + 2);
        assert_eq!(mesh.face_count(), 20 * 4usize.pow(level));
        for p in mesh.positions() {
            assert!(((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0).abs() < 1e-14);
        }
    }
    let v = signed_volume(&icosphere(4));
    assert!(v > 0.0 && (v - 4.0 * PI / 3.0).abs() < 0.01 * 4.0 * PI / 3.0);
}

#[test]
fn torus_lies_on_its_surface_and_encloses_its_volume() {
    let (big_r, r) = (3.0, 1.0);
    let mesh = Torus::new(big_r, r, 64, 32).mesh().unwrap();
    assert_eq!(
        (mesh.vertex_count(), mesh.face_count()),
        (64 * 32, 2 * 64 * 32)
    );
    for p in mesh.positions() {
        let rho = p[0].hypot(p[1]);
        assert!(((rho - big_r).powi(2) + p[2] * p[2] - r * r).abs() < 1e-12);
    }
    let exact = 2.0 * PI * PI * big_r * r * r;
    let v = signed_volume(&mesh);
    assert!(
        v > 0.0 && (v - exact).abs() < 0.01 * exact,
        "{v} vs {exact}"
    );
}

#[test]
fn bumps_displace_along_the_normal() {
    let (big_r, r, h) = (3.0, 1.0, 0.2);
    let mut torus = Torus::new(big_r, r, 40, 20);
    torus.detail = Detail::Bumps {
        amplitude: h,
        frequency: [5, 3],
    };
    for p in torus.mesh().unwrap().positions() {
        let rho = p[0].hypot(p[1]);
        let (u, v) = (p[1].atan2(p[0]), p[2].atan2(rho - big_r));
        let d = (rho - big_r).hypot(p[2]);
        assert!((d - (r + h * (5.0 * u).cos() * (3.0 * v).cos())).abs() < 1e-12);
    }
}

#[test]
fn every_detail_at_two_amplitudes_gives_a_valid_torus() {
    for amplitude in [0.05, 0.2] {
        for detail in [
            Detail::Bumps {
                amplitude,
                frequency: [6, 3],
            },
            Detail::Ridges {
                amplitude,
                frequency: 8,
            },
            Detail::Noise { amplitude, seed: 7 },
        ] {
            let mut torus = Torus::new(3.0, 1.0, 48, 24);
            torus.detail = detail;
            let mesh = torus.mesh().unwrap();
            assert_eq!(mesh.topology().genus(), 1);
            // The tube radius moves by at most the amplitude.
            for p in mesh.positions() {
                let d = (p[0].hypot(p[1]) - 3.0).hypot(p[2]);
                assert!((d - 1.0).abs() <= amplitude + 1e-12, "{detail:?}");
            }
        }
    }
}

#[test]
fn random_tessellations_are_deterministic_and_distinct() {
    let torus = |seed| {
        let mut t = Torus::new(3.0, 1.0, 32, 16);
        t.tessellation = Some(RandomTessellation { jitter: 0.25, seed });
        t.mesh().unwrap()
    };
    assert_eq!(torus(1), torus(1));
    assert_ne!(torus(1).positions(), torus(2).positions());
    assert_ne!(torus(1).faces(), torus(2).faces());
    // Jittered vertices stay on the smooth torus, and the faces still point outward.
    let mesh = torus(3);
    for p in mesh.positions() {
        assert!(((p[0].hypot(p[1]) - 3.0).powi(2) + p[2] * p[2] - 1.0).abs() < 1e-12);
    }
    assert!(signed_volume(&mesh) > 0.0);
}

#[test]
fn invalid_torus_parameters_are_typed_errors() {
    let bad = |t: Torus| matches!(t.mesh(), Err(GeneratorError::InvalidParameter { .. }));
    assert!(bad(Torus::new(1.0, 1.0, 8, 8)));
    assert!(bad(Torus::new(3.0, 1.0, 2, 8)));
    assert!(bad(Torus::new(3.0, f64::NAN, 8, 8)));
    let mut t = Torus::new(3.0, 1.0, 8, 8);
    t.tessellation = Some(RandomTessellation {
        jitter: 0.3,
        seed: 0,
    });
    assert!(bad(t));
    let mut t = Torus::new(3.0, 1.0, 8, 8);
    t.detail = Detail::Noise {
        amplitude: 1.5,
        seed: 0,
    };
    assert!(bad(t));
}

#[test]
fn cylinder_counts_positions_and_exact_normals() {
    let (n, rings, height) = (24, 10, 4.5);
    let mesh = cylinder(n, rings, height).unwrap();
    assert_eq!(mesh.vertex_count(), n * rings);
    assert_eq!(mesh.face_count(), 2 * n * (rings - 1));
    let normals = cylinder_normals(n, rings);
    assert_eq!(normals.len(), mesh.vertex_count());
    for (v, (p, nv)) in mesh.positions().iter().zip(&normals).enumerate() {
        assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15);
        assert!((p[2] - height * (v / n) as f64 / (rings - 1) as f64).abs() < 1e-15);
        // The exact normal is the unit radial direction (x, y, 0) of the vertex.
        assert_eq!(nv[2], 0.0);
        assert!((nv[0] - p[0]).abs() < 1e-15 && (nv[1] - p[1]).abs() < 1e-15);
    }
    // Rings are aligned in angle.
    for v in n..mesh.vertex_count() {
        assert_eq!(mesh.positions()[v][..2], mesh.positions()[v % n][..2]);
    }
    for (normal, c) in normals_and_centroids(&mesh) {
        assert!(
            normal[0] * c[0] + normal[1] * c[1] > 0.0,
            "faces point outward"
        );
    }
    assert!(cylinder(2, 3, 1.0).is_err() && cylinder(5, 1, 1.0).is_err());
}

#[test]
fn subdivided_cube_counts_surface_and_orientation() {
    for n in 1..5 {
        let mesh = subdivided_cube(n).unwrap();
        assert_eq!(mesh.vertex_count(), 6 * n * n + 2);
        assert_eq!(mesh.face_count(), 12 * n * n);
        for p in mesh.positions() {
            let m = p.iter().fold(0.0f64, |m, c| m.max(c.abs()));
            assert_eq!(m, 1.0);
        }
        assert!((total_area(&mesh) - 24.0).abs() < 1e-12);
        assert!((signed_volume(&mesh) - 8.0).abs() < 1e-12);
        for (normal, c) in normals_and_centroids(&mesh) {
            assert!(normal.iter().zip(c).map(|(a, b)| a * b).sum::<f64>() > 0.0);
        }
    }
    assert!(subdivided_cube(0).is_err());
}

#[test]
fn flat_grid_counts_area_and_normal() {
    let mesh = grid(4, 3, 2.0, 1.5).unwrap();
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (20, 24));
    assert!((total_area(&mesh) - 3.0).abs() < 1e-14);
    for (normal, _) in normals_and_centroids(&mesh) {
        assert!(normal[0] == 0.0 && normal[1] == 0.0 && normal[2] > 0.0);
    }
    assert!(grid(0, 3, 1.0, 1.0).is_err() && grid(2, 2, -1.0, 1.0).is_err());
}

/// Geodesic distance on the unit sphere from `c` to the direction of `p`.
fn angle(c: [f64; 3], p: [f64; 3]) -> f64 {
    let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    ((c[0] * p[0] + c[1] * p[1] + c[2] * p[2]) / n)
        .clamp(-1.0, 1.0)
        .acos()
}

/// Faces as sets of position bit patterns, so meshes with different numbering compare.
fn face_keys(mesh: &TriMesh, keep: impl Fn([f64; 3]) -> bool) -> HashSet<[[u64; 3]; 3]> {
    normals_and_centroids(mesh)
        .iter()
        .zip(mesh.faces())
        .filter(|((_, c), _)| keep(*c))
        .map(|(_, f)| {
            let mut k = f.map(|v| mesh.positions()[v].map(f64::to_bits));
            k.sort();
            k
        })
        .collect()
}

#[test]
fn sphere_patches_share_their_interior_and_differ_at_the_boundary() {
    let center = [0.0, 0.0, 1.0];
    let radius = 0.6;
    let patch = |seed, bump_amplitude| {
        SpherePatch {
            level: 4,
            center,
            radius,
            raggedness: 0.3,
            bump_amplitude,
            seed,
        }
        .mesh()
        .unwrap()
    };
    // Every face of the icosphere with centroid within `radius` of the centre (independent
    // of the patch code).
    let interior = face_keys(&icosphere(4), |c| angle(center, c) < radius);
    assert!(interior.len() > 100);
    let mut boundaries = HashSet::new();
    for seed in 0..4 {
        let mesh = patch(seed, 0.0);
        let t = mesh.topology();
        assert_eq!(t.components.len(), 1);
        assert_eq!(t.boundary_loops.len(), 1);
        assert_eq!(t.genus(), 0);
        assert!(face_keys(&mesh, |_| true).is_superset(&interior));
        assert!(
            mesh.positions()
                .iter()
                .all(|&p| angle(center, p) < radius + 0.3 + 0.1)
        );
        boundaries.insert(t.boundary_loops[0].len());
    }
    assert!(
        boundaries.len() > 1,
        "ragged boundaries differ between seeds"
    );
    let bumpy = patch(1, 0.1).topology();
    assert_eq!((bumpy.boundary_loops.len(), bumpy.genus()), (1, 0));
    assert_eq!(patch(5, 0.1), patch(5, 0.1));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Any seed and jitter gives a valid, outward, genus-1 torus with the documented counts.
    #[test]
    fn random_tessellations_are_valid(seed in any::<u64>(), jitter in 0.0..=0.25f64) {
        let mut t = Torus::new(2.0, 0.7, 20, 12);
        t.detail = Detail::Noise { amplitude: 0.1, seed };
        t.tessellation = Some(RandomTessellation { jitter, seed });
        let mesh = t.mesh().unwrap();
        prop_assert_eq!((mesh.vertex_count(), mesh.face_count()), (240, 480));
        prop_assert_eq!(mesh.topology().genus(), 1);
        prop_assert!(signed_volume(&mesh) > 0.0);
    }

    /// Ragged sphere patches around any centre are single disks.
    #[test]
    fn sphere_patches_are_disks(seed in any::<u64>(), c in prop::array::uniform3(-1.0..1.0f64)) {
        prop_assume!(c.iter().map(|x| x * x).sum::<f64>() > 0.01);
        let t = SpherePatch { level: 3, center: c, radius: 0.5, raggedness: 0.5, bump_amplitude: 0.0, seed }
            .mesh()
            .unwrap()
            .topology();
        prop_assert_eq!(t.components.len(), 1);
        prop_assert_eq!(t.boundary_loops.len(), 1);
        prop_assert_eq!(t.genus(), 0);
    }
}
