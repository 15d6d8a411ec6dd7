//! Building a [`Schedule`] from its file ([`ScheduleSpec`]): every value checked, each problem
//! with its path and fix (at most [`grasp_model::MAX_LISTED_PROBLEMS`] listed), the phases
//! resolved against the scene's finger names, CSV profiles read relative to the schedule.

// Every `!(a > b)` in this file is meant: a NaN must fail the check as well.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::path::Path;

use grasp_io::RunInputs;
use grasp_model::Readable as N;
use grasp_model::{limits::force_in_range, limits::MAX_FORCE_N, limits::MIN_NONZERO_FORCE_N};
use grasp_model::{strict_json, ProblemList};

use crate::easing::Easing;
use crate::error::ScheduleError;
use crate::load_profile::read_profile_csv_noting;
use crate::schedule::{ExternalRamp, Phase, Schedule};
use crate::schedule_spec::{
    ApproachPhase, CsvPhase, ExternalSpec, KeyValue, PhaseSpec, PoseRamp, RampPhase, ScheduleSpec,
    SpanSpec, TimeSpec, WrenchCsv, MAX_STEPS, MAX_TIME_S, MIN_STEP_S,
};

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
            phases[idx] = Some(finger_phases(&path, list, base_dir, start, &mut v));
        }
        let external = spec
            .external
            .as_ref()
            .map(|e| external_ramp(e, base_dir, &mut v));
        let hand_poses = spec
            .hands
            .iter()
            .map(|(name, ramp)| (name.clone(), pose_ramp(name, ramp, &mut v)))
            .collect();
        let input_files = std::mem::take(&mut v.files);
        v.finish()?;
        Ok(Schedule {
            times,
            phases,
            external,
            hand_poses,
            input_files,
        })
    }
}

/// Collects the problems of a schedule (at most [`grasp_model::MAX_LISTED_PROBLEMS`] listed,
/// the rest counted) and notes the CSV files read.
#[derive(Default)]
struct Problems {
    /// The problems found.
    found: ProblemList,
    /// The CSV files read.
    files: RunInputs,
}

impl Problems {
    fn push(&mut self, path: String, message: String, fix: &str) {
        self.found.add(path, message, fix);
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

    fn finish(self) -> Result<(), ScheduleError> {
        self.found.finish().map_err(ScheduleError::Invalid)
    }
}

/// The times of a span, counted without overflow and bounded by [`MAX_STEPS`].
fn span_times(s: &SpanSpec, v: &mut Problems) -> Vec<f64> {
    let start_ok = v.time("time.start".into(), s.start, true);
    let end_ok = v.time("time.end".into(), s.end, true);
    let step_ok = s.step.is_finite() && s.step >= MIN_STEP_S;
    if !step_ok {
        v.push(
            "time.step".into(),
            format!("is {} s", N(s.step)),
            &format!("give a step of at least {MIN_STEP_S:e} s (the logs count whole nanoseconds)"),
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
        } else if i > 0 && *t - times[i - 1] < MIN_STEP_S {
            v.push(
                format!("time.times[{i}]"),
                format!(
                    "is {} s, {} s after the time before it",
                    N(*t),
                    N(*t - times[i - 1])
                ),
                &format!("space the times at least {MIN_STEP_S:e} s apart (the logs count whole nanoseconds)"),
            );
        }
    }
    times.to_vec()
}

/// Resolves the phases of one finger (`path`: where they are in the file; CSV profiles found
/// relative to `base_dir`; a hold first in the list starts at `start_s`, the schedule's first
/// time, s).
fn finger_phases(
    path: &str,
    list: &[PhaseSpec],
    base_dir: &Path,
    start_s: f64,
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
                        &format!("give how long the hold lasts in seconds, in (0, {MAX_TIME_S:e}]"),
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

/// An approach ramp's keyframes: times in range and increasing, approaches in
/// [`grasp_model::limits::APPROACH_RANGE_M`] (negative: the finger withdrawn, a jaw opened).
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
        let range = grasp_model::limits::APPROACH_RANGE_M;
        if !(d.is_finite() && range.contains(d)) {
            v.push(
                kp,
                format!(
                    "approach is {} m, outside [{}, {}] m",
                    N(*d),
                    N(*range.start()),
                    N(*range.end())
                ),
                "give how far the finger is pressed in from first touch, in metres (negative \
                 withdraws it)",
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
            v.files.add(&file, identity);
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

/// The times of six-component keyframes at `path`, checked: at least one (else `empty_fix`),
/// each in range, strictly increasing.
fn keyframe_times(path: &str, keys: &[(f64, [f64; 6])], empty_fix: &str, v: &mut Problems) {
    if keys.is_empty() {
        v.push(path.to_string(), "has no keyframe".into(), empty_fix);
    }
    for (k, (t, _)) in keys.iter().enumerate() {
        let kp = format!("{path}[{k}]");
        v.time(kp.clone(), *t, false);
        if k > 0 && !(*t > keys[k - 1].0) {
            v.push(
                kp,
                format!("time {} s is not after {} s", N(*t), N(keys[k - 1].0)),
                "list keyframes in strictly increasing time",
            );
        }
    }
}

/// Largest commanded hand translation (m) or rotation (rad) component: the model is one of
/// small displacements.
const MAX_HAND_POSE: f64 = 1.0;

/// Hand `name`'s pose keyframes, checked: at least one, times in range and increasing,
/// components finite and at most [`MAX_HAND_POSE`].
fn pose_ramp(name: &str, ramp: &PoseRamp, v: &mut Problems) -> ExternalRamp {
    let path = format!("hands.{name}.keyframes");
    let keys: Vec<(f64, [f64; 6])> = ramp
        .keyframes
        .iter()
        .map(|(t, p)| {
            let (d, r) = (p.translation_m, p.rotation_rad);
            (*t, [d[0], d[1], d[2], r[0], r[1], r[2]])
        })
        .collect();
    keyframe_times(
        &path,
        &keys,
        "give at least one [time, {\"translation_m\": [..]}]",
        v,
    );
    for (k, (_, p)) in keys.iter().enumerate() {
        if !p.iter().all(|c| c.is_finite() && c.abs() <= MAX_HAND_POSE) {
            v.push(
                format!("{path}[{k}]"),
                format!("pose {p:?} has a component that is not finite or above {MAX_HAND_POSE}"),
                "give the translation in m and the rotation in rad, each at most 1 (small motions)",
            );
        }
    }
    (keys, ramp.easing)
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
    keyframe_times(
        &path,
        &keys,
        "give at least one [time, {\"force\": [..]}]",
        v,
    );
    for (k, (_, w)) in keys.iter().enumerate() {
        if !w.iter().all(|c| c.is_finite() && c.abs() <= MAX_FORCE_N) {
            v.push(
                format!("{path}[{k}]"),
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
                v.files.add(&file, identity);
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
