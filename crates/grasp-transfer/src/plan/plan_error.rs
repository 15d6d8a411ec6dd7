//! Why the planner gives no schedule: the question is malformed, the scene or template cannot
//! be run, or a constraint no schedule can keep (named, with the numbers that prove it).

use grasp_model::Readable as N;

use crate::error::{ScheduleError, TransferError};

/// A planning that ends without a checked schedule.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// Options out of range, each `(option, problem and fix)`.
    #[error("{}", .0.iter().map(|(o, m)| format!("--{o}: {m}")).collect::<Vec<_>>().join("\n"))]
    Options(Vec<(String, String)>),
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
         that holds (--template), or raise the loads"
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
    #[error("no duration: give --duration (s) or --max-rate (N/s), or a --template")]
    NoDuration,
    /// A releasing finger cannot reach 0 N at the rate limit within the duration allowed.
    #[error(
        "load rate: {finger} must fall from {} N to 0 N; at --max-rate {} N/s that takes {} s, \
         longer than the {} s allowed; fix: raise --max-rate or the duration",
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
