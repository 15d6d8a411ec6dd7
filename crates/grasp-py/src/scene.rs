//! `grasp.Scene`: a validated scene (the JSON scene format of `grasp schema`), read from a
//! file, a dict or JSON text. Validation runs once, here; a bad scene raises
//! `grasp.SceneError` with every problem found.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::errors::{grasp_error, scene_error};

/// A validated grasp scene (SI units: m, N, Pa).
///
/// The scene format is docs/scene.schema.json (docs/guide/scenes.md). Validation runs once,
/// here, and reports every problem found.
///
/// Parameters
/// ----------
/// source : str, os.PathLike or dict
///     A path to a scene file, a dict of the scene format, or the JSON text of one (a str
///     whose first non-blank character is `{`). Files the scene names (a mesh, a texture's
///     height map) are read relative to the scene file's folder (the working folder for a
///     dict or text); in a dict a texture's heights may be a NumPy array:
///     `{"heights": {"array": a, "pixel_m": [dx, dy]}}` (heights and pixels in m).
///
/// Raises
/// ------
/// SceneError
///     The scene is not valid: `problems` lists each (its JSON path, what is wrong, the fix).
/// OSError
///     The file cannot be read (missing, not a regular file, larger than 64 MiB).
/// TypeError
///     `source` is neither a path, a dict nor JSON text.
///
/// Examples
/// --------
/// >>> scene = grasp.Scene("examples/cube_a.json")
/// >>> scene.finger_names, scene.model
#[pyclass(module = "grasp", frozen)]
pub struct Scene {
    pub(crate) scene: grasp_model::LoadedScene,
    /// Where the scene came from (a path, `<dict>` or `<json>`), for messages.
    pub(crate) origin: String,
    /// The files read for it (the scene file, mesh files, height maps): no output may replace
    /// them.
    pub(crate) inputs: grasp_io::RunInputs,
}

#[pymethods]
impl Scene {
    #[new]
    fn new(py: Python<'_>, source: &Bound<'_, PyAny>) -> PyResult<Scene> {
        if let Ok(d) = source.downcast::<PyDict>() {
            return Scene::from_dict(py, d);
        }
        if source.is_instance_of::<PyString>() {
            let text: String = source.extract()?;
            if text.trim_start().starts_with('{') {
                return Scene::from_json(py, &text);
            }
        }
        match source.extract::<PathBuf>() {
            Ok(path) => Scene::from_file(py, path),
            Err(_) => Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "Scene(source): expected a path, a dict or JSON text, got {}",
                source.get_type().name()?
            ))),
        }
    }

    /// The scene in a file.
    ///
    /// Parameters
    /// ----------
    /// path : str or os.PathLike
    ///     A JSON scene file: a regular file of at most 64 MiB; the files it names (meshes,
    ///     height maps) are read relative to its folder.
    ///
    /// Returns
    /// -------
    /// Scene
    ///
    /// Raises
    /// ------
    /// SceneError
    ///     The scene is not valid (`problems`: path, message, fix of each).
    /// OSError
    ///     The file, or one it names, cannot be read.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Scene> {
        let origin = path.display().to_string();
        match py.allow_threads(|| grasp_io::read_scene_file(&path)) {
            Ok(file) => Ok(Scene {
                scene: file.scene,
                origin,
                inputs: file.inputs,
            }),
            Err(grasp_io::SceneFileError::Read(e)) => {
                Err(pyo3::exceptions::PyOSError::new_err(e.to_string()))
            }
            Err(grasp_io::SceneFileError::Scene { source, .. }) => {
                Err(scene_error(py, &origin, &source))
            }
        }
    }

    /// The scene given as JSON text.
    ///
    /// Parameters
    /// ----------
    /// text : str
    ///     The scene as JSON; the files it names are read relative to the working folder.
    ///
    /// Returns
    /// -------
    /// Scene
    ///
    /// Raises
    /// ------
    /// SceneError
    ///     The text is not JSON, or the scene is not valid (`problems`: path, message, fix).
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str) -> PyResult<Scene> {
        let arrays = grasp_io::HeightArrays::new();
        Scene::parse(py, text, "<json>".into(), std::path::Path::new(""), &arrays)
    }

    /// The scene given as a dict.
    ///
    /// Parameters
    /// ----------
    /// d : dict
    ///     The scene format as `json.load` returns it. A finger's texture heights may be a
    ///     NumPy array instead of a file: `"texture": {"heights": {"array": a, "pixel_m":
    ///     [dx, dy]}}` (heights in m, rows of `a` along `t1`, the array's centre on the
    ///     contact point; pixel sizes in m); `to_dict()` then shows `"file": "<array>"` in
    ///     its place.
    ///
    /// Returns
    /// -------
    /// Scene
    ///
    /// Raises
    /// ------
    /// SceneError
    ///     The scene is not valid, or holds a NaN or infinite number (`problems`: path,
    ///     message, fix of each).
    #[staticmethod]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyDict>) -> PyResult<Scene> {
        let origin = "<dict>";
        let (d, arrays) = crate::height_arrays::take_height_arrays(py, origin, d)?;
        let bad = crate::json_value::non_finite_numbers(d.as_any());
        if !bad.is_empty() {
            return Err(scene_error(
                py,
                origin,
                &grasp_model::SceneError::Invalid(bad),
            ));
        }
        let json = py.import("json")?;
        let text: String = json.call_method1("dumps", (d,))?.extract()?;
        Scene::parse(py, &text, origin.into(), std::path::Path::new(""), &arrays)
    }

    /// Finger names, scene order.
    #[getter]
    fn finger_names(&self) -> Vec<String> {
        self.scene.finger_names()
    }

    /// The contact model the scene asks for: `"energy"` or `"coulomb"`.
    #[getter]
    fn model(&self) -> &'static str {
        model_name(self.scene.model)
    }

    /// True for a planar scene.
    #[getter]
    fn planar(&self) -> bool {
        self.scene.planar.is_some()
    }

    /// Where the scene came from: its path, `<dict>` or `<json>`.
    #[getter]
    fn origin(&self) -> &str {
        &self.origin
    }

    /// What the object's shape gave each finger (contact point, inward normal, tangent,
    /// curvatures, radii), its volume and mass, and the shape checks' warnings; None without
    /// `object.shape`.
    #[getter]
    fn shape_report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::json_value::serialize_to_py(py, &self.scene.shape_report())
    }

    /// Warnings of the shape checks (a patch over an edge, overlapping patches, a mesh that
    /// is not closed); every `Solution` of the scene begins with them.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.scene.geometry.warnings().to_vec()
    }

    /// The texture heights of a finger at its patch's element centres.
    ///
    /// Parameters
    /// ----------
    /// finger : str or int
    ///     The finger's name (one of `finger_names`) or its index in the scene's fingers.
    ///
    /// Returns
    /// -------
    /// numpy.ndarray or None
    ///     Heights `h`, m (a peak positive, toward the other body), shape `(nx, ny)`, rows
    ///     along `t1`: element `(i, j)` is centred at `((i + 1/2) Lx/nx - Lx/2,
    ///     (j + 1/2) Ly/ny - Ly/2)` from the contact point. None for a finger without a
    ///     texture.
    ///
    /// Raises
    /// ------
    /// ValueError
    ///     The scene has no finger of that name or index.
    /// TypeError
    ///     `finger` is neither a name nor an index.
    /// GraspError
    ///     The height map cannot be sampled at the element centres.
    fn texture_heights_m<'py>(
        &self,
        py: Python<'py>,
        finger: &Bound<'py, PyAny>,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        let i = self.finger_index(finger)?;
        let f = &self.scene.fingers[i];
        let Some(texture) = &f.texture else {
            return Ok(None);
        };
        let ([lx, ly], [nx, ny]) = (f.patch.size, f.patch.grid);
        let (hx, hy) = (lx / nx as f64, ly / ny as f64);
        let centres: Vec<[f64; 2]> = (0..nx * ny)
            .map(|k| {
                let (i, j) = ((k / ny) as f64, (k % ny) as f64);
                [(i + 0.5) * hx - 0.5 * lx, (j + 0.5) * hy - 0.5 * ly]
            })
            .collect();
        let heights = py
            .allow_threads(|| {
                let map = self.scene.height_map(i);
                grasp_model::texture_heights_m(texture, map, &centres, [hx, hy])
            })
            .map_err(crate::errors::grasp_error)?;
        crate::arrays::float_array(py, &heights, &[nx, ny]).map(Some)
    }

    /// The scene as a dict (directions normalised, as validated).
    ///
    /// Returns
    /// -------
    /// dict
    ///     The scene format, SI units; `Scene(d)` reads it back.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::json_value::serialize_to_py(py, &self.scene.scene)
    }

    /// The scene as JSON text (directions normalised, as validated).
    ///
    /// Returns
    /// -------
    /// str
    ///     The scene format, pretty-printed; `Scene(text)` reads it back.
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string_pretty(&self.scene.scene).map_err(grasp_error)
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}: {} fingers {}, model {})",
            self.origin,
            self.scene.fingers.len(),
            self.finger_names().join(", "),
            self.model()
        )
    }
}

impl Scene {
    /// The index of the finger `finger` names: a name, or an index into the scene's fingers
    /// (negative from the end, as Python counts; never a bool).
    fn finger_index(&self, finger: &Bound<'_, PyAny>) -> PyResult<usize> {
        let n = self.scene.fingers.len();
        let missing = |what: String| {
            pyo3::exceptions::PyValueError::new_err(format!(
                "finger={what}: the scene's fingers are {:?} (indices 0 to {})",
                self.finger_names(),
                n.saturating_sub(1)
            ))
        };
        if let Ok(name) = finger.extract::<String>() {
            return self
                .scene
                .fingers
                .iter()
                .position(|f| f.name == name)
                .ok_or_else(|| missing(format!("{name:?}")));
        }
        let index = match finger.is_instance_of::<pyo3::types::PyBool>() {
            true => None,
            false => finger.extract::<i64>().ok(),
        };
        let Some(k) = index else {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "finger={}: give a finger's name (str) or its index (int)",
                finger.repr()?
            )));
        };
        let from_end = if k < 0 { n as i64 + k } else { k };
        usize::try_from(from_end)
            .ok()
            .filter(|&i| i < n)
            .ok_or_else(|| missing(k.to_string()))
    }

    /// The scene of `text`, the files it names read relative to `base` (the scene file's
    /// folder; the working folder for a dict or JSON text), the fingers of `arrays` taking
    /// their height maps from there.
    fn parse(
        py: Python<'_>,
        text: &str,
        origin: String,
        base: &std::path::Path,
        arrays: &grasp_io::HeightArrays,
    ) -> PyResult<Scene> {
        let mut inputs = grasp_io::RunInputs::new();
        let read = grasp_io::scene_from_json_str_with_arrays;
        match read(text, base, arrays, &mut inputs) {
            Ok(scene) => Ok(Scene {
                scene,
                origin,
                inputs,
            }),
            Err(e) => Err(scene_error(py, &origin, &e)),
        }
    }
}

/// The scene format's name of a model.
pub fn model_name(m: grasp_model::ModelKind) -> &'static str {
    match m {
        grasp_model::ModelKind::Energy => "energy",
        grasp_model::ModelKind::Coulomb => "coulomb",
    }
}

/// The model named `name` (`"energy"` or `"coulomb"`).
pub fn parse_model(name: &str) -> PyResult<grasp_model::ModelKind> {
    match name {
        "energy" => Ok(grasp_model::ModelKind::Energy),
        "coulomb" => Ok(grasp_model::ModelKind::Coulomb),
        other => Err(pyo3::exceptions::PyValueError::new_err(format!(
            "model={other:?}: choose \"energy\" or \"coulomb\""
        ))),
    }
}
