//! The planned fingers' commands where the plan starts, at its keyframes: the template's,
//! sampled (with its own duration and step count), or, without one, straight ramps; and which
//! fingers the plan drives by their approach (position control: a servo's jaws, an approach
//! ramp) rather than by their load.
//!
//! Straight ramps: a releasing finger from its load in the scene to 0 N, or from its approach
//! in the scene to [`PlanOptions::open_to_m`]; a receiving finger from 0 N to the releasing
//! fingers' mean load, or from its approach in the scene to [`PlanOptions::close_to_m`]. Either
//! option, given with a template, replaces the template's end of those fingers.

use grasp_model::Scene;

use crate::plan::option_names;
use crate::plan::plan_error::PlanError;
use crate::plan::plan_options::{Objective, PlanOptions};
use crate::schedule::Command;
use crate::stepper::StepRecord;

/// Steps of a plan without a template or `--steps`.
pub const DEFAULT_STEPS: usize = 60;

/// The planned fingers' starting commands (releasing first, then receiving).
#[derive(Debug, Clone, PartialEq)]
pub struct StartingCommands {
    /// Per planned finger, true when the plan drives its approach.
    pub approach: Vec<bool>,
    /// `commands[i][k]`: finger `i`'s load (N) or approach (m) at keyframe `k`.
    pub commands: Vec<Vec<f64>>,
    /// The starting duration, s.
    pub duration_s: f64,
    /// Steps after the first.
    pub steps: usize,
}

/// The starting commands of `fingers` (the releasing ones first: `releasing` of them), from
/// the template's run `records` when there is one (see the module).
pub fn starting_commands(
    scene: &Scene,
    fingers: &[String],
    records: Option<&[StepRecord]>,
    fractions: &[f64],
    options: &PlanOptions,
) -> Result<StartingCommands, PlanError> {
    let approach: Vec<bool> = fingers
        .iter()
        .enumerate()
        .map(|(i, n)| position_controlled(scene, n, i < options.releasing.len(), records))
        .collect();
    let released = options.releasing.len();
    uniform_control(fingers, &approach, 0..released, option_names::RELEASING)?;
    let receiving = released..fingers.len();
    uniform_control(fingers, &approach, receiving, option_names::RECEIVING)?;
    check_options_apply(&approach, released, options)?;
    let mut start = match records {
        Some(r) => sampled(r, fingers, &approach, fractions, options)?,
        None => straight(scene, fingers, &approach, fractions, options)?,
    };
    let last = fractions.len() - 1;
    let ends = start.commands.iter_mut().zip(&approach).enumerate();
    for (i, (c, _)) in ends.filter(|(_, (_, a))| **a) {
        let end = match i < released {
            true => options.open_to_m,
            false => options.close_to_m,
        };
        if let Some(end_m) = end {
            c[last] = end_m;
        }
    }
    Ok(start)
}

/// True when the plan drives `name` by its approach: the first command of the template's
/// run other than held is an approach (a held finger is one at approach 0; a template may
/// hold a finger before it ramps its load from `"current"`), or, held throughout, the scene
/// gives it an approach; without a template also when the scene holds it and it lets go (a
/// held receiving finger is loaded from 0 N, a held finger of a template from its load).
fn position_controlled(
    scene: &Scene,
    name: &str,
    releasing: bool,
    records: Option<&[StepRecord]>,
) -> bool {
    let commands = records.unwrap_or_default().iter().flat_map(|r| &r.commands);
    let first = commands
        .filter(|c| c.name == name && !matches!(c.command, Command::Held))
        .map(|c| c.command)
        .next();
    match first {
        Some(Command::Approach(_)) => true,
        Some(_) => false,
        None => scene
            .fingers
            .iter()
            .find(|f| f.name == name)
            .is_some_and(|f| {
                let held = f.control.normal_load_n().is_none();
                f.control.approach_m().is_some() || (releasing && held && records.is_none())
            }),
    }
}

/// Refuses a group `members` (indices into `fingers`, named by `option`) that mixes fingers
/// driven by approaches with ones driven by loads: one variable moves a group.
fn uniform_control(
    fingers: &[String],
    approach: &[bool],
    members: std::ops::Range<usize>,
    option: &'static str,
) -> Result<(), PlanError> {
    let of = |kind: bool| {
        let names = members.clone().filter(|&i| approach[i] == kind);
        names.map(|i| fingers[i].as_str()).collect::<Vec<_>>()
    };
    let (approaches, loads) = (of(true), of(false));
    if approaches.is_empty() || loads.is_empty() {
        return Ok(());
    }
    Err(PlanError::MixedControl {
        option,
        loads: loads.join(", "),
        approaches: approaches.join(", "),
    })
}

/// Every option given applies to a planned group (`approach`: per planned finger, releasing
/// first, `released` of them), and, for the shortest duration, every group has the rate limit
/// of its kind (N/s for loads, m/s for approaches): a group without one could change as fast
/// as the program likes, and a limit no group takes is a mistake.
fn check_options_apply(
    approach: &[bool],
    released: usize,
    options: &PlanOptions,
) -> Result<(), PlanError> {
    let groups = [
        ("releasing", &approach[..released]),
        ("receiving", &approach[released..]),
    ];
    let groups: Vec<(&str, bool)> = groups
        .iter()
        .filter(|(_, members)| !members.is_empty())
        .map(|(name, members)| (*name, members[0]))
        .collect();
    let by_approach = |name: &str| groups.iter().any(|g| g.0 == name && g.1);
    let jaws = groups.iter().any(|g| g.1);
    let loads = groups.iter().any(|g| !g.1);
    let unused = [
        (
            options.open_to_m.is_some() && !by_approach("releasing"),
            option_names::OPEN_TO,
        ),
        (
            options.close_to_m.is_some() && !by_approach("receiving"),
            option_names::CLOSE_TO,
        ),
        (
            options.min_approach_m.is_some() && !jaws,
            option_names::MIN_APPROACH,
        ),
        (
            options.max_approach_m.is_some() && !jaws,
            option_names::MAX_APPROACH,
        ),
        (
            options.max_speed_m_per_s.is_some() && !jaws,
            option_names::MAX_SPEED,
        ),
        (
            options.max_rate_n_per_s.is_some() && !loads,
            option_names::MAX_RATE,
        ),
    ];
    if let Some(&(_, option)) = unused.iter().find(|(unused, _)| *unused) {
        return Err(PlanError::OptionUnused { option });
    }
    let limit = |jaw: bool| match jaw {
        true => (options.max_speed_m_per_s, option_names::MAX_SPEED),
        false => (options.max_rate_n_per_s, option_names::MAX_RATE),
    };
    let unlimited = groups.iter().find(|g| limit(g.1).0.is_none());
    match (options.objective, unlimited) {
        (Objective::Duration, Some(&(group, jaw))) => Err(PlanError::NoRateOfGroup {
            group: group.to_string(),
            option: limit(jaw).1,
        }),
        _ => Ok(()),
    }
}

/// Finger `name`'s command at the template's step `r`: its load (N), or, when `approach`,
/// its approach (m; held is 0).
fn command_at(name: &str, r: &StepRecord, approach: bool) -> Result<f64, PlanError> {
    let c = r
        .commands
        .iter()
        .find(|c| c.name == name)
        .map(|c| c.command);
    match (approach, c) {
        (true, Some(Command::Approach(a))) => Ok(a),
        (true, Some(Command::Held)) => Ok(0.0),
        (true, _) => Err(PlanError::NotPositionControlled {
            finger: name.to_string(),
            time_s: r.time_s,
        }),
        (false, Some(Command::Load(p))) => Ok(p),
        (false, Some(Command::Released)) => Ok(0.0),
        // Held at a step (the template's `"current"` before its ramp): the load it carries.
        (false, Some(Command::Held)) if r.solution.status.has_forces() => {
            Ok(r.normal_force_n(name))
        }
        (false, _) => Err(PlanError::NotForceControlled {
            finger: name.to_string(),
            time_s: r.time_s,
        }),
    }
}

/// The template's commands at the keyframes, its duration and step count.
fn sampled(
    records: &[StepRecord],
    fingers: &[String],
    approach: &[bool],
    fractions: &[f64],
    options: &PlanOptions,
) -> Result<StartingCommands, PlanError> {
    let (t0, t1) = match (records.first(), records.last()) {
        (Some(a), Some(b)) if b.time_s > a.time_s => (a.time_s, b.time_s),
        _ => return Err(PlanError::TemplateTooShort),
    };
    let mut commands = Vec::new();
    for (name, &by_approach) in fingers.iter().zip(approach) {
        let mut row = Vec::new();
        for f in fractions {
            let t = t0 + f * (t1 - t0);
            let k = records
                .partition_point(|r| r.time_s < t)
                .min(records.len() - 1);
            let (a, b) = (&records[k.saturating_sub(1)], &records[k]);
            let ca = command_at(name, a, by_approach)?;
            let cb = command_at(name, b, by_approach)?;
            let w = if b.time_s > a.time_s {
                (t - a.time_s) / (b.time_s - a.time_s)
            } else {
                1.0
            };
            row.push(ca + w.clamp(0.0, 1.0) * (cb - ca));
        }
        commands.push(row);
    }
    Ok(StartingCommands {
        approach: approach.to_vec(),
        commands,
        duration_s: options.duration_s.unwrap_or(t1 - t0),
        steps: options.steps.unwrap_or(records.len() - 1).max(2),
    })
}

/// Straight ramps from the scene's commands (see the module).
fn straight(
    scene: &Scene,
    fingers: &[String],
    approach: &[bool],
    fractions: &[f64],
    options: &PlanOptions,
) -> Result<StartingCommands, PlanError> {
    let released = options.releasing.len();
    let mut ends = Vec::new();
    for (i, (name, &by_approach)) in fingers.iter().zip(approach).enumerate() {
        let control = scene
            .fingers
            .iter()
            .find(|f| &f.name == name)
            .expect("a checked name")
            .control;
        let start = match (by_approach, control.normal_load_n()) {
            (true, _) => control.approach_m().unwrap_or(0.0),
            // A receiving finger's load ramp starts at 0 N, whatever the scene gives it.
            (false, _) if i >= released => 0.0,
            (false, Some(p)) if p > 0.0 => p,
            (false, _) => {
                return Err(PlanError::NotForceControlled {
                    finger: name.clone(),
                    time_s: 0.0,
                })
            }
        };
        ends.push((start, end_of(name, i < released, by_approach, options)?));
    }
    let receiving_load = mean_releasing_load(&ends, approach, released, options);
    let mut commands = Vec::new();
    for (i, (start, end)) in ends.iter().enumerate() {
        let (a, b) = match (i < released, approach[i]) {
            (false, false) => (0.0, receiving_load.ok_or_else(|| no_end(&fingers[i]))?),
            _ => (*start, end.unwrap_or(0.0)),
        };
        commands.push(fractions.iter().map(|f| a + f * (b - a)).collect());
    }
    let duration_s = straight_duration(&commands, approach, options)?;
    Ok(StartingCommands {
        approach: approach.to_vec(),
        commands,
        duration_s,
        steps: options.steps.unwrap_or(DEFAULT_STEPS),
    })
}

/// Where a straight ramp of `name` ends: a releasing load at 0 N, a releasing approach at
/// [`PlanOptions::open_to_m`], a receiving approach at [`PlanOptions::close_to_m`] (each
/// needed); a receiving load is decided with the others (`None`).
fn end_of(
    name: &str,
    releasing: bool,
    by_approach: bool,
    options: &PlanOptions,
) -> Result<Option<f64>, PlanError> {
    let needed = |value: Option<f64>, option: &'static str| {
        value.map(Some).ok_or_else(|| PlanError::NoEnd {
            finger: name.to_string(),
            option,
        })
    };
    match (releasing, by_approach) {
        (true, false) => Ok(Some(0.0)),
        (true, true) => needed(options.open_to_m, option_names::OPEN_TO),
        (false, true) => needed(options.close_to_m, option_names::CLOSE_TO),
        (false, false) => Ok(None),
    }
}

/// The end of a receiving finger's straight load ramp: the releasing force-controlled
/// fingers' mean starting load within the load bounds, or, when none is force-controlled, the
/// largest load allowed when it is finite.
fn mean_releasing_load(
    ends: &[(f64, Option<f64>)],
    approach: &[bool],
    released: usize,
    options: &PlanOptions,
) -> Option<f64> {
    let loads: Vec<f64> = (0..released)
        .filter(|&i| !approach[i])
        .map(|i| ends[i].0)
        .collect();
    if loads.is_empty() {
        return options.max_load_n.is_finite().then_some(options.max_load_n);
    }
    let mean = loads.iter().sum::<f64>() / loads.len() as f64;
    Some(mean.clamp(options.min_load_n, options.max_load_n))
}

/// The refusal of a receiving force-controlled finger with no load to ramp up to.
fn no_end(finger: &str) -> PlanError {
    PlanError::NoEnd {
        finger: finger.to_string(),
        option: option_names::MAX_LOAD,
    }
}

/// The duration of straight ramps: the one given, else the longest change at its limit.
fn straight_duration(
    commands: &[Vec<f64>],
    approach: &[bool],
    options: &PlanOptions,
) -> Result<f64, PlanError> {
    if let Some(d) = options.duration_s {
        return Ok(d);
    }
    let mut longest: Option<f64> = None;
    for (c, &by_approach) in commands.iter().zip(approach) {
        let limit = if by_approach {
            options.max_speed_m_per_s
        } else {
            options.max_rate_n_per_s
        };
        let change = (c[c.len() - 1] - c[0]).abs();
        if let Some(rate) = limit {
            longest = Some(longest.unwrap_or(0.0).max(change / rate));
        }
    }
    longest.filter(|t| *t > 0.0).ok_or(PlanError::NoDuration)
}
