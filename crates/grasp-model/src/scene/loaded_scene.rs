//! A scene as read, with what reading it found: the plain [`Scene`] and its
//! [`SceneGeometry`] (the shape's report, the posed shapes, the object's triangles, the height
//! maps). It reads as the scene it holds (`Deref`), so code that reads scene fields keeps
//! reading them; the model is built from it ([`crate::GraspModel::from_loaded`]). The readers
//! that fill the geometry (from text, a JSON value, with the files a scene names) are
//! [`crate::scene::scene_reading`]'s; a plain scene is loaded here ([`LoadedScene::of_plain`]).

use std::ops::{Deref, DerefMut};
use std::sync::Arc;

use crate::error::SceneError;
use crate::geometry::surface_texture::HeightGrid;
use crate::problem_list::ProblemList;
use crate::scene::scene_format::Scene;
use crate::scene::scene_geometry::SceneGeometry;
use crate::scene::shape_report::ShapeReport;

/// The fix of a plain scene that names a file: its geometry needs the files read.
const LOAD_WITH_FILES: &str = "load the scene with its files (grasp_io's `read_scene_file` or \
     `scene_from_json_str`, the grasp CLI, grasp.Scene)";

/// A scene as read, with what reading it found.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedScene {
    /// The plain data (the file format).
    pub scene: Scene,
    /// What reading the scene found beyond its plain data (shared: a scene changed through
    /// `DerefMut`, its grids refined say, keeps the geometry of its fingers).
    pub geometry: Arc<SceneGeometry>,
}

impl Deref for LoadedScene {
    type Target = Scene;

    fn deref(&self) -> &Scene {
        &self.scene
    }
}

impl DerefMut for LoadedScene {
    fn deref_mut(&mut self) -> &mut Scene {
        &mut self.scene
    }
}

impl LoadedScene {
    /// A plain scene loaded: the geometry a scene that names no file has, derived from its
    /// plain data (the object's shape and the fingers' tip shapes posed from their specs, the
    /// object's triangles tessellated, the shape's report and warnings found again, its
    /// explicit frames checked against the shape). A mesh shape or a height map file is an
    /// error naming the field: such a scene is loaded with its files (grasp_io, the grasp
    /// CLI, grasp.Scene). Not validated: [`LoadedScene::validate`].
    pub fn of_plain(scene: Scene) -> Result<LoadedScene, SceneError> {
        files_named(&scene)?;
        let geometry = match &scene.object.shape {
            None => SceneGeometry::default(),
            Some(_) => {
                let mut value = serde_json::to_value(&scene).map_err(|e| SceneError::Parse {
                    path: ".".into(),
                    message: e.to_string(),
                })?;
                let no_mesh = |_: &crate::scene::shape_spec::MeshSpec| -> Result<_, String> {
                    Err("a plain scene holds no mesh".into())
                };
                crate::scene::finger_placement::resolve_shapes(&mut value, &no_mesh)?
                    .unwrap_or_default()
            }
        };
        Ok(LoadedScene {
            scene,
            geometry: Arc::new(geometry),
        })
    }

    /// What the object's shape gave: derived finger frames, volume, mass, warnings (`None`
    /// without `object.shape`).
    pub fn shape_report(&self) -> Option<&ShapeReport> {
        self.geometry.report.as_ref()
    }

    /// Finger `i`'s height map, if one was read or given.
    pub fn height_map(&self, i: usize) -> Option<&HeightGrid> {
        self.geometry.height_map(i)
    }

    /// Checks every value, the height maps read included (each read, finite, covering its
    /// patch); returns all problems found, each with path and fix ([`Scene::validate`], which
    /// finds a height map file unread).
    pub fn validate(&self) -> Result<(), SceneError> {
        self.scene.validate_with(&self.geometry)
    }
}

/// Refuses a plain scene that names a file (a mesh, a height map): every one, at its path.
fn files_named(scene: &Scene) -> Result<(), SceneError> {
    let mut problems = ProblemList::default();
    let mut mesh = |path: String, shape: Option<&crate::scene::shape_spec::ShapeSpec>| {
        if let Some(m) = shape.and_then(|s| s.mesh.as_ref()) {
            let message = format!("{}: a plain scene holds no mesh", m.file);
            problems.add(path, message, LOAD_WITH_FILES);
        }
    };
    mesh("object.shape.mesh.file".into(), scene.object.shape.as_ref());
    for (i, f) in scene.fingers.iter().enumerate() {
        let tip = f.tip.as_ref().and_then(|t| t.shape.as_deref());
        mesh(format!("fingers[{i}].tip.shape.mesh.file"), tip);
    }
    for (i, f) in scene.fingers.iter().enumerate() {
        if let Some(h) = f.texture.as_ref().and_then(|t| t.heights.as_ref()) {
            problems.add(
                format!("fingers[{i}].texture.heights.file"),
                format!("{}: a plain scene holds no height map", h.file),
                LOAD_WITH_FILES,
            );
        }
    }
    problems.finish().map_err(SceneError::Invalid)
}
