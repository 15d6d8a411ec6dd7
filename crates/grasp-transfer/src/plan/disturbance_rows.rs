//! The disturbance margins along a run as planner rows: each step's smallest disturbance
//! margin over the axis directions ([`crate::step_margin`], its search continued along the
//! run), divided by the threshold `PlanOptions::min_margin_n`, and its derivatives in each
//! group's load by forward differences of whole runs, each with one group's keyframe loads
//! raised by a small step. The margin has no KKT derivative: it is where a search ends, set by
//! whichever finger fails first, so it is differenced, and the trust region's ratio test
//! judges the result.

use grasp_model::MarginOptions;

use crate::plan::keyframe_path::KeyframePath;
use crate::plan::margin_row::{MarginRow, RowKind};
use crate::plan::slip_rows::note_once;
use crate::stepper::StepRecord;

/// The load step of the differences, as a fraction of the path's largest keyframe load: large
/// enough that the margins' bisection error ([`DIFFERENCE_TOLERANCE`] of a margin) stays below
/// a hundredth of a derivative of order one, small enough to stay on one side of most kinks.
pub const LOAD_STEP: f64 = 2e-2;

/// Relative bisection tolerance of the margins that are differenced: tighter than the
/// default 1e-3, so that two runs' margins differ by the load step's effect, not by where
/// each bisection stopped.
pub const DIFFERENCE_TOLERANCE: f64 = 1e-4;

/// The margin options of the runs that are differenced.
pub fn difference_options() -> MarginOptions {
    MarginOptions {
        relative_tolerance: DIFFERENCE_TOLERANCE,
        ..crate::TransferOptions::default().margin_options
    }
}

/// The load step of the differences along `path`, N.
pub fn load_step_n(path: &KeyframePath) -> f64 {
    let largest = path
        .values
        .iter()
        .flatten()
        .fold(0.0, |a: f64, &b| a.max(b.abs()));
    LOAD_STEP * largest.max(f64::MIN_POSITIVE)
}

/// `path` with group `g`'s loads raised by `step_n` at every keyframe.
pub fn raised(path: &KeyframePath, g: usize, step_n: f64) -> KeyframePath {
    let mut out = path.clone();
    out.values[g].iter_mut().for_each(|x| *x += step_n);
    out
}

/// The disturbance rows of a run along `path` (`base[s]` is step `s`, its margins computed),
/// with `raised[g]`, the run of `path` with group `g`'s loads raised by `step_n`, and the
/// threshold `threshold_n` (N); the notes say where a derivative was missing.
pub fn disturbance_rows(
    path: &KeyframePath,
    base: &[StepRecord],
    raised: &[Vec<StepRecord>],
    step_n: f64,
    threshold_n: f64,
    notes: &mut Vec<String>,
) -> Vec<MarginRow> {
    let mut rows = Vec::new();
    for r in base {
        let Some(m) = &r.margin else { continue };
        let per_load: Vec<f64> = raised
            .iter()
            .map(
                |run| match run.get(r.index).and_then(|x| x.margin.as_ref()) {
                    Some(other) => {
                        (other.known_to_hold_n() - m.known_to_hold_n()) / (step_n * threshold_n)
                    }
                    None => {
                        let why = format!(
                            "no disturbance-margin derivative at t = {:.3} s: a raised run found \
                         no equilibrium there (taken as 0)",
                            r.time_s
                        );
                        note_once(notes, why);
                        0.0
                    }
                },
            )
            .collect();
        rows.push(MarginRow {
            kind: RowKind::Disturbance,
            step: r.index,
            time_s: r.time_s,
            finger: m.failing_finger.clone().unwrap_or_default(),
            margin: m.known_to_hold_n() / threshold_n,
            gradient: path.gradient(r.index, &per_load),
            per_duration: 0.0,
        });
    }
    rows
}
