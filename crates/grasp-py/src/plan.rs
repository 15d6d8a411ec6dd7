//! `grasp.plan`: the load ramps of a hand-off planned by the library's planner exactly as
//! `grasp plan` plans them, returned as a dict: the checked schedule (`"schedule"`, which
//! `grasp.transfer` runs unchanged) and its report (margins along the plan and the template,
//! the binding constraint when one is not met, the cost). The GIL is released while it runs.

use grasp_transfer::plan::{Objective, PlanError, PlanOptions, Template};
use grasp_transfer::{Schedule, ScheduleSpec};
use pyo3::prelude::*;

use crate::errors::{grasp_error, schedule_error};
use crate::json_value::serialize_to_py;
use crate::scene::Scene;

/// Plans the hand-off of `scene`: the loads of the `releasing` fingers (down to 0 N) and of
/// the `receiving` ones (up from 0 N), keyframed and linear in between, that keep every
/// step's slip margin `1 - |Q|/(mu P)` at least `min_slip_margin` over the fingers carrying
/// 5 % of the load scale, with `min_margin` (N) every step's smallest disturbance margin at
/// least that (as `grasp.transfer(..., margins=True)` finds it; several times the planning's
/// cost), each planned load within `[min_load, max_load]` N and its rate within `max_rate`
/// N/s, the duration within `[min_duration, max_duration]` s.
///
/// - `objective`: `"duration"` (the shortest; needs `max_rate`) or `"margin"` (the largest
///   smallest margin at the fixed `duration`).
/// - `template`: a schedule (path, dict or JSON text) to start from and compare with.
/// - `keyframes`, `steps`, `max_runs`: the path's keyframes (ends included), its steps
///   (default: the template's, or 60) and the most hand-off runs allowed.
///
/// Returns the report as a dict: `met` (every constraint kept by the checked schedule),
/// `binding` (the one not kept: which, where, by how much, why), `schedule`, `margins` and
/// `template_margins` (per step), `duration_s`, `runs`, `time_s`. Raises `GraspError` for
/// constraints no schedule can meet (named) and bad arguments (`ValueError`).
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
    let report = report.map_err(|e| match e {
        PlanError::Options(list) => {
            let lines: Vec<String> = list
                .iter()
                .map(|(o, m)| format!("{}=: {}", o.replace('-', "_"), in_keywords(m)))
                .collect();
            pyo3::exceptions::PyValueError::new_err(lines.join("\n"))
        }
        other => grasp_error(in_keywords(&other.to_string())),
    })?;
    Ok(serialize_to_py(py, &report)?.unbind())
}

/// The CLI's flags in a planner message respelled as this function's keywords.
fn in_keywords(text: &str) -> String {
    let flags = [
        "max-rate",
        "duration",
        "template",
        "max-runs",
        "min-slip-margin",
        "min-margin",
    ];
    flags.iter().fold(text.to_string(), |t, f| {
        t.replace(&format!("--{f}"), &format!("{}=", f.replace('-', "_")))
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
