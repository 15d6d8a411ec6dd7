//! The schedule file users script (JSON; `grasp schema --schedule`): step times, each finger's
//! phases, an optional external wrench. Read strictly by serde here; checked and resolved
//! against a scene by [`crate::schedule_builder`] into a [`crate::Schedule`].
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

use std::collections::BTreeMap;

use grasp_model::{
    strict_json, strict_json::describe, strict_json::variant, strict_json::StrictValue,
};
use schemars::JsonSchema;
use serde::{Deserialize, Deserializer, Serialize};
use serde_json::Value;

use crate::easing::Easing;

/// Most steps a schedule may have.
pub const MAX_STEPS: usize = 1_000_000;

/// Largest absolute time in a schedule or profile, s (about 31 years; the logs store times in
/// nanoseconds as 64-bit integers).
pub const MAX_TIME_S: f64 = 1e9;

/// Shortest step between two schedule times, s: the logs store times in whole nanoseconds, and
/// a viscoelastic step shorter than this is the instantaneous response to round-off.
pub const MIN_STEP_S: f64 = 1e-9;

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
    /// Per hand of the scene (`hands`, by name, each name once), its commanded pose through
    /// time: the base's displacement from where the scene puts it (a lift, an arm moving away
    /// after the hand-off). Absent: every hand stays.
    #[serde(
        default,
        skip_serializing_if = "BTreeMap::is_empty",
        deserialize_with = "strict_json::unique_keys"
    )]
    pub hands: BTreeMap<String, PoseRamp>,
}

/// A hand's pose at one keyframe: its base's translation (m, world) and small rotation about
/// its origin (rad, world); either may be omitted (zero).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PoseValue {
    /// Translation, m, each component of magnitude at most 1.
    #[serde(default)]
    pub translation_m: [f64; 3],
    /// Small rotation vector, rad, each component of magnitude at most 1.
    #[serde(default)]
    pub rotation_rad: [f64; 3],
}

/// A hand's pose ramp: constant before the first and after the last keyframe, eased in between.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PoseRamp {
    /// Keyframes `[time s, pose]`, times strictly increasing (`|t| <= 1e9`).
    pub keyframes: Vec<(f64, PoseValue)>,
    /// Interpolation between keyframes (default `linear`).
    #[serde(default)]
    pub easing: Easing,
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
/// much from first touch (0: held at first touch; negative: withdrawn, a jaw opened), its load
/// found by the model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ApproachPhase {
    /// Keyframes `[time s, approach m]`, times strictly increasing (`|t| <= 1e9`), approaches
    /// in `[-1, 1]` m.
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
