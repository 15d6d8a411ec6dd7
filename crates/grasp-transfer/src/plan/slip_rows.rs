//! The slip margins along a run, each linearised in the planner's variables: a loaded
//! frictional finger's margin `m = 1 - |Q| / (mu P)` at a step, and its derivative with
//! respect to every keyframe load, by the chain rule through the step's load sensitivities
//! (`dP/dL`, `dQ/dL` from the KKT system at the step's active set; [`crate::StepRecord`]'s
//! `sensitivities`) and the keyframe weights of the step.

use grasp_model::{Sensitivities, Solution};

use crate::plan::keyframe_path::{KeyframePath, LoadGroup};
use crate::plan::margin_row::{MarginRow, RowKind};
use crate::stepper::StepRecord;

/// A finger counts in the slip-margin constraint at a step while its contact force (normal and
/// friction together) is at least this fraction of the step's load scale: a finger letting go
/// may slide as it leaves.
pub const CARRYING_FRACTION: f64 = 0.05;

/// True when finger `f` of a solution counts at its step: frictional, and carrying at least
/// [`CARRYING_FRACTION`] of the load scale.
pub fn carrying(f: &grasp_model::FingerSolution, load_scale_n: f64) -> bool {
    let q = f.tangential_force_n;
    let force = (f.normal_force_n.powi(2) + q.iter().map(|c| c * c).sum::<f64>()).sqrt();
    f.friction_coefficient > 0.0
        && f.normal_force_n > 0.0
        && force >= CARRYING_FRACTION * load_scale_n
}

/// The slip rows of a run along `path` (`records[s]` is step `s`); the notes say where a
/// derivative was missing and taken as zero.
pub fn slip_rows(
    path: &KeyframePath,
    records: &[StepRecord],
    notes: &mut Vec<String>,
) -> Vec<MarginRow> {
    let mut rows = Vec::new();
    for r in records {
        let sol = &r.solution;
        let sens = match &r.sensitivities {
            Some(Ok(s)) => Some(s),
            Some(Err(why)) => {
                note_once(
                    notes,
                    format!("no load derivatives at t = {:.3} s: {why}", r.time_s),
                );
                None
            }
            None => None,
        };
        for (fi, f) in sol.fingers.iter().enumerate() {
            if !carrying(f, sol.load_scale_n) {
                continue;
            }
            let per_load = sens.map_or_else(
                || vec![0.0; path.groups.len()],
                |s| margin_per_load(sol, s, fi, &path.groups),
            );
            rows.push(MarginRow {
                kind: RowKind::Slip,
                step: r.index,
                time_s: r.time_s,
                finger: f.name.clone(),
                margin: 1.0 - f.friction_utilization,
                gradient: path.gradient(r.index, &per_load),
                per_duration: 0.0,
            });
        }
    }
    rows
}

/// `dm/dL_j` of finger `fi`'s slip margin for each planned finger `j` (0 where the finger is
/// released at the step or the derivative is undefined).
fn margin_per_load(
    sol: &Solution,
    sens: &Sensitivities,
    fi: usize,
    planned: &[LoadGroup],
) -> Vec<f64> {
    let f = &sol.fingers[fi];
    let s = &sens.fingers[fi];
    let q = f.tangential_force_n;
    let q_norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    let (mu, p) = (f.friction_coefficient, f.normal_force_n);
    planned
        .iter()
        .map(|group| {
            let column = sens
                .parameters
                .iter()
                .position(|c| c.defined && c.name == format!("loads:{}", group.name));
            let Some(c) = column else { return 0.0 };
            let dq = s.tangential_force[c];
            let along = if q_norm > 0.0 {
                (0..3).map(|a| q[a] * dq[a]).sum::<f64>() / q_norm
            } else {
                0.0
            };
            -(along / p - q_norm * s.normal_force[c] / (p * p)) / mu
        })
        .collect()
}

/// Adds `note` unless it is there already (at most 8 notes).
pub(crate) fn note_once(notes: &mut Vec<String>, note: String) {
    if notes.len() < 8 && !notes.contains(&note) {
        notes.push(note);
    }
}

/// The sensitivities' load directions of the path's groups: each member moved by its share.
pub fn load_directions(path: &KeyframePath) -> Vec<grasp_model::LoadDirection> {
    path.groups
        .iter()
        .map(|g| grasp_model::LoadDirection {
            name: g.name.clone(),
            rates: g.members.clone(),
        })
        .collect()
}
