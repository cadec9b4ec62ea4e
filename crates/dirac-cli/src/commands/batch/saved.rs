//! `--save`: per-mesh arrays beside the JSON, so that learning pipelines cache eigenvectors and
//! descriptors with the spectrum.
//!
//! Each is a `float64` `.npy` named `<mesh file name>.<what>.npy`: `eigenvectors` of shape
//! `(n, k, 4)` (`[vertex, mode, (w, x, y, z)]`, as `dirac eigenfunctions` writes them), and the
//! descriptors `hks`, `dks`, `wks` of shape `(n, 100)` at the default times or energies of
//! `dirac descriptor` (`dirac::descriptors::DEFAULT_SAMPLES`), which the JSON lists under
//! `saved.<what>.parameters`.

use std::path::{Path, PathBuf};

use clap::ValueEnum;
use dirac::descriptors::{
    DEFAULT_SAMPLES, DescriptorError, Modes, default_times, default_wave_sampling,
    dirac_kernel_signature, heat_kernel_signature, wave_kernel_signature,
};
use dirac::spectrum::Spectrum;
use ndarray::{ArrayD, IxDyn};
use ndarray_npy::WriteNpyExt;

use super::output_path;
use super::publish::publish;
use crate::common::files::eigenvector_array;
use crate::common::parsers::value_name;
use crate::common::report::SavedArray;

/// What `--save` can write per mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Saved {
    /// The eigenvectors, `(n, k, 4)`.
    Eigenvectors,
    /// Heat kernel signature of the Laplacian (needs `--operator laplace`), `(n, 100)`.
    Hks,
    /// Dirac kernel signature of the operator, `(n, 100)`.
    Dks,
    /// Wave kernel signature of the operator, `(n, 100)`.
    Wks,
}

impl Saved {
    /// `DIR/<mesh file name>.<what>.npy`.
    fn path(self, out: &Path, mesh: &Path) -> PathBuf {
        output_path(out, mesh, &format!("{}.npy", value_name(&self)))
    }

    /// The array of `spectrum` and its parameters (times or log-energies; none for the
    /// eigenvectors), or why the descriptor cannot be computed.
    fn compute(self, spectrum: &Spectrum) -> Result<(ArrayD<f64>, Vec<f64>), String> {
        let text = |error: DescriptorError| error.to_string();
        let modes = Modes::from_spectrum(spectrum).map_err(text)?;
        let times = || default_times(&modes, DEFAULT_SAMPLES);
        let descriptor = match self {
            Saved::Eigenvectors => {
                let vectors = eigenvector_array(spectrum, modes.vertex_count());
                return Ok((vectors.into_dyn(), Vec::new()));
            }
            Saved::Hks => times().and_then(|t| heat_kernel_signature(&modes, &t)),
            Saved::Dks => times().and_then(|t| dirac_kernel_signature(&modes, &t)),
            Saved::Wks => default_wave_sampling(&modes, DEFAULT_SAMPLES)
                .and_then(|sampling| wave_kernel_signature(&modes, &sampling)),
        }
        .map_err(text)?;
        let shape = IxDyn(&[descriptor.vertex_count(), descriptor.parameters().len()]);
        let values = ArrayD::from_shape_vec(shape, descriptor.values().to_vec())
            .map_err(|error| format!("the descriptor's values do not fill its shape: {error}"))?;
        Ok((values, descriptor.parameters().to_vec()))
    }

    /// Computes and publishes the array for the mesh `mesh` in `out`: what the JSON records
    /// about it, or why it failed (naming the file).
    pub fn write(self, spectrum: &Spectrum, out: &Path, mesh: &Path) -> Result<SavedArray, String> {
        let path = self.path(out, mesh);
        let (array, parameters) = self
            .compute(spectrum)
            .map_err(|error| format!("{}: {error}", path.display()))?;
        publish(&path, |w| array.write_npy(w).map_err(std::io::Error::other))
            .map_err(|error| format!("{}: {error}", path.display()))?;
        Ok(SavedArray {
            file: path
                .file_name()
                .map(|name| name.to_string_lossy().into_owned())
                .unwrap_or_default(),
            shape: array.shape().to_vec(),
            parameters,
        })
    }
}
