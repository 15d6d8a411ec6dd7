//! Reading a scene file for a command: through `grasp_io` (a regular file within its size
//! limit, its mesh files read relative to its folder), every problem listed under the file's
//! name, and every file read noted ([`crate::limits::note_inputs`]).

use std::path::Path;

use anyhow::Result;
use grasp_model::Scene;

use crate::limits;

/// Reads and validates a scene file (its mesh files relative to its folder); the error
/// names the file and lists every problem.
pub(crate) fn load_scene(path: &Path) -> Result<Scene> {
    let file = grasp_io::read_scene_file(path)?;
    limits::note_inputs(&file.inputs);
    Ok(file.scene)
}
