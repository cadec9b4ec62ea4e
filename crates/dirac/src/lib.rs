//! # dirac
//!
//! Triangle meshes and the operators of "A Dirac Operator for Extrinsic Shape Analysis"
//! (Liu, Jacobson, Crane, SGP 2017). This first part holds validated meshes, the icosphere
//! generator, and the real operators every spectrum needs: face areas, barycentric vertex
//! masses and the positive-semidefinite cotangent Laplacian.

pub mod curvature;
pub mod descriptors;
mod disjoint_sets;
pub mod generators;
pub mod geometry;
pub mod io;
mod mesh;
pub mod operators;
pub mod phase;
pub mod spectrum;
mod topology;
pub mod well;

pub use io::default_mesh;
pub use mesh::{Edge, MeshError, TriMesh};
pub use topology::{Component, Topology};
