//! Scenes with their files: a scene file read through [`crate::input_file`], its mesh files
//! read relative to its folder (the scene's own `object.shape.mesh.file`), and every file read
//! noted ([`RunInputs`]) so that no output of the run can replace one of them.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use grasp_model::MeshSpec;
use grasp_model::TriangleMesh;
use grasp_model::{Scene, SceneError};

use crate::error::InputFileError;
use crate::input_file::{read_text, SCENE_FILE};
use crate::mesh_file::read_mesh_file;
use crate::run_inputs::RunInputs;

/// The folder a scene file's relative mesh paths start from.
pub fn base_dir_of(scene_path: &Path) -> PathBuf {
    scene_path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default()
}

/// Reads mesh files relative to a folder, noting each file read.
struct MeshReader<'a> {
    base: &'a Path,
    read: RefCell<RunInputs>,
}

impl MeshReader<'_> {
    fn read(&self, spec: &MeshSpec) -> Result<TriangleMesh, String> {
        let path = self.base.join(&spec.file);
        let (mesh, identity) = read_mesh_file(&path, spec)?;
        self.read.borrow_mut().add(&path, identity);
        Ok(mesh)
    }
}

/// A scene from JSON text, its mesh files read relative to `base_dir`.
pub fn scene_from_json_str(text: &str, base_dir: &Path) -> Result<Scene, SceneError> {
    scene_from_json_str_noting(text, base_dir, &mut RunInputs::new())
}

/// As [`scene_from_json_str`], adding the mesh files read to `inputs`.
pub fn scene_from_json_str_noting(
    text: &str,
    base_dir: &Path,
    inputs: &mut RunInputs,
) -> Result<Scene, SceneError> {
    let reader = MeshReader {
        base: base_dir,
        read: RefCell::new(RunInputs::new()),
    };
    let scene = Scene::from_json_str_with_meshes(text, &|m: &MeshSpec| reader.read(m));
    inputs.extend(&reader.read.into_inner());
    scene
}

/// A scene from a JSON value parsed strictly (a batch line's `scene`, parsed once), its mesh
/// files read relative to `base_dir` and added to `inputs`.
pub fn scene_from_value(
    value: serde_json::Value,
    base_dir: &Path,
    inputs: &mut RunInputs,
) -> Result<Scene, SceneError> {
    let reader = MeshReader {
        base: base_dir,
        read: RefCell::new(RunInputs::new()),
    };
    let scene = Scene::from_value_with_meshes(value, &|m: &MeshSpec| reader.read(m));
    inputs.extend(&reader.read.into_inner());
    scene
}

/// A scene read from its file, with every file read (the scene file and its meshes).
#[derive(Debug, Clone)]
pub struct SceneFile {
    /// The validated scene.
    pub scene: Scene,
    /// The files read.
    pub inputs: RunInputs,
}

/// Why a scene file gave no scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneFileError {
    /// The file itself could not be read.
    #[error(transparent)]
    Read(#[from] InputFileError),
    /// Its content is not a usable scene (every problem listed).
    #[error("{} is not a usable scene", path.display())]
    Scene {
        /// The scene file.
        path: PathBuf,
        /// The problems.
        #[source]
        source: SceneError,
    },
}

/// Reads and validates the scene file at `path` (meshes relative to its folder).
pub fn read_scene_file(path: &Path) -> Result<SceneFile, SceneFileError> {
    let (text, identity) = read_text(path, SCENE_FILE)?;
    let mut inputs = RunInputs::new();
    inputs.add(path, identity);
    let scene =
        scene_from_json_str_noting(&text, &base_dir_of(path), &mut inputs).map_err(|source| {
            SceneFileError::Scene {
                path: path.to_path_buf(),
                source,
            }
        })?;
    Ok(SceneFile { scene, inputs })
}
