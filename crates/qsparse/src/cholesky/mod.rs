//! Native supernodal sparse Cholesky `A = Pᵀ L Lᴴ P` for Hermitian positive-definite matrices
//! over any scalar with `f64` components (real, complex, quaternion).
//!
//! * **Symbolic phase** ([`SymbolicCholesky`]): a fill-reducing ordering of the `n`-node graph
//!   of the pattern (for quaternions the `n`-node graph, not the `4n` real one): faer's AMD or
//!   our nested dissection, chosen by [`FillOrdering`] (module [`ordering`]); the elimination
//!   tree and relaxed supernodes come from faer's analysis of the permuted pattern. On top of
//!   it we precompute where each input value lands in the factor and, for every supernode,
//!   the list of earlier supernodes that update it. Depends only on the pattern; reusable
//!   across refactorisations.
//! * **Numeric phase** ([`SparseCholesky`]): left-looking supernodal factorisation, on two
//!   threads over the two subtree groups when the tree splits ([`SolveThreads`]). Each
//!   supernode gathers its input columns, subtracts the updates `L_d[tail] · L_d[cols]ᴴ` of its
//!   descendants (dense `C = A Bᴴ`, see [`dense`]), then factors its dense block.
//! * **Solves**: forward and backward substitution by supernodes, one or many right-hand sides.
//!
//! Only the lower triangle (`row ≥ col`) of the input is read; the matrix is taken to be
//! Hermitian. `docs/CHOLESKY.md` describes the algorithm.

mod dense;
pub mod ordering;
mod partition;

use std::sync::Arc;

use faer::Side;
use faer::perm::PermRef;
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering, factorize_symbolic_cholesky,
};
use qscalar::Scalar;

use crate::SparseVector;
use crate::vector::{axpy, axpy_two, inner, inner_two, prefetch_head};
use crate::{CholeskyError, SparseMatrix, SymbolicStage};
use dense::{GemmWorkspace, factor_supernode, gemm_adjoint};
pub use ordering::FillOrdering;
use ordering::{Graph, NESTED_DISSECTION_MIN_UNKNOWNS, nested_dissection};
use partition::{TwoWaySplit, split_for_two_threads};

/// Marks an input entry above the diagonal, which the factorisation does not read.
const SKIPPED: usize = usize::MAX;
/// With [`SolveThreads::Automatic`], factors with at least this many stored reals are computed
/// on two threads: below it the split does not pay (set when a thread was started per
/// factorisation; with the waiting helper, 2¹⁶ left fertility's 156k-real Laplace factor at
/// 6–7 ms, faer's ordering being most of it).
const PARALLEL_FACTOR_REALS: usize = 1 << 18;

/// How the numeric factorisation and the triangular solves use threads: two threads work on
/// the two groups of subtrees of the elimination tree ([`CholeskyStats::split_columns`]), then
/// one on the supernodes above them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SolveThreads {
    /// The calling thread only.
    One,
    /// Two threads whenever the elimination tree splits well (see [`CholeskyStats::split_columns`]):
    /// the second group on the process's helper thread ([`crate::threads::join`]), or on the
    /// calling thread after the first when the helper is late or held by another computation.
    Two,
    /// Two threads when the tree splits well, the factor is large enough (at least `2¹⁸`
    /// stored reals for the factorisation, [`crate::threads::SPLIT_REALS`] for the solves),
    /// the machine has two cores, and the caller is not itself a rayon worker (a parallel batch
    /// of problems already keeps the cores busy); otherwise one.
    #[default]
    Automatic,
}

/// One descendant update of a supernode: rows `start..` of the source supernode's off-diagonal
/// pattern, the first `len` of which fall in the target supernode's columns.
#[derive(Debug, Clone, Copy)]
struct Update {
    source: usize,
    start: usize,
    len: usize,
}

/// The pattern-only part of a sparse Cholesky factorisation (ordering, supernodes, scatter plan).
#[derive(Debug, Clone)]
pub struct SymbolicCholesky {
    n: usize,
    /// The ordering used ([`FillOrdering::Automatic`] resolved).
    ordering: FillOrdering,
    /// `perm[new] = old`: row/column `new` of `P A Pᵀ` is row/column `perm[new]` of `A`.
    perm: Vec<usize>,
    /// Supernode `s` holds the columns `supernode_begin[s]..supernode_begin[s + 1]`.
    supernode_begin: Vec<usize>,
    /// Off-diagonal row indices of supernode `s`: `pattern[pattern_ptr[s]..pattern_ptr[s + 1]]`.
    pattern_ptr: Vec<usize>,
    pattern: Vec<usize>,
    /// Supernode `s` stores an `(w + pattern length) × w` column-major block at `value_ptr[s]`.
    value_ptr: Vec<usize>,
    /// Descendant updates of supernode `s`: `updates[update_ptr[s]..update_ptr[s + 1]]`.
    update_ptr: Vec<usize>,
    updates: Vec<Update>,
    /// The analysed input pattern, to reject refactorisation with another pattern.
    input_col_ptr: Vec<usize>,
    input_row_idx: Vec<usize>,
    /// For each input entry: its offset in the factor values (or `SKIPPED`), and whether it is
    /// stored conjugated (it lands in the upper triangle of `P A Pᵀ` and is mirrored).
    input_target: Vec<usize>,
    input_conj: Vec<bool>,
    /// Largest buffer a descendant update needs (entries).
    max_update_len: usize,
    /// The supernodes split between two threads for the solves, when that pays.
    split: Option<TwoWaySplit>,
}

/// The supernode-structure maps and scratch of [`SparseCholesky::solve_lower_sparse`], built
/// once per factor (`O(n)`) so that each sparse solve costs only what it touches.
#[derive(Debug, Clone)]
pub struct SparseSolveWorkspace<T> {
    /// `inverse_perm[old] = new`.
    inverse_perm: Vec<usize>,
    /// The supernode of each column (factor numbering).
    supernode_of: Vec<usize>,
    /// The parent of each supernode in the elimination tree (`None` for a root).
    parent: Vec<Option<usize>>,
    /// Dense scratch, zero between solves.
    y: Vec<T>,
    /// Supernodes reached by the current solve (all `false` between solves), and their list.
    reached: Vec<bool>,
    order: Vec<usize>,
}

/// Size and shape figures of a factorisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CholeskyStats {
    /// Dimension `n` (scalar unknowns).
    pub n: usize,
    /// Number of supernodes.
    pub supernodes: usize,
    /// Widest supernode (columns).
    pub max_supernode_width: usize,
    /// Scalar entries stored for `L` (including explicit zeros of relaxed supernodes).
    pub factor_entries: usize,
    /// Bytes of the stored factor values.
    pub factor_bytes: usize,
    /// Columns of the two threads' subtrees and of the top above them, when the solves can
    /// run on two threads (`None`: the elimination tree does not split well).
    pub split_columns: Option<[usize; 3]>,
}

impl SymbolicCholesky {
    /// Analyses the pattern of `a` (square; only the lower triangle is read): fill-reducing
    /// ordering ([`FillOrdering::Automatic`]), supernodes, and the scatter plan for numeric
    /// factorisations of matrices with this pattern.
    pub fn analyze<T: Scalar>(a: &SparseMatrix<T>) -> Result<Self, CholeskyError> {
        Self::analyze_with_ordering(a, FillOrdering::default())
    }

    /// [`Self::analyze`] with the given fill-reducing ordering.
    pub fn analyze_with_ordering<T: Scalar>(
        a: &SparseMatrix<T>,
        ordering: FillOrdering,
    ) -> Result<Self, CholeskyError> {
        let n = a.nrows();
        if a.ncols() != n {
            return Err(CholeskyError::NotSquare {
                nrows: a.nrows(),
                ncols: a.ncols(),
            });
        }
        let (ordering, supernodes) = if n == 0 {
            let ordering = match ordering {
                FillOrdering::Automatic => FillOrdering::Amd,
                explicit => explicit,
            };
            (ordering, (vec![], vec![], vec![0], vec![0], vec![]))
        } else {
            match ordering {
                FillOrdering::Automatic if n < NESTED_DISSECTION_MIN_UNKNOWNS => {
                    (FillOrdering::Amd, faer_supernodes(a, FillOrdering::Amd)?)
                }
                FillOrdering::Automatic => {
                    let amd = faer_supernodes(a, FillOrdering::Amd)?;
                    let dissection = faer_supernodes(a, FillOrdering::NestedDissection)?;
                    if factor_flops(&dissection) < factor_flops(&amd) {
                        (FillOrdering::NestedDissection, dissection)
                    } else {
                        (FillOrdering::Amd, amd)
                    }
                }
                explicit => (explicit, faer_supernodes(a, explicit)?),
            }
        };
        let (supernodes, split) = if n == 0 {
            (supernodes, None)
        } else {
            split_supernodes(supernodes)
        };
        let (perm, perm_inv, supernode_begin, pattern_ptr, pattern) = supernodes;
        let n_super = supernode_begin.len() - 1;
        let mut supernode_of = vec![0usize; n];
        let mut value_ptr = Vec::with_capacity(n_super + 1);
        value_ptr.push(0);
        for s in 0..n_super {
            let (begin, end) = (supernode_begin[s], supernode_begin[s + 1]);
            supernode_of[begin..end].fill(s);
            let rows = end - begin + pattern_ptr[s + 1] - pattern_ptr[s];
            value_ptr.push(value_ptr[s] + rows * (end - begin));
        }

        // Descendant lists: the pattern of d is sorted, so the rows falling in one target
        // supernode form a contiguous run.
        let mut per_target: Vec<Vec<Update>> = vec![Vec::new(); n_super];
        let mut max_update_len = 0;
        for d in 0..n_super {
            let rows = &pattern[pattern_ptr[d]..pattern_ptr[d + 1]];
            let mut start = 0;
            while start < rows.len() {
                let s = supernode_of[rows[start]];
                let len = rows[start..]
                    .iter()
                    .take_while(|&&r| supernode_of[r] == s)
                    .count();
                per_target[s].push(Update {
                    source: d,
                    start,
                    len,
                });
                max_update_len = max_update_len.max((rows.len() - start) * len);
                start += len;
            }
        }
        let mut update_ptr = Vec::with_capacity(n_super + 1);
        update_ptr.push(0);
        let mut updates = Vec::new();
        for list in per_target {
            updates.extend(list);
            update_ptr.push(updates.len());
        }

        // Where each input entry (lower triangle) lands in the factor block of its supernode.
        let mut input_target = vec![SKIPPED; a.nnz()];
        let mut input_conj = vec![false; a.nnz()];
        for j in 0..n {
            for k in a.col_ptr[j]..a.col_ptr[j + 1] {
                let i = a.row_idx[k];
                if i < j {
                    continue;
                }
                let (pi, pj) = (perm_inv[i], perm_inv[j]);
                let (row, col, conj) = if pi >= pj {
                    (pi, pj, false)
                } else {
                    (pj, pi, true)
                };
                let s = supernode_of[col];
                let (begin, end) = (supernode_begin[s], supernode_begin[s + 1]);
                let w = end - begin;
                let local_row = if row < end {
                    row - begin
                } else {
                    let rows = &pattern[pattern_ptr[s]..pattern_ptr[s + 1]];
                    // The factor's pattern holds every entry of the (permuted) input.
                    w + rows
                        .binary_search(&row)
                        .expect("input entry inside the factor pattern")
                };
                let m = w + pattern_ptr[s + 1] - pattern_ptr[s];
                input_target[k] = value_ptr[s] + (col - begin) * m + local_row;
                input_conj[k] = conj;
            }
        }

        Ok(Self {
            n,
            ordering,
            perm,
            supernode_begin,
            pattern_ptr,
            pattern,
            value_ptr,
            update_ptr,
            updates,
            input_col_ptr: a.col_ptr.clone(),
            input_row_idx: a.row_idx.clone(),
            input_target,
            input_conj,
            max_update_len,
            split,
        })
    }

    /// Dimension `n`.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The fill-reducing ordering used: [`FillOrdering::Amd`] or
    /// [`FillOrdering::NestedDissection`] (what [`FillOrdering::Automatic`] chose).
    pub fn ordering(&self) -> FillOrdering {
        self.ordering
    }

    /// The fill-reducing permutation, `perm()[new] = old`.
    pub fn perm(&self) -> &[usize] {
        &self.perm
    }

    /// Number of supernodes.
    pub fn supernodes(&self) -> usize {
        self.supernode_begin.len() - 1
    }

    /// Scalar entries stored for `L`.
    pub fn factor_entries(&self) -> usize {
        *self.value_ptr.last().unwrap_or(&0)
    }

    /// Where the groups of `split` end, `(first_end, second_end, c1, c2)`: supernodes
    /// `..first_end` and columns `..c1` are the first thread's, supernodes
    /// `first_end..second_end` and columns `c1..c2` the second's, the rest the top (all of it
    /// without a split).
    fn bounds(&self, split: Option<TwoWaySplit>) -> (usize, usize, usize, usize) {
        let (first_end, second_end) = split.map_or((0, 0), |p| (p.first_end, p.second_end));
        (
            first_end,
            second_end,
            self.supernode_begin[first_end],
            self.supernode_begin[second_end],
        )
    }

    fn supernode(&self, s: usize) -> (usize, usize, &[usize]) {
        let begin = self.supernode_begin[s];
        let w = self.supernode_begin[s + 1] - begin;
        (
            begin,
            w,
            &self.pattern[self.pattern_ptr[s]..self.pattern_ptr[s + 1]],
        )
    }
}

/// Runs faer's supernodal symbolic analysis on the pattern of `a` with `ordering` (AMD by
/// faer itself, nested dissection given to it as a custom permutation); returns
/// `(perm, perm_inv, supernode_begin, pattern_ptr, pattern)`.
type Supernodes = (Vec<usize>, Vec<usize>, Vec<usize>, Vec<usize>, Vec<usize>);
fn faer_supernodes<T: Scalar>(
    a: &SparseMatrix<T>,
    ordering: FillOrdering,
) -> Result<Supernodes, CholeskyError> {
    let n = a.nrows();
    let symbolic_pattern = SymbolicSparseColMatRef::new_checked(n, n, &a.col_ptr, None, &a.row_idx);
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    let custom = match ordering {
        FillOrdering::NestedDissection => {
            let forward = nested_dissection(&Graph::from_lower(n, &a.col_ptr, &a.row_idx))?;
            let mut inverse = vec![0usize; n];
            for (new, &old) in forward.iter().enumerate() {
                inverse[old] = new;
            }
            Some((forward, inverse))
        }
        FillOrdering::Amd | FillOrdering::Automatic => None,
    };
    let faer_ordering = match &custom {
        Some((forward, inverse)) => {
            SymmetricOrdering::Custom(PermRef::new_checked(forward, inverse, n))
        }
        None => SymmetricOrdering::Amd,
    };
    let symbolic =
        factorize_symbolic_cholesky(symbolic_pattern, Side::Lower, faer_ordering, params).map_err(
            |source| CholeskyError::Symbolic {
                stage: SymbolicStage::Supernodes,
                source,
            },
        )?;
    let (perm, perm_inv) = match symbolic.perm() {
        Some(p) => {
            let (fwd, inv) = p.arrays();
            (fwd.to_vec(), inv.to_vec())
        }
        None => ((0..n).collect(), (0..n).collect()),
    };
    let mut supernode_begin = vec![0];
    let mut pattern_ptr = vec![0];
    let mut pattern = Vec::new();
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sn) => {
            for s in 0..sn.n_supernodes() {
                supernode_begin.push(sn.supernode_end()[s]);
                pattern.extend_from_slice(sn.supernode(s).pattern());
                pattern_ptr.push(pattern.len());
            }
        }
        // Not expected with FORCE_SUPERNODAL; treat each column as a width-1 supernode.
        SymbolicCholeskyRaw::Simplicial(sp) => {
            for j in 0..n {
                supernode_begin.push(j + 1);
                let rows = &sp.row_idx()[sp.col_ptr()[j]..sp.col_ptr()[j + 1]];
                pattern.extend(rows.iter().copied().filter(|&r| r > j));
                pattern_ptr.push(pattern.len());
            }
        }
    }
    Ok((perm, perm_inv, supernode_begin, pattern_ptr, pattern))
}

/// Multiply-adds of a numeric factorisation with these supernodes, `Σ_j c_j²` over the columns
/// `j` with `c_j` the stored rows of column `j` (from its diagonal down): the cost model by
/// which [`FillOrdering::Automatic`] chooses.
fn factor_flops(supernodes: &Supernodes) -> f64 {
    let (_, _, begin, pattern_ptr, _) = supernodes;
    (0..begin.len() - 1)
        .map(|s| {
            let w = begin[s + 1] - begin[s];
            let below = (pattern_ptr[s + 1] - pattern_ptr[s]) as f64;
            // Column j of the block holds w − j + below rows.
            (0..w)
                .map(|j| ((w - j) as f64 + below).powi(2))
                .sum::<f64>()
        })
        .sum()
}

/// The supernode of each column and each supernode's parent in the elimination tree: the
/// supernode holding its first off-diagonal row (`None` for a root).
fn supernode_tree(
    begin: &[usize],
    pattern_ptr: &[usize],
    pattern: &[usize],
) -> (Vec<usize>, Vec<Option<usize>>) {
    let count = begin.len() - 1;
    let mut supernode_of = vec![0usize; begin[count]];
    for s in 0..count {
        supernode_of[begin[s]..begin[s + 1]].fill(s);
    }
    let parent = (0..count)
        .map(|s| {
            (pattern_ptr[s] < pattern_ptr[s + 1]).then(|| supernode_of[pattern[pattern_ptr[s]]])
        })
        .collect();
    (supernode_of, parent)
}

/// Renumbers the supernodes for two threads (module [`partition`]) when the elimination tree
/// splits well; returns the renumbered structure and the split.
fn split_supernodes(supernodes: Supernodes) -> (Supernodes, Option<TwoWaySplit>) {
    let (perm, _, begin, pattern_ptr, pattern) = &supernodes;
    let count = begin.len() - 1;
    let n = perm.len();
    let (_, parent) = supernode_tree(begin, pattern_ptr, pattern);
    let work: Vec<f64> = (0..count)
        .map(|s| {
            let w = begin[s + 1] - begin[s];
            ((w + pattern_ptr[s + 1] - pattern_ptr[s]) * w) as f64
        })
        .collect();
    let Some((order, split)) = split_for_two_threads(&parent, &work) else {
        return (supernodes, None);
    };
    let mut new_column = vec![0usize; n];
    let mut new_begin = vec![0];
    for &s in &order {
        let start = *new_begin.last().expect("non-empty");
        for (offset, old) in (begin[s]..begin[s + 1]).enumerate() {
            new_column[old] = start + offset;
        }
        new_begin.push(start + begin[s + 1] - begin[s]);
    }
    let mut new_perm = vec![0usize; n];
    for (old, &new) in new_column.iter().enumerate() {
        new_perm[new] = perm[old];
    }
    let mut new_perm_inv = vec![0usize; n];
    for (new, &original) in new_perm.iter().enumerate() {
        new_perm_inv[original] = new;
    }
    let mut new_pattern_ptr = vec![0];
    let mut new_pattern = Vec::with_capacity(pattern.len());
    for &s in &order {
        // Groups keep their relative order and ancestors lie in the same group or the top,
        // so the renumbered rows stay sorted.
        new_pattern.extend(
            pattern[pattern_ptr[s]..pattern_ptr[s + 1]]
                .iter()
                .map(|&r| new_column[r]),
        );
        new_pattern_ptr.push(new_pattern.len());
        debug_assert!(
            new_pattern[new_pattern_ptr[new_pattern_ptr.len() - 2]..]
                .windows(2)
                .all(|w| w[0] < w[1])
        );
    }
    (
        (
            new_perm,
            new_perm_inv,
            new_begin,
            new_pattern_ptr,
            new_pattern,
        ),
        Some(split),
    )
}

/// A numeric sparse Cholesky factorisation `A = Pᵀ L Lᴴ P` of a Hermitian positive-definite
/// matrix, with `L` lower triangular with a real positive diagonal and `P` the fill-reducing
/// permutation of the shared [`SymbolicCholesky`].
///
/// Writing `C = Pᵀ L`, `A = C Cᴴ`; [`SparseCholesky::solve_lower_in_place`] applies `C⁻¹` and
/// [`SparseCholesky::solve_upper_in_place`] applies `C⁻ᴴ`, the two halves an eigensolver for the
/// pencil `K x = μ A x` needs to work with the Hermitian operator `C⁻¹ K C⁻ᴴ`.
#[derive(Debug, Clone)]
pub struct SparseCholesky<T> {
    symbolic: Arc<SymbolicCholesky>,
    values: Vec<T>,
    threads: SolveThreads,
}

impl<T: Scalar<Real = f64>> SparseCholesky<T> {
    /// Symbolic analysis and numeric factorisation of `a` in one call.
    pub fn factorize(a: &SparseMatrix<T>) -> Result<Self, CholeskyError> {
        Self::factorize_with_symbolic(Arc::new(SymbolicCholesky::analyze(a)?), a)
    }

    /// Numeric factorisation of `a` reusing a symbolic analysis of the same pattern.
    pub fn factorize_with_symbolic(
        symbolic: Arc<SymbolicCholesky>,
        a: &SparseMatrix<T>,
    ) -> Result<Self, CholeskyError> {
        let mut this = Self {
            values: vec![T::zero(); symbolic.factor_entries()],
            symbolic,
            threads: SolveThreads::default(),
        };
        this.refactorize(a)?;
        Ok(this)
    }

    /// Recomputes the factor for new values of `a` with the analysed pattern, reusing storage
    /// (on two threads as set by [`Self::set_solve_threads`]).
    pub fn refactorize(&mut self, a: &SparseMatrix<T>) -> Result<(), CholeskyError> {
        let sym = &*self.symbolic;
        if a.nrows() != sym.n
            || a.ncols() != sym.n
            || a.col_ptr != sym.input_col_ptr
            || a.row_idx != sym.input_row_idx
        {
            return Err(CholeskyError::PatternMismatch);
        }
        let split = self.two_threads(PARALLEL_FACTOR_REALS);
        let values = &mut self.values;
        values.fill(T::zero());
        for (k, &v) in a.values.iter().enumerate() {
            let target = sym.input_target[k];
            if target == SKIPPED {
                continue;
            }
            if !v.is_finite() {
                let col = a.col_ptr.partition_point(|&p| p <= k) - 1;
                return Err(CholeskyError::NonFinite {
                    row: a.row_idx[k],
                    col,
                });
            }
            values[target] += if sym.input_conj[k] { v.conj() } else { v };
        }

        match split {
            Some(split) => {
                let (first_end, second_end, _, _) = sym.bounds(Some(split));
                let (low, _) = values.split_at_mut(sym.value_ptr[second_end]);
                let (first, second) = low.split_at_mut(sym.value_ptr[first_end]);
                let (first, second) = crate::threads::join(
                    || factor_range(sym, 0..first_end, first, 0),
                    || factor_range(sym, first_end..second_end, second, sym.value_ptr[first_end]),
                );
                first.and(second)?;
                factor_range(sym, second_end..sym.supernodes(), values, 0)
            }
            None => factor_range(sym, 0..sym.supernodes(), values, 0),
        }
    }

    /// Sets how later refactorisations and the solves use threads (default
    /// [`SolveThreads::Automatic`], which the first factorisation uses). The factor does not
    /// depend on it; the solutions only up to rounding: two threads add the same terms in
    /// another order.
    pub fn set_solve_threads(&mut self, threads: SolveThreads) {
        self.threads = threads;
    }

    /// The shared symbolic analysis.
    pub fn symbolic(&self) -> &Arc<SymbolicCholesky> {
        &self.symbolic
    }

    /// Size figures of the factor.
    pub fn stats(&self) -> CholeskyStats {
        let sym = &*self.symbolic;
        CholeskyStats {
            n: sym.n,
            supernodes: sym.supernodes(),
            max_supernode_width: sym
                .supernode_begin
                .windows(2)
                .map(|w| w[1] - w[0])
                .max()
                .unwrap_or(0),
            factor_entries: self.values.len(),
            factor_bytes: self.values.len() * core::mem::size_of::<T>(),
            split_columns: sym.split.map(|split| {
                let (_, _, c1, c2) = sym.bounds(Some(split));
                [c1, c2 - c1, sym.n - c2]
            }),
        }
    }

    /// Checks that `len` entries are `ncols` columns of length `n`.
    fn check_rhs(&self, len: usize, ncols: usize) -> Result<(), CholeskyError> {
        let expected = self.symbolic.n.saturating_mul(ncols);
        if len != expected {
            return Err(CholeskyError::RhsDimension {
                expected,
                found: len,
            });
        }
        Ok(())
    }

    /// Solves `A x = b` in place (`rhs` holds `b` on entry, `x` on exit).
    pub fn solve_in_place(&self, rhs: &mut [T]) -> Result<(), CholeskyError> {
        self.solve_lower_in_place(rhs)?;
        self.solve_upper_in_place(rhs)
    }

    /// Solves `A X = B` for `ncols` right-hand sides stored column-major in `rhs`, reading
    /// the factor once per half-solve for all of them.
    pub fn solve_many_in_place(&self, rhs: &mut [T], ncols: usize) -> Result<(), CholeskyError> {
        let mut work = Vec::new();
        self.solve_lower_many_in_place_with(rhs, ncols, &mut work)?;
        self.solve_upper_many_in_place_with(rhs, ncols, &mut work)
    }

    /// Returns `x` with `A x = b`.
    pub fn solve(&self, b: &[T]) -> Result<Vec<T>, CholeskyError> {
        let mut x = b.to_vec();
        self.solve_in_place(&mut x)?;
        Ok(x)
    }

    /// Applies `C⁻¹ = L⁻¹ P` in place, where `A = C Cᴴ` and `C = Pᵀ L`.
    pub fn solve_lower_in_place(&self, x: &mut [T]) -> Result<(), CholeskyError> {
        self.solve_lower_in_place_with(x, &mut Vec::new())
    }

    /// [`Self::solve_lower_in_place`] with a caller-owned workspace (resized as needed; its
    /// contents are scratch), so that repeated solves allocate nothing: an `n`-vector
    /// allocated per solve costs page faults and zeroing comparable to the solve itself.
    pub fn solve_lower_in_place_with(
        &self,
        x: &mut [T],
        work: &mut Vec<T>,
    ) -> Result<(), CholeskyError> {
        self.solve_lower_many_in_place_with(x, 1, work)
    }

    /// `X ← C⁻¹ X` for the `ncols` columns of `x` (column-major, `n × ncols`), with a
    /// caller-owned workspace. Each supernode's block is read from memory once for all
    /// columns (the other columns find it in cache), so that the memory traffic of the factor,
    /// which bounds a half-solve, is shared; every column gets exactly the result of
    /// [`Self::solve_lower_in_place_with`] (the same operations in the same order).
    pub fn solve_lower_many_in_place_with(
        &self,
        x: &mut [T],
        ncols: usize,
        work: &mut Vec<T>,
    ) -> Result<(), CholeskyError> {
        self.check_rhs(x.len(), ncols)?;
        self.forward(
            x,
            ncols,
            work,
            self.two_threads(crate::threads::SPLIT_REALS),
        );
        Ok(())
    }

    /// The workspace of [`Self::solve_lower_sparse`] for this factor's structure.
    pub fn sparse_solve_workspace(&self) -> SparseSolveWorkspace<T> {
        let sym = &*self.symbolic;
        let (n, count) = (sym.n, sym.supernodes());
        let mut inverse_perm = vec![0; n];
        for (new, &old) in sym.perm.iter().enumerate() {
            inverse_perm[old] = new;
        }
        let (supernode_of, parent) =
            supernode_tree(&sym.supernode_begin, &sym.pattern_ptr, &sym.pattern);
        SparseSolveWorkspace {
            inverse_perm,
            supernode_of,
            parent,
            y: vec![T::zero(); n],
            reached: vec![false; count],
            order: Vec::new(),
        }
    }

    /// `C⁻¹ b = L⁻¹ P b` for a sparse `b` (rows in the numbering of `A`; the result, as from
    /// [`Self::solve_lower_in_place`], in the factor's numbering). Only the supernodes on the
    /// paths from `b`'s rows to their roots of the elimination tree are touched: on a
    /// block-diagonal `A` (a mesh in pieces), a right-hand side on one piece costs that piece,
    /// not the dimension. `work` comes from [`Self::sparse_solve_workspace`] of this factor.
    pub fn solve_lower_sparse(
        &self,
        b: &SparseVector<T>,
        work: &mut SparseSolveWorkspace<T>,
    ) -> Result<SparseVector<T>, CholeskyError> {
        let sym = &*self.symbolic;
        if work.y.len() != sym.n || work.reached.len() != sym.supernodes() {
            return Err(CholeskyError::RhsDimension {
                expected: sym.n,
                found: work.y.len(),
            });
        }
        if b.values.len() != b.rows.len() {
            return Err(CholeskyError::RhsDimension {
                expected: b.rows.len(),
                found: b.values.len(),
            });
        }
        if let Some(&row) = b.rows.iter().find(|&&row| row >= sym.n) {
            return Err(CholeskyError::RhsDimension {
                expected: sym.n,
                found: row + 1,
            });
        }
        for (&old, &v) in b.rows.iter().zip(&b.values) {
            let new = work.inverse_perm[old];
            work.y[new] += v;
            let mut next = Some(work.supernode_of[new]);
            while let Some(s) = next.filter(|&s| !work.reached[s]) {
                work.reached[s] = true;
                work.order.push(s);
                next = work.parent[s];
            }
        }
        // A parent's columns follow its children's: ascending order is an elimination order.
        work.order.sort_unstable();
        let mut g = Vec::new();
        for &s in &work.order {
            let (begin, w, rows) = sym.supernode(s);
            let m = w + rows.len();
            let block = &self.values[sym.value_ptr[s]..sym.value_ptr[s] + m * w];
            g.clear();
            g.extend_from_slice(&work.y[begin..begin + w]);
            g.resize(m, T::zero());
            eliminate_forward(block, m, w, &mut g);
            work.y[begin..begin + w].copy_from_slice(&g[..w]);
            for (&row, &v) in rows.iter().zip(&g[w..]) {
                work.y[row] += v;
            }
        }
        let mut result = SparseVector::default();
        for s in work.order.drain(..) {
            work.reached[s] = false;
            let (begin, w, _) = sym.supernode(s);
            for column in begin..begin + w {
                result.rows.push(column);
                result
                    .values
                    .push(std::mem::replace(&mut work.y[column], T::zero()));
            }
        }
        Ok(result)
    }

    /// The split for two threads, if the work is to use it ([`SolveThreads`]; `threshold` is
    /// the smallest factor, in stored reals, the automatic choice splits).
    fn two_threads(&self, threshold: usize) -> Option<TwoWaySplit> {
        let use_two = match self.threads {
            SolveThreads::One => false,
            SolveThreads::Two => true,
            SolveThreads::Automatic => {
                self.values.len() * T::REAL_DIM >= threshold
                    && crate::threads::second_thread_allowed()
            }
        };
        self.symbolic.split.filter(|_| use_two)
    }

    /// `X ← L⁻¹ P X` for the `ncols` columns of `x`, on two threads with `split` (see
    /// [`partition`]): each thread substitutes through its subtrees and collects its updates
    /// of the top's unknowns in its own buffers; the buffers are added (first, then second:
    /// the result does not depend on timing) before the top is substituted.
    fn forward(&self, x: &mut [T], ncols: usize, work: &mut Vec<T>, split: Option<TwoWaySplit>) {
        let sym = &*self.symbolic;
        let n = sym.n;
        if n == 0 || ncols == 0 {
            return;
        }
        let (first_end, second_end, c1, c2) = sym.bounds(split);
        let all = sym.supernodes();
        // work = [P X | first thread's top updates | second thread's top updates], each
        // `ncols` columns; one thread needs no buffers (without a split everything is the
        // top, c2 = 0).
        let buffer_len = if split.is_some() { n - c2 } else { 0 };
        work.clear();
        for column in x.chunks_exact(n) {
            work.extend(sym.perm.iter().map(|&old| column[old]));
        }
        work.resize((n + 2 * buffer_len) * ncols, T::zero());
        let (y, buffers) = work.split_at_mut(n * ncols);
        let (first_buffer, second_buffer) = buffers.split_at_mut(buffer_len * ncols);
        let (mut lows, mut tops): (Vec<&mut [T]>, Vec<&mut [T]>) =
            y.chunks_exact_mut(n).map(|c| c.split_at_mut(c2)).unzip();
        if split.is_some() {
            let (mut firsts, mut seconds): (Vec<&mut [T]>, Vec<&mut [T]>) =
                lows.iter_mut().map(|c| c.split_at_mut(c1)).unzip();
            let mut first_tops = columns_mut(first_buffer, buffer_len, ncols);
            let mut second_tops = columns_mut(second_buffer, buffer_len, ncols);
            crate::threads::join(
                || self.forward_range(0..first_end, &mut firsts, 0, &mut first_tops, c2),
                || {
                    self.forward_range(
                        first_end..second_end,
                        &mut seconds,
                        c1,
                        &mut second_tops,
                        c2,
                    );
                },
            );
            for ((top, first), second) in tops.iter_mut().zip(&first_tops).zip(&second_tops) {
                for ((t, a), b) in top.iter_mut().zip(first.iter()).zip(second.iter()) {
                    *t += *a + *b;
                }
            }
        }
        self.forward_range(second_end..all, &mut tops, c2, &mut [], n);
        drop((lows, tops));
        x.copy_from_slice(y);
    }

    /// Forward substitution through `supernodes` (in order) on every column of `ys`, which
    /// hold the unknowns `offset..offset + len` (the columns of these supernodes); updates of
    /// unknowns `top_start..` go to `tops[c][row − top_start]` instead (`tops` may be empty
    /// when no row reaches `top_start`).
    fn forward_range(
        &self,
        supernodes: std::ops::Range<usize>,
        ys: &mut [&mut [T]],
        offset: usize,
        tops: &mut [&mut [T]],
        top_start: usize,
    ) {
        let sym = &*self.symbolic;
        let mut g = Vec::new();
        let last = supernodes.end;
        for s in supernodes {
            let (begin, w, rows) = sym.supernode(s);
            let begin = begin - offset;
            let m = w + rows.len();
            let block = &self.values[sym.value_ptr[s]..sym.value_ptr[s] + m * w];
            if s + 1 < last {
                // The next block: hardware prefetchers do not see past the current one.
                prefetch_head(&self.values[sym.value_ptr[s + 1]..sym.value_ptr[s + 2]]);
            }
            // Rows are sorted: those of this range first, then the top's.
            let inside = rows.partition_point(|&row| row < top_start);
            for (c, y) in ys.iter_mut().enumerate() {
                g.clear();
                g.extend_from_slice(&y[begin..begin + w]);
                g.resize(m, T::zero());
                eliminate_forward(block, m, w, &mut g);
                y[begin..begin + w].copy_from_slice(&g[..w]);
                let (updates_inside, updates_top) = g[w..].split_at(inside);
                for (&row, &v) in rows[..inside].iter().zip(updates_inside) {
                    y[row - offset] += v;
                }
                if !updates_top.is_empty() {
                    let top = &mut tops[c];
                    for (&row, &v) in rows[inside..].iter().zip(updates_top) {
                        top[row - top_start] += v;
                    }
                }
            }
        }
    }

    /// Applies `C⁻ᴴ = Pᵀ L⁻ᴴ` in place, where `A = C Cᴴ` and `C = Pᵀ L`.
    pub fn solve_upper_in_place(&self, x: &mut [T]) -> Result<(), CholeskyError> {
        self.solve_upper_in_place_with(x, &mut Vec::new())
    }

    /// [`Self::solve_upper_in_place`] with a caller-owned workspace, as in
    /// [`Self::solve_lower_in_place_with`].
    pub fn solve_upper_in_place_with(
        &self,
        x: &mut [T],
        work: &mut Vec<T>,
    ) -> Result<(), CholeskyError> {
        self.solve_upper_many_in_place_with(x, 1, work)
    }

    /// `X ← C⁻ᴴ X` for the `ncols` columns of `x`, each supernode's block read once for all
    /// of them, as in [`Self::solve_lower_many_in_place_with`].
    pub fn solve_upper_many_in_place_with(
        &self,
        x: &mut [T],
        ncols: usize,
        work: &mut Vec<T>,
    ) -> Result<(), CholeskyError> {
        self.check_rhs(x.len(), ncols)?;
        self.backward(
            x,
            ncols,
            work,
            self.two_threads(crate::threads::SPLIT_REALS),
        );
        Ok(())
    }

    /// `X ← Pᵀ L⁻ᴴ X` for the `ncols` columns of `x`: the top first, then on two threads
    /// with `split` the subtrees, which only read the top's (final) unknowns.
    fn backward(&self, x: &mut [T], ncols: usize, work: &mut Vec<T>, split: Option<TwoWaySplit>) {
        let sym = &*self.symbolic;
        let n = sym.n;
        if n == 0 || ncols == 0 {
            return;
        }
        let (first_end, second_end, c1, c2) = sym.bounds(split);
        let all = sym.supernodes();
        work.clear();
        work.extend_from_slice(x);
        let (mut lows, mut tops): (Vec<&mut [T]>, Vec<&mut [T]>) =
            work.chunks_exact_mut(n).map(|c| c.split_at_mut(c2)).unzip();
        self.backward_range(second_end..all, &mut tops, c2, &[], n);
        if split.is_some() {
            let (mut firsts, mut seconds): (Vec<&mut [T]>, Vec<&mut [T]>) =
                lows.iter_mut().map(|c| c.split_at_mut(c1)).unzip();
            let tops: Vec<&[T]> = tops.iter().map(|t| &**t).collect();
            crate::threads::join(
                || self.backward_range(0..first_end, &mut firsts, 0, &tops, c2),
                || self.backward_range(first_end..second_end, &mut seconds, c1, &tops, c2),
            );
        }
        drop((lows, tops));
        for (column, solved) in x.chunks_exact_mut(n).zip(work.chunks_exact(n)) {
            for (new, &old) in sym.perm.iter().enumerate() {
                column[old] = solved[new];
            }
        }
    }

    /// Backward substitution through `supernodes` (in reverse order) on every column of
    /// `ys`, which hold the unknowns `offset..offset + len`; the unknowns `top_start..` are
    /// read from `tops[c][row − top_start]` (already final; `tops` may be empty when no row
    /// reaches `top_start`).
    fn backward_range(
        &self,
        supernodes: std::ops::Range<usize>,
        ys: &mut [&mut [T]],
        offset: usize,
        tops: &[&[T]],
        top_start: usize,
    ) {
        let sym = &*self.symbolic;
        let mut g = Vec::new();
        let first = supernodes.start;
        for s in supernodes.rev() {
            let (begin, w, rows) = sym.supernode(s);
            let begin = begin - offset;
            let m = w + rows.len();
            let block = &self.values[sym.value_ptr[s]..sym.value_ptr[s] + m * w];
            if s > first {
                // The next block, which lies before this one: hardware prefetchers follow
                // ascending streams, not jumps back (measured: −25% time at 10k unknowns).
                prefetch_head(&self.values[sym.value_ptr[s - 1]..sym.value_ptr[s]]);
            }
            let inside = rows.partition_point(|&row| row < top_start);
            for (c, y) in ys.iter_mut().enumerate() {
                // g = [y_s; y[rows]] (the rows are final).
                g.clear();
                g.extend_from_slice(&y[begin..begin + w]);
                g.extend(rows[..inside].iter().map(|&row| y[row - offset]));
                if inside < rows.len() {
                    let top = tops[c];
                    g.extend(rows[inside..].iter().map(|&row| top[row - top_start]));
                }
                eliminate_backward(block, m, w, &mut g);
                y[begin..begin + w].copy_from_slice(&g[..w]);
            }
        }
    }
}

/// `ncols` consecutive slices of length `len` of `buffer` (empty ones when `len` is 0).
fn columns_mut<T>(buffer: &mut [T], len: usize, ncols: usize) -> Vec<&mut [T]> {
    if len == 0 {
        return (0..ncols).map(|_| <&mut [T]>::default()).collect();
    }
    buffer.chunks_exact_mut(len).collect()
}

/// One supernode of the forward substitution on one column: `g = [y_s; 0]` (length `m`)
/// becomes `[L₁₁⁻¹ y_s; −L₂₁ L₁₁⁻¹ y_s]`, two columns of the block at a time.
fn eliminate_forward<T: Scalar<Real = f64>>(block: &[T], m: usize, w: usize, g: &mut [T]) {
    let mut j = 0;
    while j < w {
        let column = &block[j * m..(j + 1) * m];
        g[j] = g[j].scale(1.0 / column[j].re());
        if j + 1 < w {
            let next = &block[(j + 1) * m..(j + 2) * m];
            let gj = g[j];
            g[j + 1] = (g[j + 1] - column[j + 1] * gj).scale(1.0 / next[j + 1].re());
            let (x0, x1) = (g[j], g[j + 1]);
            axpy_two(
                &mut g[j + 2..],
                &column[j + 2..],
                &next[j + 2..],
                T::zero() - x0,
                T::zero() - x1,
            );
            j += 2;
        } else {
            let gj = g[j];
            axpy(&mut g[j + 1..], &column[j + 1..], T::zero() - gj);
            j += 1;
        }
    }
}

/// One supernode of the backward substitution on one column: with `g = [y_s; y[rows]]`,
/// `y_s ← L₁₁⁻ᴴ (y_s − L₂₁ᴴ y[rows])` in `g[..w]`.
fn eliminate_backward<T: Scalar<Real = f64>>(block: &[T], m: usize, w: usize, g: &mut [T]) {
    // The product with L₂₁ᴴ has no order constraint and runs with ascending addresses, as the
    // forward solve does (hardware prefetchers follow that far better than the backward
    // column order the triangular part needs).
    let (head, below) = g.split_at_mut(w);
    let below = &*below;
    let mut j = 0;
    while j < w {
        if j + 1 < w {
            let (t0, t1) = inner_two(
                &block[j * m + w..(j + 1) * m],
                &block[(j + 1) * m + w..(j + 2) * m],
                below,
            );
            head[j] -= t0;
            head[j + 1] -= t1;
            j += 2;
        } else {
            head[j] -= inner(&block[j * m + w..(j + 1) * m], below);
            j += 1;
        }
    }
    // The triangular part, from the last column backwards, two columns at a time.
    let mut j = w;
    while j > 0 {
        if j >= 2 {
            let (first, second) = (j - 2, j - 1);
            let previous = &block[first * m..first * m + w];
            let column = &block[second * m..second * m + w];
            let (t_first, t_second) = inner_two(&previous[j..], &column[j..], &g[j..w]);
            g[second] = (g[second] - t_second).scale(1.0 / column[second].re());
            g[first] = (g[first] - t_first - previous[second].conj() * g[second])
                .scale(1.0 / previous[first].re());
            j -= 2;
        } else {
            let column = &block[..w];
            let t = inner(&column[1..], &g[1..w]);
            g[0] = (g[0] - t).scale(1.0 / column[0].re());
            j = 0;
        }
    }
}

/// Left-looking factorisation of `supernodes` (in order): each gathers the updates of its
/// descendants and factors its block. `values` holds the factor values from offset `offset`
/// on and contains the blocks of these supernodes and of all their descendants (a subtree
/// group of a [`TwoWaySplit`] holds its own descendants; the top needs everything). Groups
/// run the same operations in the same order on one thread or two, so the factor does not
/// depend on the threads.
fn factor_range<T: Scalar<Real = f64>>(
    sym: &SymbolicCholesky,
    supernodes: std::ops::Range<usize>,
    values: &mut [T],
    offset: usize,
) -> Result<(), CholeskyError> {
    let mut global_to_local = vec![0usize; sym.n];
    let mut update = vec![T::zero(); sym.max_update_len];
    let mut panel_update = Vec::new();
    let mut work = GemmWorkspace::default();
    for s in supernodes {
        let (begin, w, rows) = sym.supernode(s);
        let m = w + rows.len();
        for (r, &row) in rows.iter().enumerate() {
            global_to_local[row] = w + r;
        }
        let (done, rest) = values.split_at_mut(sym.value_ptr[s] - offset);
        let target = &mut rest[..m * w];
        for u in &sym.updates[sym.update_ptr[s]..sym.update_ptr[s + 1]] {
            let (_, wd, rows_d) = sym.supernode(u.source);
            let md = wd + rows_d.len();
            let source_begin = sym.value_ptr[u.source] - offset;
            let source = &done[source_begin..source_begin + md * wd];
            let tail = rows_d.len() - u.start;
            let first = &source[wd + u.start..];
            gemm_adjoint(
                &mut update,
                first,
                md,
                first,
                md,
                (tail, u.len, wd),
                &mut work,
            );
            for jj in 0..u.len {
                let col = rows_d[u.start + jj] - begin;
                // Rows above the diagonal (ii < jj) would land in the unused upper triangle.
                for ii in jj..tail {
                    let row = rows_d[u.start + ii];
                    let local = if row < begin + w {
                        row - begin
                    } else {
                        global_to_local[row]
                    };
                    target[col * m + local] -= update[jj * tail + ii];
                }
            }
        }
        factor_supernode(target, m, w, &mut work, &mut panel_update).map_err(
            |(local, pivot)| CholeskyError::NotPositiveDefinite {
                index: sym.perm[begin + local],
                pivot,
            },
        )?;
    }
    Ok(())
}
