//! `--relative-to B`: the second surface `f2` of the relative Dirac operator `D_{f1,f2}`
//! (paper §4, Fig. 3), for the commands that solve one mesh.

use std::path::{Path, PathBuf};

use clap::Args;
use clap::error::ErrorKind;
use dirac::{Operator, TriMesh};

use crate::common::error::CliError;
use crate::common::preparation::{MeshPreparation, PreparedMesh};

/// The reference surface of `D_{f1,f2}`.
#[derive(Debug, Clone, Default, Args)]
pub struct ReferenceArgs {
    /// A second surface with the same triangulation as the mesh (the same vertices in the same
    /// order, the same faces): the operators built on D_N = D_{f,N} (relative-dirac, squared,
    /// family:T) use the relative Dirac operator D_{mesh,B} of the two surfaces instead, whose
    /// eigenfunctions see where they differ. Read with the mesh's --repair and --component.
    #[arg(long, value_name = "B")]
    pub relative_to: Option<PathBuf>,
}

impl ReferenceArgs {
    /// A usage error (before anything is read) when `--relative-to` is given with an operator
    /// that does not use the Gauss map.
    fn check(&self, operator: Operator) -> Result<(), CliError> {
        if self.relative_to.is_some() && !operator.uses_gauss_map() {
            return Err(CliError::usage(
                ErrorKind::ArgumentConflict,
                format!(
                    "--relative-to replaces the Gauss map of D_N, which --operator {operator} \
                     does not use; use relative-dirac, squared or family:T"
                ),
            ));
        }
        Ok(())
    }

    /// The mesh at `path` (or the built-in one) prepared by `preparation`, and the reference
    /// surface prepared alike and checked to be its triangulation (`None` without
    /// `--relative-to`); first a usage error if `operator` does not use the Gauss map.
    pub fn load_with_mesh(
        &self,
        preparation: &MeshPreparation,
        path: Option<&Path>,
        operator: Operator,
        quiet: bool,
    ) -> Result<(PreparedMesh, Option<TriMesh>), CliError> {
        self.check(operator)?;
        let mesh = preparation.load(path, quiet)?;
        let reference = self.load(preparation, &mesh, quiet)?;
        Ok((mesh, reference))
    }

    /// The reference surface, prepared like `mesh` and checked to be its triangulation; `None`
    /// without `--relative-to`.
    fn load(
        &self,
        preparation: &MeshPreparation,
        mesh: &PreparedMesh,
        quiet: bool,
    ) -> Result<Option<TriMesh>, CliError> {
        let Some(path) = &self.relative_to else {
            return Ok(None);
        };
        let reference = preparation.load(Some(path), quiet)?;
        mesh.mesh
            .check_same_connectivity(&reference.mesh)
            .map_err(|source| CliError::ReferenceConnectivity {
                mesh: mesh.name.clone(),
                reference: reference.name,
                source,
            })?;
        Ok(Some(reference.mesh))
    }
}
