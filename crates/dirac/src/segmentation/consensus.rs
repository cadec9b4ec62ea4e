//! Consensus segmentation (paper §6.2, after Andreux et al. 2014 and Rodolà, Rota Bulò and
//! Cremers 2014): many randomly initialised k-means trials on per-face descriptors, combined by
//! persistence, so that the number of segments is chosen by the method (docs/MATH.md,
//! "Consensus segmentation").
//!
//! The variant implemented, with `F` faces, `T` trials and the options of
//! [`ConsensusOptions`]:
//!
//! 1. **Face descriptors**: the mean of the descriptors of a face's three corners
//!    ([`face_descriptors`]).
//! 2. **Trials**: trial `r = 1…T` draws `k_r` uniformly from
//!    `[min_clusters, max_clusters]` (clamped to `F`) and runs k-means
//!    ([`crate::clustering::kmeans`]) from a random start; one [`SplitMix64`] seeded with
//!    `seed` drives all trials.
//! 3. **Agreement**: for every interior edge `e` between faces `s` and `t`,
//!    `a(e) ∈ {0, …, T}` counts the trials in which `s` and `t` share a cluster.
//! 4. **Partitions**: for each level `j = 1…T` (threshold `θ_j = j/T`) the faces are joined
//!    along every edge with `a(e) ≥ j` (union–find, in decreasing order of `a`, ties by edge
//!    index); then **small segments are absorbed**: the remaining edges are visited in the same
//!    order and their two segments joined when either has less than `min_area_fraction` of the
//!    mesh's area, so a small segment joins the neighbour across its strongest edge. A small
//!    segment without neighbours (a small connected component of the mesh) stays. `S_j` is the
//!    number of segments of level `j`.
//! 5. **Persistence**: the levels form maximal runs `j = a…b` of equal `S_j`; a run covers the
//!    thresholds `θ ∈ ((a−1)/T, b/T]`, and its persistence is its width `(b − a + 1)/T`. The
//!    segmentation is that of the middle level `⌊(a + b)/2⌋` of the most persistent run (ties:
//!    fewer segments, then higher thresholds). Runs whose count is the number of connected
//!    components of the mesh (one segment per component, the trivial end of the diagram) are
//!    candidates only when no other run exists.
//! 6. **A forced count** `N` ([`ConsensusOptions::segments`]): the most persistent run with
//!    `S_j = N` (ties: higher thresholds) if there is one; otherwise the level with the fewest
//!    segments above `N` (ties: the lowest level), whose segments are then joined along the
//!    remaining edges in decreasing agreement until `N` are left.
//!
//! Segments are connected (faces are joined across shared edges only) and numbered `0…S−1` in
//! order of their smallest face index.

use std::cmp::Reverse;

use qscalar::random::SplitMix64;
use qsparse::DisjointSets;
use thiserror::Error;

use crate::TriMesh;
use crate::clustering::{ClusteringError, Initialisation, KMeansOptions, Points, kmeans};
use crate::descriptors::DescriptorTable;
use crate::geometry::face_areas;
use crate::segmentation::seg_file::relabel_by_first_appearance;

/// Parameters of [`consensus_segmentation`]; the defaults are those of `dirac segment` and of
/// the segmentation experiment (docs/MATH.md, "Consensus segmentation").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConsensusOptions {
    /// Number of k-means trials `T` (default 40); the thresholds are the multiples of `1/T`.
    pub trials: usize,
    /// Fewest clusters of a trial (default 2), at least 2.
    pub min_clusters: usize,
    /// Most clusters of a trial (default 6), at least `min_clusters`.
    pub max_clusters: usize,
    /// The start of every trial's k-means (default k-means++).
    pub initialisation: Initialisation,
    /// Most assignment passes of a trial's k-means (default 100).
    pub max_iterations: usize,
    /// Segments with less than this fraction of the mesh's area are absorbed by a neighbour
    /// (default 0.01), in `[0, 1)`.
    pub min_area_fraction: f64,
    /// Force this number of segments instead of choosing it by persistence (default `None`).
    pub segments: Option<usize>,
    /// Seed of the trials' random numbers (default 0).
    pub seed: u64,
}

impl Default for ConsensusOptions {
    fn default() -> Self {
        Self {
            trials: 40,
            min_clusters: 2,
            max_clusters: 6,
            initialisation: Initialisation::PlusPlus,
            max_iterations: 100,
            min_area_fraction: 0.01,
            segments: None,
            seed: 0,
        }
    }
}

/// Why a segmentation could not be computed. Each variant names the offending value.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SegmentationError {
    /// The descriptor table has a row count other than the mesh's vertex count.
    #[error(
        "the descriptor has {rows} rows but the mesh has {vertices} vertices: compute it on \
         this mesh"
    )]
    DescriptorRows {
        /// Rows of the table.
        rows: usize,
        /// Vertices of the mesh.
        vertices: usize,
    },
    /// The face descriptors do not give one row per face.
    #[error(
        "{values} descriptor values of dimension {dimension} do not give one row for each of \
         the {faces} faces"
    )]
    FaceRows {
        /// Values given.
        values: usize,
        /// Their dimension.
        dimension: usize,
        /// Faces of the mesh.
        faces: usize,
    },
    /// The face descriptors cannot be clustered (no columns, or a non-finite value; the
    /// point named is the face).
    #[error("the face descriptors cannot be clustered: {0}")]
    Descriptor(#[from] ClusteringError),
    /// No trials.
    #[error("the number of trials must be at least 1")]
    NoTrials,
    /// The range of clusters per trial is empty or starts below 2.
    #[error(
        "clusters per trial {min}…{max}: need 2 ≤ min ≤ max (a trial with one cluster agrees \
         on every edge)"
    )]
    ClusterRange {
        /// Fewest clusters.
        min: usize,
        /// Most clusters.
        max: usize,
    },
    /// No assignment passes allowed.
    #[error("k-means needs at least one assignment pass (max_iterations = 0)")]
    NoIterations,
    /// The area fraction is not in `[0, 1)`.
    #[error("the smallest segment's area fraction {0} is not in [0, 1)")]
    AreaFraction(f64),
    /// Zero segments were asked for.
    #[error("zero segments asked for: a segmentation has at least one segment")]
    ZeroSegments,
    /// Fewer segments asked for than the mesh has connected components.
    #[error(
        "{requested} segment(s) asked for, but the mesh has {components} connected \
         components and segments do not span components; ask for at least {components}"
    )]
    BelowComponents {
        /// Segments asked for.
        requested: usize,
        /// Connected components of the mesh.
        components: usize,
    },
    /// More segments asked for than any level of the consensus has.
    #[error(
        "{requested} segments asked for, but the consensus has at most {most} at any \
         threshold: use more clusters per trial, more trials or a smaller minimum area"
    )]
    AboveConsensus {
        /// Segments asked for.
        requested: usize,
        /// Most segments of any level.
        most: usize,
    },
}

/// One level of the persistence diagram.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Level {
    /// The threshold `θ_j = j/T` on the fraction of trials that agree across an edge.
    pub threshold: f64,
    /// Segments at this level, small ones absorbed.
    pub segments: usize,
}

/// A maximal run of consecutive levels with the same number of segments: the thresholds
/// `θ ∈ (lowest, highest]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Run {
    /// Segments over the run.
    pub segments: usize,
    /// Lower end of the thresholds (excluded): `(a − 1)/T` for first level `a`.
    pub lowest: f64,
    /// Upper end of the thresholds (included): `b/T` for last level `b`.
    pub highest: f64,
}

impl Run {
    /// The run's persistence, `highest − lowest`.
    pub fn persistence(&self) -> f64 {
        self.highest - self.lowest
    }
}

/// The result of [`consensus_segmentation`].
#[derive(Debug, Clone, PartialEq)]
pub struct ConsensusSegmentation {
    /// The segment (`0…S−1`) of every face.
    pub labels: Vec<usize>,
    /// The area of every segment.
    pub areas: Vec<f64>,
    /// Every level `j = 1…T`, by increasing threshold.
    pub levels: Vec<Level>,
    /// The runs of [`ConsensusSegmentation::levels`], by increasing threshold.
    pub runs: Vec<Run>,
    /// The index in [`ConsensusSegmentation::runs`] of the run whose level was used.
    pub chosen_run: usize,
    /// The threshold of the level used.
    pub threshold: f64,
    /// Whether the count was forced ([`ConsensusOptions::segments`]); the segments of the
    /// level used were then joined further when [`ConsensusSegmentation::segment_count`] is
    /// below the run's count.
    pub forced: bool,
}

impl ConsensusSegmentation {
    /// Number of segments `S`.
    pub fn segment_count(&self) -> usize {
        self.areas.len()
    }

    /// The run whose level was used.
    pub fn run(&self) -> Run {
        self.runs[self.chosen_run]
    }
}

/// The descriptor of every face, the mean of its corners' rows of `table` (a per-vertex
/// descriptor such as [`crate::descriptors::segmentation_descriptor`]), as flat rows of
/// `table.column_count()` values.
pub fn face_descriptors(
    mesh: &TriMesh,
    table: &DescriptorTable,
) -> Result<Vec<f64>, SegmentationError> {
    if table.vertex_count() != mesh.vertex_count() {
        return Err(SegmentationError::DescriptorRows {
            rows: table.vertex_count(),
            vertices: mesh.vertex_count(),
        });
    }
    let mut rows = Vec::with_capacity(mesh.face_count() * table.column_count());
    for face in mesh.faces() {
        let [a, b, c] = face.map(|v| table.row(v));
        rows.extend((0..table.column_count()).map(|j| (a[j] + b[j] + c[j]) / 3.0));
    }
    Ok(rows)
}

/// The consensus segmentation of `mesh` from a per-vertex descriptor table: [`face_descriptors`]
/// then [`consensus_segmentation`].
pub fn segment_by_descriptor(
    mesh: &TriMesh,
    table: &DescriptorTable,
    options: &ConsensusOptions,
) -> Result<ConsensusSegmentation, SegmentationError> {
    let rows = face_descriptors(mesh, table)?;
    consensus_segmentation(mesh, &rows, table.column_count(), options)
}

/// An interior edge of the face graph and its agreement count.
#[derive(Debug, Clone, Copy)]
struct Adjacency {
    faces: [usize; 2],
    agreement: usize,
}

/// The consensus segmentation of `mesh` (see the module documentation) from one descriptor
/// row of `dimension` values per face (`face_rows`, row-major, in face order).
pub fn consensus_segmentation(
    mesh: &TriMesh,
    face_rows: &[f64],
    dimension: usize,
    options: &ConsensusOptions,
) -> Result<ConsensusSegmentation, SegmentationError> {
    check_options(options)?;
    let faces = mesh.face_count();
    if face_rows.len() != faces.saturating_mul(dimension) {
        return Err(SegmentationError::FaceRows {
            values: face_rows.len(),
            dimension,
            faces,
        });
    }
    let points = Points::new(face_rows, dimension)?;
    let mut adjacency: Vec<Adjacency> = mesh
        .edges()
        .iter()
        .filter_map(|e| {
            e.opposite_face.map(|t| Adjacency {
                faces: [e.face, t],
                agreement: 0,
            })
        })
        .collect();

    let mut rng = SplitMix64::new(options.seed);
    let span = (options.max_clusters - options.min_clusters + 1) as u64;
    for _ in 0..options.trials {
        let clusters = (options.min_clusters + (rng.next_u64() % span) as usize).min(faces);
        let trial = KMeansOptions {
            clusters,
            initialisation: options.initialisation,
            max_iterations: options.max_iterations,
        };
        let assignment = kmeans(&points, &trial, &mut rng)?.assignment;
        for edge in &mut adjacency {
            let [s, t] = edge.faces;
            edge.agreement += usize::from(assignment[s] == assignment[t]);
        }
    }
    // Decreasing agreement, ties by edge index (the sort is stable).
    adjacency.sort_by_key(|e| Reverse(e.agreement));

    let areas = face_areas(mesh);
    let smallest = options.min_area_fraction * areas.iter().sum::<f64>();
    let merging = Merging {
        adjacency: &adjacency,
        areas: &areas,
        smallest,
    };
    let trials = options.trials;
    let levels: Vec<Level> = (1..=trials)
        .map(|j| Level {
            threshold: j as f64 / trials as f64,
            segments: merging.level(j).count,
        })
        .collect();
    let runs = runs(&levels, trials);
    let components = merging.components();

    let (chosen_run, level, partition) = match options.segments {
        None => {
            let candidates: Vec<usize> = (0..runs.len())
                .filter(|&r| runs[r].segments != components)
                .collect();
            let pool = if candidates.is_empty() {
                (0..runs.len()).collect()
            } else {
                candidates
            };
            let best = most_persistent(&runs, &pool);
            let level = middle_level(&runs[best], trials);
            (best, level, merging.level(level))
        }
        Some(requested) => {
            check_requested(requested, components, &levels)?;
            let exact: Vec<usize> = (0..runs.len())
                .filter(|&r| runs[r].segments == requested)
                .collect();
            if exact.is_empty() {
                // The level with the fewest segments above the count asked for, joined further.
                let level = (1..=trials)
                    .filter(|&j| levels[j - 1].segments > requested)
                    .min_by_key(|&j| (levels[j - 1].segments, j))
                    .expect("check_requested found a level with more segments");
                let mut partition = merging.level(level);
                merging.join_down_to(&mut partition, requested);
                (run_of(&runs, level, trials), level, partition)
            } else {
                let best = most_persistent(&runs, &exact);
                let level = middle_level(&runs[best], trials);
                (best, level, merging.level(level))
            }
        }
    };
    let (labels, segment_areas) = partition.labels(&areas);
    Ok(ConsensusSegmentation {
        labels,
        areas: segment_areas,
        levels,
        runs,
        chosen_run,
        threshold: level as f64 / trials as f64,
        forced: options.segments.is_some(),
    })
}

/// The checks of [`consensus_segmentation`] on its options.
fn check_options(options: &ConsensusOptions) -> Result<(), SegmentationError> {
    if options.trials == 0 {
        return Err(SegmentationError::NoTrials);
    }
    let (min, max) = (options.min_clusters, options.max_clusters);
    if min < 2 || max < min {
        return Err(SegmentationError::ClusterRange { min, max });
    }
    if options.max_iterations == 0 {
        return Err(SegmentationError::NoIterations);
    }
    let fraction = options.min_area_fraction;
    if !(0.0..1.0).contains(&fraction) {
        return Err(SegmentationError::AreaFraction(fraction));
    }
    if options.segments == Some(0) {
        return Err(SegmentationError::ZeroSegments);
    }
    Ok(())
}

/// A forced count must lie between the number of components and the most segments of a level.
fn check_requested(
    requested: usize,
    components: usize,
    levels: &[Level],
) -> Result<(), SegmentationError> {
    if requested < components {
        return Err(SegmentationError::BelowComponents {
            requested,
            components,
        });
    }
    let most = levels
        .iter()
        .map(|l| l.segments)
        .max()
        .unwrap_or(components);
    if requested > most {
        return Err(SegmentationError::AboveConsensus { requested, most });
    }
    Ok(())
}

/// The maximal runs of equal counts over the levels `1…T`.
fn runs(levels: &[Level], trials: usize) -> Vec<Run> {
    let mut runs: Vec<Run> = Vec::new();
    for (i, level) in levels.iter().enumerate() {
        match runs.last_mut() {
            Some(run) if run.segments == level.segments => run.highest = level.threshold,
            _ => runs.push(Run {
                segments: level.segments,
                lowest: i as f64 / trials as f64,
                highest: level.threshold,
            }),
        }
    }
    runs
}

/// First and last level `(a, b)` of a run.
fn run_levels(run: &Run, trials: usize) -> (usize, usize) {
    let level = |theta: f64| (theta * trials as f64).round() as usize;
    (level(run.lowest) + 1, level(run.highest))
}

/// The middle level `⌊(a + b)/2⌋` of a run.
fn middle_level(run: &Run, trials: usize) -> usize {
    let (a, b) = run_levels(run, trials);
    (a + b) / 2
}

/// The index of the run containing `level`.
fn run_of(runs: &[Run], level: usize, trials: usize) -> usize {
    runs.iter()
        .position(|run| {
            let (a, b) = run_levels(run, trials);
            (a..=b).contains(&level)
        })
        .expect("the runs cover every level")
}

/// Among the runs `pool` (non-empty), the most persistent; ties: fewer segments, then the run
/// at higher thresholds.
fn most_persistent(runs: &[Run], pool: &[usize]) -> usize {
    let width = |r: usize| runs[r].persistence();
    pool.iter()
        .copied()
        .reduce(|best, r| {
            let (wb, wr) = (width(best), width(r));
            // Widths are multiples of 1/T: compare with a tolerance far below 1/T.
            let tolerance = 1e-9;
            if wr > wb + tolerance
                || ((wr - wb).abs() <= tolerance && runs[r].segments <= runs[best].segments)
            {
                r
            } else {
                best
            }
        })
        .expect("a non-empty pool of runs")
}

/// The face graph sorted by decreasing agreement, the face areas and the smallest area of a
/// segment that is not absorbed.
struct Merging<'a> {
    adjacency: &'a [Adjacency],
    areas: &'a [f64],
    smallest: f64,
}

/// Faces joined into segments, with the area and count of the segments.
struct Partition {
    sets: DisjointSets,
    /// Area of the segment, valid at each root.
    area: Vec<f64>,
    count: usize,
}

impl Partition {
    /// Joins the segments of faces `s` and `t`; whether they were different.
    fn join(&mut self, s: usize, t: usize) -> bool {
        let (a, b) = (self.sets.find(s), self.sets.find(t));
        if a == b {
            return false;
        }
        self.sets.union(a, b);
        let root = self.sets.find(a);
        self.area[root] = self.area[a] + self.area[b];
        self.count -= 1;
        true
    }

    /// Whether the segment of face `t` has less than `smallest` area.
    fn is_small(&mut self, t: usize, smallest: f64) -> bool {
        let root = self.sets.find(t);
        self.area[root] < smallest
    }

    /// Labels `0…S−1` by smallest face, and the area of each segment.
    fn labels(mut self, areas: &[f64]) -> (Vec<usize>, Vec<f64>) {
        let roots: Vec<usize> = (0..areas.len()).map(|t| self.sets.find(t)).collect();
        let labels = relabel_by_first_appearance(&roots);
        let mut segment_areas = vec![0.0; self.count];
        for (&label, &area) in labels.iter().zip(areas) {
            segment_areas[label] += area;
        }
        (labels, segment_areas)
    }
}

impl Merging<'_> {
    /// Every face its own segment.
    fn singletons(&self) -> Partition {
        Partition {
            sets: DisjointSets::new(self.areas.len()),
            area: self.areas.to_vec(),
            count: self.areas.len(),
        }
    }

    /// The number of connected components of the face graph.
    fn components(&self) -> usize {
        let mut partition = self.singletons();
        for edge in self.adjacency {
            partition.join(edge.faces[0], edge.faces[1]);
        }
        partition.count
    }

    /// The partition of level `j`: joined along every edge with agreement `≥ j`, then small
    /// segments absorbed along the remaining edges in order.
    fn level(&self, j: usize) -> Partition {
        let mut partition = self.singletons();
        let split = self.adjacency.partition_point(|e| e.agreement >= j);
        for edge in &self.adjacency[..split] {
            partition.join(edge.faces[0], edge.faces[1]);
        }
        for edge in &self.adjacency[split..] {
            let [s, t] = edge.faces;
            if partition.is_small(s, self.smallest) || partition.is_small(t, self.smallest) {
                partition.join(s, t);
            }
        }
        partition
    }

    /// Joins segments along the edges in decreasing agreement until `count` remain (or no edge
    /// joins two segments).
    fn join_down_to(&self, partition: &mut Partition, count: usize) {
        for edge in self.adjacency {
            if partition.count <= count {
                break;
            }
            partition.join(edge.faces[0], edge.faces[1]);
        }
    }
}
