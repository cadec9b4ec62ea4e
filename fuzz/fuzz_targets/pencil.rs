//! Fuzz target: two small arbitrary quaternion matrices `K` and `S` (n ≤ 8, occasionally not
//! square or of different sizes), Hermitian-ised or not, optionally diagonally dominant, with
//! NaN, ∞, huge, slightly perturbed and moderate entries → `qeig::Pencil::new`, optional
//! arbitrary constraint vectors (through `SparseMatrix::from_dense_columns`), then `solve`
//! with the native backend, arbitrary `k`, `which` and (small) iteration limits. Every step must return `Ok` or the typed `EigError` the input
//! calls for, never panic: `NotSquare` only for a non-square operand, `NonFinite` only for a
//! non-finite value, `NotHermitian` only (and always) for an operand that is not Hermitian
//! beyond `Pencil::HERMITIAN_TOLERANCE` of its largest entry, naming an entry that differs
//! from its mirror's conjugate; a result has exactly `k` finite values in the selection's
//! order, and a positive definite `S` is factorised.

#![no_main]

use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use qeig::{EigError, Eigen, LanczosOptions, Native, Pencil, Which};
use qscalar::Quat;
use qsparse::{SparseError, SparseMatrix, TripletMatrix};

#[path = "quaternion_matrices.rs"]
mod quaternion_matrices;
use quaternion_matrices::{Q, make_dominant, push_entries, quat};

const TOLERANCE: f64 = Pencil::<Q>::HERMITIAN_TOLERANCE;

/// A generated operand and what is known about it by construction.
struct Operand {
    m: SparseMatrix<Q>,
    /// Hermitian, strictly diagonally dominant with a margin of 1 and moderate values only:
    /// certainly positive definite, also after rounding.
    positive_definite: bool,
}

/// An `nrows × ncols` matrix; Hermitian-ised with probability 3/4, then made strictly
/// diagonally dominant with probability `dominant` (out of 4).
fn operand(u: &mut Unstructured, nrows: usize, ncols: usize, dominant: u8) -> Result<Operand> {
    let n = nrows.min(ncols);
    let hermitise = u.ratio(3, 4)?;
    let mut moderate = true;
    let mut t = TripletMatrix::new(nrows, ncols);
    push_entries(u, &mut t, n, 24, hermitise, &mut moderate)?;
    let dominated =
        hermitise && nrows == ncols && u.ratio(dominant, 4)? && make_dominant(&mut t, n);
    let mut m = t.to_csc();
    let mut untouched = true;
    if m.nnz() > 0 && u.ratio(1, 8)? {
        // Plant one raw value (often NaN/∞) to check the pencil's own validation.
        let k = u.int_in_range(0..=m.nnz() - 1)?;
        let mut v = quat(u, &mut moderate)?.to_array();
        if u.arbitrary()? {
            v[u.int_in_range(0..=3)?] =
                [f64::NAN, f64::INFINITY, f64::NEG_INFINITY][u.int_in_range(0..=2)?];
        }
        m.values_mut()[k] = Quat::from_array(v);
        untouched = false;
    }
    if m.nnz() > 0 && u.ratio(1, 8)? {
        // Scale one value by 1 + ε: an off-diagonal entry of a Hermitian matrix then has a
        // defect of about ε times its size, on either side of the tolerance.
        let k = u.int_in_range(0..=m.nnz() - 1)?;
        let eps = [1e-14, 1e-12, 1e-11, 1e-9, 1e-8, 1e-6][u.int_in_range(0..=5)?];
        m.values_mut()[k] *= 1.0 + eps;
        untouched = false;
    }
    Ok(Operand {
        m,
        positive_definite: dominated && moderate && untouched,
    })
}

/// `maxᵢⱼ |Aᵢⱼ − conj(Aⱼᵢ)| / maxᵢⱼ |Aᵢⱼ|` of a square matrix with finite values (0 for the
/// zero matrix), computed on the values divided by their largest component so that neither
/// norm overflows or underflows whatever the scale.
fn relative_defect(a: &SparseMatrix<Q>) -> f64 {
    let scale = (a.values().iter())
        .flat_map(|v| v.to_array())
        .fold(0.0f64, |m, c| m.max(c.abs()));
    if scale == 0.0 {
        return 0.0;
    }
    let scaled = |i, j| Quat::from_array(a.get(i, j).to_array().map(|c| c / scale));
    let (mut defect, mut largest) = (0.0f64, 0.0f64);
    for i in 0..a.nrows() {
        for j in 0..a.ncols() {
            largest = largest.max(scaled(i, j).norm());
            defect = defect.max((scaled(i, j) - scaled(j, i).conj()).norm());
        }
    }
    defect / largest
}

/// What `Pencil::new` must decide about one operand.
struct Facts {
    square: bool,
    finite: bool,
    /// [`relative_defect`] when square and finite, else NaN.
    defect: f64,
}

impl Facts {
    fn of(a: &SparseMatrix<Q>) -> Self {
        let square = a.nrows() == a.ncols();
        let finite = a.values().iter().all(|v| v.is_finite());
        let defect = if square && finite {
            relative_defect(a)
        } else {
            f64::NAN
        };
        Self {
            square,
            finite,
            defect,
        }
    }

    /// Must be refused (a margin of 4 around the tolerance for rounding).
    fn invalid(&self) -> bool {
        !self.square || !self.finite || self.defect > 4.0 * TOLERANCE
    }

    /// Must be accepted.
    fn valid(&self) -> bool {
        self.square && self.finite && self.defect < TOLERANCE / 4.0
    }
}

fn score(which: Which, value: f64) -> f64 {
    match which {
        Which::LargestMagnitude => value.abs(),
        Which::LargestAlgebraic => value,
        Which::SmallestAlgebraic => -value,
    }
}

/// Pairs in the selection's order, with finite values and `S`-normalised (hence finite)
/// vectors of length `n`.
fn check_pairs(eig: &Eigen<Q>, n: usize, which: Which) {
    assert_eq!(eig.vectors.len(), eig.values.len());
    assert_eq!(eig.residuals.len(), eig.values.len());
    assert!(
        eig.values.iter().all(|v| v.is_finite()),
        "non-finite eigenvalue in {:?}",
        eig.values
    );
    assert!(
        (eig.values.windows(2)).all(|w| score(which, w[0]) >= score(which, w[1])),
        "values not in the order of {which:?}: {:?}",
        eig.values
    );
    for x in &eig.vectors {
        assert_eq!(x.len(), n);
        assert!(
            x.iter().all(|v| v.is_finite()),
            "non-finite eigenvector {x:?}"
        );
    }
}

/// A comparable summary of an outcome (values bit for bit, or the error's message and the
/// values of its partial result).
fn summary(outcome: &std::result::Result<Eigen<Q>, EigError<Q>>) -> String {
    let bits = |values: &[f64]| values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    match outcome {
        Ok(eig) => format!("Ok {:?}", bits(&eig.values)),
        Err(EigError::NotConverged { partial, .. }) => {
            format!("NotConverged {:?}", bits(&partial.values))
        }
        Err(e) => format!("Err {e}"),
    }
}

fn run(u: &mut Unstructured) -> Result<()> {
    let n = u.int_in_range(0..=8usize)?;
    let k_rows = match u.int_in_range(0..=31u8)? {
        0 => n + 1,
        1 => n.saturating_sub(1),
        _ => n,
    };
    let k_cols = if u.ratio(1, 16)? { k_rows + 1 } else { k_rows };
    let s_cols = if u.ratio(1, 16)? { n + 1 } else { n };
    let k = operand(u, k_rows, k_cols, 1)?.m;
    let s_operand = operand(u, n, s_cols, 3)?;
    let s = &s_operand.m;

    let (k_facts, s_facts) = (Facts::of(&k), Facts::of(s));
    let operand_named = |which: &str| match which {
        "K" => (&k, &k_facts),
        "S" => (s, &s_facts),
        _ => panic!("unknown operand {which:?}"),
    };
    let pencil = Pencil::new(&k, s);
    match &pencil {
        Ok(_) => assert!(
            !k_facts.invalid() && !s_facts.invalid() && k.nrows() == s.nrows(),
            "accepted K {}×{} (finite {}, relative defect {:e}), S {}×{} (finite {}, relative \
             defect {:e})",
            k.nrows(),
            k.ncols(),
            k_facts.finite,
            k_facts.defect,
            s.nrows(),
            s.ncols(),
            s_facts.finite,
            s_facts.defect,
        ),
        Err(EigError::NotSquare {
            which,
            nrows,
            ncols,
        }) => {
            let (m, _) = operand_named(which);
            assert!(nrows != ncols && (m.nrows(), m.ncols()) == (*nrows, *ncols));
        }
        Err(EigError::NonFinite(which)) => {
            let (_, facts) = operand_named(which);
            assert!(!facts.finite, "{which} reported non-finite");
        }
        Err(EigError::NotHermitian {
            which, row, col, ..
        }) => {
            let (m, facts) = operand_named(which);
            assert!(facts.square && facts.finite && *row < m.nrows() && *col < m.nrows());
            assert!(
                m.get(*row, *col) != m.get(*col, *row).conj(),
                "{which}({row}, {col}) reported as non-Hermitian"
            );
            assert!(
                !facts.valid(),
                "{which} refused with relative defect {:e}",
                facts.defect
            );
        }
        Err(EigError::DimensionMismatch {
            expected, found, ..
        }) => {
            assert!(k_facts.square && s_facts.square);
            assert!(*expected == s.nrows() && *found == k.nrows() && expected != found);
        }
        Err(e) => panic!("unexpected error from Pencil::new: {e}"),
    }
    if k_facts.valid() && s_facts.valid() && k.nrows() == s.nrows() {
        assert!(pencil.is_ok(), "refused a valid pencil: {:?}", pencil.err());
    }
    let Ok(mut pencil) = pencil else {
        return Ok(());
    };

    let mut constraints = 0;
    if u.ratio(1, 3)? {
        // Dense columns of `rows` entries (occasionally not the pencil's size, occasionally
        // one of another length) → `SparseMatrix::from_dense_columns` → `with_constraints`.
        let rows = match u.int_in_range(0..=15u8)? {
            0 => n + 1,
            1 => n.saturating_sub(1),
            _ => n,
        };
        let mut vectors = Vec::new();
        for _ in 0..u.int_in_range(0..=3)? {
            let len = if u.ratio(1, 16)? { rows + 1 } else { rows };
            let mut ignored = true;
            let c = (0..len)
                .map(|_| quat(u, &mut ignored))
                .collect::<Result<Vec<_>>>()?;
            vectors.push(c);
        }
        let wrong_length = vectors.iter().any(|c| c.len() != rows);
        let non_finite = vectors.iter().flatten().any(|v| !v.is_finite());
        let matrix = match SparseMatrix::from_dense_columns(rows, &vectors) {
            Ok(matrix) => matrix,
            Err(SparseError::DimensionMismatch {
                expected, found, ..
            }) => {
                assert!(wrong_length && expected == rows && found != rows);
                return Ok(());
            }
            Err(SparseError::NonFinite { row, col }) => {
                assert!(!vectors[col][row].is_finite(), "refused a finite entry");
                return Ok(());
            }
            Err(e) => panic!("unexpected error from from_dense_columns: {e}"),
        };
        assert!(!wrong_length && !non_finite, "accepted columns {vectors:?}");
        for (j, column) in vectors.iter().enumerate() {
            for (i, &v) in column.iter().enumerate() {
                assert_eq!(matrix.get(i, j), v, "entry ({i}, {j})");
            }
        }
        let count = vectors.len();
        pencil = match pencil.with_constraints(matrix) {
            Ok(pencil) => {
                assert_eq!(rows, n, "accepted constraints of {rows} rows");
                constraints = count;
                pencil
            }
            Err(EigError::DimensionMismatch {
                expected, found, ..
            }) => {
                assert!(expected == n && found == rows && rows != n);
                Pencil::new(&k, s).expect("accepted before")
            }
            Err(e) => panic!("unexpected error from with_constraints: {e}"),
        };
    }

    let which = match u.int_in_range(0..=2u8)? {
        0 => Which::LargestMagnitude,
        1 => Which::LargestAlgebraic,
        _ => Which::SmallestAlgebraic,
    };
    let mut options = LanczosOptions::new(u.int_in_range(0..=n + 1)?, which);
    options.tolerance = match u.int_in_range(0..=15u8)? {
        0 => f64::from_bits(u.arbitrary()?),
        1 => 0.0,
        2 => 1e-3,
        3 => 0.5,
        _ => 1e-10,
    };
    options.max_dim = if u.arbitrary()? {
        0
    } else {
        u.int_in_range(0..=n + 2)?
    };
    // Small limits keep every input fast; 0 is refused as an invalid option.
    options.max_restarts = u.int_in_range(0..=20)?;
    options.max_operator_applications = u.int_in_range(0..=200)?;
    options.seed = u.arbitrary()?;
    if u.ratio(1, 8)? {
        options.memory_limit = Some(u.int_in_range(0..=8192)?);
    }
    let options_valid = options.tolerance > 0.0
        && options.tolerance < 1.0
        && options.max_restarts > 0
        && options.max_operator_applications > 0;
    let available = n.saturating_sub(constraints);
    let count_valid = options.k > 0 && options.k <= available;

    let outcome = pencil.solve(&Native, &options);
    match &outcome {
        Ok(eig) => {
            assert_eq!(eig.values.len(), options.k);
            check_pairs(eig, n, which);
        }
        Err(EigError::NotConverged { wanted, partial }) => {
            assert_eq!(*wanted, options.k);
            assert!(partial.values.len() <= options.k);
            check_pairs(partial, n, which);
        }
        Err(EigError::InvalidOption(_)) => assert!(!options_valid),
        Err(EigError::InvalidCount {
            k: count,
            available: a,
        }) => {
            assert_eq!((*count, *a), (options.k, available));
            assert!(!count_valid);
        }
        Err(EigError::Factorization(e)) => assert!(
            !s_operand.positive_definite,
            "factorisation of a diagonally dominant S failed: {e}"
        ),
        Err(EigError::BasisTooLarge(_)) => assert!(options.memory_limit.is_some()),
        Err(EigError::DenseEigen(_)) => {}
        Err(e) => panic!("unexpected error from solve: {e}"),
    }
    if !options_valid || !count_valid {
        assert!(
            matches!(
                outcome,
                Err(EigError::InvalidOption(_) | EigError::InvalidCount { .. })
            ),
            "k = {}, available {available}, options {options:?}: {}",
            options.k,
            summary(&outcome)
        );
    }
    if u.ratio(1, 4)? {
        // Runs are deterministic for a given seed.
        let again = pencil.solve(&Native, &options);
        assert_eq!(summary(&outcome), summary(&again));
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
