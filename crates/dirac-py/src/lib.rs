//! `dirac_spectra._native`: the compiled half of the Python package `dirac_spectra`.
//!
//! Thin wrappers over the `dirac` crate: arrays in, dicts of arrays out. Validation of dtypes
//! and the public signatures with their defaults live in the Python half
//! (`python/dirac_spectra/`), which is what users import; errors are raised as
//! `NativeError` and given their documented class there. Every computation runs with
//! the GIL released, on at most the number of threads asked for.

mod convert;
mod error;

use std::ops::ControlFlow;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use dirac::descriptors::{self, DescriptorTable, Modes, WaveSampling};
use dirac::geometry::{barycentric_masses, cotan_laplacian};
use dirac::io::{PlyWriteOptions, read_mesh as read_mesh_file, read_raw, write_obj, write_ply};
use dirac::repair::{DEFAULT_MERGE_DISTANCE, RepairOptions, sliver_warning, slivers};
use dirac::spectrum::{
    DEFAULT_FLAT_TOLERANCE, relative_spectrum_with_progress, scale_warning, spectrum_with_progress,
};
use dirac::well::PotentialWell;
use dirac::{
    ConnectivityMismatch, Normalization, Operator, OperatorNameError, Parameter, SolverBackend,
    SpectrumError, SpectrumOptions,
};
use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use qeig::{Progress, ProgressCallback};

use crate::error::{
    Kind, NativeError, descriptor_error, operator_name_error, plain, raise, read_error,
    repair_error, spectrum_error, well_error, write_error,
};

/// `(V, F)` of the mesh file at `path` (`.obj`, `.off`, `.ply`), validated.
#[pyfunction]
fn read_mesh(py: Python<'_>, path: PathBuf) -> PyResult<(Bound<'_, PyAny>, Bound<'_, PyAny>)> {
    let mesh = py
        .detach(|| read_mesh_file(&path))
        .map_err(|e| read_error(py, &e))?;
    Ok(convert::mesh_arrays(py, &mesh))
}

/// Repairs the unvalidated `(V, F)` (negative indices count as out of range): a dict of the
/// repaired mesh, the maps to the input and the report ([`convert::repaired_dict`]).
#[pyfunction]
fn repair<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    merge_distance: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let raw = convert::raw_mesh(py, &vertices, &faces)?;
    let repaired = py
        .detach(|| dirac::repair::repair(raw, &repair_options(merge_distance)))
        .map_err(|e| repair_error(py, &e))?;
    convert::repaired_dict(py, &repaired)
}

/// Reads the mesh file at `path` without validating it and repairs it (as [`repair`]).
#[pyfunction]
fn read_and_repair(
    py: Python<'_>,
    path: PathBuf,
    merge_distance: f64,
) -> PyResult<Bound<'_, PyDict>> {
    let raw = py
        .detach(|| read_raw(&path))
        .map_err(|e| read_error(py, &e))?;
    let repaired = py
        .detach(|| dirac::repair::repair(raw, &repair_options(merge_distance)))
        .map_err(|e| repair_error(py, &e))?;
    convert::repaired_dict(py, &repaired)
}

/// The library's repair options with `merge_distance`.
fn repair_options(merge_distance: f64) -> RepairOptions {
    let mut options = RepairOptions::default();
    options.merge_distance = merge_distance;
    options
}

/// Writes the mesh `(V, F)` to `path` as OBJ or binary PLY (by the extension).
#[pyfunction]
fn write_mesh(
    py: Python<'_>,
    path: PathBuf,
    vertices: PyReadonlyArray2<'_, f64>,
    faces: PyReadonlyArray2<'_, i64>,
) -> PyResult<()> {
    let mesh = convert::mesh(py, &vertices, &faces)?;
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let written = match extension.as_deref() {
        Some("obj") => py.detach(|| write_obj(&mesh, &path)),
        Some("ply") => py.detach(|| write_ply(&mesh, &path, &PlyWriteOptions::default())),
        _ => {
            return Err(plain(
                py,
                Kind::MeshFile,
                format!(
                    "{}: cannot write this format (expected a .obj or .ply file)",
                    path.display()
                ),
            ));
        }
    };
    written.map_err(|e| write_error(py, &e))
}

/// The options of a solve, as the Python signature names them.
#[derive(FromPyObject)]
struct Request {
    #[pyo3(attribute)]
    operator: String,
    #[pyo3(attribute)]
    tau: Option<f64>,
    #[pyo3(attribute)]
    anisotropy: Option<f64>,
    #[pyo3(attribute)]
    k: usize,
    #[pyo3(attribute)]
    normalize: Option<String>,
    #[pyo3(attribute)]
    well: Option<WellRequest>,
    #[pyo3(attribute)]
    backend: String,
    #[pyo3(attribute)]
    tolerance: f64,
    #[pyo3(attribute)]
    seed: u64,
    #[pyo3(attribute)]
    max_restarts: usize,
    #[pyo3(attribute)]
    include_kernel: Option<bool>,
    #[pyo3(attribute)]
    flat_tolerance: f64,
    #[pyo3(attribute)]
    threads: usize,
    /// Seconds after which the eigensolver stops, within about 0.1 s (`None`: no limit);
    /// validated by the Python side (finite, positive).
    #[pyo3(attribute)]
    time_limit: Option<f64>,
}

/// `dirac_spectra.PotentialWell`.
#[derive(FromPyObject)]
struct WellRequest {
    #[pyo3(attribute)]
    radius: f64,
    #[pyo3(attribute)]
    center: Option<usize>,
    #[pyo3(attribute)]
    steepness: f64,
    #[pyo3(attribute)]
    height: f64,
}

impl WellRequest {
    /// The library's well.
    fn well(&self) -> PotentialWell {
        PotentialWell {
            center: self.center,
            radius: self.radius,
            steepness: self.steepness,
            height: self.height,
        }
    }
}

impl Request {
    /// The operator named `operator`, its parameter taken from the keyword that belongs to it
    /// (`tau` for the family, `anisotropy` for the anisotropic Laplacian); a keyword given to
    /// an operator it does not belong to is an error, in the keywords' terms.
    fn operator(&self, py: Python<'_>) -> PyResult<Operator> {
        let given = [
            (Parameter::Weight, self.tau),
            (Parameter::Anisotropy, self.anisotropy),
        ];
        let (name, wanted) = match Operator::from_name(&self.operator, None) {
            Ok(operator) => (operator.name(), None),
            Err(OperatorNameError::MissingParameter { name, parameter }) => (name, Some(parameter)),
            Err(error) => return Err(operator_name_error(py, &error)),
        };
        if let Some((stray, _)) = given
            .iter()
            .find(|(parameter, value)| value.is_some() && Some(*parameter) != wanted)
        {
            return Err(plain(
                py,
                Kind::Options,
                format!("operator {name:?} takes no {}", stray.keyword()),
            ));
        }
        let value = match wanted {
            None => None,
            Some(parameter) => {
                let value = given
                    .iter()
                    .find(|(p, _)| *p == parameter)
                    .and_then(|(_, v)| *v);
                if value.is_none() {
                    return Err(plain(
                        py,
                        Kind::Options,
                        format!(
                            "operator {name:?} needs {} ({}, in {})",
                            parameter.keyword(),
                            parameter.description(),
                            parameter.range()
                        ),
                    ));
                }
                value
            }
        };
        Operator::from_name(name, value).map_err(|e| operator_name_error(py, &e))
    }

    /// The library's options.
    fn options(&self, py: Python<'_>) -> PyResult<SpectrumOptions> {
        let operator = self.operator(py)?;
        let mut options = SpectrumOptions::new(operator, self.k);
        options.normalization = match self.normalize.as_deref() {
            None | Some("none") => Normalization::None,
            Some("unit-area") => Normalization::UnitArea,
            Some(other) => {
                return Err(plain(
                    py,
                    Kind::Options,
                    format!(
                        "unknown normalize {other:?}; expected None, \"none\" or \"unit-area\""
                    ),
                ));
            }
        };
        options.backend = match self.backend.as_str() {
            "native" => SolverBackend::Native,
            "real-block" => SolverBackend::RealBlock,
            "complex-adjoint" => SolverBackend::ComplexAdjoint,
            other => {
                return Err(plain(
                    py,
                    Kind::Options,
                    format!(
                        "unknown backend {other:?}; expected \"native\", \"real-block\" or \
                         \"complex-adjoint\""
                    ),
                ));
            }
        };
        options.well = self.well.as_ref().map(WellRequest::well);
        options.tolerance = self.tolerance;
        options.seed = self.seed;
        options.max_restarts = self.max_restarts;
        if let Some(include) = self.include_kernel {
            options.include_kernel = include;
        }
        options.flat_tolerance = self.flat_tolerance;
        Ok(options)
    }
}

/// Runs `work` without the GIL on the calling thread: alone (`threads = 1`) or with the one
/// helper thread the kernels use (`threads = 2`, the most the solver uses).
fn run_detached<T: Send>(
    py: Python<'_>,
    threads: usize,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    match threads {
        1 => Ok(py.detach(|| qsparse::threads::on_one_thread(work))),
        2 => Ok(py.detach(work)),
        _ => Err(plain(
            py,
            Kind::Options,
            format!("threads = {threads}: the solver uses 1 or 2 threads"),
        )),
    }
}

/// [`run_detached`] for a solve that reports progress: whenever the solver reports (after every
/// restart, and between restarts at least every 0.1 s) the GIL is taken back briefly to check
/// for signals (Ctrl-C raises `KeyboardInterrupt` within about 0.1 s)
/// and to call `progress` with a dict of the solver's state; an exception from either stops
/// the solve and is raised instead of its result. Past `deadline` the solve is stopped too,
/// and returns what converged; the flag says whether the deadline stopped it.
fn run_reporting<T: Send>(
    py: Python<'_>,
    threads: usize,
    progress: Option<Py<PyAny>>,
    deadline: Option<Instant>,
    work: impl FnOnce(ProgressCallback) -> T + Send,
) -> PyResult<(T, bool)> {
    let mut failure: Option<PyErr> = None;
    let mut past_deadline = false;
    let value = run_detached(py, threads, || {
        let mut report = |state: &Progress| {
            if deadline.is_some_and(|deadline| Instant::now() >= deadline) {
                past_deadline = true;
                return ControlFlow::Break(());
            }
            Python::attach(|py| {
                let called = py.check_signals().and_then(|()| match &progress {
                    Some(callback) => callback.call1(py, (progress_dict(py, state)?,)).map(drop),
                    None => Ok(()),
                });
                called.map_or_else(
                    |error| {
                        failure = Some(error);
                        ControlFlow::Break(())
                    },
                    |()| ControlFlow::Continue(()),
                )
            })
        };
        work(&mut report)
    })?;
    failure.map_or(Ok((value, past_deadline)), Err)
}

/// The solver's state when it reports.
fn progress_dict<'py>(py: Python<'py>, state: &Progress) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("round", state.round)?;
    dict.set_item("restarts", state.restarts)?;
    dict.set_item("operator_applications", state.operator_applications)?;
    dict.set_item("locked", state.locked)?;
    dict.set_item("wanted", state.wanted)?;
    Ok(dict)
}

/// The spectrum of `(V, F)` as a dict (see `dirac_spectra.Spectrum`); relative to the surface
/// `(relative_to, F)` when given (`D_{f1,f2}`).
#[pyfunction]
#[pyo3(signature = (vertices, faces, request, eigenvectors, progress, relative_to = None))]
fn spectrum<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    request: Request,
    eigenvectors: bool,
    progress: Option<Py<PyAny>>,
    relative_to: Option<PyReadonlyArray2<'py, f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mesh = convert::mesh(py, &vertices, &faces)?;
    let reference = reference_mesh(py, &mesh, &faces, relative_to)?;
    let options = request.options(py)?;
    // A limit beyond what a clock can hold is no limit.
    let deadline = (request.time_limit)
        .and_then(|limit| Instant::now().checked_add(Duration::try_from_secs_f64(limit).ok()?));
    let (result, stopped) =
        run_reporting(
            py,
            request.threads,
            progress,
            deadline,
            |report| match &reference {
                Some(reference) => {
                    relative_spectrum_with_progress(&mesh, reference, &options, Some(report))
                }
                None => spectrum_with_progress(&mesh, &options, Some(report)),
            },
        )?;
    match result {
        Ok(spectrum) => {
            let dict = convert::spectrum_dict(py, &spectrum, eigenvectors)?;
            let slivers = slivers(&mesh);
            let warning = (slivers.first()).map(|&first| sliver_warning(slivers.len(), first));
            dict.set_item("sliver_warning", warning)?;
            dict.set_item("scale_warning", scale_warning(&mesh, &options))?;
            Ok(dict)
        }
        Err(SpectrumError::NotConverged {
            wanted,
            partial,
            unaccepted,
        }) => {
            let details = PyDict::new(py);
            details.set_item("wanted", wanted)?;
            details.set_item("accepting_tolerance", unaccepted.accepting_tolerance())?;
            details.set_item(
                "partial",
                convert::spectrum_dict(py, &partial, eigenvectors)?,
            )?;
            let message = SpectrumError::NotConverged {
                wanted,
                partial,
                unaccepted,
            };
            let message = match request.time_limit.filter(|_| stopped) {
                Some(limit) => format!("{message} (stopped at the time limit of {limit} s)"),
                None => message.to_string(),
            };
            details.set_item("stopped_at_time_limit", stopped)?;
            Err(raise(Kind::NotConverged, message, &details))
        }
        Err(e) => Err(spectrum_error(py, &e)),
    }
}

/// The surface `(relative_to, F)` of `mesh`'s triangulation, if given. Its vertex count is
/// checked before it is built from the faces, which would otherwise name a face whose vertex
/// the shorter reference lacks as an invalid mesh.
fn reference_mesh(
    py: Python<'_>,
    mesh: &dirac::TriMesh,
    faces: &PyReadonlyArray2<'_, i64>,
    relative_to: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<Option<dirac::TriMesh>> {
    relative_to
        .map(|positions| match positions.as_array().nrows() {
            rows if rows == mesh.vertex_count() => convert::mesh(py, &positions, faces),
            rows => Err(spectrum_error(
                py,
                &SpectrumError::ReferenceConnectivity(ConnectivityMismatch::VertexCount {
                    this: mesh.vertex_count(),
                    other: rows,
                }),
            )),
        })
        .transpose()
}

/// The eigenproblem `P x = λ Q x` of the request's operator: a dict with `stiffness` and
/// `coupling` (CSC parts, see [`convert::csc`]) in `form` `"real"` (`4n × 4n`) or
/// `"complex"` (`2n × 2n`), `mass (n,)` and `scale`; relative to the surface
/// `(relative_to, F)` when given (`D_{f1,f2}`).
#[pyfunction]
#[pyo3(signature = (vertices, faces, request, form, relative_to = None))]
fn eigenproblem<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    request: Request,
    form: &str,
    relative_to: Option<PyReadonlyArray2<'py, f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mesh = convert::mesh(py, &vertices, &faces)?;
    let reference = reference_mesh(py, &mesh, &faces, relative_to)?;
    let options = request.options(py)?;
    let problem = run_detached(py, request.threads, || match &reference {
        Some(reference) => dirac::relative_eigenproblem(&mesh, reference, &options),
        None => dirac::eigenproblem(&mesh, &options),
    })?
    .map_err(|e| spectrum_error(py, &e))?;
    let dict = PyDict::new(py);
    match form {
        "real" => {
            dict.set_item(
                "stiffness",
                convert::csc(py, &problem.stiffness.to_real_block())?,
            )?;
            dict.set_item(
                "coupling",
                convert::csc(py, &problem.coupling.to_real_block())?,
            )?;
        }
        "complex" => {
            let stiffness = problem.stiffness.to_complex_adjoint();
            dict.set_item("stiffness", convert::csc(py, &stiffness)?)?;
            let coupling = problem.coupling.to_complex_adjoint();
            dict.set_item("coupling", convert::csc(py, &coupling)?)?;
        }
        other => {
            return Err(plain(
                py,
                Kind::Options,
                format!("unknown form {other:?}; expected \"real\" or \"complex\""),
            ));
        }
    }
    dict.set_item("mass", PyArray1::from_vec(py, problem.masses))?;
    dict.set_item("scale", problem.scale)?;
    Ok(dict)
}

/// The positive-semidefinite cotangent Laplacian `L (n × n)` (CSC parts) and the barycentric
/// vertex masses `(n,)`.
#[pyfunction]
fn laplacian<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyAny>)> {
    let mesh = convert::mesh(py, &vertices, &faces)?;
    let (l, masses) = py.detach(|| (cotan_laplacian(&mesh), barycentric_masses(&mesh)));
    Ok((
        convert::csc(py, &l.to_real_block())?,
        PyArray1::from_vec(py, masses).into_any(),
    ))
}

/// The geodesic distance from `sources` at every vertex (heat method).
#[pyfunction]
fn geodesic_distance<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    sources: Vec<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    let mesh = convert::mesh(py, &vertices, &faces)?;
    let distance = py
        .detach(|| dirac::well::geodesic_distance(&mesh, &sources))
        .map_err(|e| well_error(py, &e))?;
    Ok(PyArray1::from_vec(py, distance).into_any())
}

/// The potential `U` of the well at every vertex.
#[pyfunction]
fn potential_well<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    well: WellRequest,
) -> PyResult<Bound<'py, PyAny>> {
    let mesh = convert::mesh(py, &vertices, &faces)?;
    let well = well.well();
    let potential = py
        .detach(|| well.potential(&mesh))
        .map_err(|e| well_error(py, &e))?;
    Ok(PyArray1::from_vec(py, potential).into_any())
}

/// A descriptor table as `(values (n, columns), parameters (columns,))`.
fn table<'py>(py: Python<'py>, table: DescriptorTable) -> (Bound<'py, PyAny>, Bound<'py, PyAny>) {
    let (rows, columns) = (table.vertex_count(), table.column_count());
    let parameters = PyArray1::from_slice(py, table.parameters()).into_any();
    (
        convert::matrix(py, table.values().to_vec(), rows, columns),
        parameters,
    )
}

/// The heat (`kind = "heat"`: `Σ_i e^{−t λ_i} |φ_i(v)|²`, needs `λ ≥ 0`) or Dirac (`"dirac"`:
/// `Σ_i e^{−t |λ_i|} |φ_i(v)|²`) kernel signature at `times` (default: `count` times of Sun,
/// Ovsjanikov and Guibas).
#[pyfunction]
fn kernel_signature<'py>(
    py: Python<'py>,
    kind: &str,
    eigenvalues: PyReadonlyArray1<'py, f64>,
    eigenvectors: PyReadonlyArray3<'py, f64>,
    times: Option<PyReadonlyArray1<'py, f64>>,
    count: usize,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let signature = match kind {
        "heat" => descriptors::heat_kernel_signature,
        "dirac" => descriptors::dirac_kernel_signature,
        other => {
            return Err(plain(
                py,
                Kind::Options,
                format!("unknown kernel signature {other:?}; expected \"heat\" or \"dirac\""),
            ));
        }
    };
    let values = eigenvalues.as_slice()?.to_vec();
    let vectors = convert::eigenvectors(py, &eigenvectors)?;
    let times = times
        .map(|t| t.as_slice().map(<[f64]>::to_vec))
        .transpose()?;
    let computed = py.detach(|| {
        let modes = Modes::new(&values, &vectors)?;
        let times = match times {
            Some(times) => times,
            None => descriptors::default_times(&modes, count)?,
        };
        signature(&modes, &times)
    });
    Ok(table(py, computed.map_err(|e| descriptor_error(py, &e))?))
}

/// The wave kernel signature at log-energies `energies` with width `sigma` (default: the
/// sampling of Aubry, Schlickewei and Cremers with `count` energies).
#[pyfunction]
fn wave_kernel_signature<'py>(
    py: Python<'py>,
    eigenvalues: PyReadonlyArray1<'py, f64>,
    eigenvectors: PyReadonlyArray3<'py, f64>,
    energies: Option<PyReadonlyArray1<'py, f64>>,
    sigma: Option<f64>,
    count: usize,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, f64)> {
    let values = eigenvalues.as_slice()?.to_vec();
    let vectors = convert::eigenvectors(py, &eigenvectors)?;
    let energies = energies
        .map(|e| e.as_slice().map(<[f64]>::to_vec))
        .transpose()?;
    let computed = py.detach(|| {
        let modes = Modes::new(&values, &vectors)?;
        let default = descriptors::default_wave_sampling(&modes, count);
        let sampling = match (energies, sigma) {
            (Some(energies), Some(sigma)) => WaveSampling { energies, sigma },
            (Some(energies), None) => WaveSampling {
                energies,
                sigma: default?.sigma,
            },
            (None, Some(sigma)) => WaveSampling { sigma, ..default? },
            (None, None) => default?,
        };
        let table = descriptors::wave_kernel_signature(&modes, &sampling)?;
        Ok((table, sampling.sigma))
    });
    let (computed, sigma) = computed.map_err(|e| descriptor_error(py, &e))?;
    let (values, energies) = table(py, computed);
    Ok((values, energies, sigma))
}

/// The segmentation descriptor `|φ_j(v)| / √|λ_j|` over the nonzero modes.
#[pyfunction]
fn segmentation_descriptor<'py>(
    py: Python<'py>,
    eigenvalues: PyReadonlyArray1<'py, f64>,
    eigenvectors: PyReadonlyArray3<'py, f64>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let values = eigenvalues.as_slice()?.to_vec();
    let vectors = convert::eigenvectors(py, &eigenvectors)?;
    let computed = py.detach(|| {
        let modes = Modes::new(&values, &vectors)?;
        descriptors::segmentation_descriptor(&modes)
    });
    Ok(table(py, computed.map_err(|e| descriptor_error(py, &e))?))
}

/// The built-in default mesh (Keenan Crane's `spot`) as `(V, F)`.
#[pyfunction]
fn default_mesh(py: Python<'_>) -> (Bound<'_, PyAny>, Bound<'_, PyAny>) {
    convert::mesh_arrays(py, &dirac::default_mesh())
}

/// The compiled module.
#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = module.py();
    module.add("NativeError", py.get_type::<NativeError>())?;
    module.add("DEFAULT_FLAT_TOLERANCE", DEFAULT_FLAT_TOLERANCE)?;
    module.add("DEFAULT_MERGE_DISTANCE", DEFAULT_MERGE_DISTANCE)?;
    module.add("OPERATORS", Operator::names())?;
    for function in [
        wrap_pyfunction!(read_mesh, module)?,
        wrap_pyfunction!(write_mesh, module)?,
        wrap_pyfunction!(repair, module)?,
        wrap_pyfunction!(read_and_repair, module)?,
        wrap_pyfunction!(default_mesh, module)?,
        wrap_pyfunction!(spectrum, module)?,
        wrap_pyfunction!(eigenproblem, module)?,
        wrap_pyfunction!(laplacian, module)?,
        wrap_pyfunction!(geodesic_distance, module)?,
        wrap_pyfunction!(potential_well, module)?,
        wrap_pyfunction!(kernel_signature, module)?,
        wrap_pyfunction!(wave_kernel_signature, module)?,
        wrap_pyfunction!(segmentation_descriptor, module)?,
    ] {
        module.add_function(function)?;
    }
    Ok(())
}
