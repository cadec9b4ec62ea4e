//! What the structure of a first-order operator `D_{f,f2}` tells of its kernel (docs/MATH.md,
//! "The exact kernel"): the pieces a kernel vector is constant on, the linear functions `u f2`
//! of the pieces parallel to one direction, the kernel on pieces held together by rulings, and
//! the pieces where more may be in the kernel.
//! Up to the factor `−1/(2A_t)` the row of face `t` is `Σ_p (f2_r − f2_q) ψ_p` over its corners
//! `p`, `q → r` the edge opposite `p`: what it asks of a kernel vector depends only on the
//! triangle of `f2` ([`SecondTriangle`]).

use std::borrow::Cow;
use std::collections::{HashMap, HashSet};

use qscalar::{Quat, Scalar};
use qsparse::vector::axpy;
use qsparse::{DenseMatrix, DisjointSets, SparseVector};

use super::SecondSurface;
use super::determined::DeterminedCorners;
use super::flatness::{FacesAround, length_scale};
use super::kernel::{KernelStructure, PinnedVector, pivots};
use crate::TriMesh;
use crate::geometry::{cross, dot, norm, normalize, sub};
use crate::phase::{mass_inner, mass_norm};

/// What the structure of a first-order operator `D_{f,f2}` tells of its kernel
/// (docs/MATH.md, "The exact kernel"): the pieces a kernel vector is constant on, the linear
/// functions `u f2` it annihilates besides the constants on the pieces where every triangle of
/// `f2` is parallel to one direction `u` ([`parallel_faces`]), a basis of the kernel where
/// rulings leave more, and where it may be larger than all that.
#[derive(Debug, Clone)]
pub(super) struct FirstOrderKernel<T> {
    /// Which surface `f2` is.
    pub surface: SecondSurface,
    /// What the kernel's search checks against the matrices:
    /// * the pieces ([`kernel_pieces`]) of the rows that are neither skipped nor freed
    ///   ([`FreedRows`]): finer than their faces' components where two corners of a triangle
    ///   of `f2` coincide;
    /// * `u (f2 − f̄2)` on each parallel piece with no segment, `f̄2` the mass-weighted mean
    ///   over the piece (so the mode is mass-orthogonal to its constant): the kernel there is
    ///   exactly the constant and this function;
    /// * by piece root, a mass-orthonormal basis of the kernel on each piece whose rulings
    ///   leave more than the constant and `u f2` ([`RuledPieces::basis`]), pinned; it replaces
    ///   them;
    /// * the corners the freed rows determine.
    pub structure: KernelStructure<T>,
    /// The first piece whose kernel may be larger than what is removed: the spectrum stops
    /// there with an error.
    pub unremoved: Option<Unremoved>,
}

/// A piece of the kernel of `D_{f,f2}` that may hold more than its constant and `u f2`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Unremoved {
    /// A parallel piece where some triangles are segments of three distinct points, whose rows
    /// annihilate the functions linear along each segment too: its smallest vertex and `u`
    /// (`None`: every triangle a segment).
    Segments {
        vertex: usize,
        direction: Option<[f64; 3]>,
    },
    /// A piece with [`SecondTriangle::Pair`]s whose kernel ([`add_kernel_on_rulings`]) may be
    /// larger than its constant and `u f2` and is not computed (more parameters than
    /// [`PARAMETERS_COMPUTED`], or a failed eigensolve): its smallest vertex.
    Rulings { vertex: usize },
}

/// Unit face normals within this of perpendicular to a direction are parallel to it, triangles
/// whose height is below this times their longest edge are segments, two of whose corners
/// closer than this times that edge coincide, and triangles whose longest edge is below this
/// times the size of the second surface are points (rounding leaves `~10⁻¹⁶`, and `10⁻¹³` on
/// sliver faces).
const PARALLEL_TOLERANCE: f64 = 1e-10;

/// A triangle of the second surface `f2`, by what its row of `D_{f,f2}` asks of a kernel vector
/// `ψ`: up to the factor `−1/(2A)`, the row is `Σ_p (f2_r − f2_q) ψ_p` over its corners `p`, with
/// `q → r` the edge opposite `p`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum SecondTriangle {
    /// Its corners coincide: the row vanishes and asks nothing.
    Point,
    /// Two corners `a`, `b` coincide and the third `c` does not: the row is `(f2_c − f2_a)(ψ_a −
    /// ψ_b)` up to sign (the third corner's coefficient vanishes), and asks only `ψ_a = ψ_b`.
    /// A crease between flat parts and a cylinder with its vertices on straight rulings give
    /// such triangles of normals.
    Pair(usize, usize),
    /// Three distinct points on one line: the row annihilates the functions linear along the
    /// line as well as the constants.
    Segment,
    /// A proper triangle, with its unit normal: the row annihilates the constants and, on three
    /// corners, the linear functions `u f2` for `u` in its plane.
    Triangle([f64; 3]),
}

/// The triangles of a second surface `f2` (one point per vertex of the mesh).
struct SecondTriangles<'a> {
    positions: &'a [[f64; 3]],
    /// The diagonal of its bounding box, against which a [`SecondTriangle::Point`] is measured.
    size: f64,
    /// For the Gauss map: the mesh's positions and `flat tolerance / √area`. Two normals
    /// coincide only along an edge that is flat too (`|N_a − N_b| ≤ tolerance · |f_a − f_b| /
    /// √area`, [`super::flatness::FlatTest::flat_faces`]): with tolerance 0, only exactly
    /// equal normals do, and normals that differ by noise keep the rows that see it.
    flat_edges: Option<(&'a [[f64; 3]], f64)>,
}

impl<'a> SecondTriangles<'a> {
    fn new(positions: &'a [[f64; 3]], flat_edges: Option<(&'a [[f64; 3]], f64)>) -> Self {
        let (mut low, mut high) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in positions {
            for c in 0..3 {
                (low[c], high[c]) = (low[c].min(p[c]), high[c].max(p[c]));
            }
        }
        Self {
            positions,
            size: norm(sub(high, low)),
            flat_edges,
        }
    }

    /// The faces of `mesh` that are not `skipped`, each with its index and its triangle.
    fn classified<'b>(
        &'b self,
        mesh: &'b TriMesh,
        skipped: &'b [bool],
    ) -> impl Iterator<Item = (usize, [usize; 3], SecondTriangle)> + 'b {
        (mesh.faces().iter().enumerate())
            .zip(skipped)
            .filter(|(_, s)| !**s)
            .map(|((t, &face), _)| (t, face, self.classify(face)))
    }

    /// Whether corners `a` and `b`, at distance `distance` in `f2`, coincide within `bound`.
    fn coincide(&self, a: usize, b: usize, distance: f64, bound: f64) -> bool {
        distance <= bound
            && self.flat_edges.is_none_or(|(mesh, per_length)| {
                distance <= per_length * norm(sub(mesh[a], mesh[b]))
            })
    }

    /// What the triangle of `face` is (computed where needed rather than stored: the memory of
    /// a mesh's size, at the peak of the assembly).
    fn classify(&self, [a, b, c]: [usize; 3]) -> SecondTriangle {
        let (p, q, r) = (self.positions[a], self.positions[b], self.positions[c]);
        let edges = [norm(sub(r, q)), norm(sub(p, r)), norm(sub(q, p))];
        let longest = edges[0].max(edges[1]).max(edges[2]);
        // The edge opposite a corner joins the other two.
        let pairs = [(b, c), (c, a), (a, b)];
        let point = PARALLEL_TOLERANCE * self.size;
        if (0..3).all(|i| self.coincide(pairs[i].0, pairs[i].1, edges[i], point)) {
            return SecondTriangle::Point;
        }
        let pair = PARALLEL_TOLERANCE * longest;
        if let Some(i) = (0..3).find(|&i| self.coincide(pairs[i].0, pairs[i].1, edges[i], pair)) {
            return SecondTriangle::Pair(pairs[i].0, pairs[i].1);
        }
        let normal = cross(sub(q, p), sub(r, p));
        if norm(normal) > PARALLEL_TOLERANCE * longest * longest {
            SecondTriangle::Triangle(normalize(normal))
        } else {
            SecondTriangle::Segment
        }
    }
}

/// The pieces of the kernel of `D_{f,f2}` (faces `skipped` have vanishing rows): vertices joined
/// by every triangle of `f2` that ties their values in a kernel vector, all three corners of a
/// [`SecondTriangle::Triangle`] or a [`SecondTriangle::Segment`], the two coinciding corners of
/// a [`SecondTriangle::Pair`]. A kernel vector constant on each piece satisfies every row; on a
/// crease from boundary to boundary or a cylinder of straight rulings the pieces are the
/// rulings, each with its own constant.
fn kernel_pieces(mesh: &TriMesh, triangles: &SecondTriangles, skipped: &[bool]) -> DisjointSets {
    let mut pieces = DisjointSets::new(mesh.vertex_count());
    for (_, [a, b, c], triangle) in triangles.classified(mesh, skipped) {
        match triangle {
            SecondTriangle::Point => {}
            SecondTriangle::Pair(p, q) => pieces.union(p, q),
            SecondTriangle::Segment | SecondTriangle::Triangle(_) => {
                pieces.union(a, b);
                pieces.union(b, c);
            }
        }
    }
    pieces
}

/// A piece of the kernel ([`kernel_pieces`]) on which every proper triangle of a second surface
/// `f2` is parallel to one unit direction.
#[derive(Debug, Clone, PartialEq)]
struct ParallelPiece {
    /// Its vertices, ascending.
    vertices: Vec<usize>,
    /// The direction `u` (`|u · n_t| ≤` [`PARALLEL_TOLERANCE`] for the unit normals `n_t` of its
    /// proper triangles); `None` if it has none, only segments (parallel to every direction).
    direction: Option<[f64; 3]>,
    /// Whether some triangle is a segment of three distinct points.
    segments: bool,
}

/// The pieces of the kernel of `D_{f,f2}` ([`kernel_pieces`], faces `skipped`) with a proper
/// triangle or a segment of `f2`, every one of which is parallel to one unit direction `u`, by
/// smallest vertex.
///
/// On such a piece `D_{f,f2}` annihilates, besides the constant, the linear function `u f2 q`
/// (`f2` itself if every triangle is a segment): `df2 ∧ d(u f2) = df2(X) u df2(Y) − df2(Y) u
/// df2(X)` vanishes when the three vectors lie in one plane, or `df2(X)` and `df2(Y)` on one
/// line, which they do on every face, and the discrete operator is exact on linear functions;
/// the rows of [`SecondTriangle::Pair`]s ask only equal values where `f2` is equal. For `f2 = f`
/// a planar piece is parallel to every direction of its plane, a prism (an open tube of
/// straight rulings, a folded strip) to its rulings; for the Gauss map `f2 = N` the triangles
/// of normals are parallel to the axis on a tube whose normals all lie in one plane, and to the
/// crease along a crease between flat parts.
fn parallel_faces(
    mesh: &TriMesh,
    triangles: &SecondTriangles,
    skipped: &[bool],
    pieces: &mut DisjointSets,
) -> Vec<ParallelPiece> {
    let n = mesh.vertex_count();
    // Per piece: whether it has a proper triangle or a segment, the direction its normals may
    // share, and whether it has a segment.
    let mut present = vec![false; n];
    let mut shared = vec![SharedDirection::default(); n];
    let mut segments = vec![false; n];
    for (_, face, triangle) in triangles.classified(mesh, skipped) {
        let root = pieces.find(face[0]);
        match triangle {
            SecondTriangle::Point | SecondTriangle::Pair(..) => continue,
            SecondTriangle::Segment => segments[root] = true,
            SecondTriangle::Triangle(normal) => shared[root].add(normal),
        }
        present[root] = true;
    }
    let direction: Vec<Option<[f64; 3]>> = shared.iter().map(SharedDirection::candidate).collect();
    drop(shared);
    let mut parallel = present;
    for (_, face, triangle) in triangles.classified(mesh, skipped) {
        let root = pieces.find(face[0]);
        if let (Some(u), SecondTriangle::Triangle(normal)) = (direction[root], triangle) {
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

/// The [`FirstOrderKernel`] of `D_{f,f2}` with `f2 = positions` (one point per vertex), the rows
/// of the `skipped` faces vanishing, `masses` the vertex masses of the mesh, the well's
/// `potential`; the flat tolerance decides where normals coincide when `surface` is the Gauss
/// map ([`SecondTriangles`]), and nothing for the other surfaces, whose points are compared
/// exactly.
pub(super) fn first_order_kernel(
    mesh: &TriMesh,
    masses: &[f64],
    positions: &[[f64; 3]],
    skipped: &[bool],
    potential: Option<&[f64]>,
    flat_tolerance: f64,
    surface: SecondSurface,
) -> FirstOrderKernel<Quat<f64>> {
    let flat_edges = (surface == SecondSurface::GaussMap)
        .then(|| (mesh.positions(), flat_tolerance / length_scale(mesh)));
    let triangles = SecondTriangles::new(positions, flat_edges);
    let freed = FreedRows::of(mesh, &triangles, skipped, potential);
    // The rows left: neither flat nor freed.
    let skipped: Cow<[bool]> = if freed.determined.is_empty() {
        Cow::Borrowed(skipped)
    } else {
        Cow::Owned(
            (skipped.iter().zip(&freed.freed))
                .map(|(&s, &f)| s || f)
                .collect(),
        )
    };
    let skipped = skipped.as_ref();
    let mut pieces = kernel_pieces(mesh, &triangles, skipped);
    let parallel = parallel_faces(mesh, &triangles, skipped, &mut pieces);
    let mut kernel = FirstOrderKernel {
        surface,
        structure: KernelStructure {
            determined: freed.determined,
            uninvolved: freed.uninvolved,
            ..KernelStructure::of_pieces(pieces)
        },
        unremoved: None,
    };
    let mut linear_pieces = HashSet::new();
    for piece in parallel {
        let (Some(u), false) = (piece.direction, piece.segments) else {
            kernel.unremoved.get_or_insert(Unremoved::Segments {
                vertex: piece.vertices[0],
                direction: piece.direction,
            });
            continue;
        };
        linear_pieces.insert(kernel.structure.pieces.find(piece.vertices[0]));
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
        kernel.structure.linear.push(SparseVector {
            rows: piece.vertices,
            values,
        });
    }
    if kernel.unremoved.is_none() {
        add_kernel_on_rulings(
            &mut kernel,
            mesh,
            &triangles,
            skipped,
            potential,
            masses,
            &linear_pieces,
        );
    }
    kernel
}

/// The rows of `D_{f,f2}` freed by a corner that no other row involves ([`super::determined`]),
/// one after the other until none is left.
///
/// A row involves all three corners of a [`SecondTriangle::Triangle`] or a
/// [`SecondTriangle::Segment`] (every coefficient `f2_r − f2_q` is nonzero), the two
/// coinciding corners of a [`SecondTriangle::Pair`] (it asks `ψ_a = ψ_b`), and none of a
/// [`SecondTriangle::Point`]. Rows where the well's potential is not zero at a corner involve
/// the corners where their coefficients ([`Row::Well`]) are not zero.
struct FreedRows {
    /// By face: its row is freed.
    freed: Vec<bool>,
    /// How the corner of each freed row follows from the others.
    determined: DeterminedCorners<Quat<f64>>,
    /// The vertices of rows that are not skipped which no row involves once the freed rows are
    /// out and which are not determined (ascending): third corners of pairs, and corners left
    /// of rows freed around them.
    uninvolved: Vec<usize>,
}

impl FreedRows {
    /// The rows of the faces not `skipped`, freed.
    fn of(
        mesh: &TriMesh,
        triangles: &SecondTriangles,
        skipped: &[bool],
        potential: Option<&[f64]>,
    ) -> Self {
        // By face: bit `i` if the row involves corner `i`.
        let mut rows = vec![0u8; mesh.face_count()];
        let mut involving = vec![0u32; mesh.vertex_count()];
        let mut in_a_row = vec![false; mesh.vertex_count()];
        let row_of = |t: usize| Row::of(mesh, triangles.positions, potential, t);
        for (t, face, triangle) in triangles.classified(mesh, skipped) {
            let corner = |v| 1u8 << face.iter().position(|&p| p == v).unwrap_or(0);
            let corners = match (row_of(t), triangle) {
                (Row::Well(c), _) => (0..3)
                    .filter(|&i| c[i] != Quat::from_real(0.0))
                    .fold(0, |m, i| m | 1 << i),
                (_, SecondTriangle::Point) => 0,
                (_, SecondTriangle::Pair(a, b)) => corner(a) | corner(b),
                (_, SecondTriangle::Segment | SecondTriangle::Triangle(_)) => 0b111,
            };
            rows[t] = corners;
            for i in 0..3 {
                involving[face[i]] += u32::from(corners & (1 << i) != 0);
                in_a_row[face[i]] = true;
            }
        }
        let mut freed = vec![false; mesh.face_count()];
        let mut determined = DeterminedCorners::default();
        let mut candidates: Vec<usize> = (0..involving.len())
            .filter(|&v| involving[v] == 1)
            .collect();
        // Most closed meshes have none: no table of the faces around each vertex then.
        let around = (!candidates.is_empty()).then(|| FacesAround::of(mesh));
        let around_of = |v| around.as_ref().map_or(&[][..], |a| a.at(v));
        while let Some(v) = candidates.pop() {
            // The one row that involves `v`, if it may be freed.
            let row = around_of(v).iter().copied().find(|&t| {
                let i = mesh.faces()[t].iter().position(|&p| p == v).unwrap_or(0);
                rows[t] & (1 << i) != 0
            });
            let Some(t) = row.filter(|_| involving[v] == 1) else {
                continue;
            };
            let face = mesh.faces()[t];
            let involved: Vec<usize> = (0..3).filter(|i| rows[t] & (1 << i) != 0).collect();
            let free = |i: usize| involving[face[i]] == 1;
            row_of(t).determine(face, &involved, free, &mut determined);
            (rows[t], freed[t]) = (0, true);
            for &i in &involved {
                involving[face[i]] -= 1;
                if involving[face[i]] == 1 {
                    candidates.push(face[i]);
                }
            }
        }
        determined.corners().for_each(|c| in_a_row[c] = false);
        let uninvolved = (0..involving.len())
            .filter(|&v| in_a_row[v] && involving[v] == 0)
            .collect();
        Self {
            freed,
            determined,
            uninvolved,
        }
    }
}

/// The coefficients of a row of `D_{f,f2}`, up to a common factor.
enum Row {
    /// `e_p = f2_r − f2_q` at corner `p` (`q → r` the edge opposite it), which sum to zero.
    Dirac([[f64; 3]; 3]),
    /// With the well's potential `U` not zero at a corner: `−e_p / (2A) + U_p / 3`.
    Well([Quat<f64>; 3]),
}

impl Row {
    /// The row of face `t` of `mesh`, for the second surface `f2` and the well's `potential`.
    fn of(mesh: &TriMesh, f2: &[[f64; 3]], potential: Option<&[f64]>, t: usize) -> Self {
        let face = mesh.faces()[t];
        let e = |i: usize| sub(f2[face[(i + 2) % 3]], f2[face[(i + 1) % 3]]);
        match potential.filter(|u| face.iter().any(|&p| u[p] != 0.0)) {
            None => Row::Dirac([e(0), e(1), e(2)]),
            Some(u) => {
                let scale = -1.0 / (2.0 * mesh.face_area(t));
                let c =
                    |i: usize| Quat::from_vector(e(i)) * scale + Quat::from_real(u[face[i]] / 3.0);
                Row::Well([c(0), c(1), c(2)])
            }
        }
    }

    /// The coefficient at corner `i`.
    fn coefficient(&self, i: usize) -> Quat<f64> {
        match self {
            Row::Dirac(e) => Quat::from_vector(e[i]),
            Row::Well(c) => c[i],
        }
    }

    /// Records how a corner of this row of `face` that no other row involves (`free`) follows
    /// from its other `involved` corners (indices into `face`). Of several such corners, the
    /// one with the largest coefficient is determined:
    /// `ψ_c = −c_c⁻¹ (c_a ψ_a + c_b ψ_b) = −c_c⁻¹ (c_a + c_b) ψ_a − c_c⁻¹ c_b (ψ_b − ψ_a)`, whose
    /// first factor is exactly 1 for a row of `D_{f,f2}` (its coefficients sum to zero).
    fn determine(
        &self,
        face: [usize; 3],
        involved: &[usize],
        free: impl Fn(usize) -> bool,
        determined: &mut DeterminedCorners<Quat<f64>>,
    ) {
        let one = Quat::from_real(1.0);
        if let (Row::Dirac(_), [i, j]) = (self, involved) {
            // A pair asks `ψ_a = ψ_b`: the free corner takes its partner's value.
            let (leaf, other) = if free(*i) {
                (face[*i], face[*j])
            } else {
                (face[*j], face[*i])
            };
            determined.push(leaf, other, other, one, Quat::from_real(0.0));
            return;
        }
        let Some(&i) = (involved.iter()).filter(|&&i| free(i)).max_by(|&&a, &&b| {
            self.coefficient(a)
                .abs()
                .total_cmp(&self.coefficient(b).abs())
        }) else {
            return;
        };
        let others: Vec<usize> = involved.iter().copied().filter(|&j| j != i).collect();
        let inverse = -self.coefficient(i).inv();
        let (base, toward) = match others[..] {
            [a, b] => (a, b),
            [a] => (a, a),
            _ => (i, i),
        };
        let base_weight = match self {
            Row::Dirac(_) => one,
            Row::Well(_) if others.is_empty() => Quat::from_real(0.0),
            Row::Well(c) => inverse * others.iter().map(|&j| c[j]).sum::<Quat<f64>>(),
        };
        let weight = if toward == base {
            Quat::from_real(0.0)
        } else {
            inverse * self.coefficient(toward)
        };
        determined.push(face[i], face[base], face[toward], base_weight, weight);
    }
}

/// Pieces whose kernel propagation does not bound, and whose rigid parts have more
/// parameters than this, are not computed: the null space is a dense Hermitian eigensolve of
/// their order (an open tube of 128 sides, 2 edges each, takes 1.7 s in all).
pub(super) const PARAMETERS_COMPUTED: usize = 1024;

/// Adds to `kernel` the kernel on the pieces with [`SecondTriangle::Pair`]s where it is larger
/// than their constant and, on the `linear_pieces` (roots), `u f2`: a pinned basis by piece
/// root ([`RuledPieces::basis`], with `masses`), or the first piece (by smallest vertex) where
/// it is not computed.
///
/// The pieces join the three corners of proper triangles, which presumes that a kernel vector
/// is one constant (and one multiple of `u f2`) on all of them. That holds where proper
/// triangles share edges: two corners of distinct `f2` fix both parameters of a face's kernel
/// `α + (u f2) β`, and so those of its neighbour across the edge. But a piece can be held
/// together by *rulings* (the classes of coinciding corners, one value each) that meet proper
/// triangles at single vertices, as where the normals of a crease turn at the boundary, and
/// then each ruling may carry its own value. So the kernel of each piece with pairs is counted
/// ([`RuledPieces`]), and computed where the count exceeds what the constant and `u f2` hold.
/// Pieces where the well's `potential` is not zero are skipped: their rows are not those of
/// `D_{f,f2}`, and their constants are no kernel vectors anyway.
fn add_kernel_on_rulings(
    kernel: &mut FirstOrderKernel<Quat<f64>>,
    mesh: &TriMesh,
    triangles: &SecondTriangles,
    skipped: &[bool],
    potential: Option<&[f64]>,
    masses: &[f64],
    linear_pieces: &HashSet<usize>,
) {
    let pieces = &mut kernel.structure.pieces;
    let Some(mut ruled) = RuledPieces::new(mesh, triangles, skipped, potential, pieces) else {
        return;
    };
    let bound = ruled.propagated_bound();
    let mut roots: Vec<usize> = (0..mesh.vertex_count())
        .filter(|&r| ruled.ruled[r] && ruled.pieces.find(r) == r)
        .collect();
    roots.sort_by_key(|&r| ruled.smallest[r]);
    for root in roots {
        let known = 1 + usize::from(linear_pieces.contains(&root));
        if bound[root] <= known {
            continue;
        }
        let Some(basis) = ruled.basis(root, masses) else {
            let vertex = ruled.smallest[root];
            kernel.unremoved = Some(Unremoved::Rulings { vertex });
            return;
        };
        if basis.len() > known {
            kernel.structure.ruled.insert(root, basis);
        }
    }
}

/// Where a ruling meets a rigid part: at `vertex` (one per ruling and part).
#[derive(Debug, Clone, Copy)]
struct Contact {
    ruling: usize,
    part: usize,
    vertex: usize,
}

/// A rigid part of a piece with rulings ([`RuledPieces`]).
#[derive(Debug, Clone, Copy)]
struct RigidPart {
    /// The root of its piece.
    piece: usize,
    /// The index of its first parameter `α` within the piece (`β` follows).
    offset: usize,
    /// `u` if it has a `β`: every triangle parallel to it.
    direction: Option<[f64; 3]>,
    /// The longest edge of `f2` among its faces.
    size: f64,
    /// A vertex of it, from which `f2` is measured: the part's value at `v` is `α + k_v β`,
    /// `k_v = u (f2_v − f2_anchor)/size`, of order 1.
    anchor: usize,
}

/// The pieces of the kernel with [`SecondTriangle::Pair`]s, as rulings and rigid parts.
///
/// On each *rigid part* (proper triangles and segments connected through edges) a kernel
/// vector is `α + (u f2) β`, with `β` only where the part is parallel to one direction `u` (a
/// segment annihilates the functions affine along it, `α + (u f2) β` for any `u`): one or two
/// quaternionic parameters. On each *ruling* (vertices joined by coinciding corners) it is one
/// value. A ruling that meets several parts asks their values to agree there, and a ruling
/// that meets none is free: the dimension of the kernel on a piece is its free rulings plus
/// its parameters minus the rank of the agreements.
struct RuledPieces<'a> {
    pieces: &'a mut DisjointSets,
    /// By piece root: whether it has pairs (and no potential).
    ruled: Vec<bool>,
    /// By piece root: its smallest vertex.
    smallest: Vec<usize>,
    /// By piece root: its rulings that meet no part.
    free: Vec<usize>,
    /// By piece root: the parameters of its parts.
    parameters: Vec<usize>,
    /// By part: the root face of its faces.
    parts: HashMap<usize, RigidPart>,
    /// Sorted by ruling, then part.
    contacts: Vec<Contact>,
    /// The rulings: vertices joined by coinciding corners.
    rulings: DisjointSets,
    positions: &'a [[f64; 3]],
}

impl<'a> RuledPieces<'a> {
    /// `None` when no piece has pairs (the common case).
    fn new(
        mesh: &TriMesh,
        triangles: &'a SecondTriangles,
        skipped: &[bool],
        potential: Option<&[f64]>,
        pieces: &'a mut DisjointSets,
    ) -> Option<Self> {
        let (n, m) = (mesh.vertex_count(), mesh.face_count());
        let f2 = triangles.positions;
        let faces = || triangles.classified(mesh, skipped);
        let mut rulings = DisjointSets::new(n);
        let mut ruled = vec![false; n];
        for (_, _, triangle) in faces() {
            if let SecondTriangle::Pair(a, b) = triangle {
                rulings.union(a, b);
                ruled[pieces.find(a)] = true;
            }
        }
        if let Some(u) = potential {
            (0..n)
                .filter(|&p| u[p] != 0.0)
                .for_each(|p| ruled[pieces.find(p)] = false);
        }
        if !ruled.contains(&true) {
            return None;
        }
        // The rigid parts: faces joined through shared edges.
        let mut parts = DisjointSets::new(m);
        let mut rigid = vec![false; m];
        let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
        for (t, face, triangle) in faces() {
            if matches!(triangle, SecondTriangle::Point | SecondTriangle::Pair(..))
                || !ruled[pieces.find(face[0])]
            {
                continue;
            }
            rigid[t] = true;
            for (a, b) in [(face[0], face[1]), (face[1], face[2]), (face[2], face[0])] {
                let other = *edges.entry((a.min(b), a.max(b))).or_insert(t);
                parts.union(t, other);
            }
        }
        drop(edges);
        // By part: the direction its normals may share, and its longest edge of `f2`.
        let mut shared: HashMap<usize, SharedDirection> = HashMap::new();
        let mut longest: HashMap<usize, f64> = HashMap::new();
        for (t, face, triangle) in faces().filter(|(t, ..)| rigid[*t]) {
            let part = parts.find(t);
            let direction = shared.entry(part).or_default();
            if let SecondTriangle::Triangle(normal) = triangle {
                direction.add(normal);
            }
            let [a, b, c] = face.map(|p| f2[p]);
            let size = longest.entry(part).or_default();
            *size = size
                .max(norm(sub(b, a)))
                .max(norm(sub(c, b)))
                .max(norm(sub(a, c)));
        }
        // `u` per part where it has a `β`: a part of segments only takes any.
        let mut direction: HashMap<usize, Option<[f64; 3]>> = (shared.iter())
            .map(|(&part, d)| {
                (
                    part,
                    d.first.map_or(Some([1.0, 0.0, 0.0]), |_| d.candidate()),
                )
            })
            .collect();
        for (t, _, triangle) in faces().filter(|(t, ..)| rigid[*t]) {
            if let (Some(u), SecondTriangle::Triangle(normal)) =
                (direction.get_mut(&parts.find(t)), triangle)
                && u.is_some_and(|axis| dot(axis, normal).abs() > PARALLEL_TOLERANCE)
            {
                *u = None;
            }
        }
        let mut parameters = vec![0; n];
        let mut rigid_parts = HashMap::new();
        let mut contacts = Vec::new();
        for (t, face, _) in faces().filter(|(t, ..)| rigid[*t]) {
            let (part, piece) = (parts.find(t), pieces.find(face[0]));
            rigid_parts.entry(part).or_insert_with(|| {
                let offset = parameters[piece];
                parameters[piece] += 1 + usize::from(direction[&part].is_some());
                RigidPart {
                    piece,
                    offset,
                    direction: direction[&part],
                    size: longest[&part],
                    anchor: face[0],
                }
            });
            contacts.extend(face.map(|vertex| Contact {
                ruling: rulings.find(vertex),
                part,
                vertex,
            }));
        }
        contacts.sort_unstable_by_key(|c| (c.ruling, c.part));
        contacts.dedup_by_key(|c| (c.ruling, c.part));
        let mut touched = vec![false; n];
        contacts.iter().for_each(|c| touched[c.ruling] = true);
        let (mut free, mut smallest) = (vec![0; n], vec![usize::MAX; n]);
        for v in 0..n {
            let piece = pieces.find(v);
            if ruled[piece] {
                smallest[piece] = smallest[piece].min(v);
                let ruling = rulings.find(v);
                free[piece] += usize::from(!touched[ruling]);
                touched[ruling] = true;
            }
        }
        Some(Self {
            pieces,
            ruled,
            smallest,
            free,
            parameters,
            parts: rigid_parts,
            contacts,
            rulings,
            positions: f2,
        })
    }

    /// The parameters of a part.
    fn parameters_of(&self, part: usize) -> usize {
        1 + usize::from(self.parts[&part].direction.is_some())
    }

    /// By piece root, an upper bound of the dimension of its kernel: its free rulings plus the
    /// parameters of the parts that must be chosen (seeds, one-parameter parts and those with
    /// the most contacts first) for the agreements to determine every other part. A ruling is
    /// determined once a part it meets is; a part once one of its contacts is (one parameter)
    /// or two with distinct `f2` (two parameters).
    fn propagated_bound(&self) -> Vec<usize> {
        let mut by_part: HashMap<usize, Vec<Contact>> = HashMap::new();
        self.contacts
            .iter()
            .for_each(|c| by_part.entry(c.part).or_default().push(*c));
        let mut by_ruling: HashMap<usize, &[Contact]> = HashMap::new();
        for group in self.contacts.chunk_by(|a, b| a.ruling == b.ruling) {
            by_ruling.insert(group[0].ruling, group);
        }
        let mut order: Vec<usize> = by_part.keys().copied().collect();
        order.sort_by_key(|&p| (self.parameters_of(p), usize::MAX - by_part[&p].len(), p));
        let mut bound = self.free.clone();
        let mut done: HashSet<usize> = HashSet::new();
        let mut rulings_done: HashSet<usize> = HashSet::new();
        let mut first_contact: HashMap<usize, [f64; 3]> = HashMap::new();
        for seed in order {
            if !done.insert(seed) {
                continue;
            }
            bound[self.parts[&seed].piece] += self.parameters_of(seed);
            let mut queue = vec![seed];
            while let Some(part) = queue.pop() {
                for contact in &by_part[&part] {
                    if !rulings_done.insert(contact.ruling) {
                        continue;
                    }
                    let point = self.positions[contact.vertex];
                    for other in by_ruling[&contact.ruling].iter().map(|c| c.part) {
                        if done.contains(&other) {
                            continue;
                        }
                        let part = &self.parts[&other];
                        let determined = part.direction.is_none()
                            || first_contact.get(&other).is_some_and(|&first| {
                                norm(sub(point, first)) > PARALLEL_TOLERANCE * part.size
                            });
                        first_contact.entry(other).or_insert(point);
                        if determined {
                            done.insert(other);
                            queue.push(other);
                        }
                    }
                }
            }
        }
        bound
    }

    /// The value `α + k_v β` of a part at its vertex `v`, as coefficients of its parameters.
    fn value(&self, part: usize, v: usize) -> Vec<(usize, Quat<f64>)> {
        let part = &self.parts[&part];
        let mut row = vec![(part.offset, Quat::from_real(1.0))];
        if let Some(u) = part.direction {
            let relative = sub(self.positions[v], self.positions[part.anchor])
                .map(|x| x / part.size.max(f64::MIN_POSITIVE));
            row.push((
                part.offset + 1,
                Quat::from_vector(u) * Quat::from_vector(relative),
            ));
        }
        row
    }

    /// The parameters of the parts of the piece of `root` on which the agreements vanish: the
    /// eigenvectors of `CᴴC` (each row of the agreements `C` scaled to largest entry 1) whose
    /// eigenvalues are at most `10⁻⁹` of the largest, orthonormal. `None` above
    /// [`PARAMETERS_COMPUTED`] or if the eigensolve fails.
    fn null_space(&self, root: usize) -> Option<Vec<Vec<Quat<f64>>>> {
        let count = self.parameters[root];
        if count > PARAMETERS_COMPUTED {
            return None;
        }
        let mut normal = DenseMatrix::<Quat<f64>>::zeros(count, count);
        for group in self.contacts.chunk_by(|a, b| a.ruling == b.ruling) {
            let first = group[0];
            if self.parts[&first.part].piece != root {
                continue;
            }
            let reference = self.value(first.part, first.vertex);
            for other in &group[1..] {
                let mut row = reference.clone();
                let theirs = self.value(other.part, other.vertex);
                row.extend(theirs.into_iter().map(|(j, c)| (j, -c)));
                let largest = row.iter().map(|(_, c)| c.abs()).fold(0.0, f64::max);
                for &(j, a) in &row {
                    for &(k, b) in &row {
                        normal.col_mut(k)[j] += (a.conj() * b).scale(1.0 / (largest * largest));
                    }
                }
            }
        }
        if count == 0 {
            return Some(Vec::new());
        }
        let eigen = qeig::dense::hermitian_eigen(&normal).ok()?;
        let top = eigen.values.iter().fold(0.0f64, |m, v| m.max(*v));
        let null = (0..count).filter(|&j| eigen.values[j] <= 1e-9 * top);
        Some(null.map(|j| eigen.vectors.col(j).to_vec()).collect())
    }

    /// A basis of the kernel on the piece of `root`, mass-orthonormal (`masses` of the
    /// vertices), each vector with the vertex that pins it; `None` where
    /// [`Self::null_space`] is. Every vertex takes the value of its ruling: that of the part
    /// it meets first (the agreements make the others equal), or, on a free ruling, one
    /// vector of its own. The pins come from elimination with the largest entry as pivot,
    /// so that no combination of the vectors vanishes at all of them.
    fn basis(&mut self, root: usize, masses: &[f64]) -> Option<Vec<PinnedVector<Quat<f64>>>> {
        let null = self.null_space(root)?;
        let vertices: Vec<usize> = (0..masses.len())
            .filter(|&v| self.pieces.find(v) == root)
            .collect();
        let mut contact_of: HashMap<usize, Contact> = HashMap::new();
        for c in &self.contacts {
            contact_of.entry(c.ruling).or_insert(*c);
        }
        let ruling_of: Vec<usize> = vertices.iter().map(|&v| self.rulings.find(v)).collect();
        let mut vectors: Vec<Vec<Quat<f64>>> = null
            .iter()
            .map(|z| {
                (ruling_of.iter())
                    .map(|r| match contact_of.get(r) {
                        Some(c) => (self.value(c.part, c.vertex).into_iter())
                            .map(|(j, k)| k * z[j])
                            .sum(),
                        None => Quat::from_real(0.0),
                    })
                    .collect()
            })
            .collect();
        let mut free: Vec<usize> = (ruling_of.iter())
            .copied()
            .filter(|r| !contact_of.contains_key(r))
            .collect();
        free.sort_unstable();
        free.dedup();
        for ruling in free {
            vectors.push(
                (ruling_of.iter())
                    .map(|&r| Quat::from_real(if r == ruling { 1.0 } else { 0.0 }))
                    .collect(),
            );
        }
        let mass: Vec<f64> = vertices.iter().map(|&v| masses[v]).collect();
        let orthonormal: Vec<SparseVector<Quat<f64>>> = (mass_orthonormal(vectors, &mass))
            .into_iter()
            .map(|values| SparseVector {
                rows: vertices.clone(),
                values,
            })
            .collect();
        let pins = pivots(&orthonormal);
        Some(
            (orthonormal.into_iter().zip(pins))
                .map(|(vector, pin)| PinnedVector { vector, pin })
                .collect(),
        )
    }
}

/// `vectors` made orthonormal in `⟨x, y⟩ = Σ_p m_p x_p* y_p` by Gram–Schmidt with coefficients
/// on the right (twice, for orthogonality to rounding), dropping those in the span of the
/// earlier ones (norm below `10⁻⁸` of what it was).
fn mass_orthonormal(vectors: Vec<Vec<Quat<f64>>>, mass: &[f64]) -> Vec<Vec<Quat<f64>>> {
    let mut done: Vec<Vec<Quat<f64>>> = Vec::new();
    for mut x in vectors {
        let before = mass_norm(mass, &x);
        for _ in 0..2 {
            for q in &done {
                let alpha = mass_inner(mass, q, &x);
                axpy(&mut x, q, -alpha);
            }
        }
        let norm = mass_norm(mass, &x);
        if norm > 1e-8 * before {
            x.iter_mut().for_each(|a| *a = a.scale(1.0 / norm));
            done.push(x);
        }
    }
    done
}

/// The one direction a set of unit normals may all be perpendicular to: the cross product of
/// the first with the one farthest from parallel to it, or, if all are parallel, a direction
/// of their plane.
#[derive(Debug, Clone, Copy, Default)]
struct SharedDirection {
    first: Option<[f64; 3]>,
    widest: [f64; 3],
}

impl SharedDirection {
    fn add(&mut self, normal: [f64; 3]) {
        match self.first {
            None => self.first = Some(normal),
            Some(reference) => {
                let candidate = cross(reference, normal);
                if norm(candidate) > norm(self.widest) {
                    self.widest = candidate;
                }
            }
        }
    }

    /// The candidate unit direction (`None` before any normal); whether every normal is
    /// perpendicular to it is for the caller to check.
    fn candidate(&self) -> Option<[f64; 3]> {
        let reference = self.first?;
        Some(if norm(self.widest) > PARALLEL_TOLERANCE {
            normalize(self.widest)
        } else {
            // Planar: any direction of the plane; the one across the least aligned axis.
            let axis = (0..3)
                .min_by(|&i, &j| reference[i].abs().total_cmp(&reference[j].abs()))
                .map(|i| std::array::from_fn(|k| if k == i { 1.0 } else { 0.0 }))?;
            normalize(cross(reference, axis))
        })
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators::{grid, icosphere};

    /// [`parallel_faces`] on the pieces of the kernel.
    fn parallel(mesh: &TriMesh, f2: &[[f64; 3]], skipped: &[bool]) -> Vec<ParallelPiece> {
        let triangles = SecondTriangles::new(f2, None);
        let mut pieces = kernel_pieces(mesh, &triangles, skipped);
        parallel_faces(mesh, &triangles, skipped, &mut pieces)
    }

    #[test]
    fn triangles_of_the_second_surface_are_classified_by_what_their_rows_ask() {
        let f2 = [
            [0.0, 0.0, 0.0],
            [1e-17, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 1e-12],
            [0.0, 1.0, 0.0],
            [1e-12, 1.0, 0.0],
        ];
        let triangles = SecondTriangles::new(&f2, None);
        assert_eq!(triangles.classify([2, 0, 1]), SecondTriangle::Pair(0, 1));
        assert_eq!(triangles.classify([0, 2, 1]), SecondTriangle::Pair(1, 0));
        assert_eq!(triangles.classify([0, 2, 3]), SecondTriangle::Segment);
        assert_eq!(triangles.classify([4, 5, 4]), SecondTriangle::Point);
        let SecondTriangle::Triangle(normal) = triangles.classify([0, 2, 4]) else {
            panic!("a proper triangle");
        };
        assert!(norm(sub(normal, [0.0, 0.0, 1.0])) < 1e-15);
    }

    #[test]
    fn parallel_faces_finds_planes_segments_and_nothing_on_a_sphere() {
        let plane = grid(3, 2, 1.0, 1.0).unwrap();
        let none = vec![false; plane.face_count()];
        let found = parallel(&plane, plane.positions(), &none);
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
        let found = parallel(&plane, &line, &none);
        assert_eq!((found[0].direction, found[0].segments), (None, true));

        let sphere = icosphere(1);
        let none = vec![false; sphere.face_count()];
        assert_eq!(parallel(&sphere, sphere.positions(), &none), vec![]);
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
        let found = parallel(&sphere, sphere.positions(), &skipped);
        let got: Vec<Vec<usize>> = found.into_iter().map(|p| p.vertices).collect();
        assert_eq!(got, want);
    }
}
