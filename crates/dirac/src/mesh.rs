//! Validated triangle meshes.
//!
//! [`TriMesh::new`] accepts exactly the consistently oriented, edge- and vertex-manifold triangle
//! meshes without degenerate faces (docs/ARCHITECTURE.md, "The operator layer"). Boundaries and
//! several connected components are allowed; [`TriMesh::topology`] reports them.

use qscalar::Quat;
use qsparse::DisjointSets;
use thiserror::Error;

use crate::geometry::{corner_cotangent, cross, norm, scale, sub};
use crate::repair::orientation;

/// Why a mesh was rejected. Each variant names the offending element; vertex and face indices
/// refer to the arrays given to the constructor.
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
    /// No face uses this vertex ([`TriMesh::with_unreferenced_removed`] drops such vertices).
    #[error("vertex {vertex} is not used by any face")]
    UnreferencedVertex {
        /// The first unreferenced vertex.
        vertex: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// The vertex.
        vertex: usize,
    },
    /// A face has zero area, an area too small for its reciprocal to be finite (subnormal),
    /// or an area that overflows to infinity.
    #[error("face {face} has zero, subnormal or non-finite area")]
    ZeroAreaFace {
        /// The face.
        face: usize,
    },
    /// A face has an angle so close to 0° or 180° that its cotangent (a cotangent-Laplacian
    /// weight) is not finite in floating point.
    #[error("face {face} has an angle at vertex {vertex} whose cotangent is not finite")]
    DegenerateAngle {
        /// The face.
        face: usize,
        /// The vertex at the angle.
        vertex: usize,
    },
    /// More than two faces share an edge.
    #[error("edge {edge:?} is shared by {} faces {faces:?}", faces.len())]
    NonManifoldEdge {
        /// The edge's vertices, smaller index first.
        edge: [usize; 2],
        /// All faces containing the edge.
        faces: Vec<usize>,
    },
    /// Two faces traverse their shared edge in the same direction.
    #[error("faces {faces:?} both traverse edge {edge:?} in the same direction")]
    InconsistentOrientation {
        /// The edge, in the direction both faces traverse it.
        edge: [usize; 2],
        /// The two faces.
        faces: [usize; 2],
    },
    /// The surface is not orientable (a Möbius strip or similar): no choice of the faces'
    /// orientations is consistent, so [`crate::repair`] cannot fix it either. The Dirac
    /// operators act on oriented surfaces (the normal and the orientation of each face
    /// enter `D`).
    #[error(
        "the surface is not orientable (a Möbius-like surface): face {face} cannot be oriented \
         consistently with its neighbours, whatever the orientations chosen; cut the surface \
         along an edge of face {face} or remove its component"
    )]
    NonOrientable {
        /// A face whose orientation conflicts with its neighbours' under every choice.
        face: usize,
    },
    /// The faces around a vertex form more than one fan (the surface is pinched there).
    #[error("the faces around vertex {vertex} form {fans} separate fans")]
    NonManifoldVertex {
        /// The vertex.
        vertex: usize,
        /// Number of fans (edge-connected groups of incident faces).
        fans: usize,
    },
}

/// A triangle mesh: vertex positions and counter-clockwise faces (as seen from the side the
/// normals point to). Always valid: see [`TriMesh::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    positions: Vec<[f64; 3]>,
    faces: Vec<[usize; 3]>,
}

/// An undirected edge of a mesh, oriented as its first face traverses it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// Tail and head, in the direction `face` traverses the edge.
    pub vertices: [usize; 2],
    /// The face traversing `vertices[0] → vertices[1]`.
    pub face: usize,
    /// The face traversing `vertices[1] → vertices[0]`; `None` on a boundary edge.
    pub opposite_face: Option<usize>,
}

/// One face's use of an undirected edge, used to sort and group the edges of a face list
/// (here and by [`crate::repair`]). The face and its direction follow from the corners, so a
/// use takes 32 bytes: building the `3|F|` uses is most of the time of validating a mesh.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EdgeUse {
    /// Smaller vertex.
    pub(crate) lo: usize,
    /// Larger vertex.
    pub(crate) hi: usize,
    /// The face's corners (`3 face + local index`) at `lo` and at `hi`.
    pub(crate) corners: [usize; 2],
}

/// The uses of every edge of `faces`, sorted by edge and then face, so each edge's uses are
/// contiguous (group them with `chunk_by(same_edge)`).
///
/// A counting sort of the use indices `3 face + corner` by the smaller vertex, then a sort of
/// each vertex's few uses by the larger one: both stable, and the indices are counted in face
/// order, so the result is ordered by `(lo, hi, face)` in linear time. A comparison sort of all
/// `3|F|` uses cost more than any other step of reading a mesh, and every mesh is validated,
/// and its topology found, through this function; sorting indices and building each use once,
/// in its final place, halves the memory it writes.
pub(crate) fn edge_uses(faces: &[[usize; 3]]) -> Vec<EdgeUse> {
    let edge_use = |index: usize| {
        let (face, c) = (index / 3, index % 3);
        let f = faces[face];
        let (a, b) = (f[c], f[(c + 1) % 3]);
        let (ca, cb) = (index, next_corner(index));
        if a < b {
            EdgeUse {
                lo: a,
                hi: b,
                corners: [ca, cb],
            }
        } else {
            EdgeUse {
                lo: b,
                hi: a,
                corners: [cb, ca],
            }
        }
    };
    let lo = |index: usize| edge_use(index).lo;
    let uses = 3 * faces.len();
    let buckets = faces.iter().flatten().max().map_or(0, |&v| v + 1);
    let mut start = vec![0; buckets + 1];
    for index in 0..uses {
        start[lo(index) + 1] += 1;
    }
    for v in 0..buckets {
        start[v + 1] += start[v];
    }
    let mut next = start.clone();
    let mut order = vec![0; uses];
    for index in 0..uses {
        let bucket = &mut next[lo(index)];
        order[*bucket] = index;
        *bucket += 1;
    }
    let mut sorted: Vec<EdgeUse> = order.into_iter().map(edge_use).collect();
    for v in 0..buckets {
        sorted[start[v]..start[v + 1]].sort_by_key(|u| u.hi);
    }
    sorted
}

pub(crate) fn same_edge(a: &EdgeUse, b: &EdgeUse) -> bool {
    (a.lo, a.hi) == (b.lo, b.hi)
}

impl EdgeUse {
    /// The face.
    pub(crate) fn face(&self) -> usize {
        self.corners[0] / 3
    }

    /// Whether the face traverses the edge `lo → hi` (its corner after `lo`'s is `hi`'s).
    pub(crate) fn forward(&self) -> bool {
        next_corner(self.corners[0]) == self.corners[1]
    }

    /// The edge in the direction this face traverses it.
    fn directed(&self) -> [usize; 2] {
        if self.forward() {
            [self.lo, self.hi]
        } else {
            [self.hi, self.lo]
        }
    }
}

/// The corner after `corner` (`3 face + local index`) in its face's order.
fn next_corner(corner: usize) -> usize {
    corner - corner % 3 + (corner + 1) % 3
}

/// `|(b − a) × (c − a)| / 2`.
pub(crate) fn triangle_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    norm(cross(sub(b, a), sub(c, a))) / 2.0
}

/// Non-empty, indices in range and distinct within each face.
fn check_indices(vertex_count: usize, faces: &[[usize; 3]]) -> Result<(), MeshError> {
    if vertex_count == 0 || faces.is_empty() {
        return Err(MeshError::Empty {
            vertices: vertex_count,
            faces: faces.len(),
        });
    }
    for (face, f) in faces.iter().enumerate() {
        if let Some(&vertex) = f.iter().find(|&&v| v >= vertex_count) {
            return Err(MeshError::IndexOutOfRange {
                face,
                vertex,
                vertex_count,
            });
        }
        if f[0] == f[1] || f[0] == f[2] {
            return Err(MeshError::RepeatedIndex { face, vertex: f[0] });
        }
        if f[1] == f[2] {
            return Err(MeshError::RepeatedIndex { face, vertex: f[1] });
        }
    }
    Ok(())
}

/// Which vertices some face uses.
fn referenced(vertex_count: usize, faces: &[[usize; 3]]) -> Vec<bool> {
    let mut used = vec![false; vertex_count];
    for &v in faces.iter().flatten() {
        used[v] = true;
    }
    used
}

/// Whether all three coordinates are finite (neither NaN nor infinite).
pub(crate) fn is_finite_point(p: [f64; 3]) -> bool {
    p.iter().all(|c| c.is_finite())
}

/// Finite coordinates on the vertices faces use, and faces of positive finite area.
fn check_geometry(positions: &[[f64; 3]], faces: &[[usize; 3]]) -> Result<(), MeshError> {
    if let Some(&vertex) = faces
        .iter()
        .flatten()
        .find(|&&v| !is_finite_point(positions[v]))
    {
        return Err(MeshError::NonFiniteCoordinate { vertex });
    }
    for (face, &vertices) in faces.iter().enumerate() {
        check_face_shape(positions, face, vertices)?;
    }
    Ok(())
}

/// The shape test of one face `face = [i, j, k]` (indices in range): [`MeshError::ZeroAreaFace`]
/// unless its area and the area's reciprocal are finite and positive, else
/// [`MeshError::DegenerateAngle`] unless the cotangents at its three corners are finite. Shared
/// with [`crate::repair`], which drops the faces this rejects.
pub(crate) fn check_face_shape(
    positions: &[[f64; 3]],
    face: usize,
    [i, j, k]: [usize; 3],
) -> Result<(), MeshError> {
    let area = triangle_area(positions[i], positions[j], positions[k]);
    // Operators divide by the area, so its reciprocal must be finite too.
    if !(area >= f64::MIN_POSITIVE && area.is_finite()) {
        return Err(MeshError::ZeroAreaFace { face });
    }
    for (apex, a, b) in [(i, j, k), (j, k, i), (k, i, j)] {
        if !corner_cotangent(positions[apex], positions[a], positions[b]).is_finite() {
            return Err(MeshError::DegenerateAngle { face, vertex: apex });
        }
    }
    Ok(())
}

/// The error for faces `a` and `b` that traverse their shared edge the same way: whether
/// reversing some faces would fix it (then [`crate::repair`] does) or nothing would (the faces
/// sharing edges pairwise form a non-orientable surface). Only a failing mesh pays for the
/// search.
fn orientation_error(faces: &[[usize; 3]], a: &EdgeUse, b: &EdgeUse) -> MeshError {
    let glued: Vec<[EdgeUse; 2]> = edge_uses(faces)
        .chunk_by(same_edge)
        .filter_map(|group| match *group {
            [a, b] => Some([a, b]),
            _ => None,
        })
        .collect();
    // The areas only choose which orientation a part keeps, which does not matter here.
    match orientation(faces.len(), &glued, &vec![0.0; faces.len()]) {
        Err(conflict) => MeshError::NonOrientable {
            face: conflict.face,
        },
        Ok(_) => MeshError::InconsistentOrientation {
            edge: a.directed(),
            faces: [a.face(), b.face()],
        },
    }
}

/// Edge-manifold, consistently oriented and vertex-manifold. Expects indices below
/// `vertex_count`.
fn check_manifold(vertex_count: usize, faces: &[[usize; 3]]) -> Result<(), MeshError> {
    // Corners around one vertex are joined when their faces share an edge at it; each
    // resulting class is one fan.
    let mut fans = DisjointSets::new(3 * faces.len());
    for group in edge_uses(faces).chunk_by(same_edge) {
        match *group {
            [_] => {}
            [a, b] if a.forward() == b.forward() => {
                return Err(orientation_error(faces, &a, &b));
            }
            [a, b] => {
                fans.union(a.corners[0], b.corners[0]);
                fans.union(a.corners[1], b.corners[1]);
            }
            _ => {
                return Err(MeshError::NonManifoldEdge {
                    edge: [group[0].lo, group[0].hi],
                    faces: group.iter().map(EdgeUse::face).collect(),
                });
            }
        }
    }
    // Each vertex must see one fan. One pass notes the first fan seen at each vertex; only a
    // failing mesh pays for counting the fans of the smallest vertex with several.
    let vertex_of = |corner: usize| faces[corner / 3][corner % 3];
    let mut fan_at = vec![None; vertex_count];
    let mut split: Option<usize> = None;
    for corner in 0..3 * faces.len() {
        let (vertex, fan) = (vertex_of(corner), fans.find(corner));
        match fan_at[vertex] {
            None => fan_at[vertex] = Some(fan),
            Some(seen) if seen != fan => split = Some(split.map_or(vertex, |s| s.min(vertex))),
            Some(_) => {}
        }
    }
    if let Some(vertex) = split {
        let mut seen: Vec<usize> = (0..3 * faces.len())
            .filter(|&corner| vertex_of(corner) == vertex)
            .map(|corner| fans.find(corner))
            .collect();
        seen.sort_unstable();
        seen.dedup();
        return Err(MeshError::NonManifoldVertex {
            vertex,
            fans: seen.len(),
        });
    }
    Ok(())
}

/// How two meshes differ in connectivity ([`TriMesh::check_same_connectivity`]): the first
/// difference found, in the order vertex count, face count, faces.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum ConnectivityMismatch {
    /// The vertex counts differ.
    #[error("the meshes have {this} and {other} vertices")]
    VertexCount {
        /// Vertices of this mesh.
        this: usize,
        /// Vertices of the other mesh.
        other: usize,
    },
    /// The face counts differ.
    #[error("the meshes have {this} and {other} faces")]
    FaceCount {
        /// Faces of this mesh.
        this: usize,
        /// Faces of the other mesh.
        other: usize,
    },
    /// A face has other vertices (or the same in another order).
    #[error("face {face} is {this:?} in one mesh and {other:?} in the other")]
    Face {
        /// The face.
        face: usize,
        /// Its vertices in this mesh.
        this: [usize; 3],
        /// Its vertices in the other mesh.
        other: [usize; 3],
    },
}

impl TriMesh {
    /// `Ok` when `other` has the same vertex count and the same faces, vertex for vertex in the
    /// same order (two immersions of one triangulation, as the relative Dirac operator
    /// `D_{f1,f2}` needs); otherwise the first difference.
    pub fn check_same_connectivity(&self, other: &TriMesh) -> Result<(), ConnectivityMismatch> {
        if self.vertex_count() != other.vertex_count() {
            return Err(ConnectivityMismatch::VertexCount {
                this: self.vertex_count(),
                other: other.vertex_count(),
            });
        }
        if self.face_count() != other.face_count() {
            return Err(ConnectivityMismatch::FaceCount {
                this: self.face_count(),
                other: other.face_count(),
            });
        }
        match (self.faces.iter().zip(&other.faces)).position(|(a, b)| a != b) {
            None => Ok(()),
            Some(face) => Err(ConnectivityMismatch::Face {
                face,
                this: self.faces[face],
                other: other.faces[face],
            }),
        }
    }

    /// Builds and validates a mesh (docs/ARCHITECTURE.md, "Errors"). Checked in this order, the
    /// first failure is returned: non-empty; every index in range and distinct within its face;
    /// every vertex used by a face; finite coordinates; every face of positive area with a finite
    /// reciprocal and finite cotangents at its three corners
    /// ([`corner_cotangent`]); at most two faces per edge;
    /// neighbouring faces traversing their shared edge in opposite directions; the faces around
    /// each vertex forming a single fan. Boundaries and several components are allowed.
    pub fn new(positions: Vec<[f64; 3]>, faces: Vec<[usize; 3]>) -> Result<Self, MeshError> {
        check_indices(positions.len(), &faces)?;
        if let Some(vertex) = referenced(positions.len(), &faces)
            .iter()
            .position(|&used| !used)
        {
            return Err(MeshError::UnreferencedVertex { vertex });
        }
        check_geometry(&positions, &faces)?;
        check_manifold(positions.len(), &faces)?;
        Ok(Self { positions, faces })
    }

    /// Like [`TriMesh::new`], but vertices no face uses are dropped instead of rejected (their
    /// coordinates are not checked). Returns the mesh and the renumbering: `old_to_new[i]` is
    /// the new index of input vertex `i`, or `None` if it was removed. Errors name input
    /// indices.
    pub fn with_unreferenced_removed(
        positions: Vec<[f64; 3]>,
        faces: Vec<[usize; 3]>,
    ) -> Result<(Self, Vec<Option<usize>>), MeshError> {
        check_indices(positions.len(), &faces)?;
        check_geometry(&positions, &faces)?;
        check_manifold(positions.len(), &faces)?;
        let used = referenced(positions.len(), &faces);
        let mut new_index = vec![0; positions.len()];
        let mut old_to_new = vec![None; positions.len()];
        let mut kept = Vec::new();
        for (old, p) in positions.into_iter().enumerate() {
            if used[old] {
                new_index[old] = kept.len();
                old_to_new[old] = Some(kept.len());
                kept.push(p);
            }
        }
        let faces = faces.iter().map(|f| f.map(|v| new_index[v])).collect();
        Ok((
            Self {
                positions: kept,
                faces,
            },
            old_to_new,
        ))
    }

    /// The faces `t` with `keep[t]` and the vertices they use, both in their order here;
    /// returns the mesh and, for each of its vertices, its index here. Valid without a new
    /// validation only when the kept faces are whole connected components (a vertex keeps all
    /// its faces or none, so every fan stays whole), which the callers guarantee.
    pub(crate) fn with_components_of(&self, keep: &[bool]) -> (Self, Vec<usize>) {
        let faces: Vec<[usize; 3]> = self
            .faces
            .iter()
            .zip(keep)
            .filter(|&(_, &k)| k)
            .map(|(f, _)| *f)
            .collect();
        let used = referenced(self.vertex_count(), &faces);
        let vertex_origin: Vec<usize> = (0..self.vertex_count()).filter(|&v| used[v]).collect();
        let mut new_index = vec![0; self.vertex_count()];
        for (new, &old) in vertex_origin.iter().enumerate() {
            new_index[old] = new;
        }
        let mesh = Self {
            positions: vertex_origin.iter().map(|&v| self.positions[v]).collect(),
            faces: faces.iter().map(|f| f.map(|v| new_index[v])).collect(),
        };
        (mesh, vertex_origin)
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

    /// The rounding of the stored coordinates when they are single-precision floats (every
    /// coordinate exactly a 32-bit float, as STL files and most binary PLY files store them,
    /// and some using more than 16 significant bits: a grid of exact small binary fractions,
    /// as generators make, is not rounded data): half a unit in the last place at the largest
    /// coordinate, `2⁻²⁴ max |x|`. `None` for coordinates of double precision, whose rounding
    /// the tolerances already allow for.
    pub fn single_precision_rounding(&self) -> Option<f64> {
        let single = |x: f64| f64::from(x as f32) == x;
        // Significant bits of a normal number: 53 less the trailing zeros of its significand.
        let significant_bits = |x: f64| {
            let significand = (x.to_bits() & ((1 << 52) - 1)) | (1 << 52);
            53 - significand.trailing_zeros()
        };
        let coordinates = self.positions.iter().flatten();
        let rounded = coordinates.clone().all(|&x| single(x))
            && coordinates
                .clone()
                .any(|&x| x != 0.0 && significant_bits(x) > 16);
        rounded.then(|| {
            let largest = coordinates.fold(0.0, |m: f64, x| m.max(x.abs()));
            largest * f64::from(f32::EPSILON) / 2.0
        })
    }

    /// Area of face `t`, `|(f_j − f_i) × (f_k − f_i)| / 2`.
    pub fn face_area(&self, t: usize) -> f64 {
        let [i, j, k] = self.faces[t];
        triangle_area(self.positions[i], self.positions[j], self.positions[k])
    }

    /// Every edge once, sorted by (smaller vertex, larger vertex).
    pub fn edges(&self) -> Vec<Edge> {
        edge_uses(&self.faces)
            .chunk_by(same_edge)
            .map(|group| Edge {
                vertices: group[0].directed(),
                face: group[0].face(),
                opposite_face: group.get(1).map(EdgeUse::face),
            })
            .collect()
    }

    /// The boundary edges, each directed as its only face traverses it (so the surface lies to
    /// the left, seen from the side the normals point to), in the order of [`TriMesh::edges`].
    pub fn boundary_edges(&self) -> Vec<[usize; 2]> {
        boundary_of(&self.edges())
    }

    /// The same surface with every face's orientation reversed (`[i, j, k] → [i, k, j]`).
    pub fn reverse_orientation(&self) -> Self {
        Self {
            positions: self.positions.clone(),
            faces: self.faces.iter().map(|&[i, j, k]| [i, k, j]).collect(),
        }
    }

    /// The same connectivity with every position mapped by `f`. Fails if a coordinate becomes
    /// non-finite or a face loses its area or gets a degenerate angle.
    pub fn map_positions(&self, f: impl FnMut([f64; 3]) -> [f64; 3]) -> Result<Self, MeshError> {
        let positions: Vec<[f64; 3]> = self.positions.iter().copied().map(f).collect();
        check_geometry(&positions, &self.faces)?;
        Ok(Self {
            positions,
            faces: self.faces.clone(),
        })
    }

    /// The mesh moved by `t`.
    pub fn translated(&self, t: [f64; 3]) -> Result<Self, MeshError> {
        self.map_positions(|p| [p[0] + t[0], p[1] + t[1], p[2] + t[2]])
    }

    /// The mesh scaled by `s` about the origin (a negative `s` also mirrors it, which turns the
    /// faces inside out).
    pub fn scaled(&self, s: f64) -> Result<Self, MeshError> {
        self.map_positions(|p| scale(p, s))
    }

    /// The mesh rotated about the origin by the unit quaternion `r`: `p ↦ r p r̄`
    /// ([`Quat::rotate_vector`]; a non-unit `r` also scales by `|r|²`).
    pub fn rotated(&self, r: Quat<f64>) -> Result<Self, MeshError> {
        self.map_positions(|p| r.rotate_vector(p))
    }
}

/// The boundary edges among `edges` (those with one face), directed as that face traverses
/// them, in the given order.
pub(crate) fn boundary_of(edges: &[Edge]) -> Vec<[usize; 2]> {
    (edges.iter())
        .filter(|e| e.opposite_face.is_none())
        .map(|e| e.vertices)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use qscalar::random::SplitMix64;

    /// The linear-time order of [`edge_uses`] is the `(lo, hi, face)` order a comparison sort
    /// gives, on faces with random vertices (shared edges, repeated faces, gaps in the
    /// numbering, vertices used by no face).
    #[test]
    fn edge_uses_are_sorted_by_edge_then_face() {
        let mut random = SplitMix64::new(11);
        for (faces, vertices) in [(0, 1), (1, 3), (50, 8), (400, 60), (2000, 5000)] {
            let list: Vec<[usize; 3]> = (0..faces)
                .map(|_| {
                    let mut vertex = || (random.next_u64() % vertices as u64) as usize;
                    [vertex(), vertex(), vertex()]
                })
                .collect();
            let keys = |uses: &[EdgeUse]| -> Vec<(usize, usize, usize, bool, [usize; 2])> {
                (uses.iter())
                    .map(|u| (u.lo, u.hi, u.face(), u.forward(), u.corners))
                    .collect()
            };
            // Every (face, corner) edge, in face order, sorted stably by a comparison sort.
            let mut expected: Vec<_> = (list.iter().enumerate())
                .flat_map(|(face, f)| {
                    (0..3).map(move |c| {
                        let (a, b) = (f[c], f[(c + 1) % 3]);
                        let (ca, cb) = (3 * face + c, 3 * face + (c + 1) % 3);
                        let corners = if a < b { [ca, cb] } else { [cb, ca] };
                        (a.min(b), a.max(b), face, a < b, corners)
                    })
                })
                .collect();
            expected.sort_by_key(|&(lo, hi, face, ..)| (lo, hi, face));
            assert_eq!(keys(&edge_uses(&list)), expected, "{faces} faces");
        }
    }
}
