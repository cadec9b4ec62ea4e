//! What [`repair`](super::repair) changed, step by step, in the input's numbering.

use std::fmt;

/// How many examples a [`Change`] keeps.
pub const MAX_EXAMPLES: usize = 5;

/// One kind of change: how many elements it affected and the first [`MAX_EXAMPLES`] of them
/// (smallest first, in the input's numbering).
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Change<T> {
    /// Number of elements affected.
    pub count: usize,
    /// The first few of them, in increasing order.
    pub examples: Vec<T>,
}

impl<T> Default for Change<T> {
    fn default() -> Self {
        Self {
            count: 0,
            examples: Vec::new(),
        }
    }
}

impl<T: Ord> Change<T> {
    /// The change affecting `items` (in any order; each listed once).
    pub fn of(mut items: Vec<T>) -> Self {
        items.sort_unstable();
        let count = items.len();
        items.truncate(MAX_EXAMPLES);
        Self {
            count,
            examples: items,
        }
    }
}

impl<T> Change<T> {
    /// Whether nothing was affected.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }
}

/// What [`repair`](super::repair) did, one field per step in the order the steps run. Vertex
/// and face indices are those of the input. The counts describe the net effect: two
/// coincident vertices that end up in separate sheets (merged, then split again) are neither
/// merged nor split.
///
/// With the `serde` feature of `dirac`, the report serialises (e.g. to JSON) as an object with
/// one `{"count": …, "examples": […]}` per field, pairs as two-element arrays.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[non_exhaustive]
pub struct RepairReport {
    /// Faces removed because they name a vertex index `≥` the number of vertices.
    pub removed_faces_out_of_range: Change<usize>,
    /// Faces removed because one of their vertices has a NaN or infinite coordinate.
    pub removed_faces_non_finite: Change<usize>,
    /// Vertices merged into another one: `[vertex, into]`, `into` the smallest vertex whose
    /// corners became the same output vertex (its [`vertex_origin`](super::Repaired)).
    pub merged_vertices: Change<[usize; 2]>,
    /// Faces removed because they use one vertex twice (after merging).
    pub removed_faces_repeated_vertex: Change<usize>,
    /// Faces removed because an earlier face has the same three vertices (after merging; in any
    /// order or orientation): `[face, kept]`.
    pub removed_duplicate_faces: Change<[usize; 2]>,
    /// Faces removed because their area (or its reciprocal) is zero, subnormal or not finite
    /// ([`MeshError::ZeroAreaFace`](crate::MeshError::ZeroAreaFace)).
    pub removed_faces_zero_area: Change<usize>,
    /// Faces removed because an angle has a non-finite cotangent
    /// ([`MeshError::DegenerateAngle`](crate::MeshError::DegenerateAngle)).
    pub removed_faces_degenerate_angle: Change<usize>,
    /// Edges `[a, b]` (`a < b`) whose faces were separated into several sheets, each with its
    /// own copy of the edge.
    pub split_edges: Change<[usize; 2]>,
    /// Vertices split into several: `[vertex, copies]`, one copy per fan of faces around it.
    pub split_vertices: Change<[usize; 2]>,
    /// Faces whose orientation was reversed.
    pub flipped_faces: Change<usize>,
    /// Vertices removed because no remaining face uses them (never used, or used only by removed
    /// faces, including every vertex with a non-finite coordinate).
    pub removed_unreferenced: Change<usize>,
}

impl RepairReport {
    /// Whether the repair changed nothing.
    pub fn is_empty(&self) -> bool {
        self.lines().next().is_none()
    }

    /// One line per non-empty change, as [`Display`](fmt::Display) prints them.
    pub fn lines(&self) -> impl Iterator<Item = String> + '_ {
        let single = |e: &usize| e.to_string();
        [
            line(
                &self.removed_faces_out_of_range,
                "face with an out-of-range vertex index",
                "faces with out-of-range vertex indices",
                "removed",
                single,
            ),
            line(
                &self.removed_faces_non_finite,
                "face on a non-finite coordinate",
                "faces on non-finite coordinates",
                "removed",
                single,
            ),
            line(
                &self.merged_vertices,
                "vertex into a coincident one",
                "vertices into coincident ones",
                "merged",
                |[v, into]| format!("{v}→{into}"),
            ),
            line(
                &self.removed_faces_repeated_vertex,
                "face repeating a vertex",
                "faces repeating a vertex",
                "removed",
                single,
            ),
            line(
                &self.removed_duplicate_faces,
                "duplicate face",
                "duplicate faces",
                "removed",
                |[face, kept]| format!("{face} = {kept}"),
            ),
            line(
                &self.removed_faces_zero_area,
                "zero-area face",
                "zero-area faces",
                "removed",
                single,
            ),
            line(
                &self.removed_faces_degenerate_angle,
                "face with a degenerate angle",
                "faces with a degenerate angle",
                "removed",
                single,
            ),
            line(
                &self.split_edges,
                "non-manifold edge",
                "non-manifold edges",
                "split",
                |[a, b]| format!("{a}–{b}"),
            ),
            line(
                &self.split_vertices,
                "non-manifold vertex",
                "non-manifold vertices",
                "split",
                |[v, copies]| format!("{v} into {copies}"),
            ),
            line(&self.flipped_faces, "face", "faces", "flipped", single),
            line(
                &self.removed_unreferenced,
                "unreferenced vertex",
                "unreferenced vertices",
                "removed",
                single,
            ),
        ]
        .into_iter()
        .flatten()
    }
}

/// `"{verb} {count} {what} ({examples})"`, with `e.g.` and `…` when there are more than the
/// examples, or `None` for an empty change.
fn line<T>(
    change: &Change<T>,
    one: &str,
    many: &str,
    verb: &str,
    example: impl Fn(&T) -> String,
) -> Option<String> {
    if change.is_empty() {
        return None;
    }
    let what = if change.count == 1 { one } else { many };
    let mut examples: Vec<String> = change.examples.iter().map(example).collect();
    let some = change.count > examples.len();
    if some {
        examples.push("…".to_string());
    }
    let eg = if some { "e.g. " } else { "" };
    Some(format!(
        "{verb} {} {what} ({eg}{})",
        change.count,
        examples.join(", ")
    ))
}

impl fmt::Display for RepairReport {
    /// One line per change (`merged 6 vertices into coincident ones (e.g. 4→3, 9→8, …)`), or
    /// `nothing to repair`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut any = false;
        for line in self.lines() {
            if any {
                writeln!(f)?;
            }
            f.write_str(&line)?;
            any = true;
        }
        if !any {
            f.write_str("nothing to repair")?;
        }
        Ok(())
    }
}
