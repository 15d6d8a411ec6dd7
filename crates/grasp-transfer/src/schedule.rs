//! Load schedules: the file users script (JSON), its validation, and its evaluation in time.
//!
//! ```json
//! { "time": {"start": 0, "end": 20, "step": 0.1},          // or {"times": [0, 0.5, ...]}
//!   "fingers": {
//!     "f1": [ {"held": {"until": 0}},
//!             {"ramp": {"keyframes": [[0, "current"], [20, 0]], "easing": "smoothstep"}} ],
//!     "f3": [ {"ramp": {"keyframes": [[0, 0]]}}, {"held": {}} ],
//!     "f5": [ {"csv": {"path": "f5.csv", "time_column": "t_s", "load_column": "load_n"}} ] } }
//! ```
//!
//! Each finger runs through its phases in order; a phase lasts until its end time (`held.until`,
//! the last keyframe, the last CSV row); after the last phase its final state persists. A
//! finger whose scheduled load is zero is released: it leaves the problem at that step.
//! Fingers the schedule does not name keep the scene's control. Times in seconds, loads in
//! newtons. The keyframe value `"current"` is the normal force the finger carried at the step
//! before the phase began (so a ramp starts from whatever the grasp settled to).

use std::collections::BTreeMap;
use std::path::Path;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::easing::Easing;
use crate::error::{ScheduleError, ScheduleProblem};
use crate::load_profile::read_profile_csv;

/// Most steps a schedule may have.
pub const MAX_STEPS: usize = 1_000_000;

/// A schedule file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScheduleSpec {
    /// Free text.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The step times.
    pub time: TimeSpec,
    /// Per finger (by name), its phases in order.
    pub fingers: BTreeMap<String, Vec<PhaseSpec>>,
}

/// Step times: a span with a step, or explicit times (s, >= 0, strictly increasing).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "expected {\"start\", \"end\", \"step\"} or {\"times\": [...]}"
)]
pub enum TimeSpec {
    /// `start, start + step, ..., end` (end included when it falls on the grid to 1e-9 step).
    Span(SpanSpec),
    /// Explicit times.
    Explicit(ExplicitTimes),
}

/// A time span.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpanSpec {
    /// First time, s (>= 0: it becomes the MCAP log time).
    pub start: f64,
    /// Last time, s.
    pub end: f64,
    /// Step, s (> 0).
    pub step: f64,
}

/// Explicit step times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExplicitTimes {
    /// Times, s, strictly increasing, >= 0.
    pub times: Vec<f64>,
}

/// One phase of a finger's schedule.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum PhaseSpec {
    /// Position-held: the model finds its load.
    Held(HeldPhase),
    /// Normal load following keyframes.
    Ramp(RampPhase),
    /// Normal load read from a CSV file.
    Csv(CsvPhase),
}

/// A held phase.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HeldPhase {
    /// End of the phase, s (inclusive); absent: to the end of the schedule.
    #[serde(default)]
    pub until: Option<f64>,
}

/// A keyframe value: newtons, or `"current"`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged, expecting = "expected a load in newtons or \"current\"")]
pub enum KeyValue {
    /// A load, N.
    Newtons(f64),
    /// The finger's normal force at the step before this phase.
    Current(CurrentTag),
}

/// The literal `"current"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum CurrentTag {
    /// See [`KeyValue::Current`].
    Current,
}

/// A load ramp through keyframes `[time s, load]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RampPhase {
    /// Keyframes, times strictly increasing.
    pub keyframes: Vec<(f64, KeyValue)>,
    /// Interpolation between keyframes (default `linear`).
    #[serde(default)]
    pub easing: Easing,
}

/// A load profile from a CSV file (header row; comma-separated numbers).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CsvPhase {
    /// CSV file, relative to the schedule file's folder.
    pub path: String,
    /// Column of times, s.
    pub time_column: String,
    /// Column of loads, N.
    pub load_column: String,
    /// Interpolation between rows (default `linear`).
    #[serde(default)]
    pub easing: Easing,
}

/// What a finger is told to do at one step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Command {
    /// Position-held.
    Held,
    /// Prescribed normal load, N (> 0).
    Load(f64),
    /// Load zero: out of the problem.
    Released,
}

/// A validated phase with resolved keyframes.
#[derive(Debug, Clone, PartialEq)]
pub enum Phase {
    /// Held until the time (inclusive), or forever.
    Held {
        /// End, s.
        until: Option<f64>,
    },
    /// Load keyframes; `None` values are `"current"`.
    Ramp {
        /// `(time s, load N or current)`.
        keyframes: Vec<(f64, Option<f64>)>,
        /// Interpolation.
        easing: Easing,
    },
}

impl Phase {
    fn end(&self) -> Option<f64> {
        match self {
            Phase::Held { until } => *until,
            Phase::Ramp { keyframes, .. } => keyframes.last().map(|k| k.0),
        }
    }
}

/// A validated schedule, ready to evaluate.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    /// Step times, s.
    pub times: Vec<f64>,
    /// Per scene finger (scene order): its phases, or `None` to keep the scene's control.
    pub phases: Vec<Option<Vec<Phase>>>,
}

impl Schedule {
    /// Parses, validates and resolves a schedule against the scene's finger names. CSV paths
    /// are resolved relative to `base_dir`.
    pub fn from_json_str(
        text: &str,
        finger_names: &[String],
        base_dir: &Path,
    ) -> Result<Schedule, ScheduleError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let spec: ScheduleSpec =
            serde_path_to_error::deserialize(de).map_err(|e| ScheduleError::Parse {
                path: e.path().to_string(),
                message: e.inner().to_string(),
            })?;
        Schedule::from_spec(&spec, finger_names, base_dir)
    }

    /// Validates and resolves a parsed schedule.
    pub fn from_spec(
        spec: &ScheduleSpec,
        finger_names: &[String],
        base_dir: &Path,
    ) -> Result<Schedule, ScheduleError> {
        let mut v: Vec<ScheduleProblem> = Vec::new();
        let mut push = |path: String, message: String, fix: &str| {
            v.push(ScheduleProblem {
                path,
                message,
                fix: fix.to_string(),
            })
        };
        let times = match &spec.time {
            TimeSpec::Span(s) => {
                let ok = s.start.is_finite() && s.end.is_finite() && s.step.is_finite();
                if !ok || s.start < 0.0 {
                    push(
                        "time.start".into(),
                        format!("is {}", s.start),
                        "give a start time >= 0 s",
                    );
                }
                if !(s.step > 0.0) {
                    push(
                        "time.step".into(),
                        format!("is {}", s.step),
                        "give a step > 0 s",
                    );
                }
                if !(s.end >= s.start) {
                    push(
                        "time.end".into(),
                        format!("is {} s, before the start {} s", s.end, s.start),
                        "give an end time >= start (times must increase)",
                    );
                }
                if ok && s.step > 0.0 && s.end >= s.start && s.start >= 0.0 {
                    let n = ((s.end - s.start) / s.step + 1e-9).floor() as usize + 1;
                    if n > MAX_STEPS {
                        push(
                            "time.step".into(),
                            format!("gives {n} steps, more than {MAX_STEPS}"),
                            "use a larger step",
                        );
                        Vec::new()
                    } else {
                        (0..n).map(|i| s.start + i as f64 * s.step).collect()
                    }
                } else {
                    Vec::new()
                }
            }
            TimeSpec::Explicit(e) => {
                if e.times.is_empty() {
                    push(
                        "time.times".into(),
                        "is empty".into(),
                        "list at least one time",
                    );
                }
                for (i, t) in e.times.iter().enumerate() {
                    if !(t.is_finite() && *t >= 0.0) {
                        push(
                            format!("time.times[{i}]"),
                            format!("is {t}"),
                            "give times >= 0 s",
                        );
                    }
                    if i > 0 && !(*t > e.times[i - 1]) {
                        push(
                            format!("time.times[{i}]"),
                            format!("is {t} s, not after {} s", e.times[i - 1]),
                            "list times in strictly increasing order",
                        );
                    }
                }
                e.times.clone()
            }
        };
        let mut phases: Vec<Option<Vec<Phase>>> = vec![None; finger_names.len()];
        for (name, list) in &spec.fingers {
            let path = format!("fingers.{name}");
            let Some(idx) = finger_names.iter().position(|n| n == name) else {
                push(
                    path,
                    format!("no finger named `{name}` in the scene"),
                    &format!("use one of: {}", finger_names.join(", ")),
                );
                continue;
            };
            if list.is_empty() {
                push(
                    path.clone(),
                    "has no phases".into(),
                    "give at least one phase, or omit the finger",
                );
            }
            let mut resolved = Vec::with_capacity(list.len());
            let mut last_end: Option<(f64, String)> = None;
            for (p, phase) in list.iter().enumerate() {
                let pp = format!("{path}[{p}]");
                let ph = match phase {
                    PhaseSpec::Held(h) => {
                        if let Some(u) = h.until {
                            if !u.is_finite() {
                                push(
                                    format!("{pp}.held.until"),
                                    format!("is {u}"),
                                    "give a finite time in s",
                                );
                            }
                        }
                        Phase::Held { until: h.until }
                    }
                    PhaseSpec::Ramp(r) => {
                        if r.keyframes.is_empty() {
                            push(
                                format!("{pp}.ramp.keyframes"),
                                "is empty".into(),
                                "give at least one [time, load]",
                            );
                        }
                        let mut kf = Vec::with_capacity(r.keyframes.len());
                        for (k, (t, val)) in r.keyframes.iter().enumerate() {
                            let kp = format!("{pp}.ramp.keyframes[{k}]");
                            if !t.is_finite() {
                                push(
                                    kp.clone(),
                                    format!("time is {t}"),
                                    "give a finite time in s",
                                );
                            }
                            if k > 0 && !(*t > r.keyframes[k - 1].0) {
                                push(
                                    kp.clone(),
                                    format!("time {t} s is not after {} s", r.keyframes[k - 1].0),
                                    "list keyframes in strictly increasing time",
                                );
                            }
                            let load = match val {
                                KeyValue::Newtons(x) => {
                                    if !(x.is_finite() && *x >= 0.0) {
                                        push(
                                            kp.clone(),
                                            format!("load is {x} N"),
                                            "give a load >= 0 N (0 releases the finger)",
                                        );
                                    }
                                    Some(*x)
                                }
                                KeyValue::Current(_) => None,
                            };
                            kf.push((*t, load));
                        }
                        Phase::Ramp {
                            keyframes: kf,
                            easing: r.easing,
                        }
                    }
                    PhaseSpec::Csv(c) => {
                        let cp = format!("{pp}.csv");
                        match read_profile_csv(
                            &base_dir.join(&c.path),
                            &c.time_column,
                            &c.load_column,
                        ) {
                            Ok(rows) => {
                                for (k, (t, load)) in rows.iter().enumerate() {
                                    if k > 0 && !(*t > rows[k - 1].0) {
                                        push(
                                            format!("{cp}.path"),
                                            format!(
                                                "row {} of {}: time {t} s is not after {} s",
                                                k + 2,
                                                c.path,
                                                rows[k - 1].0
                                            ),
                                            "sort the rows by strictly increasing time",
                                        );
                                        break;
                                    }
                                    if *load < 0.0 {
                                        push(
                                            format!("{cp}.path"),
                                            format!(
                                                "row {} of {}: load is {load} N",
                                                k + 2,
                                                c.path
                                            ),
                                            "give loads >= 0 N (0 releases the finger)",
                                        );
                                        break;
                                    }
                                }
                                Phase::Ramp {
                                    keyframes: rows
                                        .into_iter()
                                        .map(|(t, l)| (t, Some(l)))
                                        .collect(),
                                    easing: c.easing,
                                }
                            }
                            Err((field, message, fix)) => {
                                push(format!("{cp}.{field}"), message, &fix);
                                Phase::Ramp {
                                    keyframes: Vec::new(),
                                    easing: c.easing,
                                }
                            }
                        }
                    }
                };
                if let (Some((prev, prev_path)), Some(end)) = (&last_end, ph.end()) {
                    if end < *prev {
                        push(
                            pp.clone(),
                            format!("ends at {end} s, before the previous phase ({prev_path}) ends at {prev} s"),
                            "order phases so that their end times increase",
                        );
                    }
                }
                if p + 1 < list.len() && ph.end().is_none() {
                    push(
                        pp.clone(),
                        "lasts forever but is followed by more phases".into(),
                        "give it an end (held.until), or remove the phases after it",
                    );
                }
                if let Some(e) = ph.end() {
                    last_end = Some((e, pp.clone()));
                }
                resolved.push(ph);
            }
            phases[idx] = Some(resolved);
        }
        if !v.is_empty() {
            return Err(ScheduleError::Invalid(v));
        }
        Ok(Schedule { times, phases })
    }

    /// Index of the phase of finger `i` active at time `t` (the first whose end is >= t;
    /// the last phase after every end), or `None` if the finger is unscheduled.
    pub fn phase_index(&self, i: usize, t: f64) -> Option<usize> {
        let list = self.phases[i].as_ref()?;
        let n = list.len();
        Some(
            list.iter()
                .position(|p| p.end().is_none_or(|e| t <= e + 1e-9 * e.abs().max(1.0)))
                .unwrap_or(n - 1),
        )
    }

    /// The command for finger `i` at time `t`, given the resolved value of `"current"` for its
    /// active phase (N) and the scene's own command (for unscheduled fingers).
    pub fn command(&self, i: usize, t: f64, current_n: f64, scene: Command) -> Command {
        let Some(p) = self.phase_index(i, t) else {
            return scene;
        };
        match &self.phases[i].as_ref().expect("scheduled")[p] {
            Phase::Held { .. } => Command::Held,
            Phase::Ramp { keyframes, easing } => {
                let val = |k: usize| keyframes[k].1.unwrap_or(current_n);
                let load = if t <= keyframes[0].0 {
                    val(0)
                } else if t >= keyframes[keyframes.len() - 1].0 {
                    val(keyframes.len() - 1)
                } else {
                    let k = keyframes.iter().position(|kf| kf.0 > t).expect("inside") - 1;
                    let (t0, t1) = (keyframes[k].0, keyframes[k + 1].0);
                    let s = easing.apply((t - t0) / (t1 - t0));
                    val(k) + (val(k + 1) - val(k)) * s
                };
                if load > 0.0 {
                    Command::Load(load)
                } else {
                    Command::Released
                }
            }
        }
    }
}
