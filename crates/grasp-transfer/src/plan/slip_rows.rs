//! The slip margins along a run, each linearised in the planner's variables: the margin
//! `m = 1 - |Q| / (mu P)` at a step of each finger the slip-margin rule counts
//! ([`crate::slip_margin`]), and its derivative with
//! respect to every keyframe load, by the chain rule through the step's load sensitivities
//! (`dP/dL`, `dQ/dL` from the KKT system at the step's active set; [`crate::StepRecord`]'s
//! `sensitivities`) and the keyframe weights of the step.

use grasp_model::{Sensitivities, Solution};

use crate::plan::keyframe_path::{KeyframePath, LoadGroup};
use crate::plan::margin_row::{MarginRow, RowKind};
use crate::slip_margin::{carrying, slip_margin};
use crate::stepper::StepRecord;

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
                margin: slip_margin(f),
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
