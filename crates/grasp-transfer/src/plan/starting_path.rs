//! Where the planner starts: the planned fingers' commands at the keyframes
//! ([`crate::plan::starting_commands`]) gathered into the releasing and the receiving group,
//! each moved by one variable ([`PlannedGroup`]), the duration stretched to the shortest the
//! rate limits allow; which keyframes are fixed (a releasing group's start and end, a
//! receiving group's start); and the constraints no schedule can meet whatever its shape.

use std::collections::BTreeMap;

use grasp_model::Scene;

use crate::plan::keyframe_path::{KeyframePath, SHORTEST_STEP_S};
use crate::plan::option_names;
use crate::plan::plan_error::PlanError;
use crate::plan::plan_options::{Objective, PlanOptions};
use crate::plan::planned_group::{Commanded, PlannedGroup};
use crate::plan::starting_commands::{starting_commands, StartingCommands};
use crate::plan::trust_region_qp::{group_bounds, Pinned};
use crate::schedule::Schedule;
use crate::schedule_spec::{PhaseSpec, ScheduleSpec, MAX_TIME_S};
use crate::stepper::StepRecord;

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
    let records = template.and(records);
    let start = starting_commands(scene, &fingers, records, &fractions, options)?;
    let shortest_s = start.steps.max(nk - 1) as f64 * SHORTEST_STEP_S;
    check_durations(start.duration_s, shortest_s, template.is_some(), options)?;
    let released = options.releasing.len();
    let scale = approach_scale(&start, released);
    let mut groups = vec![group(
        "releasing",
        &fingers,
        &start,
        0..released,
        scale,
        options,
    )?];
    if released < fingers.len() {
        let rest = released..fingers.len();
        groups.push(group("receiving", &fingers, &start, rest, scale, options)?);
    }
    let (groups, values): (Vec<_>, Vec<_>) = groups.into_iter().unzip();
    check_starts(&fingers, &start, shortest_s, options)?;
    check_reachable(&fingers, &start, options)?;
    let mut path = KeyframePath {
        groups,
        fractions,
        values,
        duration_s: start.duration_s,
        steps: start.steps,
    };
    let pinned: Pinned = (0..path.groups.len())
        .map(|g| {
            let mut p = vec![None; nk];
            if g == 0 {
                p[0] = Some(path.values[0][0]);
                p[nk - 1] = Some(0.0);
            } else {
                p[0] = Some(0.0);
            }
            p
        })
        .collect();
    for (g, pins) in pinned.iter().enumerate() {
        let (hi, lo) = group_bounds(&path, g, options);
        for (x, pin) in path.values[g].iter_mut().zip(pins) {
            *x = pin.unwrap_or(x.clamp(lo, hi));
        }
    }
    if options.objective == Objective::Duration {
        path.duration_s = path.duration_s.max(shortest_for_rates(&path, options));
    }
    Ok((path, pinned))
}

/// The scale `c` (N/m) of the approach groups' variables (see [`PlannedGroup`]): the largest
/// planned load over the largest planned travel from a group's reference (1 N over it
/// without loads), so that travels and loads are of one order in the program.
fn approach_scale(start: &StartingCommands, released: usize) -> f64 {
    let nk = start.commands.first().map_or(1, |c| c.len());
    let mut travel_m: f64 = 1e-9;
    let mut load_n: f64 = 0.0;
    for (i, (c, &by_approach)) in start.commands.iter().zip(&start.approach).enumerate() {
        if by_approach {
            let reference = if i < released { c[nk - 1] } else { c[0] };
            travel_m = c.iter().fold(travel_m, |a, x| a.max((x - reference).abs()));
        } else {
            load_n = c.iter().fold(load_n, |a, x| a.max(x.abs()));
        }
    }
    if load_n > 0.0 {
        load_n / travel_m
    } else {
        1.0 / travel_m
    }
}

/// The group of the planned fingers `members` (indices into `fingers`) with its keyframe
/// values: a load group's shares in proportion to the loads at its free end (equal where
/// those are 0); an approach group's references at its fixed end and shares in proportion
/// to the travels from there.
fn group(
    name: &str,
    fingers: &[String],
    start: &StartingCommands,
    members: std::ops::Range<usize>,
    scale: f64,
    options: &PlanOptions,
) -> Result<(PlannedGroup, Vec<f64>), PlanError> {
    let releasing = name == "releasing";
    // A group is all one kind ([`crate::plan::starting_commands`] refuses a mixed one).
    let by_approach = start.approach[members.start];
    let commands = &start.commands[members.clone()];
    let names = &fingers[members];
    let nk = commands[0].len();
    let (free, fixed) = if releasing { (0, nk - 1) } else { (nk - 1, 0) };
    let (commanded, unit, references) = if by_approach {
        let references: Vec<f64> = commands.iter().map(|c| c[fixed]).collect();
        let range_m = approach_range(names, commands, options, releasing)?;
        let commanded = Commanded::Approach {
            newtons_per_metre: scale,
            reference_m: references.clone(),
            range_m,
        };
        (commanded, scale, references)
    } else {
        (Commanded::Load, 1.0, vec![0.0; names.len()])
    };
    let travel: Vec<f64> = commands
        .iter()
        .zip(&references)
        .map(|(c, r)| (c[free] - r).abs())
        .collect();
    let mean = travel.iter().sum::<f64>() / travel.len() as f64;
    let even = mean > 0.0 && (!by_approach || travel.iter().all(|t| *t > 0.0));
    let shares: Vec<f64> = travel
        .iter()
        .map(|t| if even { t / mean } else { 1.0 })
        .collect();
    let total: f64 = shares.iter().sum();
    let values = (0..nk)
        .map(|k| {
            let sum: f64 = commands
                .iter()
                .zip(&references)
                .map(|(c, r)| c[k] - r)
                .sum();
            unit * sum / total
        })
        .collect();
    let group = PlannedGroup {
        name: name.into(),
        members: names.iter().cloned().zip(shares).collect(),
        commanded,
    };
    Ok((group, values))
}

/// The approaches a group keeps within, m: the options', else the span of its starting
/// commands; a releasing jaw must open, and every fixed end lie within.
fn approach_range(
    names: &[String],
    commands: &[Vec<f64>],
    options: &PlanOptions,
    releasing: bool,
) -> Result<(f64, f64), PlanError> {
    let all = commands.iter().flatten();
    let lo = options
        .min_approach_m
        .unwrap_or_else(|| all.clone().fold(f64::INFINITY, |a, &x| a.min(x)));
    let hi = options
        .max_approach_m
        .unwrap_or_else(|| all.fold(f64::NEG_INFINITY, |a, &x| a.max(x)));
    for (name, c) in names.iter().zip(commands) {
        let (start_m, end_m) = (c[0], c[c.len() - 1]);
        if releasing && end_m >= start_m {
            return Err(PlanError::NotOpening {
                finger: name.clone(),
                start_m,
                end_m,
            });
        }
        let fixed = if releasing {
            [start_m, end_m]
        } else {
            [start_m; 2]
        };
        if let Some(&a) = fixed.iter().find(|a| !(lo..=hi).contains(*a)) {
            return Err(PlanError::ApproachOutsideRange {
                finger: name.clone(),
                approach_m: a,
                range_m: (lo, hi),
            });
        }
    }
    Ok((lo, hi))
}

/// The shortest duration at which the path's keyframe spans keep the rate limits, s (0
/// without a limit that applies to a group).
fn shortest_for_rates(path: &KeyframePath, options: &PlanOptions) -> f64 {
    let limits = options.rate_limits();
    if path
        .groups
        .iter()
        .all(|g| g.variable_rate(&limits).is_none())
    {
        return 0.0;
    }
    let by_rates = path.shortest_duration_s(&limits);
    (options.min_duration_s.max(by_rates)).max(path.shortest_planned_s())
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

/// Every releasing force-controlled finger starts within the load bound (its first keyframe
/// is fixed at its starting load), and, for the shortest duration, the rate limits bind: the
/// largest starting load (the longest opening) takes longer than the shortest planned
/// schedule (`shortest_s`, s) to fall at its limit.
fn check_starts(
    fingers: &[String],
    start: &StartingCommands,
    shortest_s: f64,
    options: &PlanOptions,
) -> Result<(), PlanError> {
    for (name, c) in releasing_commands(fingers, start, options, false) {
        if c[0] > options.max_load_n {
            return Err(PlanError::MaxLoadBelowStart {
                finger: name.clone(),
                load_n: c[0],
                max_load_n: options.max_load_n,
            });
        }
    }
    if options.objective != Objective::Duration {
        return Ok(());
    }
    // The first of the largest changes (a tie names the first finger): a load falls from its
    // start to 0 N, a jaw opens from its start to its end.
    let largest = |approach: bool| {
        let each = releasing_commands(fingers, start, options, approach);
        let change = |c: &Vec<f64>| match approach {
            true => (c[0] - c[c.len() - 1]).abs(),
            false => c[0],
        };
        let changes = each.map(|(n, c)| (n, change(c)));
        changes.fold(None, |a: Option<(&String, f64)>, b| match a {
            Some(a) if a.1 >= b.1 => Some(a),
            _ => Some(b),
        })
    };
    if let (Some(rate), Some((finger, load_n))) = (options.max_rate_n_per_s, largest(false)) {
        if load_n / rate < shortest_s {
            return Err(PlanError::RateTooLarge {
                finger: finger.clone(),
                load_n,
                rate_n_per_s: rate,
                shortest_s,
            });
        }
    }
    if let (Some(speed), Some((finger, travel_m))) = (options.max_speed_m_per_s, largest(true)) {
        if travel_m / speed < shortest_s {
            return Err(PlanError::Speed {
                finger: finger.clone(),
                travel_m,
                speed_m_per_s: speed,
                limit_s: shortest_s,
                too_fast: true,
            });
        }
    }
    Ok(())
}

/// The releasing fingers driven by loads (`approach` false) or by approaches, with their
/// starting commands.
fn releasing_commands<'a>(
    fingers: &'a [String],
    start: &'a StartingCommands,
    options: &PlanOptions,
    approach: bool,
) -> impl Iterator<Item = (&'a String, &'a Vec<f64>)> {
    let each = fingers.iter().zip(&start.commands).zip(&start.approach);
    let releasing = each.take(options.releasing.len());
    releasing
        .filter(move |(_, a)| **a == approach)
        .map(|(fc, _)| fc)
}

/// A releasing finger must fall from its start to 0 N (or open from its start to its end)
/// within the longest duration allowed (the margin objective: the fixed one; at most 1e9 s):
/// otherwise no schedule keeps the rate limit.
fn check_reachable(
    fingers: &[String],
    start: &StartingCommands,
    options: &PlanOptions,
) -> Result<(), PlanError> {
    let longest = match options.objective {
        Objective::Margin => start.duration_s,
        Objective::Duration => options.max_duration_s.min(MAX_TIME_S),
    };
    if let Some(rate) = options.max_rate_n_per_s {
        for (name, c) in releasing_commands(fingers, start, options, false) {
            let needed_s = c[0] / rate;
            if needed_s > longest * (1.0 + 1e-9) {
                return Err(PlanError::RateTooSmall {
                    finger: name.clone(),
                    load_n: c[0],
                    rate_n_per_s: rate,
                    needed_s,
                    allowed_s: longest,
                });
            }
        }
    }
    let Some(speed) = options.max_speed_m_per_s else {
        return Ok(());
    };
    for (name, c) in releasing_commands(fingers, start, options, true) {
        let travel_m = (c[0] - c[c.len() - 1]).abs();
        if travel_m / speed > longest * (1.0 + 1e-9) {
            return Err(PlanError::Speed {
                finger: name.clone(),
                travel_m,
                speed_m_per_s: speed,
                limit_s: longest,
                too_fast: false,
            });
        }
    }
    Ok(())
}
