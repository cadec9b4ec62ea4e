//! Fill-reducing orderings (`qsparse::ordering`): AMD and nested dissection give a
//! permutation, the same solution as a dense Cholesky solve of the complex adjoint, and a
//! factor with `C⁻¹ A C⁻ᴴ = I` (that is `P A Pᵀ = L Lᴴ`), on structured random patterns that
//! make the dissection actually cut (grids, paths, several components, isolated vertices,
//! dense rows); nested dissection's fill is below AMD's on torus grids; `Automatic` keeps the
//! cheaper of the two.

use faer::Side;
use faer::linalg::solvers::Solve;
use num_complex::Complex;
use proptest::prelude::*;
use qscalar::{Quat, Scalar};
use qsparse::embedding::{complex_adjoint_vector, from_complex_adjoint_vector};
use qsparse::ordering::NESTED_DISSECTION_MIN_UNKNOWNS;
use qsparse::{FillOrdering, SparseCholesky, SparseMatrix, SymbolicCholesky, TripletMatrix};

use crate::common::{Lcg, assert_close, assert_whitens, unit_from_components};

/// Bound on the relative distance of two solutions (`κ(A) ≤ 3` here, see [`hpd_on_graph`]).
const AGREEMENT: f64 = 1e-11;
const ORDERINGS: [FillOrdering; 2] = [FillOrdering::Amd, FillOrdering::NestedDissection];

/// One piece of a random graph.
#[derive(Debug, Clone)]
enum Piece {
    /// A `width × height` grid, each cell with one diagonal (a triangulated grid).
    Grid(usize, usize),
    /// A path of that many vertices.
    Path(usize),
    /// That many vertices without edges (empty off-diagonal rows).
    Isolated(usize),
}

/// A random pattern: disjoint pieces, `extra` random edges between any vertices, and
/// optionally a hub joined to every vertex (a dense row). Returns `(n, edges)`.
#[derive(Debug, Clone)]
struct Pattern {
    pieces: Vec<Piece>,
    extra: usize,
    hub: bool,
    seed: u64,
}

impl Pattern {
    fn edges(&self) -> (usize, Vec<(usize, usize)>) {
        let mut n = 0;
        let mut edges = Vec::new();
        for piece in &self.pieces {
            match *piece {
                Piece::Grid(width, height) => {
                    let index = |x: usize, y: usize| n + y * width + x;
                    for y in 0..height {
                        for x in 0..width {
                            if x + 1 < width {
                                edges.push((index(x, y), index(x + 1, y)));
                            }
                            if y + 1 < height {
                                edges.push((index(x, y), index(x, y + 1)));
                            }
                            if x + 1 < width && y + 1 < height {
                                edges.push((index(x, y), index(x + 1, y + 1)));
                            }
                        }
                    }
                    n += width * height;
                }
                Piece::Path(len) => {
                    edges.extend((1..len).map(|k| (n + k - 1, n + k)));
                    n += len;
                }
                Piece::Isolated(count) => n += count,
            }
        }
        let mut rng = Lcg(self.seed);
        if n > 1 {
            for _ in 0..self.extra {
                let i = ((rng.next() + 1.0) / 2.0 * n as f64) as usize % n;
                let j = ((rng.next() + 1.0) / 2.0 * n as f64) as usize % n;
                if i != j {
                    edges.push((i, j));
                }
            }
        }
        if self.hub {
            edges.extend((0..n).map(|i| (i, n)));
            n += 1;
        }
        edges.sort_unstable_by_key(|&(i, j)| (i.min(j), i.max(j)));
        edges.dedup_by_key(|&mut (i, j)| (i.min(j), i.max(j)));
        (n, edges)
    }
}

fn piece() -> impl Strategy<Value = Piece> {
    prop_oneof![
        3 => (1..24usize, 1..24usize).prop_map(|(w, h)| Piece::Grid(w, h)),
        1 => (1..300usize).prop_map(Piece::Path),
        1 => (1..200usize).prop_map(Piece::Isolated),
    ]
}

fn pattern() -> impl Strategy<Value = Pattern> {
    (
        prop::collection::vec(piece(), 1..4),
        0..8usize,
        prop::bool::weighted(0.25),
        any::<u64>(),
    )
        .prop_map(|(pieces, extra, hub, seed)| Pattern {
            pieces,
            extra,
            hub,
            seed,
        })
}

/// `A` on the graph: `Aᵢⱼ = −rᵢⱼ/ deg_max`, `Aⱼᵢ = conj(Aᵢⱼ)` for each edge with a pseudo-random
/// unit `rᵢⱼ`, and `Aᵢᵢ = 1 + Σⱼ |Aᵢⱼ|`: Hermitian, strictly diagonally dominant, so positive
/// definite, with every eigenvalue in `[1, 1 + 2 max_i Σⱼ |Aᵢⱼ|] ⊂ [1, 3]`.
fn hpd_on_graph<T: Scalar<Real = f64>>(
    n: usize,
    edges: &[(usize, usize)],
    seed: u64,
) -> SparseMatrix<T> {
    let mut degree = vec![0usize; n];
    for &(i, j) in edges {
        degree[i] += 1;
        degree[j] += 1;
    }
    let scale = 1.0 / degree.iter().copied().max().unwrap_or(1).max(1) as f64;
    let mut rng = Lcg(seed);
    let mut t = TripletMatrix::new(n, n);
    let mut diagonal = vec![1.0; n];
    for &(i, j) in edges {
        let r: T = unit_from_components(&[rng.next(), rng.next(), rng.next(), rng.next()]);
        let value = r.scale(-scale);
        t.push(i, j, value).expect("in range, finite");
        t.push(j, i, value.conj()).expect("in range, finite");
        diagonal[i] += scale;
        diagonal[j] += scale;
    }
    for (i, &d) in diagonal.iter().enumerate() {
        t.push(i, i, T::from_real(d)).expect("in range, finite");
    }
    t.to_csc()
}

/// `A x = b` solved densely (faer's dense Cholesky of the complex adjoint `χ(A)`, which is
/// Hermitian positive definite with `A`): truth independent of any sparse ordering.
fn dense_solve<T: Scalar<Real = f64>>(a: &SparseMatrix<T>, b: &[T]) -> Vec<T> {
    let chi = a.to_complex_adjoint().to_dense();
    let rhs = complex_adjoint_vector(b);
    let rhs = faer::Mat::<faer::c64>::from_fn(rhs.len(), 1, |i, _| rhs[i]);
    let x = chi.llt(Side::Lower).expect("positive definite").solve(&rhs);
    let x: Vec<faer::c64> = (0..x.nrows()).map(|i| x[(i, 0)]).collect();
    from_complex_adjoint_vector(&x)
}

/// For both orderings: the permutation is one, the solution matches the dense solve, and
/// `C⁻¹ A C⁻ᴴ e_j = e_j` for every unit vector (`n ≤ columns_up_to`).
fn orderings_are_exact<T: Scalar<Real = f64>>(
    pattern: &Pattern,
    columns_up_to: usize,
) -> Result<(), TestCaseError> {
    let (n, edges) = pattern.edges();
    let a = hpd_on_graph::<T>(n, &edges, pattern.seed);
    let b = Lcg(pattern.seed ^ 1).vector::<T>(n);
    let expected = dense_solve(&a, &b);
    for ordering in ORDERINGS {
        let symbolic = SymbolicCholesky::analyze_with_ordering(&a, ordering).unwrap();
        prop_assert_eq!(symbolic.ordering(), ordering);
        let mut sorted = symbolic.perm().to_vec();
        sorted.sort_unstable();
        prop_assert!(
            sorted.iter().copied().eq(0..n),
            "{ordering:?}: not a permutation"
        );
        let factor = SparseCholesky::factorize_with_symbolic(symbolic.into(), &a).unwrap();
        assert_close(&factor.solve(&b).unwrap(), &expected, AGREEMENT)?;
        if n <= columns_up_to {
            assert_whitens(&factor, &a, AGREEMENT)?;
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn orderings_exact_real(pattern in pattern()) {
        orderings_are_exact::<f64>(&pattern, 400)?;
    }

    #[test]
    fn orderings_exact_complex(pattern in pattern()) {
        orderings_are_exact::<Complex<f64>>(&pattern, 0)?;
    }

    #[test]
    fn orderings_exact_quaternion(pattern in pattern()) {
        orderings_are_exact::<Quat<f64>>(&pattern, 300)?;
    }
}

/// Empty, single-vertex and edgeless matrices (the last larger than a dissection leaf, so
/// its components are batched).
#[test]
fn degenerate_patterns() {
    for pieces in [
        vec![],
        vec![Piece::Isolated(1)],
        vec![Piece::Isolated(1000)],
        vec![Piece::Grid(1, 1), Piece::Path(2)],
    ] {
        let pattern = Pattern {
            pieces,
            extra: 0,
            hub: false,
            seed: 3,
        };
        orderings_are_exact::<Quat<f64>>(&pattern, 50).unwrap();
    }
}

/// A dense row over a large grid (taken out of the dissection and numbered last).
#[test]
fn grid_with_a_dense_row() {
    let pattern = Pattern {
        pieces: vec![Piece::Grid(40, 30)],
        extra: 0,
        hub: true,
        seed: 5,
    };
    orderings_are_exact::<Quat<f64>>(&pattern, 0).unwrap();
}

/// Factor entries of `a` with `ordering`.
fn fill<T: Scalar<Real = f64>>(a: &SparseMatrix<T>, ordering: FillOrdering) -> usize {
    SymbolicCholesky::analyze_with_ordering(a, ordering)
        .unwrap()
        .factor_entries()
}

/// The graph of a `major × minor` triangulated periodic grid (a torus mesh, as
/// `dirac::generators::Torus` builds it), `(n, edges)`.
fn torus_grid(major: usize, minor: usize) -> (usize, Vec<(usize, usize)>) {
    let index = |i: usize, j: usize| (i % major) * minor + j % minor;
    let mut edges = Vec::new();
    for i in 0..major {
        for j in 0..minor {
            edges.push((index(i, j), index(i + 1, j)));
            edges.push((index(i, j), index(i, j + 1)));
            edges.push((index(i, j), index(i + 1, j + 1)));
        }
    }
    (major * minor, edges)
}

/// On triangulated torus grids (the mesh, smaller) nested dissection fills less than
/// AMD; the margin asserted is well inside the measured one (printed). On open square grids
/// and irregular meshes it does not (`docs/PERFORMANCE.md`), so nothing is claimed there.
#[test]
fn nested_dissection_fills_less_than_amd_on_torus_grids() {
    for (major, minor) in [(200, 50), (400, 100)] {
        let (n, edges) = torus_grid(major, minor);
        let a = hpd_on_graph::<f64>(n, &edges, 11);
        let (amd, nd) = (
            fill(&a, FillOrdering::Amd),
            fill(&a, FillOrdering::NestedDissection),
        );
        println!("torus grid {major}×{minor}: nested dissection {nd}, AMD {amd}");
        assert!(
            (nd as f64) < 0.95 * amd as f64,
            "torus grid {major}×{minor}: nested dissection {nd} entries, AMD {amd}"
        );
    }
}

/// `Automatic` is AMD below `NESTED_DISSECTION_MIN_UNKNOWNS`; above, it keeps exactly the
/// analysis of the cheaper ordering: nested dissection on a torus grid, AMD on an open square
/// grid (as measured, printed).
#[test]
fn automatic_keeps_the_cheaper_ordering() {
    let side = (NESTED_DISSECTION_MIN_UNKNOWNS as f64).sqrt().ceil() as usize + 1;
    let square = Pattern {
        pieces: vec![Piece::Grid(side, side)],
        extra: 0,
        hub: false,
        seed: 2,
    }
    .edges();
    let small = Pattern {
        pieces: vec![Piece::Grid(side / 2, side / 2)],
        extra: 0,
        hub: false,
        seed: 2,
    }
    .edges();
    let torus = torus_grid(2 * side, side / 2 + 1);
    for ((n, edges), expected) in [
        (small, FillOrdering::Amd),
        (square, FillOrdering::Amd),
        (torus, FillOrdering::NestedDissection),
    ] {
        let a = hpd_on_graph::<f64>(n, &edges, 4);
        let automatic = SymbolicCholesky::analyze(&a).unwrap();
        println!(
            "{n} unknowns: automatic chose {:?}; entries AMD {}, nested dissection {}",
            automatic.ordering(),
            fill(&a, FillOrdering::Amd),
            fill(&a, FillOrdering::NestedDissection)
        );
        assert_eq!(automatic.ordering(), expected, "{n} unknowns");
        let explicit = SymbolicCholesky::analyze_with_ordering(&a, expected).unwrap();
        assert_eq!(automatic.perm(), explicit.perm());
        assert_eq!(automatic.factor_entries(), explicit.factor_entries());
    }
}
