//! Heat-method geodesic distance against the exact great-circle distance on the unit sphere.

use dirac::generators::icosphere;
use dirac::well::{WellError, geodesic_distance};

/// Errors of the heat-method distance from the north pole (the vertex of largest `z`) against
/// the great-circle distance `arccos⟨s, p⟩`: `(Σ|d − d*| / Σ d*, mean of |d − d*| / d*, max |d − d*|)`.
/// The first is the "mean error" docs/MATH.md quotes (0.89% at level 4, "What the tests check
/// against").
fn sphere_errors(level: u32) -> (f64, f64, f64) {
    let mesh = icosphere(level);
    let p = mesh.positions();
    let source = (0..p.len())
        .max_by(|&a, &b| p[a][2].total_cmp(&p[b][2]))
        .unwrap();
    let distance = geodesic_distance(&mesh, &[source]).unwrap();
    let s = p[source];
    let (mut abs_sum, mut exact_sum, mut pointwise_sum, mut count, mut max_abs) =
        (0.0, 0.0, 0.0, 0, 0.0f64);
    for (q, d) in p.iter().zip(&distance) {
        let exact = (s[0] * q[0] + s[1] * q[1] + s[2] * q[2])
            .clamp(-1.0, 1.0)
            .acos();
        let error = (d - exact).abs();
        max_abs = max_abs.max(error);
        abs_sum += error;
        exact_sum += exact;
        if exact > 1e-9 {
            pointwise_sum += error / exact;
            count += 1;
        }
    }
    (abs_sum / exact_sum, pointwise_sum / count as f64, max_abs)
}

#[test]
fn unit_sphere_distance_within_one_percent_at_level_four() {
    let (relative, pointwise, max_abs) = sphere_errors(4);
    println!("level 4: Σ|err|/Σd* {relative:.4}, pointwise mean {pointwise:.4}, max {max_abs:.4}");
    assert!(relative < 0.01, "mean relative error {relative}");
    // Pointwise relative errors are largest next to the source, where d* is small.
    assert!(
        pointwise < 0.015,
        "pointwise mean relative error {pointwise}"
    );
    assert!(max_abs < 0.05, "max abs error {max_abs}");
}

#[test]
fn distance_error_falls_under_refinement() {
    let (coarse, _, _) = sphere_errors(2);
    let (fine, _, _) = sphere_errors(4);
    assert!(fine < 0.5 * coarse, "level 2: {coarse}, level 4: {fine}");
}

#[test]
fn bad_sources_are_errors() {
    let mesh = icosphere(1);
    assert_eq!(geodesic_distance(&mesh, &[]), Err(WellError::NoSource));
    assert_eq!(
        geodesic_distance(&mesh, &[42]),
        Err(WellError::SourceOutOfRange {
            vertex: 42,
            vertex_count: 42
        })
    );
}
