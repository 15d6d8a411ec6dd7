//! `grasp.solve`: one grasp, solved by the library exactly as `grasp solve` does (model
//! from the scene, a fresh solver, the scene's loads), with the GIL released meanwhile.

use std::str::FromStr;
use std::time::Instant;

use grasp_model::ComplianceChoice;
use grasp_model::{solve_at, TimePoint};
use grasp_model::{GraspModel, GraspSolver, SolveOptions, SolverChoice};
use pyo3::prelude::*;

use crate::errors::{grasp_error, scene_error};
use crate::scene::{parse_model, Scene};
use crate::solution::Solution;

/// The `compliance=` keyword's value (`ValueError` naming the keyword otherwise).
pub(crate) fn compliance_choice(compliance: &str) -> PyResult<ComplianceChoice> {
    ComplianceChoice::from_str(compliance).map_err(|e| {
        pyo3::exceptions::PyValueError::new_err(format!("compliance={compliance:?}: {e}"))
    })
}

/// Solves one grasp, as `grasp solve` does.
///
/// The scene's loads are balanced by contact forces that minimise the complementary energy
/// over the friction cones (thesis chapter 3); `model="coulomb"` runs the sequential Tresca
/// fixed point of docs/model.md instead. The GIL is released while the model is built and
/// solved, and Ctrl-C stops the call.
///
/// Parameters
/// ----------
/// scene : Scene
///     The validated grasp (SI units), from `grasp.Scene`.
/// model : {"energy", "coulomb"}, optional
///     The contact model; default: the scene's own `model`.
/// solver : {"auto", "native", "clarabel"}, default "auto"
///     `"auto"`: the native semismooth Newton solver, falling back to Clarabel.
/// tolerance : float, default 1e-10
///     Relative tolerance of the scaled program (dimensionless), in [1e-14, 1e-2].
/// compliance : {"auto", "dense", "fft"}, default "auto"
///     How the patches' influence coefficients are held: `"auto"` is dense up to 1,024
///     unknowns a patch (32x32 frictionless, 22x22 planar, 18x18 with friction in 3-D) and
///     the FFT operator above; `"fft"` is matrix-free, native solver only
///     (docs/guide/solving.md, "Fine patches").
/// at_time : float, optional
///     For a viscoelastic scene: the state this many seconds (in (0, 1e9] s) after its
///     loads and approaches were applied as a step at t = 0. Default: the instantaneous
///     response (t = 0+).
/// long_term : bool, default False
///     For a viscoelastic scene: its fully relaxed state (docs/guide/pads.md).
///
/// Returns
/// -------
/// Solution
///     Element forces (N), pressures (Pa), gaps and slips (m), states, finger resultants and
///     the solver's report. A grasp that cannot hold is a solution whose `status` is
///     `"no_equilibrium"` (with its `reason`), not an exception.
///
/// Raises
/// ------
/// ValueError
///     An option out of range or misspelt (the message names the keyword), or both
///     `at_time` and `long_term=True`.
/// TypeError
///     `at_time` is not a number.
/// SceneError
///     The scene with `model=` is not valid, or its model cannot be built (`problems` lists
///     each with its JSON path and fix).
/// MemoryError
///     The scene's model does not fit in memory (what did not fit, and the fix).
/// GraspError
///     The library refused the solve (the message says why, and the fix), or its working
///     memory could not be had.
/// UserWarning
///     Warned, not raised: `at_time` or `long_term` given for an elastic scene.
///
/// Examples
/// --------
/// >>> sol = grasp.solve(grasp.Scene("examples/cube_a.json"))
/// >>> sol.status, sol.finger_normal_forces_n
#[pyfunction]
#[pyo3(signature = (scene, *, model=None, solver="auto", tolerance=1e-10, compliance="auto", at_time=None, long_term=false))]
#[allow(clippy::too_many_arguments)]
pub fn solve(
    py: Python<'_>,
    scene: &Scene,
    model: Option<&str>,
    solver: &str,
    tolerance: f64,
    compliance: &str,
    at_time: Option<&Bound<'_, PyAny>>,
    long_term: bool,
) -> PyResult<Solution> {
    let mut options = solve_options(solver, tolerance)?;
    options.compliance = compliance_choice(compliance)?;
    let time = time_point(seconds_of(at_time)?, long_term)?;
    let scene_used = match model {
        Some(m) => {
            let mut s = scene.scene.clone();
            s.model = parse_model(m)?;
            s.validate()
                .map_err(|e| scene_error(py, &scene.origin, &e))?;
            s
        }
        None => scene.scene.clone(),
    };
    let outcome = interruptible(py, move || solve_scene(&scene_used, options, time))?;
    match outcome {
        Ok(s) => {
            if time != TimePoint::Instantaneous && s.time.is_none() {
                // As the CLI's note: the time asked changes nothing on an elastic scene.
                let message = std::ffi::CString::new(format!(
                    "the scene is elastic (no material has a relaxation law): {time} is the \
                     instantaneous response"
                ))
                .unwrap_or_default();
                let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
                PyErr::warn(py, category.as_any(), &message, 1)?;
            }
            Ok(s)
        }
        Err(Failure::Scene(e)) => Err(scene_error(py, &scene.origin, &e)),
        Err(Failure::Model(e)) => Err(grasp_error(e)),
    }
}

/// How often a long call looks for Ctrl-C (and other Python signals), s.
const SIGNAL_POLL_S: f64 = 0.1;

/// Runs `work` on its own thread with the GIL released, looking for Python signals every
/// [`SIGNAL_POLL_S`]: Ctrl-C raises KeyboardInterrupt at once (the abandoned solve finishes
/// on its thread, its answer dropped), where a call that holds the thread answers it only
/// when it returns.
pub fn interruptible<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let (tx, mut rx) = std::sync::mpsc::channel();
    std::thread::Builder::new()
        .name("grasp-solve".into())
        .spawn(move || {
            let _ = tx.send(work());
        })
        .map_err(|e| crate::errors::grasp_error(format!("cannot start the solve: {e}")))?;
    let wait = std::time::Duration::from_secs_f64(SIGNAL_POLL_S);
    loop {
        // The receiver goes to the GIL-free closure and back (it is Send, not Sync).
        let (got, back) = py.allow_threads(move || (rx.recv_timeout(wait), rx));
        rx = back;
        match got {
            Ok(answer) => return Ok(answer),
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => py.check_signals()?,
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                return Err(crate::errors::grasp_error(
                    "the solve's thread ended without an answer (a panic)",
                ))
            }
        }
    }
}

/// The options of `solver` and `tolerance`, checked by the library's
/// [`SolveOptions::validate`] (as the CLI's are), or a ValueError naming the argument.
pub fn solve_options(solver: &str, tolerance: f64) -> PyResult<SolveOptions> {
    let choice = SolverChoice::from_str(solver)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("solver={solver:?}: {e}")))?;
    let options = SolveOptions {
        solver: choice,
        tolerance,
        ..SolveOptions::default()
    };
    options.validate().map_err(|e| {
        pyo3::exceptions::PyValueError::new_err(crate::keywords::in_keywords(&e.to_string()))
    })?;
    Ok(options)
}

enum Failure {
    Scene(grasp_model::SceneError),
    Model(grasp_model::ModelError),
}

/// `at_time=` as seconds: a number, not a bool (`True` is an int to Python, and would read as
/// 1 s), or a TypeError naming the keyword.
fn seconds_of(at_time: Option<&Bound<'_, PyAny>>) -> PyResult<Option<f64>> {
    let Some(v) = at_time.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    if v.is_instance_of::<pyo3::types::PyBool>() {
        return Err(pyo3::exceptions::PyTypeError::new_err(
            "at_time= is a bool: give the time after the step in seconds (a number), or \
             long_term=True for the fully relaxed state",
        ));
    }
    v.extract::<f64>().map(Some).map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(
            "at_time= is not a number: give the time after the step in seconds",
        )
    })
}

/// The time of a viscoelastic solve (`at_time=`, `long_term=`), or a ValueError naming the
/// keyword.
fn time_point(at_time: Option<f64>, long_term: bool) -> PyResult<TimePoint> {
    Ok(match (at_time, long_term) {
        (Some(_), true) => {
            return Err(pyo3::exceptions::PyValueError::new_err(
                "at_time= and long_term=True ask for two different times: give one",
            ))
        }
        (Some(t), false) if !(t.is_finite() && t > 0.0 && t <= 1e9) => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "at_time={}: give the time after the step in seconds, in (0, 1e9]",
                grasp_model::readable(t)
            )))
        }
        (Some(t), false) => TimePoint::At { seconds: t },
        (None, true) => TimePoint::LongTerm,
        (None, false) => TimePoint::Instantaneous,
    })
}

/// Model, solver, solve: the path of `grasp solve` (no Python objects touched).
fn solve_scene(
    scene: &grasp_model::LoadedScene,
    options: SolveOptions,
    time: TimePoint,
) -> Result<Solution, Failure> {
    let t0 = Instant::now();
    let model = GraspModel::from_loaded_with(scene, options.compliance).map_err(Failure::Scene)?;
    let model = std::sync::Arc::new(model);
    let build_time_s = t0.elapsed().as_secs_f64();
    let viscoelastic = model.is_viscoelastic();
    let mut solution = match time {
        TimePoint::Instantaneous => {
            let inputs = grasp_model::StepInputs::of_scene(&model);
            GraspSolver::new(std::sync::Arc::clone(&model), options)
                .solve(&inputs)
                .map_err(Failure::Model)?
        }
        later => {
            let clock = Instant::now();
            let mut timed = solve_at(&model, options, later).map_err(Failure::Model)?;
            timed.solution.solve_time_s = clock.elapsed().as_secs_f64();
            timed.solution
        }
    };
    let sensors = match solution.status.has_forces() {
        true => grasp_model::sensor_readings(scene, &model, &solution).map_err(Failure::Model)?,
        false => Vec::new(),
    };
    crate::keywords::respell_solution(&mut solution);
    let frames = crate::solution::tangents_by_name(scene);
    let tangents = solution
        .fingers
        .iter()
        .map(|f| frames.get(&f.name).copied().unwrap_or(([0.0; 3], [0.0; 3])))
        .collect();
    Ok(Solution {
        solution,
        tangents,
        build_time_s,
        time: viscoelastic.then_some(time),
        sensors,
    })
}
