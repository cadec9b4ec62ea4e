//! Test helpers shared by several test files of the `dirac` crate.

use dirac::TriMesh;
use dirac::generators::icosphere;
use proptest::prelude::*;

/// The level-`level` icosphere with each vertex moved radially by a factor in `[1−a, 1+a]`.
pub fn perturbed_sphere(level: u32, amplitude: f64) -> impl Strategy<Value = TriMesh> {
    let base = icosphere(level);
    let n = base.vertex_count();
    prop::collection::vec(-amplitude..amplitude, n).prop_map(move |bumps| {
        let positions = base
            .positions()
            .iter()
            .zip(&bumps)
            .map(|(p, b)| p.map(|c| c * (1.0 + b)))
            .collect();
        TriMesh::new(positions, base.faces().to_vec()).expect("a mildly perturbed sphere is valid")
    })
}
