//! # experiments
//!
//! The experiments of "A Dirac Operator for Extrinsic Shape Analysis" (Liu, Jacobson, Crane
//! 2017, §6) on this implementation, as reusable pieces behind the runnable examples in
//! `examples/` (see `docs/EXPERIMENTS.md`):
//!
//! * [`tori`]: one base torus with several kinds of added detail and random tessellations
//!   (Fig. 8);
//! * [`patches`]: textured sphere patches with ragged boundaries under the infinite potential
//!   well (Fig. 7, Fig. 10);
//! * [`bumps`]: a surface with an inward and an outward bump, two tessellations,
//!   correspondence by nearest descriptor (Fig. 12);
//! * [`segmentation`]: consensus segmentation of the Princeton benchmark's models, scored
//!   against their human segmentations (§6.2, Fig. 11);
//! * [`flat_vs_curved`]: kernel and small eigenvalues of `D_N` on a cube and a sphere (Fig. 5,
//!   Fig. 9);
//! * [`two_surfaces`]: the relative Dirac operator `D_{f1,f2}` of a surface and a deformed copy
//!   (Fig. 3);
//! * [`man_made`]: man-made versus organic shapes of a labelled folder by the paper's score
//!   (mean `λ²` of the first 25 eigenvalues of `D_N`), thresholds learnt leave-one-out, and
//!   nearest neighbours on `log |λ|` (§6.1, Fig. 9);
//! * [`spectra`]: the spectra of many meshes under several operators, timed; [`metrics`]:
//!   nearest-neighbour accuracy, separation ratio and k-means purity; [`spectral_features`]:
//!   what a spectrum becomes before the distance (count, transform, normalisation);
//!   [`patches_study`]: which factor limits the patch purity; [`embedding`]: t-SNE and
//!   classical MDS for the 2-D plots; [`correspondence`]: nearest-descriptor matching and its geodesic
//!   error; [`threshold`]: one-number classifiers with a threshold learnt leave-one-out;
//!   [`report`]: the score table; [`plots`]: the charts; [`args`]: the examples' command line.

pub mod args;
pub mod bumps;
pub mod correspondence;
pub mod embedding;
pub mod flat_vs_curved;
pub mod man_made;
pub mod metrics;
pub mod patches;
pub mod patches_study;
pub mod plots;
pub mod report;
pub mod segmentation;
pub mod spectra;
pub mod spectral_features;
pub mod threshold;
pub mod tori;
pub mod two_surfaces;

use thiserror::Error;

/// Why an experiment could not run.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ExperimentError {
    /// A mesh generator rejected its parameters.
    #[error(transparent)]
    Generator(#[from] dirac::generators::GeneratorError),
    /// A generated mesh was invalid.
    #[error(transparent)]
    Mesh(#[from] dirac::MeshError),
    /// A spectrum could not be computed.
    #[error("{operator} on mesh {mesh}: {source}")]
    Spectrum {
        /// The operator.
        operator: dirac::spectrum::Operator,
        /// Index of the mesh in its experiment.
        mesh: usize,
        /// The failure.
        source: dirac::spectrum::SpectrumError,
    },
    /// A geodesic distance or potential well could not be computed.
    #[error(transparent)]
    Well(#[from] dirac::well::WellError),
    /// A descriptor could not be computed.
    #[error(transparent)]
    Descriptor(#[from] dirac::descriptors::DescriptorError),
    /// An operator could not be assembled.
    #[error(transparent)]
    Operator(#[from] dirac::operators::OperatorError),
    /// A dense eigensolver failed.
    #[error("dense eigensolver: {0}")]
    Eigen(String),
    /// A 2-D embedding could not be computed.
    #[error("embedding: {0}")]
    Embedding(String),
    /// A distance matrix is not square.
    #[error("the distance matrix is not square")]
    NotSquare,
    /// A chart could not be written.
    #[error(transparent)]
    Plot(#[from] dirac_cli::plot::PlotError),
    /// A picture could not be rendered.
    #[error(transparent)]
    Render(#[from] dirac_cli::render::RenderError),
    /// A `.seg` file could not be read.
    #[error(transparent)]
    SegFile(#[from] dirac::segmentation::seg_file::SegFileError),
    /// A segmentation could not be computed.
    #[error(transparent)]
    Segmentation(#[from] dirac::segmentation::consensus::SegmentationError),
    /// A segmentation could not be scored.
    #[error(transparent)]
    Evaluation(#[from] dirac::segmentation::evaluation::EvaluationError),
    /// A mesh file could not be written.
    #[error(transparent)]
    WriteMesh(#[from] dirac::io::WriteError),
    /// A mesh file could not be read or is not a valid mesh.
    #[error(transparent)]
    Read(#[from] dirac::io::ReadError),
    /// What went wrong with one input file.
    #[error("{}: {source}", path.display())]
    InFile {
        /// The file.
        path: std::path::PathBuf,
        /// The failure.
        source: Box<ExperimentError>,
    },
    /// A label file is missing or malformed.
    #[error("{}: line {line}: {message}", path.display())]
    Labels {
        /// The label file.
        path: std::path::PathBuf,
        /// Its line.
        line: u64,
        /// What is wrong.
        message: String,
    },
    /// An output file or directory could not be written.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// A spectrum has fewer eigenvalues than a feature vector needs.
    #[error(
        "shape {shape} has {available} eigenvalues but the features need {wanted}: compute more"
    )]
    TooFewEigenvalues {
        /// Index of the shape in its experiment.
        shape: usize,
        /// Eigenvalues computed.
        available: usize,
        /// Eigenvalues wanted.
        wanted: usize,
    },
    /// `log|λ|` of a zero eigenvalue.
    #[error(
        "eigenvalue {index} of shape {shape} is 0, so log|λ| is undefined: use another transform"
    )]
    ZeroEigenvalue {
        /// Index of the shape.
        shape: usize,
        /// Index of the eigenvalue.
        index: usize,
    },
    /// Normalising by the first nonzero eigenvalue of a spectrum that has none.
    #[error(
        "every eigenvalue of shape {shape} is 0: it cannot be divided by its first nonzero one"
    )]
    NoNonzeroEigenvalue {
        /// Index of the shape.
        shape: usize,
    },
    /// A t-SNE perplexity that the number of points cannot support.
    #[error(
        "t-SNE perplexity {perplexity} needs at least 3·perplexity + 1 = {needed} points, got {points}: lower it"
    )]
    Perplexity {
        /// The perplexity asked for.
        perplexity: f64,
        /// Points needed.
        needed: usize,
        /// Points given.
        points: usize,
    },
    /// The command line was not understood.
    #[error("{0}")]
    Usage(String),
}
