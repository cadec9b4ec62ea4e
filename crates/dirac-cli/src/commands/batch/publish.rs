//! Output files appear whole or not at all, also when several runs share a directory.
//!
//! A file is written under a temporary name unique to this process and write
//! (`.<name>.<pid>-<time>-<n>.partial`, created exclusively in the destination's directory, so
//! it is on the same file system), flushed to disk, renamed over the final name (atomic on
//! POSIX file systems) and the directory itself is synced, so the rename survives a crash.
//! A write that fails removes its temporary file. Only a process killed during a write
//! (SIGKILL, power loss) leaves one behind: its name starts with a dot and ends in `.partial`,
//! a rerun ignores it, and it can be deleted.

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

/// Writes `path` through `write`, atomically (see the module documentation).
pub fn publish(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> io::Result<()> {
    let directory = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let (temporary, file) = create_temporary(directory, path)?;
    let written = (|| {
        let mut writer = BufWriter::new(file);
        write(&mut writer)?;
        writer.flush()?;
        writer
            .into_inner()
            .map_err(|e| e.into_error())?
            .sync_all()?;
        fs::rename(&temporary, path)
    })();
    if written.is_err() {
        let _ = fs::remove_file(&temporary);
    }
    written?;
    sync_directory(directory)
}

/// A new file `.<name>.<pid>-<nanoseconds>-<n>.partial` beside `path`, created exclusively.
/// The process id and counter make names unique within a machine; the time, across machines
/// that share the directory; exclusive creation, in any case.
fn create_temporary(directory: &Path, path: &Path) -> io::Result<(PathBuf, File)> {
    static WRITES: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .unwrap_or(path.as_os_str())
        .to_string_lossy();
    loop {
        let nanoseconds = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |t| t.subsec_nanos());
        let temporary = directory.join(format!(
            ".{name}.{}-{nanoseconds}-{}.partial",
            std::process::id(),
            WRITES.fetch_add(1, Ordering::Relaxed)
        ));
        match File::create_new(&temporary) {
            Ok(file) => return Ok((temporary, file)),
            Err(error) if error.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(error) => return Err(error),
        }
    }
}

/// Flushes the directory entry of a rename to disk (POSIX; elsewhere a rename is as durable
/// as the file system makes it).
fn sync_directory(directory: &Path) -> io::Result<()> {
    #[cfg(unix)]
    File::open(directory)?.sync_all()?;
    #[cfg(not(unix))]
    let _ = directory;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("dirac-publish-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_published_file_replaces_the_old_one_and_leaves_nothing_else() {
        let dir = scratch("replace");
        let path = dir.join("out.json");
        fs::write(&path, "old").unwrap();
        publish(&path, |w| w.write_all(b"new")).unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(entries(&dir), ["out.json"]);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_and_removes_its_temporary() {
        let dir = scratch("fail");
        let path = dir.join("out.json");
        fs::write(&path, "old").unwrap();
        let error = publish(&path, |w| {
            w.write_all(b"half")?;
            Err(io::Error::other("disk full"))
        })
        .unwrap_err();
        assert_eq!(error.to_string(), "disk full");
        assert_eq!(fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(entries(&dir), ["out.json"]);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn concurrent_writers_of_one_file_each_publish_a_whole_file() {
        let dir = scratch("concurrent");
        let path = dir.join("summary.csv");
        std::thread::scope(|scope| {
            for writer in 0..8u8 {
                let path = &path;
                scope.spawn(move || {
                    for _ in 0..20 {
                        publish(path, |w| w.write_all(&[b'a' + writer; 10_000])).unwrap();
                    }
                });
            }
        });
        let text = fs::read(&path).unwrap();
        assert_eq!(text.len(), 10_000);
        assert!(text.iter().all(|&b| b == text[0]));
        assert_eq!(entries(&dir), ["summary.csv"]);
        fs::remove_dir_all(&dir).unwrap();
    }
}
