//! Rust errors as Python exceptions.
//!
//! The native module raises one exception type, `NativeError(kind, message, details)`; the
//! Python package turns it into the documented class of `dirac_spectra.errors` named by
//! `kind` (the table is in `python/dirac_spectra/errors.py`), with the entries of `details`
//! as attributes. Keeping the class hierarchy in Python lets the classes inherit from both
//! `DiracError` and the builtin they refine (`ValueError`, `ArithmeticError`, …).

use dirac::descriptors::DescriptorError;
use dirac::io::{ReadError, WriteError};
use dirac::operators::OperatorError;
use dirac::repair::RepairError;
use dirac::well::WellError;
use dirac::{MeshError, OperatorNameError, SpectrumError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

pyo3::create_exception!(
    _native,
    NativeError,
    pyo3::exceptions::PyException,
    "An error of the native code: args are (kind, message, details)."
);

/// What went wrong, in the terms of the Python exception classes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `MeshError`: the mesh fails validation (names the face or vertex); a repair can fix it,
    /// and the message says so.
    InvalidMesh,
    /// `MeshError`: the mesh cannot be used for another reason (a vanishing normal, a scale
    /// out of range); no hint to repair.
    Mesh,
    /// `MeshError` raised by a repair (the message carries no hint to repair).
    Repair,
    /// `MeshFileError`: a mesh file is malformed or of an unknown format.
    MeshFile,
    /// `OSError` (details: `errno`): a file could not be opened, read or written.
    Io,
    /// `OptionsError`: an argument has a value the computation cannot use.
    Options,
    /// `KernelError`: fewer nonzero eigenvalues exist than were asked for.
    Kernel,
    /// `SingularError`: a matrix is numerically singular.
    Singular,
    /// `SolverError`: the eigensolver failed.
    Solver,
    /// `NotConvergedError`: the eigensolver stopped early (details carry the converged part).
    NotConverged,
    /// `DescriptorError`: a descriptor cannot be computed from the given eigenpairs.
    Descriptor,
}

impl Kind {
    /// The `kind` string the Python package maps to a class.
    fn name(self) -> &'static str {
        match self {
            Kind::InvalidMesh => "invalid_mesh",
            Kind::Mesh => "mesh",
            Kind::Repair => "repair",
            Kind::MeshFile => "mesh_file",
            Kind::Io => "io",
            Kind::Options => "options",
            Kind::Kernel => "kernel",
            Kind::Singular => "singular",
            Kind::Solver => "solver",
            Kind::NotConverged => "not_converged",
            Kind::Descriptor => "descriptor",
        }
    }
}

/// A Python exception of `kind` with `message` and the attributes `details`.
pub fn raise(kind: Kind, message: impl ToString, details: &Bound<'_, PyDict>) -> PyErr {
    let py = details.py();
    match py
        .get_type::<NativeError>()
        .call1((kind.name(), message.to_string(), details))
    {
        Ok(instance) => PyErr::from_value(instance),
        Err(error) => error,
    }
}

/// A Python exception of `kind` with `message` and no attributes.
pub fn plain(py: Python<'_>, kind: Kind, message: impl ToString) -> PyErr {
    raise(kind, message, &PyDict::new(py))
}

/// A `MeshError` whose attributes `face` and `vertex` are the elements `error` names, with
/// `message` (the error itself, or the error with its file), of `kind` `InvalidMesh` (a failed
/// validation) or `Mesh`.
pub fn mesh_error(py: Python<'_>, kind: Kind, error: &MeshError, message: impl ToString) -> PyErr {
    // No repair orients a non-orientable surface: its message says what to do instead.
    let kind = match error {
        MeshError::NonOrientable { .. } => Kind::Mesh,
        _ => kind,
    };
    let (face, vertex) = mesh_elements(error);
    with_elements(py, kind, message, face, vertex)
}

/// The face and vertex a [`MeshError`] names.
fn mesh_elements(error: &MeshError) -> (Option<usize>, Option<usize>) {
    match error {
        MeshError::IndexOutOfRange { face, vertex, .. }
        | MeshError::RepeatedIndex { face, vertex }
        | MeshError::DegenerateAngle { face, vertex } => (Some(*face), Some(*vertex)),
        MeshError::UnreferencedVertex { vertex }
        | MeshError::NonFiniteCoordinate { vertex }
        | MeshError::NonManifoldVertex { vertex, .. } => (None, Some(*vertex)),
        MeshError::ZeroAreaFace { face } | MeshError::NonOrientable { face } => (Some(*face), None),
        MeshError::NonManifoldEdge { faces, .. } => (faces.first().copied(), None),
        MeshError::InconsistentOrientation { faces, .. } => (Some(faces[0]), None),
        _ => (None, None),
    }
}

/// A failed repair: `OptionsError` for a bad merge distance, else `MeshError` naming the input
/// face or vertex.
pub fn repair_error(py: Python<'_>, error: &RepairError) -> PyErr {
    let (face, vertex) = match error {
        RepairError::InvalidMergeDistance(_) => return plain(py, Kind::Options, error),
        RepairError::NonOrientable { face, .. } => (Some(*face), None),
        RepairError::Invalid(mesh) => mesh_elements(mesh),
        _ => (None, None),
    };
    with_elements(py, Kind::Repair, error, face, vertex)
}

/// An exception of `kind` whose attributes are the `face` and `vertex` given.
fn with_elements(
    py: Python<'_>,
    kind: Kind,
    message: impl ToString,
    face: Option<usize>,
    vertex: Option<usize>,
) -> PyErr {
    let details = PyDict::new(py);
    let filled = face
        .map_or(Ok(()), |f| details.set_item("face", f))
        .and(vertex.map_or(Ok(()), |v| details.set_item("vertex", v)));
    match filled {
        Ok(()) => raise(kind, message, &details),
        Err(e) => e,
    }
}

/// An `OSError` with the operating system's error number of `source`, so that Python picks
/// the subclass (`FileNotFoundError`, `PermissionError`, …).
fn os_error(py: Python<'_>, source: &std::io::Error, message: impl ToString) -> PyErr {
    let details = PyDict::new(py);
    match details.set_item("errno", source.raw_os_error()) {
        Ok(()) => raise(Kind::Io, message, &details),
        Err(e) => e,
    }
}

/// A failed read: `OSError` (the file), `MeshFileError` (its contents) or `MeshError`.
pub fn read_error(py: Python<'_>, error: &ReadError) -> PyErr {
    match error {
        ReadError::Open { source, .. } => os_error(py, source, error),
        ReadError::Directory { .. } => {
            os_error(py, &std::io::ErrorKind::IsADirectory.into(), error)
        }
        ReadError::Mesh { source, .. } => mesh_error(py, Kind::InvalidMesh, source, error),
        _ => plain(py, Kind::MeshFile, error),
    }
}

/// A failed write: `OSError`, or `MeshFileError` for what the format cannot hold.
pub fn write_error(py: Python<'_>, error: &WriteError) -> PyErr {
    match error {
        WriteError::Io { source, .. } => os_error(py, source, error),
        _ => plain(py, Kind::MeshFile, error),
    }
}

/// A failed spectrum or eigenproblem (`NotConverged` is handled by the caller, which has the
/// partial result to attach).
pub fn spectrum_error(py: Python<'_>, error: &SpectrumError) -> PyErr {
    let kind = match error {
        SpectrumError::Normalization { source, .. } => {
            return mesh_error(py, Kind::Mesh, source, error);
        }
        SpectrumError::Operator(OperatorError::DegenerateNormal { vertex }) => {
            return with_elements(py, Kind::Mesh, error, None, Some(*vertex));
        }
        SpectrumError::Well(well) => return well_error(py, well),
        SpectrumError::NearlySingular { vertex, sliver, .. } => {
            return with_elements(py, Kind::Singular, error, *sliver, *vertex);
        }
        SpectrumError::InvalidCount { .. }
        | SpectrumError::InvalidParameter { .. }
        | SpectrumError::InvalidFlatTolerance(_)
        | SpectrumError::InvalidTolerance(_)
        | SpectrumError::InvalidMaxRestarts
        | SpectrumError::ReferenceUnused { .. }
        | SpectrumError::Operator(_) => Kind::Options,
        SpectrumError::ScaleOutOfRange | SpectrumError::ReferenceConnectivity(_) => Kind::Mesh,
        SpectrumError::VanishingOperator { .. }
        | SpectrumError::TooFewNonzero { .. }
        | SpectrumError::ParallelFaces { .. }
        | SpectrumError::RuledKernel { .. } => Kind::Kernel,
        SpectrumError::Factorization(_) => Kind::Singular,
        SpectrumError::NotConverged { .. } => Kind::NotConverged,
        _ => Kind::Solver,
    };
    plain(py, kind, error)
}

/// A failed potential well.
pub fn well_error(py: Python<'_>, error: &WellError) -> PyErr {
    let kind = match error {
        WellError::Solve(_) => Kind::Singular,
        WellError::Sparse(_) => Kind::Solver,
        _ => Kind::Options,
    };
    plain(py, kind, error)
}

/// A failed descriptor.
pub fn descriptor_error(py: Python<'_>, error: &DescriptorError) -> PyErr {
    plain(py, Kind::Descriptor, error)
}

/// An unknown operator name or a misplaced `tau`.
pub fn operator_name_error(py: Python<'_>, error: &OperatorNameError) -> PyErr {
    plain(py, Kind::Options, error)
}
