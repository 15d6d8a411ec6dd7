//! Reading a scene file for a command: through `grasp_io` (a regular file within its size
//! limit, its mesh files read relative to its folder), every problem listed under the file's
//! name, and every file read noted ([`crate::limits::note_inputs`]); and its model built, a
//! model that does not fit in memory said so rather than called unusable.

use std::path::Path;

use anyhow::{anyhow, Result};
use grasp_model::{ComplianceChoice, GraspModel, LoadedScene, SceneError};

use crate::limits;

/// Reads and validates a scene file (its mesh files relative to its folder): the scene as
/// read, with its shapes and height maps; the error names the file and lists every problem.
pub(crate) fn load_scene(path: &Path) -> Result<LoadedScene> {
    let file = grasp_io::read_scene_file(path)?;
    limits::note_inputs(&file.inputs);
    Ok(file.scene)
}

/// The model of the scene read from `path`, its patch compliances in the form `compliance`
/// picks; the error names the file (a scene whose buffers the system refused: what and how
/// much, not "unusable").
pub(crate) fn model_of(
    scene: &LoadedScene,
    compliance: ComplianceChoice,
    path: &Path,
) -> Result<GraspModel> {
    GraspModel::from_loaded_with(scene, compliance).map_err(|e| match e {
        SceneError::OutOfMemory { .. } => anyhow!("{}: {e}", path.display()),
        e => anyhow::Error::new(e).context(format!("{} is not a usable scene", path.display())),
    })
}
