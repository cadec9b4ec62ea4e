//! [`CliError`]: every way a command can fail, and the exit code of each. `main` prints the
//! error once and exits with [`CliError::exit_code`]; commands only return it.

use std::io;
use std::path::PathBuf;

use dirac::descriptors::DescriptorError;
use dirac::io::{ReadError, WriteError};
use dirac::repair::RepairError;
use dirac::segmentation::consensus::SegmentationError;
use dirac::segmentation::evaluation::EvaluationError;
use dirac::segmentation::seg_file::SegFileError;
use dirac::spectrum::SpectrumError;
use dirac::well::WellError;
use dirac::{ComponentError, ConnectivityMismatch, MeshError};
use dirac_cli::plot::PlotError;
use dirac_cli::render::RenderError;
use ndarray_npy::WriteNpyError;
use thiserror::Error;

/// Exit code of a mesh that cannot be read, a spectrum or descriptor that cannot be computed,
/// or an output that cannot be written.
pub const FAILED: u8 = 1;

/// Exit code of a solve that did not converge (what converged is still reported or written).
pub const NOT_CONVERGED: u8 = 3;

/// Exit code of `dirac batch` when at least one mesh failed, did not converge or (`--merge`)
/// is in no shard's summary.
pub const SOME_FAILED: u8 = 4;

/// Exit code of a `dirac batch` stopped by Ctrl-C (128 + SIGINT), after it wrote its summary.
pub const INTERRUPTED: u8 = 130;

/// The exit codes of `dirac render` and `dirac plot`, for their `--help`.
pub const PICTURE_EXIT_CODES: &str = "\
Exit codes:
  0  success
  1  a mesh cannot be read or is invalid, a spectrum, descriptor or the potential cannot be
     computed, or the picture cannot be written (the message names the file and the problem)
  2  usage error (bad or missing arguments)
  3  the eigensolver did not converge
";

/// Why a command failed. The message names the mesh or file it is about.
#[derive(Debug, Error)]
pub enum CliError {
    /// Bad or missing arguments that clap could not reject itself (exit code 2); also clap's
    /// own errors, `--help` and `--version` (exit code 0).
    #[error("{0}")]
    Usage(clap::Error),
    /// The mesh file cannot be read or is not a valid mesh (the message names the file; for
    /// an invalid mesh it ends with the hint that `--repair` exists).
    #[error("{0}{hint}", hint = mesh_error_hint(.0))]
    Read(#[from] ReadError),
    /// `--repair` cannot make the mesh valid.
    #[error("{mesh}: cannot repair: {source}")]
    Repair {
        /// The mesh.
        mesh: String,
        /// What failed.
        source: RepairError,
    },
    /// `--component` names no component of the mesh.
    #[error("{mesh}: --component: {source}")]
    Component {
        /// The mesh.
        mesh: String,
        /// What failed.
        source: ComponentError,
    },
    /// `--relative-to`: the reference surface is not the same triangulation as the mesh.
    #[error(
        "--relative-to {reference}: not the same triangulation as {mesh} ({source}); D_{{f1,f2}} \
         needs two positions of the same vertices, faces listed identically (for example a \
         mesh and a deformed copy written by the same program)"
    )]
    ReferenceConnectivity {
        /// The mesh.
        mesh: String,
        /// The reference surface.
        reference: String,
        /// The first difference.
        source: ConnectivityMismatch,
    },
    /// The spectrum cannot be computed on this mesh.
    #[error("{mesh}: {source}")]
    Spectrum {
        /// The mesh, as in reports.
        mesh: String,
        /// What failed.
        source: SpectrumError,
    },
    /// A descriptor cannot be computed from the spectrum.
    #[error("{mesh}: {source}")]
    Descriptor {
        /// The mesh, as in reports.
        mesh: String,
        /// What failed.
        source: DescriptorError,
    },
    /// The segmentation cannot be computed from the descriptor.
    #[error("{mesh}: segmentation: {source}")]
    Segmentation {
        /// The mesh, as in reports.
        mesh: String,
        /// What failed.
        source: SegmentationError,
    },
    /// The potential well cannot be computed on this mesh.
    #[error("{mesh}: potential well: {source}")]
    Well {
        /// The mesh.
        mesh: String,
        /// What failed.
        source: WellError,
    },
    /// Normalising the mesh failed.
    #[error("{mesh}: {source}")]
    Normalize {
        /// The mesh.
        mesh: String,
        /// What failed.
        source: MeshError,
    },
    /// The eigensolver stopped before all wanted pairs converged (exit code 3); what did
    /// converge has been printed or written as `doing` says.
    #[error(
        "{mesh}: the eigensolver converged only {converged} of {wanted} eigenpairs; {doing} \
         ({advice})"
    )]
    NotConverged {
        /// The mesh.
        mesh: String,
        /// Pairs that converged.
        converged: usize,
        /// Pairs wanted.
        wanted: usize,
        /// What was done with the converged pairs (`printing those`, `nothing drawn`).
        doing: String,
        /// What to do: what the pairs found but not accepted tell
        /// ([`dirac::Unaccepted::explanation`]), or the general advice.
        advice: String,
    },
    /// A `.seg` file cannot be read, is malformed or does not fit the mesh (the message names
    /// the mesh, the `.seg` file and, for a mismatch, both numbers).
    #[error("{mesh}: {source}")]
    SegFile {
        /// The mesh file.
        mesh: String,
        /// What is wrong with the `.seg` file.
        source: SegFileError,
    },
    /// Segmentations of the mesh cannot be compared.
    #[error("{mesh}: {source}")]
    Evaluation {
        /// The mesh file.
        mesh: String,
        /// Why.
        source: EvaluationError,
    },
    /// A file or directory cannot be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What failed.
        source: io::Error,
    },
    /// An `.npy` file cannot be written.
    #[error("{}: {source}", path.display())]
    Npy {
        /// The file.
        path: PathBuf,
        /// What failed.
        source: WriteNpyError,
    },
    /// A mesh file cannot be written (the message names the file).
    #[error(transparent)]
    WriteMesh(#[from] WriteError),
    /// The picture cannot be drawn or written (the message names the file).
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The chart cannot be drawn or written (the message names the file).
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// The result cannot be printed on stdout.
    #[error("cannot write the result: {0}")]
    Stdout(io::Error),
    /// `dirac batch`: the input names no mesh.
    #[error("{}: no .obj, .off, .ply or .stl meshes found", .0.display())]
    NoMeshes(PathBuf),
    /// `dirac batch`: two inputs share a file name, up to case, so their outputs would
    /// collide.
    #[error(
        "{} and {} have the same file name (up to upper and lower case, which macOS and \
         Windows file systems do not distinguish); their outputs would collide in --out: \
         rename one",
        first.display(), second.display()
    )]
    DuplicateName {
        /// The first input.
        first: PathBuf,
        /// The second input.
        second: PathBuf,
    },
    /// `dirac batch`: the worker threads cannot be started.
    #[error("cannot start {jobs} worker threads: {message}")]
    Threads {
        /// Threads asked for.
        jobs: usize,
        /// The error.
        message: String,
    },
    /// `dirac batch --merge`: shard summaries that are not of this batch (the message says
    /// why).
    #[error("--merge: {0}")]
    Merge(String),
    /// `dirac batch`: stopped by Ctrl-C after writing its summary (exit code 130).
    #[error("interrupted; the summary is in {}, rerun the command to resume", summary.display())]
    Interrupted {
        /// The summary table.
        summary: PathBuf,
    },
    /// `dirac batch`: some meshes failed, did not converge or are missing from a merge (each
    /// is reported on stderr and in the summary; exit code 4).
    #[error("{failed} of {meshes} meshes are not complete; see {}", summary.display())]
    SomeFailed {
        /// Meshes that failed or did not converge.
        failed: usize,
        /// All meshes.
        meshes: usize,
        /// The summary table.
        summary: PathBuf,
    },
}

/// What follows the message of a mesh that cannot be read: for an invalid mesh (not for an
/// unreadable file) that `--repair` exists, unless the mesh is not orientable, which no repair
/// fixes (the message says what to do); for a directory, that `dirac batch` reads one.
pub fn mesh_error_hint(error: &ReadError) -> &'static str {
    match error {
        ReadError::Mesh {
            source: MeshError::NonOrientable { .. },
            ..
        } => "",
        ReadError::Mesh { .. } => "; --repair fixes such defects (see `dirac repair --help`)",
        ReadError::Directory { .. } => "; `dirac batch` computes every mesh of a directory",
        _ => "",
    }
}

impl CliError {
    /// A usage error (exit code 2) that clap cannot detect itself; the dispatcher, which knows
    /// the subcommand, adds its usage line ([`clap::Error::format`]).
    pub fn usage(kind: clap::error::ErrorKind, message: impl std::fmt::Display) -> Self {
        CliError::Usage(clap::Error::raw(kind, message))
    }

    /// The process exit code: 2 for usage errors (clap's own code, 0 for `--help`), 3 for a
    /// solve that did not converge, 4 for a batch with failed meshes, 130 for an interrupted one, 1 for everything else.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Usage(error) => u8::try_from(error.exit_code()).unwrap_or(2),
            CliError::NotConverged { .. } => NOT_CONVERGED,
            CliError::SomeFailed { .. } => SOME_FAILED,
            CliError::Interrupted { .. } => INTERRUPTED,
            _ => FAILED,
        }
    }
}
