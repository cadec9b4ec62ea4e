//! # dirac
//!
//! Triangle meshes and the operators of "A Dirac Operator for Extrinsic Shape Analysis"
//! (Liu, Jacobson, Crane, SGP 2017), and their spectra: the relative Dirac operator `D_N`, the
//! extrinsic Dirac operator `D_f`, the cotangent Laplacian, the family `L(τ)` between them, the
//! squared operator, the modified Dirichlet energy, the anisotropic Laplacian of Andreux et al.
//! and the infinite potential well, solved over
//! the quaternions by `qeig`; canonical eigenvectors and the descriptors built on them.
//!
//! One call gives a spectrum:
//!
//! ```
//! use dirac::{Operator, SpectrumOptions};
//!
//! let mesh = dirac::default_mesh(); // Keenan Crane's spot, 2930 vertices
//! let spectrum = dirac::spectrum(&mesh, &SpectrumOptions::new(Operator::RelativeDirac, 10))?;
//! // Signed eigenvalues sorted by |λ|; one quaternion per vertex in each eigenvector.
//! assert_eq!(spectrum.eigenvalues.len(), 10);
//! assert_eq!(spectrum.eigenvectors[0].len(), mesh.vertex_count());
//! # Ok::<(), dirac::SpectrumError>(())
//! ```
//!
//! | module | what it holds |
//! |---|---|
//! | [`TriMesh`], [`io`], [`generators`] | validated meshes; OBJ, OFF, PLY and STL files; spheres, tori, patches |
//! | [`repair`](mod@repair) | meshes as downloaded made valid: merged vertices, degenerate faces dropped, non-manifold elements split, faces oriented, with a report |
//! | [`geometry`], [`curvature`], [`operators`], [`anisotropic`] | areas, masses, the cotangent Laplacian, `D_N`, `D_f`, curvature, the anisotropic Laplacian |
//! | [`spectrum`](mod@spectrum) | each operator's eigenproblem and its solution ([`spectrum()`], [`eigenproblem`]) |
//! | [`phase`] | mass inner products and the canonical phase of eigenvectors |
//! | [`well`] | geodesic distance (heat method) and the potential well of paper §5.1 |
//! | [`descriptors`] | heat, Dirac and wave kernel signatures, the segmentation descriptor |
//! | [`clustering`] | k-means (Lloyd; uniform or k-means++ start) of flat row-major points |
//! | [`segmentation`] | per-face segmentations: consensus segmentation, the benchmark's `.seg` files and its error measures |
//!
//! The mathematics, with every convention and sign, is in `docs/MATH.md` of the repository;
//! the layers (`qscalar` → `qsparse` → `qeig` → `dirac`) in `docs/ARCHITECTURE.md`.

pub mod anisotropic;
pub mod clustering;
pub mod curvature;
pub mod descriptors;
pub mod generators;
pub mod geometry;
pub mod io;
mod mesh;
pub mod operators;
pub mod phase;
pub mod repair;
pub mod segmentation;
pub mod spectrum;
mod topology;
pub mod well;

pub use io::default_mesh;
pub use mesh::{ConnectivityMismatch, Edge, MeshError, TriMesh};
pub use spectrum::{
    Eigenproblem, Normalization, Operator, OperatorNameError, Parameter, ParseOperatorError,
    Remedy, SecondSurface, SolverBackend, Spectrum, SpectrumError, SpectrumOptions, Unaccepted,
    eigenproblem, relative_eigenproblem, relative_spectrum, scale_warning, spectrum,
};
pub use topology::{
    Component, ComponentError, ComponentSelection, ComponentSelectionParseError, Topology,
};
