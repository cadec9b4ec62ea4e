//! The summary table of a batch: one row per mesh, written as CSV and read back by
//! `--merge`.
//!
//! Columns: `mesh, status, vertices, faces, converged, seconds, error, slivers, lambda_0 …`; at
//! most as many eigenvalue columns as the largest mesh has vertices (`k` eigenvalues exist only
//! on meshes with at least `k` vertices, so a huge `-k` fails on every mesh, not here).
//! `slivers` came last among the fixed columns so that summaries written before it (without
//! it) still read back: `--merge` may combine shards computed by different versions.

use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// How one mesh went.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Computed by this run.
    Ok,
    /// Complete from an earlier run (same mesh contents and settings).
    Skipped,
    /// The eigensolver stopped early; the JSON holds the converged part.
    NotConverged,
    /// Could not be computed; `error` says why.
    Failed,
    /// Not finished because the run was interrupted (Ctrl-C); the next run computes it.
    Interrupted,
    /// In no shard's summary (`--merge`): its shard has not run or not finished.
    Missing,
}

impl Status {
    /// Every status, in the order of reports.
    pub const ALL: [Status; 6] = [
        Status::Ok,
        Status::Skipped,
        Status::NotConverged,
        Status::Failed,
        Status::Interrupted,
        Status::Missing,
    ];

    /// The name in the `status` column.
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Skipped => "skipped",
            Status::NotConverged => "not-converged",
            Status::Failed => "failed",
            Status::Interrupted => "interrupted",
            Status::Missing => "missing",
        }
    }

    /// Whether the mesh has no complete result for a reason the user must act on (reported
    /// with its error): failed, not converged or missing from a merge. An interrupted mesh is
    /// not a failure: the next run computes it.
    pub fn is_failure(self) -> bool {
        matches!(
            self,
            Status::Failed | Status::NotConverged | Status::Missing
        )
    }

    /// Whether the mesh's result is complete (computed now or earlier).
    pub fn is_complete(self) -> bool {
        matches!(self, Status::Ok | Status::Skipped)
    }

    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|status| status.name() == name)
    }
}

/// One row of the summary; `error` names the file it is about.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The mesh file, as the input names it.
    pub mesh: PathBuf,
    /// How it went.
    pub status: Status,
    /// Vertex count, when the mesh could be read.
    pub vertices: Option<u64>,
    /// Face count, when the mesh could be read.
    pub faces: Option<u64>,
    /// Wall-clock seconds (load, solve and write).
    pub seconds: Option<f64>,
    /// Sliver faces of the mesh used ([`dirac::repair::slivers`]), when it could be read and
    /// prepared (a summary written before the column: unknown).
    pub slivers: Option<u64>,
    /// Why the mesh failed or did not converge; empty otherwise.
    pub error: String,
    /// The eigenvalues that converged, sorted by `|λ|`.
    pub eigenvalues: Vec<f64>,
}

impl Row {
    /// A row of `status` with an error and nothing else.
    pub fn without_result(mesh: &Path, status: Status, error: String) -> Self {
        Self {
            mesh: mesh.to_path_buf(),
            status,
            vertices: None,
            faces: None,
            seconds: None,
            slivers: None,
            error,
            eigenvalues: Vec::new(),
        }
    }

    /// A failed row.
    pub fn failed(mesh: &Path, error: String) -> Self {
        Self::without_result(mesh, Status::Failed, error)
    }
}

const FIXED_COLUMNS: [&str; 8] = [
    "mesh",
    "status",
    "vertices",
    "faces",
    "converged",
    "seconds",
    "error",
    "slivers",
];

/// The fixed columns of summaries written before `slivers`.
const FIXED_COLUMNS_WITHOUT_SLIVERS: usize = 7;

/// Writes the summary table of `rows` for `k` eigenvalues.
pub fn write_summary(rows: &[Row], k: usize, out: impl Write) -> io::Result<()> {
    let largest = rows
        .iter()
        .filter_map(|row| row.vertices)
        .max()
        .unwrap_or(0);
    let columns = k.min(usize::try_from(largest).unwrap_or(usize::MAX));
    let mut writer = csv::Writer::from_writer(out);
    let mut header: Vec<String> = FIXED_COLUMNS.map(String::from).to_vec();
    header.extend((0..columns).map(|i| format!("lambda_{i}")));
    writer.write_record(&header).map_err(io::Error::other)?;
    let optional = |x: Option<String>| x.unwrap_or_default();
    for row in rows {
        let mut fields = vec![
            row.mesh.display().to_string(),
            row.status.name().to_string(),
            optional(row.vertices.map(|v| v.to_string())),
            optional(row.faces.map(|f| f.to_string())),
            row.status.is_complete().to_string(),
            optional(row.seconds.map(|s| format!("{s:.3}"))),
            row.error.clone(),
            optional(row.slivers.map(|s| s.to_string())),
        ];
        // `{}` of an f64 is its shortest representation that reads back exactly.
        fields.extend(row.eigenvalues.iter().map(f64::to_string));
        fields.resize(header.len(), String::new());
        writer.write_record(&fields).map_err(io::Error::other)?;
    }
    writer.flush()
}

/// The message of a field of summary line `line` that is not a valid `what`.
fn invalid(line: u64, what: &str, text: &str) -> String {
    format!("line {line}: `{text}` is not a valid {what}")
}

/// The field `text` of summary line `line` as a `what`; `None` when it is empty.
fn optional<T: FromStr>(line: u64, what: &str, text: &str) -> Result<Option<T>, String> {
    if text.is_empty() {
        return Ok(None);
    }
    text.parse()
        .map(Some)
        .map_err(|_| invalid(line, what, text))
}

/// Reads a summary written by [`write_summary`]; an error names the line that is wrong.
pub fn read_summary(input: impl Read) -> Result<Vec<Row>, String> {
    let mut reader = csv::ReaderBuilder::new().flexible(true).from_reader(input);
    let header = reader.headers().map_err(|e| e.to_string())?.clone();
    let old = &FIXED_COLUMNS[..FIXED_COLUMNS_WITHOUT_SLIVERS];
    if header.iter().take(old.len()).ne(old.iter().copied()) {
        return Err(format!(
            "line 1: expected the columns {}, found {}",
            FIXED_COLUMNS.join(","),
            header.iter().collect::<Vec<_>>().join(",")
        ));
    }
    let has_slivers = header.get(old.len()) == Some("slivers");
    let fixed = if has_slivers {
        FIXED_COLUMNS.len()
    } else {
        old.len()
    };
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| e.to_string())?;
        // The line where the record starts (a quoted field may span lines).
        let line = record.position().map_or(0, |p| p.line());
        let field = |i: usize| record.get(i).unwrap_or("");
        let status =
            Status::from_name(field(1)).ok_or_else(|| invalid(line, "status", field(1)))?;
        let eigenvalues = record
            .iter()
            .skip(fixed)
            .filter_map(|text| optional(line, "eigenvalue", text).transpose())
            .collect::<Result<_, _>>()?;
        rows.push(Row {
            mesh: PathBuf::from(field(0)),
            status,
            vertices: optional(line, "vertex count", field(2))?,
            faces: optional(line, "face count", field(3))?,
            seconds: optional(line, "time", field(5))?,
            slivers: if has_slivers {
                optional(line, "sliver count", field(7))?
            } else {
                None
            },
            error: field(6).to_string(),
            eigenvalues,
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_summary_reads_back_as_written() {
        let rows = vec![
            Row {
                mesh: PathBuf::from("a, \"quoted\".off"),
                status: Status::Ok,
                vertices: Some(4),
                faces: Some(4),
                seconds: Some(0.25),
                slivers: Some(2),
                error: String::new(),
                eigenvalues: vec![-12.220338406721039, 1e-300, 3.0],
            },
            Row::failed(Path::new("b.obj"), "b.obj: line 3,\nbad".into()),
        ];
        let mut text = Vec::new();
        write_summary(&rows, 3, &mut text).unwrap();
        let back = read_summary(&text[..]).unwrap();
        assert_eq!(back, rows);
    }

    #[test]
    fn columns_are_bounded_by_the_largest_mesh() {
        let mut row = Row::failed(Path::new("a.off"), String::new());
        row.vertices = Some(2);
        let mut text = Vec::new();
        write_summary(&[row], usize::MAX, &mut text).unwrap();
        let header = String::from_utf8(text).unwrap();
        let header = header.lines().next().unwrap();
        assert!(
            header.ends_with("error,slivers,lambda_0,lambda_1"),
            "{header}"
        );
    }

    #[test]
    fn a_summary_written_before_the_slivers_column_reads_back() {
        let text = "mesh,status,vertices,faces,converged,seconds,error,lambda_0,lambda_1\n\
                    a.off,ok,4,4,true,0.250,,-1.5,2\n";
        let rows = read_summary(text.as_bytes()).unwrap();
        assert_eq!(rows.len(), 1);
        assert_eq!((rows[0].vertices, rows[0].slivers), (Some(4), None));
        assert_eq!(rows[0].eigenvalues, [-1.5, 2.0]);
    }

    #[test]
    fn a_foreign_file_is_refused_with_its_line() {
        let error = read_summary(&b"name,value\nx,1\n"[..]).unwrap_err();
        assert!(error.starts_with("line 1:"), "{error}");
        let text = "mesh,status,vertices,faces,converged,seconds,error\na.off,done,,,,,\n";
        let error = read_summary(text.as_bytes()).unwrap_err();
        assert!(
            error.contains("line 2") && error.contains("`done`"),
            "{error}"
        );
    }
}
