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
//! Phases also ramp a position-controlled finger's approach (`{"approach": {"keyframes": [[t,
//! m], ...]}}`) or hold the phase before's last command (`{"hold": {"duration_s": D}}`, from its
//! end). Each finger runs through its phases in order; a phase lasts until its end time
//! (`held.until`, the last keyframe, the last CSV row, a hold's end); after the last phase its
//! final state persists. A
//! finger whose scheduled load is zero is released: it leaves the problem at that step.
//! Fingers the schedule does not name keep the scene's control. Times in seconds, loads in
//! newtons. The keyframe value `"current"` is the normal force the finger carried at the step
//! before the phase began (so a ramp starts from whatever the grasp settled to).

// Every `!(a > b)` in this file is meant: a NaN must fail the check as well.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::collections::BTreeMap;
use std::path::Path;

use grasp_model::Readable as N;
use grasp_model::{limits::force_in_range, limits::MAX_FORCE_N, limits::MIN_NONZERO_FORCE_N};
use grasp_model::{
    strict_json, strict_json::describe, strict_json::variant, strict_json::StrictValue,
};
use schemars::JsonSchema;
use serde::{Deserialize, Deserializer, Serialize};
use serde_json::Value;

use crate::easing::Easing;
use crate::error::ScheduleError;
use crate::load_profile::read_profile_csv_noting;
use grasp_io::RunInputs;
use grasp_model::InputProblem;

/// Most steps a schedule may have.
pub const MAX_STEPS: usize = 1_000_000;

/// Largest absolute time in a schedule or profile, s (about 31 years; the logs store times in
/// nanoseconds as 64-bit integers).
pub const MAX_TIME_S: f64 = 1e9;

/// A schedule file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScheduleSpec {
    /// Free text.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The step times.
    pub time: TimeSpec,
    /// Per finger (by name, each name once), its phases in order.
    #[serde(deserialize_with = "strict_json::unique_keys")]
    pub fingers: BTreeMap<String, Vec<PhaseSpec>>,
    /// A task-induced load ramped on the object (thesis 5.3: a pull by the receiving gripper,
    /// a bump against a fixture): a force at the centre of mass and a couple, added to the
    /// scene's weight and external forces. Absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub external: Option<ExternalSpec>,
}

/// A wrench on the object through time: keyframes, or a CSV file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum ExternalSpec {
    /// Keyframes `[time s, {"force": [N], "torque": [N m]}]` with an easing.
    Ramp(WrenchRamp),
    /// Rows of a CSV file.
    Csv(WrenchCsv),
}

/// An external wrench at one keyframe: force (N, world, at the centre of mass) and couple
/// (N m, world); either may be omitted (zero).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WrenchValue {
    /// Force, N, each component of magnitude at most 1e7.
    #[serde(default)]
    pub force: [f64; 3],
    /// Couple, N m, each component of magnitude at most 1e7.
    #[serde(default)]
    pub torque: [f64; 3],
}

/// A wrench ramp: constant before the first and after the last keyframe, eased in between.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WrenchRamp {
    /// Keyframes `[time s, wrench]`, times strictly increasing (`|t| <= 1e9`).
    pub keyframes: Vec<(f64, WrenchValue)>,
    /// Interpolation between keyframes (default `linear`).
    #[serde(default)]
    pub easing: Easing,
}

/// A wrench profile from a CSV file (same rules as a load profile), interpolated linearly:
/// the named columns give the force (N) and couple (N m) components; unnamed ones are zero.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WrenchCsv {
    /// File path, relative to the schedule file.
    pub path: String,
    /// Name of the time column (s).
    pub time_column: String,
    /// Columns of the force components `[x, y, z]` (N); `null` for a zero component.
    #[serde(default)]
    pub force_columns: [Option<String>; 3],
    /// Columns of the couple components `[x, y, z]` (N m); `null` for a zero component.
    #[serde(default)]
    pub torque_columns: [Option<String>; 3],
}

/// Step times: a span with a step, or explicit times (s, in `[0, 1e9]`, strictly increasing),
/// at most 1e6 steps.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
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
    /// First time, s, in `[0, 1e9]` (it becomes the MCAP log time).
    pub start: f64,
    /// Last time, s, in `[start, 1e9]`.
    pub end: f64,
    /// Step, s (> 0; at most 1e6 steps from start to end).
    pub step: f64,
}

/// Explicit step times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExplicitTimes {
    /// Times, s, strictly increasing, in `[0, 1e9]`; at most 1e6 of them.
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
    /// Approach (position control) following keyframes.
    Approach(ApproachPhase),
    /// The command of the phase before (or the scene's control) kept for a duration: a hold,
    /// during which a viscoelastic pad relaxes.
    Hold(HoldPhase),
}

/// An approach ramp through keyframes `[time s, approach m]`: the finger pressed in by that
/// much from first touch (0: held at first touch), its load found by the model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ApproachPhase {
    /// Keyframes `[time s, approach m]`, times strictly increasing (`|t| <= 1e9`), approaches
    /// in `[0, 1]` m.
    pub keyframes: Vec<(f64, f64)>,
    /// Interpolation between keyframes (default `linear`).
    #[serde(default)]
    pub easing: Easing,
}

/// A hold.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HoldPhase {
    /// How long, s (> 0), from the end of the phase before (or the schedule's start).
    pub duration_s: f64,
}

/// A held phase.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HeldPhase {
    /// End of the phase, s (inclusive, `|t| <= 1e9`); absent: to the end of the schedule.
    #[serde(default)]
    pub until: Option<f64>,
}

/// A keyframe value: newtons (0 or in `[1e-15, 1e7]`), or `"current"`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
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
    /// Keyframes `[time s, load]`, times strictly increasing (`|t| <= 1e9`), loads 0 or in
    /// `[1e-15, 1e7]` N, or `"current"`.
    pub keyframes: Vec<(f64, KeyValue)>,
    /// Interpolation between keyframes (default `linear`).
    #[serde(default)]
    pub easing: Easing,
}

/// A load profile from a CSV file (header row; comma-separated numbers; a regular file of at
/// most 64 MiB; times `|t| <= 1e9` s strictly increasing, loads 0 or in `[1e-15, 1e7]` N).
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

impl<'de> Deserialize<'de> for TimeSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let StrictValue(v) = StrictValue::deserialize(d)?;
        let has = |k: &str| v.get(k).is_some();
        if has("times") {
            variant(v).map(TimeSpec::Explicit)
        } else if has("start") || has("end") || has("step") {
            variant(v).map(TimeSpec::Span)
        } else {
            Err(serde::de::Error::custom(format!(
                "expected {{\"start\", \"end\", \"step\"}} or {{\"times\": [...]}}; found {}",
                describe(&v)
            )))
        }
    }
}

impl<'de> Deserialize<'de> for KeyValue {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let StrictValue(v) = StrictValue::deserialize(d)?;
        match v {
            Value::Number(_) => variant(v).map(KeyValue::Newtons),
            Value::String(ref s) if s == "current" => variant(v).map(KeyValue::Current),
            v => Err(serde::de::Error::custom(format!(
                "expected a load in newtons or \"current\"; found {}",
                describe(&v)
            ))),
        }
    }
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
    /// Pressed in by a prescribed approach from first touch, m (> 0); its load is found by
    /// the model.
    Approach(f64),
}

impl Command {
    /// How the commanded finger is driven in the step's grasp (`None`: released, out of it).
    pub fn control(&self) -> Option<grasp_model::Control> {
        use grasp_model::Control;
        match *self {
            Command::Held => Some(Control::Held),
            Command::Load(p) => Some(Control::NormalLoad { newtons: p }),
            Command::Approach(d) => Some(Control::Approach { metres: d }),
            Command::Released => None,
        }
    }
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
    /// Approach keyframes.
    Approach {
        /// `(time s, approach m)`.
        keyframes: Vec<(f64, f64)>,
        /// Interpolation.
        easing: Easing,
    },
    /// The phase before's last command (or the scene's control), until the time.
    Hold {
        /// End, s.
        until: f64,
    },
}

impl Phase {
    fn end(&self) -> Option<f64> {
        match self {
            Phase::Held { until } => *until,
            Phase::Ramp { keyframes, .. } => keyframes.last().map(|k| k.0),
            Phase::Approach { keyframes, .. } => keyframes.last().map(|k| k.0),
            Phase::Hold { until } => Some(*until),
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
    /// The ramped external wrench, if any.
    pub external: Option<ExternalRamp>,
    /// The CSV files read (no output of a run may replace one of them).
    pub input_files: RunInputs,
}

/// The scheduled external wrench at one time (world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExternalWrench {
    /// Force at the centre of mass, N.
    pub force_n: [f64; 3],
    /// Couple, N m.
    pub torque_nm: [f64; 3],
}

/// A validated external wrench ramp: keyframes `(time s, [force N; couple N m])` and easing.
pub type ExternalRamp = (Vec<(f64, [f64; 6])>, Easing);

impl Schedule {
    /// Parses, validates and resolves a schedule against the scene's finger names (one JSON
    /// document, no key twice). CSV paths are resolved relative to `base_dir`.
    pub fn from_json_str(
        text: &str,
        finger_names: &[String],
        base_dir: &Path,
    ) -> Result<Schedule, ScheduleError> {
        let spec: ScheduleSpec =
            strict_json::from_str_strict(text).map_err(|e| ScheduleError::Parse {
                path: e.path,
                message: e.message,
            })?;
        Schedule::from_spec(&spec, finger_names, base_dir)
    }

    /// Validates and resolves a parsed schedule.
    pub fn from_spec(
        spec: &ScheduleSpec,
        finger_names: &[String],
        base_dir: &Path,
    ) -> Result<Schedule, ScheduleError> {
        let mut v = Problems::default();
        let times = match &spec.time {
            TimeSpec::Span(s) => span_times(s, &mut v),
            TimeSpec::Explicit(e) => explicit_times(&e.times, &mut v),
        };
        let mut phases: Vec<Option<Vec<Phase>>> = vec![None; finger_names.len()];
        for (name, list) in &spec.fingers {
            let path = format!("fingers.{name}");
            let Some(idx) = finger_names.iter().position(|n| n == name) else {
                v.push(
                    path,
                    format!("no finger named `{name}` in the scene"),
                    &format!("use one of: {}", finger_names.join(", ")),
                );
                continue;
            };
            let start = times.first().copied().unwrap_or(0.0);
            phases[idx] = Some(finger_phases(&path, list, (base_dir, start), &mut v));
        }
        let external = spec
            .external
            .as_ref()
            .map(|e| external_ramp(e, base_dir, &mut v));
        let input_files = std::mem::take(&mut v.2);
        v.finish()?;
        Ok(Schedule {
            times,
            phases,
            external,
            input_files,
        })
    }

    /// The scheduled external wrench at time `t`; `None` when the schedule has none.
    pub fn external_at(&self, t: f64) -> Option<ExternalWrench> {
        let (keys, easing) = self.external.as_ref()?;
        let mut w = [0.0; 6];
        for (c, wc) in w.iter_mut().enumerate() {
            let comp: Vec<(f64, Option<f64>)> = keys.iter().map(|k| (k.0, Some(k.1[c]))).collect();
            *wc = ramp_load(&comp, *easing, t, 0.0);
        }
        Some(ExternalWrench {
            force_n: [w[0], w[1], w[2]],
            torque_nm: [w[3], w[4], w[5]],
        })
    }

    /// The largest force or couple component of the scheduled external wrench (N or N m; 0
    /// without one).
    pub fn external_scale(&self) -> f64 {
        self.external.as_ref().map_or(0.0, |(keys, _)| {
            keys.iter()
                .flat_map(|k| k.1.iter())
                .fold(0.0_f64, |a, v| a.max(v.abs()))
        })
    }

    /// Index of the phase of finger `i` active at time `t` (the first whose end is >= t;
    /// the last phase after every end), or `None` if the finger is unscheduled.
    pub fn phase_index(&self, i: usize, t: f64) -> Option<usize> {
        let list = self.phases.get(i)?.as_ref()?;
        let last = list.len().checked_sub(1)?;
        Some(
            list.iter()
                .position(|p| p.end().is_none_or(|e| t <= e + 1e-9 * e.abs().max(1.0)))
                .unwrap_or(last),
        )
    }

    /// The command for finger `i` at time `t`, given the resolved value of `"current"` for its
    /// active phase (N) and the scene's own command (for unscheduled fingers).
    pub fn command(&self, i: usize, t: f64, current_n: f64, scene: Command) -> Command {
        match self.phase_index(i, t) {
            None => scene,
            Some(p) => self.phase_command(i, p, t, current_n, scene),
        }
    }

    /// The command of phase `p` of finger `i` at time `t` (a hold: the phase before's at its
    /// end, or the scene's).
    fn phase_command(&self, i: usize, p: usize, t: f64, current_n: f64, scene: Command) -> Command {
        let Some(list) = self.phases.get(i).and_then(Option::as_ref) else {
            return scene;
        };
        match &list[p] {
            Phase::Held { .. } => Command::Held,
            Phase::Ramp { keyframes, easing } => {
                let load = ramp_load(keyframes, *easing, t, current_n);
                if load > 0.0 {
                    Command::Load(load)
                } else {
                    Command::Released
                }
            }
            Phase::Approach { keyframes, easing } => {
                let k: Vec<(f64, Option<f64>)> =
                    keyframes.iter().map(|k| (k.0, Some(k.1))).collect();
                let d = ramp_load(&k, *easing, t, 0.0);
                if d > 0.0 {
                    Command::Approach(d)
                } else {
                    Command::Held
                }
            }
            Phase::Hold { .. } => match p.checked_sub(1) {
                None => scene,
                Some(q) => {
                    let end = list[q].end().unwrap_or(t);
                    self.phase_command(i, q, end, current_n, scene)
                }
            },
        }
    }
}

/// The load of a ramp at time `t`: constant before the first and after the last keyframe,
/// eased in between; `"current"` keyframes (and an empty ramp) take `current_n`.
fn ramp_load(keyframes: &[(f64, Option<f64>)], easing: Easing, t: f64, current_n: f64) -> f64 {
    let val = |k: &(f64, Option<f64>)| k.1.unwrap_or(current_n);
    let (Some(first), Some(last)) = (keyframes.first(), keyframes.last()) else {
        return current_n;
    };
    if t <= first.0 {
        return val(first);
    }
    if t >= last.0 {
        return val(last);
    }
    // first.0 < t < last.0: keyframes[k].0 <= t < keyframes[k + 1].0 with 0 <= k < len - 1.
    let k = keyframes.partition_point(|kf| kf.0 <= t).saturating_sub(1);
    let k = k.min(keyframes.len() - 2);
    let (a, b) = (&keyframes[k], &keyframes[k + 1]);
    let s = easing.apply((t - a.0) / (b.0 - a.0));
    val(a) + (val(b) - val(a)) * s
}

/// Collects schedule problems; at most [`MAX_LISTED_PROBLEMS`] are listed. Also notes the
/// CSV files read.
#[derive(Default)]
struct Problems(Vec<InputProblem>, usize, RunInputs);

/// Most problems listed in one error (the rest are counted).
const MAX_LISTED_PROBLEMS: usize = 50;

impl Problems {
    fn push(&mut self, path: String, message: String, fix: &str) {
        if self.0.len() < MAX_LISTED_PROBLEMS {
            self.0.push(InputProblem {
                path,
                message,
                fix: fix.to_string(),
            });
        } else {
            self.1 += 1;
        }
    }

    /// A finite time with `|t| <= MAX_TIME_S` (and `>= 0` if `nonnegative`).
    fn time(&mut self, path: String, t: f64, nonnegative: bool) -> bool {
        let lo = if nonnegative { 0.0 } else { -MAX_TIME_S };
        if t.is_finite() && (lo..=MAX_TIME_S).contains(&t) {
            return true;
        }
        self.push(
            path,
            format!("time is {} s, outside [{lo:e}, {MAX_TIME_S:e}] s", N(t)),
            "give a finite time in seconds within that range",
        );
        false
    }

    /// A load: 0 or in `[MIN_NONZERO_FORCE_N, MAX_FORCE_N]` (the scene's force range).
    fn load(&mut self, path: String, x: f64) -> bool {
        if force_in_range(x) {
            return true;
        }
        self.push(
            path,
            format!(
                "load is {} N, neither 0 nor in [{MIN_NONZERO_FORCE_N:e}, {MAX_FORCE_N:e}] N",
                N(x)
            ),
            "give 0 N (releases the finger) or a load between 1e-15 and 1e7 N",
        );
        false
    }

    fn finish(mut self) -> Result<(), ScheduleError> {
        if self.1 > 0 {
            let more = self.1;
            self.0.push(InputProblem {
                path: "(more)".into(),
                message: format!("{more} more problem(s) not listed"),
                fix: "correct the ones above and run again".into(),
            });
        }
        if self.0.is_empty() {
            Ok(())
        } else {
            Err(ScheduleError::Invalid(self.0))
        }
    }
}

/// The times of a span, counted without overflow and bounded by [`MAX_STEPS`].
fn span_times(s: &SpanSpec, v: &mut Problems) -> Vec<f64> {
    let start_ok = v.time("time.start".into(), s.start, true);
    let end_ok = v.time("time.end".into(), s.end, true);
    let step_ok = s.step.is_finite() && s.step > 0.0;
    if !step_ok {
        v.push(
            "time.step".into(),
            format!("is {}", N(s.step)),
            "give a step > 0 s",
        );
    }
    if !(s.end >= s.start) {
        v.push(
            "time.end".into(),
            format!("is {} s, before the start {} s", N(s.end), N(s.start)),
            "give an end time >= start (times must increase)",
        );
    }
    if !(start_ok && end_ok && step_ok && s.end >= s.start) {
        return Vec::new();
    }
    // Both in [0, 1e9] and step > 0: the quotient is finite or +inf, never NaN.
    let intervals = ((s.end - s.start) / s.step + 1e-9).floor();
    if !(intervals < MAX_STEPS as f64) {
        v.push(
            "time.step".into(),
            format!(
                "gives {:.3e} steps from {} s to {} s, more than {MAX_STEPS}",
                intervals + 1.0,
                N(s.start),
                N(s.end)
            ),
            "use a larger step or a shorter span",
        );
        return Vec::new();
    }
    let n = intervals as usize + 1;
    (0..n).map(|i| s.start + i as f64 * s.step).collect()
}

/// Explicit times: bounded in number, each in range, strictly increasing.
fn explicit_times(times: &[f64], v: &mut Problems) -> Vec<f64> {
    if times.is_empty() {
        v.push(
            "time.times".into(),
            "is empty".into(),
            "list at least one time",
        );
    }
    if times.len() > MAX_STEPS {
        v.push(
            "time.times".into(),
            format!("lists {} times, more than {MAX_STEPS}", times.len()),
            "list fewer steps (or split the hand-off into several runs)",
        );
        return Vec::new();
    }
    for (i, t) in times.iter().enumerate() {
        v.time(format!("time.times[{i}]"), *t, true);
        if i > 0 && !(*t > times[i - 1]) {
            v.push(
                format!("time.times[{i}]"),
                format!("is {} s, not after {} s", N(*t), N(times[i - 1])),
                "list times in strictly increasing order",
            );
        }
    }
    times.to_vec()
}

/// Resolves the phases of one finger.
fn finger_phases(
    path: &str,
    list: &[PhaseSpec],
    (base_dir, start_s): (&Path, f64),
    v: &mut Problems,
) -> Vec<Phase> {
    if list.is_empty() {
        v.push(
            path.to_string(),
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
                    v.time(format!("{pp}.held.until"), u, false);
                }
                Phase::Held { until: h.until }
            }
            PhaseSpec::Ramp(r) => ramp_phase(&pp, r, v),
            PhaseSpec::Csv(c) => csv_phase(&format!("{pp}.csv"), c, base_dir, v),
            PhaseSpec::Approach(a) => approach_phase(&pp, a, v),
            PhaseSpec::Hold(h) => {
                let from = last_end.as_ref().map_or(start_s, |e| e.0);
                if !(h.duration_s.is_finite() && h.duration_s > 0.0 && h.duration_s <= MAX_TIME_S) {
                    v.push(
                        format!("{pp}.hold.duration_s"),
                        format!("is {} s", N(h.duration_s)),
                        "give how long the hold lasts in seconds, > 0",
                    );
                }
                Phase::Hold {
                    until: from + h.duration_s,
                }
            }
        };
        if let (Some((prev, prev_path)), Some(end)) = (&last_end, ph.end()) {
            if end < *prev {
                v.push(
                    pp.clone(),
                    format!(
                        "ends at {} s, before the previous phase ({prev_path}) ends at {} s",
                        N(end),
                        N(*prev)
                    ),
                    "order phases so that their end times increase",
                );
            }
        }
        if p + 1 < list.len() && ph.end().is_none() {
            v.push(
                pp.clone(),
                "lasts forever but is followed by more phases".into(),
                "give it an end (held.until), or remove the phases after it",
            );
        }
        if let Some(e) = ph.end() {
            last_end = Some((e, pp));
        }
        resolved.push(ph);
    }
    resolved
}

/// An approach ramp's keyframes: times in range and increasing, approaches in `[0, 1]` m.
fn approach_phase(pp: &str, a: &ApproachPhase, v: &mut Problems) -> Phase {
    if a.keyframes.is_empty() {
        v.push(
            format!("{pp}.approach.keyframes"),
            "is empty".into(),
            "give at least one [time, approach]",
        );
    }
    for (k, (t, d)) in a.keyframes.iter().enumerate() {
        let kp = format!("{pp}.approach.keyframes[{k}]");
        v.time(kp.clone(), *t, false);
        if k > 0 && !(*t > a.keyframes[k - 1].0) {
            v.push(
                kp.clone(),
                format!(
                    "time {} s is not after {} s",
                    N(*t),
                    N(a.keyframes[k - 1].0)
                ),
                "list keyframes in strictly increasing time",
            );
        }
        if !(d.is_finite() && (0.0..=1.0).contains(d)) {
            v.push(
                kp,
                format!("approach is {} m, outside [0, 1] m", N(*d)),
                "give how far the finger is pressed in from first touch, in metres",
            );
        }
    }
    Phase::Approach {
        keyframes: a.keyframes.clone(),
        easing: a.easing,
    }
}

/// A ramp's keyframes: times in range and increasing, loads in range.
fn ramp_phase(pp: &str, r: &RampPhase, v: &mut Problems) -> Phase {
    if r.keyframes.is_empty() {
        v.push(
            format!("{pp}.ramp.keyframes"),
            "is empty".into(),
            "give at least one [time, load]",
        );
    }
    let mut kf = Vec::with_capacity(r.keyframes.len());
    for (k, (t, val)) in r.keyframes.iter().enumerate() {
        let kp = format!("{pp}.ramp.keyframes[{k}]");
        v.time(kp.clone(), *t, false);
        if k > 0 && !(*t > r.keyframes[k - 1].0) {
            v.push(
                kp.clone(),
                format!(
                    "time {} s is not after {} s",
                    N(*t),
                    N(r.keyframes[k - 1].0)
                ),
                "list keyframes in strictly increasing time",
            );
        }
        let load = match val {
            KeyValue::Newtons(x) => {
                v.load(kp, *x);
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

/// A CSV profile: read (a regular file, bounded size), rows in range and increasing in time.
fn csv_phase(cp: &str, c: &CsvPhase, base_dir: &Path, v: &mut Problems) -> Phase {
    let file = base_dir.join(&c.path);
    let rows = match read_profile_csv_noting(&file, &c.time_column, &c.load_column) {
        Ok((rows, identity)) => {
            v.2.add(&file, identity);
            rows
        }
        Err((field, message, fix)) => {
            v.push(format!("{cp}.{field}"), message, &fix);
            Vec::new()
        }
    };
    for (k, (t, load)) in rows.iter().enumerate() {
        let row = format!("{cp}.path (row {} of {})", k + 2, c.path);
        let ok = v.time(row.clone(), *t, false) && v.load(row.clone(), *load);
        if !ok {
            break;
        }
        if k > 0 && !(*t > rows[k - 1].0) {
            v.push(
                row,
                format!("time {} s is not after {} s", N(*t), N(rows[k - 1].0)),
                "sort the rows by strictly increasing time",
            );
            break;
        }
    }
    Phase::Ramp {
        keyframes: rows.into_iter().map(|(t, l)| (t, Some(l))).collect(),
        easing: c.easing,
    }
}

/// The external wrench's keyframes, checked: times in range and increasing, components finite
/// and at most 1e7; CSV rows become linear keyframes.
fn external_ramp(
    e: &ExternalSpec,
    base_dir: &Path,
    v: &mut Problems,
) -> (Vec<(f64, [f64; 6])>, Easing) {
    let (keys, easing, path): (Vec<(f64, [f64; 6])>, Easing, String) = match e {
        ExternalSpec::Ramp(r) => (
            r.keyframes
                .iter()
                .map(|(t, w)| {
                    let f = w.force;
                    let m = w.torque;
                    (*t, [f[0], f[1], f[2], m[0], m[1], m[2]])
                })
                .collect(),
            r.easing,
            "external.ramp.keyframes".into(),
        ),
        ExternalSpec::Csv(c) => match wrench_rows(c, base_dir, v) {
            Some(rows) => (rows, Easing::Linear, "external.csv.path".into()),
            // The file's problem is reported; no keyframe is no second problem.
            None => return (Vec::new(), Easing::Linear),
        },
    };
    if keys.is_empty() {
        v.push(
            path.clone(),
            "has no keyframe".into(),
            "give at least one [time, {\"force\": [..]}]",
        );
    }
    for (k, (t, w)) in keys.iter().enumerate() {
        let kp = format!("{path}[{k}]");
        v.time(kp.clone(), *t, false);
        if k > 0 && !(*t > keys[k - 1].0) {
            v.push(
                kp.clone(),
                format!("time {} s is not after {} s", N(*t), N(keys[k - 1].0)),
                "list keyframes in strictly increasing time",
            );
        }
        if !w.iter().all(|c| c.is_finite() && c.abs() <= MAX_FORCE_N) {
            v.push(
                kp,
                format!("wrench {w:?} has a component that is not finite or above {MAX_FORCE_N:e}"),
                "give force components in N and couple components in N m, each at most 1e7",
            );
        }
    }
    (keys, easing)
}

/// The rows of a wrench CSV: each named column read like a load profile's, rows matched by
/// position (the same file); `None` when a problem was reported.
fn wrench_rows(c: &WrenchCsv, base_dir: &Path, v: &mut Problems) -> Option<Vec<(f64, [f64; 6])>> {
    let names: Vec<(usize, &String)> = c
        .force_columns
        .iter()
        .chain(&c.torque_columns)
        .enumerate()
        .filter_map(|(i, n)| n.as_ref().map(|n| (i, n)))
        .collect();
    if names.is_empty() {
        v.push(
            "external.csv".into(),
            "names no force or torque column".into(),
            "give force_columns and/or torque_columns, e.g. [null, null, \"fz_n\"]",
        );
        return None;
    }
    let mut rows: Vec<(f64, [f64; 6])> = Vec::new();
    for (i, name) in names {
        let file = base_dir.join(&c.path);
        match read_profile_csv_noting(&file, &c.time_column, name) {
            Ok((col, identity)) => {
                v.2.add(&file, identity);
                if rows.is_empty() {
                    rows = col.iter().map(|(t, _)| (*t, [0.0; 6])).collect();
                }
                for (r, (_, x)) in rows.iter_mut().zip(col) {
                    r.1[i] = x;
                }
            }
            Err((field, message, fix)) => {
                let field = if field == "load_column" {
                    "columns"
                } else {
                    field
                };
                v.push(format!("external.csv.{field}"), message, &fix);
                return None;
            }
        }
    }
    Some(rows)
}
