//! One value per row of the pencil table (module documentation of [`super`]): the operator's
//! own eigenproblem `P x = λ Q x`, the matrices that are solved, and how, over the scalar the
//! operator is assembled in ([`OperatorPencil`]).

use std::sync::Arc;

use qscalar::{Quat, Scalar};
use qsparse::{SparseCholesky, SparseMatrix, SymbolicCholesky};

use super::first_order::{FirstOrderKernel, first_order_kernel};
use super::flatness::{FlatTest, vanishing_faces};
use super::kernel::Reduction;
use super::{Operator, SecondSurface, SpectrumError};
use crate::TriMesh;
use crate::anisotropic::anisotropic_laplacian;
use crate::curvature::willmore_potential;
use crate::geometry::{barycentric_masses, cotan_laplacian, vertex_normals};
use crate::operators::{DiracPencil, OperatorError, quaternionic, relative_dirac};
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

impl Form {
    /// The operator's eigenvalue `λ` of an eigenvalue `μ` of the pencil this form solves.
    pub fn eigenvalue(self, mu: f64) -> f64 {
        match self {
            Form::Shifted { epsilon } => 1.0 / mu - epsilon,
            Form::Pinned => 1.0 / mu,
            Form::Literal { sigma } => 1.0 / mu - sigma,
        }
    }
}

/// The two matrices of a pencil `P x = λ Q x` over the scalar `T`.
#[derive(Debug, Clone)]
pub(super) struct Matrices<T> {
    /// `P`.
    pub stiffness: SparseMatrix<T>,
    /// `Q`.
    pub coupling: SparseMatrix<T>,
}

impl<T: Scalar<Real = f64>> Matrices<T> {
    /// `max(‖P' − P‖ / ‖P‖, ‖Q' − Q‖ / ‖Q‖)` for `other = (P', Q')`, in the norm of
    /// [`super::scaled_norm`].
    fn relative_change(&self, other: &Self, masses: &[f64]) -> Result<f64, SpectrumError> {
        let change = |a: &SparseMatrix<T>, b: &SparseMatrix<T>| {
            let size = super::scaled_norm(a, masses);
            Ok::<f64, SpectrumError>(if size > 0.0 {
                super::scaled_norm(&difference(b, a)?, masses) / size
            } else {
                0.0
            })
        };
        Ok(
            change(&self.stiffness, &other.stiffness)?
                .max(change(&self.coupling, &other.coupling)?),
        )
    }
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
    /// What the first-order operator tells of the kernel (operators built on one).
    pub first_order: Option<FirstOrderKernel<T>>,
    /// How the pencil is solved.
    pub form: Form,
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
    /// `max(‖P' − P‖ / ‖P‖, ‖Q' − Q‖ / ‖Q‖)` between the matrices as assembled of this pencil
    /// and `other` (the same operator on moved positions), in the norm
    /// `max_p Σ_q |X_pq| / √(Ā_p Ā_q)` of the backward error.
    pub fn relative_change(&self, other: &Self, masses: &[f64]) -> Result<f64, SpectrumError> {
        match (self, other) {
            (Self::Real(a), Self::Real(b)) => a.operator.relative_change(&b.operator, masses),
            (Self::Quaternionic(a), Self::Quaternionic(b)) => {
                a.operator.relative_change(&b.operator, masses)
            }
            // The same operator assembles to the same kind of pencil.
            _ => Ok(0.0),
        }
    }

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
                first_order: None,
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
            first_order: None,
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

    /// What setting the rows of flat faces to zero removed from the coupling (assembled minus
    /// solved), if it removed anything.
    pub fn zeroed_coupling(&self) -> Result<Option<SparseMatrix<T>>, SpectrumError> {
        (self.exact.as_ref())
            .map(|exact| difference(&self.operator.coupling, &exact.coupling))
            .transpose()
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
    kernel: FirstOrderKernel<Quat<f64>>,
}

impl FirstOrder {
    fn assemble(
        mesh: &TriMesh,
        masses: &[f64],
        second: SecondImmersion,
        potential: Option<&[f64]>,
        flat_tolerance: f64,
    ) -> Result<Self, SpectrumError> {
        let mut normals = None;
        // The rows of `D_f` are edge vectors over twice the area: never zero. Nor are those of
        // a surface's, whose faces have positive area ([`TriMesh::check_same_connectivity`]
        // paired it with `mesh`).
        let no_flat_faces = || vec![false; mesh.face_count()];
        let (f2, surface, flat): (&[[f64; 3]], _, _) = match second {
            SecondImmersion::GaussMap => {
                let mut gauss_map = vertex_normals(mesh)
                    .map_err(|vertex| OperatorError::DegenerateNormal { vertex })?;
                let test = FlatTest::new(mesh, flat_tolerance);
                test.denoise_gauss_map(&mut gauss_map);
                let flat = vanishing_faces(mesh, &test.flat_faces(&gauss_map, potential));
                (
                    normals.insert(gauss_map).as_slice(),
                    SecondSurface::GaussMap,
                    flat,
                )
            }
            SecondImmersion::Positions => (mesh.positions(), SecondSurface::Mesh, no_flat_faces()),
            SecondImmersion::Surface(f2) => (f2, SecondSurface::Reference, no_flat_faces()),
        };
        let d = relative_dirac(mesh, f2)?;
        let d = match potential {
            Some(u) => dirac_with_well(mesh, &d, u)?,
            None => d,
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
        let operator = pencil(&d)?;
        drop(d);
        // After the matrices, whose assembly is the peak of memory here.
        let kernel =
            first_order_kernel(mesh, masses, f2, &flat, potential, flat_tolerance, surface);
        Ok(Self {
            operator,
            exact,
            flat,
            normals,
            kernel,
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
        spec.first_order = Some(self.kernel);
        spec
    }

    /// `A x = λ G x` in pinned form.
    fn pinned(self) -> PencilSpec<Quat<f64>> {
        PencilSpec {
            operator: self.operator,
            exact: self.exact,
            flat: self.flat,
            normals: self.normals,
            first_order: Some(self.kernel),
            form: Form::Pinned,
        }
    }
}

/// `X − Y`.
fn difference<T: Scalar<Real = f64>>(
    x: &SparseMatrix<T>,
    y: &SparseMatrix<T>,
) -> Result<SparseMatrix<T>, SpectrumError> {
    SparseMatrix::linear_combination(T::one(), x, T::from_real(-1.0), y)
        .map_err(|e| SpectrumError::Operator(e.into()))
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
