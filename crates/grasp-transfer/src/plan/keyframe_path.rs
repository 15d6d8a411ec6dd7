//! A hand-off's schedule as the planner's variables: each planned group's variable (its
//! fingers' commanded normal load, or their approach, [`PlannedGroup`]) at keyframes shared by
//! all of them, linear in between, over a duration split into a fixed number of steps (the
//! thesis's load ramps, section 4.2.2, with their values and their duration set free).
//!
//! Keyframes sit at fixed fractions of the duration, so a step keeps its place along the path
//! when the duration changes: under an elastic or Coulomb model the quasi-static steps, and so
//! the margins, depend on the commands alone, and the duration only on the rates it allows.

use std::collections::BTreeMap;

use crate::plan::planned_group::{PlannedGroup, RateLimits};
use crate::schedule_spec::{
    ApproachPhase, KeyValue, PhaseSpec, RampPhase, ScheduleSpec, SpanSpec, TimeSpec,
};

/// The shortest step of a planned schedule, s: its times are written in whole nanoseconds, so
/// a step (and a keyframe span) of at least a microsecond keeps its times, and so its load
/// rates, to 1e-3 of themselves.
pub const SHORTEST_STEP_S: f64 = 1e-6;

/// The planned groups' variables at shared keyframes, and the duration they span.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyframePath {
    /// The planned groups, in the order of `values`.
    pub groups: Vec<PlannedGroup>,
    /// Keyframe times as fractions of the duration: `0` first, `1` last, increasing.
    pub fractions: Vec<f64>,
    /// `values[g][k]`: group `g`'s variable at keyframe `k` (a load group's load, N, each
    /// member's its share of it; an approach group's scaled approach, [`PlannedGroup`]).
    pub values: Vec<Vec<f64>>,
    /// Duration of the hand-off, s.
    pub duration_s: f64,
    /// Steps after the first: the schedule's times are `duration * s / steps`, `s = 0..=steps`.
    pub steps: usize,
}

impl KeyframePath {
    /// The schedule file's step, s: its duration (rounded to the nanosecond, as the file
    /// writes it) over the steps.
    pub fn step_s(&self) -> f64 {
        round_time(self.duration_s) / self.steps as f64
    }

    /// The shortest duration a schedule of this path's steps and keyframes may have, s:
    /// `SHORTEST_STEP_S` for each step (and each keyframe span, when there are more).
    pub fn shortest_planned_s(&self) -> f64 {
        let spans = self.fractions.len().saturating_sub(1);
        self.steps.max(spans) as f64 * SHORTEST_STEP_S
    }

    /// Schedule time of step `s`, s.
    pub fn time_s(&self, s: usize) -> f64 {
        self.duration_s * s as f64 / self.steps as f64
    }

    /// The two keyframes around step `s` and their interpolation weights (`k`, `1 - w`),
    /// (`k + 1`, `w`): group `g`'s load at the step is `sum w_k values[g][k]`.
    pub fn weights(&self, s: usize) -> [(usize, f64); 2] {
        let tau = s as f64 / self.steps as f64;
        let last = self.fractions.len() - 1;
        let k = self.fractions[..last]
            .iter()
            .rposition(|&f| f <= tau)
            .unwrap_or(0);
        let span = self.fractions[k + 1] - self.fractions[k];
        let w = ((tau - self.fractions[k]) / span).clamp(0.0, 1.0);
        [(k, 1.0 - w), (k + 1, w)]
    }

    /// Group `i`'s variable at step `s`.
    pub fn value(&self, i: usize, s: usize) -> f64 {
        self.weights(s)
            .iter()
            .map(|&(k, w)| w * self.values[i][k])
            .sum()
    }

    /// `dm/dx` over the keyframe values (`x[g * K + k]`) of a quantity `m` at step `s`, from
    /// `dm/dL_g`, its derivatives in each group's variable there (the chain rule through
    /// [`Self::weights`]).
    pub fn gradient(&self, s: usize, per_load: &[f64]) -> Vec<f64> {
        let k_count = self.fractions.len();
        let mut g = vec![0.0; self.groups.len() * k_count];
        for (i, d) in per_load.iter().enumerate() {
            for (k, w) in self.weights(s) {
                g[i * k_count + k] += w * d;
            }
        }
        g
    }

    /// The shortest duration at which these keyframe values keep every planned finger's
    /// command within its rate limit, s: the steepest span's `|dx| / (rate df)`; 0 where no
    /// group has a limit.
    pub fn shortest_duration_s(&self, limits: &RateLimits) -> f64 {
        let f = &self.fractions;
        let mut shortest: f64 = 0.0;
        for (group, values) in self.groups.iter().zip(&self.values) {
            let Some(rate) = group.variable_rate(limits) else {
                continue;
            };
            for k in 0..f.len() - 1 {
                let rise = (values[k + 1] - values[k]).abs();
                shortest = shortest.max(rise / (rate * (f[k + 1] - f[k])));
            }
        }
        shortest
    }

    /// The schedule file of this path: every planned finger a linear ramp of its load (a
    /// finger at 0 N is released) or of its approach through its keyframes, `others` (the template's phases of the fingers
    /// not planned) as they were.
    pub fn to_spec(
        &self,
        description: String,
        others: &BTreeMap<String, Vec<PhaseSpec>>,
    ) -> ScheduleSpec {
        // The duration in whole nanoseconds, so that the last step falls on the end.
        let duration_s = round_time(self.duration_s);
        let mut fingers = others.clone();
        for (group, values) in self.groups.iter().zip(&self.values) {
            for (m, (name, _)) in group.members.iter().enumerate() {
                let at = |k: usize| round_time(self.fractions[k] * duration_s);
                let command = |k: usize| group.member_value(m, values[k]);
                let keys = 0..self.fractions.len();
                let phase = if group.is_approach() {
                    PhaseSpec::Approach(ApproachPhase {
                        keyframes: keys.map(|k| (at(k), command(k))).collect(),
                        easing: Default::default(),
                    })
                } else {
                    PhaseSpec::Ramp(RampPhase {
                        keyframes: keys
                            .map(|k| (at(k), KeyValue::Newtons(command(k))))
                            .collect(),
                        easing: Default::default(),
                    })
                };
                fingers.insert(name.clone(), vec![phase]);
            }
        }
        ScheduleSpec {
            description: Some(description),
            time: TimeSpec::Span(SpanSpec {
                start: 0.0,
                end: duration_s,
                step: self.step_s(),
            }),
            fingers,
            external: None,
            hands: Default::default(),
        }
    }
}

/// `t` (s) rounded to the nanosecond: the schedule's times are whole nanoseconds in the logs.
fn round_time(t: f64) -> f64 {
    (t * 1e9).round() / 1e9
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::planned_group::Commanded;

    fn path() -> KeyframePath {
        KeyframePath {
            groups: vec![PlannedGroup {
                name: "releasing".into(),
                members: vec![("a".into(), 1.0)],
                commanded: Commanded::Load,
            }],
            fractions: vec![0.0, 0.25, 1.0],
            values: vec![vec![8.0, 4.0, 0.0]],
            duration_s: 8.0,
            steps: 8,
        }
    }

    #[test]
    fn loads_are_linear_between_keyframes_and_exact_on_them() {
        let p = path();
        assert_eq!(p.value(0, 0), 8.0);
        assert_eq!(p.value(0, 1), 6.0);
        assert_eq!(p.value(0, 2), 4.0);
        // 5 of the 6 steps from the second keyframe to the last: 4 N * (1 - 5/6).
        assert!((p.value(0, 7) - 4.0 / 6.0).abs() < 1e-12);
        assert_eq!(p.value(0, 8), 0.0);
    }

    #[test]
    fn the_schedule_file_ramps_through_the_keyframes_at_their_times() {
        let spec = path().to_spec("test".into(), &BTreeMap::new());
        let PhaseSpec::Ramp(r) = &spec.fingers["a"][0] else {
            panic!("a ramp")
        };
        let times: Vec<f64> = r.keyframes.iter().map(|k| k.0).collect();
        assert_eq!(times, [0.0, 2.0, 8.0]);
    }

    /// At the shortest duration the steepest ramp of the schedule file runs at the rate limit
    /// exactly, and every other within it (the file's keyframes, not the formula's spans);
    /// two members of unequal shares: the larger share sets the rate.
    #[test]
    fn at_the_shortest_duration_the_steepest_ramp_runs_at_the_rate_limit() {
        let mut p = path();
        p.groups[0].members = vec![("a".into(), 1.0), ("b".into(), 0.5)];
        let rate_n_per_s = 2.0;
        let limits = RateLimits {
            load_n_per_s: Some(rate_n_per_s),
            speed_m_per_s: None,
        };
        p.duration_s = p.shortest_duration_s(&limits);
        let spec = p.to_spec("test".into(), &BTreeMap::new());
        let mut steepest: f64 = 0.0;
        for phases in spec.fingers.values() {
            let PhaseSpec::Ramp(r) = &phases[0] else {
                panic!("a ramp")
            };
            for w in r.keyframes.windows(2) {
                let (KeyValue::Newtons(a), KeyValue::Newtons(b)) = (&w[0].1, &w[1].1) else {
                    panic!("loads in N")
                };
                steepest = steepest.max((b - a).abs() / (w[1].0 - w[0].0));
            }
        }
        // 4 N over a quarter of the duration at 2 N/s: 8 s; the file's times are rounded to
        // the nanosecond, so the rate agrees to 1e-9 of itself.
        assert!((p.duration_s - 8.0).abs() < 1e-12, "{}", p.duration_s);
        assert!((steepest - rate_n_per_s).abs() < 1e-9, "{steepest} N/s");
        assert_eq!(p.shortest_duration_s(&RateLimits::default()), 0.0);
    }
}
