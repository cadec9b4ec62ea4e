//! Preparing the mesh named on the command line: `--repair` (on request) and `--component`,
//! shared by every command that reads a mesh, and what they did, for reports.

use std::fmt::Display;
use std::path::Path;

use clap::Args;
use clap::error::ErrorKind;
use dirac::io::{RawMesh, read_raw};
use dirac::repair::{Change, RepairOptions, RepairReport, repair, sliver_warning, slivers};
use dirac::{ComponentSelection, Topology, TriMesh, default_mesh};
use serde::{Serialize, Serializer};

use crate::common::error::CliError;
use crate::common::parsers::nonnegative_real;

/// Name of the built-in mesh in reports.
pub const DEFAULT_MESH_NAME: &str = "spot (built-in)";

/// How a mesh is prepared before its spectrum is computed.
#[derive(Debug, Clone, Args)]
pub struct MeshPreparation {
    /// Repair the mesh first: merge vertices closer than --merge-distance, drop faces that
    /// name missing vertices, repeat a vertex, duplicate another, have zero area or a
    /// degenerate angle or are slivers thinner than the merge distance, split non-manifold
    /// edges and vertices, orient every component
    /// consistently and drop unused vertices. Every change is reported (and recorded in JSON
    /// output). Without it an invalid mesh is an error that names the defect.
    #[arg(long, help_heading = "Mesh")]
    pub repair: bool,

    #[command(flatten)]
    pub options: PreparationOptions,
}

/// The options of a repair and the component selection (also those of `dirac repair`).
#[derive(Debug, Clone, Args)]
pub struct PreparationOptions {
    /// With --repair: vertices closer than D times the diagonal of the bounding box are
    /// merged (0 merges only coincident vertices) [default: 1e-9].
    #[arg(long, value_name = "D", value_parser = nonnegative_real, help_heading = "Mesh")]
    pub merge_distance: Option<f64>,

    /// The connected components to use: `all`, `largest` (most faces) or an index (components
    /// numbered by their first face). Each component adds its own zero eigenvalue to the
    /// Laplacian.
    #[arg(long, value_name = "WHICH", default_value_t = ComponentSelection::All,
          help_heading = "Mesh")]
    pub component: ComponentSelection,
}

impl PreparationOptions {
    /// The repair's options.
    pub fn repair_options(&self) -> RepairOptions {
        let mut options = RepairOptions::default();
        if let Some(distance) = self.merge_distance {
            options.merge_distance = distance;
        }
        options
    }
}

/// What preparing a mesh did (JSON key `preparation`).
#[derive(Debug, Clone, Serialize)]
pub struct PreparationReport {
    /// The changes of `--repair` (`null` without it).
    pub repair: Option<RepairReport>,
    /// Connected components before `--component` selected.
    pub components: usize,
    /// The `--component` value (written as on the command line).
    #[serde(serialize_with = "as_text")]
    pub component: ComponentSelection,
    /// The faces of the mesh used that `--repair` would drop as slivers
    /// ([`dirac::repair::slivers`]; numbered as in that mesh).
    pub slivers: Change<usize>,
}

/// Serialises `value` as its `Display` text.
fn as_text<S: Serializer>(value: &impl Display, serializer: S) -> Result<S::Ok, S::Error> {
    serializer.collect_str(value)
}

/// A mesh ready for its spectrum, with its name for messages and what was done to it.
pub struct PreparedMesh {
    /// The mesh.
    pub mesh: TriMesh,
    /// The file as given, or [`DEFAULT_MESH_NAME`].
    pub name: String,
    /// The mesh's components, boundary loops and genus (found once: validating and finding the
    /// topology each sort every edge of the mesh).
    pub topology: Topology,
    /// What preparing it did.
    pub report: PreparationReport,
}

impl MeshPreparation {
    /// The mesh at `path` (or the built-in one), prepared; notes on stderr (unless `quiet`)
    /// say what was repaired or selected.
    pub fn load(&self, path: Option<&Path>, quiet: bool) -> Result<PreparedMesh, CliError> {
        let (raw, name) = match path {
            Some(path) => (read_raw(path)?, path.display().to_string()),
            None => {
                let mesh = default_mesh();
                let raw = RawMesh {
                    positions: mesh.positions().to_vec(),
                    faces: mesh.faces().to_vec(),
                };
                (raw, DEFAULT_MESH_NAME.to_string())
            }
        };
        let prepared = self.prepare(raw, path.unwrap_or(Path::new(DEFAULT_MESH_NAME)), name)?;
        if !quiet {
            prepared.print_notes();
        }
        Ok(prepared)
    }

    /// `--merge-distance` only with `--repair` (checked by the dispatcher for every command,
    /// since clap cannot relate the two across `dirac repair`, which has no `--repair`).
    pub fn check(&self) -> Result<(), CliError> {
        if self.options.merge_distance.is_some() && !self.repair {
            return Err(CliError::usage(
                ErrorKind::ArgumentConflict,
                "--merge-distance applies only with --repair",
            ));
        }
        Ok(())
    }

    /// Validates (or with `--repair` repairs) `raw`, read from `path`, and selects the
    /// component.
    pub fn prepare(
        &self,
        raw: RawMesh,
        path: &Path,
        name: String,
    ) -> Result<PreparedMesh, CliError> {
        let (mesh, repair_report) = if self.repair {
            let repaired =
                repair(raw, &self.options.repair_options()).map_err(|source| CliError::Repair {
                    mesh: name.clone(),
                    source,
                })?;
            (repaired.mesh, Some(repaired.report))
        } else {
            (raw.into_mesh_of(path)?, None)
        };
        let topology = mesh.topology();
        let components = topology.components.len();
        let (mesh, topology) = match self.options.component {
            ComponentSelection::All => (mesh, topology),
            selection => {
                let (selected, _) =
                    mesh.select_component(selection)
                        .map_err(|source| CliError::Component {
                            mesh: name.clone(),
                            source,
                        })?;
                let topology = selected.topology();
                (selected, topology)
            }
        };
        let slivers = Change::of(slivers(&mesh));
        Ok(PreparedMesh {
            mesh,
            name,
            topology,
            report: PreparationReport {
                repair: repair_report,
                components,
                component: self.options.component,
                slivers,
            },
        })
    }
}

impl PreparedMesh {
    /// Notes on stderr: every repair, the component kept, a mesh that looks like a triangle
    /// soup, slivers.
    pub fn print_notes(&self) {
        let name = &self.name;
        let slivers = &self.report.slivers;
        if let Some(&first) = slivers.examples.first() {
            eprintln!("warning: {name}: {}", sliver_warning(slivers.count, first));
        }
        if let Some(report) = &self.report.repair {
            if report.is_empty() {
                eprintln!("note: {name}: --repair changed nothing");
            }
            for line in report.lines() {
                eprintln!("note: {name}: repair: {line}");
            }
        }
        let components = self.report.components;
        if components > 1 {
            let faces = self.mesh.face_count();
            if self.report.repair.is_none() && components == faces {
                eprintln!(
                    "note: {name}: every face is a component of its own (a triangle soup, as \
                     STL files store meshes); --repair merges the coincident vertices"
                );
            } else if self.report.component == ComponentSelection::All {
                eprintln!(
                    "note: {name}: {components} connected components, used together (each adds \
                     a zero eigenvalue to the Laplacian; --component largest selects one)"
                );
            } else {
                eprintln!(
                    "note: {name}: component {} of {components} kept ({} vertices, {faces} faces)",
                    self.report.component,
                    self.mesh.vertex_count()
                );
            }
        }
    }
}
