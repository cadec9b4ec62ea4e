//! The exactly known kernel of a pencil `P x = λ Q x` and the reduced space it is solved on
//! (docs/MATH.md, "The exact kernel").
//!
//! * **Flat vertices.** A face is *flat* when the first-order operator's row of it vanishes:
//!   for `D_N` its corner normals agree within the flat tolerance relative to its edge lengths
//!   ([`super::flatness::FlatTest::flat_faces`]; with a potential well, the potential is zero
//!   at its corners too). A vertex all of whose faces are flat has `D δ_p = 0` and
//!   `G δ_p = ½ D* M_F B δ_p = 0`, so `δ_p q` is in `ker P ∩ ker Q` for every quaternion `q`. Every other eigenvector is mass-orthogonal to
//!   it, which for the diagonal mass means `x_p = 0`: the vertex is removed from the problem.
//! * **Modes of pieces.** The remaining vertices split into pieces connected through faces that
//!   are not flat. For each piece `S` whose indicator `𝟙_S` the stiffness annihilates
//!   (`Σ|P 𝟙_S| ≤ 10⁻¹⁰ Σ|P_ij|` over the piece's columns), `𝟙_S q` is in the kernel of `P`; so
//!   is, on a piece where every triangle of the second surface `f2` of `D_{f,f2}` is parallel to
//!   one direction `u`, the linear function `u (f2 − f̄2) q` (found by the pencil's assembly,
//!   checked here the same way). Each such *mode* `k` has a [`Coupling`] that says how the other
//!   eigenvectors relate to it: unless `Q k = 0`, every eigenvector with `λ ≠ 0` satisfies
//!   `(Q k)* x = 0`, because `k* P x = 0 = λ k* Q x`.
//! * **Determined corners.** The corners of freed rows ([`super::determined`]) belong to no
//!   piece: every mode is extended to them, and modes that share one are made mass-orthogonal
//!   and pinned again.

use std::collections::HashMap;

use qscalar::Scalar;
use qsparse::{DisjointSets, Gram, SparseMatrix, SparseVector};

use super::determined::DeterminedCorners;
use crate::TriMesh;

/// Relative size `Σ|P k| ≤ 10⁻¹⁰ Σ_j |k_j| Σ_i |P_ij|` below which a mode `k` is in the kernel
/// (and likewise for `Q` in [`Coupling`]); rounding leaves `~10⁻¹⁶`.
const MODE_TOLERANCE: f64 = 1e-10;

/// How the other eigenvectors relate to a mode `k` of `P`, with `g = Q k`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Coupling {
    /// `g = 0` (a closed piece of a Dirac pencil): `k` is in `ker P ∩ ker Q`, eigenvectors
    /// are defined up to it and the mass-orthogonal one is returned.
    Free,
    /// `g ≠ 0` but `k* g = 0` (a Dirac pencil on a piece with boundary): `λ = 0` is a
    /// defective eigenvalue there, and the others satisfy `g* x = 0`.
    Orthogonal,
    /// `k* g ≠ 0` (the blended family, the mass of a shifted pencil): `k` is an ordinary
    /// eigenvector with `λ = 0`, and the others satisfy `g* x = 0`.
    Oblique,
}

/// What a mode of a piece is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum ModeKind {
    /// The constant `𝟙_S`.
    Constant,
    /// A linear function `u (f2 − f̄2)` of the second surface, mass-orthogonal to `𝟙_S`.
    Linear,
    /// A basis vector of the kernel on a piece whose rulings carry more than the constant and
    /// `u f2` (the basis spans those too), mass-orthonormal to the others of its piece.
    Ruling,
}

/// A kernel vector of `P` supported on one connected piece of the non-flat vertices and the
/// corners it determines (made mass-orthogonal to the modes that share them), for a pencil over
/// the scalar `T`.
#[derive(Debug, Clone)]
pub(super) struct KernelMode<T> {
    /// Constant or linear.
    pub kind: ModeKind,
    /// `k` on its piece (rows: the piece's vertices, ascending).
    pub vector: SparseVector<T>,
    /// How the other eigenvectors relate to it.
    pub coupling: Coupling,
    /// `g = Q k`, by its entries in the rows `Q` couples to the piece: held in full, the
    /// images of a mesh of thousands of pieces (a triangle soup) would take gigabytes.
    pub image: SparseVector<T>,
    /// The vertex the pinned form sets to zero to remove it: the piece's first vertex for the
    /// constant; for a linear mode the vertex where it differs most from its value there (two
    /// pins where `k` differs exclude every combination `𝟙_S a + k b`).
    pub pin: usize,
}

/// A kernel vector known from the structure of the operator, with the vertex that pins it.
#[derive(Debug, Clone)]
pub(super) struct PinnedVector<T> {
    /// Its entries (rows ascending).
    pub vector: SparseVector<T>,
    /// The vertex the pinned form sets to zero to remove it.
    pub pin: usize,
}

/// Orthogonally coupled modes `k_i` as the pinned form restores them, with their images
/// `g_i = Q k_i`: the least squares restoration `x ← x + Σ k_i c_i` of one residual `r`,
/// `c = (GᴴG)⁻¹ Gᴴ r / λ` (see [`ExactKernel::restoration`]).
#[derive(Debug, Clone)]
pub(super) enum Restoration<T> {
    /// The modes of a group as they are, with the Cholesky factor of the Gram matrix of their
    /// images: a fit costs their supports however many overlap.
    Fit {
        vectors: Vec<SparseVector<T>>,
        images: Gram<T>,
    },
    /// One mode `k'` orthogonalised against the earlier modes of its group, whose images
    /// were too close to dependent for the Gram form: `c = (g'* r) / (λ |g'|²)`.
    Orthogonal {
        vector: SparseVector<T>,
        image: SparseVector<T>,
    },
}

/// What the structure of an operator tells of its kernel, for [`ExactKernel::find`] to check
/// against the matrices: the pieces whose constants are candidate modes, candidate linear modes
/// (each on one piece, ascending rows), bases of the kernel on ruled pieces (by piece root), and
/// the corners that freed rows determine ([`DeterminedCorners`]), to which every mode extends.
#[derive(Debug, Clone)]
pub(super) struct KernelStructure<T> {
    /// The pieces: vertices a kernel vector is constant on.
    pub pieces: DisjointSets,
    /// Candidate linear modes `u (f2 − f̄2)`.
    pub linear: Vec<SparseVector<T>>,
    /// By piece root: a pinned basis of the kernel there, in place of its constant and linear
    /// mode.
    pub ruled: HashMap<usize, Vec<PinnedVector<T>>>,
    /// Corners outside every piece, whose values the others determine.
    pub determined: DeterminedCorners<T>,
    /// Vertices of faces whose rows do not vanish that no row involves once the freed rows are
    /// out (ascending): their columns of the operator vanish by its structure.
    pub uninvolved: Vec<usize>,
}

impl<T> KernelStructure<T> {
    /// The structure of a pencil whose first-order operator tells nothing finer than its
    /// `pieces` (their constants are the only candidates).
    pub fn of_pieces(pieces: DisjointSets) -> Self {
        Self {
            pieces,
            linear: Vec::new(),
            ruled: HashMap::new(),
            determined: DeterminedCorners::default(),
            uninvolved: Vec::new(),
        }
    }
}

/// The kernel of a pencil that is known exactly: flat vertices and the modes of pieces.
#[derive(Debug, Clone)]
pub(super) struct ExactKernel<T> {
    /// Vertices whose every face is flat (ascending).
    pub flat_vertices: Vec<usize>,
    /// The modes, by piece: the constant first, then a linear mode if the piece has one.
    pub modes: Vec<KernelMode<T>>,
    /// For the pinned form: the orthogonally coupled modes by group, a group being the modes
    /// whose images are joined by shared rows of `Q` (the modes of a piece; pieces next to
    /// each other across a face whose row does not vanish, as rulings are): different groups'
    /// images are orthogonal, so the least squares restoration of one residual is exact group
    /// by group.
    pub restoration: Vec<Restoration<T>>,
}

/// How the kernel was found, as reported with a [`super::Spectrum`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct KernelSummary {
    /// Quaternionic dimension of the exactly known kernel: `flat_vertices + constants +
    /// linear_functions + ruling_functions`.
    pub dimension: usize,
    /// Vertices all of whose faces are flat (`D δ_p = 0`): one kernel dimension each.
    pub flat_vertices: usize,
    /// Connected pieces of the other vertices whose constant function is in the kernel.
    pub constants: usize,
    /// Pieces on which the linear function `u f2` is in the kernel too (every triangle of the
    /// second surface `f2` of `D_{f,f2}` parallel to one direction `u`: a planar piece or an
    /// open prism for `D_f`, vertex normals in one plane for `D_N`).
    pub linear_functions: usize,
    /// Kernel vectors of the pieces whose rulings (vertices joined by coinciding corners of
    /// the triangles of `f2`) carry more than a constant and `u f2`: a basis of the kernel on
    /// each, in place of its constant and linear function.
    pub ruling_functions: usize,
}

impl<T: Scalar<Real = f64>> ExactKernel<T> {
    /// The kernel of `P x = λ Q x` on `mesh` (vertex masses `masses`), with `flat[t]` telling
    /// whether face `t`'s row of the first-order operator vanishes (all `false` for operators
    /// without one), and the candidate modes of its `structure`, each extended to the
    /// determined corners and kept if `P` annihilates it. `stiffness` and `coupling` are the
    /// matrices solved; `zeroed` is what setting the rows of flat faces to zero removed from the
    /// coupling (assembled minus solved), when it did ([`kernel_mode`]).
    pub fn find(
        mesh: &TriMesh,
        masses: &[f64],
        flat: &[bool],
        structure: KernelStructure<T>,
        stiffness: &SparseMatrix<T>,
        coupling: &SparseMatrix<T>,
        zeroed: Option<&SparseMatrix<T>>,
    ) -> Self {
        let KernelStructure {
            mut pieces,
            linear,
            mut ruled,
            determined,
            uninvolved,
        } = structure;
        let n = mesh.vertex_count();
        let mut touches_curved = vec![false; n];
        for (face, _) in mesh.faces().iter().zip(flat).filter(|(_, f)| !**f) {
            face.iter().for_each(|&p| touches_curved[p] = true);
        }
        let flat_vertices = (0..n).filter(|&p| !touches_curved[p]).collect();
        // Determined corners belong to no piece: their values follow from the pieces'.
        determined.corners().for_each(|c| touches_curved[c] = false);
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); n];
        for p in (0..n).filter(|&p| touches_curved[p]) {
            members[pieces.find(p)].push(p);
        }
        // By root: few pieces have one.
        let mut linear_of_piece: HashMap<usize, SparseVector<T>> = HashMap::new();
        for mode in linear {
            if let Some(&first) = mode.rows.first() {
                linear_of_piece.insert(pieces.find(first), mode);
            }
        }
        let mut accumulator = Accumulator::new(n);
        let matrices = ModeMatrices {
            stiffness,
            coupling,
            zeroed,
            uninvolved: &uninvolved,
        };
        let mut modes = Vec::new();
        for (root, vertices) in members.into_iter().enumerate() {
            let Some(&first) = vertices.first() else {
                continue;
            };
            if let Some(basis) = ruled.remove(&root) {
                modes.extend(basis.into_iter().filter_map(|b| {
                    let (kind, vector) = (ModeKind::Ruling, determined.extend(b.vector));
                    kernel_mode(&mut accumulator, kind, vector, b.pin, matrices)
                }));
                continue;
            }
            let vector = determined.extend(SparseVector {
                values: vec![T::one(); vertices.len()],
                rows: vertices,
            });
            let Some(mode) = kernel_mode(
                &mut accumulator,
                ModeKind::Constant,
                vector,
                first,
                matrices,
            ) else {
                continue;
            };
            let linear = linear_of_piece.remove(&root).and_then(|k| {
                // `k` starts at the piece's first vertex, the constant's pin.
                let base = k.values[0];
                let pin = (k.rows.iter().zip(&k.values))
                    .max_by(|a, b| (*a.1 - base).abs().total_cmp(&(*b.1 - base).abs()))
                    .filter(|(_, v)| (**v - base).abs() > 0.0)?
                    .0;
                let (pin, k) = (*pin, determined.extend(k));
                kernel_mode(&mut accumulator, ModeKind::Linear, k, pin, matrices)
            });
            // Against `G = sym(Bᵀ M_F D)` a linear mode is free or orthogonal (`k* G k = 0` for
            // every kernel vector of `D`), so the pinned form never compresses two modes of one
            // piece; against the mass (shifted form) it is oblique, and only constrained.
            modes.extend(std::iter::once(mode).chain(linear));
        }
        if !determined.is_empty() {
            orthogonalise_at_determined_corners(&mut modes, &determined, masses, |mode| {
                coupled(&mut accumulator, mode, matrices)
            });
        }
        let restoration = restorations(&modes, n);
        Self {
            flat_vertices,
            modes,
            restoration,
        }
    }

    /// Counts for the report.
    pub fn summary(&self) -> KernelSummary {
        let count = |kind| self.modes.iter().filter(|m| m.kind == kind).count();
        let (constants, linear_functions) = (count(ModeKind::Constant), count(ModeKind::Linear));
        let ruling_functions = count(ModeKind::Ruling);
        KernelSummary {
            dimension: self.flat_vertices.len() + constants + linear_functions + ruling_functions,
            flat_vertices: self.flat_vertices.len(),
            constants,
            linear_functions,
            ruling_functions,
        }
    }

    /// A mass-orthonormal basis of the kernel: the modes `k / ‖k‖_M` by piece (the constants
    /// real and positive), then `δ_p / √Ā_p` by vertex. At most `count` vectors.
    pub fn basis(&self, masses: &[f64], count: usize) -> Vec<Vec<T>> {
        let n = masses.len();
        let modes = self.modes.iter().map(|mode| {
            let norm = mass_norm_squared(masses, &mode.vector).sqrt();
            mode.vector.times(T::from_real(1.0 / norm)).to_dense(n)
        });
        let vertices = self.flat_vertices.iter().map(|&p| {
            let mut x = vec![T::zero(); n];
            x[p] = T::from_real(1.0 / masses[p].sqrt());
            x
        });
        modes.chain(vertices).take(count).collect()
    }
}

/// The pieces of `mesh` for a pencil whose first-order operator tells nothing finer: its
/// vertices connected through the faces that are not `flat` (whose rows of the first-order
/// operator do not vanish).
pub(super) fn pieces(mesh: &TriMesh, flat: &[bool]) -> DisjointSets {
    let mut pieces = DisjointSets::new(mesh.vertex_count());
    for (&[i, j, k], _) in mesh.faces().iter().zip(flat).filter(|(_, f)| !**f) {
        pieces.union(i, j);
        pieces.union(j, k);
    }
    pieces
}

/// `Σ_p Ā_p |k_p|²`.
pub(super) fn mass_norm_squared<T: Scalar<Real = f64>>(masses: &[f64], k: &SparseVector<T>) -> f64 {
    (k.rows.iter().zip(&k.values))
        .map(|(&p, v)| masses[p] * v.abs2())
        .sum()
}

/// The orthogonally coupled `modes` (images in rows `0..n`) as the pinned form restores them:
/// grouped by shared rows of their images (union–find over the rows), each group's images
/// orthogonalised in turn, so that every two images are orthogonal. The modes of a piece share
/// rows; on most meshes different pieces do not, and a group costs its own supports only.
fn restorations<T: Scalar<Real = f64>>(modes: &[KernelMode<T>], n: usize) -> Vec<Restoration<T>> {
    let coupled: Vec<&KernelMode<T>> = modes
        .iter()
        .filter(|m| m.coupling == Coupling::Orthogonal)
        .collect();
    let mut groups = joined_by_shared_rows(coupled.iter().map(|m| &m.image), n);
    let mut members: Vec<Vec<&KernelMode<T>>> = vec![Vec::new(); coupled.len()];
    for (i, mode) in coupled.iter().enumerate() {
        members[groups.find(i)].push(mode);
    }
    // An empty group (a set's other members) falls through to `orthogonalised`, which makes
    // nothing of it; one mode needs no fit: its own coefficient (the common case).
    members
        .iter()
        .flat_map(|group| {
            let fit = (group.len() > 1).then(|| {
                let images: Vec<SparseVector<T>> = group.iter().map(|m| m.image.clone()).collect();
                Gram::new(&images)
            });
            match fit.flatten() {
                Some(images) => vec![Restoration::Fit {
                    vectors: group.iter().map(|m| m.vector.clone()).collect(),
                    images,
                }],
                None => orthogonalised(group),
            }
        })
        .collect()
}

/// Orthogonally coupled modes with their images orthogonalised in turn
/// (Gram–Schmidt with coefficients on the right): `k'_i = k_i − Σ_{j<i} k'_j α_j`,
/// `α_j = (g'_j* g_i)/|g'_j|²`, so that `g'_i = Q k'_i` are mutually orthogonal. Sparse, but
/// each `k'_i` takes the supports of the earlier ones: for groups whose images are nearly
/// dependent, which the Gram form refuses.
fn orthogonalised<T: Scalar<Real = f64>>(modes: &[&KernelMode<T>]) -> Vec<Restoration<T>> {
    let mut done: Vec<(SparseVector<T>, SparseVector<T>)> = Vec::new();
    for mode in modes {
        let (mut vector, mut image) = (mode.vector.clone(), mode.image.clone());
        let before = image.norm_squared();
        for (earlier_vector, earlier_image) in &done {
            let alpha =
                (earlier_image.inner_sparse(&image)).scale(1.0 / earlier_image.norm_squared());
            vector = vector.minus_times(earlier_vector, alpha);
            image = image.minus_times(earlier_image, alpha);
        }
        // An image in the span of the earlier ones: `k'` is in `ker P ∩ ker Q`, free, and
        // nothing is restored along it (its constraint is dependent too, and dropped).
        if image.norm_squared() > 1e-16 * before {
            done.push((vector, image));
        }
    }
    (done.into_iter())
        .map(|(vector, image)| Restoration::Orthogonal { vector, image })
        .collect()
}

/// `Σ_i |g_i|`.
fn l1<T: Scalar<Real = f64>>(g: &SparseVector<T>) -> f64 {
    g.values.iter().map(|q| q.abs()).sum()
}

/// `Σ_j |k_j| Σ_i |X_ij|`: the scale of `X k` without cancellation.
fn column_mass<T: Scalar<Real = f64>>(x: &SparseMatrix<T>, k: &SparseVector<T>) -> f64 {
    (k.rows.iter().zip(&k.values))
        .map(|(&j, v)| v.abs() * column_l1(x, j))
        .sum()
}

/// `Σ_i |x_ij|`.
fn column_l1<T: Scalar<Real = f64>>(x: &SparseMatrix<T>, j: usize) -> f64 {
    x.col(j).1.iter().map(|q| q.abs()).sum()
}

/// `Σ_j |k_j| s_j`: the scale against which the stiffness's image of `k` is judged, `s_j` the
/// mass of column `j` of `x` or, for a vertex that no row of the first-order operator
/// involves (`uninvolved`, ascending), the largest mass of the columns it is coupled to. Such
/// a vertex's own column vanishes by the structure, exactly where the two coinciding corners
/// of its rows' triangles of `f2` are equal and to rounding where they differ by rounding (a
/// crease of a rotated CAD model), so it cannot be its own scale.
fn stiffness_scale<T: Scalar<Real = f64>>(
    x: &SparseMatrix<T>,
    k: &SparseVector<T>,
    uninvolved: &[usize],
) -> f64 {
    (k.rows.iter().zip(&k.values))
        .map(|(&j, v)| {
            let scale = if uninvolved.binary_search(&j).is_ok() {
                x.col(j)
                    .0
                    .iter()
                    .map(|&i| column_l1(x, i))
                    .fold(0.0, f64::max)
            } else {
                column_l1(x, j)
            };
            v.abs() * scale
        })
        .sum()
}

/// Sums of sparse columns into a dense scratch, cleared after each sum: a piece's image costs
/// the entries of its columns, not the size of the mesh.
struct Accumulator<T> {
    sums: Vec<T>,
    touched: Vec<usize>,
    seen: Vec<bool>,
}

impl<T: Scalar<Real = f64>> Accumulator<T> {
    fn new(n: usize) -> Self {
        Self {
            sums: vec![T::zero(); n],
            touched: Vec::new(),
            seen: vec![false; n],
        }
    }

    /// `X k = Σ_j X e_j k_j` (`X` with the accumulator's number of rows).
    fn image(&mut self, x: &SparseMatrix<T>, k: &SparseVector<T>) -> SparseVector<T> {
        for (&j, &c) in k.rows.iter().zip(&k.values) {
            let (rows, values) = x.col(j);
            for (&i, &v) in rows.iter().zip(values) {
                if !self.seen[i] {
                    self.seen[i] = true;
                    self.touched.push(i);
                }
                self.sums[i] += v * c;
            }
        }
        self.touched.sort_unstable();
        let values = self.touched.iter().map(|&i| self.sums[i]).collect();
        for &i in &self.touched {
            (self.sums[i], self.seen[i]) = (T::zero(), false);
        }
        SparseVector {
            rows: std::mem::take(&mut self.touched),
            values,
        }
    }
}

/// The matrices a mode is judged by: the pencil solved, and what setting the rows of flat
/// faces to zero removed from its coupling.
#[derive(Clone, Copy)]
struct ModeMatrices<'a, T> {
    stiffness: &'a SparseMatrix<T>,
    coupling: &'a SparseMatrix<T>,
    zeroed: Option<&'a SparseMatrix<T>>,
    /// The vertices no row of the first-order operator involves (ascending).
    uninvolved: &'a [usize],
}

/// The modes that share determined corners made mass-orthogonal, group by group (modes joined
/// by shared rows) in their order (Gram–Schmidt with coefficients on the right, twice), each
/// then `recoupled`, and the group pinned again ([`pivots`]): the removal of a mode's mass
/// component (shifted form, free modes) and the kernel's basis take the modes as orthogonal,
/// as those of different pieces are without the corners, and those of one piece are made.
/// Combinations of kernel vectors, they stay in the kernel. The pins of the extended modes
/// (at their pieces' first vertices) can be nearly dependent: on a strip freed from end to
/// end both modes are pinned at one end, where they nearly agree, and the pinned form left
/// residuals of `10⁻⁷`.
fn orthogonalise_at_determined_corners<T: Scalar<Real = f64>>(
    modes: &mut [KernelMode<T>],
    determined: &DeterminedCorners<T>,
    masses: &[f64],
    mut recoupled: impl FnMut(&mut KernelMode<T>),
) {
    // Modes that share rows: those of one piece, and those of pieces whose rows determine a
    // common corner.
    let mut groups = joined_by_shared_rows(modes.iter().map(|m| &m.vector), masses.len());
    let mut owner = vec![usize::MAX; masses.len()];
    for (i, mode) in modes.iter().enumerate() {
        mode.vector.rows.iter().for_each(|&row| owner[row] = i);
    }
    let mut determines = vec![false; modes.len()];
    for corner in determined.corners() {
        if owner[corner] != usize::MAX {
            determines[groups.find(owner[corner])] = true;
        }
    }
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); modes.len()];
    for i in 0..modes.len() {
        members[groups.find(i)].push(i);
    }
    let touched = (members.into_iter().enumerate())
        .filter(|(root, group)| determines[*root] && group.len() > 1)
        .map(|(_, group)| group);
    for group in touched {
        for (position, &i) in group.iter().enumerate() {
            for _ in 0..2 {
                for &j in &group[..position] {
                    let (earlier, mode) = (&modes[j].vector, &modes[i].vector);
                    let c = mass_weighted(masses, earlier)
                        .inner_sparse(mode)
                        .scale(1.0 / mass_norm_squared(masses, earlier));
                    modes[i].vector = mode.minus_times(earlier, c);
                }
            }
            recoupled(&mut modes[i]);
        }
        let vectors: Vec<SparseVector<T>> =
            group.iter().map(|&i| modes[i].vector.clone()).collect();
        for (&i, pin) in group.iter().zip(pivots(&vectors)) {
            modes[i].pin = pin;
        }
    }
}

/// One row per vector at which no combination of the vectors vanishes entirely: Gaussian
/// elimination on working copies, each pivot the largest remaining entry of its vector (pins
/// where the vectors are far from dependent keep the pinned form well conditioned).
pub(super) fn pivots<T: Scalar<Real = f64>>(vectors: &[SparseVector<T>]) -> Vec<usize> {
    let mut work = vectors.to_vec();
    let mut pins = Vec::with_capacity(vectors.len());
    for i in 0..work.len() {
        let (earlier, later) = work.split_at_mut(i + 1);
        let row = &earlier[i];
        // A vector eliminated to zero (dependent on the earlier ones, which checked modes are
        // not) has no pivot: it keeps its first row, as an empty one does, rather than
        // dividing by zero.
        let Some((&pin, &value)) = (row.rows.iter().zip(&row.values))
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .filter(|(_, value)| value.abs() > 0.0)
        else {
            pins.push(vectors[i].rows.first().copied().unwrap_or(0));
            continue;
        };
        let inverse = value.inv();
        for other in later {
            if let Ok(at) = other.rows.binary_search(&pin) {
                // `other ← other − row (row_pin⁻¹ other_pin)`: zero at the pin.
                let factor = inverse * other.values[at];
                *other = other.minus_times(row, factor);
                other.values[at] = T::zero();
            }
        }
        pins.push(pin);
    }
    pins
}

/// The sparse `vectors` (rows in `0..n`) in sets joined by shared rows (union–find over the
/// rows), by index.
fn joined_by_shared_rows<'a, T: 'a>(
    vectors: impl Iterator<Item = &'a SparseVector<T>>,
    n: usize,
) -> DisjointSets {
    let mut owner = vec![usize::MAX; n];
    let mut unions = Vec::new();
    let mut count = 0;
    for (i, vector) in vectors.enumerate() {
        count = i + 1;
        for &row in &vector.rows {
            if owner[row] == usize::MAX {
                owner[row] = i;
            } else {
                unions.push((i, owner[row]));
            }
        }
    }
    let mut sets = DisjointSets::new(count);
    unions.into_iter().for_each(|(a, b)| sets.union(a, b));
    sets
}

/// `M k` for the diagonal mass.
fn mass_weighted<T: Scalar<Real = f64>>(masses: &[f64], k: &SparseVector<T>) -> SparseVector<T> {
    SparseVector {
        rows: k.rows.clone(),
        values: (k.rows.iter().zip(&k.values))
            .map(|(&p, &v)| v.scale(masses[p]))
            .collect(),
    }
}

/// The mode `k` pinned at `pin` if the stiffness annihilates it, with its [`Coupling`].
///
/// The image `g = Q k` counts as zero (and `k* g` likewise) within rounding of the scale of
/// `Q k`, plus the scale `Σ_j |k_j| Σ_i |ΔQ_ij|` of what zeroing the rows of flat faces
/// removed from `Q` (`ΔQ`). That much image the zeroing alone can leave: on a closed piece
/// `Q 𝟙 = 0` as assembled (the normal differences around each vertex sum to zero), and the
/// zeroed rows take their terms out of those sums, so `|g_p| ≤ Σ_q |ΔQ_pq|`. The rows held
/// normal differences within the flat tolerance, zero on exactly flat faces but the noise of
/// the positions on a mesh stored in single precision (`~10⁻⁷`): an image of that size is
/// the zeroing's, not a coupling. Taken for one, it made the pinned form divide by it
/// (`c = (g* r)/(λ |g|²)`) and return pairs that missed the operator by relative residuals
/// near 1 (a rotated cube of flat grids rounded to 32 bits).
fn kernel_mode<T: Scalar<Real = f64>>(
    accumulator: &mut Accumulator<T>,
    kind: ModeKind,
    vector: SparseVector<T>,
    pin: usize,
    matrices: ModeMatrices<'_, T>,
) -> Option<KernelMode<T>> {
    let residue = accumulator.image(matrices.stiffness, &vector);
    let scale = stiffness_scale(matrices.stiffness, &vector, matrices.uninvolved);
    if l1(&residue) > MODE_TOLERANCE * scale {
        return None;
    }
    let mut mode = KernelMode {
        kind,
        vector,
        coupling: Coupling::Free,
        image: SparseVector {
            rows: Vec::new(),
            values: Vec::new(),
        },
        pin,
    };
    coupled(accumulator, &mut mode, matrices);
    Some(mode)
}

/// Sets `mode`'s image `g = Q k` and its [`Coupling`] for its vector `k` (see [`kernel_mode`]).
fn coupled<T: Scalar<Real = f64>>(
    accumulator: &mut Accumulator<T>,
    mode: &mut KernelMode<T>,
    matrices: ModeMatrices<'_, T>,
) {
    let vector = &mode.vector;
    let image = accumulator.image(matrices.coupling, vector);
    let zeroed = matrices
        .zeroed
        .map_or(0.0, |zeroed| column_mass(zeroed, vector));
    let reference = MODE_TOLERANCE * column_mass(matrices.coupling, vector);
    let largest = vector.values.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let coupling = if l1(&image) <= reference + zeroed {
        Coupling::Free
    } else if vector.inner_sparse(&image).abs() <= reference + largest * zeroed {
        Coupling::Orthogonal
    } else {
        Coupling::Oblique
    };
    (mode.coupling, mode.image) = (coupling, image);
}

/// The vertices kept in a reduced problem, in mass-scaled coordinates `z = M^{1/2} y`, and the
/// map back. In these coordinates Euclidean norms are the mass norm of vectors and the dual
/// norm of integrated quantities, so the eigensolver's residual test is the one the results
/// are judged by (sliver triangles would otherwise dominate it), and the matrices are
/// equilibrated.
#[derive(Debug, Clone)]
pub(super) struct Reduction {
    /// Reduced index → vertex.
    pub kept: Vec<usize>,
    /// Vertex → reduced index.
    index: Vec<Option<usize>>,
    /// `1/√Ā_p` per reduced index.
    weights: Vec<f64>,
}

impl Reduction {
    /// Keeps the vertices `0..n` (`n = masses.len()`) not in `removed`.
    pub fn without(masses: &[f64], removed: impl IntoIterator<Item = usize>) -> Self {
        let n = masses.len();
        let mut keep = vec![true; n];
        removed.into_iter().for_each(|p| keep[p] = false);
        let kept: Vec<usize> = (0..n).filter(|&p| keep[p]).collect();
        let mut index = vec![None; n];
        kept.iter()
            .enumerate()
            .for_each(|(r, &p)| index[p] = Some(r));
        let weights = kept.iter().map(|&p| 1.0 / masses[p].sqrt()).collect();
        Self {
            kept,
            index,
            weights,
        }
    }

    /// `W X W` on the kept vertices, `W = M^{-1/2}`: the matrix in scaled coordinates; `None`
    /// if an entry leaves floating-point range. Built column by column from `X`'s own arrays:
    /// the kept vertices are ascending, so the row indices stay sorted and nothing is re-sorted
    /// (a triplet assembly would sort every column again).
    pub fn matrix<T: Scalar<Real = f64>>(&self, x: &SparseMatrix<T>) -> Option<SparseMatrix<T>> {
        let mut col_ptr = Vec::with_capacity(self.kept.len() + 1);
        let mut row_idx = Vec::with_capacity(x.nnz());
        let mut values = Vec::with_capacity(x.nnz());
        col_ptr.push(0);
        for (c, &j) in self.kept.iter().enumerate() {
            let (rows, entries) = x.col(j);
            for (&i, &v) in rows.iter().zip(entries) {
                if let Some(r) = self.index[i] {
                    row_idx.push(r);
                    values.push(v.scale(self.weights[r] * self.weights[c]));
                }
            }
            col_ptr.push(row_idx.len());
        }
        // The pattern is valid by construction, so the only failure is a non-finite entry.
        SparseMatrix::try_from_csc(self.kept.len(), self.kept.len(), col_ptr, row_idx, values).ok()
    }

    /// `W c` on the kept vertices: an integrated quantity (a constraint's functional, a term of
    /// a low-rank update) in scaled coordinates.
    pub fn functional<T: Scalar<Real = f64>>(&self, c: &SparseVector<T>) -> SparseVector<T> {
        // `kept` increases, so reduced indices increase with the vertices.
        let (rows, values) = (c.rows.iter().zip(&c.values))
            .filter_map(|(&p, &v)| self.index[p].map(|r| (r, v.scale(self.weights[r]))))
            .unzip();
        SparseVector { rows, values }
    }

    /// The full vector `x = W z` (zero at removed vertices) of a scaled reduced one.
    pub fn expand<T: Scalar<Real = f64>>(&self, z: &[T], n: usize) -> Vec<T> {
        let mut x = vec![T::zero(); n];
        for ((&p, &w), &v) in self.kept.iter().zip(&self.weights).zip(z) {
            x[p] = v.scale(w);
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vector(entries: &[(usize, f64)]) -> SparseVector<f64> {
        SparseVector {
            rows: entries.iter().map(|e| e.0).collect(),
            values: entries.iter().map(|e| e.1).collect(),
        }
    }

    #[test]
    fn pivots_are_rows_where_no_combination_vanishes() {
        // Both vectors are largest at row 1; the second, eliminated there, keeps row 2.
        let vectors = [
            vector(&[(0, 0.5), (1, 2.0), (2, 0.1)]),
            vector(&[(1, 1.0), (2, 0.3)]),
        ];
        let pins = pivots(&vectors);
        assert_eq!(pins, [1, 2]);
        // The 2 × 2 matrix of the vectors at the pins is not singular.
        let at = |v: &SparseVector<f64>, row| v.to_dense(3)[row];
        let det = at(&vectors[0], pins[0]) * at(&vectors[1], pins[1])
            - at(&vectors[0], pins[1]) * at(&vectors[1], pins[0]);
        assert!(det.abs() > 0.1, "determinant {det}");
    }

    #[test]
    fn a_dependent_vector_has_no_pivot_and_no_division_by_zero() {
        let vectors = [vector(&[(3, 1.0), (4, 2.0)]), vector(&[(3, 2.0), (4, 4.0)])];
        assert_eq!(pivots(&vectors), [4, 3]);
    }
}
