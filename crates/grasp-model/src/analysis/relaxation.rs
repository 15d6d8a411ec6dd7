//! A viscoelastic scene solved at a chosen time: its loads and approaches applied as a step at
//! `t = 0`, the answer the instantaneous response, the state `T` seconds later, or the fully
//! relaxed one.
//!
//! Later than `0+`, the history is stepped ([`crate::solve::viscous_history`], each step one
//! program, warm-started): a first step of `min(T, 1e-3 lambda_min)` (`lambda_min` the fastest
//! retardation time of the scene), then [`STEPS_PER_DECADE`] equal steps in each decade of time
//! up to `T`. The scheme is exact for forces linear within a step and second order otherwise;
//! with 50 steps a decade a step spans 18 % of the decade's start, and the Lee-Radok checks
//! (`tests/viscoelastic_pads.rs`) meet 1 %. The fully relaxed state is one elastic solve with
//! every viscoelastic body at its long-term modulus (exact for loads held since `t = 0`).

use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::solve::contact_state::ContactState;
use crate::solve::grasp_solver::GraspSolver;
use crate::solve::solution::Solution;
use crate::solve::step_inputs::StepInputs;
use crate::solver::options::SolveOptions;

/// Equal steps in each decade of time of a solve at a later time.
pub const STEPS_PER_DECADE: usize = 50;

/// When a viscoelastic scene is solved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimePoint {
    /// Just after the loads were applied (`t = 0+`): the elastic answer at the instantaneous
    /// moduli.
    Instantaneous,
    /// `seconds` after the loads were applied as a step at `t = 0`.
    At {
        /// Time since the step, s (> 0).
        seconds: f64,
    },
    /// After full relaxation: every viscoelastic body at its long-term modulus.
    LongTerm,
}

impl std::fmt::Display for TimePoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TimePoint::Instantaneous => write!(f, "the instantaneous response (t = 0+)"),
            TimePoint::At { seconds } => write!(f, "t = {seconds} s after the loads were applied"),
            TimePoint::LongTerm => write!(f, "the fully relaxed response (t -> infinity)"),
        }
    }
}

/// What [`solve_at`] answered: the solution at the time asked, and the time steps it took.
#[derive(Debug, Clone)]
pub struct TimedSolution {
    /// The solution at the time asked (or the first step that failed).
    pub solution: Solution,
    /// The time asked.
    pub time: TimePoint,
    /// Programs solved (1 for the instantaneous and the relaxed answers).
    pub steps: usize,
}

/// Solves `model` with its scene's loads at `time` (module docs). An elastic model answers the
/// same at every time. A step that fails (no equilibrium, no convergence) is the answer, with
/// the time it was reached in its reason.
pub fn solve_at(
    model: &GraspModel,
    options: SolveOptions,
    time: TimePoint,
) -> Result<TimedSolution, ModelError> {
    solve_at_reporting(model, options, time, &mut |_, _| {})
}

/// [`solve_at`], calling `step(k, n)` after each of the `n` time steps of a history (`k` done
/// so far), for a progress bar.
pub fn solve_at_reporting(
    model: &GraspModel,
    options: SolveOptions,
    time: TimePoint,
    step: &mut dyn FnMut(usize, usize),
) -> Result<TimedSolution, ModelError> {
    let inputs = StepInputs::of_scene(model);
    let seconds = match time {
        TimePoint::At { seconds } if model.is_viscoelastic() => seconds,
        TimePoint::LongTerm if model.is_viscoelastic() => {
            let relaxed = inputs.with_time_step(f64::INFINITY);
            let solution = GraspSolver::new(model.clone(), options).solve(&relaxed)?;
            return Ok(TimedSolution {
                solution,
                time,
                steps: 1,
            });
        }
        _ => {
            let solution = GraspSolver::new(model.clone(), options).solve(&inputs)?;
            return Ok(TimedSolution {
                solution,
                time,
                steps: 1,
            });
        }
    };
    let mut state = ContactState::new(model);
    let mut solver = GraspSolver::new(model.clone(), options);
    let mut solution = solver.solve_step(&inputs, &mut state)?;
    let mut steps = 1;
    if !solution.status.has_forces() {
        return Ok(TimedSolution {
            solution,
            time,
            steps,
        });
    }
    state.advance_time_step(model, &solution);
    let mut t = 0.0;
    let steps_of_history = time_steps(seconds, fastest_retardation_s(model));
    let n = steps_of_history.len();
    for dt in steps_of_history {
        // A step of another length assembles its program afresh (the solver's doing).
        solution = solver.solve_step(&inputs.clone().with_time_step(dt), &mut state)?;
        step(steps, n);
        steps += 1;
        t += dt;
        if !solution.status.has_forces() {
            if let Some(r) = &mut solution.reason {
                *r = format!("at t = {t:.6e} s of the relaxation: {r}");
            }
            break;
        }
        state.advance_time_step(model, &solution);
    }
    Ok(TimedSolution {
        solution,
        time,
        steps,
    })
}

/// The fastest retardation time of the model's viscoelastic bodies, s.
fn fastest_retardation_s(model: &GraspModel) -> f64 {
    model
        .fingers
        .iter()
        .filter_map(|f| f.viscous.as_ref())
        .flat_map(|v| v.bodies.iter())
        .flat_map(|b| b.creep.terms.iter().map(|t| t.time_s))
        .fold(f64::INFINITY, f64::min)
}

/// The step lengths from `0` to `end_s` (module docs): a first step of `min(end, 1e-3
/// fastest)`, then [`STEPS_PER_DECADE`] equal steps per decade (the last decade cut at `end`,
/// its steps in proportion to its logarithmic length, at least one).
pub fn time_steps(end_s: f64, fastest_s: f64) -> Vec<f64> {
    let first = end_s.min(1e-3 * fastest_s);
    let mut steps = vec![first];
    let mut a = first;
    while a < end_s * (1.0 - 1e-12) {
        let b = (10.0 * a).min(end_s);
        let n = ((STEPS_PER_DECADE as f64) * (b / a).log10())
            .ceil()
            .max(1.0) as usize;
        let dt = (b - a) / n as f64;
        steps.extend(std::iter::repeat_n(dt, n));
        a = b;
    }
    steps
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steps end at the time asked (to round-off), the first is the fraction of the fastest
    /// retardation time, and a decade takes [`STEPS_PER_DECADE`] steps.
    #[test]
    fn steps_reach_the_time_asked() {
        for (end, fastest) in [(100.0, 1.0), (0.5, 2.0), (1e-6, 1.0), (3e3, 0.01)] {
            let s = time_steps(end, fastest);
            let total: f64 = s.iter().sum();
            assert!((total - end).abs() <= 1e-9 * end, "{end}: {total}");
            assert_eq!(s[0], end.min(1e-3 * fastest));
        }
        // 1e-3 to 100 s: five decades of 50 steps, and the first step.
        assert_eq!(time_steps(100.0, 1.0).len(), 1 + 5 * STEPS_PER_DECADE);
    }
}
