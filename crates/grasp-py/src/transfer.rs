//! `grasp.transfer`: a hand-off run by the library's driver exactly as `grasp transfer`
//! runs it (same schedule format, same MCAP, Rerun and CSV files), returning the force
//! histories as NumPy arrays (time x finger). The GIL is released while the driver runs.

use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};

use grasp_transfer::{
    Command, CsvSink, McapSink, RerunSink, Schedule, Sink, StepRecord, TransferOptions,
    TransferSummary,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::arrays::{float_array, int_array, str_array};
use crate::errors::{grasp_error, schedule_error};
use crate::json_value::serialize_to_py;
use crate::outputs::{check_targets, Pending};
use crate::scene::Scene;
use crate::solution::{tangents_by_name, Solution, Tangents};

/// Runs the load schedule `schedule` (a path, a dict or JSON text of the schedule format of
/// `grasp schema --schedule`) over `scene`, step by step, each step warm-started from the
/// previous one (thesis section 4.2.2: the releasing fingers' normal forces ramped down).
///
/// - `mcap`, `rrd`, `csv`: paths of the files to write, the same as `grasp transfer`'s.
///   Existing files are replaced only with `overwrite=True`; files appear only when the run
///   completes (with a failed step: only with `keep_going=True`).
/// - `solver`: `"auto"`, `"native"` or `"clarabel"`; `cold=True` starts every step cold.
/// - `keep_going`: continue past a step without equilibrium (default: stop there).
/// - `margins`: compute each step's smallest disturbance margin (costly).
///
/// CSV paths inside a schedule file are read relative to its folder (to the working folder
/// for a dict or JSON text).
#[pyfunction]
#[pyo3(signature = (scene, schedule, *, mcap=None, rrd=None, csv=None, solver="auto",
                    cold=false, keep_going=false, margins=false, overwrite=false))]
#[allow(clippy::too_many_arguments)]
pub fn transfer(
    py: Python<'_>,
    scene: &Scene,
    schedule: &Bound<'_, PyAny>,
    mcap: Option<PathBuf>,
    rrd: Option<PathBuf>,
    csv: Option<PathBuf>,
    solver: &str,
    cold: bool,
    keep_going: bool,
    margins: bool,
    overwrite: bool,
) -> PyResult<Transfer> {
    let options = TransferOptions {
        keep_going,
        warm_start: !cold,
        solve: crate::solve::solve_options(solver, 1e-10)?,
        margins,
    };
    let (schedule, schedule_path) = load_schedule(py, scene, schedule)?;
    let targets: Vec<(&str, &Path)> = [("mcap", &mcap), ("rrd", &rrd), ("csv", &csv)]
        .into_iter()
        .filter_map(|(n, p)| p.as_deref().map(|p| (n, p)))
        .collect();
    let inputs: Vec<&Path> = schedule_path.iter().map(PathBuf::as_path).collect();
    check_targets(&targets, &inputs, overwrite)?;
    let files = Files {
        mcap: mcap.as_deref().map(Pending::new),
        rrd: rrd.as_deref().map(Pending::new),
        csv: csv.as_deref().map(Pending::new),
    };
    let run = py.allow_threads(|| run_transfer(&scene.scene, &schedule, options, files));
    let (records, summary, written) = run.map_err(grasp_error)?;
    let tangents = tangents_by_name(&scene.scene);
    Ok(Transfer {
        names: scene.scene.fingers.iter().map(|f| f.name.clone()).collect(),
        records,
        summary,
        tangents,
        written,
    })
}

/// The schedule resolved against the scene, and its file when it came from one.
fn load_schedule(
    py: Python<'_>,
    scene: &Scene,
    source: &Bound<'_, PyAny>,
) -> PyResult<(Schedule, Option<PathBuf>)> {
    let (text, origin, base, path) = if let Ok(d) = source.downcast::<PyDict>() {
        let text: String = py.import("json")?.call_method1("dumps", (d,))?.extract()?;
        (text, "<dict>".to_string(), PathBuf::new(), None)
    } else if let Some(t) = json_text(source)? {
        (t, "<json>".to_string(), PathBuf::new(), None)
    } else {
        let path: PathBuf = source.extract().map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err("schedule: expected a path, a dict or JSON text")
        })?;
        let text = std::fs::read_to_string(&path).map_err(|e| {
            pyo3::exceptions::PyOSError::new_err(format!(
                "cannot read schedule file {}: {e}",
                path.display()
            ))
        })?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        (text, path.display().to_string(), base, Some(path))
    };
    let names: Vec<String> = scene.scene.fingers.iter().map(|f| f.name.clone()).collect();
    Schedule::from_json_str(&text, &names, &base)
        .map(|s| (s, path))
        .map_err(|e| schedule_error(py, &origin, &e))
}

/// The text of `source` when it is a str holding JSON (first non-blank character `{`).
fn json_text(source: &Bound<'_, PyAny>) -> PyResult<Option<String>> {
    if !source.is_instance_of::<PyString>() {
        return Ok(None);
    }
    let text: String = source.extract()?;
    Ok(text.trim_start().starts_with('{').then_some(text))
}

/// The output files of a run, each under its temporary name.
struct Files {
    mcap: Option<Pending>,
    rrd: Option<Pending>,
    csv: Option<Pending>,
}

type RunResult = (Vec<StepRecord>, TransferSummary, Vec<String>);

/// The driver with the sinks asked for; commits the files when the run is complete.
fn run_transfer(
    scene: &grasp_model::Scene,
    schedule: &Schedule,
    options: TransferOptions,
    files: Files,
) -> Result<RunResult, String> {
    let create =
        |p: &Pending| File::create(&p.tmp).map_err(|e| format!("{}: {e}", p.target.display()));
    let mut mcap = match &files.mcap {
        Some(p) => Some(McapSink::from_file(create(p)?, &p.target).map_err(|e| e.to_string())?),
        None => None,
    };
    let mut rrd = match &files.rrd {
        Some(p) => Some(RerunSink::create_as(&p.tmp, &p.target).map_err(|e| e.to_string())?),
        None => None,
    };
    let mut csv = match &files.csv {
        Some(p) => Some(CsvSink::from_file(create(p)?, &p.target)),
        None => None,
    };
    let mut sinks: Vec<&mut dyn Sink> = Vec::new();
    if let Some(s) = mcap.as_mut() {
        sinks.push(s);
    }
    if let Some(s) = rrd.as_mut() {
        sinks.push(s);
    }
    if let Some(s) = csv.as_mut() {
        sinks.push(s);
    }
    let (records, summary) = grasp_transfer::run_collect(scene, schedule, options, &mut sinks)
        .map_err(|e| e.to_string())?;
    drop(sinks);
    drop((mcap, rrd, csv));
    let complete = summary.failed_step_count == 0 || options.keep_going;
    let mut written = Vec::new();
    for p in [files.mcap, files.rrd, files.csv].into_iter().flatten() {
        if complete {
            let target = p.target.display().to_string();
            p.commit().map_err(|e| format!("{target}: {e}"))?;
            written.push(target);
        }
    }
    Ok((records, summary, written))
}

/// A hand-off's result: per step (time) and finger, the forces the driver computed.
/// Released fingers carry 0 N; failed steps carry 0 N for every finger (see `statuses`).
#[pyclass(module = "grasp", frozen)]
pub struct Transfer {
    names: Vec<String>,
    records: Vec<StepRecord>,
    summary: TransferSummary,
    tangents: BTreeMap<String, Tangents>,
    written: Vec<String>,
}

#[pymethods]
impl Transfer {
    /// Scene finger names: the columns of the `(T, F)` arrays.
    #[getter]
    fn finger_names(&self) -> Vec<String> {
        self.names.clone()
    }

    /// Step times, s, shape `(T,)`.
    #[getter]
    fn times_s<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<f64> = self.records.iter().map(|r| r.time_s).collect();
        float_array(py, &v, &[v.len()])
    }

    /// Finger normal forces `P_i`, N, shape `(T, F)`.
    #[getter]
    fn normal_forces_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v = self.per_finger(|r, name| r.normal_force_n(name));
        float_array(py, &v, &[self.records.len(), self.names.len()])
    }

    /// Finger friction forces `Q_i`, world frame, N, shape `(T, F, 3)`.
    #[getter]
    fn tangential_forces_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<f64> = self
            .records
            .iter()
            .flat_map(|r| self.names.iter().flat_map(move |n| tangential(r, n)))
            .collect();
        float_array(py, &v, &[self.records.len(), self.names.len(), 3])
    }

    /// Commanded normal loads, N, shape `(T, F)`: NaN for a held finger, 0 when released.
    #[getter]
    fn commanded_loads_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v = self.per_finger(|r, name| {
            match r
                .commands
                .iter()
                .find(|c| c.name == name)
                .map(|c| &c.command)
            {
                Some(Command::Load(l)) => *l,
                Some(Command::Released) => 0.0,
                _ => f64::NAN,
            }
        });
        float_array(py, &v, &[self.records.len(), self.names.len()])
    }

    /// Scheduled external force at the centre of mass, N, shape `(T, 3)`.
    #[getter]
    fn external_forces_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<f64> = self
            .records
            .iter()
            .flat_map(|r| r.external_force_n)
            .collect();
        float_array(py, &v, &[self.records.len(), 3])
    }

    /// Each step's status (`"solved"`, `"no_equilibrium"`, ...), shape `(T,)`.
    #[getter]
    fn statuses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<&str> = self
            .records
            .iter()
            .map(|r| r.solution.status.as_str())
            .collect();
        str_array(py, &v)
    }

    /// Wall time of each step (model building when the structure changed, solve), s, `(T,)`.
    #[getter]
    fn wall_times_s<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<f64> = self.records.iter().map(|r| r.wall_time_s).collect();
        float_array(py, &v, &[v.len()])
    }

    /// Solver iterations of each step, shape `(T,)`.
    #[getter]
    fn iterations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<i64> = self
            .records
            .iter()
            .map(|r| i64::from(r.solution.solver.iterations))
            .collect();
        int_array(py, &v, &[v.len()])
    }

    /// Each step's smallest disturbance margin, N, shape `(T,)` (NaN where not computed:
    /// without `margins=True`, or at a failed step).
    #[getter]
    fn smallest_margins_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: Vec<f64> = self
            .records
            .iter()
            .map(|r| r.margin.as_ref().map_or(f64::NAN, |m| m.smallest_n))
            .collect();
        float_array(py, &v, &[v.len()])
    }

    /// The closing summary (the fields `grasp transfer` prints), as a dict.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        serialize_to_py(py, &self.summary)
    }

    /// The files written (paths), in the order mcap, rrd, csv; empty when a failed step
    /// stopped the run (existing files are then untouched).
    #[getter]
    fn written(&self) -> Vec<String> {
        self.written.clone()
    }

    /// The full solution of step `index` (element arrays included).
    fn step(&self, index: isize) -> PyResult<Solution> {
        let n = self.records.len() as isize;
        let i = if index < 0 { index + n } else { index };
        let r = usize::try_from(i)
            .ok()
            .and_then(|i| self.records.get(i))
            .ok_or_else(|| {
                pyo3::exceptions::PyIndexError::new_err(format!("step {index} of {n}"))
            })?;
        let tangents = r
            .solution
            .fingers
            .iter()
            .map(|f| {
                self.tangents
                    .get(&f.name)
                    .copied()
                    .unwrap_or(([0.0; 3], [0.0; 3]))
            })
            .collect();
        let mut solution = r.solution.clone();
        crate::keywords::respell_solution(&mut solution);
        Ok(Solution {
            solution,
            tangents,
            build_time_s: 0.0,
        })
    }

    fn __len__(&self) -> usize {
        self.records.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Transfer({} steps, {} fingers, {} failed)",
            self.records.len(),
            self.names.len(),
            self.summary.failed_step_count
        )
    }
}

impl Transfer {
    /// `f(step, finger name)` over steps then fingers.
    fn per_finger(&self, f: impl Fn(&StepRecord, &str) -> f64) -> Vec<f64> {
        self.records
            .iter()
            .flat_map(|r| self.names.iter().map(move |n| (r, n)))
            .map(|(r, n)| f(r, n))
            .collect()
    }
}

fn tangential(r: &StepRecord, name: &str) -> [f64; 3] {
    r.solution
        .finger(name)
        .map_or([0.0; 3], |f| f.tangential_force_n)
}
