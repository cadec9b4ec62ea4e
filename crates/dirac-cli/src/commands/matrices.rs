//! `dirac matrices`: the eigenproblem `P x = λ Q x` that `dirac spectrum` solves, written as
//! Matrix Market files, so that a result can be checked with any solver.
//!
//! `--out NAME.mtx` writes three files next to each other:
//!
//! - `NAME.stiffness.mtx`: `P` (`L` for Laplace, `A = D* M_F D` for the Dirac operators, …;
//!   docs/USER_GUIDE.md has the table);
//! - `NAME.coupling.mtx`: `Q` (`M`, or `G = sym(Bᵀ M_F D)` for relative and extrinsic Dirac);
//! - `NAME.mass.mtx`: the barycentric vertex masses `Ā_p` (`n × 1`), the weights of the mass
//!   norm in which `dirac` measures eigenvectors and residuals.
//!
//! The quaternionic matrices are written in their real (`4n × 4n` symmetric) or complex
//! (`2n × 2n` Hermitian) form, lower triangle, with the convention in the files' comments.

use std::path::{Path, PathBuf};

use clap::error::ErrorKind;
use clap::{Args, ValueEnum};
use dirac::spectrum::{Eigenproblem, eigenproblem, relative_eigenproblem};

use crate::common::error::CliError;
use crate::common::files::{has_extension, tell};
use crate::common::matrix_market::{write_column, write_lower_triangle};
use crate::common::parsers::value_name;
use crate::common::preparation::PreparedMesh;
use crate::common::reference::ReferenceArgs;
use crate::common::solve_args::ProblemArgs;

/// Output and examples shown by `dirac matrices --help`.
pub const AFTER_HELP: &str = "\
Output (Matrix Market, read by scipy.io.mmread, MATLAB's mmread, Julia's MatrixMarket):
  NAME.stiffness.mtx  P, the left side of P x = λ Q x
  NAME.coupling.mtx   Q, the right side
  NAME.mass.mtx       the barycentric vertex masses (n × 1), the weights of the mass norm
  --form real (default): 4n × 4n symmetric; vertex p owns rows 4p+1 … 4p+4, a quaternion
  w + xi + yj + zk is the column (w, x, y, z) and each entry its left-multiplication matrix,
  so every eigenvalue appears four times. --form complex: 2n × 2n Hermitian, z₁ + z₂j ↦
  (z₁, conj z₂), every eigenvalue twice. Lower triangles, as the solvers read them.

Exit codes:
  0  success
  1  the mesh cannot be read or is invalid, the operator cannot be assembled on it, or a file
     cannot be written (the message names the file and the problem)
  2  usage error (bad or missing arguments, an --out that is not .mtx)

Examples:
  dirac matrices --out spot.mtx                   # built-in spot mesh, relative Dirac
  dirac matrices bunny.obj --operator laplace --normalize unit-area --out bunny.mtx";

/// Arguments of `dirac matrices`.
#[derive(Debug, Args)]
pub struct MatricesArgs {
    /// Mesh file (.obj, .off, .ply or .stl); without it, the built-in `spot` mesh.
    pub mesh: Option<PathBuf>,

    /// The eigenproblem.
    #[command(flatten)]
    pub problem: ProblemArgs,

    /// The second surface of D_{f1,f2}.
    #[command(flatten)]
    pub reference: ReferenceArgs,

    /// Output: NAME.mtx writes NAME.stiffness.mtx (P), NAME.coupling.mtx (Q) and
    /// NAME.mass.mtx (the vertex masses).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,

    /// The form of the quaternionic matrices.
    #[arg(long, value_enum, default_value_t = Form::Real)]
    pub form: Form,

    /// No messages on stderr while the mesh is read.
    #[arg(short, long)]
    pub quiet: bool,
}

/// `--form` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Form {
    /// 4n × 4n real symmetric (each quaternion its left-multiplication matrix).
    Real,
    /// 2n × 2n complex Hermitian (each quaternion its complex adjoint).
    Complex,
}

impl Form {
    /// Rows of the written matrices per vertex.
    fn rows_per_vertex(self) -> usize {
        match self {
            Form::Real => 4,
            Form::Complex => 2,
        }
    }

    /// How a quaternionic matrix is written in this form, for the files' comments.
    fn convention(self) -> &'static str {
        match self {
            Form::Real => {
                "real form: vertex p owns rows 4p+1 ... 4p+4; a quaternion w + xi + yj + zk is \
                 the column (w, x, y, z), each entry its left-multiplication matrix; every \
                 eigenvalue appears four times"
            }
            Form::Complex => {
                "complex form: vertex p owns rows 2p+1, 2p+2; a quaternion z1 + z2 j is the \
                 column (z1, conj z2), each entry its complex adjoint; every eigenvalue appears \
                 twice"
            }
        }
    }
}

/// `NAME.mtx` → `NAME.<part>.mtx`.
fn sibling(path: &Path, part: &str) -> PathBuf {
    path.with_extension(format!("{part}.mtx"))
}

/// Runs `dirac matrices`.
pub fn run(args: &MatricesArgs) -> Result<(), CliError> {
    if !has_extension(&args.out, "mtx") {
        return Err(CliError::usage(
            ErrorKind::ValueValidation,
            format!(
                "--out {}: expected a .mtx file name (NAME.mtx writes NAME.stiffness.mtx, \
                 NAME.coupling.mtx and NAME.mass.mtx)",
                args.out.display()
            ),
        ));
    }
    let operator = args.problem.operator;
    let options = args.problem.options(operator, 1);
    let (prepared, reference) = args.reference.load_with_mesh(
        &args.problem.preparation,
        args.mesh.as_deref(),
        operator,
        args.quiet,
    )?;
    let PreparedMesh { mesh, name, .. } = prepared;
    let assembled = match &reference {
        Some(reference) => relative_eigenproblem(&mesh, reference, &options),
        None => eigenproblem(&mesh, &options),
    };
    let Eigenproblem {
        stiffness,
        coupling,
        masses,
        scale,
    } = assembled.map_err(|source| CliError::Spectrum {
        mesh: name.clone(),
        source,
    })?;

    let mut heading =
        format!("dirac matrices: {name}, --operator {operator}, positions scaled by {scale:e}");
    if let Some(reference) = &args.reference.relative_to {
        heading += &format!(", relative to {}", reference.display());
    }
    if let Some(well) = options.well {
        heading += &format!(", potential well of radius {}", well.radius);
    }
    let comments = |what: &str| {
        vec![
            heading.clone(),
            what.to_string(),
            args.form.convention().to_string(),
        ]
    };
    let paths = ["stiffness", "coupling", "mass"].map(|part| sibling(&args.out, part));
    for (path, matrix, what) in [
        (
            &paths[0],
            &stiffness,
            "P, the left side of P x = lambda Q x",
        ),
        (
            &paths[1],
            &coupling,
            "Q, the right side of P x = lambda Q x",
        ),
    ] {
        match args.form {
            Form::Real => write_lower_triangle(path, &matrix.to_real_block(), &comments(what)),
            Form::Complex => {
                write_lower_triangle(path, &matrix.to_complex_adjoint(), &comments(what))
            }
        }?;
    }
    let mass_comments = [
        heading,
        "the barycentric vertex masses (one per vertex): the weights of the mass norm; \
         repeat each 4 (real form) or 2 (complex form) times for the rows of P and Q"
            .to_string(),
    ];
    write_column(&paths[2], &masses, &mass_comments)?;
    let size = args.form.rows_per_vertex() * masses.len();
    tell(format_args!(
        "wrote {}, {} ({size} × {size}, {} form) and {}",
        paths[0].display(),
        paths[1].display(),
        value_name(&args.form),
        paths[2].display()
    ));
    Ok(())
}
