//! The slip margins along a run, each linearised in the planner's variables: the margin
//! `m = 1 - |Q| / (mu P)` at a step of each finger the slip-margin rule counts
//! ([`crate::slip_margin`]), and its derivative with
//! respect to every keyframe value, by the chain rule through the step's sensitivities
//! (`dP/dL`, `dQ/dL` along a load group's direction, or `dP/dd`, `dQ/dd` of an approach
//! group's members' approaches, from the KKT system at the step's active set;
//! [`crate::StepRecord`]'s `sensitivities`) and the keyframe weights of the step.

use grasp_model::{Sensitivities, Solution};

use crate::plan::keyframe_path::KeyframePath;
use crate::plan::margin_row::{MarginRow, RowKind};
use crate::plan::planned_group::{Commanded, PlannedGroup};
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

/// `dm/dx_g` of finger `fi`'s slip margin for each planned group's variable `x_g` (0 where the
/// finger is released at the step or the derivative is undefined).
fn margin_per_load(
    sol: &Solution,
    sens: &Sensitivities,
    fi: usize,
    planned: &[PlannedGroup],
) -> Vec<f64> {
    let f = &sol.fingers[fi];
    let q = f.tangential_force_n;
    let q_norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    let (mu, p) = (f.friction_coefficient, f.normal_force_n);
    planned
        .iter()
        .map(|group| {
            let Some((dp, dq)) = group_derivative(sens, fi, group) else {
                return 0.0;
            };
            let along = if q_norm > 0.0 {
                (0..3).map(|a| q[a] * dq[a]).sum::<f64>() / q_norm
            } else {
                0.0
            };
            -(along / p - q_norm * dp / (p * p)) / mu
        })
        .collect()
}

/// `(dP, dQ)` of finger `fi` per unit of `group`'s variable: its load direction's column
/// (`loads:<group>`), or the sum of its members' `approach:<finger>` columns, each per metre,
/// times the metres a member moves per unit (`share / c`); `None` where a column is undefined.
fn group_derivative(
    sens: &Sensitivities,
    fi: usize,
    group: &PlannedGroup,
) -> Option<(f64, [f64; 3])> {
    let column = |name: String| {
        let c = sens.parameters.iter().position(|c| c.name == name)?;
        sens.parameters[c].defined.then_some(c)
    };
    let s = &sens.fingers[fi];
    let terms: Vec<(usize, f64)> = match &group.commanded {
        Commanded::Load => vec![(column(format!("loads:{}", group.name))?, 1.0)],
        Commanded::Approach {
            newtons_per_metre, ..
        } => group
            .members
            .iter()
            .map(|(name, share)| {
                Some((
                    column(format!("approach:{name}"))?,
                    share / newtons_per_metre,
                ))
            })
            .collect::<Option<_>>()?,
    };
    let mut out = (0.0, [0.0; 3]);
    for (c, w) in terms {
        out.0 += w * s.normal_force[c];
        for a in 0..3 {
            out.1[a] += w * s.tangential_force[c][a];
        }
    }
    Some(out)
}

/// Adds `note` unless it is there already (at most 8 notes).
pub(crate) fn note_once(notes: &mut Vec<String>, note: String) {
    if notes.len() < 8 && !notes.contains(&note) {
        notes.push(note);
    }
}

/// The sensitivities' load directions of the path's load groups: each member moved by its
/// share (an approach group's members have their own `approach:<finger>` columns).
pub fn load_directions(path: &KeyframePath) -> Vec<grasp_model::LoadDirection> {
    path.groups
        .iter()
        .filter(|g| !g.is_approach())
        .map(|g| grasp_model::LoadDirection {
            name: g.name.clone(),
            rates: g.members.clone(),
        })
        .collect()
}
