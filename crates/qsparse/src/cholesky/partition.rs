//! Splitting the supernodal elimination tree between two threads.
//!
//! Column `j` of `L` has nonzeros only in rows that are ancestors of `j` in the elimination
//! tree, so disjoint subtrees never touch each other's unknowns: two threads can substitute
//! through two sets of subtrees at once, and only the supernodes above them (the *top*) need
//! the other thread's results. The split is chosen greedily: start from the roots, assign the
//! candidate subtrees to the two threads largest first (each to the lighter thread), and
//! while that is unbalanced, move the root of the largest candidate to the top and its
//! children to the candidates. The estimated time `top + max(first, second)` (work counted in
//! stored factor entries: the solves are bound by memory traffic) is minimised over the
//! sequence of splits. The sequence stops early when no later split can win: the top only
//! grows, and a split with top `t` costs at least `(total + t) / 2`. (Sorting all candidates
//! again at each of up to 256 splits took 0.7 ms, a quarter of analysing a 3k-vertex
//! Laplacian; they are now kept sorted.)
//!
//! The supernodes are then renumbered `[first thread | second thread | top]`, keeping their
//! relative order inside each group. That is again a topological order of the tree (children
//! before parents), so the factor has the same fill; it only makes each group a contiguous
//! range of columns and of factor storage.

/// Supernodes `0..first_end` are the first thread's subtrees, `first_end..second_end` the
/// second thread's, `second_end..` the top (after renumbering).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct TwoWaySplit {
    pub(super) first_end: usize,
    pub(super) second_end: usize,
}

/// A split under consideration: estimated time, top supernodes, `(subtree root, thread)`.
type Candidate = (f64, Vec<usize>, Vec<(usize, usize)>);

/// How many supernodes may move to the top before the search stops.
const MAX_SPLITS: usize = 256;
/// A split must promise at least this speed-up factor over one thread to be used.
const MIN_GAIN: f64 = 1.15;

/// For the supernodal tree `parent` (`None` for roots; parents come after their children)
/// with `work[s]` per supernode, the new order of the supernodes (`order[new] = old`) and
/// the split, or `None` if two threads would not gain [`MIN_GAIN`].
pub(super) fn split_for_two_threads(
    parent: &[Option<usize>],
    work: &[f64],
) -> Option<(Vec<usize>, TwoWaySplit)> {
    let count = parent.len();
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); count];
    let mut subtree = work.to_vec();
    let mut candidates = Vec::new();
    for s in 0..count {
        match parent[s] {
            Some(p) => {
                children[p].push(s);
                subtree[p] += subtree[s];
            }
            None => candidates.push(s),
        }
    }
    let total: f64 = work.iter().sum();
    if total <= 0.0 {
        return None;
    }

    // Greedy splitting; remember the best (top, assignment) seen. The candidates stay sorted
    // by decreasing subtree work (ties by index): a split removes one and inserts its children.
    let before = |a: usize, b: usize| subtree[b].total_cmp(&subtree[a]).then(a.cmp(&b));
    candidates.sort_by(|&a, &b| before(a, b));
    let mut top = Vec::new();
    let mut top_work = 0.0;
    let mut best: Option<Candidate> = None;
    for _ in 0..=MAX_SPLITS {
        let mut bins = [0.0f64; 2];
        let assignment: Vec<(usize, usize)> = candidates
            .iter()
            .map(|&c| {
                let bin = usize::from(bins[1] < bins[0]);
                bins[bin] += subtree[c];
                (c, bin)
            })
            .collect();
        let cost = top_work + bins[0].max(bins[1]);
        if best.as_ref().is_none_or(|(b, _, _)| cost < *b) {
            best = Some((cost, top.clone(), assignment));
        }
        // Every later split costs at least `top + (total − top) / 2` with a larger top: once
        // that reaches the best cost, none can beat it (the margin covers rounding).
        let best_cost = best.as_ref().map_or(f64::INFINITY, |(b, _, _)| *b);
        if (total + top_work) / 2.0 >= best_cost * (1.0 + 1e-9) {
            break;
        }
        // Split the largest candidate that has children.
        let Some(position) = candidates.iter().position(|&c| !children[c].is_empty()) else {
            break;
        };
        let c = candidates.remove(position);
        top.push(c);
        top_work += work[c];
        for &child in &children[c] {
            let at = candidates.partition_point(|&d| before(d, child).is_lt());
            candidates.insert(at, child);
        }
    }
    let (cost, top, assignment) = best?;
    if cost * MIN_GAIN > total {
        return None;
    }

    // Groups: 0 and 1 for the threads, 2 for the top; parents are decided before children.
    const TOP: usize = 2;
    let mut group = vec![usize::MAX; count];
    for &s in &top {
        group[s] = TOP;
    }
    for &(c, bin) in &assignment {
        group[c] = bin;
    }
    for s in (0..count).rev() {
        if group[s] == usize::MAX {
            // Neither top nor a candidate: inside a candidate's subtree.
            group[s] = group[parent[s].expect("only candidates and top nodes are roots")];
        }
    }
    let mut order = Vec::with_capacity(count);
    for g in 0..=TOP {
        order.extend((0..count).filter(|&s| group[s] == g));
    }
    let first_end = group.iter().filter(|&&g| g == 0).count();
    let second_end = first_end + group.iter().filter(|&&g| g == 1).count();
    Some((
        order,
        TwoWaySplit {
            first_end,
            second_end,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Renumbered order is a permutation, topological, and groups are closed under descendants.
    fn check(parent: &[Option<usize>], work: &[f64]) -> Option<TwoWaySplit> {
        let (order, split) = split_for_two_threads(parent, work)?;
        let count = parent.len();
        let mut new_of = vec![usize::MAX; count];
        for (new, &old) in order.iter().enumerate() {
            assert_eq!(new_of[old], usize::MAX, "order repeats {old}");
            new_of[old] = new;
        }
        let group = |new: usize| {
            if new < split.first_end {
                0
            } else if new < split.second_end {
                1
            } else {
                2
            }
        };
        for s in 0..count {
            if let Some(p) = parent[s] {
                assert!(new_of[s] < new_of[p], "child {s} after parent {p}");
                let (gs, gp) = (group(new_of[s]), group(new_of[p]));
                assert!(gp == gs || gp == 2, "{s} in group {gs}, its parent in {gp}");
            }
        }
        Some(split)
    }

    #[test]
    fn balanced_binary_tree_splits_below_the_root() {
        // 7 nodes: leaves 0, 1 → 2; leaves 3, 4 → 5; root 6.
        let parent = [Some(2), Some(2), Some(6), Some(5), Some(5), Some(6), None];
        let split = check(&parent, &[1.0; 7]).expect("a split");
        assert_eq!((split.first_end, split.second_end), (3, 6));
    }

    #[test]
    fn a_path_is_not_split() {
        let parent = [Some(1), Some(2), Some(3), None];
        assert!(check(&parent, &[1.0; 4]).is_none());
    }

    #[test]
    fn a_forest_of_two_trees_needs_no_top() {
        let parent = [Some(1), None, Some(3), None];
        let split = check(&parent, &[1.0; 4]).expect("a split");
        assert_eq!((split.first_end, split.second_end), (2, 4));
    }

    #[test]
    fn random_trees_give_valid_orders() {
        let mut state = 12345u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as usize
        };
        for count in [1usize, 2, 3, 10, 50, 300] {
            for _ in 0..20 {
                let parent: Vec<Option<usize>> = (0..count)
                    .map(|s| {
                        if s + 1 == count || next() % 10 == 0 {
                            None
                        } else {
                            Some(s + 1 + next() % (count - s - 1))
                        }
                    })
                    .collect();
                let work: Vec<f64> = (0..count).map(|_| 1.0 + (next() % 100) as f64).collect();
                check(&parent, &work);
            }
        }
    }
}
