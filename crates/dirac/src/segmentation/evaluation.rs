//! The Princeton benchmark's error measures between a computed segmentation `S₁` and a
//! reference `S₂` (Chen, Golovinskiy, Funkhouser, "A Benchmark for 3D Mesh Segmentation",
//! SIGGRAPH 2009, §4), computed as the benchmark's own evaluation program (`segEval`)
//! computes them, so that scores compare with the published tables. All are errors: 0 for
//! identical segmentations, larger is worse; docs/MATH.md, "Segmentation benchmark measures".
//!
//! Both segmentations are per-face labels on the same mesh; only the partitions matter. With
//! `n_ij` faces (`w_ij` area) in segment `i` of `S₁` and segment `j` of `S₂`, `a_i = Σ_j n_ij`,
//! `b_j = Σ_i n_ij`, `N` faces and total area `A`:
//!
//! - **Cut Discrepancy** ([`SegmentationEvaluator::cut_discrepancy`]): the mean, over the cut
//!   vertices of both segmentations, of the distance to the nearest cut vertex of the other,
//!   divided by the mean distance `R̄` from the surface to its centroid. A cut vertex is an
//!   end of an interior edge whose two faces lie in different segments.
//! - **Hamming distance** ([`SegmentationEvaluator::hamming_distance`]), area-weighted:
//!   missing rate `Rm = (A − Σ_j max_i w_ij) / A`, false-alarm rate
//!   `Rf = (A − Σ_i max_j w_ij) / A`, distance `(Rm + Rf) / 2`.
//! - **Rand Index** ([`rand_index_error`]), over faces (not area), reported as
//!   `1 − RI = [Σ_i C(a_i,2) + Σ_j C(b_j,2) − 2 Σ_ij C(n_ij,2)] / C(N,2)`.
//! - **Global and Local Consistency Error** ([`consistency_errors`]), over faces (not area):
//!   `GCE = min(Σ_ij n_ij (1 − n_ij/a_i), Σ_ij n_ij (1 − n_ij/b_j)) / N` and
//!   `LCE = Σ_ij n_ij min(1 − n_ij/a_i, 1 − n_ij/b_j) / N`.
//!
//! The benchmark's per-model score is the mean over the model's human segmentations
//! ([`SegmentationEvaluator::scores_against_references`]). Every measure is computed from the
//! sparse contingency table (`O(N)`), the cuts by one multi-source Dijkstra per segmentation.

use std::cmp::{Ordering, Reverse};
use std::collections::{BinaryHeap, HashMap};
use std::fmt;

use thiserror::Error;

use crate::TriMesh;
use crate::geometry::{face_areas, norm, sub};

use super::seg_file::relabel_by_first_appearance;

/// Which segmentation an [`EvaluationError`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentationRole {
    /// The segmentation being scored (`S₁`).
    Computed,
    /// A reference (`S₂`), by its position in the list of references (0-based).
    Reference(usize),
}

impl fmt::Display for SegmentationRole {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Computed => write!(f, "the computed segmentation"),
            Self::Reference(index) => write!(f, "reference segmentation {index}"),
        }
    }
}

/// Why segmentations could not be compared.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum EvaluationError {
    /// A segmentation does not have one label per face.
    #[error(
        "{segmentation} has {labels} labels for {faces} faces (one label per face, in the mesh's \
         face order)"
    )]
    LabelCount {
        /// The segmentation.
        segmentation: SegmentationRole,
        /// Its number of labels.
        labels: usize,
        /// The number of faces: of the mesh, or the computed segmentation's number of labels
        /// when no mesh is involved.
        faces: usize,
    },
    /// No reference segmentation was given to average over.
    #[error("no reference segmentation to compare with: give at least one")]
    NoReferences,
    /// Fewer than two faces: the Rand index counts pairs of faces.
    #[error("{faces} face(s): the measures need at least 2 faces")]
    TooFewFaces {
        /// The number of faces.
        faces: usize,
    },
}

/// The Hamming distance and its two directional parts, fractions of the surface area in
/// `[0, 1]` (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct HammingDistance {
    /// `(Rm + Rf) / 2`.
    pub distance: f64,
    /// `Rm = (A − Σ_j max_i w_ij) / A`: the area of each reference segment outside the
    /// computed segment overlapping it most.
    pub missing_rate: f64,
    /// `Rf = (A − Σ_i max_j w_ij) / A`: the area of each computed segment outside the
    /// reference segment overlapping it most.
    pub false_alarm_rate: f64,
}

/// The Global and Local Consistency Errors, in `[0, 1]` (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ConsistencyErrors {
    /// GCE: the smaller of the two directional refinement errors, summed over faces.
    pub global: f64,
    /// LCE: the smaller directional refinement error per face, summed.
    pub local: f64,
}

/// All the benchmark's measures between a computed segmentation and one reference, or their
/// means over several ([`ModelScores::mean`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Scores {
    /// Cut Discrepancy; `None` when one of the segmentations has no cut (a single segment),
    /// where it is undefined (`segEval` reports no value then). Infinite when a cut vertex
    /// cannot reach the other segmentation's cut along the edges (a connected component cut
    /// in only one of them); JSON writes that as `null` too.
    pub cut_discrepancy: Option<f64>,
    /// Hamming distance with `Rm` and `Rf`.
    pub hamming: HammingDistance,
    /// `1 − RI`, the Rand index as the benchmark reports it (an error).
    pub rand_index_error: f64,
    /// GCE and LCE.
    pub consistency: ConsistencyErrors,
}

/// The benchmark's per-model score: the measures against each reference and their mean.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ModelScores {
    /// Against each reference, in the order given.
    pub per_reference: Vec<Scores>,
    /// The arithmetic mean of each measure over the references; the Cut Discrepancy over
    /// those where it is defined (`None` if it is defined for none).
    pub mean: Scores,
    /// How many references the mean Cut Discrepancy averages over.
    pub cut_discrepancy_references: usize,
}

/// `1 − RI` between two per-face segmentations (module doc): the fraction of pairs of faces
/// on which they disagree (together in one, apart in the other). Symmetric.
pub fn rand_index_error(computed: &[usize], reference: &[usize]) -> Result<f64, EvaluationError> {
    check_label_counts(computed, reference)?;
    Ok(Contingency::new(computed, reference).rand_index_error())
}

/// GCE and LCE between two per-face segmentations (module doc). Symmetric; 0 whenever one is a
/// refinement of the other.
pub fn consistency_errors(
    computed: &[usize],
    reference: &[usize],
) -> Result<ConsistencyErrors, EvaluationError> {
    check_label_counts(computed, reference)?;
    Ok(Contingency::new(computed, reference).consistency_errors())
}

/// The parts of a mesh the measures need, computed once for any number of comparisons: face
/// areas, the mean radius `R̄`, and the edge graph for the cut distances.
#[derive(Debug, Clone)]
pub struct SegmentationEvaluator {
    face_areas: Vec<f64>,
    /// Interior edges as (vertices, its two faces).
    interior_edges: Vec<([usize; 2], [usize; 2])>,
    /// The edge graph in compressed rows: the neighbours of `v` and the edge lengths are
    /// `neighbours[offsets[v]..offsets[v + 1]]`.
    offsets: Vec<usize>,
    neighbours: Vec<(usize, f64)>,
    mean_radius: f64,
}

impl SegmentationEvaluator {
    /// Prepares `mesh` (at least 2 faces) for evaluating segmentations of its faces.
    pub fn new(mesh: &TriMesh) -> Result<Self, EvaluationError> {
        if mesh.face_count() < 2 {
            return Err(EvaluationError::TooFewFaces {
                faces: mesh.face_count(),
            });
        }
        let positions = mesh.positions();
        let edges = mesh.edges();
        let mut degree = vec![0; mesh.vertex_count() + 1];
        for edge in &edges {
            degree[edge.vertices[0] + 1] += 1;
            degree[edge.vertices[1] + 1] += 1;
        }
        let offsets: Vec<usize> = degree
            .iter()
            .scan(0, |sum, &d| {
                *sum += d;
                Some(*sum)
            })
            .collect();
        let mut fill = offsets.clone();
        let mut neighbours = vec![(0, 0.0); offsets[mesh.vertex_count()]];
        for edge in &edges {
            let [u, v] = edge.vertices;
            let length = norm(sub(positions[u], positions[v]));
            neighbours[fill[u]] = (v, length);
            fill[u] += 1;
            neighbours[fill[v]] = (u, length);
            fill[v] += 1;
        }
        let interior_edges = edges
            .iter()
            .filter_map(|e| e.opposite_face.map(|o| (e.vertices, [e.face, o])))
            .collect();
        let face_areas = face_areas(mesh);
        let mean_radius = mean_radius(mesh, &face_areas);
        Ok(Self {
            face_areas,
            interior_edges,
            offsets,
            neighbours,
            mean_radius,
        })
    }

    /// Number of faces of the mesh.
    pub fn face_count(&self) -> usize {
        self.face_areas.len()
    }

    /// `R̄ = Σ_t A_t |c_t − c| / Σ_t A_t`, the area-weighted mean distance from the face
    /// centroids `c_t` to the surface centroid `c = Σ_t A_t c_t / Σ_t A_t`: the benchmark's
    /// scale for the Cut Discrepancy.
    pub fn mean_radius(&self) -> f64 {
        self.mean_radius
    }

    /// Every measure between `computed` and `reference` (module doc).
    pub fn scores(
        &self,
        computed: &[usize],
        reference: &[usize],
    ) -> Result<Scores, EvaluationError> {
        self.check_pair(computed, reference)?;
        let table = Contingency::new(computed, reference);
        Ok(Scores {
            cut_discrepancy: self.cut_discrepancy_unchecked(computed, reference),
            hamming: table.hamming_distance(&self.face_areas),
            rand_index_error: table.rand_index_error(),
            consistency: table.consistency_errors(),
        })
    }

    /// The benchmark's per-model score: [`scores`](Self::scores) against each of `references`
    /// and their means.
    pub fn scores_against_references<R: AsRef<[usize]>>(
        &self,
        computed: &[usize],
        references: &[R],
    ) -> Result<ModelScores, EvaluationError> {
        if references.is_empty() {
            return Err(EvaluationError::NoReferences);
        }
        for (index, reference) in references.iter().enumerate() {
            self.check(SegmentationRole::Reference(index), reference.as_ref())?;
        }
        let per_reference = references
            .iter()
            .map(|reference| self.scores(computed, reference.as_ref()))
            .collect::<Result<Vec<_>, _>>()?;
        let count = per_reference.len() as f64;
        let mean_of =
            |measure: fn(&Scores) -> f64| per_reference.iter().map(measure).sum::<f64>() / count;
        let defined: Vec<f64> = per_reference
            .iter()
            .filter_map(|s| s.cut_discrepancy)
            .collect();
        let mean = Scores {
            cut_discrepancy: (!defined.is_empty())
                .then(|| defined.iter().sum::<f64>() / defined.len() as f64),
            hamming: HammingDistance {
                distance: mean_of(|s| s.hamming.distance),
                missing_rate: mean_of(|s| s.hamming.missing_rate),
                false_alarm_rate: mean_of(|s| s.hamming.false_alarm_rate),
            },
            rand_index_error: mean_of(|s| s.rand_index_error),
            consistency: ConsistencyErrors {
                global: mean_of(|s| s.consistency.global),
                local: mean_of(|s| s.consistency.local),
            },
        };
        Ok(ModelScores {
            per_reference,
            mean,
            cut_discrepancy_references: defined.len(),
        })
    }

    /// The area-weighted Hamming distance, `Rm` and `Rf` (module doc).
    pub fn hamming_distance(
        &self,
        computed: &[usize],
        reference: &[usize],
    ) -> Result<HammingDistance, EvaluationError> {
        self.check_pair(computed, reference)?;
        Ok(Contingency::new(computed, reference).hamming_distance(&self.face_areas))
    }

    /// The Cut Discrepancy (module doc; `None` and infinity as in [`Scores::cut_discrepancy`]):
    ///
    /// `CD = (Σ_{v∈C₁} d(v, C₂) + Σ_{v∈C₂} d(v, C₁)) / ((|C₁| + |C₂|) R̄)`
    ///
    /// with `C_k` the cut vertices of `S_k` and `d` the shortest-path distance along the mesh
    /// edges (Dijkstra), as `segEval` computes it: it pools both directions into one mean,
    /// where the paper's formula adds the two directional means (about twice as much when
    /// `|C₁| ≈ |C₂|`); the published tables come from the program. The edge-path distance
    /// is exact along edges and overestimates the geodesic distance where that crosses faces
    /// (zigzag paths); it is what the benchmark used, needs no linear solve and is exactly 0
    /// on the cut vertices themselves.
    pub fn cut_discrepancy(
        &self,
        computed: &[usize],
        reference: &[usize],
    ) -> Result<Option<f64>, EvaluationError> {
        self.check_pair(computed, reference)?;
        Ok(self.cut_discrepancy_unchecked(computed, reference))
    }

    fn cut_discrepancy_unchecked(&self, computed: &[usize], reference: &[usize]) -> Option<f64> {
        let cut_computed = self.cut_vertices(computed);
        let cut_reference = self.cut_vertices(reference);
        if cut_computed.is_empty() || cut_reference.is_empty() {
            return None;
        }
        let to_reference = self.distances_from(&cut_reference);
        let to_computed = self.distances_from(&cut_computed);
        let sum = cut_computed.iter().map(|&v| to_reference[v]).sum::<f64>()
            + cut_reference.iter().map(|&v| to_computed[v]).sum::<f64>();
        let count = (cut_computed.len() + cut_reference.len()) as f64;
        Some(sum / count / self.mean_radius)
    }

    /// The vertices of interior edges whose two faces have different labels, ascending.
    fn cut_vertices(&self, labels: &[usize]) -> Vec<usize> {
        let mut on_cut = vec![false; self.offsets.len() - 1];
        for &(vertices, [f, g]) in &self.interior_edges {
            if labels[f] != labels[g] {
                vertices.iter().for_each(|&v| on_cut[v] = true);
            }
        }
        (0..on_cut.len()).filter(|&v| on_cut[v]).collect()
    }

    /// Shortest edge-path distance from every vertex to the nearest of `sources` (Dijkstra;
    /// infinite where none is reachable).
    fn distances_from(&self, sources: &[usize]) -> Vec<f64> {
        let mut distance = vec![f64::INFINITY; self.offsets.len() - 1];
        let mut heap = BinaryHeap::new();
        for &s in sources {
            distance[s] = 0.0;
            heap.push(Reverse(Tentative(0.0, s)));
        }
        while let Some(Reverse(Tentative(d, v))) = heap.pop() {
            if d > distance[v] {
                continue; // a stale entry: v was reached more cheaply since
            }
            for &(w, length) in &self.neighbours[self.offsets[v]..self.offsets[v + 1]] {
                let through = d + length;
                if through < distance[w] {
                    distance[w] = through;
                    heap.push(Reverse(Tentative(through, w)));
                }
            }
        }
        distance
    }

    /// One label per face in both (a mismatched reference named as reference 0).
    fn check_pair(&self, computed: &[usize], reference: &[usize]) -> Result<(), EvaluationError> {
        self.check(SegmentationRole::Computed, computed)?;
        self.check(SegmentationRole::Reference(0), reference)
    }

    fn check(
        &self,
        segmentation: SegmentationRole,
        labels: &[usize],
    ) -> Result<(), EvaluationError> {
        if labels.len() == self.face_count() {
            Ok(())
        } else {
            Err(EvaluationError::LabelCount {
                segmentation,
                labels: labels.len(),
                faces: self.face_count(),
            })
        }
    }
}

/// A distance and its vertex, ordered by the distance (finite, never NaN) for the heap.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Tentative(f64, usize);

impl Eq for Tentative {}

impl PartialOrd for Tentative {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Tentative {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0).then(self.1.cmp(&other.1))
    }
}

/// `R̄` of [`SegmentationEvaluator::mean_radius`].
fn mean_radius(mesh: &TriMesh, areas: &[f64]) -> f64 {
    let positions = mesh.positions();
    let centroids: Vec<[f64; 3]> = mesh
        .faces()
        .iter()
        .map(|face| {
            let mut c = [0.0; 3];
            for &v in face {
                (0..3).for_each(|k| c[k] += positions[v][k] / 3.0);
            }
            c
        })
        .collect();
    let total: f64 = areas.iter().sum();
    let mut center = [0.0; 3];
    for (c, a) in centroids.iter().zip(areas) {
        (0..3).for_each(|k| center[k] += a * c[k] / total);
    }
    centroids
        .iter()
        .zip(areas)
        .map(|(&c, a)| a * norm(sub(c, center)))
        .sum::<f64>()
        / total
}

/// `computed` and `reference` label the same faces, at least 2 of them.
fn check_label_counts(computed: &[usize], reference: &[usize]) -> Result<(), EvaluationError> {
    let faces = computed.len();
    if faces < 2 {
        return Err(EvaluationError::TooFewFaces { faces });
    }
    if reference.len() != faces {
        return Err(EvaluationError::LabelCount {
            segmentation: SegmentationRole::Reference(0),
            labels: reference.len(),
            faces,
        });
    }
    Ok(())
}

/// The sparse contingency table of two segmentations: the nonzero `n_ij` with the segment
/// sizes `a_i`, `b_j` (segments renumbered `0…S−1` by first appearance).
struct Contingency {
    /// `(i, j, n_ij)` for every nonzero cell.
    cells: Vec<(usize, usize, usize)>,
    /// The cell of each face, an index into `cells`.
    cell_of_face: Vec<usize>,
    row_sizes: Vec<usize>,
    column_sizes: Vec<usize>,
}

impl Contingency {
    fn new(computed: &[usize], reference: &[usize]) -> Self {
        let rows = relabel_by_first_appearance(computed);
        let columns = relabel_by_first_appearance(reference);
        let mut index: HashMap<(usize, usize), usize> = HashMap::new();
        let mut cells = Vec::new();
        let cell_of_face = rows
            .iter()
            .zip(&columns)
            .map(|(&i, &j)| {
                let cell = *index.entry((i, j)).or_insert_with(|| {
                    cells.push((i, j, 0));
                    cells.len() - 1
                });
                cells[cell].2 += 1;
                cell
            })
            .collect();
        Self {
            cells,
            cell_of_face,
            row_sizes: sizes(&rows),
            column_sizes: sizes(&columns),
        }
    }

    fn faces(&self) -> usize {
        self.cell_of_face.len()
    }

    fn rand_index_error(&self) -> f64 {
        // Exact in integers: every sum is at most C(N, 2) (the one subtracted twice is at
        // most either of the others).
        let pairs = |n: usize| (n as u128) * (n as u128).saturating_sub(1) / 2;
        let together_computed: u128 = self.row_sizes.iter().map(|&a| pairs(a)).sum();
        let together_reference: u128 = self.column_sizes.iter().map(|&b| pairs(b)).sum();
        let together_both: u128 = self.cells.iter().map(|&(_, _, n)| pairs(n)).sum();
        let disagreeing = together_computed + together_reference - 2 * together_both;
        disagreeing as f64 / pairs(self.faces()) as f64
    }

    fn consistency_errors(&self) -> ConsistencyErrors {
        let (mut computed_in_reference, mut reference_in_computed, mut local) = (0.0, 0.0, 0.0);
        for &(i, j, n) in &self.cells {
            let n = n as f64;
            // E(S₁, S₂, p) and E(S₂, S₁, p), the same for the n faces p of this cell.
            let e12 = 1.0 - n / self.row_sizes[i] as f64;
            let e21 = 1.0 - n / self.column_sizes[j] as f64;
            computed_in_reference += n * e12;
            reference_in_computed += n * e21;
            local += n * e12.min(e21);
        }
        let faces = self.faces() as f64;
        ConsistencyErrors {
            global: computed_in_reference.min(reference_in_computed) / faces,
            local: local / faces,
        }
    }

    /// With the cell areas `w_ij` summed from `face_areas`.
    fn hamming_distance(&self, face_areas: &[f64]) -> HammingDistance {
        let mut cell_areas = vec![0.0; self.cells.len()];
        for (&cell, &area) in self.cell_of_face.iter().zip(face_areas) {
            cell_areas[cell] += area;
        }
        let mut best_for_row = vec![0.0_f64; self.row_sizes.len()];
        let mut best_for_column = vec![0.0_f64; self.column_sizes.len()];
        for (&(i, j, _), &w) in self.cells.iter().zip(&cell_areas) {
            best_for_row[i] = best_for_row[i].max(w);
            best_for_column[j] = best_for_column[j].max(w);
        }
        let total: f64 = face_areas.iter().sum();
        // Summed in another order, identical segmentations can leave −1e−17; the rates are ≥ 0.
        let rate = |best: &[f64]| ((total - best.iter().sum::<f64>()) / total).max(0.0);
        let missing_rate = rate(&best_for_column);
        let false_alarm_rate = rate(&best_for_row);
        HammingDistance {
            distance: (missing_rate + false_alarm_rate) / 2.0,
            missing_rate,
            false_alarm_rate,
        }
    }
}

/// How many faces carry each label `0…S−1`.
fn sizes(labels: &[usize]) -> Vec<usize> {
    let mut sizes = Vec::new();
    for &label in labels {
        if label >= sizes.len() {
            sizes.resize(label + 1, 0);
        }
        sizes[label] += 1;
    }
    sizes
}
