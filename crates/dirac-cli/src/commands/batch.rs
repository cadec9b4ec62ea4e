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
//! - `summary.csv`, written at the end of every run (also an interrupted one), one row per mesh
//!   in input order (see [`summary`]): status `ok`, `skipped` (complete from an earlier run),
//!   `not-converged` (the JSON holds the converged part), `failed` (`error` says why) or
//!   `interrupted`. With `--shard I/N` it is `summary-I-of-N.csv`, and `--merge` combines the
//!   shards' summaries into `summary.csv` ([`shard`], [`merge`]).
//!
//! Every file is published whole: written under a unique temporary name in `--out`, synced and
//! renamed ([`mod@publish`]), so concurrent runs on one directory never see half a file. Ctrl-C
//! stops the solves in progress within about 0.1 s, writes the summary (the unfinished meshes
//! `interrupted`) and exits 130; the next run resumes. A second Ctrl-C exits at once.
//!
//! Meshes run in parallel on `--jobs` threads (default: the available parallelism); each solve
//! itself is sequential (every faer call in `qeig` runs with `Par::Seq`), so `--jobs N` keeps N
//! cores busy without oversubscription. A failing mesh is reported on stderr and in the summary
//! and does not stop the others; `--time-limit` stops a mesh's eigensolver at its first restart
//! past the limit (the mesh is then `not-converged`). Each mesh file is read once: its bytes are
//! hashed and parsed.

mod merge;
mod publish;
mod saved;
mod shard;
mod summary;

use std::fs;
use std::io::{self, IsTerminal};
use std::num::NonZeroUsize;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use clap::Args;
use clap::error::ErrorKind;
use dirac::io::{Format, parse_raw};
use dirac::spectrum::{Operator, SpectrumOptions};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use serde_json::Value;
use sha2::{Digest, Sha256};

use self::publish::publish;
pub use self::saved::Saved;
pub use self::shard::Shard;
use self::summary::{Row, Status, write_summary};
use crate::common::error::{CliError, INTERRUPTED};
use crate::common::parsers::{positive_count, positive_real, value_name};
use crate::common::preparation::PreparedMesh;
use crate::common::report::{Report, RunSettings, write_json};
use crate::common::solve::solve_until;
use crate::common::solve_args::SolveArgs;

/// Name of the summary table in the output directory.
pub const SUMMARY: &str = "summary.csv";

/// Exit codes and examples shown by `dirac batch --help`.
pub const AFTER_HELP: &str = "\
Output in --out DIR: <mesh file name>.json per mesh (the object of `dirac spectrum --json`)
and summary.csv (mesh, status, vertices, faces, converged, seconds, error, lambda_0 ...).
A rerun skips meshes whose JSON is complete (converged, same mesh file contents by SHA-256,
same operator and options). Files appear whole (temporary name, sync, rename).

Several machines: `--shard I/N` computes the I-th of N parts (1 <= I <= N; every part sees
the same input) and writes summary-I-of-N.csv; then `--merge` with the same input and --out
combines them into summary.csv, computing nothing.

Exit codes:
  0    every mesh is complete (computed now or skipped as finished earlier)
  1    the batch cannot run: unreadable input, no meshes, file names that collide (also
       ignoring case), an unwritable output directory or summary, or shard summaries that
       do not belong to this input (--merge)
  2    usage error (bad or missing arguments)
  4    some meshes failed, did not converge, or (--merge) are in no shard summary;
       reported on stderr and in the summary; the others are complete
  130  interrupted (Ctrl-C): the summary is written, the next run resumes

Examples:
  dirac batch meshes/ -k 30 --out spectra/
  dirac batch list.txt --operator laplace --normalize unit-area -k 50 --jobs 2 --out spectra/
  dirac batch meshes/ -k 30 --out spectra/ --shard 2/8      # one of 8 machines
  dirac batch meshes/ -k 30 --out spectra/ --merge          # after all 8";

/// Arguments of `dirac batch`.
#[derive(Debug, Args)]
pub struct BatchArgs {
    /// A directory (all .obj, .off, .ply and .stl files in it) or a text file of mesh paths, one per
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

    /// Compute only part I of N (1-based): the meshes at positions I−1, I−1+N, … of the
    /// input; the summary is summary-I-of-N.csv.
    #[arg(long, value_name = "I/N", conflicts_with = "merge")]
    pub shard: Option<Shard>,

    /// Compute nothing: combine the shards' summaries in --out into summary.csv (input
    /// order), checking each complete result against these options.
    #[arg(long)]
    pub merge: bool,

    /// Also write these arrays per mesh beside its JSON, comma-separated: `eigenvectors`
    /// (n × k × 4), `hks` (needs --operator laplace), `dks`, `wks` (n × 100 at the default
    /// times or energies, listed in the JSON). A result is complete only with them.
    #[arg(long, value_enum, value_delimiter = ',', value_name = "WHAT")]
    pub save: Vec<Saved>,

    /// Stop a mesh's eigensolver once this many seconds have passed since the mesh was read
    /// (checked whenever the eigensolver reports progress: after every restart, and between
    /// restarts at least every 0.1 s): the mesh is `not-converged`, its JSON holds the pairs
    /// that converged, and a rerun tries it again. Keeps a few pathological meshes from
    /// holding up a data set.
    #[arg(long, value_name = "SECONDS", value_parser = positive_real)]
    pub time_limit: Option<f64>,

    /// Recompute meshes whose output is already complete.
    #[arg(long, conflicts_with = "merge")]
    pub force: bool,

    /// No progress on stderr (errors and the final counts are still reported).
    #[arg(short, long)]
    pub quiet: bool,
}

/// Set by the first Ctrl-C: no new mesh starts and the solves in progress stop.
static INTERRUPT: AtomicBool = AtomicBool::new(false);

fn interrupted() -> bool {
    INTERRUPT.load(Ordering::SeqCst)
}

/// Handles Ctrl-C for the rest of the process: the first stops the batch gracefully, a
/// second exits at once (a file being written may then leave its temporary behind).
fn watch_interrupts() {
    let installed = ctrlc::set_handler(|| {
        if INTERRUPT.swap(true, Ordering::SeqCst) {
            std::process::exit(i32::from(INTERRUPTED));
        }
        eprintln!("\ninterrupted: stopping the solves in progress (Ctrl-C again to quit at once)");
    });
    if let Err(error) = installed {
        eprintln!("note: Ctrl-C will stop the batch at once, without its summary: {error}");
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
    let folded = |path: &Path| {
        path.file_name()
            .map(|name| name.to_string_lossy().to_lowercase())
    };
    let mut seen = std::collections::HashMap::new();
    for mesh in &meshes {
        if let Some(first) = seen.insert(folded(mesh), mesh) {
            return Err(CliError::DuplicateName {
                first: first.clone(),
                second: mesh.clone(),
            });
        }
    }
    Ok(meshes)
}

/// `DIR/<file name of mesh>.<suffix>`: where a mesh's outputs go.
fn output_path(out: &Path, mesh: &Path, suffix: &str) -> PathBuf {
    let mut name = mesh.file_name().unwrap_or(mesh.as_os_str()).to_os_string();
    name.push(".");
    name.push(suffix);
    out.join(name)
}

/// `DIR/<file name of mesh>.json`.
fn json_path(out: &Path, mesh: &Path) -> PathBuf {
    output_path(out, mesh, "json")
}

/// The SHA-256 of `bytes`, in hexadecimal.
fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|byte| format!("{byte:02x}"))
        .collect()
}

/// The summary row of a complete earlier result, or `None` when `json` is missing,
/// incomplete, of another mesh (another content hash), from other settings, or lacks one of
/// the arrays `saved` (beside it).
fn finished(
    json: &Path,
    mesh: &Path,
    digest: &str,
    settings: &Value,
    k: usize,
    saved: &[Saved],
) -> Option<Row> {
    let report: Value = serde_json::from_str(&fs::read_to_string(json).ok()?).ok()?;
    if report["mesh_sha256"].as_str() != Some(digest) {
        return None;
    }
    let directory = json.parent()?;
    let has_arrays = saved.iter().all(|what| {
        report["saved"][value_name(what)]["file"]
            .as_str()
            .is_some_and(|file| directory.join(file).is_file())
    });
    if !has_arrays {
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
            slivers: report["preparation"]["slivers"]["count"].as_u64(),
            seconds: Some(
                timings["load"].as_f64().unwrap_or(0.0)
                    + timings["assemble_and_solve"].as_f64().unwrap_or(0.0),
            ),
            error: String::new(),
            eigenvalues,
        },
    )
}

/// What every mesh of one run shares.
struct Job<'a> {
    args: &'a BatchArgs,
    options: SpectrumOptions,
    /// The settings as the JSON records them, for comparing with earlier results.
    settings: Value,
}

impl Job<'_> {
    /// The mesh file's bytes and their SHA-256, or why they cannot be read.
    fn read(&self, mesh_path: &Path) -> Result<(Vec<u8>, String), String> {
        let bytes =
            fs::read(mesh_path).map_err(|error| format!("{}: {error}", mesh_path.display()))?;
        let digest = sha256_hex(&bytes);
        Ok((bytes, digest))
    }

    /// Computes (or skips) one mesh.
    fn process(&self, mesh_path: &Path) -> Row {
        if interrupted() {
            return Row::without_result(
                mesh_path,
                Status::Interrupted,
                format!("{}: not started (interrupted)", mesh_path.display()),
            );
        }
        let json = json_path(&self.args.out, mesh_path);
        let start = Instant::now();
        let (bytes, digest) = match self.read(mesh_path) {
            Ok(read) => read,
            Err(error) => return Row::failed(mesh_path, error),
        };
        if !self.args.force
            && let Some(row) = finished(
                &json,
                mesh_path,
                &digest,
                &self.settings,
                self.options.k,
                &self.args.save,
            )
        {
            return row;
        }
        let name = mesh_path.display().to_string();
        let prepared = parse_raw(mesh_path, &bytes)
            .map_err(CliError::from)
            .and_then(|raw| {
                self.args
                    .solve
                    .problem
                    .preparation
                    .prepare(raw, mesh_path, name.clone())
            });
        drop(bytes);
        let PreparedMesh {
            mesh,
            topology,
            report: preparation,
            ..
        } = match prepared {
            Ok(prepared) => prepared,
            Err(error) => return Row::failed(mesh_path, error.to_string()),
        };
        let mut report = Report::new(
            name.clone(),
            &mesh,
            topology,
            RunSettings::new(&self.args.solve, &self.options),
            start.elapsed(),
        );
        let slivers = Some(preparation.slivers.count as u64);
        report.preparation = Some(preparation);
        report.mesh_sha256 = Some(digest);
        let mut row = Row {
            vertices: Some(mesh.vertex_count() as u64),
            faces: Some(mesh.face_count() as u64),
            slivers,
            ..Row::failed(mesh_path, String::new())
        };
        // A limit beyond what a clock can hold is no limit.
        let deadline = (self.args.time_limit)
            .and_then(|limit| start.checked_add(Duration::try_from_secs_f64(limit).ok()?));
        let past_deadline = || deadline.is_some_and(|deadline| Instant::now() >= deadline);
        let stop = || interrupted() || past_deadline();
        match solve_until(&mesh, None, &name, &self.options, true, stop) {
            Ok(solved) if !solved.converged && interrupted() => {
                row.status = Status::Interrupted;
                row.error = format!("{name}: stopped (interrupted); the next run computes it");
            }
            Ok(solved) => {
                report.set_spectrum(&solved.spectrum, solved.elapsed);
                report.converged = solved.converged;
                let stopped = (self.args.time_limit)
                    .filter(|_| past_deadline())
                    .map(|limit| {
                        format!(
                            "stopped at the time limit of {limit} s (--time-limit); a larger \
                             limit may let it finish"
                        )
                    });
                // What converged is in the JSON; the message is the command line's own.
                row.status = match solved.check_converged_unless_stopped(
                    &name,
                    self.options.k,
                    "the JSON holds those",
                    stopped,
                ) {
                    Ok(()) => Status::Ok,
                    Err(error) => {
                        row.error = error.to_string();
                        Status::NotConverged
                    }
                };
                if solved.converged {
                    for &what in &self.args.save {
                        match what.write(&solved.spectrum, &self.args.out, mesh_path) {
                            Ok(array) => {
                                report.saved.insert(value_name(&what), array);
                            }
                            Err(error) => {
                                row.status = Status::Failed;
                                row.error = error;
                                return row;
                            }
                        }
                    }
                }
                row.eigenvalues = solved.spectrum.eigenvalues;
                if let Err(error) = publish(&json, |w| write_json(&report, w)) {
                    row.status = Status::Failed;
                    row.error = format!("{}: {error}", json.display());
                }
            }
            Err(error) => row.error = error.to_string(),
        }
        row.seconds = Some(start.elapsed().as_secs_f64());
        row
    }
}

/// Progress over meshes on stderr: a bar with the time left on a terminal, one line per
/// mesh otherwise (a job's log file); nothing with `quiet`.
struct MeshProgress {
    bar: ProgressBar,
    lines: bool,
    done: AtomicUsize,
    total: usize,
}

impl MeshProgress {
    fn new(total: usize, quiet: bool) -> Self {
        let terminal = io::stderr().is_terminal();
        let bar = if quiet || !terminal {
            ProgressBar::hidden()
        } else {
            let bar =
                ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr());
            if let Ok(style) = ProgressStyle::with_template(
                "{elapsed:>4} [{bar:30}] {pos}/{len} meshes, {eta} left  {wide_msg}",
            ) {
                bar.set_style(style);
            }
            bar
        };
        Self {
            bar,
            lines: !quiet && !terminal,
            done: AtomicUsize::new(0),
            total,
        }
    }

    /// Reports a finished mesh: its error always, its line without a terminal.
    fn finished(&self, row: &Row) {
        let done = self.done.fetch_add(1, Ordering::SeqCst) + 1;
        let failed = row.status.is_failure();
        if self.lines {
            let what = if failed {
                format!("{}: {}", row.status.name(), row.error)
            } else {
                let seconds = row
                    .seconds
                    .map(|s| format!(" ({s:.1} s)"))
                    .unwrap_or_default();
                format!("{}: {}{seconds}", row.mesh.display(), row.status.name())
            };
            eprintln!("[{done}/{}] {what}", self.total);
        } else if failed {
            self.bar.suspend(|| eprintln!("error: {}", row.error));
        }
        self.bar.set_message(row.mesh.display().to_string());
        self.bar.inc(1);
    }
}

/// The final counts and the failed meshes with their reasons (at most `LISTED`; the
/// summary has all).
fn print_outcome(rows: &[Row], summary: &Path) {
    const LISTED: usize = 20;
    let count = |status: Status| rows.iter().filter(|row| row.status == status).count();
    eprintln!("{} meshes, summary in {}:", rows.len(), summary.display());
    for status in Status::ALL {
        let n = count(status);
        if n > 0 || matches!(status, Status::Ok | Status::Failed) {
            eprintln!("  {:<14}{n:>7}", status.name());
        }
    }
    let with_slivers = rows.iter().filter(|row| row.slivers > Some(0)).count();
    if with_slivers > 0 {
        eprintln!(
            "warning: {with_slivers} mesh{} sliver faces, which dominate every operator and can \
             spoil its spectrum (column slivers of the summary): --repair removes them",
            if with_slivers == 1 { " has" } else { "es have" }
        );
    }
    let unfinished: Vec<&Row> = rows.iter().filter(|row| row.status.is_failure()).collect();
    if !unfinished.is_empty() {
        eprintln!("not complete:");
        for row in unfinished.iter().take(LISTED) {
            eprintln!("  {}", row.error);
        }
        if unfinished.len() > LISTED {
            eprintln!(
                "  … and {} more (see the summary)",
                unfinished.len() - LISTED
            );
        }
    }
}

/// Publishes the summary `name` in `--out`.
fn write_summary_file(out: &Path, name: &str, rows: &[Row], k: usize) -> Result<PathBuf, CliError> {
    let path = out.join(name);
    publish(&path, |w| write_summary(rows, k, w)).map_err(|source| CliError::Io {
        path: path.clone(),
        source,
    })?;
    Ok(path)
}

/// `--merge`: the shards' rows, each complete one checked against this run's settings.
fn merged_rows(job: &Job, meshes: &[PathBuf]) -> Result<Vec<Row>, CliError> {
    let (mut rows, missing_parts) = merge::merge(meshes, &job.args.out)?;
    if !missing_parts.is_empty() {
        eprintln!(
            "warning: no summary of shard {} in {}",
            missing_parts.join(", "),
            job.args.out.display()
        );
    }
    for row in rows.iter_mut().filter(|row| row.status.is_complete()) {
        let json = json_path(&job.args.out, &row.mesh);
        let complete = job.read(&row.mesh).ok().and_then(|(_, digest)| {
            finished(
                &json,
                &row.mesh,
                &digest,
                &job.settings,
                job.options.k,
                &job.args.save,
            )
        });
        if complete.is_none() {
            *row = Row::failed(
                &row.mesh,
                format!(
                    "{}: {} is missing or not a complete result of this mesh file with these \
                     options; merge with the options the shards ran with, or rerun its shard",
                    row.mesh.display(),
                    json.display()
                ),
            );
        }
    }
    Ok(rows)
}

/// Runs `dirac batch`: `Ok` when every mesh is complete (computed now or earlier),
/// [`CliError::SomeFailed`] when some mesh is not, [`CliError::Interrupted`] after Ctrl-C.
pub fn run(args: &BatchArgs) -> Result<(), CliError> {
    let options = args.solve.options();
    if args.save.contains(&Saved::Hks) && options.operator != Operator::Laplace {
        return Err(CliError::usage(
            ErrorKind::ArgumentConflict,
            "--save hks is the heat kernel signature of the Laplacian: add --operator laplace \
             (dks and wks are those of --operator)",
        ));
    }
    if let Some(tau) = options.weight_by_scale() {
        // The solves are quiet (per-mesh lines only); one warning for the whole data set.
        eprintln!(
            "warning: the family weighs D_N and the Laplacian by each mesh's scale, and the \
             meshes are not normalised: family:{tau} amounts to another weight on every mesh \
             whose area is not 1; --normalize unit-area makes it mean the same on all"
        );
    }
    let all = inputs(&args.input)?;
    fs::create_dir_all(&args.out).map_err(|source| CliError::Io {
        path: args.out.clone(),
        source,
    })?;
    let job = Job {
        args,
        settings: serde_json::to_value(RunSettings::new(&args.solve, &options))
            .expect("the settings serialise to a JSON object"),
        options,
    };

    let (rows, summary_name) = if args.merge {
        (merged_rows(&job, &all)?, SUMMARY.to_string())
    } else {
        let meshes: Vec<&PathBuf> = match args.shard {
            Some(shard) => all
                .iter()
                .enumerate()
                .filter(|(position, _)| shard.contains(*position))
                .map(|(_, mesh)| mesh)
                .collect(),
            None => all.iter().collect(),
        };
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
        watch_interrupts();
        let progress = MeshProgress::new(meshes.len(), args.quiet);
        let rows: Vec<Row> = pool.install(|| {
            meshes
                .par_iter()
                .map(|mesh| {
                    let row =
                        catch_unwind(AssertUnwindSafe(|| job.process(mesh))).unwrap_or_else(|_| {
                            Row::failed(mesh, format!("{}: internal error (panic)", mesh.display()))
                        });
                    progress.finished(&row);
                    row
                })
                .collect()
        });
        progress.bar.finish_and_clear();
        let name = args
            .shard
            .map_or_else(|| SUMMARY.to_string(), Shard::summary_name);
        (rows, name)
    };

    let summary = write_summary_file(&args.out, &summary_name, &rows, job.options.k)?;
    print_outcome(&rows, &summary);
    let incomplete = rows.iter().filter(|row| !row.status.is_complete()).count();
    // Exit 130 only when this run was stopped: in a merge, a shard's interrupted rows are
    // incomplete (exit 4).
    if interrupted() && rows.iter().any(|row| row.status == Status::Interrupted) {
        Err(CliError::Interrupted { summary })
    } else if incomplete > 0 {
        Err(CliError::SomeFailed {
            failed: incomplete,
            meshes: rows.len(),
            summary,
        })
    } else {
        Ok(())
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
        let row = finished(&json, Path::new("m.off"), "00", &settings, 1, &[]);
        let _ = fs::remove_file(&json);
        let row = row.expect("a complete output");
        assert_eq!(row.status, Status::Skipped);
        assert_eq!(row.eigenvalues, [lambda]);
        assert_eq!(row.vertices, None);
    }

    #[test]
    fn names_that_differ_only_in_case_collide() {
        let dir = std::env::temp_dir().join(format!("dirac-batch-case-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let list = dir.join("list.txt");
        fs::write(&list, "a/Bunny.OBJ\nb/bunny.obj\n").unwrap();
        let error = inputs(&list).unwrap_err();
        let _ = fs::remove_dir_all(&dir);
        assert!(matches!(error, CliError::DuplicateName { .. }), "{error}");
        assert!(error.to_string().contains("Bunny.OBJ"), "{error}");
    }
}
