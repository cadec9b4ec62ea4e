//! Segmentations of a mesh's faces, as the Princeton segmentation benchmark (Chen, Golovinskiy,
//! Funkhouser, "A Benchmark for 3D Mesh Segmentation", SIGGRAPH 2009) stores and scores them.
//!
//! A segmentation is one label per face (`labels[t]` is the segment of face `t`, faces in the
//! mesh's order); only the partition matters, not the names of its segments. Output follows
//! the convention `0…S−1` in order of first appearance
//! ([`seg_file::relabel_by_first_appearance`]).
//!
//! | module | what it holds |
//! |---|---|
//! | [`consensus`] | the consensus segmentation of paper §6.2: k-means trials combined by persistence |
//! | [`seg_file`] | the benchmark's `.seg` files: one segment number per line |
//! | [`evaluation`] | the benchmark's error measures between a segmentation and references |

pub mod consensus;
pub mod evaluation;
pub mod seg_file;
