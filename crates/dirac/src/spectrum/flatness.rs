//! Which faces are flat: the test behind the exact kernel's flat vertices (docs/MATH.md, "The
//! exact kernel"). A face is flat when the vertex normals at its corners agree within the flat
//! tolerance relative to its edges ([`face_flatness`]); for positions stored in single
//! precision, within what their rounding explains ([`NormalNoise`],
//! [`FlatTest::noisy_plane`]).

use qsparse::DisjointSets;

use crate::TriMesh;
use crate::geometry::{add, cross, dot, norm, normalize, scale, sub};
use crate::mesh::{EdgeUse, edge_uses, same_edge};

/// What the flat test forgives of the difference of two vertex normals along an edge.
#[derive(Clone, Copy)]
enum Discount<'a> {
    /// Nothing: the flatness as measured.
    None,
    /// The noise `ν_a + ν_b` of single-precision positions ([`NormalNoise`]), at most
    /// `cap · |f_a − f_b| / L` (`cap` infinite: all of it).
    Noise { noise: &'a NormalNoise, cap: f64 },
}

/// The flatness `max (|N_a − N_b| − d_ab)⁺ · L / |f_a − f_b|` over the edges of a face,
/// `L = √area`: a dimensionless bound on its discrete curvature, which the flat tolerance
/// bounds. `d_ab` is what `discount` forgives of the normals' difference.
fn face_flatness(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    discount: Discount,
    length: f64,
    [i, j, k]: [usize; 3],
) -> f64 {
    let p = mesh.positions();
    let edge = |a: usize, b: usize| {
        let span = norm(sub(p[a], p[b]));
        let forgiven = match discount {
            Discount::None => 0.0,
            Discount::Noise { noise, cap } => (noise.at(a) + noise.at(b)).min(cap * span / length),
        };
        let difference = norm(sub(normals[a], normals[b])) - forgiven;
        length * difference.max(0.0) / span
    };
    edge(i, j).max(edge(j, k)).max(edge(k, i))
}

/// The most that the noise of single-precision positions may stretch the flat tolerance face
/// by face, as a multiple of it. The noise is a bound (the normals of four meshes rounded to 32
/// bits moved by 1–15 % of it in the median), and locally a gently curved face cannot be told
/// from a noisy flat one: beyond this, faces are flat only as part of a [`noisy plane`], whose
/// positions contradict the curvature its normals suggest. The flat faces of pyvista's
/// `nut.ply` measure up to 3.9 times the tolerance.
///
/// [`noisy plane`]: FlatTest::denoise_gauss_map
const NOISE_STRETCH: f64 = 4.0;

/// How far the rounding of the stored positions can move each vertex normal, for a mesh stored
/// in single precision ([`TriMesh::single_precision_rounding`]; nothing otherwise).
///
/// A face's normal moves by about `δ / h` when its corners move by `δ` (`h` its smallest
/// height), and an area-weighted vertex normal by no more than the normals of its faces:
/// `ν_a = δ / min h` over the faces around `a` (rounded to 32 bits, the fandisk, the camel
/// head and a PSB model, also moved by 100 times their size, moved their normals by 0.6–7 %
/// of it in the median and at most 41 %). On a model away from the origin this is far
/// above the flat tolerance's `T |f_a − f_b| / L`: pyvista's `nut.ply` (coordinates near 100,
/// edges near 4) has faces flat to `10⁻⁶` in their normals that measured `1–4 · 10⁻⁵` against
/// the default `10⁻⁵`, and each left a vertex that `P` annihilates to `10⁻¹⁴` in the problem.
struct NormalNoise {
    /// `δ`, the rounding of the largest coordinate.
    rounding: f64,
    /// `ν_a` by vertex.
    at_vertex: Vec<f64>,
}

impl NormalNoise {
    /// The noise of `mesh`'s normals, if its positions are stored in single precision.
    fn of(mesh: &TriMesh) -> Option<Self> {
        let rounding = mesh.single_precision_rounding()?;
        let p = mesh.positions();
        let mut smallest_height = vec![f64::INFINITY; mesh.vertex_count()];
        for (t, &[i, j, k]) in mesh.faces().iter().enumerate() {
            let longest = norm(sub(p[i], p[j]))
                .max(norm(sub(p[j], p[k])))
                .max(norm(sub(p[k], p[i])));
            let height = 2.0 * mesh.face_area(t) / longest;
            for v in [i, j, k] {
                smallest_height[v] = smallest_height[v].min(height);
            }
        }
        Some(Self {
            rounding,
            at_vertex: smallest_height.into_iter().map(|h| rounding / h).collect(),
        })
    }

    /// `ν_a`.
    fn at(&self, vertex: usize) -> f64 {
        self.at_vertex[vertex]
    }
}

/// The faces around each vertex.
pub(super) struct FacesAround {
    /// The faces around vertex `v` are `faces[start[v]..start[v + 1]]`.
    start: Vec<usize>,
    faces: Vec<usize>,
}

impl FacesAround {
    pub fn of(mesh: &TriMesh) -> Self {
        let mut start = vec![0; mesh.vertex_count() + 1];
        for &v in mesh.faces().iter().flatten() {
            start[v + 1] += 1;
        }
        for v in 0..mesh.vertex_count() {
            start[v + 1] += start[v];
        }
        let mut next = start.clone();
        let mut faces = vec![0; 3 * mesh.face_count()];
        for (t, face) in mesh.faces().iter().enumerate() {
            for &v in face {
                faces[next[v]] = t;
                next[v] += 1;
            }
        }
        Self { start, faces }
    }

    pub fn at(&self, vertex: usize) -> &[usize] {
        &self.faces[self.start[vertex]..self.start[vertex + 1]]
    }
}

/// `√(total area)`.
pub(super) fn length_scale(mesh: &TriMesh) -> f64 {
    (0..mesh.face_count())
        .map(|t| mesh.face_area(t))
        .sum::<f64>()
        .sqrt()
}

/// The flat test on one mesh with one tolerance: its length scale `L` and, for positions
/// stored in single precision, the noise of its normals, found once for both the Gauss map's
/// noisy planes and its flat faces.
pub(super) struct FlatTest<'a> {
    mesh: &'a TriMesh,
    tolerance: f64,
    length: f64,
    noise: Option<NormalNoise>,
}

impl<'a> FlatTest<'a> {
    pub(super) fn new(mesh: &'a TriMesh, tolerance: f64) -> Self {
        Self {
            mesh,
            tolerance,
            length: length_scale(mesh),
            noise: NormalNoise::of(mesh),
        }
    }

    /// [`face_flatness`] of `face` on this mesh.
    fn flatness(&self, normals: &[[f64; 3]], discount: Discount, face: [usize; 3]) -> f64 {
        face_flatness(self.mesh, normals, discount, self.length, face)
    }

    /// Faces whose Gauss map is flat within the tolerance (their [`face_flatness`] is at most
    /// it: along every edge `|N_a − N_b| ≤ tolerance · |f_a − f_b| / L` beyond the noise of
    /// positions stored in single precision, so a sliver face is flat only if its normals
    /// agree to the scale of its short edge) and, with a potential, whose corners all have
    /// `U = 0`. The row of `D_N` of such a face, `−(N_r − N_q)/(2A_t)`, is negligible against
    /// that of `D_f` divided by `L`.
    pub(super) fn flat_faces(&self, normals: &[[f64; 3]], potential: Option<&[f64]>) -> Vec<bool> {
        let discount = (self.noise.as_ref()).map_or(Discount::None, |noise| Discount::Noise {
            noise,
            cap: NOISE_STRETCH * self.tolerance,
        });
        (self.mesh.faces().iter())
            .map(|&face| {
                self.flatness(normals, discount, face) <= self.tolerance
                    && potential.is_none_or(|u| face.iter().all(|&p| u[p] == 0.0))
            })
            .collect()
    }

    /// For a mesh stored in single precision, sets the vertex normals of every *noisy plane*
    /// to the plane's normal: a region of faces (connected through edges) that are flat within
    /// the tolerance once all the noise of the rounding is discounted ([`NormalNoise`]), and
    /// whose positions [`FlatTest::noisy_plane`] shows to be a plane that only the rounding
    /// bends. Its faces are then flat as they are in the exact data, their rows of `D_N`
    /// vanish, and the exact kernel sees the pieces and flat vertices it has there (on a
    /// rotated cube with a drilled hole, subdivided and rounded to 32 bits, the constant of a
    /// second piece was lost without it, and the squared operator listed `1.1 · 10⁻⁸` in its
    /// place). Nothing changes for positions of double precision.
    pub(super) fn denoise_gauss_map(&self, normals: &mut [[f64; 3]]) {
        let Some(noise) = &self.noise else {
            return;
        };
        let whole = Discount::Noise {
            noise,
            cap: f64::INFINITY,
        };
        let faces = self.mesh.faces();
        let candidate: Vec<bool> = (faces.iter())
            .map(|&face| self.flatness(normals, whole, face) <= self.tolerance)
            .collect();
        let mut regions = DisjointSets::new(faces.len());
        for uses in edge_uses(faces).chunk_by(same_edge) {
            let mut sharing = uses.iter().map(EdgeUse::face).filter(|&t| candidate[t]);
            if let Some(first) = sharing.next() {
                sharing.for_each(|t| regions.union(first, t));
            }
        }
        // Regions in the order of their first faces, so that a vertex two planes share takes
        // the same normal in every run.
        let mut index_of_root = vec![usize::MAX; faces.len()];
        let mut by_region: Vec<Vec<usize>> = Vec::new();
        for t in (0..faces.len()).filter(|&t| candidate[t]) {
            let index = &mut index_of_root[regions.find(t)];
            if *index == usize::MAX {
                *index = by_region.len();
                by_region.push(Vec::new());
            }
            by_region[*index].push(t);
        }
        let around = FacesAround::of(self.mesh);
        // All regions are judged on the normals as computed, then their normals are set.
        let planes: Vec<([f64; 3], Vec<usize>)> = (by_region.iter())
            .filter_map(|region| {
                let normal = self.noisy_plane(normals, &around, region, noise.rounding)?;
                Some((normal, region.iter().flat_map(|&t| faces[t]).collect()))
            })
            .collect();
        for (normal, vertices) in planes {
            vertices.into_iter().for_each(|v| normals[v] = normal);
        }
    }

    /// The normal of `region`'s plane if the positions around it contradict the curvature its
    /// normals suggest: every vertex of every face around the region's vertices (whose normals
    /// the flat test compared) lies within `d ≤` [`PLANE_SLACK`]` δ` of the plane through the
    /// region's area-weighted centroid, normal to its area-weighted normal, while a curvature `κ`
    /// as large as the region's largest flatness suggests (`κ = flatness / L`), kept over its
    /// extent `E` (twice the largest distance from the centroid within the plane), would move
    /// them by `κ E² / 8`, at least [`CURVATURE_EVIDENCE`]` · max(d, δ)`. A curved region moves
    /// from its plane by about half of `κ E² / 8`: its positions bend with its normals. On the
    /// fandisk rounded to 32 bits and moved by 100, the regions left out lie 6–17 `δ` from their
    /// planes, where their normals suggest 4–13 `δ`; the flat panels around a hole drilled into a
    /// cube (subdivided, rotated, rounded) lie within `0.8 δ` of theirs, where their normals
    /// suggest 55–860 `δ`.
    fn noisy_plane(
        &self,
        normals: &[[f64; 3]],
        around: &FacesAround,
        region: &[usize],
        rounding: f64,
    ) -> Option<[f64; 3]> {
        let (p, faces) = (self.mesh.positions(), self.mesh.faces());
        let mut area_normal = [0.0; 3];
        let mut weighted_centroid = [0.0; 3];
        let mut area = 0.0;
        let mut flatness: f64 = 0.0;
        for &t in region {
            let [i, j, k] = faces[t];
            let doubled = cross(sub(p[j], p[i]), sub(p[k], p[i]));
            let face_area = norm(doubled) / 2.0;
            area_normal = add(area_normal, doubled);
            let centroid = scale(add(add(p[i], p[j]), p[k]), 1.0 / 3.0);
            weighted_centroid = add(weighted_centroid, scale(centroid, face_area));
            area += face_area;
            flatness = flatness.max(self.flatness(normals, Discount::None, faces[t]));
        }
        if norm(area_normal) <= f64::MIN_POSITIVE || area <= f64::MIN_POSITIVE {
            return None;
        }
        let normal = normalize(area_normal);
        let centroid = scale(weighted_centroid, 1.0 / area);
        let mut deviation: f64 = 0.0;
        let mut reach: f64 = 0.0;
        // Each face around the region once per corner it shares with it: a maximum does not mind.
        let star = (region.iter())
            .flat_map(|&t| faces[t])
            .flat_map(|v| around.at(v));
        for v in star.flat_map(|&t| faces[t]) {
            let offset = sub(p[v], centroid);
            let height = dot(offset, normal);
            deviation = deviation.max(height.abs());
            reach = reach.max(norm(sub(offset, scale(normal, height))));
        }
        let extent = 2.0 * reach;
        let suggested = flatness / self.length * extent * extent / 8.0;
        (deviation <= PLANE_SLACK * rounding
            && suggested >= CURVATURE_EVIDENCE * deviation.max(rounding))
        .then_some(normal)
    }
}

/// How far from its fitted plane, in units of the rounding `δ`, a plane stored in single
/// precision may put a vertex: each coordinate is off by at most `δ`, a point by `√3 δ`, and
/// the fitted plane is off by a little more.
const PLANE_SLACK: f64 = 4.0;

/// How many times more than its positions a noisy plane's normals must bend: by at least this
/// much more than its vertices' distance from the plane (and than `δ`).
const CURVATURE_EVIDENCE: f64 = 4.0;

/// The faces around flat vertices (vertices all of whose faces are `flat`): the rows of `D_N`
/// that must vanish exactly for `δ_p` and the constants of the remaining pieces to be exact
/// kernel vectors. Flat faces elsewhere keep their (tiny) rows: zeroing them would perturb the
/// operator for nothing.
pub(super) fn vanishing_faces(mesh: &TriMesh, flat: &[bool]) -> Vec<bool> {
    let mut all_flat = vec![true; mesh.vertex_count()];
    for (face, _) in mesh.faces().iter().zip(flat).filter(|(_, f)| !**f) {
        face.iter().for_each(|&p| all_flat[p] = false);
    }
    mesh.faces()
        .iter()
        .map(|face| face.iter().any(|&p| all_flat[p]))
        .collect()
}

/// [`face_flatness`] up to which a face where the operator nearly vanishes may sensibly be
/// treated as flat: a discrete curvature of 1 % of `1/√area`. A flat tolerance above more
/// curved faces would call the mesh flat where it is not.
pub(super) const NEARLY_FLAT: f64 = 1e-2;

/// The flatness that explains a near-singularity at `vertex`: the largest [`face_flatness`] of
/// the nearly flat faces around it (at most [`NEARLY_FLAT`]; a flat tolerance above it makes
/// them flat), or, when every face around it is more curved, the smallest.
///
/// The factorisation fails at the last vertex of the nearly null region it eliminates, often
/// at its edge: next to a curved bump the largest flatness around it is the bump's, and a
/// tolerance above that would flatten the bump too.
pub(super) fn flatness_around(mesh: &TriMesh, normals: &[[f64; 3]], vertex: usize) -> f64 {
    let length = length_scale(mesh);
    let around: Vec<f64> = (mesh.faces().iter())
        .filter(|face| face.contains(&vertex))
        .map(|&face| face_flatness(mesh, normals, Discount::None, length, face))
        .collect();
    let nearly_flat = around.iter().copied().filter(|&s| s <= NEARLY_FLAT);
    match nearly_flat.reduce(f64::max) {
        Some(largest) => largest,
        None => around.into_iter().fold(f64::INFINITY, f64::min),
    }
}
