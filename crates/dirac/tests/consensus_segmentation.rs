//! Consensus segmentation (`dirac::segmentation::consensus`): known answers on meshes split
//! into halves with separated descriptors, forced counts, determinism, and a property test that
//! labels are `0…S−1` with every segment connected, checked by an independent search over
//! faces that share two vertices.

use std::collections::HashMap;

use dirac::TriMesh;
use dirac::generators::{grid, icosphere};
use dirac::segmentation::consensus::{
    ConsensusOptions, ConsensusSegmentation, SegmentationError, consensus_segmentation,
};
use proptest::prelude::*;

/// Faces sharing an edge, found from the face list alone.
fn face_neighbours(mesh: &TriMesh) -> Vec<Vec<usize>> {
    let mut by_edge: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
    for (t, f) in mesh.faces().iter().enumerate() {
        for c in 0..3 {
            let (a, b) = (f[c], f[(c + 1) % 3]);
            by_edge.entry([a.min(b), a.max(b)]).or_default().push(t);
        }
    }
    let mut neighbours = vec![Vec::new(); mesh.face_count()];
    for faces in by_edge.values() {
        if let [s, t] = faces[..] {
            neighbours[s].push(t);
            neighbours[t].push(s);
        }
    }
    neighbours
}

/// Asserts labels `0…S−1`, each used, in order of first face, each segment connected, and the
/// areas their faces' sums.
fn assert_valid(mesh: &TriMesh, result: &ConsensusSegmentation) {
    let s = result.segment_count();
    assert_eq!(result.labels.len(), mesh.face_count());
    let mut next = 0;
    for &l in &result.labels {
        assert!(l < s, "label {l} ≥ {s}");
        assert!(l <= next, "labels are numbered by first face");
        next = next.max(l + 1);
    }
    assert_eq!(next, s, "every label is used");
    let neighbours = face_neighbours(mesh);
    let mut seen = vec![false; mesh.face_count()];
    for label in 0..s {
        let start = result.labels.iter().position(|&l| l == label).unwrap();
        let mut stack = vec![start];
        seen[start] = true;
        while let Some(t) = stack.pop() {
            for &u in &neighbours[t] {
                if !seen[u] && result.labels[u] == label {
                    seen[u] = true;
                    stack.push(u);
                }
            }
        }
        let reached = (0..mesh.face_count())
            .filter(|&t| result.labels[t] == label)
            .all(|t| seen[t]);
        assert!(reached, "segment {label} is not connected");
        let area: f64 = (0..mesh.face_count())
            .filter(|&t| result.labels[t] == label)
            .map(|t| mesh.face_area(t))
            .sum();
        assert!((area - result.areas[label]).abs() <= 1e-12 * area.max(1.0));
    }
}

/// A 12 × 8 grid on `[−1, 1] × [−1, 1]` and one descriptor row per face: `(0, 0)` on the left
/// half, `(10, 10)` on the right half, plus `slope · (y, 0)` (a gentle trend that random k-means
/// trials cut into bands at different places).
fn halves(slope: f64) -> (TriMesh, Vec<f64>, Vec<usize>) {
    let mesh = grid(12, 8, 2.0, 2.0).unwrap();
    let mut rows = Vec::new();
    let mut side = Vec::new();
    for f in mesh.faces() {
        let centroid =
            |axis: usize| f.iter().map(|&v| mesh.positions()[v][axis]).sum::<f64>() / 3.0;
        let right = centroid(0) > 0.0;
        let base = if right { 10.0 } else { 0.0 };
        rows.extend([base + slope * centroid(1), base]);
        side.push(usize::from(right));
    }
    (mesh, rows, side)
}

#[test]
fn constant_halves_give_two_segments_at_every_threshold() {
    let (mesh, rows, side) = halves(0.0);
    let options = ConsensusOptions::default();
    let result = consensus_segmentation(&mesh, &rows, 2, &options).unwrap();
    assert_valid(&mesh, &result);
    assert_eq!(result.segment_count(), 2);
    assert_eq!(
        result.labels, side,
        "face 0 is on the left, so the left half is 0"
    );
    // Every trial separates the halves and nothing else: one run over all thresholds.
    assert_eq!(result.levels.len(), options.trials);
    assert!(result.levels.iter().all(|l| l.segments == 2));
    assert_eq!(result.runs.len(), 1);
    assert_eq!((result.run().lowest, result.run().highest), (0.0, 1.0));
    assert_eq!(
        result.threshold,
        20.0 / 40.0,
        "the middle level ⌊(1 + 40)/2⌋ = 20"
    );
    assert!((result.areas[0] - 2.0).abs() < 1e-12 && (result.areas[1] - 2.0).abs() < 1e-12);
}

#[test]
fn halves_with_a_trend_inside_are_still_two_segments() {
    let (mesh, rows, side) = halves(1.0);
    let result = consensus_segmentation(&mesh, &rows, 2, &ConsensusOptions::default()).unwrap();
    assert_valid(&mesh, &result);
    assert_eq!(result.segment_count(), 2, "runs {:?}", result.runs);
    assert_eq!(result.labels, side);
    // The halves are cut into bands at high thresholds, so there is more than one run, and
    // the chosen one is the widest.
    assert!(result.runs.len() > 1);
    let widest = result
        .runs
        .iter()
        .map(|r| r.persistence())
        .fold(0.0, f64::max);
    assert_eq!(result.run().persistence(), widest);
}

#[test]
fn a_forced_count_is_honoured() {
    let (mesh, rows, side) = halves(1.0);
    for n in [1, 2, 3, 4, 6] {
        let options = ConsensusOptions {
            segments: Some(n),
            ..ConsensusOptions::default()
        };
        let result = consensus_segmentation(&mesh, &rows, 2, &options).unwrap();
        assert_valid(&mesh, &result);
        assert_eq!(result.segment_count(), n);
        assert!(result.forced);
        if n >= 2 {
            // Segments never straddle the halves, which no trial joins.
            for (t, &l) in result.labels.iter().enumerate() {
                let first = result.labels.iter().position(|&m| m == l).unwrap();
                assert_eq!(side[t], side[first], "segment {l} crosses the middle");
            }
        }
    }
    let too_many = ConsensusOptions {
        segments: Some(mesh.face_count() + 1),
        ..ConsensusOptions::default()
    };
    assert!(matches!(
        consensus_segmentation(&mesh, &rows, 2, &too_many),
        Err(SegmentationError::AboveConsensus { requested, .. }) if requested == mesh.face_count() + 1
    ));
}

#[test]
fn the_seed_determines_the_result() {
    let (mesh, rows, _) = halves(1.0);
    let options = ConsensusOptions {
        seed: 42,
        ..ConsensusOptions::default()
    };
    let a = consensus_segmentation(&mesh, &rows, 2, &options).unwrap();
    let b = consensus_segmentation(&mesh, &rows, 2, &options).unwrap();
    assert_eq!(a, b);
}

#[test]
fn separate_components_are_separate_segments() {
    // Two copies of a sphere side by side with equal descriptors: segments cannot span them.
    let sphere = icosphere(1);
    let n = sphere.vertex_count();
    let mut positions = sphere.positions().to_vec();
    positions.extend(sphere.positions().iter().map(|p| [p[0] + 3.0, p[1], p[2]]));
    let mut faces = sphere.faces().to_vec();
    faces.extend(sphere.faces().iter().map(|f| f.map(|v| v + n)));
    let mesh = TriMesh::new(positions, faces).unwrap();
    let rows = vec![1.0; mesh.face_count()];
    let result = consensus_segmentation(&mesh, &rows, 1, &ConsensusOptions::default()).unwrap();
    assert_valid(&mesh, &result);
    assert_eq!(result.segment_count(), 2);
    let one = ConsensusOptions {
        segments: Some(1),
        ..ConsensusOptions::default()
    };
    assert_eq!(
        consensus_segmentation(&mesh, &rows, 1, &one).unwrap_err(),
        SegmentationError::BelowComponents {
            requested: 1,
            components: 2
        }
    );
}

#[test]
fn bad_input_is_named() {
    let (mesh, rows, _) = halves(0.0);
    let run = |rows: &[f64], dimension, options: ConsensusOptions| {
        consensus_segmentation(&mesh, rows, dimension, &options).unwrap_err()
    };
    let default = ConsensusOptions::default();
    assert_eq!(
        run(&rows[1..], 2, default),
        SegmentationError::FaceRows {
            values: rows.len() - 1,
            dimension: 2,
            faces: mesh.face_count()
        }
    );
    let mut bad = rows.clone();
    bad[7] = f64::INFINITY;
    let message = run(&bad, 2, default).to_string();
    assert!(message.contains("point 3"), "{message}");
    for (min, max) in [(1, 5), (6, 5)] {
        let options = ConsensusOptions {
            min_clusters: min,
            max_clusters: max,
            ..default
        };
        assert_eq!(
            run(&rows, 2, options),
            SegmentationError::ClusterRange { min, max }
        );
    }
    let options = ConsensusOptions {
        min_area_fraction: 1.0,
        ..default
    };
    assert_eq!(run(&rows, 2, options), SegmentationError::AreaFraction(1.0));
    let options = ConsensusOptions {
        trials: 0,
        ..default
    };
    assert_eq!(run(&rows, 2, options), SegmentationError::NoTrials);
    let options = ConsensusOptions {
        segments: Some(0),
        ..default
    };
    assert_eq!(run(&rows, 2, options), SegmentationError::ZeroSegments);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn labels_are_dense_and_segments_connected(
        values in prop::collection::vec(-1.0..1.0f64, 80 * 3),
        trials in 1usize..12,
        min_clusters in 2usize..6,
        extra in 0usize..6,
        fraction in 0.0..0.3f64,
        segments in prop::option::of(1usize..12),
        seed in any::<u64>(),
    ) {
        let mesh = icosphere(1);
        let options = ConsensusOptions {
            trials,
            min_clusters,
            max_clusters: min_clusters + extra,
            min_area_fraction: fraction,
            segments,
            seed,
            ..ConsensusOptions::default()
        };
        match consensus_segmentation(&mesh, &values, 3, &options) {
            Ok(result) => {
                assert_valid(&mesh, &result);
                if let Some(n) = segments {
                    prop_assert_eq!(result.segment_count(), n);
                }
                prop_assert_eq!(result.levels.len(), trials);
            }
            Err(SegmentationError::AboveConsensus { requested, most }) => {
                prop_assert!(segments == Some(requested) && most < requested);
            }
            Err(other) => prop_assert!(false, "unexpected error {other}"),
        }
    }
}
