//! The search of the disturbance margins ([`super::margin_report`] defines them and what
//! holding means).
//!
//! Search: the disturbance grows monotonically along the direction, each trial one
//! quasi-static step from the state at the last magnitude that held (so the coulomb model's
//! slip memory follows the loading path) and warm-started from its solution; the step doubles
//! from the load scale until the grasp fails (or the magnitude passes
//! [`MarginOptions::max_factor`] times the load scale: unbounded), then bisection narrows the
//! bracket to [`MarginOptions::relative_tolerance`]. Directions run in parallel; each is
//! deterministic.
//!
//! No trial is solved at or beyond the direction's load capacity
//! ([`crate::analysis::load_capacity`]), the magnitude from which no contact forces within the
//! friction cones balance the load: a proof that no model holds there replaces the solves that
//! would stall at the edge of equilibrium. The growth stops at the capacity, and a bracket
//! ending there is probed first just below it ([`CAPACITY_PROBE`]). Where no capacity is
//! sought (a fine patch, a load-dependent friction coefficient, a held finger the proof cannot
//! bound) the search is as above.

use std::sync::Arc;
use std::time::Instant;

use nalgebra::Vector3;

use crate::analysis::load_capacity::{LoadCapacity, UnitDisturbance};
use crate::analysis::margin_report::{
    failing_undisturbed, holds, most_utilised, sliding_fingers, utilisation_of, DirectionMargin,
    Failure, MarginOptions, MarginReport,
};
use crate::analysis::trial_forces::TrialForces;
use crate::analysis::wrench_directions::WrenchDirection;
use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::number_text::Readable;
use crate::scene::scene_format::ModelKind;
use crate::solve::contact_state::ContactState;
use crate::solve::grasp_solver::GraspSolver;
use crate::solve::solution::Solution;
use crate::solve::step_inputs::StepInputs;
use crate::solver::options::SolveOptions;

/// First growth step of the search, as a fraction of the load scale: small, because a trial
/// that holds is cheap (a warm-started step) and one that fails is not (the solver must certify
/// that no equilibrium exists), so the search should fail as few times as it can.
pub(crate) const INITIAL_STEP: f64 = 1e-2;

/// Below this fraction of the load scale a margin counts as zero: the bisection stops (the
/// solves themselves balance the load only to about 1e-10 of it).
pub(crate) const ZERO_MARGIN: f64 = 1e-6;

/// Largest number of growth steps along one direction (the step doubles from
/// [`INITIAL_STEP`]: 27 reach the largest cap).
const MAX_GROWTH_STEPS: u32 = 200;

/// Largest number of bisection steps along one direction (geometric, then arithmetic: about
/// 35 narrow the widest bracket to the finest tolerance).
const MAX_BISECTION_STEPS: u32 = 200;

/// Where a bracket whose upper end is the load capacity `c` is probed first, as a fraction of
/// the tolerance below it: `c (1 - 0.9 tol)`. When the grasp holds there (the margin is the
/// capacity, as where the fingers can only all slip together), the bracket is done in one solve.
pub(crate) const CAPACITY_PROBE: f64 = 0.9;

/// A guided trial's least step above the largest magnitude that held, as a fraction of the
/// tolerance: a failure there leaves a bracket within the tolerance.
pub(crate) const CHECK_STEP: f64 = 0.99;

/// The search along one direction.
pub(crate) struct Search<'a> {
    pub(crate) model: &'a GraspModel,
    pub(crate) inputs: &'a StepInputs,
    pub(crate) solver: &'a mut GraspSolver,
    pub(crate) direction: WrenchDirection,
    pub(crate) length_m: f64,
    pub(crate) solves: u32,
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
}

/// The largest magnitude known to hold, N, with the contact state and solution there.
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

impl Search<'_> {
    /// The step's inputs with the disturbance of magnitude `s` (N) along the direction: a
    /// force at the centre of mass and a couple.
    fn inputs_at(&self, s: f64) -> StepInputs {
        let d = &self.direction;
        let f = Vector3::from(d.force) * s;
        let t = Vector3::from(d.torque) * (s * self.length_m);
        self.inputs
            .clone()
            .with_load_at_center_of_mass(self.model, &f, &t)
    }

    /// One quasi-static step to magnitude `s` from `state`.
    pub(crate) fn trial(
        &mut self,
        s: f64,
        state: &ContactState,
    ) -> Result<Result<(ContactState, Solution), Failure>, ModelError> {
        if s >= self.capacity_n {
            return Ok(Err(self.beyond_capacity(s)));
        }
        let inputs = self.inputs_at(s);
        let mut next = state.clone();
        self.start_from_guess(s, &mut next);
        let sol = self.solver.solve_step(&inputs, &mut next)?;
        self.solves += 1;
        if self.guessing && sol.status.has_forces() {
            let forces = sol.fingers.iter();
            let forces = forces.map(|f| f.elements.iter().map(|e| e.normal_force_n).collect());
            self.trial_forces.push(s, forces.collect());
        }
        let held = holds(self.model, &sol, self.exempt);
        if held.is_ok() {
            self.note_held(s, &sol);
        }
        Ok(held.map(|()| (next, sol)))
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

    /// Grows the magnitude from `held` (the step doubling from [`INITIAL_STEP`] of the load
    /// scale) until the grasp fails (`Some`) or holds at `cap` (`None`); the note says why it
    /// stopped below the cap when it did.
    pub(crate) fn grow(
        &mut self,
        held: &mut Held,
        cap: f64,
    ) -> Result<(Option<Fails>, Option<String>), ModelError> {
        let mut step = INITIAL_STEP * self.model.scales.load_n;
        for _ in 0..MAX_GROWTH_STEPS {
            if held.s >= cap || cap.is_nan() {
                return Ok((None, None));
            }
            let s = (held.s + step).min(cap).min(self.capacity_n);
            match self.trial(s, &held.state)? {
                Ok((state, sol)) => (*held, step) = (Held { s, state, sol }, 2.0 * step),
                Err(f) => return Ok((Some(Fails { s, failure: f }), None)),
            }
        }
        let note = format!(
            "the growth stopped after {MAX_GROWTH_STEPS} steps at {} N, below the cap {} N",
            Readable(held.s),
            Readable(cap)
        );
        Ok((None, Some(note)))
    }

    /// A trial at `s` (N) from `held`'s state: the bracket's lower end moves up to it when the
    /// grasp holds there, its upper end down to it when it fails.
    fn probe(&mut self, s: f64, held: &mut Held, fails: &mut Fails) -> Result<(), ModelError> {
        match self.trial(s, &held.state)? {
            Ok((state, sol)) => *held = Held { s, state, sol },
            Err(failure) => *fails = Fails { s, failure },
        }
        Ok(())
    }

    /// Narrows the bracket `(held, fails)` by bisection to `tolerance` of its upper end (or
    /// below [`ZERO_MARGIN`] of the load scale); the note says why it stopped wider, when it
    /// did.
    pub(crate) fn narrow(
        &mut self,
        held: &mut Held,
        fails: &mut Fails,
        tolerance: f64,
    ) -> Result<Option<String>, ModelError> {
        let zero = ZERO_MARGIN * self.model.scales.load_n;
        // Failed at the capacity without a solve: the margin is most often just below it.
        let below = self.capacity_n * (1.0 - CAPACITY_PROBE * tolerance);
        if fails.s >= self.capacity_n && held.s < below && below > zero {
            self.probe(below, held, fails)?;
        }
        // Failed at the first step: is the direction resisted at all? (One solve, not a
        // bisection down to zero: commanded loads leave some directions unresisted.)
        if held.s == 0.0 {
            self.probe(zero, held, fails)?;
        }
        let (mut steps, mut bisect) = (0, false);
        while fails.s - held.s > tolerance * fails.s && fails.s > zero {
            let width = fails.s - held.s;
            let guided = self
                .guided_point(held.s, fails.s, tolerance)
                .filter(|_| !bisect);
            // Geometric while the bracket spans more than a factor 2, then arithmetic.
            let mid = if let Some(t) = guided {
                t
            } else if held.s > 0.0 && fails.s > 2.0 * held.s {
                (held.s * fails.s).sqrt()
            } else {
                0.5 * (held.s + fails.s)
            };
            let why = if !(mid > held.s && mid < fails.s) {
                "no number lies between its ends in double precision".to_string()
            } else if steps == MAX_BISECTION_STEPS {
                format!("the bisection stopped after {MAX_BISECTION_STEPS} steps")
            } else {
                steps += 1;
                self.probe(mid, held, fails)?;
                // A guided trial that did not halve the bracket is followed by a bisection.
                bisect = guided.is_some() && fails.s - held.s > 0.5 * width;
                continue;
            };
            return Ok(Some(format!(
                "the bracket [{}, {}] N (relative width {:.1e}) was not narrowed to the \
                 tolerance {}: {why}",
                Readable(held.s),
                Readable(fails.s),
                (fails.s - held.s) / fails.s,
                Readable(tolerance)
            )));
        }
        Ok(None)
    }
}

/// A step's undisturbed solve: the contact state it left (before time moves on:
/// [`ContactState::advance_time_step`]) and its solution. Every direction's search starts
/// there.
#[derive(Debug, Clone, Copy)]
pub struct SolvedStep<'a> {
    /// The contact state after the solve.
    pub state: &'a ContactState,
    /// The solution.
    pub solution: &'a Solution,
}

/// What the searches of every direction of one step share: the grasp and its inputs, its
/// undisturbed solve, and how to search.
#[derive(Clone, Copy)]
pub(crate) struct StepSearch<'a> {
    /// The grasp.
    pub model: &'a Arc<GraspModel>,
    /// Its inputs (loads, extra wrench, approaches, time step).
    pub inputs: &'a StepInputs,
    /// Its undisturbed solve.
    pub solved: SolvedStep<'a>,
    /// The options of every trial's solve.
    pub solve_options: SolveOptions,
    /// The margins' options.
    pub options: &'a MarginOptions,
    /// The characteristic length `L`, m.
    pub length_m: f64,
    /// The fingers that already slide undisturbed (not judged by sliding).
    pub exempt: &'a [String],
}

/// The margin along `direction` of the step `step`, searched from scratch.
fn along(step: &StepSearch, direction: WrenchDirection) -> Result<DirectionMargin, ModelError> {
    let clock = Instant::now();
    let (model, options) = (step.model, step.options);
    let mut solver = GraspSolver::new(Arc::clone(model), step.solve_options);
    let mut search = Search {
        model: model.as_ref(),
        inputs: step.inputs,
        solver: &mut solver,
        direction,
        length_m: step.length_m,
        solves: 0,
        exempt: step.exempt,
        capacity_n: f64::INFINITY,
        trial_forces: TrialForces::default(),
        guessing: false,
        utilisation: Vec::new(),
    };
    let cap = options.max_factor * model.scales.load_n;
    if let Some(mut certificate) = options
        .load_capacity
        .then(|| search.find_capacity(cap))
        .flatten()
    {
        search.bound_by(&mut certificate);
    }
    let mut held = Held {
        s: 0.0,
        state: step.solved.state.clone(),
        sol: step.solved.solution.clone(),
    };
    let (mut hi, mut stopped_early) = search.grow(&mut held, cap)?;
    if let Some(fails) = &mut hi {
        stopped_early = search.narrow(&mut held, fails, options.relative_tolerance)?;
    }
    Ok(search.finish(held, hi, stopped_early, clock))
}

impl Search<'_> {
    /// The margin of a finished search: `held` the largest magnitude found to hold, `hi` the
    /// smallest found to fail (`None`: held at the cap), `stopped_early` why the bracket is
    /// wider than asked, `clock` started with the search.
    pub(crate) fn finish(
        &self,
        held: Held,
        hi: Option<Fails>,
        stopped_early: Option<String>,
        clock: Instant,
    ) -> DirectionMargin {
        let lo = held.s;
        let failing_finger = match &hi {
            Some(Fails {
                failure: Failure::Slides { finger },
                ..
            }) => Some(finger.clone()),
            Some(_) => most_utilised(self.model, &held.sol),
            None => None,
        };
        let direction = self.direction;
        DirectionMargin {
            direction,
            margin_n: lo,
            fails_at_n: hi.as_ref().map(|h| h.s),
            force_n: direction.force.map(|v| v * lo),
            torque_nm: direction.torque.map(|v| v * lo * self.length_m),
            bounded: hi.is_some(),
            failing_finger,
            failure: hi.map(|h| h.failure),
            solves: self.solves,
            time_s: clock.elapsed().as_secs_f64(),
            stopped_early,
            warnings: held
                .sol
                .warnings
                .into_iter()
                .filter(|w| !self.model.scene_warnings().contains(w))
                .collect(),
        }
    }
}

/// The margins of `model` under `inputs` (its loads, extra wrench and approaches) along
/// `directions`, starting from `state` (a fresh [`ContactState`] for a single grasp; a hand-off
/// step's state to continue its path). If the grasp does not hold undisturbed every margin is 0 with that failure. Options
/// outside their ranges are an error ([`MarginOptions::validate`],
/// [`SolveOptions::validate`]).
pub fn disturbance_margins(
    model: &Arc<GraspModel>,
    inputs: &StepInputs,
    state: &ContactState,
    solve_options: SolveOptions,
    directions: &[WrenchDirection],
    options: &MarginOptions,
) -> Result<MarginReport, ModelError> {
    let quiet = |_: usize| {};
    disturbance_margins_reporting(
        model,
        inputs,
        state,
        solve_options,
        directions,
        options,
        &quiet,
    )
}

/// [`disturbance_margins`], calling `done(k)` from the worker threads as each direction's
/// search ends (`k` directions done so far), for a progress bar.
pub fn disturbance_margins_reporting(
    model: &Arc<GraspModel>,
    inputs: &StepInputs,
    state: &ContactState,
    solve_options: SolveOptions,
    directions: &[WrenchDirection],
    options: &MarginOptions,
    done: &(dyn Fn(usize) + Sync),
) -> Result<MarginReport, ModelError> {
    use rayon::prelude::*;
    let finished = std::sync::atomic::AtomicUsize::new(0);
    solve_options.validate()?;
    options.validate()?;
    let clock = Instant::now();
    let length_m = options.length_m.unwrap_or(model.scales.length_m);
    let mut base_state = state.clone();
    let base =
        GraspSolver::new(Arc::clone(model), solve_options).solve_step(inputs, &mut base_state)?;
    let sliding_undisturbed = match model.kind() {
        ModelKind::Coulomb if base.status.has_forces() => sliding_fingers(&base),
        _ => Vec::new(),
    };
    let margins: Vec<DirectionMargin> = match holds(model, &base, &sliding_undisturbed) {
        Err(f) => directions
            .iter()
            .map(|&d| failing_undisturbed(d, &f))
            .collect(),
        Ok(()) => {
            let step = StepSearch {
                model,
                inputs,
                solved: SolvedStep {
                    state: &base_state,
                    solution: &base,
                },
                solve_options,
                options,
                length_m,
                exempt: &sliding_undisturbed,
            };
            directions
                .par_iter()
                .map(|&d| {
                    let m = along(&step, d);
                    done(finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
                    m
                })
                .collect::<Result<_, _>>()?
        }
    };
    let mut report = MarginReport::of(model, length_m, sliding_undisturbed, margins, clock);
    report.warnings = base.warnings;
    Ok(report)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::option_names;

    /// A block pinched along x by two flat steel pads (commanded load 10 N each, mu 0.5),
    /// weight 4 N: downwards it takes `2 mu P - W = 6 N` more (the pads' friction capacity).
    pub(crate) fn pinch() -> Arc<GraspModel> {
        let finger = |name: &str, x: f64, nx: f64| {
            serde_json::json!({
                "name": name, "contact_point": [x, 0.0, 0.0], "normal": [nx, 0.0, 0.0],
                "tangent": [0.0, 1.0, 0.0],
                "material": {"youngs_modulus": 210e9, "poisson_ratio": 0.3},
                "patch": {"size": [0.01, 0.01], "grid": [3, 3]},
                "friction": {"mu": 0.5}, "control": {"normal_load": 10.0}
            })
        };
        let scene = serde_json::json!({
            "object": {"weight": 4.0, "center_of_mass": [0.0, 0.0, 0.0],
                       "material": {"youngs_modulus": 210e9, "poisson_ratio": 0.3}},
            "fingers": [finger("left", -0.02, 1.0), finger("right", 0.02, -1.0)],
            "model": "energy"
        });
        let scene = crate::Scene::from_json_str(&scene.to_string()).unwrap();
        Arc::new(GraspModel::from_scene(&scene).unwrap())
    }

    pub(crate) const DOWN: WrenchDirection = WrenchDirection {
        force: [0.0, 0.0, -1.0],
        torque: [0.0; 3],
    };

    /// A tolerance no double-precision bracket can meet (reachable only by bypassing
    /// `validate`, as a library caller could): the bisection stops where no number lies
    /// between the bracket's ends, says so, and the bracket still holds the closed form
    /// 6 N (to 1e-9 relative: the solver tolerance). Bounded: at most the growth and
    /// bisection limits in solves.
    #[test]
    fn a_bisection_that_cannot_reach_its_tolerance_stops_and_says_so() {
        let model = pinch();
        let mut base_state = ContactState::new(&model);
        let solve = SolveOptions::default();
        let inputs = StepInputs::of_scene(&model);
        let base = GraspSolver::new(Arc::clone(&model), solve)
            .solve_step(&inputs, &mut base_state)
            .unwrap();
        for tolerance in [1e-300, 0.0, 1e-17] {
            let options = MarginOptions {
                relative_tolerance: tolerance,
                ..MarginOptions::default()
            };
            let step = StepSearch {
                model: &model,
                inputs: &inputs,
                solved: SolvedStep {
                    state: &base_state,
                    solution: &base,
                },
                solve_options: solve,
                options: &options,
                length_m: 0.05,
                exempt: &[],
            };
            let m = along(&step, DOWN).unwrap();
            let note = m
                .stopped_early
                .as_deref()
                .unwrap_or_else(|| panic!("no note at {tolerance:e}: {m:?}"));
            assert!(note.contains("not narrowed to the tolerance"), "{note}");
            let hi = m.fails_at_n.unwrap();
            assert!(
                m.margin_n <= 6.0 * (1.0 + 1e-9) && hi >= 6.0 * (1.0 - 1e-9),
                "{m:?}"
            );
            assert!((hi - m.margin_n) <= 1e-9 * 6.0, "{m:?}");
            assert!(
                m.solves <= MAX_GROWTH_STEPS + MAX_BISECTION_STEPS + 1,
                "{m:?}"
            );
        }
    }

    /// At a valid tolerance the search does not stop early and brackets the closed form.
    #[test]
    fn a_reachable_tolerance_leaves_no_note() {
        let model = pinch();
        let r = disturbance_margins(
            &model,
            &StepInputs::of_scene(&model),
            &ContactState::new(&model),
            SolveOptions::default(),
            &[DOWN],
            &MarginOptions::default(),
        )
        .unwrap();
        let m = &r.directions[0];
        assert_eq!(m.stopped_early, None);
        assert!(m.margin_n <= 6.0 * (1.0 + 1e-9) && m.fails_at_n.unwrap() >= 6.0 * (1.0 - 1e-9));
    }

    /// Options outside their ranges are refused by name before any solve; a direction that
    /// is not finite is an outcome of the search (no convergence), not a panic.
    #[test]
    fn bad_options_are_errors_and_bad_directions_are_outcomes() {
        let model = pinch();
        let state = ContactState::new(&model);
        let cases = [
            (
                MarginOptions {
                    length_m: Some(1e305),
                    ..MarginOptions::default()
                },
                option_names::MARGIN_LENGTH,
            ),
            (
                MarginOptions {
                    relative_tolerance: 2e-16,
                    ..MarginOptions::default()
                },
                option_names::MARGIN_TOLERANCE,
            ),
            (
                MarginOptions {
                    max_factor: f64::INFINITY,
                    ..MarginOptions::default()
                },
                option_names::MARGIN_MAX_FACTOR,
            ),
        ];
        for (options, name) in cases {
            let e = disturbance_margins(
                &model,
                &StepInputs::of_scene(&model),
                &state,
                SolveOptions::default(),
                &[DOWN],
                &options,
            )
            .unwrap_err();
            match e {
                ModelError::Option(o) => assert_eq!(o.option, name),
                other => panic!("{other}"),
            }
        }
        let nan = WrenchDirection {
            force: [f64::NAN, 0.0, 0.0],
            torque: [0.0; 3],
        };
        let r = disturbance_margins(
            &model,
            &StepInputs::of_scene(&model),
            &state,
            SolveOptions::default(),
            &[nan],
            &MarginOptions::default(),
        )
        .unwrap();
        assert!(
            matches!(r.directions[0].failure, Some(Failure::NoConvergence { .. })),
            "{:?}",
            r.directions[0]
        );
    }
}
