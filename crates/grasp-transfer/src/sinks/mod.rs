//! Log sinks of a hand-off, each optional and independent: MCAP, Rerun, CSV.

mod csv_history;
mod mcap_log;
mod rerun_log;

pub use csv_history::CsvSink;
pub use mcap_log::{FingerMessage, FingersMessage, McapSink, FINGERS_TOPIC, PATCHES_TOPIC};
pub use rerun_log::RerunSink;

use grasp_model::{GraspModel, Scene};

use crate::error::TransferError;
use crate::stepper::StepRecord;

/// What every sink may need to know about the run.
pub struct RunInfo<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The model of the full scene (every finger): frames and patches for drawing.
    pub geometry: &'a GraspModel,
}

/// A destination for step records.
pub trait Sink {
    /// Called once before the first step.
    fn begin(&mut self, run: &RunInfo) -> Result<(), TransferError>;
    /// Called after every step, in order.
    fn step(&mut self, run: &RunInfo, record: &StepRecord) -> Result<(), TransferError>;
    /// Called once after the last step; flushes and closes the output.
    fn finish(&mut self) -> Result<(), TransferError>;
}

pub(crate) fn sink_err(sink: &'static str, e: impl std::fmt::Display) -> TransferError {
    TransferError::Sink {
        sink,
        message: e.to_string(),
    }
}
