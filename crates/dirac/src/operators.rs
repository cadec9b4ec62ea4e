//! The paper's discrete operators (docs/MATH.md, "The operators"), assembled as sparse matrices.
//!
//! For a face `t = ijk` with cyclic shifts `(p, q, r) ∈ {(i,j,k), (j,k,i), (k,i,j)}`:
//!
//! ```text
//! (D_{f1,f2})_{t,p} = −(f2_r − f2_q) / (2 A_t)      (imaginary quaternion, A_t from f1)
//! B_{t,p} = 1/3,   M_F = diag(A_t),   M_V = diag(Ā_p)
//! A = D* M_F D,    G = sym(Bᵀ M_F D) = (Bᵀ M_F D + (Bᵀ M_F D)*)/2
//! ```
//!
//! `D_N = D_{f,N}` uses vertex normals, `D_f = D_{f,f}` positions. `D 𝟙 = 0` on every mesh
//! because the three differences `f2_r − f2_q` of a face sum to zero. All matrices act by left
//! multiplication on quaternion vectors (docs/ARCHITECTURE.md, "Conventions").

use qscalar::Quat;
use qsparse::{SparseError, SparseMatrix, TripletMatrix};
use thiserror::Error;

use crate::TriMesh;
use crate::geometry::{barycentric_masses, face_areas, sub, vertex_normals};

/// Why an operator could not be assembled.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum OperatorError {
    /// Per-vertex values of the wrong length.
    #[error("expected {expected} per-vertex values, found {found}")]
    VertexValueCount {
        /// Number of vertices.
        expected: usize,
        /// Number of values given.
        found: usize,
    },
    /// Per-face values of the wrong length.
    #[error("expected {expected} per-face values, found {found}")]
    FaceValueCount {
        /// Number of faces.
        expected: usize,
        /// Number of values given.
        found: usize,
    },
    /// A per-vertex value is NaN or infinite.
    #[error("the value at vertex {vertex} is not finite")]
    NonFiniteValue {
        /// The vertex.
        vertex: usize,
    },
    /// The area-weighted normal of a vertex vanishes.
    #[error("the area-weighted normal of vertex {vertex} vanishes")]
    DegenerateNormal {
        /// The vertex.
        vertex: usize,
    },
    /// A sparse-matrix operation failed (a bug if it happens: shapes are built consistently).
    #[error(transparent)]
    Sparse(#[from] SparseError),
}

fn imaginary(v: [f64; 3]) -> Quat<f64> {
    Quat::from_vector(v)
}

/// The cyclic shifts `(p, q, r)` of a face.
fn cyclic_shifts([i, j, k]: [usize; 3]) -> [(usize, usize, usize); 3] {
    [(i, j, k), (j, k, i), (k, i, j)]
}

/// The relative Dirac operator `D_{f1,f2}` (`|F| × |V|`, quaternionic), with `f1` the mesh
/// positions and `f2` the given per-vertex values (docs/MATH.md, "The operators"):
/// `(D ψ)_t = −(1/(2A_t)) Σ_{(p,q,r)∈C(t)} (f2_r − f2_q) ψ_p`.
pub fn relative_dirac(
    mesh: &TriMesh,
    f2: &[[f64; 3]],
) -> Result<SparseMatrix<Quat<f64>>, OperatorError> {
    if f2.len() != mesh.vertex_count() {
        return Err(OperatorError::VertexValueCount {
            expected: mesh.vertex_count(),
            found: f2.len(),
        });
    }
    if let Some(vertex) = f2.iter().position(|v| v.iter().any(|c| !c.is_finite())) {
        return Err(OperatorError::NonFiniteValue { vertex });
    }
    let mut d = TripletMatrix::with_capacity(
        mesh.face_count(),
        mesh.vertex_count(),
        3 * mesh.face_count(),
    );
    for (t, &face) in mesh.faces().iter().enumerate() {
        let scale = -1.0 / (2.0 * mesh.face_area(t));
        for (p, q, r) in cyclic_shifts(face) {
            d.push(t, p, imaginary(sub(f2[r], f2[q])) * scale)?;
        }
    }
    Ok(d.to_csc())
}

/// The relative Dirac operator `D_N = D_{f,N}` with area-weighted vertex normals.
pub fn normal_dirac(mesh: &TriMesh) -> Result<SparseMatrix<Quat<f64>>, OperatorError> {
    let normals =
        vertex_normals(mesh).map_err(|vertex| OperatorError::DegenerateNormal { vertex })?;
    relative_dirac(mesh, &normals)
}

/// The extrinsic Dirac operator `D_f = D_{f,f}` of Crane, Pinkall and Schröder (2011).
pub fn extrinsic_dirac(mesh: &TriMesh) -> Result<SparseMatrix<Quat<f64>>, OperatorError> {
    relative_dirac(mesh, mesh.positions())
}

/// The vertex-to-face averaging operator `B` (`|F| × |V|`, real): `B_{t,p} = 1/3` for `p ∈ t`.
pub fn averaging(mesh: &TriMesh) -> SparseMatrix<f64> {
    let mut b = TripletMatrix::with_capacity(
        mesh.face_count(),
        mesh.vertex_count(),
        3 * mesh.face_count(),
    );
    for (t, face) in mesh.faces().iter().enumerate() {
        for &p in face {
            b.push(t, p, 1.0 / 3.0)
                .expect("face indices of a validated mesh are in range");
        }
    }
    b.to_csc()
}

/// The face mass `M_F = diag(A_t)`.
pub fn face_mass(mesh: &TriMesh) -> SparseMatrix<f64> {
    SparseMatrix::from_diagonal(&face_areas(mesh))
}

/// The barycentric vertex mass `M_V = diag(Ā_p)`.
pub fn vertex_mass(mesh: &TriMesh) -> SparseMatrix<f64> {
    SparseMatrix::from_diagonal(&barycentric_masses(mesh))
}

/// A real matrix as a quaternionic one acting componentwise (`X ⊗ I₄`).
pub fn quaternionic(x: &SparseMatrix<f64>) -> SparseMatrix<Quat<f64>> {
    x.map(Quat::from_real)
}

/// The two Hermitian matrices of a Dirac pencil (docs/MATH.md, "The operators"): the stiffness
/// `A = D* M_F D` (positive semidefinite) and the coupling `G = sym(Bᵀ M_F D)`.
#[derive(Debug, Clone)]
pub struct DiracPencil {
    /// `A = D* M_F D`.
    pub stiffness: SparseMatrix<Quat<f64>>,
    /// `G = (Bᵀ M_F D + (Bᵀ M_F D)*)/2`.
    pub coupling: SparseMatrix<Quat<f64>>,
}

impl DiracPencil {
    /// Assembles `A` and `G` from `D` (`|F| × |V|`) on `mesh`.
    pub fn new(mesh: &TriMesh, d: &SparseMatrix<Quat<f64>>) -> Result<Self, OperatorError> {
        let weighted = d.scale_rows(&face_areas(mesh))?;
        let stiffness = d.adjoint().matmul(&weighted)?;
        let averaged = quaternionic(&averaging(mesh)).adjoint().matmul(&weighted)?;
        let half = Quat::from_real(0.5);
        let coupling =
            SparseMatrix::linear_combination(half, &averaged, half, &averaged.adjoint())?;
        Ok(Self {
            stiffness,
            coupling,
        })
    }
}
