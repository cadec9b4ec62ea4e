//! Library part of the `dirac` command line: what the binary draws and writes, reusable by
//! the experiments (rendering meshes shaded by a function, plotting spectra).

pub mod plot;
pub mod render;
