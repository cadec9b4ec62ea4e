//! `dirac batch`: the spectra of many meshes, in parallel and resumable.
//!
//! Input: a directory (every `.obj`, `.off` and `.ply` file directly inside it, sorted by
//! name) or a text file listing mesh paths, one per line (`#` starts a comment, blank lines are
//! skipped, relative paths are relative to the list's directory).
//!
//! Output, in `--out DIR` (created if missing):
//!
//! - `<mesh file name>.json` per mesh: the object `dirac spectrum --json` prints. It is written
//!   to a temporary file and renamed, so a JSON that exists is whole. A rerun skips every mesh
//!   whose JSON is *complete*: it parses, reports `"converged": true` with `k` eigenvalues, its
//!   `mesh_sha256` (the SHA-256 of the mesh file's bytes, recorded by `batch`) is the file's
//!   now, and every setting that changes the result (`operator`, `tau`, `k`, `backend`,
//!   `normalize`, `well`, `include_kernel`, `flat_tolerance`, `tolerance`, `seed`,
//!   `max_restarts`) equals this run's. Anything else is computed again (`--force`:
//!   everything).
//! - `summary.csv`, rewritten at the end of every run, one row per mesh in input order:
//!   `mesh, status, vertices, faces, converged, seconds, error, lambda_0 … lambda_{k−1}` with
//!   status `ok`, `skipped` (complete from an earlier run), `not-converged` (the JSON holds the
//!   converged part) or `failed` (`error` says why; the other fields may be empty).
//!
//! Meshes run in parallel on `--jobs` threads (default: the available parallelism); each solve
//! itself is sequential (every faer call in `qeig` runs with `Par::Seq`), so `--jobs N` keeps N
//! cores busy without oversubscription. A failing mesh is reported on stderr and in the summary
//! and does not stop the others.

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::num::NonZeroUsize;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use dirac::io::Format;
use dirac::spectrum::SpectrumOptions;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use serde_json::Value;
use sha2::{Digest, Sha256};

use crate::common::error::CliError;
use crate::common::parsers::positive_count;
use crate::common::report::{Report, RunSettings, write_json};
use crate::common::solve::{load_mesh, solve};
use crate::common::solve_args::SolveArgs;

/// Name of the summary table in the output directory.
pub const SUMMARY: &str = "summary.csv";

/// Exit codes and examples shown by `dirac batch --help`.
pub const AFTER_HELP: &str = "\
Output in --out DIR: <mesh file name>.json per mesh (the object of `dirac spectrum --json`)
and summary.csv (mesh, status, vertices, faces, converged, seconds, error, lambda_0 ...).
A rerun skips meshes whose JSON is complete (converged, same mesh file contents by SHA-256,
same operator and options).

Exit codes:
  0  every mesh is complete (computed now or skipped as finished earlier)
  1  the batch cannot run: unreadable input, no meshes, colliding file names, or an
     unwritable output directory or summary
  2  usage error (bad or missing arguments)
  4  some meshes failed or did not converge (reported on stderr and in summary.csv);
     the others are complete

Examples:
  dirac batch meshes/ -k 30 --out spectra/
  dirac batch list.txt --operator laplace --normalize unit-area -k 50 --jobs 2 --out spectra/";

/// Arguments of `dirac batch`.
#[derive(Debug, Args)]
pub struct BatchArgs {
    /// A directory (all .obj, .off and .ply files in it) or a text file of mesh paths, one per
    /// line (`#` comments; relative to the list's directory).
    pub input: PathBuf,

    /// Operator and eigensolver.
    #[command(flatten)]
    pub solve: SolveArgs,

    /// Output directory: one JSON per mesh and summary.csv (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,

    /// Meshes solved at the same time [default: available parallelism].
    #[arg(short, long, value_name = "N", value_parser = positive_count)]
    pub jobs: Option<usize>,

    /// Recompute meshes whose output is already complete.
    #[arg(long)]
    pub force: bool,

    /// No progress bar on stderr (errors are still reported).
    #[arg(short, long)]
    pub quiet: bool,
}

/// How one mesh went.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Status {
    Ok,
    Skipped,
    NotConverged,
    Failed,
}

impl Status {
    fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Skipped => "skipped",
            Status::NotConverged => "not-converged",
            Status::Failed => "failed",
        }
    }
}

/// One row of the summary; `error` names the file it is about.
#[derive(Debug)]
struct Row {
    mesh: PathBuf,
    status: Status,
    vertices: Option<u64>,
    faces: Option<u64>,
    seconds: Option<f64>,
    error: String,
    eigenvalues: Vec<f64>,
}

impl Row {
    fn failed(mesh: &Path, error: String) -> Self {
        Self {
            mesh: mesh.to_path_buf(),
            status: Status::Failed,
            vertices: None,
            faces: None,
            seconds: None,
            error,
            eigenvalues: Vec::new(),
        }
    }
}

/// The meshes named by `input`: a directory's mesh files sorted by name, or a list's lines.
fn inputs(input: &Path) -> Result<Vec<PathBuf>, CliError> {
    let io_error = |source| CliError::Io {
        path: input.to_path_buf(),
        source,
    };
    let meshes = if input.is_dir() {
        let mut meshes = Vec::new();
        for entry in fs::read_dir(input).map_err(io_error)? {
            let path = entry.map_err(io_error)?.path();
            if path.is_file() && Format::from_path(&path).is_some() {
                meshes.push(path);
            }
        }
        meshes.sort();
        meshes
    } else {
        let text = fs::read_to_string(input).map_err(io_error)?;
        let base = input.parent().unwrap_or(Path::new(""));
        text.lines()
            .map(|line| line.split('#').next().unwrap_or("").trim())
            .filter(|line| !line.is_empty())
            .map(|line| base.join(line))
            .collect()
    };
    if meshes.is_empty() {
        return Err(CliError::NoMeshes(input.to_path_buf()));
    }
    for (i, first) in meshes.iter().enumerate() {
        if let Some(second) = meshes[i + 1..]
            .iter()
            .find(|other| other.file_name() == first.file_name())
        {
            return Err(CliError::DuplicateName {
                first: first.clone(),
                second: second.clone(),
            });
        }
    }
    Ok(meshes)
}

/// `DIR/<file name of mesh>.json`.
fn json_path(out: &Path, mesh: &Path) -> PathBuf {
    let mut name = mesh.file_name().unwrap_or(mesh.as_os_str()).to_os_string();
    name.push(".json");
    out.join(name)
}

/// The SHA-256 of a file's bytes, in hexadecimal.
fn file_sha256(path: &Path) -> io::Result<String> {
    let digest = Sha256::digest(fs::read(path)?);
    Ok(digest.iter().map(|byte| format!("{byte:02x}")).collect())
}

/// The summary row of a complete earlier result, or `None` when `json` is missing,
/// incomplete, of another mesh (another content hash) or from other settings.
fn finished(json: &Path, mesh: &Path, digest: &str, settings: &Value, k: usize) -> Option<Row> {
    let report: Value = serde_json::from_str(&fs::read_to_string(json).ok()?).ok()?;
    if report["mesh_sha256"].as_str() != Some(digest) {
        return None;
    }
    let same_settings = settings
        .as_object()?
        .iter()
        .all(|(key, value)| report.get(key) == Some(value));
    let eigenvalues: Vec<f64> = report["eigenvalues"]
        .as_array()?
        .iter()
        .map(Value::as_f64)
        .collect::<Option<_>>()?;
    let timings = &report["timings"];
    (same_settings && report["converged"] == Value::Bool(true) && eigenvalues.len() == k).then(
        || Row {
            mesh: mesh.to_path_buf(),
            status: Status::Skipped,
            vertices: report["vertices"].as_u64(),
            faces: report["faces"].as_u64(),
            seconds: Some(
                timings["load"].as_f64().unwrap_or(0.0)
                    + timings["assemble_and_solve"].as_f64().unwrap_or(0.0),
            ),
            error: String::new(),
            eigenvalues,
        },
    )
}

/// Writes `report` to `path` through a temporary file, so that `path` is never partial.
fn write_report(report: &Report, path: &Path) -> io::Result<()> {
    let mut partial = path.as_os_str().to_os_string();
    partial.push(".partial");
    let partial = PathBuf::from(partial);
    let mut file = BufWriter::new(File::create(&partial)?);
    write_json(report, &mut file)?;
    file.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    fs::rename(&partial, path)
}

/// Computes (or skips) one mesh.
fn process(mesh_path: &Path, args: &BatchArgs, options: &SpectrumOptions, settings: &Value) -> Row {
    let json = json_path(&args.out, mesh_path);
    let start = Instant::now();
    let digest = match file_sha256(mesh_path) {
        Ok(digest) => digest,
        Err(error) => return Row::failed(mesh_path, format!("{}: {error}", mesh_path.display())),
    };
    if !args.force
        && let Some(row) = finished(&json, mesh_path, &digest, settings, options.k)
    {
        return row;
    }
    let (mesh, name) = match load_mesh(Some(mesh_path)) {
        Ok(loaded) => loaded,
        Err(error) => return Row::failed(mesh_path, error.to_string()),
    };
    let mut report = Report::new(
        name,
        &mesh,
        RunSettings::new(&args.solve, options),
        start.elapsed(),
    );
    report.mesh_sha256 = Some(digest);
    let mut row = Row {
        vertices: Some(mesh.vertex_count() as u64),
        faces: Some(mesh.face_count() as u64),
        ..Row::failed(mesh_path, String::new())
    };
    match solve(&mesh, &report.mesh, options, true) {
        Ok(solved) => {
            report.set_spectrum(&solved.spectrum, solved.elapsed);
            report.converged = solved.converged;
            row.status = if solved.converged {
                Status::Ok
            } else {
                row.error = format!(
                    "{}: the eigensolver converged only {} of {} eigenvalues",
                    mesh_path.display(),
                    solved.spectrum.eigenvalues.len(),
                    options.k
                );
                Status::NotConverged
            };
            row.eigenvalues = solved.spectrum.eigenvalues;
            if let Err(error) = write_report(&report, &json) {
                row.status = Status::Failed;
                row.error = format!("{}: {error}", json.display());
            }
        }
        Err(error) => row.error = error.to_string(),
    }
    row.seconds = Some(start.elapsed().as_secs_f64());
    row
}

/// `field` quoted for CSV when it holds a comma, quote or line break.
fn csv_field(field: &str) -> String {
    if field.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_string()
    }
}

/// Writes the summary table.
fn write_summary(rows: &[Row], k: usize, out: &mut impl Write) -> io::Result<()> {
    let mut header: Vec<String> = [
        "mesh",
        "status",
        "vertices",
        "faces",
        "converged",
        "seconds",
        "error",
    ]
    .map(String::from)
    .to_vec();
    // `k` eigenvalues exist only on meshes with at least `k` vertices: no more columns than
    // the largest mesh can fill (a huge `-k` fails on every mesh, not here).
    let largest = rows
        .iter()
        .filter_map(|row| row.vertices)
        .max()
        .unwrap_or(0);
    let columns = k.min(usize::try_from(largest).unwrap_or(usize::MAX));
    header.extend((0..columns).map(|i| format!("lambda_{i}")));
    writeln!(out, "{}", header.join(","))?;
    let optional = |x: Option<String>| x.unwrap_or_default();
    for row in rows {
        let mut fields = vec![
            csv_field(&row.mesh.display().to_string()),
            row.status.name().to_string(),
            optional(row.vertices.map(|v| v.to_string())),
            optional(row.faces.map(|f| f.to_string())),
            (matches!(row.status, Status::Ok | Status::Skipped)).to_string(),
            optional(row.seconds.map(|s| format!("{s:.3}"))),
            csv_field(&row.error),
        ];
        fields.extend(row.eigenvalues.iter().map(f64::to_string));
        fields.resize(header.len(), String::new());
        writeln!(out, "{}", fields.join(","))?;
    }
    out.flush()
}

/// The progress bar over meshes: hidden with `quiet` or when stderr is not a terminal.
fn progress_bar(count: usize, quiet: bool) -> ProgressBar {
    use std::io::IsTerminal;
    if quiet || !io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(count as u64), ProgressDrawTarget::stderr());
    if let Ok(style) =
        ProgressStyle::with_template("{elapsed:>4} [{bar:30}] {pos}/{len} meshes {wide_msg}")
    {
        bar.set_style(style);
    }
    bar
}

/// Runs `dirac batch`: `Ok` when every mesh is complete (computed now or earlier),
/// [`CliError::SomeFailed`] (exit code 4) when some mesh failed or did not converge; errors
/// that stop the whole batch (exit code 1) otherwise.
pub fn run(args: &BatchArgs) -> Result<(), CliError> {
    let options = args.solve.options();
    let meshes = inputs(&args.input)?;
    fs::create_dir_all(&args.out).map_err(|source| CliError::Io {
        path: args.out.clone(),
        source,
    })?;
    let settings = serde_json::to_value(RunSettings::new(&args.solve, &options))
        .expect("the settings serialise to a JSON object");
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, NonZeroUsize::get));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|error| CliError::Threads {
            jobs,
            message: error.to_string(),
        })?;

    let bar = progress_bar(meshes.len(), args.quiet);
    let rows: Vec<Row> = pool.install(|| {
        meshes
            .par_iter()
            .map(|mesh| {
                let row = catch_unwind(AssertUnwindSafe(|| {
                    process(mesh, args, &options, &settings)
                }))
                .unwrap_or_else(|_| {
                    Row::failed(mesh, format!("{}: internal error (panic)", mesh.display()))
                });
                if matches!(row.status, Status::Failed | Status::NotConverged) {
                    bar.suspend(|| eprintln!("error: {}", row.error));
                }
                bar.set_message(mesh.display().to_string());
                bar.inc(1);
                row
            })
            .collect()
    });
    bar.finish_and_clear();

    let summary = args.out.join(SUMMARY);
    File::create(&summary)
        .and_then(|file| write_summary(&rows, options.k, &mut BufWriter::new(file)))
        .map_err(|source| CliError::Io {
            path: summary.clone(),
            source,
        })?;
    let failed = rows
        .iter()
        .filter(|row| matches!(row.status, Status::Failed | Status::NotConverged))
        .count();
    let skipped = rows
        .iter()
        .filter(|row| row.status == Status::Skipped)
        .count();
    if !args.quiet {
        eprintln!(
            "{} meshes: {} computed, {skipped} skipped (complete), {failed} failed; summary in {}",
            rows.len(),
            rows.len() - skipped - failed,
            summary.display()
        );
    }
    if failed == 0 {
        Ok(())
    } else {
        Err(CliError::SomeFailed {
            failed,
            meshes: rows.len(),
            summary,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finished_outputs_keep_their_eigenvalues_exactly() {
        // serde_json without its `float_roundtrip` feature reads this one unit in the last
        // place off.
        let lambda = -12.220338406721039_f64;
        let json =
            std::env::temp_dir().join(format!("dirac-batch-finished-{}.json", std::process::id()));
        let text = format!(
            r#"{{"k": 1, "converged": true, "eigenvalues": [{lambda:?}], "timings": {{}}, "mesh_sha256": "00"}}"#
        );
        fs::write(&json, text).expect("the temporary directory is writable");
        let settings = serde_json::json!({ "k": 1 });
        let row = finished(&json, Path::new("m.off"), "00", &settings, 1);
        let _ = fs::remove_file(&json);
        let row = row.expect("a complete output");
        assert_eq!(row.status, Status::Skipped);
        assert_eq!(row.eigenvalues, [lambda]);
        assert_eq!(row.vertices, None);
    }
}
