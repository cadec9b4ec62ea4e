//! Merging vertices closer than a tolerance: spatial hashing and union–find.

use std::collections::HashMap;

use qsparse::DisjointSets;

use crate::geometry::bounding_box;

/// The Euclidean distance `|a − b|`, by `hypot` so that it neither underflows nor overflows
/// before the result does (and is never below a coordinate difference, which the grid relies on).
pub(super) fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1]).hypot(a[2] - b[2])
}

/// The bounding box of the points `p[v]` with `selected[v]`, or `None` if none is selected.
fn selected_box(positions: &[[f64; 3]], selected: &[bool]) -> Option<([f64; 3], [f64; 3])> {
    bounding_box(
        positions
            .iter()
            .zip(selected)
            .filter(|&(_, &s)| s)
            .map(|(p, _)| *p),
    )
}

/// The absolute tolerance `merge_distance · d`, `d` the diagonal of the bounding box of the
/// selected points (`0` without any; may be infinite for coordinates near `±f64::MAX`).
pub(super) fn tolerance(positions: &[[f64; 3]], selected: &[bool], merge_distance: f64) -> f64 {
    // Not `0 · ∞`: zero merges only equal points even when the box overflows.
    match selected_box(positions, selected) {
        Some((lo, hi)) if merge_distance != 0.0 => {
            let extent: [f64; 3] = std::array::from_fn(|c| hi[c] - lo[c]);
            merge_distance * extent[0].hypot(extent[1]).hypot(extent[2])
        }
        _ => 0.0,
    }
}

/// For every vertex, the smallest index of its cluster: the selected vertices (finite
/// coordinates) are joined whenever `|p_a − p_b| ≤ merge_distance · d`, `d` the diagonal of
/// their bounding box, and clusters are the connected components of that relation (so chains
/// merge, whatever the order of the vertices). Unselected vertices are their own cluster.
///
/// `merge_distance = 0` joins exactly equal coordinates only (`−0 = +0`). The tolerance of a
/// subset of the points is never larger (its box is inside this one), which makes merging
/// idempotent: the representatives of two clusters stay farther apart than the tolerance.
pub(super) fn clusters(
    positions: &[[f64; 3]],
    selected: &[bool],
    merge_distance: f64,
) -> Vec<usize> {
    let mut sets = DisjointSets::new(positions.len());
    if let Some((lo, hi)) = selected_box(positions, selected) {
        let extent: [f64; 3] = std::array::from_fn(|c| hi[c] - lo[c]);
        let tolerance = tolerance(positions, selected, merge_distance);
        let members = (0..positions.len()).filter(|&v| selected[v]);
        if tolerance.is_finite() {
            join_close(&mut sets, positions, members, lo, extent, tolerance);
        } else {
            // Coordinates near ±f64::MAX: every point is within an infinite tolerance.
            let members: Vec<usize> = members.collect();
            for pair in members.windows(2) {
                sets.union(pair[0], pair[1]);
            }
        }
    }
    // The representative is the smallest index of each class, whatever union–find chose.
    let mut smallest = vec![usize::MAX; positions.len()];
    let roots: Vec<usize> = (0..positions.len()).map(|v| sets.find(v)).collect();
    for (v, &root) in roots.iter().enumerate() {
        smallest[root] = smallest[root].min(v);
    }
    roots.iter().map(|&root| smallest[root]).collect()
}

/// Joins the `members` within `tolerance` (finite, ≥ 0) of each other. Points are hashed to a
/// grid; a pair within the tolerance lies in the same or neighbouring cells.
fn join_close(
    sets: &mut DisjointSets,
    positions: &[[f64; 3]],
    members: impl Iterator<Item = usize>,
    lo: [f64; 3],
    extent: [f64; 3],
    tolerance: f64,
) {
    // Cells of twice the tolerance, so that rounding in the cell coordinates cannot move two
    // close points more than one cell apart; and at most 2⁴⁰ cells across, so that rounding
    // stays far below a cell.
    let widest = extent.iter().fold(0.0f64, |a, &b| a.max(b));
    let cell = (2.0 * tolerance).max(widest * 2f64.powi(-40));
    // `cell = 0` only when all points coincide: then one cell holds them all. `as` saturates
    // (and maps NaN from `∞ / ∞` to 0); the quotient is at most 2⁴⁰ otherwise.
    let key = |p: [f64; 3]| -> [i64; 3] {
        if cell > 0.0 {
            std::array::from_fn(|c| ((p[c] - lo[c]) / cell).floor() as i64)
        } else {
            [0; 3]
        }
    };
    let offsets: Vec<[i64; 3]> = if cell > 0.0 {
        (0..27)
            .map(|i| [i / 9 - 1, i / 3 % 3 - 1, i % 3 - 1])
            .collect()
    } else {
        vec![[0; 3]]
    };
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for v in members {
        let home = key(positions[v]);
        for offset in &offsets {
            let neighbour: [i64; 3] = std::array::from_fn(|c| home[c].saturating_add(offset[c]));
            for &u in grid.get(&neighbour).into_iter().flatten() {
                if distance(positions[u], positions[v]) <= tolerance {
                    sets.union(u, v);
                }
            }
        }
        grid.entry(home).or_default().push(v);
    }
}

#[cfg(test)]
mod tests {
    use super::clusters;

    #[test]
    fn chains_merge_to_the_smallest_index() {
        // 0 — 2 — 1 within 0.1 of each other in a chain, 0 and 1 farther apart; 3 far away.
        // The box diagonal is 1, so the tolerance is 0.1.
        let p = [
            [0.0, 0.0, 0.0],
            [0.16, 0.0, 0.0],
            [0.08, 0.0, 0.0],
            [1.0, 0.0, 0.0],
        ];
        assert_eq!(clusters(&p, &[true; 4], 0.1), [0, 0, 0, 3]);
    }

    #[test]
    fn zero_merges_equal_points_only() {
        let p = [
            [0.0, 0.0, 0.0],
            [-0.0, 0.0, 0.0],
            [1e-300, 0.0, 0.0],
            [1.0, 1.0, 1.0],
        ];
        assert_eq!(clusters(&p, &[true; 4], 0.0), [0, 0, 2, 3]);
    }

    #[test]
    fn unselected_vertices_stay_alone() {
        let p = [[0.0; 3], [0.0; 3], [1.0; 3]];
        assert_eq!(clusters(&p, &[true, false, true], 0.1), [0, 1, 2]);
    }

    #[test]
    fn huge_coordinates_do_not_overflow() {
        let p = [[f64::MAX, 0.0, 0.0], [-f64::MAX, 0.0, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(clusters(&p, &[true; 3], 1e-9), [0, 0, 0]);
        assert_eq!(clusters(&p, &[true; 3], 0.0), [0, 1, 2]);
    }
}
