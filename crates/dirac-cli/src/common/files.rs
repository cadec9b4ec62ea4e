//! Writing results: `.npy` arrays, the closing "wrote …" line, output file extensions.

use std::ffi::OsStr;
use std::io::{self, Write};
use std::path::Path;

use dirac::spectrum::Spectrum;
use ndarray::{Array, Array3, Dimension};
use ndarray_npy::write_npy;

use crate::common::error::CliError;

/// Writes `array` as `.npy` (`float64`) to `path`.
pub fn write_array<D: Dimension>(path: &Path, array: &Array<f64, D>) -> Result<(), CliError> {
    write_npy(path, array).map_err(|source| CliError::Npy {
        path: path.to_path_buf(),
        source,
    })
}

/// The eigenvectors as an `n × k × 4` array of `(w, x, y, z)`.
pub fn eigenvector_array(spectrum: &Spectrum, vertices: usize) -> Array3<f64> {
    Array3::from_shape_fn((vertices, spectrum.eigenvectors.len(), 4), |(v, i, c)| {
        let q = spectrum.eigenvectors[i][v];
        [q.w, q.x, q.y, q.z][c]
    })
}

/// Prints an informational line (what was written where) on stdout. The files are written by
/// then, so a reader that has gone away (`dirac render … | head -0`) is not an error.
pub fn tell(line: std::fmt::Arguments) {
    let _ = writeln!(io::stdout().lock(), "{line}");
}

/// Whether `path` has the extension `ext` (case-insensitive).
pub fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension()
        .and_then(OsStr::to_str)
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}
