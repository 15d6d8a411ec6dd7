//! `grasp.transfer`: a hand-off run by the library's driver exactly as `grasp transfer`
//! runs it (same schedule format, same MCAP, Rerun and CSV files, written through the same
//! output policy), returning the force histories as NumPy arrays (time x finger). The GIL is
//! released while the driver runs. Steps stream as in the CLI: the histories are kept
//! compactly, every step's full solution only while it fits `max_memory` (checked before
//! the run; `keep_solutions=False` keeps the last step's only).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use grasp_io::{OutputError, OutputSet, RunInputs, SCHEDULE_FILE};
use grasp_transfer::{
    McapProfile, OpenError, OutputFiles, OutputPaths, Schedule, StepRecord, TransferOptions,
    TransferSummary,
};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyInt, PyString};

use crate::arrays::{float_array, int_array, str_array};
use crate::errors::{grasp_error, schedule_error, GraspError};
use crate::histories::{solution_bytes_per_step, Histories};
use crate::json_value::serialize_to_py;
use crate::outputs::{claim, output_error};
use crate::scene::Scene;
use crate::solution::{tangents_by_name, Solution, Tangents};

/// The MCAP profile `name` with its start time `start_s` (s after the Unix epoch; ros2 only)
/// of an MCAP that is written when `mcap` (as the CLI, which refuses them without `--mcap`).
fn profile(name: &str, start_s: Option<f64>, mcap: bool) -> PyResult<McapProfile> {
    let bad = |m: String| pyo3::exceptions::PyValueError::new_err(m);
    if !mcap && (name != "json" || start_s.is_some()) {
        return Err(bad(
            "mcap_profile= and ros2_start_time= describe the MCAP file: give mcap= too".into(),
        ));
    }
    match (name, start_s) {
        ("json", None) => Ok(McapProfile::Json),
        ("json", Some(_)) => Err(bad(
            "ros2_start_time= applies to the ros2 MCAP profile: add mcap_profile=\"ros2\"".into(),
        )),
        ("ros2", t) => McapProfile::ros2_from(t.unwrap_or(0.0))
            .map_err(|why| bad(format!("ros2_start_time={}: {why}", t.unwrap_or(0.0)))),
        (other, _) => Err(bad(format!(
            "mcap_profile={other:?}: give \"json\" (Foxglove's JSON messages) or \"ros2\" (ROS 2 \
             messages, CDR)"
        ))),
    }
}

/// `progress=` is callable (or absent).
fn check_progress(py: Python<'_>, progress: Option<&Py<PyAny>>) -> PyResult<()> {
    if progress.is_some_and(|p| !p.bind(py).is_callable()) {
        return Err(pyo3::exceptions::PyTypeError::new_err(
            "progress= is not callable: give a function progress(done, total), or None",
        ));
    }
    Ok(())
}

/// Runs a hand-off: a load schedule over a scene, step by step, as `grasp transfer` does.
///
/// Each step is warm-started from the previous one (thesis section 4.2.2: the releasing
/// fingers' normal forces ramped down while the others take the load). The GIL is released
/// while the driver runs; Ctrl-C stops the run between steps.
///
/// Parameters
/// ----------
/// scene : Scene
///     The validated grasp (SI units), from `grasp.Scene`.
/// schedule : str, os.PathLike or dict
///     The load schedule: a path to a schedule file, a dict, or its JSON text (the format of
///     docs/schedule.schema.json: times in s, loads in N, approaches in m). CSV paths inside
///     a schedule file are read relative to its folder (to the working folder for a dict or
///     JSON text).
/// mcap, rrd, csv, npz : str or os.PathLike, optional
///     Files to write, the same as `grasp transfer`'s: a Foxglove MCAP, a Rerun recording,
///     the per-step CSV, and every step's element fields (`step_<k>/<finger>/<field>`). An
///     existing file is replaced only with `overwrite=True` (never a folder, a link, a device
///     or an input of the run); files appear only when the run completes (after a failed
///     step: only with `keep_going=True`); a second run writing the same file is refused
///     while this one runs.
/// mcap_profile : {"json", "ros2"}, default "json"
///     What the MCAP holds: JSON messages with JSON Schemas (Foxglove), or CDR-encoded ROS 2
///     messages with ros2msg schemas as `ros2 bag record` writes them (docs/guide/outputs.md,
///     "ROS 2"), as `grasp transfer --mcap-profile`.
/// ros2_start_time : float, optional
///     With `mcap_profile="ros2"`: the stamp of the schedule's time 0, in seconds after the
///     Unix epoch (default 0), as `grasp transfer --ros2-start-time`.
/// solver : {"auto", "native", "clarabel"}, default "auto"
///     The solver of every step, as in `solve`.
/// cold : bool, default False
///     Start every step cold (and search every step's margins from scratch).
/// keep_going : bool, default False
///     Continue past a step without equilibrium (default: stop there).
/// margins : bool, default False
///     Compute each step's smallest disturbance margin, N (costly: a search per step).
/// overwrite : bool, default False
///     Replace existing output files.
/// keep_solutions : bool, default True
///     Keep every step's full solution for `Transfer.step`; with False only the histories
///     and the last step are kept.
/// max_memory : int, optional
///     The most memory, bytes (in [1, 2**64 - 1]), the kept solutions may take; the run is
///     refused before it starts when they need more. Default: a quarter of the machine's
///     memory.
/// compliance : {"auto", "dense", "fft"}, default "auto"
///     As in `solve` (docs/guide/solving.md, "Fine patches").
/// progress : callable, optional
///     `progress(done, total)`, called after each step (a `tqdm`'s `update` wrapped, say);
///     an exception it raises stops the run, and no output file is written then.
///
/// Returns
/// -------
/// Transfer
///     The force histories, time x finger (N, s), each step's status, the closing summary,
///     the files written, and the steps' full solutions (`Transfer.step`).
///
/// Raises
/// ------
/// ScheduleError
///     The schedule is not valid for the scene (`problems` lists each with its JSON path and
///     fix).
/// ValueError
///     An option out of range or misspelt (the message names the keyword), or an output
///     that may not be written (a folder, a link, an input of the run, one path twice).
/// TypeError
///     `progress` is not callable, or `max_memory` is not an int.
/// FileExistsError
///     An output exists and `overwrite` is False.
/// FileNotFoundError
///     An output's folder does not exist.
/// GraspError
///     The kept solutions would exceed `max_memory`, another run is writing an output, or
///     the driver failed (the message says why, and the fix).
/// KeyboardInterrupt
///     Ctrl-C during the run (no output is written); whatever `progress` raised propagates
///     the same way.
///
/// Examples
/// --------
/// >>> run = grasp.transfer(grasp.Scene("examples/plate_transfer.json"),
/// ...                      "examples/plate_transfer.schedule.json", mcap="out.mcap")
/// >>> run.times_s, run.normal_forces_n
#[pyfunction]
#[pyo3(signature = (scene, schedule, *, mcap=None, rrd=None, csv=None, npz=None,
                    mcap_profile="json", ros2_start_time=None, solver="auto",
                    cold=false, keep_going=false, margins=false, overwrite=false,
                    keep_solutions=true, max_memory=None, compliance="auto", progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn transfer(
    py: Python<'_>,
    scene: &Scene,
    schedule: &Bound<'_, PyAny>,
    mcap: Option<PathBuf>,
    rrd: Option<PathBuf>,
    csv: Option<PathBuf>,
    npz: Option<PathBuf>,
    mcap_profile: &str,
    ros2_start_time: Option<f64>,
    solver: &str,
    cold: bool,
    keep_going: bool,
    margins: bool,
    overwrite: bool,
    keep_solutions: bool,
    max_memory: Option<&Bound<'_, PyAny>>,
    compliance: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<Transfer> {
    check_progress(py, progress.as_ref())?;
    let max_memory = max_memory.map(memory_limit).transpose()?;
    let mcap_profile = profile(mcap_profile, ros2_start_time, mcap.is_some())?;
    let mut solve = crate::solve::solve_options(solver, 1e-10)?;
    solve.compliance = crate::solve::compliance_choice(compliance)?;
    let options = TransferOptions {
        keep_going,
        warm_start: !cold,
        solve,
        margins,
        margins_from_scratch: cold,
        margin_threshold_n: None,
        sensitivities: false,
        ..TransferOptions::default()
    };
    let (schedule, mut inputs) = load_schedule(py, scene, schedule)?;
    inputs.extend(&scene.inputs);
    check_memory(&scene.scene, &schedule, keep_solutions, max_memory)?;
    let named = [("mcap", &mcap), ("rrd", &rrd), ("csv", &csv), ("npz", &npz)];
    let targets: Vec<(&str, &Path)> = named
        .into_iter()
        .filter_map(|(n, p)| p.as_deref().map(|p| (n, p)))
        .collect();
    let outputs = claim(&targets, &inputs, overwrite)?;
    let files = OutputPaths {
        mcap: mcap.as_deref(),
        mcap_profile,
        rrd: rrd.as_deref(),
        csv: csv.as_deref(),
        npz: npz.as_deref(),
    };
    let run = py.allow_threads(|| {
        run_transfer(
            &scene.scene,
            &schedule,
            options,
            &outputs,
            files,
            Following {
                keep_solutions,
                progress: progress.as_ref(),
            },
            &recording_name(&scene.origin),
        )
    });
    let kept = run.map_err(|e| match e {
        RunError::Output(e) => output_error(&targets, &e),
        RunError::Driver(e) => grasp_error(e),
        RunError::Stopped(e) => e,
    })?;
    Ok(Transfer {
        histories: kept.histories,
        records: kept.records,
        last: kept.last,
        summary: kept.summary,
        tangents: tangents_by_name(&scene.scene),
        written: kept.written,
    })
}

/// Largest `max_memory=`, bytes.
const MAX_MEMORY_LIMIT: u64 = u64::MAX;

/// `max_memory=` as bytes: an int in [1, 2**64 - 1] (0 or a negative number is a
/// `ValueError` naming the keyword and its range, not an `OverflowError`).
fn memory_limit(value: &Bound<'_, PyAny>) -> PyResult<u64> {
    if !value.is_instance_of::<PyInt>() || value.is_instance_of::<PyBool>() {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "`max_memory=` is {}; give a number of bytes (an int)",
            value.repr()?
        )));
    }
    if let Ok(bytes @ 1..) = value.extract::<u64>() {
        return Ok(bytes);
    }
    let shown = if value.gt(0)? {
        format!("more than {MAX_MEMORY_LIMIT}")
    } else {
        value.repr()?.to_string()
    };
    Err(pyo3::exceptions::PyValueError::new_err(format!(
        "`max_memory=` is {shown}; give the bytes a run may keep in memory, in [1, \
         {MAX_MEMORY_LIMIT}], e.g. 2**30 (1 GiB)"
    )))
}

/// Refuses a run whose kept steps would need more than `max_memory` (default: a quarter of
/// the machine's memory), naming the way out.
fn check_memory(
    scene: &grasp_model::Scene,
    schedule: &Schedule,
    keep_solutions: bool,
    max_memory: Option<u64>,
) -> PyResult<()> {
    let limit = max_memory.unwrap_or_else(grasp_io::default_memory_limit);
    let steps = schedule.times.len() as u64;
    let history = Histories::bytes_per_step(scene).saturating_mul(steps);
    let solution = solution_bytes_per_step(scene);
    let need = if keep_solutions {
        solution.saturating_mul(steps).saturating_add(history)
    } else {
        solution.saturating_add(history)
    };
    if need <= limit {
        return Ok(());
    }
    let mib = |b: u64| b as f64 / 1048576.0;
    let way_out = if keep_solutions {
        format!(
            "pass keep_solutions=False to keep the force histories ({:.1} MiB) and the last \
             step's solution only, shorten the schedule, or raise max_memory",
            mib(history + solution)
        )
    } else {
        "shorten the schedule (or split it into several runs), or raise max_memory".into()
    };
    Err(GraspError::new_err(format!(
        "this run would keep about {:.1} MiB for its {steps} steps ({:.1} kB per step{}), more \
         than max_memory ({:.1} MiB{}); {way_out}",
        mib(need),
        need as f64 / steps.max(1) as f64 / 1000.0,
        if keep_solutions {
            " with every step's full solution"
        } else {
            ""
        },
        mib(limit),
        if max_memory.is_none() {
            ", a quarter of this machine's memory"
        } else {
            ""
        }
    )))
}

/// The recording's name: the scene file's stem (`scene` for a dict or JSON text).
fn recording_name(origin: &str) -> String {
    match origin {
        "<dict>" | "<json>" => "scene".into(),
        path => Path::new(path)
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned()),
    }
}

/// The schedule resolved against the scene, and the files read for it (the schedule file,
/// its CSV profiles).
fn load_schedule(
    py: Python<'_>,
    scene: &Scene,
    source: &Bound<'_, PyAny>,
) -> PyResult<(Schedule, RunInputs)> {
    let (text, origin, base, mut inputs) = schedule_text(py, source)?;
    let names = scene.scene.finger_names();
    let schedule = Schedule::from_json_str(&text, &names, &base)
        .map_err(|e| schedule_error(py, &origin, &e))?;
    inputs.extend(&schedule.input_files);
    Ok((schedule, inputs))
}

/// A schedule's JSON text from a path, a dict or JSON text: the text, where it came from
/// (for messages), the folder its CSV paths are relative to, and the file read.
pub(crate) fn schedule_text(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
) -> PyResult<(String, String, PathBuf, RunInputs)> {
    let mut inputs = RunInputs::new();
    if let Ok(d) = source.downcast::<PyDict>() {
        let bad = crate::json_value::non_finite_numbers(d.as_any());
        if !bad.is_empty() {
            let e = grasp_transfer::ScheduleError::Invalid(bad);
            return Err(crate::errors::schedule_error(py, "<dict>", &e));
        }
        let text: String = py.import("json")?.call_method1("dumps", (d,))?.extract()?;
        return Ok((text, "<dict>".to_string(), PathBuf::new(), inputs));
    }
    if let Some(t) = json_text(source)? {
        return Ok((t, "<json>".to_string(), PathBuf::new(), inputs));
    }
    let path: PathBuf = source.extract().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err("schedule: expected a path, a dict or JSON text")
    })?;
    let (text, identity) = grasp_io::read_text(&path, SCHEDULE_FILE)
        .map_err(|e| pyo3::exceptions::PyOSError::new_err(e.to_string()))?;
    inputs.add(&path, identity);
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    Ok((text, path.display().to_string(), base, inputs))
}

/// The text of `source` when it is a str holding JSON (first non-blank character `{`).
fn json_text(source: &Bound<'_, PyAny>) -> PyResult<Option<String>> {
    if !source.is_instance_of::<PyString>() {
        return Ok(None);
    }
    let text: String = source.extract()?;
    Ok(text.trim_start().starts_with('{').then_some(text))
}

/// Why a run gave no result.
enum RunError {
    /// An output refused or not written.
    Output(OutputError),
    /// The driver or a sink failed.
    Driver(String),
    /// A signal (Ctrl-C) or the progress callback raised: the run stopped after a step.
    Stopped(PyErr),
}

impl From<OutputError> for RunError {
    fn from(e: OutputError) -> Self {
        RunError::Output(e)
    }
}

/// What a run keeps.
struct Kept {
    histories: Histories,
    records: Option<Vec<StepRecord>>,
    last: Option<StepRecord>,
    summary: TransferSummary,
    written: Vec<String>,
}

/// What the caller follows of a run as it goes, besides the histories every run keeps.
struct Following<'a> {
    /// Keep every step's record (its solution).
    keep_solutions: bool,
    /// The caller's `progress(done, total)`, called after each step.
    progress: Option<&'a Py<PyAny>>,
}

/// The driver with the sinks asked for, keeping the histories (and the solutions when asked);
/// commits the files when the run is complete.
fn run_transfer(
    scene: &grasp_model::LoadedScene,
    schedule: &Schedule,
    options: TransferOptions,
    outputs: &OutputSet,
    files: OutputPaths<'_>,
    following: Following<'_>,
    recording_name: &str,
) -> Result<Kept, RunError> {
    let Following {
        keep_solutions,
        progress,
    } = following;
    let mut open = OutputFiles::open(outputs, files).map_err(|e| match e {
        OpenError::Output(e) => RunError::Output(e),
        OpenError::Sink(e) => RunError::Driver(e.to_string()),
    })?;
    open.name_recording(recording_name);
    open.respell_options(crate::keywords::in_keywords);
    let mut histories = Histories::new(scene);
    let mut records = keep_solutions.then(Vec::new);
    let total = schedule.times.len();
    let mut stopped: Option<PyErr> = None;
    let ran = grasp_transfer::run_until(scene, schedule, options, &mut open.sinks(None), |r| {
        histories.push(r);
        if let Some(all) = records.as_mut() {
            all.push(r.clone());
        }
        match after_step(r.index + 1, total, progress) {
            Ok(()) => std::ops::ControlFlow::Continue(()),
            Err(e) => {
                let reason = e.to_string();
                stopped = Some(e);
                std::ops::ControlFlow::Break(reason)
            }
        }
    });
    let (mut summary, last) = match (ran, stopped) {
        (_, Some(e)) => return Err(RunError::Stopped(e)),
        (Ok(done), None) => done,
        (Err(e), None) => return Err(RunError::Driver(e.to_string())),
    };
    for w in &mut summary.warnings {
        w.message = crate::keywords::in_keywords(&w.message);
    }
    let pending = open.take_pending();
    drop(open); // sinks closed: their files complete
    let complete = summary.failed_step_count == 0 || options.keep_going;
    let mut written = Vec::new();
    if complete {
        written = pending
            .iter()
            .map(|p| p.target().display().to_string())
            .collect();
        outputs.commit(pending)?;
    }
    Ok(Kept {
        histories,
        records,
        last,
        summary,
        written,
    })
}

/// After each step: Python's signals (Ctrl-C raises KeyboardInterrupt here, between steps)
/// and the caller's `progress(done, total)`, whose exception stops the run too.
fn after_step(done: usize, total: usize, progress: Option<&Py<PyAny>>) -> PyResult<()> {
    Python::with_gil(|py| {
        py.check_signals()?;
        if let Some(callback) = progress {
            callback.call1(py, (done, total))?;
        }
        Ok(())
    })
}

/// A hand-off's result: per step (time) and finger, the forces the driver computed.
/// Released fingers carry 0 N; failed steps carry 0 N for every finger (see `statuses`).
#[pyclass(module = "grasp", frozen)]
pub struct Transfer {
    histories: Histories,
    /// Every step's record (`keep_solutions=True`).
    records: Option<Vec<StepRecord>>,
    /// The last step's record.
    last: Option<StepRecord>,
    summary: TransferSummary,
    tangents: BTreeMap<String, Tangents>,
    written: Vec<String>,
}

#[pymethods]
impl Transfer {
    /// Scene finger names: the columns of the `(T, F)` arrays.
    #[getter]
    fn finger_names(&self) -> Vec<String> {
        self.histories.names.clone()
    }

    /// Step times, s, shape `(T,)`.
    #[getter]
    fn times_s<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let h = &self.histories;
        float_array(py, &h.times_s, &[h.len()])
    }

    /// Finger normal forces `P_i`, N, shape `(T, F)`.
    #[getter]
    fn normal_forces_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let h = &self.histories;
        float_array(py, &h.normal_n, &[h.len(), h.names.len()])
    }

    /// Finger friction forces `Q_i`, world frame, N, shape `(T, F, 3)`.
    #[getter]
    fn tangential_forces_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let h = &self.histories;
        float_array(py, &h.tangential_n, &[h.len(), h.names.len(), 3])
    }

    /// Commanded normal loads, N, shape `(T, F)`: NaN for a held finger, 0 when released.
    #[getter]
    fn commanded_loads_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let h = &self.histories;
        float_array(py, &h.commanded_n, &[h.len(), h.names.len()])
    }

    /// Scheduled external force at the centre of mass, N, shape `(T, 3)`.
    #[getter]
    fn external_forces_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let h = &self.histories;
        float_array(py, &h.external_n, &[h.len(), 3])
    }

    /// Each step's status (`"solved"`, `"no_equilibrium"`, ...), shape `(T,)`.
    #[getter]
    fn statuses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        str_array(py, &self.histories.statuses)
    }

    /// Wall time of each step (model building when the structure changed, solve), s, `(T,)`.
    #[getter]
    fn wall_times_s<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let h = &self.histories;
        float_array(py, &h.wall_times_s, &[h.len()])
    }

    /// Solver iterations of each step, shape `(T,)`.
    #[getter]
    fn iterations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let h = &self.histories;
        int_array(py, &h.iterations, &[h.len()])
    }

    /// Each step's smallest disturbance margin, N, shape `(T,)`: infinite where unbounded
    /// (every direction held to the search's cap), NaN where undetermined (no solver
    /// converged above what held) or not computed (without `margins=True`, or at a failed
    /// step).
    #[getter]
    fn smallest_margins_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let h = &self.histories;
        float_array(py, &h.margins_n, &[h.len()])
    }

    /// The tactile readings of `finger` at every step (its `sensor`; docs/guide/tactile.md),
    /// as `Solution.sensor` gives one step's, with the steps first.
    ///
    /// Parameters
    /// ----------
    /// finger : str
    ///     The finger's name (one with a `sensor` in the scene).
    ///
    /// Returns
    /// -------
    /// dict
    ///     `"taxels"` (when the sensor has taxels): `{"force_n": (T, nx, ny, 3)}` (normal, t1,
    ///     t2; N); `"markers"` (when it has markers): `{"displacement_m": (T, nx, ny, 3)}`
    ///     (normal into the finger, t1, t2; m); `"gel"` (when it has a gel image):
    ///     `{"height_m": (T, nx, ny), "rgb": (T, nx, ny, 3)}` (m into the pad; colours in
    ///     [0, 1]). NaN at the steps where the finger has no readings (released, or a step
    ///     without forces).
    ///
    /// Raises
    /// ------
    /// KeyError
    ///     `finger` has no sensor.
    fn sensor_history<'py>(&self, py: Python<'py>, finger: &str) -> PyResult<Bound<'py, PyDict>> {
        let h = &self.histories;
        let s = h
            .sensors
            .0
            .iter()
            .find(|s| s.finger == finger)
            .ok_or_else(|| {
                let with: Vec<&str> = h.sensors.0.iter().map(|s| s.finger.as_str()).collect();
                pyo3::exceptions::PyKeyError::new_err(format!(
                    "`{finger}` has no sensor; the fingers with one: {with:?}"
                ))
            })?;
        let out = PyDict::new(py);
        let kinds = [
            ("taxels", "force_n", &s.taxels),
            ("markers", "displacement_m", &s.markers),
        ];
        for (kind, field, values) in kinds {
            if let Some(([nx, ny], v)) = values {
                let d = PyDict::new(py);
                d.set_item(field, float_array(py, v, &[h.len(), *nx, *ny, 3])?)?;
                out.set_item(kind, d)?;
            }
        }
        if let Some(([nx, ny], heights, colours)) = &s.gel {
            let d = PyDict::new(py);
            d.set_item("height_m", float_array(py, heights, &[h.len(), *nx, *ny])?)?;
            d.set_item("rgb", float_array(py, colours, &[h.len(), *nx, *ny, 3])?)?;
            out.set_item("gel", d)?;
        }
        Ok(out)
    }

    /// The closing summary (the fields `grasp transfer` prints), as a dict.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        serialize_to_py(py, &self.summary)
    }

    /// The warnings of the run's solves (the summary's `warnings`), each once: dicts with
    /// `message` (a figure that changed between steps as its range), `count` (steps that gave
    /// it), `steps` (which: runs `{"first": i, "last": j}` of step indices) and
    /// `first_time_s`, `last_time_s` (s).
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        serialize_to_py(py, &self.summary.warnings)
    }

    /// The files written (paths), in the order mcap, rrd, csv, npz; empty when a failed step
    /// stopped the run (existing files are then untouched).
    #[getter]
    fn written(&self) -> Vec<String> {
        self.written.clone()
    }

    /// The full solution of one step, element arrays included.
    ///
    /// Parameters
    /// ----------
    /// index : int
    ///     The step, from 0 (negative counts from the end: `step(-1)` is the last). With
    ///     `keep_solutions=False` only the last step is kept.
    ///
    /// Returns
    /// -------
    /// Solution
    ///
    /// Raises
    /// ------
    /// IndexError
    ///     No such step, or a step not kept (`keep_solutions=False`).
    fn step(&self, index: isize) -> PyResult<Solution> {
        let n = self.histories.len() as isize;
        let i = if index < 0 { index + n } else { index };
        let out_of_range =
            || pyo3::exceptions::PyIndexError::new_err(format!("step {index} of {n}"));
        let i = usize::try_from(i)
            .ok()
            .filter(|&i| i < self.histories.len())
            .ok_or_else(out_of_range)?;
        let r = match (&self.records, &self.last) {
            (Some(all), _) => all.get(i).ok_or_else(out_of_range)?,
            (None, Some(last)) if last.index == i => last,
            (None, _) => {
                return Err(pyo3::exceptions::PyIndexError::new_err(format!(
                    "step {index}: the run kept only the last step's solution \
                     (keep_solutions=False); its histories cover every step"
                )))
            }
        };
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
            time: None,
            sensors: r.sensors.clone(),
        })
    }

    fn __len__(&self) -> usize {
        self.histories.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Transfer({} steps, {} fingers, {} failed)",
            self.histories.len(),
            self.histories.names.len(),
            self.summary.failed_step_count
        )
    }
}
