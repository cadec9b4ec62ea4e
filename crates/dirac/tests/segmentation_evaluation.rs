//! The benchmark's measures against truths computed by hand (in the comments), closed forms,
//! an O(N²) Rand index over all pairs, and their algebraic properties (symmetry, refinements,
//! renaming); and, when `../shared/meshes/psb` is present (the repository does not carry it;
//! without it the test says so on stderr and checks nothing), human against human
//! segmentations of the 19 benchmark models.

use std::path::PathBuf;

use dirac::TriMesh;
use dirac::generators::{cylinder, grid, icosphere};
use dirac::io::read_mesh;
use dirac::segmentation::evaluation::{
    EvaluationError, SegmentationEvaluator, SegmentationRole, consistency_errors, rand_index_error,
};
use dirac::segmentation::seg_file::read_seg_file;

fn close(a: f64, b: f64, tolerance: f64) -> bool {
    (a - b).abs() <= tolerance
}

/// Three unit squares `[−1.5, 1.5] × [−0.5, 0.5]` in a row, two triangles each: faces
/// `2i, 2i + 1` form square `i`; all six have area ½.
fn strip() -> TriMesh {
    grid(3, 1, 3.0, 1.0).unwrap()
}

/// Squares `[0, 1] × [0, 1]` (faces 0, 1, area ½ each) and `[1, 3] × [0, 1]` (faces 2, 3,
/// area 1 each).
fn uneven_strip() -> TriMesh {
    let positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [3.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [3.0, 1.0, 0.0],
    ];
    TriMesh::new(positions, vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]]).unwrap()
}

/// A fixed pseudo-random sequence (64-bit LCG) in `0..modulus`.
fn pseudo_random_labels(count: usize, modulus: u64, seed: u64) -> Vec<usize> {
    let mut state = seed;
    (0..count)
        .map(|_| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) % modulus) as usize
        })
        .collect()
}

/// `1 − RI` by definition: the fraction of the `C(N, 2)` pairs of faces together in one
/// segmentation and apart in the other.
fn rand_index_error_over_all_pairs(a: &[usize], b: &[usize]) -> f64 {
    let n = a.len();
    let mut disagreeing = 0;
    for p in 0..n {
        for q in p + 1..n {
            if (a[p] == a[q]) != (b[p] == b[q]) {
                disagreeing += 1;
            }
        }
    }
    disagreeing as f64 / (n * (n - 1) / 2) as f64
}

#[test]
fn identical_segmentations_score_zero_on_every_measure() {
    let mesh = icosphere(2);
    let evaluator = SegmentationEvaluator::new(&mesh).unwrap();
    let labels = pseudo_random_labels(mesh.face_count(), 7, 1);
    let scores = evaluator.scores(&labels, &labels).unwrap();
    assert_eq!(scores.cut_discrepancy, Some(0.0));
    assert!(scores.hamming.distance.abs() < 1e-14, "{scores:?}");
    assert!(scores.hamming.missing_rate.abs() < 1e-14);
    assert!(scores.hamming.false_alarm_rate.abs() < 1e-14);
    assert_eq!(scores.rand_index_error, 0.0);
    assert_eq!(scores.consistency.global, 0.0);
    assert_eq!(scores.consistency.local, 0.0);
}

#[test]
fn hand_computed_strip_case() {
    // S₁ = squares {0, 1} | {2}, S₂ = {0} | {1, 2}; six faces of area ½.
    let s1 = [0, 0, 0, 0, 1, 1];
    let s2 = [0, 0, 1, 1, 1, 1];
    // Cells n_00 = 2, n_01 = 2, n_11 = 2; a = (4, 2), b = (2, 4).
    // Rand: ΣC(a,2) = 6 + 1, ΣC(b,2) = 1 + 6, ΣC(n,2) = 3; (7 + 7 − 6) / C(6,2) = 8/15.
    assert!(close(
        rand_index_error(&s1, &s2).unwrap(),
        8.0 / 15.0,
        1e-15
    ));
    assert!(close(
        rand_index_error_over_all_pairs(&s1, &s2),
        8.0 / 15.0,
        1e-15
    ));
    // E₁₂ per cell: 1 − 2/4, 1 − 2/4, 1 − 2/2 → Σ n E₁₂ = 1 + 1 + 0 = 2;
    // E₂₁: 1 − 2/2, 1 − 2/4, 1 − 2/4 → Σ n E₂₁ = 0 + 1 + 1 = 2. GCE = 2/6.
    // LCE: Σ n min = 2·0 + 2·½ + 2·0 = 1 → 1/6.
    let ce = consistency_errors(&s1, &s2).unwrap();
    assert!(close(ce.global, 1.0 / 3.0, 1e-15), "{ce:?}");
    assert!(close(ce.local, 1.0 / 6.0, 1e-15), "{ce:?}");
    // Areas w_00 = w_01 = w_11 = 1, A = 3: Rm = (3 − (1 + 1))/3, Rf = (3 − (1 + 1))/3.
    let mesh = strip();
    let evaluator = SegmentationEvaluator::new(&mesh).unwrap();
    let hd = evaluator.hamming_distance(&s1, &s2).unwrap();
    assert!(close(hd.missing_rate, 1.0 / 3.0, 1e-15), "{hd:?}");
    assert!(close(hd.false_alarm_rate, 1.0 / 3.0, 1e-15), "{hd:?}");
    assert!(close(hd.distance, 1.0 / 3.0, 1e-15), "{hd:?}");
    // Cuts: S₁ at x = 0.5, S₂ at x = −0.5 (two vertices each), 1 apart along the horizontal
    // edges. Face centroids (x₀ + 2/3, −1/6) and (x₀ + 1/3, 1/6) for x₀ = −1.5, −0.5, 0.5,
    // centroid 0: R̄ = (√26 + √50 + √2)/18, so CD = 1/R̄ = 18/(√26 + √50 + √2).
    let mean_radius = (26f64.sqrt() + 50f64.sqrt() + 2f64.sqrt()) / 18.0;
    assert!(close(evaluator.mean_radius(), mean_radius, 1e-14));
    let cd = evaluator.cut_discrepancy(&s1, &s2).unwrap().unwrap();
    assert!(close(cd, 1.0 / mean_radius, 1e-13), "{cd}");
}

#[test]
fn hamming_distance_weights_faces_by_area() {
    // Faces of area ½, ½, 1, 1 (A = 3); S₁ = {0} | {1, 2, 3}, S₂ = {0, 1, 2} | {3}.
    // w_00 = ½ (face 0), w_10 = 1.5 (faces 1, 2), w_11 = 1 (face 3).
    // Rm = (3 − (max(½, 1.5) + 1))/3 = 1/6, Rf = (3 − (½ + max(1.5, 1)))/3 = 1/3, HD = 1/4.
    // (Counting faces instead would give Rm = Rf = 1/4.)
    let mesh = uneven_strip();
    let evaluator = SegmentationEvaluator::new(&mesh).unwrap();
    let hd = evaluator
        .hamming_distance(&[0, 1, 1, 1], &[0, 0, 0, 1])
        .unwrap();
    assert!(close(hd.missing_rate, 1.0 / 6.0, 1e-15), "{hd:?}");
    assert!(close(hd.false_alarm_rate, 1.0 / 3.0, 1e-15), "{hd:?}");
    assert!(close(hd.distance, 0.25, 1e-15), "{hd:?}");
}

#[test]
fn one_segment_against_a_refinement() {
    // S₁ one segment, S₂ = {0} | {1, 2} on the strip.
    let one = [0; 6];
    let s2 = [0, 0, 1, 1, 1, 1];
    // S₂ refines S₁: E(S₂, S₁, p) = 0 for every face, so GCE = LCE = 0.
    let ce = consistency_errors(&one, &s2).unwrap();
    assert_eq!((ce.global, ce.local), (0.0, 0.0));
    // Rand: ΣC(a,2) = 15, ΣC(b,2) = 1 + 6, ΣC(n,2) = 1 + 6: (15 + 7 − 14)/15 = 8/15.
    assert!(close(
        rand_index_error(&one, &s2).unwrap(),
        8.0 / 15.0,
        1e-15
    ));
    // w_00 = 1, w_01 = 2: Rm = (3 − (1 + 2))/3 = 0, Rf = (3 − 2)/3 = 1/3.
    let evaluator = SegmentationEvaluator::new(&strip()).unwrap();
    let scores = evaluator.scores(&one, &s2).unwrap();
    assert!(close(scores.hamming.missing_rate, 0.0, 1e-15));
    assert!(close(scores.hamming.false_alarm_rate, 1.0 / 3.0, 1e-15));
    // No cut in S₁: the Cut Discrepancy is undefined.
    assert_eq!(scores.cut_discrepancy, None);

    // One segment against every face its own: every pair disagrees; GCE = LCE = 0.
    let mesh = icosphere(1);
    let n = mesh.face_count();
    let singletons: Vec<usize> = (0..n).collect();
    assert_eq!(rand_index_error(&vec![0; n], &singletons).unwrap(), 1.0);
    let ce = consistency_errors(&vec![0; n], &singletons).unwrap();
    assert_eq!((ce.global, ce.local), (0.0, 0.0));
}

#[test]
fn consistency_errors_vanish_for_every_refinement_and_not_otherwise() {
    let n = icosphere(2).face_count();
    let coarse = pseudo_random_labels(n, 4, 3);
    // Refine: split each coarse segment by a second labelling.
    let split = pseudo_random_labels(n, 3, 4);
    let fine: Vec<usize> = coarse.iter().zip(&split).map(|(c, s)| 3 * c + s).collect();
    for (a, b) in [(&coarse, &fine), (&fine, &coarse)] {
        let ce = consistency_errors(a, b).unwrap();
        assert!(ce.global.abs() < 1e-15 && ce.local.abs() < 1e-15, "{ce:?}");
    }
    // Two unrelated labellings: neither refines the other, GCE ≥ LCE > 0.
    let ce = consistency_errors(&coarse, &split).unwrap();
    assert!(ce.local > 0.1 && ce.global >= ce.local, "{ce:?}");
}

#[test]
fn rand_index_from_the_contingency_table_equals_the_count_over_all_pairs() {
    let mesh = icosphere(2); // 320 faces, 51040 pairs
    let n = mesh.face_count();
    for (k1, k2, seed) in [(2, 2, 5), (5, 3, 6), (9, 17, 7), (1, 4, 8)] {
        let a = pseudo_random_labels(n, k1, seed);
        let b = pseudo_random_labels(n, k2, seed + 100);
        let fast = rand_index_error(&a, &b).unwrap();
        let slow = rand_index_error_over_all_pairs(&a, &b);
        assert!(close(fast, slow, 1e-14), "{k1} {k2}: {fast} vs {slow}");
    }
}

#[test]
fn symmetric_measures_are_symmetric_and_the_hamming_rates_swap() {
    let mesh = icosphere(2);
    let evaluator = SegmentationEvaluator::new(&mesh).unwrap();
    let a = pseudo_random_labels(mesh.face_count(), 3, 9);
    let b = pseudo_random_labels(mesh.face_count(), 5, 10);
    let ab = evaluator.scores(&a, &b).unwrap();
    let ba = evaluator.scores(&b, &a).unwrap();
    assert_eq!(ab.rand_index_error, ba.rand_index_error);
    assert!(close(ab.consistency.global, ba.consistency.global, 1e-14));
    assert!(close(ab.consistency.local, ba.consistency.local, 1e-14));
    assert!(close(ab.hamming.distance, ba.hamming.distance, 1e-14));
    assert!(close(
        ab.hamming.missing_rate,
        ba.hamming.false_alarm_rate,
        1e-14
    ));
    assert!(close(
        ab.hamming.false_alarm_rate,
        ba.hamming.missing_rate,
        1e-14
    ));
    let (cd_ab, cd_ba) = (ab.cut_discrepancy.unwrap(), ba.cut_discrepancy.unwrap());
    assert!(close(cd_ab, cd_ba, 1e-14), "{cd_ab} {cd_ba}");
}

#[test]
fn renaming_segments_changes_no_score() {
    let mesh = icosphere(2);
    let evaluator = SegmentationEvaluator::new(&mesh).unwrap();
    let a = pseudo_random_labels(mesh.face_count(), 4, 11);
    let b = pseudo_random_labels(mesh.face_count(), 6, 12);
    // Non-contiguous, reordered names for the same partition.
    let renamed: Vec<usize> = a.iter().map(|&l| 1000 - 7 * l).collect();
    assert_eq!(
        evaluator.scores(&a, &b).unwrap(),
        evaluator.scores(&renamed, &b).unwrap()
    );
}

#[test]
fn cut_discrepancy_of_two_rings_on_a_cylinder_is_their_distance_over_the_mean_radius() {
    // Radius 1, height H = 4, rings every 0.1; cuts at z = 1 and z = 2.5.
    let height = 4.0;
    let mesh = cylinder(64, 41, height).unwrap();
    let evaluator = SegmentationEvaluator::new(&mesh).unwrap();
    let below = |cut: f64| -> Vec<usize> {
        mesh.faces()
            .iter()
            .map(|f| {
                let z = f.iter().map(|&v| mesh.positions()[v][2]).sum::<f64>() / 3.0;
                usize::from(z > cut)
            })
            .collect()
    };
    let cd = evaluator
        .cut_discrepancy(&below(1.0), &below(2.5))
        .unwrap()
        .unwrap();
    // Every cut vertex is 1.5 from the other ring along the vertical edges, and no edge path
    // is shorter, so the edge-graph distance is exact here.
    assert!(close(cd * evaluator.mean_radius(), 1.5, 1e-12), "{cd}");
    // R̄ of the smooth cylinder: (1/H) ∫₀^H √(1 + (z − H/2)²) dz
    //   = (1/H) [u √(1 + u²) + asinh u] at u = H/2.
    let u: f64 = height / 2.0;
    let smooth_radius = (u * (1.0 + u * u).sqrt() + u.asinh()) / height;
    assert!(
        close(evaluator.mean_radius(), smooth_radius, 1e-2 * smooth_radius),
        "{} vs {smooth_radius}",
        evaluator.mean_radius()
    );
    assert!(close(cd, 1.5 / smooth_radius, 1e-2 * cd), "{cd}");
}

#[test]
fn the_model_score_is_the_mean_over_the_references() {
    let evaluator = SegmentationEvaluator::new(&strip()).unwrap();
    let computed = [0, 0, 0, 0, 1, 1];
    let references = [vec![0, 0, 1, 1, 1, 1], computed.to_vec(), vec![0; 6]];
    let model = evaluator
        .scores_against_references(&computed, &references)
        .unwrap();
    assert_eq!(model.per_reference.len(), 3);
    for (scores, reference) in model.per_reference.iter().zip(&references) {
        assert_eq!(*scores, evaluator.scores(&computed, reference).unwrap());
    }
    // Rand: 8/15 (hand case), 0 (identical), and against one segment
    // (ΣC(a,2) = 7, ΣC(b,2) = 15, ΣC(n,2) = 7: (7 + 15 − 14)/15 = 8/15): mean 16/45.
    assert!(close(model.mean.rand_index_error, 16.0 / 45.0, 1e-15));
    // Cut Discrepancy: defined against the first two only (the third has no cut).
    assert_eq!(model.cut_discrepancy_references, 2);
    let first = model.per_reference[0].cut_discrepancy.unwrap();
    assert!(close(
        model.mean.cut_discrepancy.unwrap(),
        first / 2.0,
        1e-15
    ));
}

#[test]
fn mismatched_or_missing_input_is_a_typed_error() {
    let evaluator = SegmentationEvaluator::new(&strip()).unwrap();
    let error = evaluator.scores(&[0; 5], &[0; 6]).unwrap_err();
    assert_eq!(
        error,
        EvaluationError::LabelCount {
            segmentation: SegmentationRole::Computed,
            labels: 5,
            faces: 6
        }
    );
    assert!(
        error.to_string().contains("5 labels for 6 faces"),
        "{error}"
    );
    let error = evaluator
        .scores_against_references(&[0; 6], &[vec![0; 6], vec![0; 7]])
        .unwrap_err();
    assert_eq!(
        error,
        EvaluationError::LabelCount {
            segmentation: SegmentationRole::Reference(1),
            labels: 7,
            faces: 6
        }
    );
    assert!(
        error
            .to_string()
            .starts_with("reference segmentation 1 has 7 labels")
    );
    let none: [Vec<usize>; 0] = [];
    assert_eq!(
        evaluator.scores_against_references(&[0; 6], &none),
        Err(EvaluationError::NoReferences)
    );
    assert_eq!(
        rand_index_error(&[0], &[0]),
        Err(EvaluationError::TooFewFaces { faces: 1 })
    );
    assert!(matches!(
        consistency_errors(&[0, 1], &[0, 1, 1]),
        Err(EvaluationError::LabelCount {
            labels: 3,
            faces: 2,
            ..
        })
    ));
}

#[test]
fn human_segmentations_of_the_benchmark_models_agree_as_the_paper_reports() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes/psb");
    if !dir.is_dir() {
        eprintln!("{} is absent: nothing checked", dir.display());
        return;
    }
    // Each human segmentation scored against the model's other humans (the per-model score),
    // averaged over the humans, then over the models.
    let mut sums = [0.0; 7];
    let (mut models, mut cd_models) = (0, 0);
    let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "off"))
        .collect();
    names.sort();
    for mesh_path in names {
        let mesh = read_mesh(&mesh_path).unwrap();
        let evaluator = SegmentationEvaluator::new(&mesh).unwrap();
        let stem = mesh_path.file_stem().unwrap().to_str().unwrap().to_string();
        let humans: Vec<Vec<usize>> = (0..)
            .map(|j| dir.join("seg").join(format!("{stem}_{j}.seg")))
            .take_while(|p| p.is_file())
            .map(|p| read_seg_file(p, mesh.face_count()).unwrap())
            .collect();
        let mut model = [0.0; 7];
        let (mut cd_sum, mut cd_count) = (0.0, 0);
        for (j, human) in humans.iter().enumerate() {
            let others: Vec<&[usize]> = humans
                .iter()
                .enumerate()
                .filter(|&(k, _)| k != j)
                .map(|(_, h)| h.as_slice())
                .collect();
            let m = evaluator
                .scores_against_references(human, &others)
                .unwrap()
                .mean;
            if let Some(cd) = m.cut_discrepancy {
                cd_sum += cd;
                cd_count += 1;
            }
            let values = [
                0.0,
                m.hamming.distance,
                m.hamming.missing_rate,
                m.hamming.false_alarm_rate,
                m.rand_index_error,
                m.consistency.global,
                m.consistency.local,
            ];
            for (s, v) in model.iter_mut().zip(values) {
                *s += v / humans.len() as f64;
            }
        }
        if cd_count > 0 {
            sums[0] += cd_sum / cd_count as f64;
            cd_models += 1;
        }
        for k in 1..7 {
            sums[k] += model[k];
        }
        models += 1;
        eprintln!(
            "{stem}: {} humans, CD {:.3} HD {:.3} RI {:.3} GCE {:.3} LCE {:.3}",
            humans.len(),
            cd_sum / cd_count.max(1) as f64,
            model[1],
            model[4],
            model[5],
            model[6]
        );
    }
    let cd = sums[0] / cd_models as f64;
    let [hd, rm, rf, ri, gce, lce] = [1, 2, 3, 4, 5, 6].map(|k| sums[k] / models as f64);
    eprintln!(
        "human vs human over {models} models: CD {cd:.3}, Hamming {hd:.3} (Rm {rm:.3}, Rf {rf:.3}), \
         Rand {ri:.3}, GCE {gce:.3}, LCE {lce:.3} (paper, whole benchmark: CD 0.17, GCE 0.07, \
         Hamming 0.10, Rand 0.10)"
    );
    assert_eq!(models, 19);
    // Loose: of the order of the paper's "Human" row, and LCE ≤ GCE as for every pair.
    for (name, value) in [("CD", cd), ("Hamming", hd), ("Rand", ri), ("GCE", gce)] {
        assert!(value > 0.01 && value < 0.4, "{name} = {value}");
    }
    assert!(lce <= gce);
}
