//! Manifold sheets of a face list: which faces are glued along which edges, a consistent
//! orientation of each connected part, and the fans of corners that become vertices.

use std::collections::VecDeque;

use qsparse::DisjointSets;

use crate::mesh::{EdgeUse, edge_uses, same_edge};

/// The pairs of edge uses whose faces are glued along their shared edge, for faces `merged`
/// (after merging; distinct vertices) that were `input` before merging (same order).
///
/// An edge of exactly two faces glues them, whatever their orientation (orientation is fixed
/// afterwards). An edge of more faces (non-manifold) glues only faces that already shared it
/// before merging, pairing each, in face order, with the next one traversing it the other way;
/// the others keep the edge to themselves. Pairing by the input edge, not by the current
/// orientation, is what makes repair idempotent: in a repaired mesh the faces that share an
/// edge are exactly the pairs glued before.
pub(super) fn glued_edges(merged: &[[usize; 3]], input: &[[usize; 3]]) -> Vec<[EdgeUse; 2]> {
    let input_edge = |u: &EdgeUse| {
        let [a, b] = u.corners.map(|c| input[c / 3][c % 3]);
        [a.min(b), a.max(b)]
    };
    let mut glued = Vec::new();
    for group in edge_uses(merged).chunk_by(same_edge) {
        match group {
            [_] => {}
            [a, b] => glued.push([*a, *b]),
            _ => {
                let mut uses = group.to_vec();
                // Stable: faces stay in order within each input edge.
                uses.sort_by_key(input_edge);
                for sheet in uses.chunk_by(|a, b| input_edge(a) == input_edge(b)) {
                    let mut paired = vec![false; sheet.len()];
                    for i in 0..sheet.len() {
                        if paired[i] {
                            continue;
                        }
                        let partner = (i + 1..sheet.len())
                            .find(|&j| !paired[j] && sheet[j].forward() != sheet[i].forward());
                        if let Some(j) = partner {
                            paired[i] = true;
                            paired[j] = true;
                            glued.push([sheet[i], sheet[j]]);
                        }
                    }
                }
            }
        }
    }
    glued
}

/// A connected part of the glued faces that admits no consistent orientation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct NonOrientable {
    /// The part, numbered by smallest face.
    pub(crate) component: usize,
    /// A face whose orientation conflicts with its neighbours'.
    pub(crate) face: usize,
}

/// Which faces to reverse so that glued faces traverse their shared edge in opposite
/// directions. Parts (faces connected through glued edges) are visited breadth-first from their
/// smallest face; each keeps the orientation of the larger total area (ties: that of its
/// smallest face).
pub(crate) fn orientation(
    face_count: usize,
    glued: &[[EdgeUse; 2]],
    area: &[f64],
) -> Result<Vec<bool>, NonOrientable> {
    // `(neighbour, same)`: whether the two traverse their edge the same way (a conflict unless
    // exactly one of them is reversed).
    let mut neighbours = vec![Vec::new(); face_count];
    for [a, b] in glued {
        let same = a.forward() == b.forward();
        neighbours[a.face()].push((b.face(), same));
        neighbours[b.face()].push((a.face(), same));
    }
    let mut flip: Vec<Option<bool>> = vec![None; face_count];
    let mut component = 0;
    for root in 0..face_count {
        if flip[root].is_some() {
            continue;
        }
        flip[root] = Some(false);
        let mut members = vec![root];
        let mut queue = VecDeque::from([root]);
        while let Some(f) = queue.pop_front() {
            let flip_f = flip[f] == Some(true);
            for &(g, same) in &neighbours[f] {
                let wanted = flip_f ^ same;
                match flip[g] {
                    None => {
                        flip[g] = Some(wanted);
                        members.push(g);
                        queue.push_back(g);
                    }
                    Some(actual) if actual != wanted => {
                        return Err(NonOrientable { component, face: g });
                    }
                    Some(_) => {}
                }
            }
        }
        let reversed: f64 = members
            .iter()
            .filter(|&&t| flip[t] == Some(true))
            .map(|&t| area[t])
            .sum();
        let kept: f64 = members
            .iter()
            .filter(|&&t| flip[t] == Some(false))
            .map(|&t| area[t])
            .sum();
        if reversed > kept {
            for &t in &members {
                flip[t] = flip[t].map(|x| !x);
            }
        }
        component += 1;
    }
    Ok(flip.into_iter().map(|x| x == Some(true)).collect())
}

/// The fan of every corner (`3 face + local index`): corners at the same point joined through
/// glued edges, numbered in the order of their first corner.
pub(super) fn fans(face_count: usize, glued: &[[EdgeUse; 2]]) -> Vec<usize> {
    let mut sets = DisjointSets::new(3 * face_count);
    for [a, b] in glued {
        // Both uses are of one edge, so their corners at `lo` (and at `hi`) meet.
        sets.union(a.corners[0], b.corners[0]);
        sets.union(a.corners[1], b.corners[1]);
    }
    let mut number = vec![usize::MAX; 3 * face_count];
    let mut count = 0;
    (0..3 * face_count)
        .map(|c| {
            let root = sets.find(c);
            if number[root] == usize::MAX {
                number[root] = count;
                count += 1;
            }
            number[root]
        })
        .collect()
}
