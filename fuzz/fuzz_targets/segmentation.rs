//! Fuzz target: the `.seg` reader, the benchmark's measures and consensus segmentation on
//! arbitrary input. A `.seg` text is read against the 20 faces of the icosahedron and, when it
//! parses, scored against itself (every measure 0 but the undefined Cut Discrepancy) and
//! against a fixed partition; arbitrary descriptor values (NaN, ∞, huge) and options are
//! segmented. The outcome must be a result or a typed error, never a panic; a segmentation
//! labels every face with `0…S−1`.
#![no_main]

use std::path::Path;

use dirac::clustering::Initialisation;
use dirac::generators::icosphere;
use dirac::segmentation::consensus::{ConsensusOptions, consensus_segmentation};
use dirac::segmentation::evaluation::SegmentationEvaluator;
use dirac::segmentation::seg_file::read_seg;
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;

/// A descriptor value: NaN, ±∞, any bit pattern or a moderate number.
fn value(u: &mut Unstructured) -> Result<f64> {
    Ok(match u.int_in_range(0..=15u8)? {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => f64::from_bits(u.arbitrary()?),
        _ => f64::from(u.arbitrary::<i16>()?) / 64.0,
    })
}

fn run(u: &mut Unstructured) -> Result<()> {
    let mesh = icosphere(0);
    let faces = mesh.face_count();
    if u.arbitrary()? {
        let text = u.bytes(u.len())?;
        if let Ok(labels) = read_seg(Path::new("fuzz.seg"), text, faces) {
            let evaluator = SegmentationEvaluator::new(&mesh).expect("the icosahedron is valid");
            let itself = evaluator.scores(&labels, &labels).expect("same face count");
            assert_eq!(itself.rand_index_error, 0.0);
            let halves: Vec<usize> = (0..faces).map(|t| t % 2).collect();
            let _ = evaluator.scores(&labels, &halves);
        }
        return Ok(());
    }
    let dimension = u.int_in_range(0..=3usize)?;
    let count = faces * dimension + usize::from(u.ratio(1, 16)?);
    let rows = (0..count).map(|_| value(u)).collect::<Result<Vec<f64>>>()?;
    let options = ConsensusOptions {
        trials: u.int_in_range(0..=4)?,
        min_clusters: u.int_in_range(0..=4)?,
        max_clusters: u.int_in_range(0..=6)?,
        initialisation: if u.arbitrary()? {
            Initialisation::PlusPlus
        } else {
            Initialisation::Uniform
        },
        max_iterations: u.int_in_range(0..=20)?,
        min_area_fraction: value(u)?,
        segments: if u.arbitrary()? {
            Some(u.int_in_range(0..=25)?)
        } else {
            None
        },
        seed: u.arbitrary()?,
    };
    if let Ok(segmentation) = consensus_segmentation(&mesh, &rows, dimension, &options) {
        let count = segmentation.segment_count();
        assert_eq!(segmentation.labels.len(), faces);
        assert!(segmentation.labels.iter().all(|&l| l < count));
        if let Some(wanted) = options.segments {
            assert_eq!(count, wanted);
        }
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
