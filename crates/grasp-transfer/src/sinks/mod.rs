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
    /// Called once after the last step; flushes, closes and moves the output into place.
    fn finish(&mut self) -> Result<(), TransferError>;
    /// Called instead of `finish` when the run fails: the output written so far stays in its
    /// `.partial` file and the file the user named is left untouched.
    fn abort(&mut self) {}
}

/// The temporary file a sink writes before moving it into place: `<path>.partial`.
pub fn partial_path(path: &std::path::Path) -> std::path::PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(".partial");
    path.with_file_name(name)
}

pub(crate) fn move_into_place(
    sink: &'static str,
    tmp: &std::path::Path,
    path: &std::path::Path,
) -> Result<(), TransferError> {
    std::fs::rename(tmp, path).map_err(|e| {
        sink_err(
            sink,
            format!("cannot move {} to {}: {e}", tmp.display(), path.display()),
        )
    })
}

pub(crate) fn sink_err(sink: &'static str, e: impl std::fmt::Display) -> TransferError {
    TransferError::Sink {
        sink,
        message: e.to_string(),
    }
}
