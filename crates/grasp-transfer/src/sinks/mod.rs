//! Log sinks of a hand-off, each optional and independent: MCAP, Rerun, CSV, NumPy `.npz`.

mod colour_key;
mod csv_history;
mod element_maps;
mod fingertip_drawing;
mod foxglove_scene;
mod identical_curves;
mod mcap_log;
mod npz_steps;
mod patch_maps_message;
mod patch_views;
mod rerun_grid_maps;
mod rerun_layout;
mod rerun_log;

pub use colour_key::{
    state_rgb, unit_rgb, FORCE_KEY, FRICTION_FORCE_RGB, NORMAL_FORCE_RGB, STATE_KEY,
};
pub use csv_history::CsvSink;
pub use element_maps::{is_compact, state_code, ElementMaps, COMPACT_ABOVE_ELEMENTS, STATE_NAMES};
pub use fingertip_drawing::{tip_drawings, TipDrawing, LARGEST_DRAWN};
pub use foxglove_scene::SCENE_TOPIC;
pub use identical_curves::IdenticalCurves;
pub use mcap_log::{FingerMessage, FingersMessage, McapSink, FINGERS_TOPIC, PATCHES_TOPIC};
pub use npz_steps::NpzSink;
pub use patch_maps_message::{PATCH_MAPS_SCHEMA, PATCH_MAPS_TOPIC};
pub use rerun_layout::{layout_messages, LayoutContent};
pub use rerun_log::{RerunSink, FLUSH_EVERY_STEPS};

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

/// One CSV field as RFC 4180 writes it: quoted (inner quotes doubled) when it holds a comma, a
/// quote or a line break.
pub fn csv_field(s: &str) -> std::borrow::Cow<'_, str> {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\"")).into()
    } else {
        s.into()
    }
}

/// The box around the contact points and the centre of mass, `(low, high)` corners, m.
pub(crate) fn contact_bounds(g: &GraspModel) -> (nalgebra::Vector3<f64>, nalgebra::Vector3<f64>) {
    let c = g.center_of_mass_m();
    g.fingers().iter().fold((c, c), |(lo, hi), f| {
        (lo.inf(&f.frame().origin_m), hi.sup(&f.frame().origin_m))
    })
}

/// The scene's size (diagonal of the box around the contact points and the centre of mass,
/// m, at least 1 mm) and the force arrows' scale ([`arrow_scale_m_per_n`] of that size, m per
/// N), the same in every sink and in the package's drawings of other force sets.
pub fn drawing_scale(g: &GraspModel) -> (f64, f64) {
    let (lo, hi) = contact_bounds(g);
    let size = (hi - lo).norm().max(1e-3);
    (size, arrow_scale_m_per_n(size, g.scales().load_n))
}

/// The fraction of a drawing's size that an arrow of the load scale spans.
pub const ARROW_FRACTION: f64 = 0.3;

/// The force arrows' scale, m per N, of a drawing `size_m` across: the load scale
/// (`load_scale_n`, N) drawn as [`ARROW_FRACTION`] of the size. The one scale of every drawing
/// of forces: the sinks' arrows and the CLI's force diagram.
pub fn arrow_scale_m_per_n(size_m: f64, load_scale_n: f64) -> f64 {
    ARROW_FRACTION * size_m / load_scale_n
}
