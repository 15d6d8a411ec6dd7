//! # grasp-transfer: quasi-static hand-off driver
//!
//! Replays an object being handed from one set of fingers to another (Sinha 1989, section
//! 4.2): a [`Schedule`] commands each finger (held, a load ramp, a CSV profile, released);
//! the [`Stepper`] solves the grasp at every step with `grasp-model`, reusing the assembled
//! program while the grasp's structure is unchanged; each [`Sink`] logs every step (MCAP, Rerun,
//! CSV, `.npz`; [`OutputFiles`] opens them under the run's output policy); [`TransferSummary`]
//! says when the load moved and how close any finger came to sliding. [`minimum_squeeze`] finds
//! the least squeeze that holds, and [`plan()`] plans the load ramps of a hand-off.
//!
//! ## Layout: the driver's files at the root, the sinks and the planner above them (private)
//!
//! The schedule, the stepper, the margins, the minimum squeeze and the summary sit at the root;
//! `sinks/` (the [`Sink`] trait and one file per output, or what they share) and `plan/` (the
//! planner) build on them and not on each other. The folders and files are private: this page
//! is the crate's whole face, its names grouped below in data-flow order.
//!
//! Depends on `grasp-model` and `grasp-io`, never the reverse.
//!
//! ```
//! use grasp_model::LoadedScene;
//! use grasp_transfer::{Schedule, TransferOptions};
//!
//! // Thesis section 4.2.1: the pair f1, f2 lets go of a plate while f3, f4 take it over.
//! let text = include_str!("../../../examples/plate_transfer.json");
//! let scene = LoadedScene::from_json_str(text)?;
//! let names = scene.finger_names();
//! let text = include_str!("../../../examples/plate_transfer.schedule.json");
//! let schedule = Schedule::from_json_str(text, &names, std::path::Path::new("."))?;
//! let (summary, last) =
//!     grasp_transfer::run(&scene, &schedule, TransferOptions::default(), &mut [], |_| {})?;
//! assert_eq!(summary.steps, 200);
//! assert_eq!(summary.releasing, ["f1", "f2"]);
//! assert_eq!(summary.receiving, ["f3", "f4"]);
//! // At the last step the receiving pair carries the plate alone.
//! let last = last.expect("the run has steps");
//! assert_eq!(last.normal_force_n("f1"), 0.0);
//! assert!(last.normal_force_n("f3") > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

mod easing;
mod error;
mod load_profile;
mod minimum_squeeze;
mod plan;
mod schedule;
mod schedule_builder;
mod schedule_scene_checks;
mod schedule_spec;
mod sinks;
mod slip_margin;
mod step_margin;
mod stepper;
mod summary;

use grasp_model::{GraspModel, LoadedScene};

// ---- The schedule: the file (validated) and its commands in time ----
pub use easing::Easing;
pub use schedule::{Command, ExternalRamp, ExternalWrench, Schedule};
pub use schedule_spec::ScheduleSpec;

// ---- Stepping: one solve a step ([`run`] drives a whole schedule) ----
pub use stepper::{FingerCommand, StepRecord, Stepper, TransferOptions};

// ---- The summary, folded step by step ----
pub use summary::{
    FailedStep, Fallbacks, HeldRelaxation, LeastSafeStep, MarginCost, OtherEquilibria,
    SequentialTotals, SlipMargin, SummaryAccumulator, TransferSummary, MAX_FOLDED_FINGERS,
    MAX_LISTED_FAILED_STEPS,
};

// ---- The slip-margin rule of the summary and the planner ----
pub use slip_margin::{
    carrying, slip_margin, step_slip_margins, FingerSlipMargin, StepSlipMargins, CARRYING_FRACTION,
    SLIP_MARGIN_RULE,
};

// ---- Sinks: what every step is logged to, and the files a run writes ----
pub use sinks::csv_history::{CsvSink, CSV_WARNING_SEPARATOR};
pub use sinks::element_maps::{state_code, COMPACT_ABOVE_ELEMENTS};
pub use sinks::foxglove_scene::SCENE_TOPIC;
pub use sinks::mcap_log::{
    FingerMessage, FingersMessage, McapSink, FINGERS_TOPIC, PATCHES_TOPIC, WARNING_METADATA,
};
pub use sinks::output_files::{McapProfile, OpenError, OutputFiles, OutputPaths};
pub use sinks::patch_maps_message::{PATCH_MAPS_SCHEMA, PATCH_MAPS_TOPIC};
pub use sinks::rerun_log::{RerunSink, FLUSH_EVERY_STEPS};
pub use sinks::ros2_log::{ros_name_problem, Ros2McapSink};
pub use sinks::sink::{RunInfo, Sink};
pub use sinks::tactile_message::{TactileMessage, TACTILE_SCHEMA, TACTILE_TOPIC};

// ---- What the sinks draw, shared with the CLI's pictures ----
pub use sinks::colour_key::{FRICTION_FORCE_RGB, NORMAL_FORCE_RGB};
pub use sinks::drawing_scale::{arrow_scale_m_per_n, drawing_scale, ARROW_FRACTION};
pub use sinks::fingertip_drawing::{tip_drawings, TipDrawing};
pub use sinks::identical_curves::IdenticalCurves;

// ---- Margins: a step's disturbance margins ----
pub use step_margin::{step_margin, MarginPath, OtherEquilibrium, StepMargin};

// ---- Minimum squeeze: the least load that holds ----
pub use minimum_squeeze::{minimum_squeeze, MinimumSqueeze, SqueezeOutcome};

// ---- The planner: load ramps that keep the margins ----
pub use plan::planned_group::{Commanded, PlannedGroup, RateLimits};
pub use plan::{
    plan, Binding, CheckedAt, KeyframePath, MarginsAtStep, Objective, PlanError, PlanOptions,
    PlanReport, Template, DISTURBANCE_TOLERANCE, FINE_STEPS, MARGIN_TOLERANCE,
};

/// How the planner's messages name its options ([`PlanOptions`]' fields as the Rust API spells
/// them, between backticks); front ends respell them into their own (the CLI's flags,
/// Python's keyword arguments), as they respell `grasp_model::option_names`.
pub mod plan_option_names {
    pub use crate::plan::option_names::*;
}

/// The planner's linearisation, for checking it against differences of whole runs: the slip
/// margins of a run with their derivatives in the keyframe loads (`slip_rows`), and the load
/// directions whose sensitivities they need (`load_directions`).
pub mod plan_linearisation {
    pub use crate::plan::slip_rows::{load_directions, slip_rows};
}

// ---- Errors ----
pub use error::{ScheduleError, TransferError};

/// Runs a whole schedule, streaming every step to the sinks and to `on_step` (nothing is kept
/// but the summary, folded step by step, and the last step). Returns the summary and the last
/// record. A run that stops at a failed step (without `keep_going`) still finishes its sinks:
/// `summary.steps < schedule.times.len()` tells the caller it is incomplete.
pub fn run(
    scene: &LoadedScene,
    schedule: &Schedule,
    options: TransferOptions,
    sinks: &mut [&mut dyn Sink],
    mut on_step: impl FnMut(&StepRecord),
) -> Result<(TransferSummary, Option<StepRecord>), TransferError> {
    let go_on = |r: &StepRecord| {
        on_step(r);
        std::ops::ControlFlow::Continue(())
    };
    run_until(scene, schedule, options, sinks, go_on)
}

/// [`run`], stopped after the step at which `on_step` answers `Break(reason)`: the sinks are
/// aborted (their temporary files removed) and the run ends in [`TransferError::Stopped`]
/// (Python's Ctrl-C and progress callbacks).
pub fn run_until(
    scene: &LoadedScene,
    schedule: &Schedule,
    options: TransferOptions,
    sinks: &mut [&mut dyn Sink],
    mut on_step: impl FnMut(&StepRecord) -> std::ops::ControlFlow<String>,
) -> Result<(TransferSummary, Option<StepRecord>), TransferError> {
    // The scene's model, built once: the sinks draw it, the stepper restricts it to each
    // step's active fingers.
    let model =
        GraspModel::from_loaded_with(scene, options.solve.compliance).map_err(|source| {
            TransferError::Scene {
                time_s: 0.0,
                source,
            }
        })?;
    let info = RunInfo {
        scene,
        model: &model,
        margins: options.margins,
    };
    let names = scene.finger_names();
    let coulomb_margins = options.margins && model.kind() == grasp_model::ModelKind::Coulomb;
    let mut summary = SummaryAccumulator::new(&names)
        .with_margin_threshold(options.margin_threshold_n)
        .with_equilibrium_probe(coulomb_margins.then_some(options.margin_options.probe_equilibria));
    let mut last = None;
    let outcome = (|| {
        for s in sinks.iter_mut() {
            s.begin(&info)?;
        }
        for r in Stepper::with_model(scene, &model, schedule, options) {
            let r = r?;
            for s in sinks.iter_mut() {
                s.step(&info, &r)?;
            }
            if let std::ops::ControlFlow::Break(reason) = on_step(&r) {
                return Err(TransferError::Stopped {
                    time_s: r.time_s,
                    reason,
                });
            }
            summary.add(&r);
            last = Some(r);
        }
        for s in sinks.iter_mut() {
            s.finish()?;
        }
        Ok(())
    })();
    if let Err(e) = outcome {
        for s in sinks.iter_mut() {
            s.abort();
        }
        return Err(e);
    }
    Ok((summary.finish(), last))
}

/// [`run`], keeping every record (memory grows with the number of steps: for tests and short
/// schedules).
pub fn run_collect(
    scene: &LoadedScene,
    schedule: &Schedule,
    options: TransferOptions,
    sinks: &mut [&mut dyn Sink],
) -> Result<(Vec<StepRecord>, TransferSummary), TransferError> {
    let mut records = Vec::new();
    let (summary, _) = run(scene, schedule, options, sinks, |r| records.push(r.clone()))?;
    Ok((records, summary))
}
