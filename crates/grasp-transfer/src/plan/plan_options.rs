//! What the planner is asked: which fingers let go and which take over, the constraints every
//! step must keep, the objective, and the planner's own limits; each checked, a problem named
//! by its option with the fix.

use grasp_model::limits::MAX_FORCE_N;
use grasp_model::{OptionError, Readable};

use crate::plan::option_names;
use crate::plan::planned_group::RateLimits;
use crate::schedule_spec::MAX_TIME_S;

/// What the plan optimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Objective {
    /// The shortest duration that keeps every constraint (needs a load-rate limit: without
    /// one, a quasi-static hand-off has no shortest duration).
    #[default]
    Duration,
    /// The largest smallest slip margin within the given (or the template's) duration.
    Margin,
}

/// The planner's question (forces N, times s, rates N/s).
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// Fingers that let go: their load ends at 0 N (released at the last step).
    pub releasing: Vec<String>,
    /// Fingers that take over: their load starts at 0 N (not in contact at the first step).
    pub receiving: Vec<String>,
    /// Smallest slip margin `1 - |Q| / (mu P)` at every step, over the fingers carrying at
    /// least 5 % of the load scale (in `[0, 1)`).
    pub min_slip_margin: f64,
    /// Smallest disturbance margin at every step, N: the smallest, over the axis directions of
    /// force and couple, of the wrench the grasp resists on top of the step's loads (as a run
    /// with `TransferOptions::margins` finds it); `None`: not constrained.
    pub min_margin_n: Option<f64>,
    /// Smallest commanded load of a planned finger between its ends, N.
    pub min_load_n: f64,
    /// Largest commanded load of a planned finger, N.
    pub max_load_n: f64,
    /// Largest load rate of a planned force-controlled finger, N/s; `None`: no limit.
    pub max_rate_n_per_s: Option<f64>,
    /// Largest approach speed of a planned position-controlled finger (a jaw's opening or
    /// closing speed), m/s; `None`: no limit.
    pub max_speed_m_per_s: Option<f64>,
    /// Where the releasing position-controlled fingers end, m of approach (negative: opened
    /// short of first touch); `None`: where the template ends them (needed without one).
    pub open_to_m: Option<f64>,
    /// Where the receiving position-controlled fingers close to in the starting path, m of
    /// approach (the plan moves their end within the bounds); `None`: where the template
    /// ends them (needed without one).
    pub close_to_m: Option<f64>,
    /// Smallest approach of a planned position-controlled finger, m; `None`: the smallest
    /// its group's starting path commands (the releasing fingers' end included).
    pub min_approach_m: Option<f64>,
    /// Largest approach of a planned position-controlled finger, m; `None`: the largest its
    /// group's starting path commands (the releasing fingers' start included).
    pub max_approach_m: Option<f64>,
    /// Shortest duration, s.
    pub min_duration_s: f64,
    /// Longest duration, s.
    pub max_duration_s: f64,
    /// The objective.
    pub objective: Objective,
    /// The duration, s: fixed with the margin objective, the first guess with the duration
    /// objective; `None`: the template's, or the shortest the rate allows.
    pub duration_s: Option<f64>,
    /// Steps after the first (2 to 10,000); `None`: the template's, or 60.
    pub steps: Option<usize>,
    /// Keyframes per finger, the ends included (2 to 20).
    pub keyframes: usize,
    /// Largest number of hand-off runs the planner may make (2 to 1000), the final check
    /// included.
    pub max_runs: usize,
    /// Options of every solve of the planner's runs.
    pub solve: grasp_model::SolveOptions,
    /// The planner stops when a step's predicted improvement of its merit is below this
    /// (in `(0, 1)`; the merit is the duration relative to the current one plus 100 times the
    /// largest violation of the margin threshold, or minus the smallest margin).
    pub tolerance: f64,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            releasing: Vec::new(),
            receiving: Vec::new(),
            min_slip_margin: 0.0,
            min_margin_n: None,
            min_load_n: 0.0,
            max_load_n: f64::INFINITY,
            max_rate_n_per_s: None,
            max_speed_m_per_s: None,
            open_to_m: None,
            close_to_m: None,
            min_approach_m: None,
            max_approach_m: None,
            min_duration_s: 0.0,
            max_duration_s: f64::INFINITY,
            objective: Objective::Duration,
            duration_s: None,
            steps: None,
            keyframes: 5,
            max_runs: 30,
            solve: grasp_model::SolveOptions::default(),
            tolerance: 1e-4,
        }
    }
}

impl PlanOptions {
    /// The rate limits of the planned commands.
    pub fn rate_limits(&self) -> RateLimits {
        RateLimits {
            load_n_per_s: self.max_rate_n_per_s,
            speed_m_per_s: self.max_speed_m_per_s,
        }
    }

    /// Every problem of the options against the scene's finger names, each named as the Rust
    /// API spells the option ([`crate::plan_option_names`]): `expected` says what is wrong and the fix,
    /// `value` is the value given.
    pub fn problems(&self, finger_names: &[String]) -> Vec<OptionError> {
        let mut out = self.finger_problems(finger_names);
        out.extend(self.range_problems());
        out.extend(self.approach_problems());
        out.extend(self.search_problems());
        out
    }

    /// The planned fingers: named in the scene, at least one releasing, none in both lists.
    fn finger_problems(&self, finger_names: &[String]) -> Vec<OptionError> {
        let mut out = Vec::new();
        for (option, list) in [
            (option_names::RELEASING, &self.releasing),
            (option_names::RECEIVING, &self.receiving),
        ] {
            for name in list.iter().filter(|n| !finger_names.contains(n)) {
                let known = finger_names.join(", ");
                let expected =
                    format!("no finger named `{name}` in the scene; use one of: {known}");
                out.push(problem(option, name, expected));
            }
            for (i, name) in list.iter().enumerate() {
                if list[..i].contains(name) && !list[i + 1..].contains(name) {
                    let expected = format!("`{name}` is named more than once; name it once");
                    out.push(problem(option, name, expected));
                }
            }
        }
        if self.releasing.is_empty() {
            let expected = "name at least one finger that lets go".into();
            out.push(problem(option_names::RELEASING, "none", expected));
        }
        if let Some(both) = self.releasing.iter().find(|n| self.receiving.contains(n)) {
            let expected = format!("`{both}` is also releasing; a finger is one or the other");
            out.push(problem(option_names::RECEIVING, both, expected));
        }
        out
    }

    /// The loads, rates and durations: each within its range.
    fn range_problems(&self) -> Vec<OptionError> {
        let mut out = Vec::new();
        let mut say = |option, value: f64, expected: String| {
            out.push(problem(option, Readable(value), expected));
        };
        if !(0.0..1.0).contains(&self.min_slip_margin) {
            let expected = format!(
                "{} is outside [0, 1): 1 - |Q|/(mu P) is below 1",
                Readable(self.min_slip_margin)
            );
            say(
                option_names::MIN_SLIP_MARGIN,
                self.min_slip_margin,
                expected,
            );
        }
        if let Some(n) = self.min_margin_n.filter(|n| !(*n > 0.0 && n.is_finite())) {
            let expected =
                "must be a positive number of newtons (a disturbance the grasp resists)".into();
            say(option_names::MIN_MARGIN, n, expected);
        }
        if self.min_load_n > MAX_FORCE_N {
            let expected = format!(
                "must be at most {} N, the largest force a scene or schedule takes",
                Readable(MAX_FORCE_N)
            );
            say(option_names::MIN_LOAD, self.min_load_n, expected);
        } else if !(self.min_load_n >= 0.0 && self.min_load_n < self.max_load_n) {
            let expected = format!(
                "needs 0 <= `{}` (got {} and {})",
                option_names::LOAD_ORDER,
                Readable(self.min_load_n),
                Readable(self.max_load_n)
            );
            say(option_names::MIN_LOAD, self.min_load_n, expected);
        }
        if let Some(r) = self
            .max_rate_n_per_s
            .filter(|r| !(*r > 0.0 && r.is_finite()))
        {
            let expected = "must be a positive number of newtons per second".into();
            say(option_names::MAX_RATE, r, expected);
        }
        if self.min_duration_s > MAX_TIME_S {
            let expected = format!(
                "must be at most {} s, the longest a schedule spans",
                Readable(MAX_TIME_S)
            );
            say(option_names::MIN_DURATION, self.min_duration_s, expected);
        } else if !(self.min_duration_s >= 0.0 && self.min_duration_s <= self.max_duration_s) {
            let expected = format!("needs 0 <= `{}`", option_names::DURATION_ORDER);
            say(option_names::MIN_DURATION, self.min_duration_s, expected);
        }
        out
    }

    /// The approach options: the speed positive, the approaches within the `[-1, 1]` m a
    /// schedule takes, the bounds in order.
    fn approach_problems(&self) -> Vec<OptionError> {
        let mut out = Vec::new();
        if let Some(v) = self
            .max_speed_m_per_s
            .filter(|v| !(*v > 0.0 && v.is_finite()))
        {
            let expected = "must be a positive number of metres per second".into();
            out.push(problem(option_names::MAX_SPEED, Readable(v), expected));
        }
        for (option, value) in [
            (option_names::OPEN_TO, self.open_to_m),
            (option_names::CLOSE_TO, self.close_to_m),
            (option_names::MIN_APPROACH, self.min_approach_m),
            (option_names::MAX_APPROACH, self.max_approach_m),
        ] {
            if let Some(a) = value.filter(|a| !(-1.0..=1.0).contains(a)) {
                let expected = "must be an approach in [-1, 1] m, as a schedule takes".into();
                out.push(problem(option, Readable(a), expected));
            }
        }
        if let (Some(lo), Some(hi)) = (self.min_approach_m, self.max_approach_m) {
            if lo >= hi {
                let expected = format!(
                    "needs `{}` (got {} and {})",
                    option_names::APPROACH_ORDER,
                    Readable(lo),
                    Readable(hi)
                );
                out.push(problem(option_names::MIN_APPROACH, Readable(lo), expected));
            }
        }
        out
    }

    /// The search's settings: the objective given what it needs; the duration, the counts and
    /// the tolerance within their ranges.
    fn search_problems(&self) -> Vec<OptionError> {
        let mut out = Vec::new();
        let no_limit = self.max_rate_n_per_s.is_none() && self.max_speed_m_per_s.is_none();
        if self.objective == Objective::Duration && no_limit {
            let expected = format!(
                "the shortest duration needs a rate limit (a quasi-static hand-off is as \
                 fast as its rates allow): give `{}` (loads) or `{}` (approaches), or `{}`",
                option_names::MAX_RATE,
                option_names::MAX_SPEED,
                option_names::OBJECTIVE_MARGIN
            );
            out.push(problem(option_names::OBJECTIVE, "duration", expected));
        }
        if let Some(d) = self.duration_s.filter(|d| !(*d > 0.0 && *d <= 1e9)) {
            let expected = "must be a positive number of seconds (at most 1e9)".into();
            out.push(problem(option_names::DURATION, Readable(d), expected));
        }
        if let Some(s) = self.steps.filter(|s| !(2..=10_000).contains(s)) {
            out.push(problem(
                option_names::STEPS,
                s,
                "must be 2 to 10,000".into(),
            ));
        }
        if !(2..=20).contains(&self.keyframes) {
            let expected = format!("{} is outside 2 to 20", self.keyframes);
            out.push(problem(option_names::KEYFRAMES, self.keyframes, expected));
        }
        if !(2..=1000).contains(&self.max_runs) {
            let expected = format!("{} is outside 2 to 1000", self.max_runs);
            out.push(problem(option_names::MAX_RUNS, self.max_runs, expected));
        }
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            let expected = "must be in (0, 1)".into();
            out.push(problem(
                option_names::TOLERANCE,
                Readable(self.tolerance),
                expected,
            ));
        }
        out
    }
}

/// The problem of `option`, given `value`.
fn problem(option: &'static str, value: impl std::fmt::Display, expected: String) -> OptionError {
    OptionError {
        option,
        value: value.to_string(),
        expected,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every option out of range at once: each problem named as the API spells the option,
    /// in the order the checks run, and no message names a command-line flag.
    #[test]
    fn problems_name_options_as_the_api_spells_them() {
        let options = PlanOptions {
            releasing: vec!["f9".into(), "a".into()],
            receiving: vec!["a".into()],
            min_slip_margin: 1.5,
            min_margin_n: Some(0.0),
            min_load_n: 5.0,
            max_load_n: 3.0,
            max_rate_n_per_s: Some(-1.0),
            max_speed_m_per_s: Some(0.0),
            open_to_m: Some(2.0),
            min_approach_m: Some(0.001),
            max_approach_m: Some(-0.001),
            min_duration_s: 5.0,
            max_duration_s: 3.0,
            duration_s: Some(0.0),
            steps: Some(1),
            keyframes: 1,
            max_runs: 1,
            tolerance: 2.0,
            ..PlanOptions::default()
        };
        let problems = options.problems(&["a".into(), "b".into()]);
        let named: Vec<&str> = problems.iter().map(|p| p.option).collect();
        use option_names::*;
        assert_eq!(
            named,
            [
                RELEASING,
                RECEIVING,
                MIN_SLIP_MARGIN,
                MIN_MARGIN,
                MIN_LOAD,
                MAX_RATE,
                MIN_DURATION,
                MAX_SPEED,
                OPEN_TO,
                MIN_APPROACH,
                DURATION,
                STEPS,
                KEYFRAMES,
                MAX_RUNS,
                TOLERANCE
            ]
        );
        assert_eq!(problems[0].value, "f9");
        assert_eq!(
            problems[4].expected,
            format!("needs 0 <= `{LOAD_ORDER}` (got 5 and 3)")
        );
        for p in &problems {
            assert!(!p.expected.contains("--"), "{}", p.expected);
        }
        let no_rate = PlanOptions {
            releasing: vec!["a".into()],
            ..PlanOptions::default()
        };
        let problems = no_rate.problems(&["a".into()]);
        assert_eq!(problems.len(), 1);
        assert_eq!(problems[0].option, OBJECTIVE);
        assert!(problems[0].expected.ends_with(&format!(
            "give `{MAX_RATE}` (loads) or `{MAX_SPEED}` (approaches), or \
                 `{OBJECTIVE_MARGIN}`"
        )));
    }

    /// A huge value is quoted as written (`1e308`), never as the 309 digits Rust's `{}` gives,
    /// in the value and in the expectation alike.
    #[test]
    fn huge_values_are_quoted_without_hundreds_of_digits() {
        let options = PlanOptions {
            releasing: vec!["a".into()],
            min_slip_margin: 1e308,
            min_load_n: 1e300,
            max_load_n: -1e300,
            max_rate_n_per_s: Some(1.0),
            ..PlanOptions::default()
        };
        let problems = options.problems(&["a".into()]);
        // The slip margin out of range, the loads each beyond the largest force and their
        // order: every value quoted in exponent form.
        assert!(problems.len() >= 2, "{problems:?}");
        assert_eq!(problems[0].value, "1e308");
        assert!(
            problems[0].expected.starts_with("1e308 is outside"),
            "{}",
            problems[0].expected
        );
        assert!(
            problems
                .iter()
                .any(|p| p.value == "1e300" || p.expected.contains("1e300")),
            "{problems:?}"
        );
        for p in &problems {
            assert!(p.value.len() + p.expected.len() < 200, "{p:?}");
        }
    }
}
