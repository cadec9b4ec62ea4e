//! Validated triangle meshes.

use thiserror::Error;

/// Why a mesh was rejected. Each variant names the offending element.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The mesh has no vertices or no faces.
    #[error("mesh is empty ({vertices} vertices, {faces} faces)")]
    Empty {
        /// Number of vertices.
        vertices: usize,
        /// Number of faces.
        faces: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but the mesh has {vertex_count} vertices")]
    IndexOutOfRange {
        /// The face.
        face: usize,
        /// The bad index.
        vertex: usize,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// A face uses one vertex twice.
    #[error("face {face} repeats vertex {vertex}")]
    RepeatedIndex {
        /// The face.
        face: usize,
        /// The repeated vertex.
        vertex: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// The vertex.
        vertex: usize,
    },
    /// A face has zero area.
    #[error("face {face} has zero area")]
    ZeroAreaFace {
        /// The face.
        face: usize,
    },
}

/// A triangle mesh: vertex positions and counter-clockwise faces (as seen from the side the
/// normals point to).
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    positions: Vec<[f64; 3]>,
    faces: Vec<[usize; 3]>,
}

impl TriMesh {
    /// Builds and validates a mesh: non-empty, indices in range and distinct within each face,
    /// finite coordinates, faces of non-zero area.
    pub fn new(positions: Vec<[f64; 3]>, faces: Vec<[usize; 3]>) -> Result<Self, MeshError> {
        if positions.is_empty() || faces.is_empty() {
            return Err(MeshError::Empty {
                vertices: positions.len(),
                faces: faces.len(),
            });
        }
        if let Some(vertex) = positions
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))
        {
            return Err(MeshError::NonFiniteCoordinate { vertex });
        }
        for (face, f) in faces.iter().enumerate() {
            if let Some(&vertex) = f.iter().find(|&&v| v >= positions.len()) {
                return Err(MeshError::IndexOutOfRange {
                    face,
                    vertex,
                    vertex_count: positions.len(),
                });
            }
            if f[0] == f[1] || f[0] == f[2] {
                return Err(MeshError::RepeatedIndex { face, vertex: f[0] });
            }
            if f[1] == f[2] {
                return Err(MeshError::RepeatedIndex { face, vertex: f[1] });
            }
        }
        let mesh = Self { positions, faces };
        if let Some(face) = (0..mesh.faces.len()).find(|&t| mesh.face_area(t) <= 0.0) {
            return Err(MeshError::ZeroAreaFace { face });
        }
        Ok(mesh)
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }

    /// Faces (vertex index triples, counter-clockwise).
    pub fn faces(&self) -> &[[usize; 3]] {
        &self.faces
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Area of face `t`, `|(f_j − f_i) × (f_k − f_i)| / 2`.
    pub fn face_area(&self, t: usize) -> f64 {
        let [i, j, k] = self.faces[t];
        let (a, b, c) = (self.positions[i], self.positions[j], self.positions[k]);
        crate::geometry::norm(crate::geometry::cross(
            crate::geometry::sub(b, a),
            crate::geometry::sub(c, a),
        )) / 2.0
    }
}
