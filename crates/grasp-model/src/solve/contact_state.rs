//! The mutable state carried from one solve to the next: slip memory (the coulomb model's
//! path dependence) and the previous forces (the sequential solve's warm start).
//!
//! The [`crate::GraspModel`] is constant; a [`ContactState`] is what changes as a hand-off
//! steps (the split MuJoCo makes between `mjModel` and `mjData`).

use crate::model::grasp_model::GraspModel;
use crate::solve::solution::Solution;

/// Converged solves remembered before the last (two: with the last, they span two directions
/// of load change).
pub const EARLIER_KEPT: usize = 2;

/// State of one finger's contact patch.
#[derive(Debug, Clone, PartialEq)]
pub struct FingerState {
    /// Finger name (the state follows a finger when the set of fingers in contact changes).
    pub name: String,
    /// Slip memory `m_k`, m, per element along `[t1, t2]`: the relative tangential
    /// displacement (object minus finger) at the end of the last converged step. A sticking
    /// element keeps it; a slipping one adds its slip to it. Zero for a fresh contact.
    pub slip_memory_m: Vec<[f64; 2]>,
    /// Element normal forces `F_k` of the last converged solve, N (warm start of the Tresca
    /// radii); `None` before the first solve.
    pub normal_forces_n: Option<Vec<f64>>,
    /// Total normal load of the last converged solve, N (warm start of a load-dependent
    /// `mu`).
    pub normal_load_n: Option<f64>,
    /// The finger's approach in the last converged solve, m (commanded for a
    /// position-controlled finger: from it and the earlier ones the warm start continues an
    /// approach ramp).
    pub approach_m: Option<f64>,
    /// `normal_forces_n` and `normal_load_n` of the converged solves before the last (at
    /// most `EARLIER_KEPT`, oldest first): from them the sequential solve's warm start
    /// continues the loads' ramp.
    pub earlier: Vec<EarlierSolve>,
    /// The displacement a viscoelastic body's history adds to this step's elastic one, m, in
    /// the finger's unknown layout (normal, then `t1`, `t2`): `C h` of
    /// `crate::model::viscoelasticity`. `None`: none (an elastic pair, or the first step).
    pub history_m: Option<Vec<f64>>,
    /// The viscoelastic internal variables of the contact (`crate::solve::viscous_history`);
    /// `None` for an elastic contact and before its first solve of a time history.
    pub viscous: Option<ViscousState>,
}

/// A finger's viscoelastic internal variables.
#[derive(Debug, Clone, PartialEq)]
pub struct ViscousState {
    /// Per viscoelastic body of the contact, per creep term, `z_k` (N, finger layout).
    pub internal_n: Vec<Vec<Vec<f64>>>,
    /// The forces at the end of the last step (N, finger layout).
    pub forces_n: Vec<f64>,
}

/// A finger's forces at one earlier converged solve.
#[derive(Debug, Clone, PartialEq)]
pub struct EarlierSolve {
    /// Element normal forces `F_k`, N.
    pub normal_forces_n: Vec<f64>,
    /// Total normal load, N.
    pub normal_load_n: f64,
    /// Approach, m.
    pub approach_m: f64,
}

impl FingerState {
    /// A fresh contact of `elements` elements: no slip memory, no warm start.
    pub fn fresh(name: &str, elements: usize) -> Self {
        FingerState {
            name: name.to_string(),
            slip_memory_m: vec![[0.0; 2]; elements],
            normal_forces_n: None,
            normal_load_n: None,
            approach_m: None,
            earlier: Vec::new(),
            history_m: None,
            viscous: None,
        }
    }
}

/// State of every finger of a model, in the model's finger order.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactState {
    /// Per finger, scene order.
    pub fingers: Vec<FingerState>,
    /// The time step this state was last prepared for, s
    /// ([`ContactState::prepare_time_step`]; `None`: none, the instantaneous response):
    /// the step [`ContactState::advance_time_step`] moves time on by.
    pub(crate) time_step_s: Option<f64>,
}

impl ContactState {
    /// A fresh state for `model`: zero slip memory, no warm start.
    pub fn new(model: &GraspModel) -> Self {
        Self::of_fingers(
            model
                .fingers
                .iter()
                .map(|f| FingerState::fresh(&f.name, f.patch.len()))
                .collect(),
        )
    }

    /// The state of these fingers (a model's, in its order), not yet prepared for a time
    /// step.
    pub fn of_fingers(fingers: Vec<FingerState>) -> Self {
        ContactState {
            fingers,
            time_step_s: None,
        }
    }

    /// True when the state belongs to `model` (same finger names and element counts, in
    /// order).
    pub fn matches(&self, model: &GraspModel) -> bool {
        self.fingers.len() == model.fingers.len()
            && self.fingers.iter().zip(&model.fingers).all(|(s, f)| {
                s.name == f.name
                    && s.slip_memory_m.len() == f.patch.len()
                    && s.normal_forces_n
                        .as_ref()
                        .is_none_or(|v| v.len() == f.patch.len())
                    && s.earlier
                        .iter()
                        .all(|e| e.normal_forces_n.len() == f.patch.len())
                    && s.history_m
                        .as_ref()
                        .is_none_or(|h| h.len() == f.n_unknowns())
            })
    }

    /// The displacement added to the elastic one of every unknown of `model` (m, program
    /// layout; `program/cone_program.rs`): `-d` on the normal unknowns of a finger pressed in
    /// by its commanded approach `d` (`approach_m`, m, per finger), plus each finger's
    /// viscoelastic history and its mount's preload (`FingerMount::add_preload_offset`).
    pub(crate) fn offsets_m(&self, model: &GraspModel, approach_m: &[f64]) -> Vec<f64> {
        let mut o = vec![0.0; model.n_unknowns];
        for ((f, s), &d) in model.fingers.iter().zip(&self.fingers).zip(approach_m) {
            if d != 0.0 {
                o[f.offset..f.offset + f.patch.len()].fill(-d);
            }
            if let Some(h) = &s.history_m {
                for (oj, hj) in o[f.offset..f.offset + f.n_unknowns()].iter_mut().zip(h) {
                    *oj += hj;
                }
            }
            if let Some(m) = &f.mount {
                m.add_preload_offset(&mut o[f.offset..f.offset + f.n_unknowns()]);
            }
        }
        o
    }

    /// Slip memory of every finger, m.
    pub fn slip_memory_m(&self) -> Vec<Vec<[f64; 2]>> {
        self.fingers
            .iter()
            .map(|f| f.slip_memory_m.clone())
            .collect()
    }
}

impl ContactState {
    /// Writes a successful solution into the state: forces and loads (warm start) and, for the
    /// coulomb model (`memory`), the accumulated slip as the new slip memory.
    pub fn record(&mut self, model: &GraspModel, sol: &Solution, memory: bool) {
        for ((fs, f), fm) in self
            .fingers
            .iter_mut()
            .zip(&sol.fingers)
            .zip(&model.fingers)
        {
            if let Some((normal_forces_n, normal_load_n)) =
                fs.normal_forces_n.take().zip(fs.normal_load_n)
            {
                if fs.earlier.len() == EARLIER_KEPT {
                    fs.earlier.remove(0);
                }
                fs.earlier.push(EarlierSolve {
                    normal_forces_n,
                    normal_load_n,
                    approach_m: fs.approach_m.unwrap_or(0.0),
                });
            }
            fs.normal_forces_n = Some(crate::solve::solution::element_values(&f.elements, |e| {
                e.normal_force_n
            }));
            fs.normal_load_n = Some(f.normal_force_n);
            fs.approach_m = Some(f.approach_m);
            if memory && fm.n_tangential > 0 {
                for (m, e) in fs.slip_memory_m.iter_mut().zip(&f.elements) {
                    *m = e.slip_m;
                }
            }
        }
    }
}
