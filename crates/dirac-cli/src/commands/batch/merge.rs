//! `dirac batch INPUT --out DIR --merge`: one `summary.csv` from the shards' summaries
//! (`summary-I-of-N.csv`, see [`super::shard`]) in `DIR`, rows in input order, computing
//! nothing.
//!
//! Rows are matched to the input by file name (unique within a batch), so shards may have
//! named their input by other paths (another working directory, another machine). A mesh in
//! no shard's summary is `missing`; a summary row naming a mesh that is not in the input, or
//! two shard counts in one directory, make the merge fail: those summaries are not of this
//! batch.

use std::collections::HashMap;
use std::ffi::OsString;
use std::fs::{self, File};
use std::path::{Path, PathBuf};

use super::summary::{Row, Status, read_summary};
use crate::common::error::CliError;

/// The shard summaries in `out`: `(I, N, path)`, sorted.
fn shard_summaries(out: &Path) -> Result<Vec<(usize, usize, PathBuf)>, CliError> {
    let io_error = |source| CliError::Io {
        path: out.to_path_buf(),
        source,
    };
    let mut found = Vec::new();
    for entry in fs::read_dir(out).map_err(io_error)? {
        let path = entry.map_err(io_error)?.path();
        let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
            continue;
        };
        let parts = name
            .strip_prefix("summary-")
            .and_then(|rest| rest.strip_suffix(".csv"))
            .and_then(|rest| rest.split_once("-of-"));
        if let Some((Ok(index), Ok(count))) = parts.map(|(i, n)| (i.parse(), n.parse())) {
            found.push((index, count, path));
        }
    }
    found.sort();
    Ok(found)
}

/// The merged rows of `meshes` (the whole input, in order) from the shard summaries in
/// `out`, and the parts that have no summary (`"2/3"`, …).
pub fn merge(meshes: &[PathBuf], out: &Path) -> Result<(Vec<Row>, Vec<String>), CliError> {
    let summaries = shard_summaries(out)?;
    let Some(&(_, count, _)) = summaries.first() else {
        return Err(CliError::Merge(format!(
            "{}: no shard summaries (summary-I-of-N.csv); run `dirac batch … --shard I/N` \
             with the same --out first",
            out.display()
        )));
    };
    if let Some((_, other, path)) = summaries.iter().find(|(_, n, _)| *n != count) {
        return Err(CliError::Merge(format!(
            "{}: summaries of {count} and of {other} shards in one directory ({}); \
             remove those of the other run",
            out.display(),
            path.display()
        )));
    }
    let mut by_name: HashMap<OsString, Row> = HashMap::new();
    for (_, _, path) in &summaries {
        let file = File::open(path).map_err(|source| CliError::Io {
            path: path.clone(),
            source,
        })?;
        let rows = read_summary(file)
            .map_err(|problem| CliError::Merge(format!("{}: {problem}", path.display())))?;
        for row in rows {
            let name = row.mesh.file_name().unwrap_or_default().to_os_string();
            if !meshes.iter().any(|m| m.file_name() == Some(&name)) {
                return Err(CliError::Merge(format!(
                    "{} lists {}, which is not in the input; merge with the input the \
                     shards ran on",
                    path.display(),
                    row.mesh.display()
                )));
            }
            by_name.insert(name, row);
        }
    }
    let missing_parts = (1..=count)
        .filter(|index| !summaries.iter().any(|(i, _, _)| i == index))
        .map(|index| format!("{index}/{count}"))
        .collect();
    let rows = meshes
        .iter()
        .map(|mesh| {
            let name = mesh.file_name().unwrap_or_default();
            match by_name.remove(name) {
                Some(row) => Row {
                    mesh: mesh.clone(),
                    ..row
                },
                None => Row::without_result(
                    mesh,
                    Status::Missing,
                    format!(
                        "{}: in no shard summary (its shard has not run or not finished)",
                        mesh.display()
                    ),
                ),
            }
        })
        .collect();
    Ok((rows, missing_parts))
}
