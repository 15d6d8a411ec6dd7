//! One trial of a margin search: the grasp under the search's disturbance at one magnitude,
//! reached by a quasi-static ramp from a state that held, and judged by [`holds`].
//!
//! **The ramp.** The coulomb model remembers slip, so whether the grasp holds under a push of
//! magnitude `s` depends on how the push got there. A margin is the first failure along the
//! push ramped quasi-statically from the step's state ([`super::margin_report`]); one step from
//! the undisturbed state straight to a push far beyond it can land on an equilibrium that
//! holds (the coulomb disc hand-off at t = 1.5 s: f3 slides under every push along +x from
//! 0.36 N to 4 N, ramped or in one step, but one step to 5 N holds). So a coulomb trial reaches
//! its magnitude in steps that at most double it (the first up to [`INITIAL_STEP`] of the load
//! scale), each from the state the last one left; the search's own growth and bisection already
//! step so, and a trial jumping further (the continued search's check of a predicted margin)
//! is ramped. On that state, ramps whose steps grow tenfold and by 1 % give the same margin to
//! 1e-4. The energy model has no slip memory: a trial is one step.
//!
//! **A stall is not a failure.** When the chosen solver does not converge on a step, the other
//! one (Clarabel for the native solver, the native solver for Clarabel; `auto` has already
//! tried both) solves the same step from the same state and its answer counts
//! ([`Search::fallbacks`]). When neither converges the trial [`Trial::Stalls`]: the search
//! reports the magnitude undetermined, never a margin.

use std::sync::Arc;

use nalgebra::Vector3;

use crate::analysis::load_capacity::{LoadCapacity, UnitDisturbance};
use crate::analysis::margin_report::{holds, utilisation_of, Failure};
use crate::analysis::trial_forces::TrialForces;
use crate::analysis::wrench_directions::WrenchDirection;
use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::number_text::Readable;
use crate::scene::scene_format::ModelKind;
use crate::solve::contact_state::ContactState;
use crate::solve::grasp_solver::GraspSolver;
use crate::solve::solution::{Solution, SolveStatus};
use crate::solve::step_inputs::StepInputs;

/// First growth step of the search, as a fraction of the load scale: small, because a trial
/// that holds is cheap (a warm-started step) and one that fails is not (the solver must certify
/// that no equilibrium exists), so the search should fail as few times as it can. Also the
/// first step of a coulomb ramp.
pub(crate) const INITIAL_STEP: f64 = 1e-2;

/// Below this fraction of the load scale a margin counts as zero: the bisection stops (the
/// solves themselves balance the load only to about 1e-10 of it).
pub(crate) const ZERO_MARGIN: f64 = 1e-6;

/// Largest number of steps of one coulomb ramp (halving from the magnitude passes below any
/// first step within 64).
const MAX_RAMP_STEPS: usize = 64;

/// Largest ratio of two successive magnitudes of a coulomb trial's ramp.
const RAMP_RATIO: f64 = 1.25;

/// The search along one direction.
pub(crate) struct Search<'a> {
    pub(crate) model: &'a GraspModel,
    pub(crate) inputs: &'a StepInputs,
    pub(crate) solver: &'a mut GraspSolver,
    pub(crate) direction: WrenchDirection,
    pub(crate) length_m: f64,
    /// The margins' load scale, N: the unit of the growth step, the cap and the zero margin.
    pub(crate) load_n: f64,
    pub(crate) solves: u32,
    /// Trials whose chosen solver did not converge and the other solver answered.
    pub(crate) fallbacks: u32,
    pub(crate) exempt: &'a [String],
    /// The magnitude from which no equilibrium exists, N ([`LoadCapacity`]; infinite when
    /// unknown): trials there fail without a solve.
    pub(crate) capacity_n: f64,
    /// The forces of the last trials solved along the direction, the first input of the next
    /// trial's Tresca iteration instead of its start state's ([`TrialForces`]).
    pub(crate) trial_forces: TrialForces,
    /// Whether trials take and keep [`Search::trial_forces`] (not: the start state's forces,
    /// as the search from scratch takes them), and the narrowing is guided by
    /// [`Search::utilisation`].
    pub(crate) guessing: bool,
    /// The magnitudes that held (N) with the largest friction utilisation of the fingers
    /// judged by sliding there ([`utilisation_of`]), in the order tried.
    pub(crate) utilisation: Vec<(f64, f64)>,
    /// The other solver, made at the first step the chosen one does not converge on.
    pub(crate) other: Option<GraspSolver>,
    /// Whether the bracket's failing end is probed for another equilibrium
    /// ([`crate::MarginOptions::probe_equilibria`]).
    pub(crate) probe_equilibria: bool,
}

/// A magnitude known to hold, N, with the contact state and solution there.
pub(crate) struct Held {
    pub(crate) s: f64,
    pub(crate) state: ContactState,
    pub(crate) sol: Solution,
}

/// The smallest magnitude known to fail, N, and how.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Fails {
    /// The magnitude, N.
    pub(crate) s: f64,
    /// How the grasp failed there.
    pub(crate) failure: Failure,
}

/// What a trial found.
pub(crate) enum Trial {
    /// The grasp holds at the magnitude.
    Holds(Held),
    /// It fails at `fails.s`: the magnitude, or a step of the ramp below it. `below`: the
    /// ramp's last magnitude that held above the trial's start, if any.
    Fails { fails: Fails, below: Option<Held> },
    /// Neither solver converged at `at_n` (the magnitude or a step of the ramp below it):
    /// whether the grasp holds there is not known. `below` as for `Fails`.
    Stalls {
        at_n: f64,
        reason: String,
        below: Option<Held>,
    },
}

/// One step's verdict (short-lived: the state and solution move on into a [`Held`] at once,
/// so the variants' sizes do not matter).
#[allow(clippy::large_enum_variant)]
enum Step {
    Holds(ContactState, Solution),
    Fails(Failure),
    Stalls(String),
}

impl Search<'_> {
    /// The step's inputs with the disturbance of magnitude `s` (N) along the direction: a
    /// force at the centre of mass and a couple.
    pub(crate) fn inputs_at(&self, s: f64) -> StepInputs {
        let d = &self.direction;
        let f = Vector3::from(d.force) * s;
        let t = Vector3::from(d.torque) * (s * self.length_m);
        self.inputs
            .clone()
            .with_load_at_center_of_mass(self.model, &f, &t)
    }

    /// The grasp at magnitude `s` (N), ramped from `from` (see the module).
    pub(crate) fn trial(&mut self, s: f64, from: &Held) -> Result<Trial, ModelError> {
        let mut below: Option<Held> = None;
        for p in self.ramp(from.s, s) {
            let start = below.as_ref().map_or(&from.state, |h| &h.state);
            match self.step(p, start)? {
                Step::Holds(state, sol) => below = Some(Held { s: p, state, sol }),
                Step::Fails(failure) => {
                    let fails = Fails { s: p, failure };
                    return Ok(Trial::Fails { fails, below });
                }
                Step::Stalls(reason) => {
                    return Ok(Trial::Stalls {
                        at_n: p,
                        reason,
                        below,
                    })
                }
            }
        }
        Ok(match below {
            Some(held) => Trial::Holds(held),
            None => Trial::Stalls {
                at_n: s,
                reason: "no ramp step was taken".into(),
                below: None,
            },
        })
    }

    /// The magnitudes of the ramp from `from` N to `s` N, ascending, `s` last: `s` alone
    /// unless the model remembers slip; else `s` halved until a step from `from` at most
    /// doubles it (plus [`INITIAL_STEP`] of the load scale).
    pub(crate) fn ramp(&self, from: f64, s: f64) -> Vec<f64> {
        let mut points = vec![s];
        if self.model.kind() != ModelKind::Coulomb {
            return points;
        }
        let reach = (RAMP_RATIO * from + INITIAL_STEP * self.load_n) * (1.0 + 1e-9);
        let mut p = s;
        while p > reach && points.len() < MAX_RAMP_STEPS {
            p /= RAMP_RATIO;
            points.push(p);
        }
        points.reverse();
        points
    }

    /// One quasi-static step to magnitude `s` (N) from `state`, by the other solver when the
    /// chosen one does not converge.
    fn step(&mut self, s: f64, state: &ContactState) -> Result<Step, ModelError> {
        if s >= self.capacity_n {
            return Ok(Step::Fails(self.beyond_capacity(s)));
        }
        let inputs = self.inputs_at(s);
        let mut next = state.clone();
        self.start_from_guess(s, &mut next);
        let mut sol = self.solver.solve_step(&inputs, &mut next)?;
        self.solves += 1;
        if sol.status == SolveStatus::NoConvergence {
            if let Some((again, other_sol)) = self.solve_with_other(&inputs, state, &sol)? {
                (next, sol) = (again, other_sol);
            }
        }
        if self.guessing && sol.status.has_forces() {
            let forces = sol.fingers.iter();
            let forces = forces.map(|f| f.elements.iter().map(|e| e.normal_force_n).collect());
            self.trial_forces.push(s, forces.collect());
        }
        Ok(match holds(self.model, &sol, self.exempt) {
            Ok(()) => {
                self.note_held(s, &sol);
                Step::Holds(next, sol)
            }
            Err(Failure::NoConvergence { reason }) => Step::Stalls(reason),
            Err(failure) => Step::Fails(failure),
        })
    }

    /// The step of `inputs` from `state` solved by the solver other than the chosen one, whose
    /// solution `stalled` did not converge (Clarabel for `auto`, whose native solve may end on an
    /// answer that fails its own checks without trying Clarabel).
    /// When the other does not converge either, its solution says why both did not.
    fn solve_with_other(
        &mut self,
        inputs: &StepInputs,
        state: &ContactState,
        stalled: &Solution,
    ) -> Result<Option<(ContactState, Solution)>, ModelError> {
        let mut options = *self.solver.options();
        options.solver = options.solver.other();
        let model = Arc::clone(self.solver.shared_model());
        let other = self
            .other
            .get_or_insert_with(|| GraspSolver::new(model, options));
        let mut next = state.clone();
        let mut sol = other.solve_step(inputs, &mut next)?;
        self.solves += 1;
        if sol.status == SolveStatus::NoConvergence {
            let why = |s: &Solution| s.reason.clone().unwrap_or_default();
            sol.reason = Some(format!(
                "neither solver converged: {} ({}); {} ({})",
                self.solver.options().solver,
                why(stalled),
                options.solver,
                why(&sol)
            ));
        } else {
            self.fallbacks += 1;
        }
        Ok(Some((next, sol)))
    }

    /// The next trial in the bracket `(lo, hi)` N when guided: half a tolerance above where
    /// sliding is predicted ([`Search::sliding_predicted_at`]), at least a tolerance above `lo`
    /// (so that a failure there closes the bracket) and at most twice `lo` (the line through
    /// two magnitudes far below the margin says little); a tolerance below `hi` when the
    /// prediction is at or beyond `hi`, which failed (a line through magnitudes that held
    /// reaches 1 late where the utilisation bends up), so that holding there closes the
    /// bracket; `None` when that is not inside it.
    pub(crate) fn guided_point(&self, lo: f64, hi: f64, tolerance: f64) -> Option<f64> {
        let root = self.sliding_predicted_at()?;
        let t = (root * (1.0 + 0.5 * tolerance)).max(lo * (1.0 + CHECK_STEP * tolerance));
        let t = if t >= hi {
            hi * (1.0 - CHECK_STEP * tolerance)
        } else {
            t.min(2.0 * lo)
        };
        (t > lo && t < hi).then_some(t)
    }

    /// Records the utilisation at `s` N, where `sol` held (when guided, in a planar scene:
    /// in 3-D a finger's elements can slide in different directions, its utilisation stays
    /// below 1, and guided trials land at the edge where solves cost more; on the MuJoCo
    /// hand-off, 3-D, they cost half as much again, for no fewer solves).
    pub(crate) fn note_held(&mut self, s: f64, sol: &Solution) {
        let guided = self.guessing && self.model.plane().is_some();
        if let Some(u) = utilisation_of(self.model, sol, self.exempt).filter(|_| guided) {
            self.utilisation.push((s, u));
        }
    }

    /// Where the line through the utilisation at the two largest magnitudes that held reaches
    /// 1, the utilisation of a finger sliding as a whole in the plane (a guess in 3-D, where
    /// slip directions can differ); `None` unless guided, with two such magnitudes, the
    /// utilisation rising between them, and the root beyond them.
    pub(crate) fn sliding_predicted_at(&self) -> Option<f64> {
        let mut top = self.utilisation.iter().filter(|p| p.0 > 0.0 || p.1 > 0.0);
        let first = top.next()?;
        let (a, b) = top.fold((first, first), |(a, b), p| {
            if p.0 > b.0 {
                (b, p)
            } else if p.0 > a.0 && p.0 < b.0 {
                (p, b)
            } else {
                (a, b)
            }
        });
        let rise = (b.1 - a.1) / (b.0 - a.0);
        let root = b.0 + (1.0 - b.1) / rise;
        (b.0 > a.0 && rise > 0.0 && root.is_finite() && root > b.0).then_some(root)
    }

    /// Puts the forces [`Search::trial_forces`] predicts at magnitude `s` (N) into `state`
    /// as its last forces, the sequential solve's first input (the start only: its slip
    /// memory, which sets the answer, stays).
    fn start_from_guess(&self, s: f64, state: &mut ContactState) {
        let Some(guess) = self.trial_forces.at(s).filter(|_| self.guessing) else {
            return;
        };
        for (f, g) in state.fingers.iter_mut().zip(guess) {
            if f.normal_forces_n
                .as_ref()
                .is_some_and(|v| v.len() == g.len())
            {
                f.normal_forces_n = Some(g);
            }
        }
    }

    /// The failure of a trial at `s` N at or beyond the load capacity.
    fn beyond_capacity(&self, s: f64) -> Failure {
        Failure::NoEquilibrium {
            reason: format!(
                "no equilibrium: no contact forces within the friction cones balance {} N \
                 along this direction (the contacts resist at most {} N along it with the \
                 commanded loads)",
                Readable(s),
                Readable(self.capacity_n)
            ),
        }
    }

    /// A certificate of the load capacity along the direction at this step, searched up to
    /// `cap_n` N (`None`: none sought or found, see [`LoadCapacity::find`]).
    pub(crate) fn find_capacity(&self, cap_n: f64) -> Option<LoadCapacity> {
        LoadCapacity::find(self.model, self.inputs, &self.per_newton(), cap_n)
    }

    /// Takes the capacity that `certificate` proves at this step.
    pub(crate) fn bound_by(&mut self, certificate: &mut LoadCapacity) {
        self.capacity_n = certificate.bound_n(self.model, self.inputs, &self.per_newton());
    }

    /// The disturbance per newton of magnitude: force (N) and couple (N m).
    pub(crate) fn per_newton(&self) -> UnitDisturbance {
        let d = &self.direction;
        UnitDisturbance {
            force_n: Vector3::from(d.force),
            torque_nm: Vector3::from(d.torque) * self.length_m,
        }
    }
}

/// A guided trial's least step above the largest magnitude that held, as a fraction of the
/// tolerance: a failure there leaves a bracket within the tolerance.
pub(crate) const CHECK_STEP: f64 = 0.99;
