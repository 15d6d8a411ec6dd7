//! Errors of the transfer driver.

use grasp_model::{format_problems, InputProblem};

/// A schedule that cannot be used.
#[derive(Debug, Clone, thiserror::Error)]
pub enum ScheduleError {
    /// Not valid JSON of the schedule format.
    #[error("{path}: {message}")]
    Parse {
        /// Where parsing stopped.
        path: String,
        /// Parser message.
        message: String,
    },
    /// Every problem found.
    #[error("{}", format_problems("schedule", .0))]
    Invalid(Vec<InputProblem>),
}

impl ScheduleError {
    /// Every problem as one list.
    pub fn problems(&self) -> Vec<InputProblem> {
        match self {
            ScheduleError::Parse { path, message } => vec![InputProblem {
                path: path.clone(),
                message: message.clone(),
                fix: "correct the JSON (the schedule format: docs/schedule.schema.json)".into(),
            }],
            ScheduleError::Invalid(p) => p.clone(),
        }
    }
}

/// Errors of a transfer run that are not solver outcomes.
#[derive(Debug, thiserror::Error)]
pub enum TransferError {
    /// The scene restricted to the active fingers is not usable.
    #[error(
        "at t = {} s the active fingers do not form a usable scene: {source}",
        grasp_model::Readable(*time_s)
    )]
    Scene {
        /// Step time, s.
        time_s: f64,
        /// Cause.
        #[source]
        source: grasp_model::SceneError,
    },
    /// A held finger's `"current"` load at the first step needs the scene as written to hold.
    #[error(
        "fingers.{finger}: \"current\" at the first step is the load the finger carries in the \
         scene as written, but that grasp has no equilibrium; fix: give a number instead, or make \
         the scene hold"
    )]
    Current {
        /// Finger name.
        finger: String,
    },
    /// The schedule asks what the scene cannot do (a hand it lacks, a load on a servo's jaw,
    /// a hand moved out of a planar scene's plane).
    #[error("{path}: {message}; fix: {fix}")]
    ScheduleAgainstScene {
        /// The schedule's field.
        path: String,
        /// What is wrong.
        message: String,
        /// What to do.
        fix: String,
    },
    /// The model refused the data.
    #[error(transparent)]
    Model(#[from] grasp_model::ModelError),
    /// An invariant of the stepper did not hold (a bug; please report the scene and schedule).
    #[error("internal error: {0}; please report the scene and schedule")]
    Internal(&'static str),
    /// The caller stopped the run after a step ([`crate::run_until`]: Ctrl-C in Python).
    #[error("stopped after t = {} s: {reason}", grasp_model::Readable(*time_s))]
    Stopped {
        /// The last step's time, s.
        time_s: f64,
        /// Why.
        reason: String,
    },
    /// A sink failed to write.
    #[error("{sink}: {message}")]
    Sink {
        /// Which sink.
        sink: &'static str,
        /// What failed.
        message: String,
    },
}
