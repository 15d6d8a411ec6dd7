//! Reading a scene: strict JSON text or an already parsed value, the object's shape resolved
//! (fingers placed on it), the height maps its fingers' textures name read (what reading
//! found kept beside the plain scene: a [`LoadedScene`]), directions normalised on load
//! (scaled by their largest component first, so `[1e200, 0, 0]` is `[1, 0, 0]`), then the
//! validation pass ([`crate::scene::scene_validation`]). A document
//! that does not read as a scene reports every structural problem at once (against the JSON
//! Schema), each with its path and fix. The files a scene names are read by the caller
//! ([`SceneFiles`]): this crate does no I/O.

use std::sync::Arc;

use crate::error::{InputProblem, SceneError};
use crate::geometry::mesh_surface::TriangleMesh;
use crate::problem_list::ProblemList;
use crate::scene::loaded_scene::LoadedScene;
use crate::scene::scene_format::{Scene, Vec3};
use crate::scene::scene_geometry::SceneGeometry;
use crate::scene::shape_spec::MeshSpec;
use crate::scene::strict_json::StrictValue;
use crate::scene::texture_spec::{HeightGrid, HeightMapSpec};
use crate::scene::vector_math::unit_vector;

/// Why a file a scene names could not be read: what is wrong (naming the file) and the fix.
/// The scene reader adds the JSON path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileProblem {
    /// What is wrong.
    pub message: String,
    /// How to fix it.
    pub fix: String,
}

/// The files a scene names, read for it by the caller: a mesh shape's file
/// (`object.shape.mesh.file`) and the fingers' height maps (`fingers[i].texture.heights.file`),
/// each path relative to the scene file's folder.
pub trait SceneFiles {
    /// The mesh of `object.shape.mesh`, in metres; the error names the file.
    fn mesh(&self, spec: &MeshSpec) -> Result<TriangleMesh, String>;
    /// The heights of `fingers[finger].texture.heights` (m, rows along `t1`).
    fn height_map(
        &self,
        finger: usize,
        spec: &HeightMapSpec,
    ) -> Result<Arc<HeightGrid>, FileProblem>;
}

/// Meshes from a closure; height maps refused (the readers of [`LoadedScene::from_json_str`]
/// and [`LoadedScene::from_json_str_with_meshes`]).
struct MeshesOnly<'a>(&'a dyn Fn(&MeshSpec) -> Result<TriangleMesh, String>);

impl SceneFiles for MeshesOnly<'_> {
    fn mesh(&self, spec: &MeshSpec) -> Result<TriangleMesh, String> {
        (self.0)(spec)
    }

    fn height_map(&self, _: usize, spec: &HeightMapSpec) -> Result<Arc<HeightGrid>, FileProblem> {
        Err(FileProblem {
            message: format!("{}: this loader reads no height maps", spec.file),
            fix: "load the scene with its files: the grasp CLI, grasp.Scene or grasp_io".into(),
        })
    }
}

impl LoadedScene {
    /// Parses a scene from JSON text (one document, nothing after it; duplicate keys refused),
    /// normalises its directions (see [`Scene::normalize_directions`]) and validates it (see
    /// [`LoadedScene::validate`]), keeping what reading found.
    ///
    /// A scene with `object.shape` is resolved first (fingers placed on it, the weight from a
    /// density, explicit frames checked: `crate::scene::finger_placement`); this entry point reads
    /// no files, so a mesh shape needs [`LoadedScene::from_json_str_with_meshes`], and a
    /// texture's height map [`LoadedScene::from_json_str_with_files`] (grasp_io reads both).
    pub fn from_json_str(text: &str) -> Result<LoadedScene, SceneError> {
        LoadedScene::from_json_str_with_meshes(text, &|m: &MeshSpec| {
            Err(format!(
                "{}: this loader reads no files; load the scene with the grasp CLI, grasp.Scene \
                 or grasp_io",
                m.file
            ))
        })
    }

    /// As [`LoadedScene::from_json_str`], reading a mesh shape's file with `load_mesh` (a
    /// height map is refused: see [`LoadedScene::from_json_str_with_files`]).
    pub fn from_json_str_with_meshes(
        text: &str,
        load_mesh: &dyn Fn(&MeshSpec) -> Result<TriangleMesh, String>,
    ) -> Result<LoadedScene, SceneError> {
        LoadedScene::from_json_str_with_files(text, &MeshesOnly(load_mesh))
    }

    /// As [`LoadedScene::from_json_str`], reading the files the scene names with `files`.
    pub fn from_json_str_with_files(
        text: &str,
        files: &dyn SceneFiles,
    ) -> Result<LoadedScene, SceneError> {
        let parse_error = |e: crate::scene::strict_json::JsonError| structure_error(text, e);
        // Most scenes name no shape: read them once, as written (a key inside a string only
        // sends a scene down the resolving path, which reads it the same way).
        if !["\"shape\"", "\"place\"", "\"density\""]
            .iter()
            .any(|k| text.contains(k))
        {
            let scene: Scene =
                crate::scene::strict_json::from_str_strict(text).map_err(parse_error)?;
            return loaded(scene, None, files);
        }
        let StrictValue(mut value) =
            crate::scene::strict_json::from_str_strict::<StrictValue>(text).map_err(parse_error)?;
        let load_mesh = |m: &MeshSpec| files.mesh(m);
        let shape = crate::scene::finger_placement::resolve_shapes(&mut value, &load_mesh)?;
        let scene: Scene = match shape {
            // Without a shape the text is read as written (positions in messages are its own).
            None => crate::scene::strict_json::from_str_strict(text).map_err(parse_error)?,
            Some(_) => {
                let resolved = serde_json::to_string_pretty(&value).unwrap_or_default();
                crate::scene::strict_json::from_str_strict(&resolved).map_err(parse_error)?
            }
        };
        loaded(scene, shape, files)
    }

    /// As [`LoadedScene::from_json_str_with_files`], from a JSON value already parsed strictly
    /// (no key twice: [`StrictValue`]), so a scene inside a larger document (a batch line) is
    /// parsed once: its shape resolved on the value, then the typed scene read from it.
    pub fn from_value_with_files(
        mut value: serde_json::Value,
        files: &dyn SceneFiles,
    ) -> Result<LoadedScene, SceneError> {
        // As written, for the structural problems of a scene that does not parse.
        let written = value.clone();
        let load_mesh = |m: &MeshSpec| files.mesh(m);
        let shape = crate::scene::finger_placement::resolve_shapes(&mut value, &load_mesh)?;
        let scene: Scene = crate::scene::strict_json::from_value_strict(value)
            .map_err(|e| structure_error_of(&written, e))?;
        loaded(scene, shape, files)
    }
}

/// The scene read, with what its shape gave (`shape`; `None` without one): its height maps
/// read from `files`, its directions normalised, then validated.
fn loaded(
    mut scene: Scene,
    shape: Option<SceneGeometry>,
    files: &dyn SceneFiles,
) -> Result<LoadedScene, SceneError> {
    let mut geometry = shape.unwrap_or_default();
    geometry.height_maps = read_height_maps(&scene, files)?;
    scene.normalize_directions();
    let loaded = LoadedScene {
        scene,
        geometry: Arc::new(geometry),
    };
    loaded.validate()?;
    Ok(loaded)
}

/// Per finger, its height map read from `files` (`None` for a finger whose texture names
/// none; empty when no finger's does); every map that cannot be read is a problem at
/// `fingers[i].texture.heights.file`.
fn read_height_maps(
    scene: &Scene,
    files: &dyn SceneFiles,
) -> Result<Vec<Option<Arc<HeightGrid>>>, SceneError> {
    fn spec(f: &crate::scene::scene_format::FingerSpec) -> Option<&HeightMapSpec> {
        f.texture.as_ref().and_then(|t| t.heights.as_ref())
    }
    if !scene.fingers.iter().any(|f| spec(f).is_some()) {
        return Ok(Vec::new());
    }
    let mut problems = ProblemList::default();
    let mut maps = Vec::with_capacity(scene.fingers.len());
    for (i, f) in scene.fingers.iter().enumerate() {
        let Some(map) = spec(f) else {
            maps.push(None);
            continue;
        };
        match files.height_map(i, map) {
            Ok(grid) => maps.push(Some(grid)),
            Err(e) => {
                maps.push(None);
                problems.add(
                    format!("fingers[{i}].texture.heights.file"),
                    e.message,
                    e.fix,
                );
            }
        }
    }
    problems.finish().map_err(SceneError::Invalid)?;
    Ok(maps)
}

impl Scene {
    /// Parses a scene from JSON text (one document, nothing after it; duplicate keys refused),
    /// normalises its directions (see [`Scene::normalize_directions`]) and validates it (see
    /// [`Scene::validate`]): the plain scene of [`LoadedScene::from_json_str`], what reading
    /// found beyond it (the shape's report, the posed shapes) dropped.
    pub fn from_json_str(text: &str) -> Result<Scene, SceneError> {
        LoadedScene::from_json_str(text).map(|loaded| loaded.scene)
    }

    /// Replaces every direction (gravity, planar normal, finger normals and tangents) by its
    /// unit vector, computed without overflow (`unit_vector`); zero or non-finite directions
    /// are left for [`Scene::validate`] to refuse.
    pub fn normalize_directions(&mut self) {
        let fix = |x: &mut Vec3| {
            if let Some(u) = unit_vector(x) {
                *x = u;
            }
        };
        fix(&mut self.object.gravity);
        if let Some(p) = &mut self.planar {
            fix(&mut p.normal);
        }
        for f in &mut self.fingers {
            fix(&mut f.normal);
            if let Some(t) = &mut f.tangent {
                fix(t);
            }
        }
    }
}

/// The error of a scene text the typed reader stopped on (`e`): every structural problem of
/// the document (missing, unknown and mistyped fields, each with a fix;
/// [`crate::scene::schema_check`]) when it is valid JSON, the reader's own error kept among
/// them; else `e` alone (a syntax error).
fn structure_error(text: &str, e: crate::scene::strict_json::JsonError) -> SceneError {
    match crate::scene::strict_json::from_str_strict::<StrictValue>(text) {
        Ok(StrictValue(value)) => structure_error_of(&value, e),
        // Not even a JSON document: the reader's error, with its position.
        Err(_) => single_problem(e),
    }
}

/// A reader's error as the one problem of a scene.
fn single_problem(e: crate::scene::strict_json::JsonError) -> SceneError {
    SceneError::Parse {
        path: e.path,
        message: e.message,
    }
}

/// serde_json's data error without its trailing ` at line L column C`.
fn without_position(message: &str) -> &str {
    match message.rfind(" at line ") {
        Some(i)
            if message[i + 9..]
                .split(" column ")
                .all(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit())) =>
        {
            &message[..i]
        }
        _ => message,
    }
}

/// [`structure_error`] of a scene already parsed into `value` (as written, before any shape
/// was resolved). The reader's message loses its position (` at line L column C`): the JSON
/// path locates a data error, and a scene parsed from text or from a value (a batch line)
/// reports it alike.
fn structure_error_of(
    value: &serde_json::Value,
    e: crate::scene::strict_json::JsonError,
) -> SceneError {
    let e = crate::scene::strict_json::JsonError {
        message: without_position(&e.message).to_string(),
        path: e.path,
    };
    let single = single_problem;
    let schema = crate::scene::scene_format::scene_json_schema();
    let mut found = crate::scene::schema_check::structural_problems(value, schema.as_value());
    found.extend(conditionally_missing(value));
    if found.is_empty() {
        return single(e);
    }
    // Where the walk only knows that no form fits, the reader's message says which it expected.
    for p in found.iter_mut() {
        if p.path == e.path && p.message.contains(NO_FORM_FITS) {
            p.message = e.message.clone();
        }
    }
    // The walk knows the format's structure, the reader its details: keep the reader's error
    // when no problem found lies on its path.
    let related = |p: &InputProblem| p.path.starts_with(&e.path) || e.path.starts_with(&p.path);
    let reader_error = (!found.iter().any(related)).then(|| reader_problem(&e));
    let problems: ProblemList = found.into_iter().chain(reader_error).collect();
    problems
        .finish()
        .err()
        .map_or_else(|| single(e), SceneError::Invalid)
}

/// The fields the schema leaves optional but this scene needs, each with its fix: a finger's
/// `contact_point` and `normal` unless it has `place`, the object's `weight` and
/// `center_of_mass` unless it has a `density` (every one at once, where the reader stops at
/// the first).
fn conditionally_missing(value: &serde_json::Value) -> Vec<InputProblem> {
    let mut out = Vec::new();
    let object = &value["object"];
    if object.is_object() && object.get("density").is_none() {
        for key in ["center_of_mass", "weight"] {
            if object.get(key).is_none() {
                out.push(InputProblem::new(
                    format!("object.{key}"),
                    "is missing",
                    conditional_fix(key),
                ));
            }
        }
    }
    let fingers = value["fingers"].as_array().map_or(&[][..], Vec::as_slice);
    for (i, f) in fingers.iter().enumerate() {
        if !f.is_object() || f.get("place").is_some() {
            continue;
        }
        for key in ["contact_point", "normal"] {
            if f.get(key).is_none() {
                out.push(InputProblem::new(
                    format!("fingers[{i}].{key}"),
                    "is missing",
                    conditional_fix(key),
                ));
            }
        }
    }
    out
}

/// The fix for a missing field of [`conditionally_missing`].
fn conditional_fix(key: &str) -> String {
    match key {
        "weight" => {
            "give the object's weight in newtons, or object.shape with object.density \
                     (the weight and centre of mass then follow)"
        }
        "center_of_mass" => {
            "give the centre of mass in metres (world frame), or object.shape \
                             with object.density"
        }
        "contact_point" => {
            "give the contact point on the object's surface in metres (world \
                            frame), or `place` to derive it from object.shape"
        }
        "normal" => {
            "give the contact normal pointing into the object, or `place` to derive it \
                     from object.shape"
        }
        _ => return format!("add `{key}` (see `grasp schema`)"),
    }
    .to_string()
}

/// The reader's error `e` as a problem: a field the schema leaves optional (a placed finger
/// derives its frame) but this scene needs, or the reader's message.
fn reader_problem(e: &crate::scene::strict_json::JsonError) -> InputProblem {
    match missing_field(&e.message) {
        Some(name) => {
            let path = if e.path == "." {
                name.to_string()
            } else {
                format!("{}.{name}", e.path)
            };
            InputProblem::new(path, "is missing", conditional_fix(name))
        }
        None => InputProblem::new(
            e.path.clone(),
            e.message.clone(),
            "correct the JSON (see `grasp schema`)",
        ),
    }
}

/// What [`crate::scene::schema_check`] says of a value that fits none of a field's forms.
const NO_FORM_FITS: &str = crate::scene::schema_check::NO_FORM_FITS;

/// The field named by serde's "missing field `name` at line ..." message.
fn missing_field(message: &str) -> Option<&str> {
    message.strip_prefix("missing field `")?.split('`').next()
}
