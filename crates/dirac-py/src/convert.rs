//! numpy arrays to and from the library's types. The Python package hands over C-contiguous
//! `float64 (n, 3)` positions and `int64 (m, 3)` faces (it converts any other dtype or order);
//! shapes are checked again here, so that the native module is safe to call directly.

use dirac::io::RawMesh;
use dirac::repair::Repaired;
use dirac::{Spectrum, TriMesh};
use faer::sparse::SparseColMat;
use ndarray::{Array2, Array3, ArrayView3};
use numpy::{Element, IntoPyArray, PyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use qscalar::Quat;

use crate::error::{Kind, mesh_error, plain};

/// Positions and faces as numpy holds them (negative indices possible).
type Rows = (Vec<[f64; 3]>, Vec<[i64; 3]>);

/// The rows of `vertices (n, 3)` and `faces (m, 3)`, shapes checked.
fn rows(
    py: Python<'_>,
    vertices: &PyReadonlyArray2<'_, f64>,
    faces: &PyReadonlyArray2<'_, i64>,
) -> PyResult<Rows> {
    let (v, f) = (vertices.as_array(), faces.as_array());
    for (name, shape) in [("V", v.shape()), ("F", f.shape())] {
        if shape[1] != 3 {
            return Err(plain(
                py,
                Kind::Options,
                format!("{name} must have shape (n, 3), found {shape:?}"),
            ));
        }
    }
    Ok((
        v.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect(),
        f.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect(),
    ))
}

/// Positions `vertices (n, 3)` and faces `faces (m, 3)`, not validated: a negative index
/// becomes `usize::MAX`, out of range like any index `≥ n` (for [`dirac::repair`]).
pub fn raw_mesh(
    py: Python<'_>,
    vertices: &PyReadonlyArray2<'_, f64>,
    faces: &PyReadonlyArray2<'_, i64>,
) -> PyResult<RawMesh> {
    let (positions, faces) = rows(py, vertices, faces)?;
    let faces = faces
        .iter()
        .map(|f| f.map(|i| usize::try_from(i).unwrap_or(usize::MAX)))
        .collect();
    Ok(RawMesh { positions, faces })
}

/// The mesh of positions `vertices (n, 3)` and faces `faces (m, 3)`.
pub fn mesh(
    py: Python<'_>,
    vertices: &PyReadonlyArray2<'_, f64>,
    faces: &PyReadonlyArray2<'_, i64>,
) -> PyResult<TriMesh> {
    let (positions, f) = rows(py, vertices, faces)?;
    let mut triangles = Vec::with_capacity(f.len());
    for (face, row) in f.iter().enumerate() {
        let mut corners = [0; 3];
        for (corner, &index) in corners.iter_mut().zip(row) {
            *corner = usize::try_from(index).map_err(|_| {
                plain(
                    py,
                    Kind::InvalidMesh,
                    format!("face {face} refers to vertex {index}; indices start at 0"),
                )
            })?;
        }
        triangles.push(corners);
    }
    TriMesh::new(positions, triangles).map_err(|e| mesh_error(py, Kind::InvalidMesh, &e, &e))
}

/// `(V, F)` of a mesh: `float64 (n, 3)` and `int64 (m, 3)`.
pub fn mesh_arrays<'py>(py: Python<'py>, mesh: &TriMesh) -> (Bound<'py, PyAny>, Bound<'py, PyAny>) {
    let positions: Vec<f64> = mesh.positions().iter().flatten().copied().collect();
    let faces: Vec<i64> = mesh.faces().iter().flatten().map(|&i| index(i)).collect();
    (
        matrix(py, positions, mesh.vertex_count(), 3),
        matrix(py, faces, mesh.face_count(), 3),
    )
}

/// A repaired mesh as a dict: `vertices`, `faces`, `vertex_origin`, `face_origin` (int64
/// arrays), `report` (the report as JSON text) and `summary` (its lines).
pub fn repaired_dict<'py>(py: Python<'py>, repaired: &Repaired) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let (vertices, faces) = mesh_arrays(py, &repaired.mesh);
    dict.set_item("vertices", vertices)?;
    dict.set_item("faces", faces)?;
    for (name, origin) in [
        ("vertex_origin", &repaired.vertex_origin),
        ("face_origin", &repaired.face_origin),
    ] {
        let origin: Vec<i64> = origin.iter().map(|&i| index(i)).collect();
        dict.set_item(name, PyArray1::from_vec(py, origin))?;
    }
    let report = serde_json::to_string(&repaired.report)
        .map_err(|e| plain(py, Kind::Solver, format!("the repair report: {e}")))?;
    dict.set_item("report", report)?;
    dict.set_item("summary", repaired.report.to_string())?;
    Ok(dict)
}

/// A vertex or face index as numpy stores it.
fn index(i: usize) -> i64 {
    i64::try_from(i).expect("an index of an in-memory array fits in i64")
}

/// A C-ordered `(rows, columns)` array of `values`.
pub fn matrix<T: Element>(
    py: Python<'_>,
    values: Vec<T>,
    rows: usize,
    columns: usize,
) -> Bound<'_, PyAny> {
    Array2::from_shape_vec((rows, columns), values)
        .expect("rows · columns values")
        .into_pyarray(py)
        .into_any()
}

/// Eigenvectors as one `(n, k, 4)` array: `[p, i, :]` is `(w, x, y, z)` of `φ_i` at vertex `p`.
pub fn eigenvector_array<'py>(
    py: Python<'py>,
    eigenvectors: &[Vec<Quat<f64>>],
    n: usize,
) -> Bound<'py, PyAny> {
    let k = eigenvectors.len();
    let mut values = Vec::with_capacity(n * k * 4);
    for p in 0..n {
        for phi in eigenvectors {
            let q = phi[p];
            values.extend([q.w, q.x, q.y, q.z]);
        }
    }
    Array3::from_shape_vec((n, k, 4), values)
        .expect("n · k · 4 values")
        .into_pyarray(py)
        .into_any()
}

/// The `k` eigenvectors of an `(n, k, 4)` array.
pub fn eigenvectors(
    py: Python<'_>,
    array: &PyReadonlyArray3<'_, f64>,
) -> PyResult<Vec<Vec<Quat<f64>>>> {
    let a: ArrayView3<f64> = array.as_array();
    let (n, k, four) = a.dim();
    if four != 4 {
        return Err(plain(
            py,
            Kind::Options,
            format!(
                "eigenvectors must have shape (n, k, 4) (w, x, y, z per vertex), found {:?}",
                a.shape()
            ),
        ));
    }
    Ok((0..k)
        .map(|i| {
            (0..n)
                .map(|p| Quat::new(a[[p, i, 0]], a[[p, i, 1]], a[[p, i, 2]], a[[p, i, 3]]))
                .collect()
        })
        .collect())
}

/// A sparse matrix as the CSC arrays of `scipy.sparse.csc_array((data, indices, indptr),
/// shape)`: a dict with those four keys.
pub fn csc<'py, T: Element + Copy>(
    py: Python<'py>,
    matrix: &SparseColMat<usize, T>,
) -> PyResult<Bound<'py, PyDict>> {
    let m = matrix.as_ref();
    let index = |v: &[usize]| -> Vec<i64> {
        v.iter()
            .map(|&i| i64::try_from(i).expect("a sparse index fits in i64"))
            .collect()
    };
    let dict = PyDict::new(py);
    dict.set_item("data", PyArray1::from_slice(py, m.val()))?;
    dict.set_item("indices", PyArray1::from_vec(py, index(m.row_idx())))?;
    dict.set_item("indptr", PyArray1::from_vec(py, index(m.col_ptr())))?;
    dict.set_item("shape", (m.nrows(), m.ncols()))?;
    Ok(dict)
}

/// The fields of a spectrum as a dict of arrays and numbers (`eigenvectors` only if asked).
pub fn spectrum_dict<'py>(
    py: Python<'py>,
    spectrum: &Spectrum,
    with_eigenvectors: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item(
        "eigenvalues",
        PyArray1::from_slice(py, &spectrum.eigenvalues),
    )?;
    dict.set_item("residuals", PyArray1::from_slice(py, &spectrum.residuals))?;
    dict.set_item(
        "backward_errors",
        PyArray1::from_slice(py, &spectrum.backward_errors),
    )?;
    dict.set_item("backward_error_floor", spectrum.backward_error_floor)?;
    let eigenvectors = with_eigenvectors
        .then(|| eigenvector_array(py, &spectrum.eigenvectors, spectrum.masses.len()));
    dict.set_item("eigenvectors", eigenvectors)?;
    dict.set_item("mass", PyArray1::from_slice(py, &spectrum.masses))?;
    dict.set_item("scale", spectrum.scale)?;
    dict.set_item("kernel_dimension", spectrum.kernel.dimension)?;
    dict.set_item("kernel_flat_vertices", spectrum.kernel.flat_vertices)?;
    dict.set_item("kernel_constants", spectrum.kernel.constants)?;
    dict.set_item("kernel_linear_functions", spectrum.kernel.linear_functions)?;
    dict.set_item("kernel_ruling_functions", spectrum.kernel.ruling_functions)?;
    let s = &spectrum.statistics;
    let statistics = PyDict::new(py);
    statistics.set_item("iterations", s.iterations)?;
    statistics.set_item("restarts", s.restarts)?;
    statistics.set_item("rounds", s.rounds)?;
    statistics.set_item("operator_applications", s.operator_applications)?;
    statistics.set_item("solves", s.solves)?;
    statistics.set_item("locked", s.locked)?;
    statistics.set_item("basis_columns_read", s.basis_columns_read)?;
    statistics.set_item("factor_bytes", s.factor_bytes)?;
    statistics.set_item("basis_bytes", s.basis_bytes)?;
    statistics.set_item("factorization_seconds", s.factorization_time.as_secs_f64())?;
    statistics.set_item("solve_seconds", s.solve_time.as_secs_f64())?;
    statistics.set_item(
        "orthogonalization_seconds",
        s.orthogonalization_time.as_secs_f64(),
    )?;
    statistics.set_item("total_seconds", s.total_time.as_secs_f64())?;
    dict.set_item("statistics", statistics)?;
    Ok(dict)
}
