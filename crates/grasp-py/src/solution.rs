//! `grasp.Solution`: the answer of one solve. Scalars and per-finger resultants as Python
//! values (the CLI's JSON field names), element fields as NumPy arrays over all elements of
//! all fingers, scene order then row-major within a patch. Arrays are made when asked for.

use grasp_model::FingerSolution;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{float_array, int_array, state_array};
use crate::json_value::serialize_to_py;

/// The answer of one solve (SI units). Solver outcomes are its `status`, never exceptions:
/// `"solved"`, `"reduced_accuracy"`, `"no_equilibrium"` (the fingers cannot hold the object;
/// `reason` says why) or `"no_convergence"`.
#[pyclass(module = "grasp", frozen)]
pub struct Solution {
    pub(crate) solution: grasp_model::Solution,
    /// Unit tangents `(t1, t2)` of each finger of `solution.fingers`, world frame.
    pub(crate) tangents: Vec<([f64; 3], [f64; 3])>,
    /// Time to build the model from the scene (influence matrices), s.
    pub(crate) build_time_s: f64,
    /// When a viscoelastic scene was solved (`None` for an elastic one, or a hand-off step's
    /// solution): written as `"time"` by `to_dict` and `to_json`, as `grasp solve --json`
    /// does.
    pub(crate) time: Option<grasp_model::TimePoint>,
    /// The readings of the fingers' tactile sensors (empty when the scene has none, or the
    /// solve found no forces).
    pub(crate) sensors: Vec<grasp_model::SensorReadings>,
}

#[pymethods]
impl Solution {
    /// `"solved"`, `"reduced_accuracy"`, `"no_equilibrium"` or `"no_convergence"`.
    #[getter]
    fn status(&self) -> &'static str {
        self.solution.status.as_str()
    }

    /// True when the solution carries forces (solved, or solved to reduced accuracy).
    #[getter]
    fn has_forces(&self) -> bool {
        self.solution.status.has_forces()
    }

    /// Why, when the status is not `"solved"` (else None).
    #[getter]
    fn reason(&self) -> Option<String> {
        self.solution.reason.clone()
    }

    /// Things to know about the answer: first the scene's (`Scene.warnings`: a patch over
    /// an edge, overlapping patches, an open mesh; whatever the status), then the solve's
    /// own (undersized patches, ...). The CLI's JSON and batch lines carry the same list.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.solution.warnings.clone()
    }

    /// Finger names of the element arrays' `finger` index, scene order.
    #[getter]
    fn finger_names(&self) -> Vec<String> {
        self.solution
            .fingers
            .iter()
            .map(|f| f.name.clone())
            .collect()
    }

    /// Per-finger resultants, scene order: dicts with `name`, `normal_force_n`,
    /// `tangential_force_n` (world, N), `torsional_moment_nm`, `center_of_pressure_m`,
    /// `contact_area_m2`, `friction_utilization`, `stick_count`, ... (the CLI's JSON fields,
    /// without the element list; see the element arrays).
    #[getter]
    fn fingers<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        self.solution
            .fingers
            .iter()
            .map(|f| {
                // The resultants alone: the elements are handed out as arrays.
                let resultants = FingerSolution {
                    name: f.name.clone(),
                    elements: Vec::new(),
                    ..*f
                };
                let d = serialize_to_py(py, &resultants)?;
                d.downcast::<PyDict>()?.del_item("elements")?;
                Ok(d)
            })
            .collect()
    }

    /// Each finger's total normal force `P_i`, N, shape `(F,)`, in `finger_names` order.
    #[getter]
    fn finger_normal_forces_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<f64> = self
            .solution
            .fingers
            .iter()
            .map(|f| f.normal_force_n)
            .collect();
        float_array(py, &v, &[v.len()])
    }

    /// Residuals computed from the solution (dict of relative and absolute residuals), or
    /// None without forces.
    #[getter]
    fn residuals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        serialize_to_py(py, &self.solution.residuals)
    }

    /// Solver statistics: `solver` (`"native"` or `"clarabel"`), `fallback`, `iterations`,
    /// `factorizations`, `solver_time_s`, `unknowns`, `equality_rows`, `cone_rows`.
    #[getter]
    fn solver<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        serialize_to_py(py, &self.solution.solver)
    }

    /// The sequential (fixed-point) solve's report, or None for one convex program.
    #[getter]
    fn sequential<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        serialize_to_py(py, &self.solution.sequential)
    }

    /// Per hand (`hands`), a dict: `name`, `force_n` and `moment_nm` (what its fingers put on
    /// the object, about its origin), `translation_m` and `rotation_rad` (how its base moved
    /// from its commanded pose); empty without hands.
    #[getter]
    fn hands<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        serialize_to_py(py, &self.solution.hands)
    }

    /// Per servo (`servos`), a dict: `name`, `force_n` (the sum of its jaws' normal forces)
    /// and `travel_m` (their travel from the command, negative: pushed back); empty without
    /// servos.
    #[getter]
    fn servos<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        serialize_to_py(py, &self.solution.servos)
    }

    /// Load scale that normalises the residuals, N.
    #[getter]
    fn load_scale_n(&self) -> f64 {
        self.solution.load_scale_n
    }

    /// Wall time of the solve (program assembly, solver, readout), s.
    #[getter]
    fn solve_time_s(&self) -> f64 {
        self.solution.solve_time_s
    }

    /// Time to build the model from the scene (influence matrices), s.
    #[getter]
    fn build_time_s(&self) -> f64 {
        self.build_time_s
    }

    /// Index into `finger_names` of each element, shape `(N,)`.
    #[getter]
    fn finger<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<i64> = self.per_finger(|i, _| i as i64);
        int_array(py, &v, &[v.len()])
    }

    /// Element centres, world frame, m, shape `(N, 3)`.
    #[getter]
    fn positions_m<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.vectors(py, |_, e| e.position_m)
    }

    /// Element normal forces `F_k` along the finger's inward normal, N, shape `(N,)`.
    #[getter]
    fn normal_forces_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.scalars(py, |e| e.normal_force_n)
    }

    /// Element friction forces `G_k`, world frame, N, shape `(N, 3)`.
    #[getter]
    fn tangential_forces_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.vectors(py, |(t1, t2), e| {
            let g = e.tangential_force_n;
            std::array::from_fn(|a| g[0] * t1[a] + g[1] * t2[a])
        })
    }

    /// Element friction forces along the finger's `[t1, t2]`, N, shape `(N, 2)`.
    #[getter]
    fn tangential_forces_local_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<f64> = self.flat(|e| e.tangential_force_n.to_vec());
        float_array(py, &v, &[v.len() / 2, 2])
    }

    /// Element mean pressures `F_k / A`, Pa, shape `(N,)`.
    #[getter]
    fn pressures_pa<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.scalars(py, |e| e.pressure_pa)
    }

    /// Element gaps after loading, m, shape `(N,)`.
    #[getter]
    fn gaps_m<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.scalars(py, |e| e.gap_m)
    }

    /// Element slips along `[t1, t2]`, m, shape `(N, 2)` (coulomb: accumulated).
    #[getter]
    fn slips_m<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<f64> = self.flat(|e| e.slip_m.to_vec());
        float_array(py, &v, &[v.len() / 2, 2])
    }

    /// Element states, shape `(N,)`: `"stick"`, `"slip"`, `"separated"`, `"off_surface"`, or
    /// `"frictionless"` (in contact on a frictionless finger: neither stick nor slip).
    #[getter]
    fn states<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let states = self.solution.fingers.iter().flat_map(|f| &f.elements);
        state_array(py, states.map(|e| e.state))
    }

    /// The whole solution as a dict, field for field the JSON of `grasp solve --json`.
    ///
    /// Returns
    /// -------
    /// dict
    ///     Status, residuals, solver report and every finger with its elements (SI units,
    ///     names carry them: `normal_force_n`, `pressure_pa`, `gap_m`, ...).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        serialize_to_py(py, &self.record())
    }

    /// The whole solution as JSON text, the same as `grasp solve --json` writes.
    ///
    /// Returns
    /// -------
    /// str
    ///     The JSON of `to_dict`.
    fn to_json(&self) -> PyResult<String> {
        let mut text = Vec::new();
        grasp_io::write_solution_json(&mut text, &self.record())
            .map_err(crate::errors::grasp_error)?;
        String::from_utf8(text).map_err(crate::errors::grasp_error)
    }

    /// One finger's element fields as NumPy arrays, as `grasp solve --npz` writes them.
    ///
    /// Parameters
    /// ----------
    /// finger : str
    ///     The finger's name (one of `finger_names`).
    ///
    /// Returns
    /// -------
    /// dict of str to numpy.ndarray
    ///     By field name, element order `k = i ny + j`: `index` int64 `(N, 2)`, `local_m`
    ///     `(N, 2)`, `position_m` `(N, 3)`, `normal_force_n`, `pressure_pa`, `gap_m` `(N,)`,
    ///     `tangential_force_n` (N), `traction_pa`, `slip_m`, `step_slip_m` (m) along
    ///     `[t1, t2]` `(N, 2)`, `state` strings `(N,)`, and `viscous_displacement_m` `(N, 3)`
    ///     on a viscoelastic contact; `grid` int64 `(2,)`, the patch's `[nx, ny]` (a field
    ///     reshaped to `(nx, ny)` is the patch's map).
    ///
    /// Raises
    /// ------
    /// KeyError
    ///     `finger` is not in `finger_names`.
    fn element_fields<'py>(&self, py: Python<'py>, finger: &str) -> PyResult<Bound<'py, PyDict>> {
        let f = self.solution.finger(finger).ok_or_else(|| {
            pyo3::exceptions::PyKeyError::new_err(format!(
                "no finger `{finger}` in this solution; its fingers: {:?}",
                self.finger_names()
            ))
        })?;
        crate::element_fields::element_fields(py, &f.elements)
    }

    /// The tactile sensor's readings of `finger` (`fingers[i].sensor`; docs/guide/tactile.md),
    /// as NumPy arrays over its grids, `i` along the grid's first side.
    ///
    /// Parameters
    /// ----------
    /// finger : str
    ///     The finger's name (one of `finger_names` with a `sensor` in the scene).
    ///
    /// Returns
    /// -------
    /// dict
    ///     `"taxels"` (when the sensor has taxels): `force_n` `(nx, ny, 3)` (normal, t1, t2;
    ///     N), `centre_m` `(nx, ny, 2)` (along t1, t2 from the contact point; m), `depth_m`
    ///     and `size_m` (floats, m); `"markers"` (when it has markers): `displacement_m`
    ///     `(nx, ny, 3)` (normal into the finger, t1, t2; m) and `position_m` `(nx, ny, 2)`;
    ///     `"gel"` (when it has a gel image): `height_m` `(nx, ny)` (m, into the pad),
    ///     `normal` `(nx, ny, 3)` (u, v, w toward the camera), `rgb` `(nx, ny, 3)` (in
    ///     [0, 1]), `position_m` `(nx, ny, 2)` (the pixels' centres), `pixel_m` (the pitch)
    ///     and `path` (how the height map was read: `"lattice"`, `"dense"` or `"flat"`).
    ///
    /// Raises
    /// ------
    /// KeyError
    ///     `finger` has no sensor, or is not in this solution (released, or no forces).
    fn sensor<'py>(&self, py: Python<'py>, finger: &str) -> PyResult<Bound<'py, PyDict>> {
        let r = self
            .sensors
            .iter()
            .find(|s| s.finger == finger)
            .ok_or_else(|| {
                let read: Vec<&str> = self.sensors.iter().map(|s| s.finger.as_str()).collect();
                pyo3::exceptions::PyKeyError::new_err(format!(
                "no sensor readings of `{finger}` in this solution; the fingers read: {read:?} \
                 (give the finger a `sensor` in the scene)"
            ))
            })?;
        crate::sensor_arrays::sensor_arrays(py, r)
    }

    /// Writes every finger's element fields to a `.npz` file, as `grasp solve --npz` does.
    ///
    /// Read it back with `numpy.load(path)["f1/pressure_pa"]` (the fields of
    /// `element_fields`, under `<finger>/`).
    ///
    /// Parameters
    /// ----------
    /// path : str or os.PathLike
    ///     The file to write; its folder must exist.
    /// overwrite : bool, default False
    ///     Replace an existing file.
    ///
    /// Returns
    /// -------
    /// None
    ///
    /// Raises
    /// ------
    /// FileExistsError
    ///     The file exists and `overwrite` is False.
    /// FileNotFoundError
    ///     The folder does not exist.
    /// ValueError
    ///     The path is not a file one may write (a folder, a link, a device).
    /// GraspError
    ///     Another run is writing the file.
    /// OSError
    ///     The file system refused the write.
    #[pyo3(signature = (path, *, overwrite=false))]
    fn to_npz(&self, py: Python<'_>, path: std::path::PathBuf, overwrite: bool) -> PyResult<()> {
        let targets = [("path", path.as_path())];
        let set = crate::outputs::claim(&targets, &grasp_io::RunInputs::default(), overwrite)?;
        py.allow_threads(|| -> Result<(), grasp_io::OutputError> {
            let pending = set.create(&path)?;
            grasp_io::write_solution_npz(&pending, &self.solution, &self.sensors)?;
            set.commit(vec![pending])
        })
        .map_err(|e| crate::outputs::output_error(&targets, &e))
    }

    fn __repr__(&self) -> String {
        let forces: Vec<String> = self
            .solution
            .fingers
            .iter()
            .map(|f| format!("{} {:.6} N", f.name, f.normal_force_n))
            .collect();
        format!("Solution({}: {})", self.status(), forces.join(", "))
    }
}

type Element = grasp_model::ElementSolution;
/// Unit tangents `(t1, t2)` of a finger, world frame.
pub type Tangents = ([f64; 3], [f64; 3]);

impl Solution {
    /// What the solution's JSON holds: the solution, with the solve's time for a
    /// viscoelastic scene.
    fn record(&self) -> grasp_io::SolutionRecord<'_> {
        grasp_io::SolutionRecord {
            solution: &self.solution,
            time: self.time,
            sensitivities: None,
            sensors: (!self.sensors.is_empty()).then_some(self.sensors.as_slice()),
        }
    }

    fn fingers_with_tangents(&self) -> impl Iterator<Item = (usize, &FingerSolution, &Tangents)> {
        self.solution
            .fingers
            .iter()
            .zip(&self.tangents)
            .enumerate()
            .map(|(i, (f, t))| (i, f, t))
    }

    /// `f(finger index, element)` over every element, scene order.
    fn per_finger<T>(&self, f: impl Fn(usize, &Element) -> T) -> Vec<T> {
        self.fingers_with_tangents()
            .flat_map(|(i, fs, _)| fs.elements.iter().map(move |e| (i, e)))
            .map(|(i, e)| f(i, e))
            .collect()
    }

    fn flat(&self, f: impl Fn(&Element) -> Vec<f64>) -> Vec<f64> {
        self.per_finger(|_, e| f(e)).concat()
    }

    fn scalars<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&Element) -> f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        let v = self.per_finger(|_, e| f(e));
        float_array(py, &v, &[v.len()])
    }

    fn vectors<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&Tangents, &Element) -> [f64; 3],
    ) -> PyResult<Bound<'py, PyAny>> {
        let f = &f;
        let v: Vec<f64> = self
            .fingers_with_tangents()
            .flat_map(|(_, fs, t)| fs.elements.iter().flat_map(move |e| f(t, e)))
            .collect();
        float_array(py, &v, &[v.len() / 3, 3])
    }
}

/// The unit tangents `(t1, t2)` of every finger of `scene`, world frame, by name: the frames
/// the model builds (`ContactFrame::new` on the scene's point, normal, tangent and plane),
/// without building the model.
pub fn tangents_by_name(
    scene: &grasp_model::Scene,
) -> std::collections::BTreeMap<String, Tangents> {
    let v3 = |a: &[f64; 3]| nalgebra::Vector3::new(a[0], a[1], a[2]);
    let arr = |v: &nalgebra::Vector3<f64>| [v.x, v.y, v.z];
    let plane = scene.planar.as_ref().map(|p| v3(&p.normal));
    scene
        .fingers
        .iter()
        .map(|f| {
            let frame = grasp_model::ContactFrame::new(
                v3(&f.contact_point),
                v3(&f.normal),
                f.tangent.as_ref().map(v3),
                plane,
            );
            (f.name.clone(), (arr(&frame.t1), arr(&frame.t2)))
        })
        .collect()
}
