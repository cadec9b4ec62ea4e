//! Repair of meshes as downloaded: triangle soups, duplicated vertices, degenerate and
//! duplicate faces, non-manifold edges and vertices, inconsistent orientation.
//!
//! [`TriMesh::new`] rejects such meshes; [`repair`] turns a [`RawMesh`] into a valid
//! [`TriMesh`] and reports every change ([`RepairReport`]), with maps from the output back
//! to the input ([`Repaired::vertex_origin`], [`Repaired::face_origin`]) to carry per-vertex
//! data and per-face labels. The steps, in order (docs/USER_GUIDE.md, "Repair"):
//!
//! 1. drop faces naming a vertex out of range or with a non-finite coordinate;
//! 2. merge vertices within [`RepairOptions::merge_distance`] (relative to the bounding box);
//! 3. drop faces that repeat a vertex, then faces with the same vertices as an earlier face;
//! 4. drop zero-area faces and faces with a degenerate angle (the tests of [`TriMesh::new`]),
//!    and slivers that merging could flatten: faces whose smallest height, `2 · area / longest
//!    edge`, is at most the merge tolerance (a vertex within the tolerance of the opposite
//!    edge: its cotangent weights would be ~`1/height`, and its area no more than rounding);
//! 5. glue faces into manifold sheets: an edge of two faces joins them, an edge of more faces
//!    joins only pairs that shared it before merging;
//! 6. orient each connected sheet consistently (the larger area decides); a non-orientable
//!    one is [`RepairError::NonOrientable`];
//! 7. make one vertex per fan of corners (this splits non-manifold edges and vertices, and
//!    undoes merges that would join separate sheets), dropping unreferenced vertices;
//! 8. validate with [`TriMesh::new`].
//!
//! Repair is idempotent: repairing a repaired mesh changes nothing and reports nothing. A
//! valid mesh without coincident vertices or slivers passes through unchanged (same positions
//! and faces).

mod merge;
mod report;
mod sheets;

pub(crate) use sheets::orientation;

use thiserror::Error;

use crate::io::RawMesh;
use crate::mesh::{check_face_shape, is_finite_point, triangle_area};
use crate::{MeshError, TriMesh};

pub use report::{Change, MAX_EXAMPLES, RepairReport};

/// The default [`RepairOptions::merge_distance`].
pub const DEFAULT_MERGE_DISTANCE: f64 = 1e-9;

/// How [`repair`] works. Plain data: start from [`RepairOptions::default`] and set fields.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct RepairOptions {
    /// Vertices closer than `merge_distance · d` (Euclidean distance `≤`), `d` the diagonal of
    /// the bounding box of the vertices faces use, are merged; `0` merges only exactly
    /// coincident vertices. Finite and `≥ 0`.
    ///
    /// The default, [`DEFAULT_MERGE_DISTANCE`] `= 1e-9`, is seven orders of magnitude above
    /// double-precision rounding (so copies of a vertex computed along different arithmetic
    /// paths merge) and far below any edge a mesh file holds (an edge of `10⁻⁹ d` would need
    /// `10¹⁸` faces to tile the surface). Coordinates that went through single precision
    /// (`float` PLY properties) differ by up to `6·10⁻⁸` relative; raise it to about `1e-6`
    /// for soups written that way by different code paths.
    pub merge_distance: f64,
}

impl Default for RepairOptions {
    fn default() -> Self {
        Self {
            merge_distance: DEFAULT_MERGE_DISTANCE,
        }
    }
}

/// A repaired mesh with what was done and where each element came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Repaired {
    /// The valid mesh.
    pub mesh: TriMesh,
    /// What was changed, in the input's numbering.
    pub report: RepairReport,
    /// For each output vertex, the input vertex it came from: the smallest of the input
    /// vertices merged into it. Its position is that of the smallest vertex of its merge
    /// cluster, so it may differ from the origin's by up to the merge tolerance.
    pub vertex_origin: Vec<usize>,
    /// For each output face, the input face it came from (faces keep their relative order).
    pub face_origin: Vec<usize>,
}

/// Why [`repair`] failed. Indices are those of the input.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RepairError {
    /// [`RepairOptions::merge_distance`] is negative, NaN or infinite.
    #[error(
        "merge distance {0} is not a finite number ≥ 0 (use e.g. 1e-9, relative to the bounding-box diagonal)"
    )]
    InvalidMergeDistance(f64),
    /// Every face was removed (or there were none).
    #[error(
        "no face is left of the {faces} input faces: each names a missing vertex or a \
         non-finite coordinate, repeats a vertex, duplicates another or is degenerate (if \
         merging collapsed them, try a smaller merge distance)"
    )]
    NoFacesLeft {
        /// Number of input faces.
        faces: usize,
    },
    /// A connected sheet is not orientable (a Möbius strip or similar), so no orientation of
    /// its faces is consistent.
    #[error(
        "component {component} is not orientable: face {face} cannot be oriented consistently \
         with its neighbours (a Möbius-like surface); cut it along an edge of face {face} or \
         remove the component"
    )]
    NonOrientable {
        /// The component (sheets connected through shared edges after repair), numbered by
        /// smallest face.
        component: usize,
        /// An input face whose orientation conflicts with its neighbours'.
        face: usize,
    },
    /// The repaired mesh is still invalid, with the elements named in the input's numbering:
    /// a non-manifold edge whose sheets stay joined through their vertices, or two faces that
    /// share their vertices without being glued.
    #[error(
        "the repaired mesh is still invalid ({0}; indices of the input): remove the faces named"
    )]
    Invalid(MeshError),
}

/// Whether the triangle `p` is a sliver of height at most `tolerance` (step 4): `2 · area /
/// longest edge ≤ tolerance`, written without a division. Only for `tolerance > 0`.
fn collapses(p: [[f64; 3]; 3], tolerance: f64) -> bool {
    let edge = |a: usize, b: usize| merge::distance(p[a], p[b]);
    let longest = edge(0, 1).max(edge(1, 2)).max(edge(2, 0));
    tolerance > 0.0 && 2.0 * triangle_area(p[0], p[1], p[2]) <= tolerance * longest
}

/// The faces of `mesh` that [`repair`] with the default options drops as slivers (step 4:
/// height at most [`DEFAULT_MERGE_DISTANCE`] times the bounding box's diagonal), in order. A
/// valid mesh may hold them (their area is not zero, as where CAD exporters fan a cap over
/// collinear corners), but their cotangent weights, up to the inverse of that ratio, dominate
/// every operator built on the mesh: its spectrum then says more about them than about the
/// shape, and where an operator is numerically singular they are the likely cause.
pub fn slivers(mesh: &TriMesh) -> Vec<usize> {
    let used = vec![true; mesh.vertex_count()];
    let tolerance = merge::tolerance(mesh.positions(), &used, DEFAULT_MERGE_DISTANCE);
    (mesh.faces().iter().enumerate())
        .filter(|(_, face)| collapses(face.map(|v| mesh.positions()[v]), tolerance))
        .map(|(t, _)| t)
        .collect()
}

/// The warning a mesh with `count` [`slivers`] deserves, the first of them `first`.
pub fn sliver_warning(count: usize, first: usize) -> String {
    format!(
        "{count} sliver face{} (face {first}{}): height at most 1e-9 of the mesh's size, with \
         cotangent weights a billion or more times the others'; they dominate every operator and \
         can spoil its spectrum: remove them with --repair",
        if count == 1 { "" } else { "s" },
        if count == 1 { "" } else { " first" },
    )
}

/// The first of the [`slivers`] around `vertex`, if any.
pub(crate) fn sliver_around(mesh: &TriMesh, vertex: usize) -> Option<usize> {
    (slivers(mesh).into_iter()).find(|&t| mesh.faces()[t].contains(&vertex))
}

/// Repairs `raw` into a valid [`TriMesh`] (see the [module documentation](self) for the
/// steps). Never panics; each step is reported in [`Repaired::report`].
pub fn repair(raw: RawMesh, options: &RepairOptions) -> Result<Repaired, RepairError> {
    let merge_distance = options.merge_distance;
    if !(merge_distance.is_finite() && merge_distance >= 0.0) {
        return Err(RepairError::InvalidMergeDistance(merge_distance));
    }
    let RawMesh { positions, faces } = raw;
    let n = positions.len();
    let mut report = RepairReport::default();

    // 1. Faces must name existing vertices with finite coordinates.
    let (mut out_of_range, mut non_finite, mut kept) = (Vec::new(), Vec::new(), Vec::new());
    for (t, face) in faces.iter().enumerate() {
        if face.iter().any(|&v| v >= n) {
            out_of_range.push(t);
        } else if face.iter().any(|&v| !is_finite_point(positions[v])) {
            non_finite.push(t);
        } else {
            kept.push(t);
        }
    }
    report.removed_faces_out_of_range = Change::of(out_of_range);
    report.removed_faces_non_finite = Change::of(non_finite);

    // 2. Merge: only vertices some face uses take part (and span the bounding box).
    let mut used = vec![false; n];
    for &t in &kept {
        for &v in &faces[t] {
            used[v] = true;
        }
    }
    let point = merge::clusters(&positions, &used, merge_distance);

    // 3. and 4. Faces that merging or their shape make invalid.
    let (mut repeated, mut shape_faces, mut shaped) = (Vec::new(), Vec::new(), Vec::new());
    let mut first_with = std::collections::HashMap::new();
    let mut duplicates = Vec::new();
    for &t in &kept {
        let f = faces[t].map(|v| point[v]);
        if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
            repeated.push(t);
            continue;
        }
        let mut key = f;
        key.sort_unstable();
        if let Some(&first) = first_with.get(&key) {
            duplicates.push([t, first]);
            continue;
        }
        first_with.insert(key, t);
        shaped.push((t, f));
    }
    let (mut zero_area, mut degenerate) = (Vec::new(), Vec::new());
    let collapse = merge::tolerance(&positions, &used, merge_distance);
    for (t, f) in shaped {
        if collapses(f.map(|v| positions[v]), collapse) {
            zero_area.push(t);
            continue;
        }
        match check_face_shape(&positions, t, f) {
            Ok(()) => shape_faces.push((t, f)),
            Err(MeshError::DegenerateAngle { .. }) => degenerate.push(t),
            Err(_) => zero_area.push(t),
        }
    }
    report.removed_faces_repeated_vertex = Change::of(repeated);
    report.removed_duplicate_faces = Change::of(duplicates);
    report.removed_faces_zero_area = Change::of(zero_area);
    report.removed_faces_degenerate_angle = Change::of(degenerate);
    if shape_faces.is_empty() {
        return Err(RepairError::NoFacesLeft { faces: faces.len() });
    }

    // 5. and 6. Sheets and their orientation, on the kept faces numbered 0, 1, ….
    let face_origin: Vec<usize> = shape_faces.iter().map(|&(t, _)| t).collect();
    let merged: Vec<[usize; 3]> = shape_faces.iter().map(|&(_, f)| f).collect();
    let input: Vec<[usize; 3]> = face_origin.iter().map(|&t| faces[t]).collect();
    let glued = sheets::glued_edges(&merged, &input);
    let area: Vec<f64> = merged
        .iter()
        .map(|&[i, j, k]| triangle_area(positions[i], positions[j], positions[k]))
        .collect();
    let flip = sheets::orientation(merged.len(), &glued, &area).map_err(|e| {
        RepairError::NonOrientable {
            component: e.component,
            face: face_origin[e.face],
        }
    })?;

    // 7. One vertex per fan, numbered by (origin, first corner): a clean mesh keeps its order.
    let fan = sheets::fans(merged.len(), &glued);
    let corner_input = |c: usize| input[c / 3][c % 3];
    let fan_count = fan.iter().map(|&f| f + 1).max().unwrap_or(0);
    let mut fan_origin = vec![usize::MAX; fan_count];
    for (c, &f) in fan.iter().enumerate() {
        fan_origin[f] = fan_origin[f].min(corner_input(c));
    }
    // Fans are numbered by first corner, so sorting by origin (stable) breaks ties by it.
    let mut order: Vec<usize> = (0..fan_count).collect();
    order.sort_by_key(|&f| fan_origin[f]);
    let mut new_index = vec![0; fan_count];
    for (new, &f) in order.iter().enumerate() {
        new_index[f] = new;
    }
    let vertex_origin: Vec<usize> = order.iter().map(|&f| fan_origin[f]).collect();
    let out_positions: Vec<[f64; 3]> = vertex_origin.iter().map(|&v| positions[point[v]]).collect();
    let out_faces: Vec<[usize; 3]> = (0..merged.len())
        .map(|t| {
            let [i, j, k] = [0, 1, 2].map(|c| new_index[fan[3 * t + c]]);
            if flip[t] { [i, k, j] } else { [i, j, k] }
        })
        .collect();

    report_net_changes(
        &mut report,
        &fan,
        &new_index,
        &corner_input,
        &vertex_origin,
        n,
    );
    report.flipped_faces = Change::of(
        (0..merged.len())
            .filter(|&t| flip[t])
            .map(|t| face_origin[t])
            .collect(),
    );

    // 8. Validate.
    let mesh = TriMesh::new(out_positions, out_faces)
        .map_err(|e| RepairError::Invalid(in_input_numbering(e, &vertex_origin, &face_origin)))?;
    Ok(Repaired {
        mesh,
        report,
        vertex_origin,
        face_origin,
    })
}

/// Fills the merged, split and unreferenced entries of `report` from the final corner → vertex
/// map (`new_index[fan[c]]`): net effects, so a merge undone by a split shows as neither.
fn report_net_changes(
    report: &mut RepairReport,
    fan: &[usize],
    new_index: &[usize],
    corner_input: &impl Fn(usize) -> usize,
    vertex_origin: &[usize],
    vertex_count: usize,
) {
    let out = |c: usize| new_index[fan[c]];
    // (output vertex, input vertex) of every corner, each once.
    let mut links: Vec<(usize, usize)> =
        (0..fan.len()).map(|c| (out(c), corner_input(c))).collect();
    links.sort_unstable();
    links.dedup();
    report.merged_vertices = Change::of(
        links
            .iter()
            .filter(|&&(o, v)| v != vertex_origin[o])
            .map(|&(o, v)| [v, vertex_origin[o]])
            .collect(),
    );
    let mut copies = vec![0usize; vertex_count];
    for &(_, v) in &links {
        copies[v] += 1;
    }
    report.split_vertices = Change::of(
        (0..vertex_count)
            .filter(|&v| copies[v] > 1)
            .map(|v| [v, copies[v]])
            .collect(),
    );
    report.removed_unreferenced =
        Change::of((0..vertex_count).filter(|&v| copies[v] == 0).collect());

    // (input edge, output edge) of every face side, each once: an input edge on several
    // output edges was split.
    let mut sides: Vec<([usize; 2], [usize; 2])> = (0..fan.len())
        .map(|c| {
            let d = c - c % 3 + (c + 1) % 3;
            let (a, b) = (corner_input(c), corner_input(d));
            let (x, y) = (out(c), out(d));
            ([a.min(b), a.max(b)], [x.min(y), x.max(y)])
        })
        .collect();
    sides.sort_unstable();
    sides.dedup();
    report.split_edges = Change::of(
        sides
            .chunk_by(|a, b| a.0 == b.0)
            .filter(|group| group.len() > 1)
            .map(|group| group[0].0)
            .collect(),
    );
}

/// `error` of the repaired mesh with its vertices and faces renamed to the input's.
fn in_input_numbering(
    error: MeshError,
    vertex_origin: &[usize],
    face_origin: &[usize],
) -> MeshError {
    let v = |i: usize| vertex_origin.get(i).copied().unwrap_or(i);
    let f = |i: usize| face_origin.get(i).copied().unwrap_or(i);
    match error {
        MeshError::IndexOutOfRange {
            face,
            vertex,
            vertex_count,
        } => MeshError::IndexOutOfRange {
            face: f(face),
            vertex,
            vertex_count,
        },
        MeshError::RepeatedIndex { face, vertex } => MeshError::RepeatedIndex {
            face: f(face),
            vertex: v(vertex),
        },
        MeshError::UnreferencedVertex { vertex } => {
            MeshError::UnreferencedVertex { vertex: v(vertex) }
        }
        MeshError::NonFiniteCoordinate { vertex } => {
            MeshError::NonFiniteCoordinate { vertex: v(vertex) }
        }
        MeshError::ZeroAreaFace { face } => MeshError::ZeroAreaFace { face: f(face) },
        MeshError::DegenerateAngle { face, vertex } => MeshError::DegenerateAngle {
            face: f(face),
            vertex: v(vertex),
        },
        MeshError::NonManifoldEdge { edge, faces } => MeshError::NonManifoldEdge {
            edge: {
                let [a, b] = edge.map(v);
                [a.min(b), a.max(b)]
            },
            faces: faces.into_iter().map(f).collect(),
        },
        MeshError::InconsistentOrientation { edge, faces } => MeshError::InconsistentOrientation {
            edge: edge.map(v),
            faces: faces.map(f),
        },
        MeshError::NonOrientable { face } => MeshError::NonOrientable { face: f(face) },
        MeshError::NonManifoldVertex { vertex, fans } => MeshError::NonManifoldVertex {
            vertex: v(vertex),
            fans,
        },
        other => other,
    }
}
