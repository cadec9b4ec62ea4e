//! One module per subcommand; each defines its arguments and a `run` function returning the
//! process exit code. Shared here: loading the mesh named on the command line.

pub mod spectrum;

use std::path::Path;

use dirac::io::{ReadError, read_mesh};
use dirac::{TriMesh, default_mesh};

/// Name of the built-in mesh in reports.
pub const DEFAULT_MESH_NAME: &str = "spot (built-in)";

/// The mesh at `path`, or the built-in one without a path, with its name for reports.
pub fn load_mesh(path: Option<&Path>) -> Result<(TriMesh, String), ReadError> {
    match path {
        Some(path) => Ok((read_mesh(path)?, path.display().to_string())),
        None => Ok((default_mesh(), DEFAULT_MESH_NAME.to_string())),
    }
}
