//! Why the planner gives no schedule: the question is malformed, the scene or template cannot
//! be run, or a constraint no schedule can keep (named, with the numbers that prove it).
//! Options are named as the Rust API spells them, between backticks
//! ([`crate::plan::option_names`]), for front ends to respell.

use grasp_model::{OptionError, Readable as N};

use crate::error::{ScheduleError, TransferError};
use crate::plan::option_names::{DURATION, MAX_RATE, TEMPLATE};

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
    /// The starting schedule has a step without equilibrium.
    #[error(
        "the starting schedule has a step without equilibrium; fix: start from a template \
         that holds (`{TEMPLATE}`), or raise the loads"
    )]
    StartHasNoEquilibrium,
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
        N(*load_n), N(*rate_n_per_s), N(*needed_s), N(*allowed_s)
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
            PlanError::StartHasNoEquilibrium,
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
