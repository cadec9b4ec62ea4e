//! The Princeton benchmark's error measures between a segmentation and reference
//! segmentations (Chen, Golovinskiy, Funkhouser 2009, §4): Cut Discrepancy, Hamming distance,
//! Rand Index, Global and Local Consistency Error.
