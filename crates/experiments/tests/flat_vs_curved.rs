//! Experiment 4 at reduced size: `D_N` on a subdivided cube has a kernel of at least
//! `6 (n − 3)² + 1` (every function supported at a vertex whose neighbours share one normal,
//! plus the constants), while on a sphere only the constants are in its kernel and its
//! smallest nonzero `|λ|` is near `4π` at unit area.

use dirac::generators::{icosphere, subdivided_cube};
use experiments::flat_vs_curved::kernel_counts;

#[test]
fn cube_has_a_large_kernel_and_sphere_only_the_constants() {
    for n in [4usize, 6] {
        let counts = kernel_counts(&subdivided_cube(n).unwrap()).unwrap();
        println!("cube {n}: {counts:?}");
        let flat_vertices = 6 * (n - 3) * (n - 3);
        assert!(counts.kernel > flat_vertices, "{counts:?}");
        assert!(counts.kernel >= counts.flat_bound);
    }
    let sphere = kernel_counts(&icosphere(2)).unwrap();
    println!("sphere: {sphere:?}");
    assert_eq!(sphere.kernel, 1);
    assert_eq!(sphere.small, 0);
    let four_pi = 4.0 * std::f64::consts::PI;
    assert!((sphere.smallest_nonzero - four_pi).abs() < 0.05 * four_pi);
}
