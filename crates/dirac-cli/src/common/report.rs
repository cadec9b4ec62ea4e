//! What `dirac spectrum` prints and `dirac batch` writes: one [`Report`], as tables for people
//! or as one JSON object.

use std::collections::BTreeMap;
use std::io::{self, Write};
use std::time::Duration;

use dirac::spectrum::{Spectrum, SpectrumOptions};
use dirac::{Topology, TriMesh};
use serde::Serialize;

use crate::common::parsers::value_name;
use crate::common::preparation::PreparationReport;
use crate::common::solve_args::SolveArgs;

/// Everything a run reports. Field names are the JSON keys.
#[derive(Debug, Serialize)]
pub struct Report {
    /// The mesh file as given, or `spot (built-in)`.
    pub mesh: String,
    /// SHA-256 of the mesh file's bytes (`dirac batch` only: what a rerun checks before it
    /// reuses this result).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh_sha256: Option<String>,
    /// Number of vertices.
    pub vertices: usize,
    /// Number of faces.
    pub faces: usize,
    /// What `--repair` and `--component` did.
    pub preparation: Option<PreparationReport>,
    /// `dirac batch --save`: the arrays written beside the JSON, by name (`eigenvectors`,
    /// `hks`, …).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub saved: BTreeMap<String, SavedArray>,
    /// Boundary loops, components and genus (human output only).
    #[serde(skip)]
    pub topology: Topology,
    /// The operator and solver options (the keys `operator`, `tau`, `anisotropy`, `k`, `backend`,
    /// `normalize`, `well`, `include_kernel`, `flat_tolerance`, `tolerance`, `seed`,
    /// `max_restarts`, `repair`, `component`, and `relative_to` when given).
    #[serde(flatten)]
    pub settings: RunSettings,
    /// Whether all `k` eigenvalues converged (otherwise the lists hold those that did).
    pub converged: bool,
    /// Eigenvalues, signed, sorted by `|λ|`.
    pub eigenvalues: Vec<f64>,
    /// Relative residual of each eigenpair.
    pub residuals: Vec<f64>,
    /// Normwise backward error of each eigenpair (`dirac::spectrum::Spectrum::backward_errors`).
    pub backward_errors: Vec<f64>,
    /// The backward error at which a pair counts as converged whatever its relative residual
    /// (`dirac::spectrum::Spectrum::backward_error_floor`).
    pub backward_error_floor: f64,
    /// Quaternionic dimension of the operator's exactly known kernel (eigenvalue 0).
    pub kernel_dimension: usize,
    /// How the kernel was found.
    pub kernel: KernelReport,
    /// Eigensolver counts.
    pub statistics: StatisticsReport,
    /// Wall-clock times in seconds.
    pub timings: Timings,
}

/// The parts of the kernel.
#[derive(Debug, Default, Serialize)]
pub struct KernelReport {
    /// Vertices all of whose faces are flat: one dimension each.
    pub flat_vertices: usize,
    /// Connected pieces of the other vertices whose constant function is in the kernel.
    pub constants: usize,
    /// Pieces where a linear function of the second surface is in the kernel too (planes and
    /// open prisms for extrinsic Dirac).
    pub linear_functions: usize,
    /// Kernel vectors of the pieces whose rulings carry more than a constant and a linear
    /// function, in their place.
    pub ruling_functions: usize,
}

/// An array written beside a batch's JSON (`--save`).
#[derive(Debug, Serialize)]
pub struct SavedArray {
    /// Its file name, in the same directory as the JSON.
    pub file: String,
    /// Its shape.
    pub shape: Vec<usize>,
    /// The times (`hks`, `dks`) or log-energies (`wks`) of its columns; empty for eigenvectors.
    pub parameters: Vec<f64>,
}

/// The options of a run, as [`Report`] and the JSON name them.
#[derive(Debug, Serialize)]
pub struct RunSettings {
    /// The operator's name ([`dirac::spectrum::Operator::name`]: `family` for `--operator
    /// family:0.5`).
    pub operator: String,
    /// `τ` of the family, `null` for the other operators.
    pub tau: Option<f64>,
    /// `α` of the anisotropic Laplacian, `null` for the other operators.
    pub anisotropy: Option<f64>,
    /// Number of eigenvalues asked for.
    pub k: usize,
    /// The `--backend` value.
    pub backend: String,
    /// The `--normalize` value.
    pub normalize: String,
    /// The potential well, `null` without one.
    pub well: Option<WellReport>,
    /// Whether the kernel's zeros are listed among the eigenvalues.
    pub include_kernel: bool,
    /// The `--flat-tolerance`.
    pub flat_tolerance: f64,
    /// The eigensolver's `--tolerance`.
    pub tolerance: f64,
    /// The `--seed` of its start vectors.
    pub seed: u64,
    /// The `--max-restarts`.
    pub max_restarts: usize,
    /// `--repair`'s merge distance (relative to the bounding-box diagonal); `null` without
    /// `--repair`.
    pub repair: Option<f64>,
    /// The `--component` value.
    pub component: String,
    /// The `--relative-to` surface `f2` of `D_{f1,f2}`; absent without it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub relative_to: Option<String>,
}

impl RunSettings {
    /// The settings of a run with the command-line options `solve`, translated to `options`.
    pub fn new(solve: &SolveArgs, options: &SpectrumOptions) -> Self {
        let preparation = &solve.problem.preparation;
        Self {
            operator: solve.problem.operator.name().to_string(),
            tau: solve.problem.operator.tau(),
            anisotropy: solve.problem.operator.anisotropy(),
            k: solve.k,
            backend: value_name(&solve.backend),
            normalize: value_name(&solve.problem.normalize),
            well: options.well.map(|w| WellReport {
                center: w.center,
                radius: w.radius,
                steepness: w.steepness,
                height: w.height,
            }),
            include_kernel: options.include_kernel,
            flat_tolerance: options.flat_tolerance,
            tolerance: options.tolerance,
            seed: options.seed,
            max_restarts: options.max_restarts,
            repair: preparation
                .repair
                .then(|| preparation.options.repair_options().merge_distance),
            component: preparation.options.component.to_string(),
            relative_to: None,
        }
    }
}

/// The potential well's parameters.
#[derive(Debug, Serialize)]
pub struct WellReport {
    /// Centre vertex (`null`: the vertex nearest the area centroid).
    pub center: Option<usize>,
    /// Radius `β`.
    pub radius: f64,
    /// Steepness `γ`.
    pub steepness: f64,
    /// Height `c`.
    pub height: f64,
}

/// Eigensolver counts (of the last solve for the literal family).
#[derive(Debug, Default, Serialize)]
pub struct StatisticsReport {
    /// Lanczos steps.
    pub iterations: usize,
    /// Thick restarts.
    pub restarts: usize,
    /// Krylov sequences started from a fresh vector.
    pub rounds: usize,
    /// Applications of the operator.
    pub operator_applications: usize,
    /// Triangular solves.
    pub solves: usize,
    /// Basis vectors read by Gram–Schmidt (the orthogonalisation's work, independent of load).
    pub basis_columns_read: usize,
    /// Bytes of the Cholesky factor's values.
    pub factor_bytes: usize,
    /// Bytes of the Krylov basis at its largest.
    pub basis_bytes: usize,
    /// Bytes of the returned eigenvectors (`k · n` quaternions).
    pub eigenvector_bytes: usize,
}

/// Wall-clock times in seconds.
#[derive(Debug, Default, Serialize)]
pub struct Timings {
    /// Reading and validating the mesh.
    pub load: f64,
    /// Assembly and eigensolve together (everything after loading).
    pub assemble_and_solve: f64,
    /// Symbolic analysis and numeric factorisation.
    pub factorization: f64,
    /// Triangular solves.
    pub solves: f64,
    /// Gram–Schmidt and restarts.
    pub orthogonalization: f64,
}

impl Report {
    /// The report of a run on `mesh` (named `name`, of the given topology, read in `load`)
    /// before its spectrum is known: no eigenvalues yet, `converged` true.
    pub fn new(
        name: String,
        mesh: &TriMesh,
        topology: Topology,
        settings: RunSettings,
        load: Duration,
    ) -> Self {
        Self {
            mesh: name,
            mesh_sha256: None,
            preparation: None,
            saved: BTreeMap::new(),
            vertices: mesh.vertex_count(),
            faces: mesh.face_count(),
            topology,
            settings,
            converged: true,
            eigenvalues: Vec::new(),
            residuals: Vec::new(),
            backward_errors: Vec::new(),
            backward_error_floor: dirac::spectrum::ROUNDING_BACKWARD_ERROR,
            kernel_dimension: 0,
            kernel: KernelReport::default(),
            statistics: StatisticsReport::default(),
            timings: Timings {
                load: load.as_secs_f64(),
                ..Timings::default()
            },
        }
    }

    /// Copies the eigenvalues, residuals and statistics of `spectrum` into the report.
    pub fn set_spectrum(&mut self, spectrum: &Spectrum, assemble_and_solve: Duration) {
        let s = &spectrum.statistics;
        self.eigenvalues.clone_from(&spectrum.eigenvalues);
        self.residuals.clone_from(&spectrum.residuals);
        self.backward_errors.clone_from(&spectrum.backward_errors);
        self.backward_error_floor = spectrum.backward_error_floor;
        self.kernel_dimension = spectrum.kernel.dimension;
        self.kernel = KernelReport {
            flat_vertices: spectrum.kernel.flat_vertices,
            constants: spectrum.kernel.constants,
            linear_functions: spectrum.kernel.linear_functions,
            ruling_functions: spectrum.kernel.ruling_functions,
        };
        self.statistics = StatisticsReport {
            iterations: s.iterations,
            restarts: s.restarts,
            rounds: s.rounds,
            operator_applications: s.operator_applications,
            solves: s.solves,
            basis_columns_read: s.basis_columns_read,
            factor_bytes: s.factor_bytes,
            basis_bytes: s.basis_bytes,
            eigenvector_bytes: (spectrum.eigenvectors.iter())
                .map(|x| std::mem::size_of_val(x.as_slice()))
                .sum(),
        };
        self.timings.assemble_and_solve = assemble_and_solve.as_secs_f64();
        self.timings.factorization = s.factorization_time.as_secs_f64();
        self.timings.solves = s.solve_time.as_secs_f64();
        self.timings.orthogonalization = s.orthogonalization_time.as_secs_f64();
    }
}

/// Writes the report as one JSON object and a newline.
pub fn write_json(report: &Report, out: &mut impl Write) -> io::Result<()> {
    serde_json::to_writer_pretty(&mut *out, report)?;
    writeln!(out)
}

/// Writes the report as text: mesh summary, eigenvalue table, statistics and timings.
pub fn write_human(report: &Report, out: &mut impl Write) -> io::Result<()> {
    let t = &report.topology;
    let boundary = match t.boundary_loops.len() {
        0 => "closed".to_string(),
        1 => "1 boundary loop".to_string(),
        b => format!("{b} boundary loops"),
    };
    let components = match t.components.len() {
        1 => "1 component".to_string(),
        c => format!("{c} components"),
    };
    writeln!(out, "mesh        {}", report.mesh)?;
    writeln!(
        out,
        "            {} vertices, {} faces, {boundary}, {components}, genus {}",
        report.vertices,
        report.faces,
        t.genus()
    )?;
    let settings = &report.settings;
    let tau = match (settings.tau, settings.anisotropy) {
        (Some(t), _) => format!(" (tau = {t})"),
        (_, Some(a)) => format!(" (anisotropy = {a})"),
        (None, None) => String::new(),
    };
    writeln!(
        out,
        "operator    {}{tau}, k = {}, backend {}, normalize {}",
        settings.operator, settings.k, settings.backend, settings.normalize
    )?;
    if let Some(reference) = &settings.relative_to {
        writeln!(
            out,
            "relative to {reference} (D_N replaced by D_(mesh, {reference}))"
        )?;
    }
    if let Some(w) = &settings.well {
        let center = w
            .center
            .map_or_else(|| "centroid vertex".to_string(), |c| format!("vertex {c}"));
        writeln!(
            out,
            "well        radius {}, centre {center}, steepness {}, height {:e}",
            as_given(w.radius),
            as_given(w.steepness),
            w.height
        )?;
    }
    let kernel = &report.kernel;
    let plural = |count: usize, one: &str, many: &str| {
        format!("{count} {}", if count == 1 { one } else { many })
    };
    let linear = match kernel.linear_functions {
        0 => String::new(),
        count => format!(
            " + {}",
            plural(count, "linear function", "linear functions")
        ),
    };
    let linear = match kernel.ruling_functions {
        0 => linear,
        count => format!(
            "{linear} + {}",
            plural(count, "function of rulings", "functions of rulings")
        ),
    };
    writeln!(
        out,
        "kernel      dimension {}: {} + {}{linear}; {}; flat tolerance {:e}",
        report.kernel_dimension,
        plural(kernel.flat_vertices, "flat vertex", "flat vertices"),
        plural(kernel.constants, "constant", "constants"),
        if settings.include_kernel {
            "listed as eigenvalue 0"
        } else {
            "not listed (--include-kernel lists it)"
        },
        settings.flat_tolerance
    )?;
    writeln!(out)?;
    writeln!(
        out,
        "{:>5}  {:>20}  {:>9}  {:>14}",
        "index", "eigenvalue", "residual", "backward error"
    )?;
    let errors = report.residuals.iter().zip(&report.backward_errors);
    for (i, (value, (residual, backward))) in report.eigenvalues.iter().zip(errors).enumerate() {
        writeln!(
            out,
            "{i:>5}  {:>20}  {residual:>9.2e}  {backward:>14.2e}",
            significant(*value)
        )?;
    }
    if !report.converged {
        writeln!(
            out,
            "(only {} of {} eigenvalues converged)",
            report.eigenvalues.len(),
            settings.k
        )?;
    }
    writeln!(out)?;
    let s = &report.statistics;
    writeln!(
        out,
        "statistics  {} iterations, {} restarts, {} rounds, {} operator applications, {} solves",
        s.iterations, s.restarts, s.rounds, s.operator_applications, s.solves
    )?;
    let tm = &report.timings;
    writeln!(
        out,
        "timings     load {:.3} s, assemble+solve {:.3} s \
         (factorization {:.3} s, solves {:.3} s, orthogonalization {:.3} s)",
        tm.load, tm.assemble_and_solve, tm.factorization, tm.solves, tm.orthogonalization
    )
}

/// `x` as the shortest text that reads back to it: plain for moderate magnitudes, scientific
/// otherwise (a radius of `4e-107` is not printed as 107 digits).
fn as_given(x: f64) -> String {
    if x == 0.0 || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `x` with 10 significant digits: fixed-point for moderate magnitudes, scientific otherwise.
fn significant(x: f64) -> String {
    let magnitude = x.abs();
    if x == 0.0 {
        format!("{:.9}", 0.0)
    } else if (1e-4..1e9).contains(&magnitude) {
        let decimals = (9 - magnitude.log10().floor() as i32).clamp(0, 13) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.9e}")
    }
}

#[cfg(test)]
mod tests {
    use super::{as_given, significant};

    #[test]
    fn given_values_are_printed_short_and_exact() {
        for (x, text) in [
            (0.3, "0.3"),
            (4e-107, "4e-107"),
            (100.0, "100"),
            (2.5e20, "2.5e20"),
        ] {
            assert_eq!(as_given(x), text);
            assert_eq!(as_given(x).parse::<f64>(), Ok(x));
        }
    }

    #[test]
    fn significant_digits() {
        assert_eq!(significant(-19.995093148123), "-19.99509315");
        assert_eq!(significant(2.0), "2.000000000");
        assert_eq!(significant(0.0), "0.000000000");
        assert_eq!(significant(1.5e-7), "1.500000000e-7");
        assert_eq!(significant(f64::NAN), "NaN");
    }
}
