//! Reading a scene file for a command: its size checked ([`crate::limits`]), its mesh files
//! read relative to its folder, every problem listed under the file's name.

use std::path::Path;

use anyhow::{Context, Result};
use grasp_model::Scene;

use crate::limits;

/// Reads and validates a scene file (its mesh files relative to its folder); the error
/// names the file and lists every problem.
pub(crate) fn load_scene(path: &Path) -> Result<Scene> {
    let text = limits::read_input(path, "scene file")?;
    grasp_io::scene_from_json_str(&text, &grasp_io::base_dir_of(path))
        .with_context(|| format!("{} is not a usable scene", path.display()))
}
