//! The minimum squeeze of a hand-off: the smallest load of the receiving fingers at which the
//! releasing fingers can let go without any finger sliding as a whole.
//!
//! The grasp after the hand-off (the commands of the schedule's last step: held fingers,
//! force-controlled receiving fingers, released ones dropped) is solved with every receiving
//! finger's load scaled by a common factor `s` of its scheduled final load; bisection on `s`
//! finds the smallest factor at which the grasp holds: the step solves and every loaded
//! frictional finger keeps at least one sticking element (a finger whose elements all slip
//! slides as a whole, `|Q| = mu P`). Each trial starts from a fresh contact state (no slip
//! memory): the answer is a property of the final grasp, not of the path to it. Under the
//! coulomb model normal forces come only from the commanded loads, so this is the grip the
//! receiving gripper must command; under the energy model it is the load above which the
//! model's own squeeze suffices.

use grasp_model::Readable;
use grasp_model::{
    Control, GraspModel, GraspSolver, LoadedScene, Solution, SolveOptions, StepInputs,
};
use serde::Serialize;

use crate::error::TransferError;
use crate::schedule::Command;
use crate::stepper::StepRecord;

/// Relative width of the final bisection bracket.
pub const SQUEEZE_TOLERANCE: f64 = 1e-4;

/// Largest factor over the scheduled loads that is tried.
pub const MAX_SQUEEZE_FACTOR: f64 = 1e3;

/// Smallest factor over the scheduled loads the bisection narrows to: below it the receiving
/// loads are within the solves' accuracy (about 1e-10 of the load) of none, and the search
/// stops there and says so.
pub const MIN_SQUEEZE_FACTOR: f64 = 1e-6;

/// Largest number of bisection steps: narrowing `[0, 1e3]` to [`SQUEEZE_TOLERANCE`] of an
/// upper end as small as [`MIN_SQUEEZE_FACTOR`] takes about 44.
const MAX_BISECTION_STEPS: u32 = 100;

/// One receiving finger's minimum and scheduled loads.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SqueezeFinger {
    /// Finger name.
    pub name: String,
    /// Smallest load at which the grasp holds, N.
    pub minimum_n: f64,
    /// The schedule's final load, N.
    pub scheduled_n: f64,
}

/// The minimum squeeze of a hand-off.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MinimumSqueeze {
    /// The receiving (force-controlled at the end) fingers.
    pub fingers: Vec<SqueezeFinger>,
    /// Scheduled over minimum loads: above 1 the schedule has that much margin; below 1 the
    /// scheduled grip does not hold.
    pub margin: f64,
    /// What fails just below the minimum: the finger sliding as a whole, or the solver's
    /// reason.
    pub limiting: String,
}

/// Outcome of the search.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SqueezeOutcome {
    /// Found.
    Found(MinimumSqueeze),
    /// Not applicable or not found: why.
    NotFound(String),
}

/// Whether a solved grasp holds, and if not, why.
fn holds(sol: &Solution) -> Result<(), String> {
    if !sol.status.has_forces() {
        return Err(sol.reason.clone().unwrap_or_else(|| "no solution".into()));
    }
    match sol.fingers_sliding_as_a_whole().next() {
        Some(f) => Err(format!("{} slides as a whole", f.name)),
        None => Ok(()),
    }
}

/// Finds the minimum squeeze of the grasp given by the commands of `last`, the final step of a
/// schedule over `scene`.
pub fn minimum_squeeze(
    scene: &LoadedScene,
    last: &StepRecord,
    options: SolveOptions,
) -> Result<SqueezeOutcome, TransferError> {
    let commands: Vec<Command> = last.commands.iter().map(|c| c.command).collect();
    let scheduled: Vec<(usize, f64)> = commands
        .iter()
        .enumerate()
        .filter_map(|(i, c)| match c {
            Command::Load(p) => Some((i, *p)),
            _ => None,
        })
        .collect();
    if scheduled.is_empty() {
        return Ok(SqueezeOutcome::NotFound(
            "no finger is force-controlled at the end of the schedule: the receiving grip is \
             position-held, so there is no load to minimise"
                .into(),
        ));
    }
    let base = GraspModel::from_loaded_with(scene, options.compliance).map_err(|source| {
        TransferError::Scene {
            time_s: last.time_s,
            source,
        }
    })?;
    // The final grasp with the receiving loads scaled by `s`: the scene's model restricted to
    // the active fingers (their compliance blocks are shared, not recomputed), its commanded
    // loads the trial's. The trial load is the model's, not only its inputs': a model's scales
    // follow its commanded loads (model.md, "Scale before solving"), and a program scaled to
    // the scheduled loads fails to certify the trials just below the minimum (the coulomb
    // plate hand-off's ended in Clarabel's iteration limit, `tests/coulomb_handoff.rs`).
    let trial = |s: f64| -> Result<Solution, TransferError> {
        let active: Vec<(usize, Control)> = commands
            .iter()
            .enumerate()
            .filter_map(|(i, c)| match c.control()? {
                Control::NormalLoad { newtons } => Some((
                    i,
                    Control::NormalLoad {
                        newtons: s * newtons,
                    },
                )),
                control => Some((i, control)),
            })
            .collect();
        let model = base.restricted(&active).ok_or(TransferError::Internal(
            "the final grasp has no active finger",
        ))?;
        let inputs = StepInputs::of_scene(&model);
        Ok(GraspSolver::new(model, options).solve(&inputs)?)
    };
    let (hi, limiting) = match smallest_factor(|s| Ok(holds(&trial(s)?)))? {
        Ok(found) => found,
        Err(why) => return Ok(SqueezeOutcome::NotFound(why)),
    };
    Ok(SqueezeOutcome::Found(MinimumSqueeze {
        fingers: scheduled
            .iter()
            .map(|&(i, p)| SqueezeFinger {
                name: scene.fingers[i].name.clone(),
                minimum_n: hi * p,
                scheduled_n: p,
            })
            .collect(),
        margin: if hi > 0.0 { 1.0 / hi } else { f64::INFINITY },
        limiting,
    }))
}

/// The smallest factor `s` of the scheduled loads at which the grasp holds (`holds_at(s)` is
/// `Ok(Ok(()))`, or `Ok(Err(why))` where it does not), with what fails just below it; `Err` (why) when it does not hold up to [`MAX_SQUEEZE_FACTOR`]. Bracketed by
/// the smallest power of two (from 1) that holds, then bisected to [`SQUEEZE_TOLERANCE`] (at
/// most [`MAX_BISECTION_STEPS`] steps, down to [`MIN_SQUEEZE_FACTOR`]; stopping there is said
/// in the second value).
fn smallest_factor(
    mut holds_at: impl FnMut(f64) -> Result<Result<(), String>, TransferError>,
) -> Result<Result<(f64, String), String>, TransferError> {
    let mut hi = 1.0;
    while let Err(why) = holds_at(hi)? {
        hi *= 2.0;
        if hi > MAX_SQUEEZE_FACTOR {
            return Ok(Err(format!(
                "the grasp does not hold even at {MAX_SQUEEZE_FACTOR} times the scheduled \
                 loads ({why})"
            )));
        }
    }
    let mut lo = 0.0;
    let mut limiting = match holds_at(0.0)? {
        Ok(()) => {
            hi = 0.0;
            "the grasp holds without any receiving load".to_string()
        }
        Err(why) => why,
    };
    let mut steps = 0;
    while hi - lo > SQUEEZE_TOLERANCE * hi {
        let stop = if hi <= MIN_SQUEEZE_FACTOR {
            "the grasp holds with practically no receiving load"
        } else if steps == MAX_BISECTION_STEPS {
            "the bisection reached its step limit"
        } else {
            ""
        };
        if !stop.is_empty() {
            limiting = format!(
                "{limiting}; the search stopped at {} times the scheduled loads, before its \
                 tolerance {SQUEEZE_TOLERANCE:e}: {stop}",
                Readable(hi)
            );
            break;
        }
        steps += 1;
        let mid = 0.5 * (lo + hi);
        match holds_at(mid)? {
            Ok(()) => hi = mid,
            Err(why) => {
                lo = mid;
                limiting = why;
            }
        }
    }
    Ok(Ok((hi, limiting)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The search against predicates with known answers: a threshold is found within
    /// [`SQUEEZE_TOLERANCE`] from above; a grasp that holds at every positive load but not at
    /// none stops at [`MIN_SQUEEZE_FACTOR`] and says so; one that never holds is not found.
    /// Each is bounded in trials.
    #[test]
    fn the_search_finds_thresholds_and_stops_where_it_cannot_narrow() {
        // (The bracket doubles from 1 up to 512: a threshold above that is not found.)
        for threshold in [0.3, 1.0, 7.5, 500.0] {
            let mut trials = 0;
            let (hi, why) = smallest_factor(|s| {
                trials += 1;
                Ok(if s >= threshold {
                    Ok(())
                } else {
                    Err("slides".into())
                })
            })
            .unwrap()
            .unwrap();
            assert!(
                hi >= threshold && hi - threshold <= SQUEEZE_TOLERANCE * hi,
                "{hi}"
            );
            assert_eq!(why, "slides");
            assert!(trials < 40, "{trials}");
        }
        let mut trials = 0;
        let (hi, why) = smallest_factor(|s| {
            trials += 1;
            Ok(if s > 0.0 {
                Ok(())
            } else {
                Err("slides".into())
            })
        })
        .unwrap()
        .unwrap();
        assert!(hi <= MIN_SQUEEZE_FACTOR && hi > 0.0, "{hi}");
        assert!(why.contains("practically no receiving load"), "{why}");
        assert!(why.contains("stopped at 9.5367431640625e-7 times"), "{why}");
        assert!(trials <= 2 + 21, "{trials}");
        let beyond: [fn(f64) -> bool; 2] = [|_| false, |s| s > 600.0];
        for never in beyond {
            let found = smallest_factor(|s| {
                Ok(if never(s) {
                    Ok(())
                } else {
                    Err("no equilibrium".into())
                })
            })
            .unwrap();
            assert!(found.unwrap_err().contains("even at 1000 times"));
        }
        let at_zero = smallest_factor(|_| Ok(Ok(()))).unwrap().unwrap();
        assert_eq!(at_zero.0, 0.0);
    }
}
