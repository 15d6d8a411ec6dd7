//! The viscoelastic history carried from one time step to the next: per viscoelastic body of a
//! contact and per term of its creep function, the internal variables `z_k` (N, one per
//! unknown of the finger), and the last step's forces; from them the history displacement of
//! the next step, `sum_b C_b h_b` ([`crate::model::viscoelasticity`], exact for forces linear
//! within a step).
//!
//! A time-stepping caller (a hand-off, a solve at a later time) gives each solve its step's
//! length ([`crate::StepInputs::time_step_s`]); the solve prepares the state
//! ([`ContactState::prepare_time_step`]: the history displacement written into the contact
//! state, which the program adds to the gaps and tangential displacements) and is solved with
//! the compliance over the step; [`ContactState::advance_time_step`], after a successful one,
//! moves the internal variables to the step's end. The first solve of a history is the
//! instantaneous response (the loads applied as a step): no history displacement.

use crate::model::grasp_model::GraspModel;
use crate::solve::contact_state::{ContactState, ViscousState};
use crate::solve::solution::Solution;

impl ContactState {
    /// Writes each viscoelastic finger's history displacement for a step of `dt_s` seconds of
    /// `model` into this state (`C_b h_b` summed over its bodies,
    /// `h_b = sum_k w_k (E_k z_k + (A_k - E_k) F)`; none where the finger has no history yet),
    /// and remembers the step. A solve of the step does it ([`crate::GraspSolver::solve_step`]).
    pub(crate) fn prepare_time_step(&mut self, model: &GraspModel, dt_s: f64) {
        prepare_step(model, self, dt_s);
        self.time_step_s = Some(dt_s);
    }

    /// Moves each viscoelastic finger's internal variables to the end of the step this state
    /// was solved for (the instantaneous response when none), whose solution is `sol`: time
    /// moves on. `model` is the model the solve was given.
    pub fn advance_time_step(&mut self, model: &GraspModel, sol: &Solution) {
        advance_step(model, self, self.time_step_s.unwrap_or(0.0), sol);
    }
}

/// [`ContactState::prepare_time_step`] for a step of `dt_s` seconds.
fn prepare_step(model: &GraspModel, state: &mut ContactState, dt_s: f64) {
    for (f, s) in model.fingers.iter().zip(state.fingers.iter_mut()) {
        s.history_m = None;
        let (Some(v), Some(vs)) = (&f.viscous, &s.viscous) else {
            continue;
        };
        let n = f.n_unknowns();
        let mut total = vec![0.0; n];
        for (body, z) in v.bodies.iter().zip(&vs.internal_n) {
            let c = body.creep.step(dt_s);
            let mut h = vec![0.0; n];
            for (k, term) in body.creep.terms.iter().enumerate() {
                let (e, a) = (c.decay[k], c.average[k]);
                for ((hj, zj), fj) in h.iter_mut().zip(&z[k]).zip(&vs.forces_n) {
                    *hj += term.weight * (e * zj + (a - e) * fj);
                }
            }
            let mut u = vec![0.0; n];
            body.compliance_m_per_n.apply(&h, &mut u);
            for (t, uj) in total.iter_mut().zip(u) {
                *t += uj;
            }
        }
        s.history_m = Some(total);
    }
}

/// Moves each viscoelastic finger's internal variables to the end of a step of `dt_s` seconds
/// whose solution is `sol` (`z_k <- E_k z_k + (A_k - E_k) F_old + (1 - A_k) F_new`), starting
/// them at zero after a finger's first solve.
fn advance_step(model: &GraspModel, state: &mut ContactState, dt_s: f64, sol: &Solution) {
    for ((f, s), fs) in model
        .fingers
        .iter()
        .zip(state.fingers.iter_mut())
        .zip(&sol.fingers)
    {
        let Some(v) = &f.viscous else {
            continue;
        };
        let forces = finger_forces(f.n_tangential, fs);
        match &mut s.viscous {
            None => {
                s.viscous = Some(ViscousState {
                    internal_n: v
                        .bodies
                        .iter()
                        .map(|b| vec![vec![0.0; forces.len()]; b.creep.terms.len()])
                        .collect(),
                    forces_n: forces,
                });
            }
            Some(vs) => {
                for (body, z) in v.bodies.iter().zip(vs.internal_n.iter_mut()) {
                    let c = body.creep.step(dt_s);
                    for (k, zk) in z.iter_mut().enumerate() {
                        let (e, a) = (c.decay[k], c.average[k]);
                        for ((zj, old), new) in zk.iter_mut().zip(&vs.forces_n).zip(&forces) {
                            *zj = e * *zj + (a - e) * old + (1.0 - a) * new;
                        }
                    }
                }
                vs.forces_n = forces;
            }
        }
    }
}

/// A finger's forces in its unknown layout (N): normal, then `t1`, `t2` as it has them.
fn finger_forces(n_tangential: usize, f: &crate::solve::solution::FingerSolution) -> Vec<f64> {
    let ne = f.elements.len();
    let mut out = vec![0.0; ne * (1 + n_tangential)];
    for (k, e) in f.elements.iter().enumerate() {
        out[k] = e.normal_force_n;
        for c in 0..n_tangential {
            out[(c + 1) * ne + k] = e.tangential_force_n[c];
        }
    }
    out
}
