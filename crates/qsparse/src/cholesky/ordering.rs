//! Fill-reducing orderings of the `n`-node graph of a symmetric pattern: faer's approximate
//! minimum degree (AMD) and our own nested dissection.
//!
//! **Nested dissection** (George 1973; the level-structure variant of George and Liu,
//! *Computer Solution of Large Sparse Positive Definite Systems*, 1981, ch. 8) numbers a graph
//! `G` as `[order(A), order(B), S]` where the separator `S` splits `G − S` into parts `A` and
//! `B` with no edge between them, recursively. Eliminating `A` and `B` then fills nothing
//! between them, so on a mesh of `n` vertices with `O(√n)` separators the factor holds
//! `O(n log n)` entries and costs `O(n^{3/2})` operations. How good it is depends on the
//! separators found: the level separators below are short on closed regular meshes, where
//! they beat AMD (icospheres, the million-vertex torus), and ragged on irregular scanned
//! meshes and open grids, where AMD is better (measured in `docs/PERFORMANCE.md`, "Nested
//! dissection (issue 15)"); hence [`FillOrdering::Automatic`].
//!
//! Each part is split by the level structure of a breadth-first search from a
//! pseudo-peripheral vertex (levels `L₀, …, L_h`, every edge joins equal or adjacent levels):
//! one level `L_m` is a separator of `L_{<m}` and `L_{>m}`. We take the smallest level whose
//! two sides each hold at least 30 % of the vertices outside it (without one, the level of
//! the median vertex), then thin it: a separator vertex with no neighbour in `B` moves to
//! `A`, then one with no neighbour in `A` moves to `B`. Disconnected parts are ordered
//! component by component (small components together); parts of at most 128 vertices,
//! parts whose level structure has fewer than 5 levels (diameter at most 3, e.g. a clique)
//! and parts whose cut leaves more than 3/4 on one side are ordered by AMD — the last rule
//! also keeps the depth of the dissection logarithmic. Vertices of very high degree (dense
//! rows: above `max(16, 10 √n)`, AMD's rule) would join every level structure into two
//! levels; like AMD we take them out first and number them last.
//!
//! The result is finally renumbered in a postorder of its elimination tree, which keeps the
//! fill and makes the columns of each subtree contiguous, as the supernodal analysis expects.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::{FaerError, SymbolicSparseColMatRef};

use crate::{CholeskyError, SymbolicStage};

/// Which fill-reducing ordering [`crate::SymbolicCholesky::analyze_with_ordering`] uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FillOrdering {
    /// faer's approximate minimum degree.
    Amd,
    /// Nested dissection by level structures, small parts by AMD (module [`ordering`](self)).
    NestedDissection,
    /// Below [`NESTED_DISSECTION_MIN_UNKNOWNS`] unknowns AMD; from there both orderings are
    /// analysed and the one whose factorisation costs fewer multiply-adds (`Σ_j c_j²` over
    /// the factor's column counts `c_j`) is kept. Neither wins everywhere (measured in
    /// `docs/PERFORMANCE.md`, "Nested dissection (issue 15)"): nested dissection on closed
    /// regular meshes (icospheres, the million-vertex torus: 20–30 % less fill, factorisation
    /// 2–3× faster), AMD on irregular scanned meshes and open grids; the second analysis costs
    /// 3–6 % of the factorisation it chooses for.
    #[default]
    Automatic,
}

/// Dimension from which [`FillOrdering::Automatic`] analyses both orderings: below it the
/// factorisation is so cheap (under 0.8 s at 41k unknowns) that the second analysis would
/// cost about what nested dissection can save.
pub const NESTED_DISSECTION_MIN_UNKNOWNS: usize = 50_000;

/// Parts of at most this many vertices are ordered by AMD.
const LEAF_VERTICES: usize = 128;
/// Each side of a level separator holds at least this fraction of the part.
const BALANCE: f64 = 0.3;
/// Level structures of smaller height (parts of diameter at most 3) are ordered by AMD: a
/// level separator of them would hold most of the part.
const MIN_HEIGHT: usize = 5;
/// Pseudo-peripheral vertex search: at most this many breadth-first searches.
const PERIPHERAL_SEARCHES: usize = 6;

/// In graphs of more than [`LEAF_VERTICES`] vertices, vertices of degree above this are
/// "dense" and numbered last: `max(16, 10 √n)`, AMD's rule.
fn dense_degree(n: usize) -> usize {
    16.max((10.0 * (n as f64).sqrt()) as usize)
}

/// The undirected graph of a symmetric pattern: the neighbours of `v` (no self loop) are
/// `neighbours[offsets[v]..offsets[v + 1]]`.
pub(super) struct Graph {
    offsets: Vec<usize>,
    neighbours: Vec<usize>,
}

impl Graph {
    /// The graph of the lower triangle of the `n × n` CSC pattern (`col_ptr`, `row_idx`), each
    /// stored entry `(i, j)`, `i > j`, an edge; the upper triangle is ignored, as the
    /// factorisation ignores it.
    pub(super) fn from_lower(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        let mut degree = vec![0usize; n];
        for j in 0..n {
            for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
                if i > j {
                    degree[i] += 1;
                    degree[j] += 1;
                }
            }
        }
        let mut offsets = Vec::with_capacity(n + 1);
        offsets.push(0);
        for d in &degree {
            offsets.push(offsets.last().expect("non-empty") + d);
        }
        let mut fill = offsets[..n].to_vec();
        let mut neighbours = vec![0usize; offsets[n]];
        for j in 0..n {
            for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
                if i > j {
                    neighbours[fill[i]] = j;
                    fill[i] += 1;
                    neighbours[fill[j]] = i;
                    fill[j] += 1;
                }
            }
        }
        Self {
            offsets,
            neighbours,
        }
    }

    fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    fn neighbours(&self, v: usize) -> &[usize] {
        &self.neighbours[self.offsets[v]..self.offsets[v + 1]]
    }
}

/// faer's AMD ordering of the `n × n` pattern (rows need not be sorted), `perm[new] = old`.
pub(super) fn amd_order(
    n: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> Result<Vec<usize>, CholeskyError> {
    let pattern = SymbolicSparseColMatRef::new_unsorted_checked(n, n, col_ptr, None, row_idx);
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let mut buffer =
        MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(n, row_idx.len()))
            .map_err(|_| amd_failed(FaerError::OutOfMemory))?;
    amd::order_maybe_unsorted(
        &mut perm,
        &mut perm_inv,
        pattern,
        amd::Control::default(),
        MemStack::new(&mut buffer),
    )
    .map_err(amd_failed)?;
    Ok(perm)
}

fn amd_failed(source: FaerError) -> CholeskyError {
    CholeskyError::Symbolic {
        stage: SymbolicStage::AmdOrdering,
        source,
    }
}

/// Nested dissection ordering of `graph` (module documentation), `perm[new] = old`, in a
/// postorder of its elimination tree.
pub(super) fn nested_dissection(graph: &Graph) -> Result<Vec<usize>, CholeskyError> {
    let n = graph.len();
    // A small graph is one AMD leaf, dense rows included (AMD treats them itself).
    let dense = if n <= LEAF_VERTICES {
        usize::MAX
    } else {
        dense_degree(n)
    };
    let (sparse, dense_vertices): (Vec<usize>, Vec<usize>) =
        (0..n).partition(|&v| graph.neighbours(v).len() <= dense);
    let mut state = Dissection::new(graph);
    // A dense vertex keeps the stamp `usize::MAX`, which no part has: searches skip it.
    let mut perm = vec![usize::MAX; n];
    let mut tasks = vec![(sparse, 0usize)];
    while let Some((part, start)) = tasks.pop() {
        state.order_part(part, start, &mut perm, &mut tasks)?;
    }
    let first_dense = n - dense_vertices.len();
    perm[first_dense..].copy_from_slice(&dense_vertices);
    Ok(postorder(graph, perm))
}

/// Scratch of the dissection, indexed by vertex.
struct Dissection<'g> {
    graph: &'g Graph,
    /// The part a vertex belongs to while that part is processed (a fresh number per part).
    stamp: Vec<usize>,
    next_stamp: usize,
    /// Breadth-first level within the current part (`usize::MAX`: not reached).
    level: Vec<usize>,
    /// Position within the current part (for the induced subgraph given to AMD), or the side
    /// of the split (`SIDE_*`) while a separator is thinned.
    local: Vec<usize>,
}

/// Where a vertex goes when a part is split.
const SIDE_A: usize = 0;
const SIDE_B: usize = 1;
const SIDE_SEPARATOR: usize = 2;

impl<'g> Dissection<'g> {
    fn new(graph: &'g Graph) -> Self {
        let n = graph.len();
        Self {
            graph,
            stamp: vec![usize::MAX; n],
            next_stamp: 0,
            level: vec![usize::MAX; n],
            local: vec![0; n],
        }
    }

    /// Numbers the vertices of `part` as `start..start + part.len()`, directly (AMD) or by
    /// pushing its pieces onto `tasks`.
    fn order_part(
        &mut self,
        part: Vec<usize>,
        start: usize,
        perm: &mut [usize],
        tasks: &mut Vec<(Vec<usize>, usize)>,
    ) -> Result<(), CholeskyError> {
        if part.is_empty() {
            return Ok(());
        }
        let stamp = self.next_stamp;
        self.next_stamp += 1;
        for &v in &part {
            self.stamp[v] = stamp;
            self.level[v] = usize::MAX;
        }
        if part.len() <= LEAF_VERTICES {
            return self.order_by_amd(&part, start, perm);
        }
        let mut components = self.components(&part, stamp);
        if components.len() > 1 {
            // Small components together by one AMD call (one per component would cost
            // O(n) calls on a matrix with many empty rows), the others as tasks.
            let (small, large): (Vec<_>, Vec<_>) = components
                .into_iter()
                .map(|(order, _)| order)
                .partition(|order| order.len() <= LEAF_VERTICES);
            let small = small.concat();
            if !small.is_empty() {
                self.order_by_amd(&small, start, perm)?;
            }
            let mut next = start + small.len();
            for component in large {
                let len = component.len();
                tasks.push((component, next));
                next += len;
            }
            return Ok(());
        }
        let first = components.pop().expect("a non-empty part has a component");
        let (order, level_ends) = self.pseudo_peripheral_levels(stamp, first);
        if level_ends.len() < MIN_HEIGHT {
            return self.order_by_amd(&order, start, perm);
        }
        let m = separator_level(&level_ends);
        let (a, b, separator) = self.thin(&order, &level_ends, m, stamp);
        if 4 * a.len().max(b.len()) > 3 * order.len() {
            // Too unbalanced to pay (a level structure whose last level holds most of the
            // part); AMD also keeps the dissection's depth logarithmic.
            return self.order_by_amd(&order, start, perm);
        }
        let separator_start = start + a.len() + b.len();
        perm[separator_start..separator_start + separator.len()].copy_from_slice(&separator);
        let b_start = start + a.len();
        tasks.push((b, b_start));
        tasks.push((a, start));
        Ok(())
    }

    /// The connected components of the part `stamp`, each with its breadth-first level
    /// structure from its first vertex in `part` ([`Self::breadth_first`]).
    fn components(&mut self, part: &[usize], stamp: usize) -> Vec<(Vec<usize>, Vec<usize>)> {
        let mut components = Vec::new();
        for &v in part {
            if self.level[v] == usize::MAX {
                components.push(self.breadth_first(v, stamp));
            }
        }
        components
    }

    /// Breadth-first search from `root` within the part `stamp`: the visited vertices in
    /// order and the end of each level in that list. Sets `level`.
    fn breadth_first(&mut self, root: usize, stamp: usize) -> (Vec<usize>, Vec<usize>) {
        let mut order = vec![root];
        let mut level_ends = Vec::new();
        self.level[root] = 0;
        let mut begin = 0;
        while begin < order.len() {
            let end = order.len();
            let depth = level_ends.len();
            for k in begin..end {
                for &u in self.graph.neighbours(order[k]) {
                    if self.stamp[u] == stamp && self.level[u] == usize::MAX {
                        self.level[u] = depth + 1;
                        order.push(u);
                    }
                }
            }
            level_ends.push(end);
            begin = end;
        }
        (order, level_ends)
    }

    /// Level structure from a pseudo-peripheral vertex of the connected part (George and
    /// Liu's search: restart from a vertex of least degree in the last level while the height
    /// grows), starting from the structure `first` (whose levels are set).
    fn pseudo_peripheral_levels(
        &mut self,
        stamp: usize,
        first: (Vec<usize>, Vec<usize>),
    ) -> (Vec<usize>, Vec<usize>) {
        let mut best = first;
        for _ in 0..PERIPHERAL_SEARCHES {
            let (order, level_ends) = &best;
            let last_begin = match level_ends.len() {
                0 | 1 => 0,
                h => level_ends[h - 2],
            };
            let candidate = *order[last_begin..]
                .iter()
                .min_by_key(|&&v| self.graph.neighbours(v).len())
                .expect("the last level is not empty");
            let height = level_ends.len();
            self.clear_levels(&best.0);
            // The candidate lies at distance height − 1 from the root, so its structure is
            // at least as high; keep it, and stop once it is no higher.
            best = self.breadth_first(candidate, stamp);
            if best.1.len() <= height {
                break;
            }
        }
        best
    }

    fn clear_levels(&mut self, vertices: &[usize]) {
        for &v in vertices {
            self.level[v] = usize::MAX;
        }
    }

    /// Splits the level structure at level `m` into `(A, B, S)` and thins `S`.
    fn thin(
        &mut self,
        order: &[usize],
        level_ends: &[usize],
        m: usize,
        stamp: usize,
    ) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
        let separator_begin = if m == 0 { 0 } else { level_ends[m - 1] };
        let separator_end = level_ends[m];
        // `local` holds the side of each vertex of the part for the thinning.
        for (k, &v) in order.iter().enumerate() {
            self.local[v] = if k < separator_begin {
                SIDE_A
            } else if k < separator_end {
                SIDE_SEPARATOR
            } else {
                SIDE_B
            };
        }
        let separator = &order[separator_begin..separator_end];
        for (from, to) in [(SIDE_B, SIDE_A), (SIDE_A, SIDE_B)] {
            for &s in separator {
                if self.local[s] == SIDE_SEPARATOR
                    && !self
                        .graph
                        .neighbours(s)
                        .iter()
                        .any(|&u| self.stamp[u] == stamp && self.local[u] == from)
                {
                    self.local[s] = to;
                }
            }
        }
        let mut parts = (Vec::new(), Vec::new(), Vec::new());
        for &v in order {
            match self.local[v] {
                SIDE_A => parts.0.push(v),
                SIDE_B => parts.1.push(v),
                _ => parts.2.push(v),
            }
        }
        (parts.0, parts.1, parts.2)
    }

    /// Orders `part` by AMD on its induced subgraph into `perm[start..start + part.len()]`.
    fn order_by_amd(
        &mut self,
        part: &[usize],
        start: usize,
        perm: &mut [usize],
    ) -> Result<(), CholeskyError> {
        let stamp = self.stamp[part[0]];
        for (k, &v) in part.iter().enumerate() {
            self.local[v] = k;
        }
        let mut col_ptr = Vec::with_capacity(part.len() + 1);
        col_ptr.push(0);
        let mut row_idx = Vec::new();
        for &v in part {
            row_idx.extend(
                self.graph
                    .neighbours(v)
                    .iter()
                    .filter(|&&u| self.stamp[u] == stamp)
                    .map(|&u| self.local[u]),
            );
            col_ptr.push(row_idx.len());
        }
        let local_perm = amd_order(part.len(), &col_ptr, &row_idx)?;
        for (offset, &k) in local_perm.iter().enumerate() {
            perm[start + offset] = part[k];
        }
        Ok(())
    }
}

/// The separator level of a level structure with `level_ends` (height ≥ [`MIN_HEIGHT`]): the smallest
/// level `m` (neither the first nor the last) whose sides each hold at least [`BALANCE`] of
/// the vertices outside it; without one, the level holding the median vertex.
fn separator_level(level_ends: &[usize]) -> usize {
    let total = *level_ends.last().expect("height ≥ MIN_HEIGHT");
    let size = |m: usize| level_ends[m] - if m == 0 { 0 } else { level_ends[m - 1] };
    let balanced = (1..level_ends.len() - 1)
        .filter(|&m| {
            let below = level_ends[m - 1];
            let above = total - level_ends[m];
            let outside = (below + above) as f64;
            below.min(above) as f64 >= BALANCE * outside
        })
        .min_by_key(|&m| size(m));
    balanced.unwrap_or_else(|| {
        let median = level_ends.partition_point(|&end| end <= total / 2);
        median.clamp(1, level_ends.len() - 2)
    })
}

/// Renumbers `perm` (`perm[new] = old`) in a postorder of the elimination tree of the
/// permuted graph (Liu's algorithm with path compression; children in increasing order).
fn postorder(graph: &Graph, perm: Vec<usize>) -> Vec<usize> {
    const NONE: usize = usize::MAX;
    let n = perm.len();
    let mut perm_inv = vec![0usize; n];
    for (new, &old) in perm.iter().enumerate() {
        perm_inv[old] = new;
    }
    let mut parent = vec![NONE; n];
    let mut ancestor = vec![NONE; n];
    for k in 0..n {
        for &u in graph.neighbours(perm[k]) {
            let mut i = perm_inv[u];
            if i >= k {
                continue;
            }
            while ancestor[i] != NONE && ancestor[i] != k {
                let next = ancestor[i];
                ancestor[i] = k;
                i = next;
            }
            if ancestor[i] == NONE {
                ancestor[i] = k;
                parent[i] = k;
            }
        }
    }
    // Children lists (pushed in decreasing order so that each list is increasing).
    let mut first_child = vec![NONE; n];
    let mut next_sibling = vec![NONE; n];
    for v in (0..n).rev() {
        if parent[v] != NONE {
            next_sibling[v] = first_child[parent[v]];
            first_child[parent[v]] = v;
        }
    }
    let mut result = Vec::with_capacity(n);
    let mut stack = Vec::new();
    for root in (0..n).filter(|&v| parent[v] == NONE) {
        stack.push(root);
        while let Some(&top) = stack.last() {
            let child = first_child[top];
            if child == NONE {
                stack.pop();
                result.push(perm[top]);
            } else {
                first_child[top] = next_sibling[child];
                stack.push(child);
            }
        }
    }
    result
}
