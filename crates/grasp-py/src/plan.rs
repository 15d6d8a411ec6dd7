//! `grasp.plan`: the load ramps of a hand-off planned by the library's planner exactly as
//! `grasp plan` plans them, returned as a dict: the checked schedule (`"schedule"`, which
//! `grasp.transfer` runs unchanged) and its report (margins along the plan and the template,
//! the binding constraint when one is not met, the cost). The GIL is released while it runs.

use grasp_transfer::{Objective, PlanError, PlanOptions, Schedule, ScheduleSpec, Template};
use pyo3::prelude::*;

use crate::errors::{grasp_error, schedule_error};
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
///     The fastest a planned load may change, N/s (needed by `objective="duration"`).
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
///     The report: `met` (every constraint kept by the checked schedule), `binding` (the one
///     not kept: which, where, by how much, why), `schedule` (runs unchanged in
///     `transfer`), `margins` and `template_margins` (per step: the smallest slip margin, and
///     `disturbance_n` with `min_margin`), `warnings` (the checked run's solves', each once
///     with its steps), `duration_s`, `runs` and `time_s`.
///
/// Raises
/// ------
/// ValueError
///     An argument out of range or misspelt (each line names the keyword).
/// ScheduleError
///     The template is not a valid schedule for the scene.
/// GraspError
///     Constraints no schedule can meet (the one that binds is named), or a run failed.
///
/// Examples
/// --------
/// >>> plan = grasp.plan(scene, releasing=["f1", "f2"], receiving=["f3", "f4"], max_rate=1.5)
/// >>> plan["met"], plan["duration_s"]
#[pyfunction]
#[pyo3(signature = (scene, *, releasing, receiving=Vec::new(), template=None,
                    min_slip_margin=0.0, min_margin=None, min_load=0.0, max_load=None, max_rate=None,
                    min_duration=0.0, max_duration=None, duration=None, objective="duration",
                    steps=None, keyframes=5, max_runs=30, solver="auto", compliance="auto"))]
#[allow(clippy::too_many_arguments)]
pub fn plan(
    py: Python<'_>,
    scene: &Scene,
    releasing: Vec<String>,
    receiving: Vec<String>,
    template: Option<&Bound<'_, PyAny>>,
    min_slip_margin: f64,
    min_margin: Option<f64>,
    min_load: f64,
    max_load: Option<f64>,
    max_rate: Option<f64>,
    min_duration: f64,
    max_duration: Option<f64>,
    duration: Option<f64>,
    objective: &str,
    steps: Option<usize>,
    keyframes: usize,
    max_runs: usize,
    solver: &str,
    compliance: &str,
) -> PyResult<PyObject> {
    let objective = match objective {
        "duration" => Objective::Duration,
        "margin" => Objective::Margin,
        other => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "objective={other:?}: give \"duration\" or \"margin\""
            )))
        }
    };
    let mut solve = crate::solve::solve_options(solver, 1e-10)?;
    solve.compliance = crate::solve::compliance_choice(compliance)?;
    let options = PlanOptions {
        releasing,
        receiving,
        min_slip_margin,
        min_margin_n: min_margin,
        min_load_n: min_load,
        max_load_n: max_load.unwrap_or(f64::INFINITY),
        max_rate_n_per_s: max_rate,
        min_duration_s: min_duration,
        max_duration_s: max_duration.unwrap_or(f64::INFINITY),
        objective,
        duration_s: duration,
        steps,
        keyframes,
        max_runs,
        solve,
        ..PlanOptions::default()
    };
    let template = template.map(|t| read_template(py, scene, t)).transpose()?;
    let report = py.allow_threads(|| {
        let t = template
            .as_ref()
            .map(|(spec, schedule)| Template { spec, schedule });
        grasp_transfer::plan(&scene.scene, t, &options)
    });
    let mut report = report.map_err(|e| match e {
        PlanError::Options(_) => {
            pyo3::exceptions::PyValueError::new_err(in_keywords(&e.to_string()))
        }
        other => grasp_error(in_keywords(&other.to_string())),
    })?;
    report.respell_options(in_keywords);
    Ok(serialize_to_py(py, &report)?.unbind())
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
