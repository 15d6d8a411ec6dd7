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
    let mesh = |shape: Option<&crate::scene::shape_spec::ShapeSpec>| {
        let m = shape?.mesh.as_ref()?;
        Some(format!("{}: a plain scene holds no mesh", m.file))
    };
    if let Some(message) = mesh(scene.object.shape.as_ref()) {
        problems.add("object.shape.mesh.file", message, LOAD_WITH_FILES);
    }
    for (i, f) in scene.fingers.iter().enumerate() {
        if let Some(h) = f.texture.as_ref().and_then(|t| t.heights.as_ref()) {
            problems.add(
                format!("fingers[{i}].texture.heights.file"),
                format!("{}: a plain scene holds no height map", h.file),
                LOAD_WITH_FILES,
            );
        }
        if let Some(message) = mesh(f.tip.as_ref().and_then(|t| t.shape.as_deref())) {
            problems.add(
                format!("fingers[{i}].tip.shape.mesh.file"),
                message,
                LOAD_WITH_FILES,
            );
        }
    }
    problems.finish().map_err(SceneError::Invalid)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box with a finger on its top face past the edge (the quadratic gap: a warning) and
    /// one under it whose tip is a posed sphere.
    fn shaped() -> serde_json::Value {
        let pad = serde_json::json!({"youngs_modulus": 2e6, "poisson_ratio": 0.45});
        serde_json::json!({
            "object": {"weight": 1.0, "center_of_mass": [0, 0, 0], "material": "rigid",
                       "shape": {"box": {"size": [0.1, 0.1, 0.1]}}},
            "fingers": [
                {"name": "f", "place": {"point": [0.0495, 0.0, 0.05]}, "gap": "quadratic",
                 "material": pad, "patch": {"size": [0.002, 0.002], "grid": [3, 3]},
                 "friction": {"mu": 0.5}},
                {"name": "g", "place": {"point": [0.0, 0.0, -0.05]},
                 "tip": {"shape": {"sphere": {"radius": 0.01}, "position": [0, 0, -0.06]}},
                 "material": pad, "patch": {"size": [0.002, 0.002], "grid": [3, 3]},
                 "friction": {"mu": 0.5}}
            ]
        })
    }

    #[test]
    fn a_plain_scene_loads_the_geometry_reading_found() {
        let read = LoadedScene::from_json_str(&shaped().to_string()).unwrap();
        let plain = LoadedScene::of_plain(read.scene.clone()).unwrap();
        let (a, b) = (&read.geometry, &plain.geometry);
        assert_eq!(a.surface, b.surface);
        assert_eq!(a.warnings().len(), 1, "{:?}", a.warnings());
        assert_eq!(a.warnings(), b.warnings());
        let (ra, rb) = (a.report.as_ref().unwrap(), b.report.as_ref().unwrap());
        assert_eq!((ra.volume_m3, ra.centroid_m), (rb.volume_m3, rb.centroid_m));
        // The plain scene's frames are written out: checked as explicit ones.
        assert_eq!(ra.fingers[0].source, "point");
        assert_eq!(rb.fingers[0].source, "explicit");
        let tips = |g: &SceneGeometry| g.tips.iter().map(Option::is_some).collect::<Vec<_>>();
        assert_eq!(tips(a), [false, true]);
        assert_eq!(tips(a), tips(b));
        assert!(plain.validate().is_ok());
    }

    #[test]
    fn a_plain_scene_that_names_files_is_refused_at_each() {
        let mut v = shaped();
        v["object"]["shape"] = serde_json::json!({"mesh": {"file": "mug.obj"}});
        v["fingers"][1]["tip"]["shape"] = serde_json::json!({"mesh": {"file": "tip.stl"}});
        v["fingers"][0]["texture"] =
            serde_json::json!({"heights": {"file": "h.npy", "pixel_m": [1e-4, 1e-4]}});
        for f in v["fingers"].as_array_mut().unwrap() {
            let f = f.as_object_mut().unwrap();
            f.remove("place");
            f.insert("contact_point".into(), serde_json::json!([0, 0, 0]));
            f.insert("normal".into(), serde_json::json!([0, 0, 1]));
        }
        let scene: Scene = serde_json::from_value(v).unwrap();
        let problems = LoadedScene::of_plain(scene).unwrap_err().problems();
        let paths: Vec<&str> = problems.iter().map(|p| p.path.as_str()).collect();
        assert_eq!(
            paths,
            [
                "object.shape.mesh.file",
                "fingers[0].texture.heights.file",
                "fingers[1].tip.shape.mesh.file"
            ]
        );
        assert!(problems.iter().all(|p| p.fix.contains("with its files")));
        assert!(problems[0].message.contains("mug.obj"), "{problems:?}");
    }
}
