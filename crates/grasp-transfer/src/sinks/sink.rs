//! The one trait of the sinks: what a destination of step records is told about the run
//! ([`RunInfo`]) and what it must do ([`Sink`]), and the error of a sink writing its file.

use grasp_model::{GraspModel, Scene};

use crate::error::TransferError;
use crate::stepper::StepRecord;

/// What every sink may need to know about the run.
pub struct RunInfo<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The model of the full scene (every finger): frames and patches for drawing.
    pub model: &'a GraspModel,
    /// Every step carries a disturbance margin (`TransferOptions::margins`): the recording's
    /// layout shows their plot.
    pub margins: bool,
}

impl RunInfo<'_> {
    /// The fingers whose sensor has a gel image, scene order (their images are logged).
    pub fn gel_fingers(&self) -> Vec<String> {
        self.scene
            .fingers
            .iter()
            .filter(|f| f.sensor.as_ref().is_some_and(|s| s.gel.is_some()))
            .map(|f| f.name.clone())
            .collect()
    }
}

/// A destination for step records.
///
/// A sink writes to the file it was given and never moves or deletes files: where the output
/// lands (through a temporary file, moved into place only when the run succeeds) is the
/// caller's decision (the `grasp` binary's `output` module).
pub trait Sink {
    /// Called once before the first step.
    fn begin(&mut self, run: &RunInfo) -> Result<(), TransferError>;
    /// Called after every step, in order.
    fn step(&mut self, run: &RunInfo, record: &StepRecord) -> Result<(), TransferError>;
    /// Called once after the last step: writes what is buffered, completes and closes the file.
    fn finish(&mut self) -> Result<(), TransferError>;
    /// Called instead of `finish` when the run fails: closes the file as it is (the caller
    /// discards it).
    fn abort(&mut self) {}
}

/// An error of a sink writing `path`: names the file and the cause.
pub(crate) fn io_err(
    sink: &'static str,
    path: &std::path::Path,
    e: impl std::fmt::Display,
) -> TransferError {
    TransferError::Sink {
        sink,
        message: format!("cannot write {}: {e}", path.display()),
    }
}

/// An error of a sink writing `path`, with the chain of causes (e.g. the MCAP writer's I/O
/// error and, below it, "No space left on device").
pub(crate) fn io_err_chain(
    sink: &'static str,
    path: &std::path::Path,
    e: &dyn std::error::Error,
) -> TransferError {
    let mut message = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        message.push_str(&format!(": {c}"));
        cause = c.source();
    }
    io_err(sink, path, message)
}
