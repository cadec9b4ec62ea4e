//! Corners whose value in a kernel vector the others determine: the corners of *freed rows*
//! (docs/MATH.md, "The exact kernel").
//!
//! A row of a first-order operator `D` is a linear equation in the values at its corners. When
//! one of its corners `c` appears in no other row (with a nonzero coefficient), the row asks
//! nothing of the other vertices: whatever their values, it holds for exactly one `ψ_c`. So the
//! kernel of `D` is the kernel of `D` without that row and without `c`, each vector extended to
//! `c`. Removing the row can free another row in turn (a thin strip is freed from one end to
//! the other), and the structure of the rest tells its kernel as before: a vertex whose rows are
//! all freed or flat spans a dimension of its own, and pieces that the row joined come apart.
//! On open meshes cut from CAD solids, a jagged boundary has corners in a single boundary face;
//! joining them with their neighbours, as the row's face did, lost such dimensions.

use std::collections::{HashMap, HashSet};

use qscalar::Scalar;
use qsparse::SparseVector;

/// How one determined corner follows from two other vertices of its row:
/// `ψ_corner = base_weight ψ_base + weight (ψ_toward − ψ_base)`, weights on the left as the
/// operator's coefficients are. (A row `Σ_p e_p ψ_p = 0` of `D_{f,f2}`, whose coefficients
/// sum to zero, solved for `c` gives `ψ_c = ψ_a − e_c⁻¹ e_b (ψ_b − ψ_a)`, with `base_weight`
/// exactly 1: `ψ_a` where the others are equal, as on a constant. A row with a potential does
/// not sum to zero.)
#[derive(Debug, Clone, Copy)]
struct Determination<T> {
    corner: usize,
    base: usize,
    toward: usize,
    base_weight: T,
    weight: T,
}

/// The determined corners of a first-order operator, in the order their rows were freed: a
/// corner's base and toward vertices are never determined earlier than it.
#[derive(Debug, Clone)]
pub(super) struct DeterminedCorners<T> {
    steps: Vec<Determination<T>>,
    /// By vertex: the steps that read its value.
    readers: HashMap<usize, Vec<usize>>,
}

impl<T> Default for DeterminedCorners<T> {
    fn default() -> Self {
        Self {
            steps: Vec::new(),
            readers: HashMap::new(),
        }
    }
}

impl<T: Scalar<Real = f64>> DeterminedCorners<T> {
    /// Records that `corner` is `base_weight ψ_base + weight (ψ_toward − ψ_base)`; `base` and
    /// `toward` are not determined yet.
    pub fn push(&mut self, corner: usize, base: usize, toward: usize, base_weight: T, weight: T) {
        let step = self.steps.len();
        self.readers.entry(base).or_default().push(step);
        if toward != base {
            self.readers.entry(toward).or_default().push(step);
        }
        self.steps.push(Determination {
            corner,
            base,
            toward,
            base_weight,
            weight,
        });
    }

    /// Whether there are none (the common case: closed meshes, curved open ones without ears).
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    /// The determined corners.
    pub fn corners(&self) -> impl Iterator<Item = usize> + '_ {
        self.steps.iter().map(|s| s.corner)
    }

    /// A kernel vector `k` of the operator without the freed rows and the determined corners
    /// (none of which is among its rows), extended to the determined corners it reaches: a
    /// kernel vector of the operator itself. Costs the steps it reaches.
    pub fn extend(&self, k: SparseVector<T>) -> SparseVector<T> {
        if self.steps.is_empty() {
            return k;
        }
        let mut reached = Vec::new();
        let mut seen = HashSet::new();
        let mut frontier = k.rows.clone();
        while let Some(v) = frontier.pop() {
            for &step in self.readers.get(&v).into_iter().flatten() {
                if seen.insert(step) {
                    reached.push(step);
                    frontier.push(self.steps[step].corner);
                }
            }
        }
        if reached.is_empty() {
            return k;
        }
        // Latest first: a step reads only vertices that later steps (or `k`) determine.
        reached.sort_unstable_by(|a, b| b.cmp(a));
        let mut values: HashMap<usize, T> = k.rows.iter().copied().zip(k.values).collect();
        for step in reached {
            let Determination {
                corner,
                base,
                toward,
                base_weight,
                weight,
            } = self.steps[step];
            let at = |v| values.get(&v).copied().unwrap_or_else(T::zero);
            let value = base_weight * at(base) + weight * (at(toward) - at(base));
            if value != T::zero() {
                values.insert(corner, value);
            }
        }
        let mut entries: Vec<(usize, T)> = values.into_iter().collect();
        entries.sort_unstable_by_key(|&(row, _)| row);
        let (rows, values) = entries.into_iter().unzip();
        SparseVector { rows, values }
    }
}
