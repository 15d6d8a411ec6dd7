//! `grasp.plan`: the load ramps of a hand-off planned by the library's planner exactly as
//! `grasp plan` plans them, returned as a dict: the checked schedule (`"schedule"`, which
//! `grasp.transfer` runs unchanged) and its report (margins along the plan and the template,
//! the binding constraint when one is not met, the cost). The GIL is released while it runs.

use grasp_model::Readable;
use grasp_transfer::{
    Binding, Objective, PlanError, PlanOptions, Schedule, ScheduleSpec, Template,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyInt, PyString};

use crate::errors::{grasp_error, schedule_error, GraspError};
use crate::json_value::serialize_to_py;
use crate::keywords::in_keywords;
use crate::scene::Scene;

/// Plans a hand-off's load ramps, as `grasp plan` does.
///
/// The loads of the `releasing` fingers (down to 0 N) and of the `receiving` ones (up from
/// 0 N), keyframed and linear in between, that keep every step's slip margin
/// `1 - |Q|/(mu P)` at least `min_slip_margin` over the fingers carrying 5 % of the load
/// scale, each planned load within `[min_load, max_load]` and its rate within `max_rate`,
/// the duration within `[min_duration, max_duration]`; with `min_margin`, every step's
/// smallest disturbance margin at least that. The GIL is released while it runs.
///
/// Parameters
/// ----------
/// scene : Scene
///     The validated grasp (SI units), from `grasp.Scene`.
/// releasing : sequence of str
///     The fingers that let go (their loads ramp down to 0 N).
/// receiving : sequence of str, default ()
///     The fingers that take the object (their loads ramp up from 0 N).
/// template : str, os.PathLike or dict, optional
///     A schedule (path, dict or JSON text) to start from and compare with.
/// min_slip_margin : float, default 0.0
///     The smallest slip margin allowed at any step (dimensionless, in [0, 1)).
/// min_margin : float, optional
///     The smallest disturbance margin allowed at any step, N: the smallest, over the axis
///     directions of force and couple, of the extra wrench the grasp resists, as
///     `transfer(..., margins=True)` finds it (default: not constrained; several times the
///     planning's cost).
/// min_load, max_load : float, optional
///     The range of every planned load, N (default: 0 N and no upper bound).
/// max_rate : float, optional
///     The fastest a planned load may change, N/s (`objective="duration"` needs it or
///     `max_speed`).
/// max_speed : float, optional
///     The fastest a planned position-controlled finger's approach may change (a jaw opening
///     or closing), m/s.
/// open_to : float, optional
///     Where the releasing position-controlled fingers end, m of approach (negative: opened
///     short of first touch; default: where the template ends them).
/// close_to : float, optional
///     Where the receiving position-controlled fingers close to in the starting path, m of
///     approach (the plan moves it within the bounds; default: where the template ends them).
/// min_approach, max_approach : float, optional
///     The range of every planned approach, m (default: the range the starting path spans).
/// min_duration, max_duration : float, optional
///     The range of the hand-off's duration, s (default: 0 s and no upper bound).
/// duration : float, optional
///     The fixed duration, s, of `objective="margin"`.
/// objective : {"duration", "margin"}, default "duration"
///     `"duration"`: the shortest hand-off; `"margin"`: the largest smallest margin at the
///     fixed `duration`.
/// steps : int, optional
///     Steps of the planned schedule (default: the template's, or 60).
/// keyframes : int, default 5
///     Keyframes of each load's path, its ends included.
/// max_runs : int, default 30
///     The most hand-off runs the search may make.
/// solver : {"auto", "native", "clarabel"}, default "auto"
///     The solver of every run, as in `solve`.
/// compliance : {"auto", "dense", "fft"}, default "auto"
///     As in `solve`.
///
/// Returns
/// -------
/// dict
///     The report of a schedule that keeps every constraint: `met` (True), `schedule` (runs
///     unchanged in `transfer`), `margins` and `template_margins` (per step: the smallest slip
///     margin over the fingers carrying 5 % of the load scale, the rule of `transfer`'s summary
///     too, and `disturbance_n` with `min_margin`), `slip_margin_rule`, `smallest_not_counted`, `warnings` (the checked run's solves', each
///     once with its steps)
///     (the lighter fingers' smallest slip margin), `checked` (the resolutions checked: the
///     schedule's own steps, and its ramps at 600 steps when it has fewer), `duration_s`,
///     `runs` and `time_s`.
///
/// Raises
/// ------
/// ValueError
///     An argument out of range (each line names the keyword).
/// TypeError
///     An argument of the wrong type: a bool or a str for a number, a str for a list of
///     finger names (`releasing="f1"`: give `["f1"]`).
/// ScheduleError
///     The template is not a valid schedule for the scene.
/// GraspError
///     Constraints no schedule can meet (the one that binds is named), a run failed, or, as
///     `grasp plan` writes no schedule (exit code 2), the best schedule found does not keep
///     every constraint: the message names the one that binds and why, and the exception's
///     `report` attribute holds the whole report (`met` False, `binding`, the margins along
///     the best schedule, and that schedule, to inspect rather than to run).
///
/// Examples
/// --------
/// >>> plan = grasp.plan(scene, releasing=["f1", "f2"], receiving=["f3", "f4"], max_rate=1.5)
/// >>> plan["met"], plan["duration_s"]
#[pyfunction]
#[pyo3(signature = (scene, *, releasing, receiving=None, template=None,
                    min_slip_margin=None, min_margin=None, min_load=None, max_load=None,
                    max_rate=None, max_speed=None, open_to=None, close_to=None,
                    min_approach=None,
                    max_approach=None, min_duration=None, max_duration=None, duration=None,
                    objective="duration", steps=None, keyframes=None, max_runs=None,
                    solver="auto", compliance="auto"))]
#[allow(clippy::too_many_arguments)]
pub fn plan(
    py: Python<'_>,
    scene: &Scene,
    releasing: &Bound<'_, PyAny>,
    receiving: Option<&Bound<'_, PyAny>>,
    template: Option<&Bound<'_, PyAny>>,
    min_slip_margin: Option<&Bound<'_, PyAny>>,
    min_margin: Option<&Bound<'_, PyAny>>,
    min_load: Option<&Bound<'_, PyAny>>,
    max_load: Option<&Bound<'_, PyAny>>,
    max_rate: Option<&Bound<'_, PyAny>>,
    max_speed: Option<&Bound<'_, PyAny>>,
    open_to: Option<&Bound<'_, PyAny>>,
    close_to: Option<&Bound<'_, PyAny>>,
    min_approach: Option<&Bound<'_, PyAny>>,
    max_approach: Option<&Bound<'_, PyAny>>,
    min_duration: Option<&Bound<'_, PyAny>>,
    max_duration: Option<&Bound<'_, PyAny>>,
    duration: Option<&Bound<'_, PyAny>>,
    objective: &str,
    steps: Option<&Bound<'_, PyAny>>,
    keyframes: Option<&Bound<'_, PyAny>>,
    max_runs: Option<&Bound<'_, PyAny>>,
    solver: &str,
    compliance: &str,
) -> PyResult<PyObject> {
    let objective = objective_of(objective)?;
    let mut solve = crate::solve::solve_options(solver, 1e-10)?;
    solve.compliance = crate::solve::compliance_choice(compliance)?;
    let defaults = PlanOptions::default();
    let options = PlanOptions {
        releasing: finger_names("releasing", Some(releasing))?,
        receiving: finger_names("receiving", receiving)?,
        min_slip_margin: number("min_slip_margin", min_slip_margin)?.unwrap_or(0.0),
        min_margin_n: number("min_margin", min_margin)?,
        min_load_n: number("min_load", min_load)?.unwrap_or(0.0),
        max_load_n: number("max_load", max_load)?.unwrap_or(f64::INFINITY),
        max_rate_n_per_s: number("max_rate", max_rate)?,
        max_speed_m_per_s: number("max_speed", max_speed)?,
        open_to_m: number("open_to", open_to)?,
        close_to_m: number("close_to", close_to)?,
        min_approach_m: number("min_approach", min_approach)?,
        max_approach_m: number("max_approach", max_approach)?,
        min_duration_s: number("min_duration", min_duration)?.unwrap_or(0.0),
        max_duration_s: number("max_duration", max_duration)?.unwrap_or(f64::INFINITY),
        objective,
        duration_s: number("duration", duration)?,
        steps: whole("steps", steps)?,
        keyframes: whole("keyframes", keyframes)?.unwrap_or(defaults.keyframes),
        max_runs: whole("max_runs", max_runs)?.unwrap_or(defaults.max_runs),
        solve,
        ..defaults
    };
    let template = template.map(|t| read_template(py, scene, t)).transpose()?;
    let report = py.allow_threads(|| {
        let t = template
            .as_ref()
            .map(|(spec, schedule)| Template { spec, schedule });
        grasp_transfer::plan(&scene.scene, t, &options)
    });
    let mut report = report.map_err(|e| match e {
        PlanError::Options(_) => PyValueError::new_err(in_keywords(&e.to_string())),
        other => grasp_error(in_keywords(&other.to_string())),
    })?;
    report.respell_options(in_keywords);
    let dict = serialize_to_py(py, &report)?;
    match &report.binding {
        None => Ok(dict.unbind()),
        Some(b) => {
            // As `grasp plan` writes no schedule (exit 2): an exception, the report on it.
            let err = GraspError::new_err(not_met(b));
            err.value(py).setattr("report", dict)?;
            Err(err)
        }
    }
}

/// The message of a plan that does not keep every constraint: the one that binds, where, by
/// how much, and why (option names already keywords).
fn not_met(b: &Binding) -> String {
    let who = b
        .finger
        .as_deref()
        .map_or(String::new(), |f| format!(" ({f})"));
    format!(
        "no schedule written: the best one found does not keep every constraint; binding: \
         {}{who} at t = {} s is {} against {} (short by {}): {}. The exception's `report` \
         holds the whole report (margins along the best schedule, `binding`, `schedule`)",
        b.constraint,
        Readable(b.time_s),
        Readable(b.value),
        Readable(b.limit),
        Readable(b.short_by),
        b.why
    )
}

/// `keyword=` as a real number (N, N/s, s), `None` when not given: an int or float, not a bool
/// (`True` is an int to Python, and would read as 1), else a TypeError naming the keyword.
fn number(keyword: &str, value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<f64>> {
    let Some(v) = value.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    if v.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "`{keyword}=` is {}, a bool: give a number",
            v.repr()?
        )));
    }
    v.extract::<f64>().map(Some).map_err(|_| {
        let shown = v.repr().map(|r| r.to_string()).unwrap_or_default();
        PyTypeError::new_err(format!("`{keyword}=` is {shown}: give a number"))
    })
}

/// `keyword=` as a count, `None` when not given: a non-negative int, not a bool; the range is
/// the planner's to check (its message names the keyword).
fn whole(keyword: &str, value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    let Some(v) = value.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    if !v.is_instance_of::<PyInt>() || v.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "`{keyword}=` is {}: give a whole number (an int)",
            v.repr()?
        )));
    }
    v.extract::<usize>().map(Some).map_err(|_| {
        let shown = v.repr().map(|r| r.to_string()).unwrap_or_default();
        PyValueError::new_err(format!(
            "`{keyword}=` is {shown}: give a positive whole number"
        ))
    })
}

/// `keyword=` as finger names: a list or tuple of str (a single str is refused: it is not a
/// list of one name), empty when not given.
fn finger_names(keyword: &str, value: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let Some(v) = value.filter(|v| !v.is_none()) else {
        return Ok(Vec::new());
    };
    if let Ok(text) = v.downcast::<PyString>() {
        return Err(PyTypeError::new_err(format!(
            "`{keyword}=` is the string {}, not a list of finger names; give [{}]",
            text.repr()?,
            text.repr()?
        )));
    }
    v.extract::<Vec<String>>().map_err(|_| {
        let shown = v.repr().map(|r| r.to_string()).unwrap_or_default();
        PyTypeError::new_err(format!(
            "`{keyword}=` is {shown}: give a list of finger names (str), e.g. [\"f1\", \"f2\"]"
        ))
    })
}

/// The template as written and resolved against the scene's fingers.
fn read_template(
    py: Python<'_>,
    scene: &Scene,
    source: &Bound<'_, PyAny>,
) -> PyResult<(ScheduleSpec, Schedule)> {
    let (text, origin, base, _) = crate::transfer::schedule_text(py, source)?;
    let spec: ScheduleSpec = grasp_model::strict_json::from_str_strict(&text).map_err(|e| {
        let e = grasp_transfer::ScheduleError::Parse {
            path: e.path,
            message: e.message,
        };
        schedule_error(py, &origin, &e)
    })?;
    let schedule = Schedule::from_spec(&spec, &scene.scene.finger_names(), &base)
        .map_err(|e| schedule_error(py, &origin, &e))?;
    Ok((spec, schedule))
}

/// The objective named `name`, or the error naming the keyword.
fn objective_of(name: &str) -> PyResult<Objective> {
    match name {
        "duration" => Ok(Objective::Duration),
        "margin" => Ok(Objective::Margin),
        other => Err(PyValueError::new_err(format!(
            "objective={other:?}: give \"duration\" or \"margin\""
        ))),
    }
}
