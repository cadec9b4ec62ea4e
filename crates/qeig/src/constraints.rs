//! The linear constraints of an eigenproblem, stored over the entries they touch.
//!
//! The iteration runs in the orthogonal complement of a set of directions (a pencil's
//! constraints `cᴴ x = 0` become directions `C⁻¹ c` of the iteration space). On a mesh with
//! many components the directions are local: the Laplacian's kernel is one constant per
//! component, and since the factor `C` of a block-diagonal matrix is block diagonal, each
//! `C⁻¹ c` is zero outside its component. Stored as full columns, `c` directions cost `c · n`
//! memory and `c · n` work per projection (a triangle soup of 5,856 faces: 0.8 GB); stored over
//! their supports, both are the total size of the supports.
//!
//! Directions whose supports share an entry form a **group**; different groups have disjoint
//! supports, so their directions are orthogonal exactly and the projection is one pass per
//! group over its own entries. Within a group the projection `w ← w − Z (ZᴴZ)⁻¹ Zᴴ w` onto the
//! complement of its members `Z` takes one of two forms ([`Projector`]): the members kept
//! sparse with the Cholesky factor of their Gram matrix `ZᴴZ`, which costs the size of their
//! supports and `c²` per projection, or, where that is not accurate enough (members close to
//! dependent: its error grows as the square of their condition number), an orthonormal basis
//! of their span stored densely over the group's entries (`c` times the group's size). The
//! pieces of an open man-made shape are such a group: the members `C⁻¹ c` of 512 pieces of an
//! open prism touch 166 entries each, and the union, through the factor, every one.

use qscalar::Scalar;
use qsparse::{DisjointSets, Gram, SparseVector, vector};

/// Constraint directions grouped by disjoint supports, each group with the projection onto the
/// complement of its span.
#[derive(Debug, Default)]
pub(crate) struct Constraints<V> {
    groups: Vec<Group<V>>,
    /// Entries of the longest group's support (the scratch a projection needs).
    longest: usize,
    /// The dimension of the vectors.
    dimension: usize,
}

/// Directions whose supports overlap, restricted to the union of their supports.
#[derive(Debug)]
struct Group<V> {
    /// The entries the group touches, increasing (all of them for the constant of a mesh in
    /// one piece: then an ordinary vector is projected where it is, without a copy).
    rows: Vec<usize>,
    /// The projection onto the complement of the group's span.
    projector: Projector<V>,
}

/// `w ← w − Z (ZᴴZ)⁻¹ Zᴴ w` for the independent members `Z` of a group, over its rows.
#[derive(Debug)]
enum Projector<V> {
    /// Orthonormal directions `yᵢ` spanning the members, one after another (each of the
    /// group's length): `w ← w − Σ yᵢ ⟨yᵢ, w⟩` by modified Gram–Schmidt.
    Orthonormal(Vec<V>),
    /// The members as given (rows local to the group) with the Cholesky factor of their Gram
    /// matrix.
    Gram(Gram<V>),
}

/// A member whose component orthogonal to the earlier ones is below this fraction of its norm
/// adds nothing (it is in their span to rounding).
const DEPENDENT: f64 = 1e-8;

impl<V: Scalar<Real = f64>> Projector<V> {
    /// Projects `w` (ordinary, the group's rows) onto the complement of the span.
    fn project(&self, w: &mut [V]) {
        match self {
            Projector::Orthonormal(directions) => project_out(directions, w),
            Projector::Gram(gram) => gram.project(w),
        }
    }

    /// Number of independent directions.
    fn count(&self, rows: usize) -> usize {
        match self {
            Projector::Orthonormal(directions) => directions.len() / rows,
            Projector::Gram(gram) => gram.members().len(),
        }
    }

    /// Bytes of what is stored.
    fn bytes(&self) -> usize {
        match self {
            Projector::Orthonormal(directions) => directions.len() * std::mem::size_of::<V>(),
            Projector::Gram(gram) => gram.bytes(),
        }
    }
}

impl<V: Scalar<Real = f64>> Constraints<V> {
    /// The orthonormalised span of `vectors` (of dimension `dimension`, in order; a vector
    /// whose component outside the span of the previous ones is below `1e−8` of its norm
    /// adds nothing).
    pub(crate) fn new(
        dimension: usize,
        vectors: impl IntoIterator<Item = SparseVector<V>>,
    ) -> Self {
        // Two vectors are in one group when they share an entry.
        let sparse: Vec<SparseVector<V>> = vectors.into_iter().collect();
        let mut sets = DisjointSets::new(sparse.len());
        let mut owner = vec![usize::MAX; dimension];
        for (id, v) in sparse.iter().enumerate() {
            for &row in &v.rows {
                match owner[row] {
                    usize::MAX => owner[row] = id,
                    other => sets.union(id, other),
                }
            }
        }
        // Groups in the order of their first vector, each vector's in order.
        let mut group_of_root = vec![usize::MAX; sparse.len()];
        let mut members: Vec<Vec<usize>> = Vec::new();
        for id in 0..sparse.len() {
            let root = sets.find(id);
            if group_of_root[root] == usize::MAX {
                group_of_root[root] = members.len();
                members.push(Vec::new());
            }
            members[group_of_root[root]].push(id);
        }
        let groups: Vec<Group<V>> = members
            .iter()
            .filter_map(|m| group(m.iter().map(|&id| &sparse[id])))
            .collect();
        let longest = groups.iter().map(|g| g.rows.len()).max().unwrap_or(0);
        Self {
            groups,
            longest,
            dimension,
        }
    }

    /// Number of independent directions.
    pub(crate) fn count(&self) -> usize {
        (self.groups.iter())
            .map(|g| g.projector.count(g.rows.len()))
            .sum()
    }

    /// Bytes of the stored directions and their rows.
    pub(crate) fn bytes(&self) -> usize {
        (self.groups.iter())
            .map(|g| g.projector.bytes() + g.rows.len() * std::mem::size_of::<usize>())
            .sum()
    }

    /// One projection onto the complement of every group's span, for `w` in the blocked
    /// layout ([`vector::blocked_len`]).
    pub(crate) fn project(&self, w: &mut [V]) {
        if self.groups.is_empty() {
            return;
        }
        if let [group] = &self.groups[..]
            && group.rows.len() == self.dimension
            && vector::blocked_is_ordinary::<V>()
        {
            group.projector.project(&mut w[..self.dimension]);
            return;
        }
        let mut local = vec![V::zero(); self.longest];
        for group in &self.groups {
            let local = &mut local[..group.rows.len()];
            vector::gather_from_blocked(w, &group.rows, local);
            group.projector.project(local);
            vector::scatter_to_blocked(local, &group.rows, w);
        }
    }
}

/// The members, in order, over the union of their supports, with the projector of their span:
/// the Gram form for several members where it is accurate, else an orthonormal basis; `None`
/// if nothing is left.
fn group<'a, V: Scalar<Real = f64>>(
    members: impl Iterator<Item = &'a SparseVector<V>> + Clone,
) -> Option<Group<V>> {
    let mut rows: Vec<usize> = members
        .clone()
        .flat_map(|m| m.rows.iter().copied())
        .collect();
    rows.sort_unstable();
    rows.dedup();
    if rows.is_empty() {
        return None;
    }
    // Rows local to the group: both row lists increase, so walk them together.
    let local: Vec<SparseVector<V>> = members
        .map(|m| {
            let mut position = 0;
            let local_rows = (m.rows.iter())
                .map(|&row| {
                    while rows[position] != row {
                        position += 1;
                    }
                    position
                })
                .collect();
            SparseVector {
                rows: local_rows,
                values: m.values.clone(),
            }
        })
        .collect();
    // One direction is its own orthonormal basis, projected by the vectorised dense kernels
    // (the constant of a mesh in one piece: the common case, unchanged).
    let gram = (local.len() > 1).then(|| Gram::new(&local)).flatten();
    let projector = match gram {
        Some(gram) => Projector::Gram(gram),
        None => orthonormal(&local, rows.len()),
    };
    (projector.count(rows.len()) > 0).then_some(Group { rows, projector })
}

/// An orthonormal basis of the span of `members` (local rows below `len`), by two modified
/// Gram–Schmidt passes each ("twice is enough"), a member whose component orthogonal to the
/// earlier ones is below [`DEPENDENT`] of its norm dropped.
fn orthonormal<V: Scalar<Real = f64>>(members: &[SparseVector<V>], len: usize) -> Projector<V> {
    let mut directions: Vec<V> = Vec::new();
    let mut dense = vec![V::zero(); len];
    for member in members {
        dense.fill(V::zero());
        member.add_to(&mut dense, V::one());
        let before = vector::norm(&dense);
        for _ in 0..2 {
            project_out(&directions, &mut dense);
        }
        let after = vector::norm(&dense);
        if after.is_finite() && after > DEPENDENT * before && after > 0.0 {
            vector::scale(&mut dense, 1.0 / after);
            directions.extend_from_slice(&dense);
        }
    }
    Projector::Orthonormal(directions)
}

/// `w ← w − Σ yᵢ ⟨yᵢ, w⟩` for the orthonormal `yᵢ` stored one after another in `directions`
/// (each of `w`'s length), by modified Gram–Schmidt.
fn project_out<V: Scalar<Real = f64>>(directions: &[V], w: &mut [V]) {
    for y in directions.chunks_exact(w.len()) {
        let c = vector::inner(y, w);
        vector::axpy(w, y, -c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use qscalar::Quat;

    const ZERO: Quat<f64> = Quat::new(0.0, 0.0, 0.0, 0.0);

    fn quaternion(a: f64, b: f64, c: f64, d: f64) -> Quat<f64> {
        Quat::new(a, b, c, d)
    }

    fn blocked(x: &[Quat<f64>]) -> Vec<Quat<f64>> {
        let mut out = vec![ZERO; vector::blocked_len::<Quat<f64>>(x.len())];
        vector::to_blocked(x, &mut out);
        out
    }

    /// `Constraints::new(vectors)`, after checking that its projection equals the dense one
    /// `w − Y (Yᴴ w)` computed from an orthonormal basis of the same span, and leaves the
    /// entries outside every support (4 and 7) untouched.
    fn projects_like_a_dense_basis(
        n: usize,
        vectors: Vec<Vec<Quat<f64>>>,
    ) -> Constraints<Quat<f64>> {
        let constraints = Constraints::new(n, vectors.iter().map(|v| SparseVector::from_dense(v)));
        // A dense orthonormal basis of the span, by Gram–Schmidt twice.
        let mut basis: Vec<Vec<Quat<f64>>> = Vec::new();
        for mut v in vectors {
            for _ in 0..2 {
                for y in &basis {
                    let c = vector::inner(y, &v);
                    vector::axpy(&mut v, y, -c);
                }
            }
            let norm = vector::norm(&v);
            if norm > 1e-6 {
                vector::scale(&mut v, 1.0 / norm);
                basis.push(v);
            }
        }
        assert_eq!(constraints.count(), basis.len());
        let w: Vec<Quat<f64>> = (0..n)
            .map(|i| quaternion(i as f64, 1.0, -(i as f64) * 0.5, 2.0))
            .collect();
        let mut expected = w.clone();
        for y in &basis {
            let c = vector::inner(y, &w);
            vector::axpy(&mut expected, y, -c);
        }
        let mut projected = blocked(&w);
        constraints.project(&mut projected);
        let mut ordinary = vec![ZERO; n];
        vector::from_blocked(&projected, &mut ordinary);
        for (a, b) in ordinary.iter().zip(&expected) {
            assert!((*a - *b).abs2().sqrt() < 1e-12, "{a:?} against {b:?}");
        }
        assert_eq!(
            ordinary[4], w[4],
            "an entry outside every support is untouched"
        );
        assert_eq!(ordinary[7], w[7]);
        constraints
    }

    /// Directions with entries on `rows`, values from `seed`.
    fn on(n: usize, rows: &[usize], seed: f64) -> Vec<Quat<f64>> {
        let mut v = vec![ZERO; n];
        for (t, &r) in rows.iter().enumerate() {
            v[r] = quaternion(1.0 + seed + t as f64, seed - 0.5 * t as f64, 0.25, -seed);
        }
        v
    }

    /// Per-component directions (disjoint) and one overlapping two of them: three groups
    /// collapse to two. Independent directions keep the Gram form; with a dependent one
    /// added, the group is orthonormalised and the dependent direction adds nothing.
    #[test]
    fn groups_follow_shared_entries_and_project_like_a_dense_basis() {
        let n = 11;
        let mut vectors = vec![
            on(n, &[0, 1, 2], 0.0),
            on(n, &[5, 6], 1.0),
            on(n, &[8, 9, 10], 2.0),
            on(n, &[2, 3, 5], 3.0),
        ];
        let constraints = projects_like_a_dense_basis(n, vectors.clone());
        assert_eq!(constraints.groups.len(), 2);
        assert_eq!(constraints.groups[0].rows, vec![0, 1, 2, 3, 5, 6]);
        assert!(matches!(
            constraints.groups[0].projector,
            Projector::Gram(_)
        ));

        vectors.push(on(n, &[0, 1, 2], 0.0)); // dependent: adds nothing
        let constraints = projects_like_a_dense_basis(n, vectors);
        assert_eq!((constraints.groups.len(), constraints.count()), (2, 4));
        assert!(matches!(
            constraints.groups[0].projector,
            Projector::Orthonormal(_)
        ));
    }
}
