//! # dirac
//!
//! Triangle meshes and the operators of "A Dirac Operator for Extrinsic Shape Analysis"
//! (Liu, Jacobson, Crane, SGP 2017). This first part holds validated meshes, the icosphere
//! generator, and the real operators every spectrum needs: face areas, barycentric vertex
//! masses and the positive-semidefinite cotangent Laplacian.

pub mod generators;
pub mod geometry;
mod mesh;

pub use mesh::{MeshError, TriMesh};
