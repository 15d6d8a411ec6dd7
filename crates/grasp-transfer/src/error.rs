//! Errors of the transfer driver.

use std::fmt;

/// One problem found in a schedule: where, what, and how to fix it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScheduleProblem {
    /// JSON path, e.g. `fingers.f1[1].ramp.keyframes[2]`.
    pub path: String,
    /// What is wrong.
    pub message: String,
    /// What to do.
    pub fix: String,
}

impl fmt::Display for ScheduleProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}; fix: {}", self.path, self.message, self.fix)
    }
}

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
    #[error("{}", format_problems(.0))]
    Invalid(Vec<ScheduleProblem>),
}

impl ScheduleError {
    /// Every problem as one list.
    pub fn problems(&self) -> Vec<ScheduleProblem> {
        match self {
            ScheduleError::Parse { path, message } => vec![ScheduleProblem {
                path: path.clone(),
                message: message.clone(),
                fix: "correct the JSON (see `grasp schema --schedule`)".into(),
            }],
            ScheduleError::Invalid(p) => p.clone(),
        }
    }
}

fn format_problems(p: &[ScheduleProblem]) -> String {
    let mut s = format!("the schedule has {} problem(s):", p.len());
    for q in p {
        s.push_str("\n  - ");
        s.push_str(&q.to_string());
    }
    s
}

/// Errors of a transfer run that are not solver outcomes.
#[derive(Debug, thiserror::Error)]
pub enum TransferError {
    /// The scene restricted to the active fingers is not usable.
    #[error("at t = {time_s} s the active fingers do not form a usable scene: {source}")]
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
    /// The model refused the data.
    #[error(transparent)]
    Model(#[from] grasp_model::ModelError),
    /// An invariant of the stepper did not hold (a bug; please report the scene and schedule).
    #[error("internal error: {0}; please report the scene and schedule")]
    Internal(&'static str),
    /// A sink failed to write.
    #[error("{sink}: {message}")]
    Sink {
        /// Which sink.
        sink: &'static str,
        /// What failed.
        message: String,
    },
}
