//! Where the planner starts: the template's loads sampled at the keyframes (its own duration
//! and step count), or, without one, straight ramps (the releasing fingers from their loads
//! in the scene to 0 N, the receiving ones from 0 N to the releasing fingers' mean), the
//! duration stretched to the shortest the load-rate limit allows; which keyframes are fixed;
//! and the constraints no schedule can meet whatever its shape.

use std::collections::BTreeMap;

use grasp_model::Scene;

use crate::plan::keyframe_path::{KeyframePath, LoadGroup, SHORTEST_STEP_S};
use crate::plan::option_names;
use crate::plan::plan_error::PlanError;
use crate::plan::plan_options::{Objective, PlanOptions};
use crate::plan::trust_region_qp::{group_bounds, Pinned};
use crate::schedule::{Command, Schedule};
use crate::schedule_spec::{PhaseSpec, ScheduleSpec, MAX_TIME_S};
use crate::stepper::StepRecord;

/// Steps of a plan without a template or `--steps`.
pub const DEFAULT_STEPS: usize = 60;

/// The user's schedule: the planner's start and its comparison.
pub struct Template<'a> {
    /// As written (the phases of the fingers not planned are kept as they are).
    pub spec: &'a ScheduleSpec,
    /// Resolved against the scene.
    pub schedule: &'a Schedule,
}

impl Template<'_> {
    /// The template's phases of the fingers the plan leaves alone.
    pub fn others(&self, options: &PlanOptions) -> BTreeMap<String, Vec<PhaseSpec>> {
        let planned = |n: &String| options.releasing.contains(n) || options.receiving.contains(n);
        let mut out = self.spec.fingers.clone();
        out.retain(|n, _| !planned(n));
        out
    }
}

/// The starting path and its fixed keyframes (see the module).
pub fn starting_path(
    scene: &Scene,
    template: Option<&Template<'_>>,
    records: Option<&[StepRecord]>,
    options: &PlanOptions,
) -> Result<(KeyframePath, Pinned), PlanError> {
    let fingers: Vec<String> = options
        .releasing
        .iter()
        .chain(&options.receiving)
        .cloned()
        .collect();
    let nk = options.keyframes;
    let fractions: Vec<f64> = (0..nk).map(|k| k as f64 / (nk - 1) as f64).collect();
    let (loads_n, duration_s, steps) = match (template, records) {
        (Some(_), Some(r)) => sampled(r, &fingers, &fractions, options)?,
        _ => straight(scene, &fingers, &fractions, options)?,
    };
    let shortest_s = steps.max(nk - 1) as f64 * SHORTEST_STEP_S;
    check_durations(duration_s, shortest_s, template.is_some(), options)?;
    check_starts(&fingers, &loads_n, shortest_s, options)?;
    check_reachable(&fingers, &loads_n, duration_s, options)?;
    let released = options.releasing.len();
    let mut groups = vec![group(
        "releasing",
        &fingers[..released],
        &loads_n[..released],
        0,
    )];
    if released < fingers.len() {
        let rest = (&fingers[released..], &loads_n[released..]);
        groups.push(group("receiving", rest.0, rest.1, nk - 1));
    }
    let group_loads = groups
        .iter()
        .enumerate()
        .map(|(g, grp)| {
            let members = if g == 0 {
                &loads_n[..released]
            } else {
                &loads_n[released..]
            };
            let shares: f64 = grp.members.iter().map(|m| m.1).sum();
            (0..nk)
                .map(|k| members.iter().map(|l| l[k]).sum::<f64>() / shares)
                .collect()
        })
        .collect();
    let mut path = KeyframePath {
        groups,
        fractions,
        loads_n: group_loads,
        duration_s,
        steps,
    };
    let pinned: Pinned = (0..path.groups.len())
        .map(|g| {
            let mut p = vec![None; nk];
            if g == 0 {
                p[0] = Some(path.loads_n[0][0]);
                p[nk - 1] = Some(0.0);
            } else {
                p[0] = Some(0.0);
            }
            p
        })
        .collect();
    for (g, pins) in pinned.iter().enumerate() {
        let (hi, lo) = group_bounds(&path, g, options);
        for (x, pin) in path.loads_n[g].iter_mut().zip(pins) {
            *x = pin.unwrap_or(x.clamp(lo, hi));
        }
    }
    if options.objective == Objective::Duration {
        path.duration_s = path.duration_s.max(shortest_for_rates(&path, options));
    }
    Ok((path, pinned))
}

/// The group of `fingers` with their keyframe loads: shares in proportion to their loads at
/// keyframe `k` (equal where those are 0).
fn group(name: &str, fingers: &[String], loads: &[Vec<f64>], k: usize) -> LoadGroup {
    let mean = loads.iter().map(|l| l[k]).sum::<f64>() / loads.len().max(1) as f64;
    let members = fingers
        .iter()
        .zip(loads)
        .map(|(f, l)| (f.clone(), if mean > 0.0 { l[k] / mean } else { 1.0 }))
        .collect();
    LoadGroup {
        name: name.into(),
        members,
    }
}

/// The template's loads at the keyframes, its duration and step count.
fn sampled(
    records: &[StepRecord],
    fingers: &[String],
    fractions: &[f64],
    options: &PlanOptions,
) -> Result<(Vec<Vec<f64>>, f64, usize), PlanError> {
    let (t0, t1) = match (records.first(), records.last()) {
        (Some(a), Some(b)) if b.time_s > a.time_s => (a.time_s, b.time_s),
        _ => return Err(PlanError::TemplateTooShort),
    };
    let load_at = |name: &str, r: &StepRecord| -> Result<f64, PlanError> {
        let c = r
            .commands
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.command);
        match c {
            Some(Command::Load(p)) => Ok(p),
            Some(Command::Released) => Ok(0.0),
            // Held at a step (the template's `"current"` before its ramp): the load it carries.
            Some(Command::Held) if r.solution.status.has_forces() => Ok(r.normal_force_n(name)),
            _ => Err(PlanError::NotForceControlled {
                finger: name.to_string(),
                time_s: r.time_s,
            }),
        }
    };
    let mut loads = Vec::new();
    for name in fingers {
        let mut row = Vec::new();
        for f in fractions {
            let t = t0 + f * (t1 - t0);
            let k = records
                .partition_point(|r| r.time_s < t)
                .min(records.len() - 1);
            let (a, b) = (&records[k.saturating_sub(1)], &records[k]);
            let (la, lb) = (load_at(name, a)?, load_at(name, b)?);
            let w = if b.time_s > a.time_s {
                (t - a.time_s) / (b.time_s - a.time_s)
            } else {
                1.0
            };
            row.push(la + w.clamp(0.0, 1.0) * (lb - la));
        }
        loads.push(row);
    }
    let duration = options.duration_s.unwrap_or(t1 - t0);
    Ok((
        loads,
        duration,
        options.steps.unwrap_or(records.len() - 1).max(2),
    ))
}

/// Straight ramps from the scene's loads (see the module).
fn straight(
    scene: &Scene,
    fingers: &[String],
    fractions: &[f64],
    options: &PlanOptions,
) -> Result<(Vec<Vec<f64>>, f64, usize), PlanError> {
    let mut starts = Vec::new();
    for name in &options.releasing {
        let f = scene
            .fingers
            .iter()
            .find(|f| &f.name == name)
            .expect("a checked name");
        match f.control.normal_load_n() {
            Some(p) if p > 0.0 => starts.push(p),
            _ => {
                return Err(PlanError::NotForceControlled {
                    finger: name.clone(),
                    time_s: 0.0,
                })
            }
        }
    }
    let end = (starts.iter().sum::<f64>() / starts.len() as f64)
        .clamp(options.min_load_n, options.max_load_n);
    let loads = fingers
        .iter()
        .enumerate()
        .map(|(i, _)| {
            let (a, b) = if i < starts.len() {
                (starts[i], 0.0)
            } else {
                (0.0, end)
            };
            fractions.iter().map(|f| a + f * (b - a)).collect()
        })
        .collect();
    let duration = match (options.duration_s, options.max_rate_n_per_s) {
        (Some(d), _) => d,
        (None, Some(r)) => starts.iter().fold(end, |a: f64, &b| a.max(b)) / r,
        (None, None) => return Err(PlanError::NoDuration),
    };
    Ok((loads, duration, options.steps.unwrap_or(DEFAULT_STEPS)))
}

/// The shortest duration at which the path's keyframe spans keep the rate limit, s.
fn shortest_for_rates(path: &KeyframePath, options: &PlanOptions) -> f64 {
    let Some(rate) = options.max_rate_n_per_s else {
        return 0.0;
    };
    let mut t: f64 = options.min_duration_s;
    for (group, loads) in path.groups.iter().zip(&path.loads_n) {
        for k in 0..loads.len() - 1 {
            let span = path.fractions[k + 1] - path.fractions[k];
            let change = group.largest_share() * (loads[k + 1] - loads[k]).abs();
            t = t.max(change / (rate * span));
        }
    }
    t.max(path.shortest_planned_s())
}

/// The durations against what a planned schedule spans (`shortest_s`, a microsecond a step, to
/// 1e9 s): the starting one (given, the template's, or the rate's: that one is judged by the
/// rate's own checks) and the longest allowed.
fn check_durations(
    duration_s: f64,
    shortest_s: f64,
    template: bool,
    options: &PlanOptions,
) -> Result<(), PlanError> {
    let out = |option, duration_s| PlanError::DurationOutOfRange {
        option,
        duration_s,
        shortest_s,
    };
    if options.max_duration_s < shortest_s {
        return Err(out(option_names::MAX_DURATION, options.max_duration_s));
    }
    let given = match (options.duration_s, template) {
        (Some(_), _) => Some(option_names::DURATION),
        (None, true) => Some(option_names::TEMPLATE),
        (None, false) => None,
    };
    match given {
        Some(option) if !(shortest_s..=MAX_TIME_S).contains(&duration_s) => {
            Err(out(option, duration_s))
        }
        _ => Ok(()),
    }
}

/// Every releasing finger starts within the load bound (its first keyframe is fixed at its
/// starting load), and, for the shortest duration, the rate limit binds: the largest starting
/// load takes longer than the shortest planned schedule (`shortest_s`, s) to fall at it.
fn check_starts(
    fingers: &[String],
    loads_n: &[Vec<f64>],
    shortest_s: f64,
    options: &PlanOptions,
) -> Result<(), PlanError> {
    let releasing = fingers.iter().zip(loads_n).take(options.releasing.len());
    let mut largest: Option<(&String, f64)> = None;
    for (name, loads) in releasing {
        if loads[0] > options.max_load_n {
            return Err(PlanError::MaxLoadBelowStart {
                finger: name.clone(),
                load_n: loads[0],
                max_load_n: options.max_load_n,
            });
        }
        if largest.is_none_or(|l| loads[0] > l.1) {
            largest = Some((name, loads[0]));
        }
    }
    let (Some(rate), Some((finger, load_n))) = (options.max_rate_n_per_s, largest) else {
        return Ok(());
    };
    if options.objective == Objective::Duration && load_n / rate < shortest_s {
        return Err(PlanError::RateTooLarge {
            finger: finger.clone(),
            load_n,
            rate_n_per_s: rate,
            shortest_s,
        });
    }
    Ok(())
}

/// A releasing finger must fall from its start to 0 N within the longest duration allowed
/// (the margin objective: the fixed one; at most 1e9 s): otherwise no schedule keeps the rate
/// limit.
fn check_reachable(
    fingers: &[String],
    loads_n: &[Vec<f64>],
    duration_s: f64,
    options: &PlanOptions,
) -> Result<(), PlanError> {
    let Some(rate) = options.max_rate_n_per_s else {
        return Ok(());
    };
    let longest = match options.objective {
        Objective::Margin => duration_s,
        Objective::Duration => options.max_duration_s.min(MAX_TIME_S),
    };
    let releasing = fingers.iter().zip(loads_n).take(options.releasing.len());
    for (name, loads) in releasing {
        let needed_s = loads[0] / rate;
        if needed_s > longest * (1.0 + 1e-9) {
            return Err(PlanError::RateTooSmall {
                finger: name.clone(),
                load_n: loads[0],
                rate_n_per_s: rate,
                needed_s,
                allowed_s: longest,
            });
        }
    }
    Ok(())
}
