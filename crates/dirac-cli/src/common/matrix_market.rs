//! Matrix Market files (the NIST exchange format that scipy, MATLAB, Julia and most sparse
//! solvers read): the eigenproblems `dirac matrices` writes.
//!
//! Numbers are written as the shortest decimals that read back to the same `f64`, so a reader
//! gets the matrices bit for bit.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use faer::c64;
use faer::sparse::SparseColMat;

use crate::common::error::CliError;

/// A scalar of a Matrix Market `coordinate` file of a self-adjoint matrix.
pub trait MarketEntry {
    /// The header's field and symmetry (`real symmetric`, `complex hermitian`).
    const KIND: &'static str;
    /// Writes the entry's numbers.
    fn write_to(&self, out: &mut impl Write) -> io::Result<()>;
}

impl MarketEntry for f64 {
    const KIND: &'static str = "real symmetric";
    fn write_to(&self, out: &mut impl Write) -> io::Result<()> {
        write!(out, "{self:e}")
    }
}

impl MarketEntry for c64 {
    const KIND: &'static str = "complex hermitian";
    fn write_to(&self, out: &mut impl Write) -> io::Result<()> {
        write!(out, "{:e} {:e}", self.re, self.im)
    }
}

/// Writes the lower triangle (row ≥ column: what the solvers read) of the self-adjoint
/// `matrix` to `path` as a `coordinate` file whose symmetry says that the upper triangle is
/// its conjugate transpose, with a `%` line for each of `comments` after the header.
pub fn write_lower_triangle<E: MarketEntry>(
    path: &Path,
    matrix: &SparseColMat<usize, E>,
    comments: &[String],
) -> Result<(), CliError> {
    let lower = || matrix.triplet_iter().filter(|t| t.row >= t.col);
    write_file(path, |out| {
        writeln!(out, "%%MatrixMarket matrix coordinate {}", E::KIND)?;
        write_comments(out, comments)?;
        let size = (matrix.nrows(), matrix.ncols(), lower().count());
        writeln!(out, "{} {} {}", size.0, size.1, size.2)?;
        for entry in lower() {
            write!(out, "{} {} ", entry.row + 1, entry.col + 1)?;
            entry.val.write_to(out)?;
            writeln!(out)?;
        }
        Ok(())
    })
}

/// Writes `values` to `path` as an `array real general` file of one column.
pub fn write_column(path: &Path, values: &[f64], comments: &[String]) -> Result<(), CliError> {
    write_file(path, |out| {
        writeln!(out, "%%MatrixMarket matrix array real general")?;
        write_comments(out, comments)?;
        writeln!(out, "{} 1", values.len())?;
        values.iter().try_for_each(|v| writeln!(out, "{v:e}"))
    })
}

fn write_comments(out: &mut impl Write, comments: &[String]) -> io::Result<()> {
    comments.iter().try_for_each(|c| writeln!(out, "% {c}"))
}

/// Creates `path` and writes it through a buffer; an error names the file.
fn write_file(
    path: &Path,
    contents: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> Result<(), CliError> {
    let written = File::create(path).and_then(|file| {
        let mut out = BufWriter::new(file);
        contents(&mut out)?;
        out.flush()
    });
    written.map_err(|source| CliError::Io {
        path: path.to_path_buf(),
        source,
    })
}
