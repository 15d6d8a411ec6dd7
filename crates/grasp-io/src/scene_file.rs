//! Scenes with their files: a scene file read through [`crate::input_file`], the files it
//! names read relative to its folder (the object's `object.shape.mesh.file`, each finger's
//! `texture.heights.file`), and every file read noted ([`RunInputs`]) so that no output of the
//! run can replace one of them. A caller holding heights in memory (a Python array) gives them
//! by finger ([`HeightArrays`]) instead of a file.

use std::cell::RefCell;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use grasp_model::{FileProblem, HeightGrid, HeightMapSpec, MeshSpec, SceneFiles, TriangleMesh};
use grasp_model::{LoadedScene, SceneError};

use crate::error::InputFileError;
use crate::height_map_file::read_height_map;
use crate::input_file::{read_text, SCENE_FILE};
use crate::mesh_file::read_mesh_file;
use crate::run_inputs::RunInputs;

/// Height maps given in memory, by finger index (a Python caller's NumPy arrays): a finger
/// listed here takes its heights from here, and its `texture.heights.file` is not read.
pub type HeightArrays = BTreeMap<usize, Arc<HeightGrid>>;

/// The folder a scene file's relative mesh paths start from.
pub fn base_dir_of(scene_path: &Path) -> PathBuf {
    scene_path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default()
}

/// Reads the files a scene names relative to a folder, noting each file read; a height map
/// named twice is read once.
struct FileReader<'a> {
    base: &'a Path,
    arrays: &'a HeightArrays,
    read: RefCell<RunInputs>,
    maps: RefCell<HashMap<PathBuf, Arc<HeightGrid>>>,
}

impl<'a> FileReader<'a> {
    fn new(base: &'a Path, arrays: &'a HeightArrays) -> Self {
        FileReader {
            base,
            arrays,
            read: RefCell::new(RunInputs::new()),
            maps: RefCell::new(HashMap::new()),
        }
    }
}

impl SceneFiles for FileReader<'_> {
    fn mesh(&self, spec: &MeshSpec) -> Result<TriangleMesh, String> {
        let path = self.base.join(&spec.file);
        let (mesh, identity) = read_mesh_file(&path, spec)?;
        self.read.borrow_mut().add(&path, identity);
        Ok(mesh)
    }

    fn height_map(
        &self,
        finger: usize,
        spec: &HeightMapSpec,
    ) -> Result<Arc<HeightGrid>, FileProblem> {
        if let Some(grid) = self.arrays.get(&finger) {
            return Ok(grid.clone());
        }
        let path = self.base.join(&spec.file);
        if let Some(grid) = self.maps.borrow().get(&path) {
            return Ok(grid.clone());
        }
        let (grid, identity) = read_height_map(&path)?;
        self.read.borrow_mut().add(&path, identity);
        let grid = Arc::new(grid);
        self.maps.borrow_mut().insert(path, grid.clone());
        Ok(grid)
    }
}

/// A scene from JSON text, the files it names read relative to `base_dir` (the scene as read,
/// with its shapes and height maps).
pub fn scene_from_json_str(text: &str, base_dir: &Path) -> Result<LoadedScene, SceneError> {
    scene_from_json_str_noting(text, base_dir, &mut RunInputs::new())
}

/// As [`scene_from_json_str`], adding the files read to `inputs`.
pub fn scene_from_json_str_noting(
    text: &str,
    base_dir: &Path,
    inputs: &mut RunInputs,
) -> Result<LoadedScene, SceneError> {
    scene_from_json_str_with_arrays(text, base_dir, &HeightArrays::new(), inputs)
}

/// As [`scene_from_json_str_noting`], the fingers of `arrays` taking their height maps from
/// it rather than from their `texture.heights.file`.
pub fn scene_from_json_str_with_arrays(
    text: &str,
    base_dir: &Path,
    arrays: &HeightArrays,
    inputs: &mut RunInputs,
) -> Result<LoadedScene, SceneError> {
    let reader = FileReader::new(base_dir, arrays);
    let scene = LoadedScene::from_json_str_with_files(text, &reader);
    inputs.extend(&reader.read.into_inner());
    scene
}

/// A scene from a JSON value parsed strictly (a batch line's `scene`, parsed once), the files
/// it names read relative to `base_dir` and added to `inputs`.
pub fn scene_from_value(
    value: serde_json::Value,
    base_dir: &Path,
    inputs: &mut RunInputs,
) -> Result<LoadedScene, SceneError> {
    let arrays = HeightArrays::new();
    let reader = FileReader::new(base_dir, &arrays);
    let scene = LoadedScene::from_value_with_files(value, &reader);
    inputs.extend(&reader.read.into_inner());
    scene
}

/// A scene read from its file, with every file read (the scene file, its meshes and height
/// maps).
#[derive(Debug, Clone)]
pub struct SceneFile {
    /// The validated scene, with what reading it found (its shapes, its height maps).
    pub scene: LoadedScene,
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

/// Reads and validates the scene file at `path` (the files it names relative to its folder).
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
