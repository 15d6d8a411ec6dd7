//! Why the planner gives no schedule: the question is malformed, the scene or template cannot
//! be run, or a constraint no schedule can keep (named, with the numbers that prove it).
//! Options are named as the Rust API spells them, between backticks
//! ([`crate::plan::option_names`]), for front ends to respell.

use grasp_model::{OptionError, Readable as N};

use crate::error::{ScheduleError, TransferError};
use crate::plan::option_names::{DURATION, MAX_LOAD, MAX_RATE, OBJECTIVE_MARGIN, TEMPLATE};

/// A planning that ends without a checked schedule.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// Options out of range ([`crate::plan::PlanOptions::problems`]), one line each:
    /// `` `option`: `` what is wrong and the fix.
    #[error("{}", option_lines(.0))]
    Options(Vec<OptionError>),
    /// The scene cannot be modelled.
    #[error(transparent)]
    Scene(grasp_model::SceneError),
    /// A schedule the planner wrote or read is refused.
    #[error(transparent)]
    Schedule(ScheduleError),
    /// A run failed (not a solver outcome: those are constraints).
    #[error(transparent)]
    Transfer(TransferError),
    /// The trust-region program could not be solved.
    #[error("the planner's program: {0}")]
    Program(String),
    /// The starting schedule has a step without equilibrium: where, the planned loads there,
    /// the solver's reason and the fix (the start diagnosis).
    #[error(
        "the starting schedule has no equilibrium at t = {} s (planned loads there: {loads}): \
         {reason}; fix: {fix}",
        rounded(*time_s)
    )]
    StartHasNoEquilibrium {
        /// Where, s.
        time_s: f64,
        /// The planned fingers' commands there.
        loads: String,
        /// The solver's reason.
        reason: String,
        /// What to change (options named between backticks).
        fix: String,
    },
    /// A releasing finger starts above the load bound.
    #[error(
        "`{MAX_LOAD}` {} N is below {finger}'s starting load, {} N (a releasing finger's \
         first keyframe is its load in the template or the scene); fix: raise `{MAX_LOAD}` to \
         at least {} N",
        N(*max_load_n), N(*load_n), N(*load_n)
    )]
    MaxLoadBelowStart {
        /// The finger.
        finger: String,
        /// Its starting load, N.
        load_n: f64,
        /// The bound, N.
        max_load_n: f64,
    },
    /// The rate limit is so fast that it cannot bind, so the shortest duration is not its.
    #[error(
        "`{MAX_RATE}` {} N/s lets {finger}'s {} N fall in {} s, within the shortest hand-off \
         the planner writes ({} s: a microsecond a step), so the rate never binds and there is \
         no shortest duration to find; fix: a rate that binds (below {} N/s), or \
         `{OBJECTIVE_MARGIN}` with a `{DURATION}`",
        N(*rate_n_per_s), N(*load_n), rounded(*load_n / *rate_n_per_s), rounded(*shortest_s),
        rounded(*load_n / *shortest_s)
    )]
    RateTooLarge {
        /// The finger with the largest starting load.
        finger: String,
        /// Its starting load, N.
        load_n: f64,
        /// The limit, N/s.
        rate_n_per_s: f64,
        /// The shortest planned duration, s.
        shortest_s: f64,
    },
    /// A duration (given, or bounding) outside what a planned schedule can span.
    #[error(
        "`{option}` {} s is outside the durations a planned schedule spans, {} s (a \
         microsecond for each of its steps) to 1e9 s; fix: give one within them",
        N(*duration_s), rounded(*shortest_s)
    )]
    DurationOutOfRange {
        /// The option (as [`crate::plan_option_names`] spells it).
        option: &'static str,
        /// Its value, s.
        duration_s: f64,
        /// The shortest planned duration, s.
        shortest_s: f64,
    },
    /// A planned finger is not force-controlled.
    #[error(
        "fingers.{finger} is not force-controlled at t = {} s: the planner ramps commanded \
         normal loads; fix: give the finger a `control.normal_load` (or a load ramp in the \
         template)",
        N(*time_s)
    )]
    NotForceControlled {
        /// The finger.
        finger: String,
        /// Where, s.
        time_s: f64,
    },
    /// The template has fewer than two step times.
    #[error("the template needs at least two step times")]
    TemplateTooShort,
    /// Neither a duration nor a rate limit to derive one.
    #[error("no duration: give `{DURATION}` (s) or `{MAX_RATE}` (N/s), or a `{TEMPLATE}`")]
    NoDuration,
    /// A releasing finger cannot reach 0 N at the rate limit within the duration allowed.
    #[error(
        "load rate: {finger} must fall from {} N to 0 N; at `{MAX_RATE}` {} N/s that takes {} \
         s, longer than the {} s allowed; fix: raise `{MAX_RATE}` or the duration",
        N(*load_n), N(*rate_n_per_s), rounded(*needed_s), N(*allowed_s)
    )]
    RateTooSmall {
        /// The finger.
        finger: String,
        /// Its starting load, N.
        load_n: f64,
        /// The limit, N/s.
        rate_n_per_s: f64,
        /// The shortest time to 0 N at the limit, s.
        needed_s: f64,
        /// The longest duration allowed, s.
        allowed_s: f64,
    },
}

/// A number the planner computed (a load, a time, a rate), as its messages show it: four
/// significant digits, written as [`N`] writes a number (`0.00012`, `6.667e4`, `8e300`).
pub fn rounded(x: f64) -> N {
    N(format!("{x:.3e}").parse().unwrap_or(x))
}

/// One line per problem: `` `option`: `` what is wrong and the fix (the value given is in the
/// text where it helps).
fn option_lines(problems: &[OptionError]) -> String {
    let line = |p: &OptionError| format!("`{}`: {}", p.option, p.expected);
    problems.iter().map(line).collect::<Vec<_>>().join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The planner's messages name options between backticks, never a command-line flag.
    #[test]
    fn messages_name_options_not_flags() {
        let errors = [
            PlanError::StartHasNoEquilibrium {
                time_s: 4.0,
                loads: "f1 released".into(),
                reason: "no equilibrium".into(),
                fix: format!("name the fingers that take over (`{TEMPLATE}`)"),
            },
            PlanError::NoDuration,
            PlanError::RateTooSmall {
                finger: "f1".into(),
                load_n: 8.0,
                rate_n_per_s: 0.5,
                needed_s: 16.0,
                allowed_s: 4.0,
            },
        ];
        for e in &errors {
            let text = e.to_string();
            assert!(!text.contains("--"), "{text}");
        }
        assert_eq!(
            errors[2].to_string(),
            format!(
                "load rate: f1 must fall from 8 N to 0 N; at `{MAX_RATE}` 0.5 N/s that takes 16 \
                 s, longer than the 4 s allowed; fix: raise `{MAX_RATE}` or the duration"
            )
        );
    }
}
