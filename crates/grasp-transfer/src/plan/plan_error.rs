//! Why the planner gives no schedule: the question is malformed, the scene or template cannot
//! be run, or a constraint no schedule can keep (named, with the numbers that prove it).
//! Options are named as the Rust API spells them, between backticks
//! ([`crate::plan::option_names`]), for front ends to respell.

use grasp_model::{OptionError, Readable as N};

use crate::error::{ScheduleError, TransferError};
use crate::plan::option_names::{
    CLOSE_TO, DURATION, MAX_APPROACH, MAX_LOAD, MAX_RATE, MAX_SPEED, MIN_APPROACH,
    OBJECTIVE_MARGIN, OPEN_TO, TEMPLATE,
};

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
    /// A planned finger driven by its approach is not position-controlled at a step.
    #[error(
        "fingers.{finger} is not position-controlled at t = {} s: the planner ramps its \
         approach, as its template's first step or the scene drives it; fix: give it one \
         approach ramp in the template (or an `approach_m` in the scene)",
        N(*time_s)
    )]
    NotPositionControlled {
        /// The finger.
        finger: String,
        /// Where, s.
        time_s: f64,
    },
    /// A group of planned fingers mixes loads and approaches.
    #[error(
        "`{option}` mixes force-controlled fingers ({loads}) with position-controlled ones \
         ({approaches}): one group moves by one command; fix: plan them in two plannings, or \
         drive them alike"
    )]
    MixedControl {
        /// The option naming the group.
        option: &'static str,
        /// The force-controlled fingers.
        loads: String,
        /// The position-controlled fingers.
        approaches: String,
    },
    /// A planned finger's straight ramp has no end.
    #[error(
        "fingers.{finger} has no end for its ramp without a `{TEMPLATE}`: give `{option}` \
         ({})",
        end_meaning(option)
    )]
    NoEnd {
        /// The finger.
        finger: String,
        /// The option that gives the end.
        option: &'static str,
    },
    /// A releasing position-controlled finger does not open.
    #[error(
        "fingers.{finger} starts at approach {} m and would end at {} m: a releasing jaw \
         opens (its approach falls) to let go; fix: `{OPEN_TO}` below {} m",
        N(*start_m), N(*end_m), N(*start_m)
    )]
    NotOpening {
        /// The finger.
        finger: String,
        /// Its starting approach, m.
        start_m: f64,
        /// Its end, m.
        end_m: f64,
    },
    /// A fixed approach (a start, a releasing end) lies outside the approach bounds.
    #[error(
        "fingers.{finger}'s approach {} m (a fixed end of its ramp) is outside the planned \
         approaches [{}, {}] m; fix: widen `{MIN_APPROACH}` or `{MAX_APPROACH}`",
        N(*approach_m), N(range_m.0), N(range_m.1)
    )]
    ApproachOutsideRange {
        /// The finger.
        finger: String,
        /// Its fixed approach, m.
        approach_m: f64,
        /// The bounds, m.
        range_m: (f64, f64),
    },
    /// The speed limit cannot be kept, or never binds.
    #[error("{}", speed_message(finger, *travel_m, *speed_m_per_s, *limit_s, *too_fast))]
    Speed {
        /// The finger with the longest travel.
        finger: String,
        /// Its travel, m.
        travel_m: f64,
        /// The limit, m/s.
        speed_m_per_s: f64,
        /// The longest duration allowed, or the shortest planned one (`too_fast`), s.
        limit_s: f64,
        /// True when the speed is so fast that it never binds.
        too_fast: bool,
    },
    /// An option that applies to no planned group.
    #[error(
        "`{option}` is given but applies to no planned finger (it limits or ends the \
         {}); fix: drop it, or plan the fingers it is meant for",
        applies_to(option)
    )]
    OptionUnused {
        /// The option.
        option: &'static str,
    },
    /// A planned group without the rate limit of its kind, for the shortest duration.
    #[error(
        "the {group} fingers have no rate limit, so the shortest duration does not exist \
         (their commands could change as fast as the program likes); fix: give `{option}`, \
         or `{OBJECTIVE_MARGIN}` with a `{DURATION}`"
    )]
    NoRateOfGroup {
        /// `releasing` or `receiving`.
        group: String,
        /// The limit of its kind.
        option: &'static str,
    },
    /// The template has fewer than two step times.
    #[error("the template needs at least two step times")]
    TemplateTooShort,
    /// Neither a duration nor a rate limit to derive one.
    #[error(
        "no duration: give `{DURATION}` (s), `{MAX_RATE}` (N/s) or `{MAX_SPEED}` (m/s), or a \
         `{TEMPLATE}`"
    )]
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

/// What `option` limits or ends, for [`PlanError::OptionUnused`].
fn applies_to(option: &str) -> &'static str {
    match option {
        OPEN_TO => "releasing fingers driven by their approach",
        CLOSE_TO => "receiving fingers driven by their approach",
        MAX_RATE => "loads of force-controlled fingers",
        _ => "approaches of position-controlled fingers",
    }
}

/// What option `option` gives as a ramp's end.
fn end_meaning(option: &str) -> &'static str {
    match option {
        OPEN_TO => "the approach, m, the releasing jaws open to",
        CLOSE_TO => "the approach, m, the receiving fingers close to",
        _ => "the load, N, the receiving fingers ramp up to, when no releasing finger is force-controlled",
    }
}

/// The message of [`PlanError::Speed`].
fn speed_message(finger: &str, travel_m: f64, speed: f64, limit_s: f64, too_fast: bool) -> String {
    let needed_s = travel_m / speed;
    if too_fast {
        format!(
            "`{MAX_SPEED}` {} m/s moves {finger} its {} m in {} s, within the shortest hand-off \
             the planner writes ({} s: a microsecond a step), so the speed never binds and there \
             is no shortest duration to find; fix: a speed that binds (below {} m/s), or \
             `{OBJECTIVE_MARGIN}` with a `{DURATION}`",
            N(speed),
            rounded(travel_m),
            rounded(needed_s),
            rounded(limit_s),
            rounded(travel_m / limit_s)
        )
    } else {
        format!(
            "approach speed: {finger} must travel {} m; at `{MAX_SPEED}` {} m/s that takes {} s, \
             longer than the {} s allowed; fix: raise `{MAX_SPEED}` or the duration",
            rounded(travel_m),
            N(speed),
            rounded(needed_s),
            N(limit_s)
        )
    }
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
