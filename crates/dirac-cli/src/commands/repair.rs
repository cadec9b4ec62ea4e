//! `dirac repair IN --out OUT`: a mesh as downloaded made valid, every change reported
//! (`dirac::repair`: merge close vertices, drop bad faces, split non-manifold edges and
//! vertices, orient components, drop unused vertices), optionally one component kept.

use std::io::{self, Write};
use std::path::PathBuf;

use clap::Args;
use clap::error::ErrorKind;
use dirac::io::{Format, PlyWriteOptions, read_raw, write_obj, write_ply};
use serde::Serialize;

use crate::common::error::CliError;
use crate::common::files::tell;
use crate::common::preparation::{MeshPreparation, PreparationOptions, PreparationReport};

/// Exit codes and examples shown by `dirac repair --help`.
pub const AFTER_HELP: &str = "\
Every command that reads a mesh also takes --repair (and --merge-distance, --component), so
a separate repaired file is needed only to keep it.

Exit codes:
  0  repaired (or nothing to repair) and written
  1  the file cannot be read, the mesh cannot be repaired (e.g. a Möbius-like component),
     or the output cannot be written
  2  usage error (bad or missing arguments, an --out that is neither .obj nor .ply)

Examples:
  dirac repair scan.ply --out scan-fixed.obj
  dirac repair soup.obj --merge-distance 1e-6 --component largest --out part.ply --json";

/// Arguments of `dirac repair`.
#[derive(Debug, Args)]
pub struct RepairArgs {
    /// Mesh file (.obj, .off, .ply or .stl).
    pub input: PathBuf,

    /// The repaired mesh: a .obj or .ply file.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,

    /// Merge distance and component.
    #[command(flatten)]
    pub options: PreparationOptions,

    /// Print one JSON object (sizes and the report) instead of lines.
    #[arg(long)]
    pub json: bool,
}

/// What `dirac repair --json` prints.
#[derive(Serialize)]
struct RepairOutput {
    input: String,
    output: String,
    input_vertices: usize,
    input_faces: usize,
    vertices: usize,
    faces: usize,
    preparation: PreparationReport,
}

/// Runs `dirac repair`.
pub fn run(args: &RepairArgs) -> Result<(), CliError> {
    let format = Format::from_path(&args.out);
    if !matches!(format, Some(Format::Obj | Format::Ply)) {
        return Err(CliError::usage(
            ErrorKind::ValueValidation,
            format!(
                "--out {}: expected a .obj or .ply file name",
                args.out.display()
            ),
        ));
    }
    let raw = read_raw(&args.input)?;
    let (input_vertices, input_faces) = (raw.positions.len(), raw.faces.len());
    let preparation = MeshPreparation {
        repair: true,
        options: args.options.clone(),
    };
    let name = args.input.display().to_string();
    let prepared = preparation.prepare(raw, &args.input, name.clone())?;
    match format {
        Some(Format::Ply) => write_ply(&prepared.mesh, &args.out, &PlyWriteOptions::default())?,
        _ => write_obj(&prepared.mesh, &args.out)?,
    }
    let output = RepairOutput {
        input: name,
        output: args.out.display().to_string(),
        input_vertices,
        input_faces,
        vertices: prepared.mesh.vertex_count(),
        faces: prepared.mesh.face_count(),
        preparation: prepared.report.clone(),
    };
    if args.json {
        let mut out = io::stdout().lock();
        serde_json::to_writer_pretty(&mut out, &output)
            .map_err(io::Error::from)
            .and_then(|()| writeln!(out))
            .map_err(CliError::Stdout)?;
    } else {
        prepared.print_notes();
        tell(format_args!(
            "{} ({} vertices, {} faces; read {input_vertices} vertices, {input_faces} faces)",
            output.output, output.vertices, output.faces
        ));
    }
    Ok(())
}
