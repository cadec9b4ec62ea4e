//! Mesh segmentation: the consensus segmentation of paper §6.2 ([`consensus`]).

pub mod consensus;
