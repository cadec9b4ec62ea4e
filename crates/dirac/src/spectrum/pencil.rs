//! One value per row of the pencil table (module documentation of [`super`]): the operator's
//! own eigenproblem `P x = λ Q x`, the matrices that are solved, and how, over the scalar the
//! operator is assembled in ([`OperatorPencil`]).

use std::sync::Arc;

use qscalar::{Quat, Scalar};
use qsparse::{SparseCholesky, SparseMatrix, SparseVector, SymbolicCholesky};

use super::kernel::{Reduction, flat_faces, pieces, vanishing_faces};
use super::{Operator, SecondSurface, SpectrumError};
use crate::TriMesh;
use crate::anisotropic::anisotropic_laplacian;
use crate::curvature::willmore_potential;
use crate::geometry::{
    barycentric_masses, cotan_laplacian, cross, dot, norm, normalize, sub, vertex_normals,
};
use crate::operators::{DiracPencil, OperatorError, extrinsic_dirac, quaternionic, relative_dirac};
use crate::well::{dirac_with_well, laplacian_with_well};

/// How a pencil `P x = λ Q x` is turned into a Hermitian-definite one for `qeig`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Form {
    /// `Q` positive definite, `P` semidefinite: `Q x = μ (P + εQ) x`, `λ = 1/μ − ε`.
    Shifted {
        /// The shift `ε`.
        epsilon: f64,
    },
    /// `P` semidefinite, `Q` indefinite: with the kernel of `P` removed (flat vertices
    /// dropped, each constant pinned at one vertex of its piece), `Q' y = μ P y` (`P` is then
    /// positive definite), `λ = y*Py / y*Q'y`, where `Q'` is `Q` compressed to the eigenvectors'
    /// subspace ([`super::kernel::Coupling`]).
    Pinned,
    /// `Q = M`, `P` indefinite: `M x = μ (P + σM) x`, `λ = 1/μ − σ`, collected from the bottom
    /// of the spectrum until the `k` of smallest `|λ|` are certain.
    Literal {
        /// A shift `σ` that makes `P + σM` positive definite, as small as a factorisation
        /// allows (`definite_shift`).
        sigma: f64,
    },
}

/// The two matrices of a pencil `P x = λ Q x` over the scalar `T`.
#[derive(Debug, Clone)]
pub(super) struct Matrices<T> {
    /// `P`.
    pub stiffness: SparseMatrix<T>,
    /// `Q`.
    pub coupling: SparseMatrix<T>,
}

impl Matrices<f64> {
    /// `P⊗I` and `Q⊗I` over the quaternions.
    fn lifted(&self) -> Matrices<Quat<f64>> {
        Matrices {
            stiffness: quaternionic(&self.stiffness),
            coupling: quaternionic(&self.coupling),
        }
    }
}

/// Everything that differs between operators, for a pencil over the scalar `T`.
#[derive(Debug, Clone)]
pub(super) struct PencilSpec<T> {
    /// The operator's own eigenproblem, as assembled: residuals are measured against it.
    pub operator: Matrices<T>,
    /// The same with the rows of flat faces of `D` set to zero, when any face is flat: the
    /// matrices that are solved, whose kernel is then exact.
    pub exact: Option<Matrices<T>>,
    /// Per face: its row of the first-order operator is set to zero, because the face is flat
    /// and around a flat vertex (all `false` without a first-order operator).
    pub flat: Vec<bool>,
    /// The Gauss map `N` that decides flatness (relative Dirac operators).
    pub normals: Option<Vec<[f64; 3]>>,
    /// The linear functions of the second surface the first-order operator annihilates
    /// (operators built on one).
    pub linear: Option<LinearKernel<T>>,
    /// How the pencil is solved.
    pub form: Form,
}

/// The linear functions `u f2` a first-order operator `D_{f,f2}` annihilates besides the
/// constants, on the pieces where every triangle of `f2` is parallel to one direction `u`
/// ([`parallel_faces`]; docs/MATH.md, "The exact kernel").
#[derive(Debug, Clone)]
pub(super) struct LinearKernel<T> {
    /// Which surface `f2` is.
    pub surface: SecondSurface,
    /// `u (f2 − f̄2)` on each such piece with no triangle a segment, `f̄2` the mass-weighted mean
    /// over the piece (so the mode is mass-orthogonal to its constant): the kernel there is
    /// exactly the constants and this function.
    pub modes: Vec<SparseVector<T>>,
    /// A piece where some triangles are segments, which may leave more of the kernel than
    /// `u f2` (functions constant along the rulings of a crease or a cylinder): its smallest
    /// vertex and `u` (`None`: every triangle a segment). The pinned form stops there.
    pub unremoved: Option<(usize, Option<[f64; 3]>)>,
}

/// An operator's pencil over the scalar it is assembled in.
///
/// Realness is decided by the operator, at assembly, rather than by inspecting the matrices: a
/// real operator (Laplace, anisotropic Laplace, modified Dirichlet, with or without a well) is
/// assembled as `SparseMatrix<f64>` and never lifted to `L⊗I`, so the test is exact and free,
/// and no quaternionic copy of its matrices is built (four times the memory and the assembly
/// time). Scanning assembled quaternionic matrices for zero imaginary parts would instead need
/// that copy first, and would decide by a floating-point test what is known by construction.
/// The Dirac operators and the family for `τ > 0` (at `τ = 0` it is Laplace) are quaternionic
/// even where a mesh makes some of their entries real.
#[derive(Debug, Clone)]
pub(super) enum OperatorPencil {
    /// A real operator: `P` and `Q` real symmetric; its quaternionic form is `P⊗I`, `Q⊗I`.
    Real(PencilSpec<f64>),
    /// A quaternionic operator.
    Quaternionic(PencilSpec<Quat<f64>>),
}

impl OperatorPencil {
    /// The pencil of `operator` on `mesh` with an optional well potential; faces whose corner
    /// normals agree within `flat_tolerance` are flat. With a `reference` surface `f2` (one
    /// point per vertex), the operators built on `D_N = D_{f,N}` are built on `D_{f,f2}`
    /// instead.
    pub fn for_operator(
        operator: Operator,
        mesh: &TriMesh,
        reference: Option<&[[f64; 3]]>,
        potential: Option<&[f64]>,
        flat_tolerance: f64,
    ) -> Result<Self, SpectrumError> {
        let masses = barycentric_masses(mesh);
        let real_mass = || SparseMatrix::from_diagonal(&masses);
        let laplacian = |base: SparseMatrix<f64>| -> Result<_, SpectrumError> {
            Ok(match potential {
                Some(u) => laplacian_with_well(mesh, &base, u)?,
                None => base,
            })
        };
        let real = |stiffness: SparseMatrix<f64>| {
            Self::Real(PencilSpec::shifted(
                stiffness,
                real_mass(),
                &masses,
                potential,
                mesh,
            ))
        };
        let mass = || quaternionic(&real_mass());
        let relative = reference.map_or(SecondImmersion::GaussMap, SecondImmersion::Surface);
        let dirac = |second: SecondImmersion| {
            FirstOrder::assemble(mesh, &masses, second, potential, flat_tolerance)
        };
        let spec = match operator {
            Operator::Laplace | Operator::Family { tau: 0.0 } => {
                return Ok(real(laplacian(cotan_laplacian(mesh))?));
            }
            Operator::AnisotropicLaplace { anisotropy } => {
                return Ok(real(laplacian(anisotropic_laplacian(mesh, anisotropy)?)?));
            }
            Operator::ModifiedDirichlet => {
                return Ok(real(laplacian(modified_dirichlet(mesh, &masses)?)?));
            }
            Operator::Squared => dirac(relative)?.squared(mass(), &masses, potential, mesh),
            Operator::RelativeDirac | Operator::Family { tau: 1.0 } => dirac(relative)?.pinned(),
            Operator::ExtrinsicDirac => dirac(SecondImmersion::Positions)?.pinned(),
            Operator::Family { tau } => {
                // `L` does not vanish on flat faces: no face is flat for the blend.
                let first = dirac(relative)?.operator;
                let l = quaternionic(&laplacian(cotan_laplacian(mesh))?);
                let matrices = Matrices {
                    stiffness: blend(tau, &first.stiffness, &l)?,
                    coupling: blend(tau, &first.coupling, &mass())?,
                };
                PencilSpec::plain(matrices, Form::Pinned, mesh)
            }
            Operator::FamilyLiteral { tau } => {
                let first = dirac(relative)?.operator;
                let l = quaternionic(&laplacian(cotan_laplacian(mesh))?);
                let stiffness = blend(tau, &first.coupling, &l)?;
                let sigma = definite_shift(&stiffness, &masses);
                let matrices = Matrices {
                    stiffness,
                    coupling: mass(),
                };
                PencilSpec::plain(matrices, Form::Literal { sigma }, mesh)
            }
        };
        Ok(Self::Quaternionic(spec))
    }

    /// The pencil over the quaternions: a real one as `P⊗I`, `Q⊗I`.
    pub fn into_quaternionic(self) -> PencilSpec<Quat<f64>> {
        match self {
            Self::Real(spec) => PencilSpec {
                operator: spec.operator.lifted(),
                exact: spec.exact.as_ref().map(Matrices::lifted),
                flat: spec.flat,
                normals: spec.normals,
                linear: None,
                form: spec.form,
            },
            Self::Quaternionic(spec) => spec,
        }
    }
}

impl<T: Scalar<Real = f64>> PencilSpec<T> {
    /// A pencil with no flat faces.
    fn plain(operator: Matrices<T>, form: Form, mesh: &TriMesh) -> Self {
        Self {
            operator,
            exact: None,
            flat: vec![false; mesh.face_count()],
            normals: None,
            linear: None,
            form,
        }
    }

    /// `P x = λ M x` with `P` semidefinite, in shifted form.
    fn shifted(
        stiffness: SparseMatrix<T>,
        mass: SparseMatrix<T>,
        masses: &[f64],
        potential: Option<&[f64]>,
        mesh: &TriMesh,
    ) -> Self {
        let epsilon = regularization(&stiffness, masses, potential);
        let operator = Matrices {
            stiffness,
            coupling: mass,
        };
        Self::plain(operator, Form::Shifted { epsilon }, mesh)
    }

    /// The matrices that are solved.
    pub fn solved(&self) -> &Matrices<T> {
        self.exact.as_ref().unwrap_or(&self.operator)
    }
}

/// The second immersion `f2` of the first-order operator `D_{f,f2}` a Dirac pencil is built on.
#[derive(Debug, Clone, Copy, PartialEq)]
enum SecondImmersion<'a> {
    /// The Gauss map `N` (area-weighted vertex normals): `D_N`.
    GaussMap,
    /// The positions `f` themselves: `D_f`.
    Positions,
    /// Another surface with the same triangulation: `D_{f1,f2}`.
    Surface(&'a [[f64; 3]]),
}

/// A Dirac pencil `A = D* M_F D`, `G = sym(Bᵀ M_F D)`, as assembled and with the rows of flat
/// faces of `D` set to zero.
struct FirstOrder {
    operator: Matrices<Quat<f64>>,
    exact: Option<Matrices<Quat<f64>>>,
    flat: Vec<bool>,
    normals: Option<Vec<[f64; 3]>>,
    linear: LinearKernel<Quat<f64>>,
}

impl FirstOrder {
    fn assemble(
        mesh: &TriMesh,
        masses: &[f64],
        second: SecondImmersion,
        potential: Option<&[f64]>,
        flat_tolerance: f64,
    ) -> Result<Self, SpectrumError> {
        let (d, normals) = match second {
            SecondImmersion::GaussMap => {
                let normals = vertex_normals(mesh)
                    .map_err(|vertex| OperatorError::DegenerateNormal { vertex })?;
                (relative_dirac(mesh, &normals)?, Some(normals))
            }
            // The rows of `D_f` are edge vectors over twice the area: never zero.
            SecondImmersion::Positions => (extrinsic_dirac(mesh)?, None),
            // Nor are those of a surface's, whose faces have positive area
            // ([`TriMesh::check_same_connectivity`] paired it with `mesh`).
            SecondImmersion::Surface(f2) => (relative_dirac(mesh, f2)?, None),
        };
        let d = match potential {
            Some(u) => dirac_with_well(mesh, &d, u)?,
            None => d,
        };
        let flat = match &normals {
            Some(normals) => {
                vanishing_faces(mesh, &flat_faces(mesh, normals, potential, flat_tolerance))
            }
            None => vec![false; mesh.face_count()],
        };
        let pencil = |d: &SparseMatrix<Quat<f64>>| -> Result<Matrices<_>, SpectrumError> {
            let p = DiracPencil::new(mesh, d)?;
            Ok(Matrices {
                stiffness: p.stiffness,
                coupling: p.coupling,
            })
        };
        let exact = if flat.iter().any(|&f| f) {
            let keep: Vec<f64> = flat.iter().map(|&f| if f { 0.0 } else { 1.0 }).collect();
            Some(pencil(&d.scale_rows(&keep).map_err(OperatorError::from)?)?)
        } else {
            None
        };
        let (f2, surface) = match second {
            SecondImmersion::GaussMap => (normals.as_deref(), SecondSurface::GaussMap),
            SecondImmersion::Positions => (Some(mesh.positions()), SecondSurface::Mesh),
            SecondImmersion::Surface(f2) => (Some(f2), SecondSurface::Reference),
        };
        let linear = linear_kernel(mesh, masses, f2.unwrap_or_default(), &flat, surface);
        Ok(Self {
            operator: pencil(&d)?,
            exact,
            flat,
            normals,
            linear,
        })
    }

    /// `A x = ν M x` in shifted form, with the flat faces of `D_N`.
    fn squared(
        self,
        mass: SparseMatrix<Quat<f64>>,
        masses: &[f64],
        potential: Option<&[f64]>,
        mesh: &TriMesh,
    ) -> PencilSpec<Quat<f64>> {
        let mut spec = PencilSpec::shifted(self.operator.stiffness, mass, masses, potential, mesh);
        spec.exact = self.exact.map(|exact| Matrices {
            stiffness: exact.stiffness,
            coupling: spec.operator.coupling.clone(),
        });
        (spec.flat, spec.normals) = (self.flat, self.normals);
        spec.linear = Some(self.linear);
        spec
    }

    /// `A x = λ G x` in pinned form.
    fn pinned(self) -> PencilSpec<Quat<f64>> {
        PencilSpec {
            operator: self.operator,
            exact: self.exact,
            flat: self.flat,
            normals: self.normals,
            linear: Some(self.linear),
            form: Form::Pinned,
        }
    }
}

/// `τ X + (1 − τ) Y`.
fn blend(
    tau: f64,
    x: &SparseMatrix<Quat<f64>>,
    y: &SparseMatrix<Quat<f64>>,
) -> Result<SparseMatrix<Quat<f64>>, SpectrumError> {
    SparseMatrix::linear_combination(Quat::from_real(tau), x, Quat::from_real(1.0 - tau), y)
        .map_err(|e| SpectrumError::Operator(e.into()))
}

/// `L + M diag(U)`: the modified Dirichlet Hessian with the Willmore potential `U`, `masses`
/// the diagonal of `M`.
fn modified_dirichlet(mesh: &TriMesh, masses: &[f64]) -> Result<SparseMatrix<f64>, SpectrumError> {
    let weighted: Vec<f64> = masses
        .iter()
        .zip(willmore_potential(mesh))
        .map(|(m, u)| m * u)
        .collect();
    SparseMatrix::linear_combination(
        1.0,
        &cotan_laplacian(mesh),
        1.0,
        &SparseMatrix::from_diagonal(&weighted),
    )
    .map_err(|e| SpectrumError::Operator(e.into()))
}

/// Unit face normals within this of perpendicular to a direction are parallel to it, and
/// triangles whose height is below this times their longest edge are segments (rounding leaves
/// `~10⁻¹⁶`, and `10⁻¹³` on sliver faces).
const PARALLEL_TOLERANCE: f64 = 1e-10;

/// A piece of the mesh (connected through the faces not skipped) on which every triangle of a
/// second surface `f2` is parallel to one unit direction.
#[derive(Debug, Clone, PartialEq)]
struct ParallelPiece {
    /// Its vertices, ascending.
    vertices: Vec<usize>,
    /// The direction `u` (`|u · n_t| ≤` [`PARALLEL_TOLERANCE`] for the unit normals `n_t` of its
    /// triangles that are not segments); `None` if every triangle is a segment (parallel to
    /// every direction).
    direction: Option<[f64; 3]>,
    /// Whether some triangle is a segment.
    segments: bool,
}

/// The pieces of the mesh (connected through the faces not `skipped`) on which every triangle
/// of the second surface `f2 = positions` is parallel to one unit direction `u`, by smallest
/// vertex.
///
/// On such a piece `D_{f,f2}` annihilates, besides the constants, the linear function `u f2 q`
/// (`f2` itself if every triangle is a segment): `df2 ∧ d(u f2) = df2(X) u df2(Y) − df2(Y) u
/// df2(X)` vanishes when the three vectors lie in one plane, or `df2(X)` and `df2(Y)` on one
/// line, which they do on every face, and the discrete operator is exact on linear functions.
/// For `f2 = f` a planar piece is parallel to every direction of its plane, a prism (an open
/// tube of straight rulings, a folded strip) to its rulings; for the Gauss map `f2 = N` the
/// triangles of normals are segments along a crease between flat parts and on a cylinder, and
/// parallel to the axis on a tube whose normals all lie in one plane.
fn parallel_faces(mesh: &TriMesh, positions: &[[f64; 3]], skipped: &[bool]) -> Vec<ParallelPiece> {
    let n = mesh.vertex_count();
    let faces = || {
        (mesh.faces().iter())
            .zip(skipped)
            .filter(|(_, s)| !**s)
            .map(|(f, _)| f)
    };
    let mut pieces = pieces(mesh, skipped);
    // Roots of pieces with a face (a vertex whose faces are all skipped is in none).
    let mut present = vec![false; n];
    for &[a, ..] in faces() {
        present[pieces.find(a)] = true;
    }
    // The unit normal of a triangle that is not a segment (computed in each of the two passes
    // rather than stored: the memory of a mesh's size, at the peak of the assembly).
    let normal_of = |&[a, b, c]: &[usize; 3]| {
        let (p, q, r) = (positions[a], positions[b], positions[c]);
        let normal = cross(sub(q, p), sub(r, p));
        let longest = norm(sub(q, p)).max(norm(sub(r, q))).max(norm(sub(p, r)));
        (norm(normal) > PARALLEL_TOLERANCE * longest * longest).then(|| normalize(normal))
    };
    // Per piece: its first normal, and the cross product of it with the normal farthest from
    // parallel to it, whose direction is the only candidate unless the piece is planar.
    let mut first: Vec<Option<[f64; 3]>> = vec![None; n];
    let mut widest = vec![[0.0; 3]; n];
    let mut segments = vec![false; n];
    for face in faces() {
        let root = pieces.find(face[0]);
        let Some(normal) = normal_of(face) else {
            segments[root] = true;
            continue;
        };
        match first[root] {
            None => first[root] = Some(normal),
            Some(reference) => {
                let candidate = cross(reference, normal);
                if norm(candidate) > norm(widest[root]) {
                    widest[root] = candidate;
                }
            }
        }
    }
    let direction: Vec<Option<[f64; 3]>> = (0..n)
        .map(|root| {
            let reference = first[root]?;
            Some(if norm(widest[root]) > PARALLEL_TOLERANCE {
                normalize(widest[root])
            } else {
                // Planar: any direction of the plane; the one across the least aligned axis.
                let axis = (0..3)
                    .min_by(|&i, &j| reference[i].abs().total_cmp(&reference[j].abs()))
                    .map(|i| std::array::from_fn(|k| if k == i { 1.0 } else { 0.0 }))?;
                normalize(cross(reference, axis))
            })
        })
        .collect();
    let mut parallel = present;
    for face in faces() {
        let root = pieces.find(face[0]);
        if let Some(u) = direction[root]
            && let Some(normal) = normal_of(face)
        {
            parallel[root] &= dot(u, normal).abs() <= PARALLEL_TOLERANCE;
        }
    }
    if !parallel.contains(&true) {
        return Vec::new(); // the common case: no piece is parallel
    }
    let mut found: Vec<Option<ParallelPiece>> = vec![None; n];
    let mut order = Vec::new();
    for v in 0..n {
        let root = pieces.find(v);
        if !parallel[root] {
            continue;
        }
        let piece = found[root].get_or_insert_with(|| {
            order.push(root);
            ParallelPiece {
                vertices: Vec::new(),
                direction: direction[root].map(canonical_direction),
                segments: segments[root],
            }
        });
        piece.vertices.push(v);
    }
    order
        .into_iter()
        .filter_map(|root| found[root].take())
        .collect()
}

/// The [`LinearKernel`] of `D_{f,f2}` with `f2 = positions` (empty when there is none), the
/// rows of the `skipped` faces vanishing, `masses` the vertex masses of the mesh.
fn linear_kernel(
    mesh: &TriMesh,
    masses: &[f64],
    positions: &[[f64; 3]],
    skipped: &[bool],
    surface: SecondSurface,
) -> LinearKernel<Quat<f64>> {
    let mut linear = LinearKernel {
        surface,
        modes: Vec::new(),
        unremoved: None,
    };
    if positions.is_empty() {
        return linear;
    }
    for piece in parallel_faces(mesh, positions, skipped) {
        let (Some(u), false) = (piece.direction, piece.segments) else {
            linear
                .unremoved
                .get_or_insert((piece.vertices[0], piece.direction));
            continue;
        };
        let total: f64 = piece.vertices.iter().map(|&p| masses[p]).sum();
        let mean: [f64; 3] = std::array::from_fn(|c| {
            (piece.vertices.iter())
                .map(|&p| masses[p] * positions[p][c])
                .sum::<f64>()
                / total
        });
        let u = Quat::from_vector(u);
        let values = (piece.vertices.iter())
            .map(|&p| u * Quat::from_vector(sub(positions[p], mean)))
            .collect();
        linear.modes.push(SparseVector {
            rows: piece.vertices,
            values,
        });
    }
    linear
}

/// `±u` with its largest component positive and rounding-sized ones zero: the direction as a
/// reader would write it.
fn canonical_direction(u: [f64; 3]) -> [f64; 3] {
    let largest = u
        .into_iter()
        .fold(0.0, |a: f64, c| if c.abs() > a.abs() { c } else { a });
    u.map(|c| {
        if c.abs() <= 1e-12 {
            0.0
        } else {
            c * largest.signum()
        }
    })
}

/// `ε = 10⁻¹⁰ · Σ_p P_pp / Σ_p M_pp` over the vertices inside the well (`U_p = 0`; all
/// vertices without one), or `10⁻¹⁰` if that vanishes: the mass-weighted mean of the diagonal
/// ratios, a scale of the operator itself (not of the well's wall, up to `c` or `c²`, nor of
/// the few sliver triangles that set the largest ratio). With the kernel removed exactly, `ε`
/// only lifts the constant directions, `𝟙* (P + εM) 𝟙 = ε 𝟙* M 𝟙`, a factor `10⁶` above the
/// rounding `~10⁻¹⁶ Σ|P_ij|` of `𝟙* P 𝟙`, and the map `λ = 1/μ − ε` is exact.
fn regularization<T: Scalar<Real = f64>>(
    stiffness: &SparseMatrix<T>,
    masses: &[f64],
    potential: Option<&[f64]>,
) -> f64 {
    let inside = (0..masses.len()).filter(|&p| potential.is_none_or(|u| u[p] == 0.0));
    let (trace, mass) = inside.fold((0.0, 0.0), |(t, m), p| {
        (t + stiffness.get(p, p).re(), m + masses[p])
    });
    let ratio = trace / mass;
    1e-10
        * if ratio > 0.0 && ratio.is_finite() {
            ratio
        } else {
            1.0
        }
}

/// The shift `σ` of the literal family's pencil `M x = μ (K + σM) x`, `λ = 1/μ − σ`: the
/// smallest, within a factor of 2, whose `M^{-1/2} (K + σM) M^{-1/2}` (the matrix the
/// eigensolver factors) the Cholesky factorisation accepts.
///
/// It must be small: the wanted `μ = 1/(λ + σ)` of the smallest `|λ|` differ by about
/// `|λ|/σ` relative to `1/σ`, so Gershgorin's shift, of the order of the largest eigenvalue
/// (10⁴ above the smallest nonzero one on a 3,000-vertex mesh), left them inseparable and
/// Lanczos without a converged pair. Tried from below: the shifted form's `ε`
/// ([`regularization`]), which suffices when `K` is semidefinite (small `τ`), then by
/// bisection of the exponent between the largest shift refused and Gershgorin's, which is
/// certain in exact arithmetic. Each trial is one numeric factorisation of one pattern.
fn definite_shift(stiffness: &SparseMatrix<Quat<f64>>, masses: &[f64]) -> f64 {
    let certain = gershgorin_shift(stiffness, masses);
    let Some(scaled) = Reduction::without(masses, []).matrix(stiffness) else {
        return certain;
    };
    let identity = SparseMatrix::identity(masses.len());
    let shifted = |sigma: f64| {
        SparseMatrix::linear_combination(
            Quat::from_real(1.0),
            &scaled,
            Quat::from_real(sigma),
            &identity,
        )
    };
    let Ok(symbolic) = shifted(certain)
        .map_err(|_| ())
        .and_then(|a| SymbolicCholesky::analyze(&a).map_err(|_| ()))
    else {
        return certain;
    };
    let symbolic = Arc::new(symbolic);
    let accepted = |sigma: f64| {
        shifted(sigma).is_ok_and(|a| {
            SparseCholesky::factorize_with_symbolic(Arc::clone(&symbolic), &a).is_ok()
        })
    };
    // `ε` underflows to zero when the operator's scale is below `10³⁰⁰ ·` the least normal
    // number; the bisection needs a positive lower end.
    let lowest = regularization(stiffness, masses, None).max(f64::MIN_POSITIVE);
    let (mut refused, mut accepting) = (lowest, certain);
    if refused >= accepting || accepted(refused) {
        return refused.min(accepting);
    }
    // Each step halves `log(accepting / refused)`, at most 2¹¹ over the normal numbers: the
    // geometric mean taken as `√r · √a` neither underflows nor overflows, so it lies strictly
    // between the ends.
    while accepting > 2.0 * refused {
        let middle = refused.sqrt() * accepting.sqrt();
        if accepted(middle) {
            accepting = middle;
        } else {
            refused = middle;
        }
    }
    accepting
}

/// Gershgorin on `M^{-1/2} K M^{-1/2}`: every `λ ≥ min_p (K_pp/M_pp − Σ_{q≠p} |K_pq|/√(M_pp
/// M_qq))`; `σ` is 1% above minus that bound plus `10⁻⁸` of the largest weighted entry.
fn gershgorin_shift(operator: &SparseMatrix<Quat<f64>>, masses: &[f64]) -> f64 {
    let mut lower = vec![0.0; masses.len()];
    let mut scale: f64 = 0.0;
    for (p, q, v) in operator.triplets() {
        let weighted = v.abs() / (masses[p] * masses[q]).sqrt();
        scale = scale.max(weighted);
        lower[p] += if p == q {
            v.re() / masses[p]
        } else {
            -weighted
        };
    }
    let bound = lower.iter().copied().fold(f64::INFINITY, f64::min);
    1.01 * (-bound).max(0.0) + 1e-8 * scale.max(f64::MIN_POSITIVE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators::{grid, icosphere};

    #[test]
    fn parallel_faces_finds_planes_segments_and_nothing_on_a_sphere() {
        let plane = grid(3, 2, 1.0, 1.0).unwrap();
        let none = vec![false; plane.face_count()];
        let found = parallel_faces(&plane, plane.positions(), &none);
        assert_eq!(found.len(), 1);
        let direction = found[0].direction.unwrap();
        assert_eq!(
            found[0].vertices,
            (0..plane.vertex_count()).collect::<Vec<_>>()
        );
        assert!(!found[0].segments);
        assert!(direction[2] == 0.0 && (norm(direction) - 1.0).abs() < 1e-15);

        // A second surface on one line: every triangle is a segment, parallel to everything.
        let line: Vec<[f64; 3]> = (0..plane.vertex_count())
            .map(|v| [v as f64, 2.0 * v as f64, 0.5])
            .collect();
        let found = parallel_faces(&plane, &line, &none);
        assert_eq!((found[0].direction, found[0].segments), (None, true));

        let sphere = icosphere(1);
        let none = vec![false; sphere.face_count()];
        assert_eq!(parallel_faces(&sphere, sphere.positions(), &none), vec![]);
        // With all but two faces far apart skipped, each is a planar piece of its own; the
        // vertices of skipped faces only are in none.
        let mut skipped = vec![true; sphere.face_count()];
        let far = (1..sphere.face_count())
            .find(|&t| {
                sphere.faces()[t]
                    .iter()
                    .all(|v| !sphere.faces()[0].contains(v))
            })
            .unwrap();
        (skipped[0], skipped[far]) = (false, false);
        let mut want = vec![sphere.faces()[0].to_vec(), sphere.faces()[far].to_vec()];
        want.iter_mut().for_each(|v| v.sort_unstable());
        want.sort();
        let found = parallel_faces(&sphere, sphere.positions(), &skipped);
        let got: Vec<Vec<usize>> = found.into_iter().map(|p| p.vertices).collect();
        assert_eq!(got, want);
    }
}
