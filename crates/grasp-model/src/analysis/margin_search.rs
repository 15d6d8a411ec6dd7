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

use crate::analysis::margin_report::{
    failing_undisturbed, holds, most_utilised, sliding_fingers, DirectionMargin, Failure,
    MarginOptions, MarginReport,
};
use crate::analysis::margin_trial::{Fails, Held, Search, Trial, INITIAL_STEP, ZERO_MARGIN};
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

/// How a search along a direction ended above the largest magnitude that held.
pub(crate) enum End {
    /// At a magnitude that fails: the bracket's upper end.
    Fails(Fails),
    /// The grasp held at the cap: unbounded.
    Cap,
    /// Nothing is known above: why (neither solver converged, the growth's step limit).
    Undetermined(String),
}

/// A finished search: the largest magnitude found to hold, how it ended above it, and why the
/// bracket is wider than asked, when it is.
pub(crate) struct Found {
    pub(crate) held: Held,
    pub(crate) end: End,
    pub(crate) note: Option<String>,
}

impl End {
    /// The end of a trial above `held` that did not hold, `held` moved up to the ramp's last
    /// magnitude that held; `None` when the trial held (`held` moved to it).
    pub(crate) fn of_trial(trial: Trial, held: &mut Held) -> Option<End> {
        match trial {
            Trial::Holds(h) => {
                *held = h;
                None
            }
            Trial::Fails { fails, below } => {
                if let Some(b) = below {
                    *held = b;
                }
                Some(End::Fails(fails))
            }
            Trial::Stalls {
                at_n,
                reason,
                below,
            } => {
                if let Some(b) = below {
                    *held = b;
                }
                Some(End::Undetermined(stall_note(at_n, &reason)))
            }
        }
    }
}

/// What an undetermined margin says of a stall at `at_n` N.
pub(crate) fn stall_note(at_n: f64, reason: &str) -> String {
    format!("no answer at {} N: {reason}", Readable(at_n))
}

impl Search<'_> {
    /// Grows the magnitude from `held` (the step doubling from [`INITIAL_STEP`] of the load
    /// scale) until the grasp fails, holds at `cap`, or no solver answers.
    pub(crate) fn grow(&mut self, held: &mut Held, cap: f64) -> Result<End, ModelError> {
        let mut step = INITIAL_STEP * self.load_n;
        for _ in 0..MAX_GROWTH_STEPS {
            if held.s >= cap || cap.is_nan() {
                return Ok(End::Cap);
            }
            let s = (held.s + step).min(cap).min(self.capacity_n);
            let trial = self.trial(s, held)?;
            if let Some(end) = End::of_trial(trial, held) {
                return Ok(end);
            }
            step *= 2.0;
        }
        Ok(End::Undetermined(format!(
            "the growth stopped after {MAX_GROWTH_STEPS} steps at {} N, below the cap {} N",
            Readable(held.s),
            Readable(cap)
        )))
    }

    /// A trial at `s` (N) from `held`'s state: the bracket's lower end moves up to it (or the
    /// ramp's last magnitude that held) when the grasp holds there, its upper end down to it
    /// when it fails; `Some(why)` when neither solver answered.
    fn probe(
        &mut self,
        s: f64,
        held: &mut Held,
        fails: &mut Fails,
    ) -> Result<Option<String>, ModelError> {
        Ok(match End::of_trial(self.trial(s, held)?, held) {
            Some(End::Fails(f)) => {
                *fails = f;
                None
            }
            Some(End::Undetermined(why)) => Some(why),
            Some(End::Cap) | None => None,
        })
    }

    /// Narrows the bracket `(held, fails)` by bisection to `tolerance` of its upper end (or
    /// below [`ZERO_MARGIN`] of the load scale); the note says why it stopped wider, when it
    /// did (a step limit, double precision, or a magnitude no solver answered at: the bracket
    /// is a true one still).
    pub(crate) fn narrow(
        &mut self,
        held: &mut Held,
        fails: &mut Fails,
        tolerance: f64,
    ) -> Result<Option<String>, ModelError> {
        let zero = ZERO_MARGIN * self.load_n;
        // The bisection's upper end: where it fails, or lower, a magnitude no solver answered
        // at (whether it holds there is not known, so the bisection goes on below it).
        let mut upper = Upper::at(fails.s);
        // Failed at the capacity without a solve: the margin is most often just below it.
        let below = self.capacity_n * (1.0 - CAPACITY_PROBE * tolerance);
        if fails.s >= self.capacity_n && held.s < below && below > zero {
            upper.probed(below, self.probe(below, held, fails)?, fails);
        }
        // Failed at the first step: is the direction resisted at all? (One solve, not a
        // bisection down to zero: commanded loads leave some directions unresisted.)
        if held.s == 0.0 && upper.stall.is_none() {
            upper.probed(zero, self.probe(zero, held, fails)?, fails);
        }
        let (mut steps, mut bisect) = (0, false);
        while upper.s - held.s > tolerance * upper.s && upper.s > zero {
            let width = upper.s - held.s;
            let guided = self
                .guided_point(held.s, upper.s, tolerance)
                .filter(|_| !bisect);
            // Geometric while the bracket spans more than a factor 2, then arithmetic.
            let mid = if let Some(t) = guided {
                t
            } else if held.s > 0.0 && upper.s > 2.0 * held.s {
                (held.s * upper.s).sqrt()
            } else {
                0.5 * (held.s + upper.s)
            };
            let why = if !(mid > held.s && mid < upper.s) {
                "no number lies between its ends in double precision".to_string()
            } else if steps == MAX_BISECTION_STEPS {
                format!("the bisection stopped after {MAX_BISECTION_STEPS} steps")
            } else {
                steps += 1;
                upper.probed(mid, self.probe(mid, held, fails)?, fails);
                // A guided trial that did not halve the bracket is followed by a bisection.
                bisect = guided.is_some() && upper.s - held.s > 0.5 * width;
                continue;
            };
            return Ok(Some(format!(
                "the bracket [{}, {}] N (relative width {:.1e}) was not narrowed to the \
                 tolerance {}: {why}",
                Readable(held.s),
                Readable(upper.s),
                (upper.s - held.s) / upper.s,
                Readable(tolerance)
            )));
        }
        Ok(upper.stall.filter(|_| upper.s < fails.s).map(|(at, why)| {
            format!(
                "no solver answered at {} N ({why}), between the margin and {} N where the \
                 grasp fails: the margin was narrowed below it, and is the largest magnitude \
                 known to hold",
                Readable(at),
                Readable(fails.s)
            )
        }))
    }
}

/// The upper end of a bisection: the smallest magnitude found to fail, or a smaller one at
/// which no solver answered (the first such, with why).
struct Upper {
    s: f64,
    stall: Option<(f64, String)>,
}

impl Upper {
    fn at(fails_n: f64) -> Upper {
        Upper {
            s: fails_n,
            stall: None,
        }
    }

    /// After a probe at `s` N: lowered to where it fails, or to `s` when no solver answered.
    fn probed(&mut self, s: f64, stalled: Option<String>, fails: &Fails) {
        self.s = self.s.min(fails.s);
        if let Some(why) = stalled {
            self.s = self.s.min(s);
            self.stall.get_or_insert((s, why));
        }
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
    /// The fingers that already slide undisturbed (not judged by sliding).
    pub exempt: &'a [String],
}

impl<'a> StepSearch<'a> {
    /// A search along `direction` with `solver` (fresh for the search from scratch; the
    /// direction's own, warm, when `guessing`: see [`Search::guessing`]).
    pub(crate) fn search<'s>(
        &self,
        solver: &'s mut GraspSolver,
        direction: WrenchDirection,
        guessing: bool,
    ) -> Search<'s>
    where
        'a: 's,
    {
        Search {
            model: self.model.as_ref(),
            inputs: self.inputs,
            solver,
            direction,
            length_m: self.options.length_for(self.model),
            load_n: self.options.load_scale_for(self.model),
            solves: 0,
            fallbacks: 0,
            exempt: self.exempt,
            capacity_n: f64::INFINITY,
            trial_forces: TrialForces::default(),
            guessing,
            utilisation: Vec::new(),
            other: None,
            probe_equilibria: self.options.probe_equilibria,
        }
    }

    /// The undisturbed state and solution, the magnitude 0 of every search.
    pub(crate) fn base(&self) -> Held {
        Held {
            s: 0.0,
            state: self.solved.state.clone(),
            sol: self.solved.solution.clone(),
        }
    }

    /// The cap of the searches, N.
    pub(crate) fn cap_n(&self) -> f64 {
        self.options.max_factor * self.options.load_scale_for(self.model)
    }
}

/// The margin along `direction` of the step `step`, searched from scratch.
fn along(step: &StepSearch, direction: WrenchDirection) -> Result<DirectionMargin, ModelError> {
    let clock = Instant::now();
    let mut solver = GraspSolver::new(Arc::clone(step.model), step.solve_options);
    let mut search = step.search(&mut solver, direction, false);
    let cap = step.cap_n();
    if let Some(mut certificate) = step
        .options
        .load_capacity
        .then(|| search.find_capacity(cap))
        .flatten()
    {
        search.bound_by(&mut certificate);
    }
    let found = search.search_from_zero(step.base(), cap, step.options.relative_tolerance)?;
    search.finish(found, clock)
}

impl Search<'_> {
    /// The search from `held` (the undisturbed state): growth, then bisection.
    pub(crate) fn search_from_zero(
        &mut self,
        mut held: Held,
        cap: f64,
        tolerance: f64,
    ) -> Result<Found, ModelError> {
        let mut end = self.grow(&mut held, cap)?;
        let note = match &mut end {
            End::Fails(fails) => self.narrow(&mut held, fails, tolerance)?,
            End::Cap | End::Undetermined(_) => None,
        };
        Ok(Found { held, end, note })
    }

    /// The margin of a finished search, `clock` started with it, its failing end probed for
    /// another equilibrium ([`crate::analysis::equilibrium_probe`]).
    pub(crate) fn finish(
        &mut self,
        found: Found,
        clock: Instant,
    ) -> Result<DirectionMargin, ModelError> {
        let Found { held, end, note } = found;
        let other_equilibrium = match &end {
            End::Fails(f) => self.other_equilibrium(&held, f, self.probe_equilibria)?,
            End::Cap | End::Undetermined(_) => None,
        };
        let s = held.s;
        let (fails, undetermined) = match end {
            End::Fails(f) => (Some(f), None),
            End::Cap => (None, None),
            End::Undetermined(why) => (None, Some(why)),
        };
        let failing_finger = match &fails {
            Some(Fails {
                failure: Failure::Slides { finger },
                ..
            }) => Some(finger.clone()),
            Some(_) => most_utilised(self.model, &held.sol),
            None => None,
        };
        let direction = self.direction;
        Ok(DirectionMargin {
            direction,
            margin_n: fails.as_ref().map(|_| s),
            held_to_n: s,
            fails_at_n: fails.as_ref().map(|h| h.s),
            force_n: direction.force.map(|v| v * s),
            torque_nm: direction.torque.map(|v| v * s * self.length_m),
            bounded: fails.is_some(),
            failing_finger,
            failure: match (fails, &undetermined) {
                (Some(f), _) => Some(f.failure),
                (None, Some(why)) => Some(Failure::NoConvergence {
                    reason: why.clone(),
                }),
                (None, None) => None,
            },
            solves: self.solves,
            time_s: clock.elapsed().as_secs_f64(),
            stopped_early: note,
            undetermined,
            solver_fallbacks: self.fallbacks,
            warnings: held
                .sol
                .warnings
                .iter()
                .filter(|w| !self.model.scene_warnings().contains(w))
                .cloned()
                .collect(),
            other_equilibrium,
        })
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
    let mut report = MarginReport::of(model, options, sliding_undisturbed, margins, clock);
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
        pinch_under("energy")
    }

    /// [`pinch`] under the contact law `law` (`"energy"` or `"coulomb"`).
    pub(crate) fn pinch_under(law: &str) -> Arc<GraspModel> {
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
            "model": law
        });
        let scene = crate::Scene::from_json_str(&scene.to_string()).unwrap();
        Arc::new(GraspModel::from_scene(&scene).unwrap())
    }

    /// A model's step at its scene's loads, solved undisturbed with the default options: where
    /// a test's searches start.
    pub(crate) struct Undisturbed {
        pub(crate) inputs: StepInputs,
        pub(crate) state: ContactState,
        pub(crate) solution: Solution,
    }

    impl Undisturbed {
        pub(crate) fn of(model: &Arc<GraspModel>) -> Undisturbed {
            let inputs = StepInputs::of_scene(model);
            let mut state = ContactState::new(model);
            let solution = GraspSolver::new(Arc::clone(model), SolveOptions::default())
                .solve_step(&inputs, &mut state)
                .unwrap();
            Undisturbed {
                inputs,
                state,
                solution,
            }
        }

        /// The searches of `model` from this step with `options`.
        pub(crate) fn step<'a>(
            &'a self,
            model: &'a Arc<GraspModel>,
            options: &'a MarginOptions,
        ) -> StepSearch<'a> {
            StepSearch {
                model,
                inputs: &self.inputs,
                solved: SolvedStep {
                    state: &self.state,
                    solution: &self.solution,
                },
                solve_options: SolveOptions::default(),
                options,
                exempt: &[],
            }
        }
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
        let undisturbed = Undisturbed::of(&model);
        for tolerance in [1e-300, 0.0, 1e-17] {
            let options = MarginOptions {
                relative_tolerance: tolerance,
                length_m: Some(0.05),
                ..MarginOptions::default()
            };
            let m = along(&undisturbed.step(&model, &options), DOWN).unwrap();
            let note = m
                .stopped_early
                .as_deref()
                .unwrap_or_else(|| panic!("no note at {tolerance:e}: {m:?}"));
            assert!(note.contains("not narrowed to the tolerance"), "{note}");
            let (lo, hi) = (m.margin_n.unwrap(), m.fails_at_n.unwrap());
            assert!(
                lo <= 6.0 * (1.0 + 1e-9) && hi >= 6.0 * (1.0 - 1e-9),
                "{m:?}"
            );
            assert!((hi - lo) <= 1e-9 * 6.0, "{m:?}");
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
        let lo = m.margin_n.unwrap();
        assert!(lo <= 6.0 * (1.0 + 1e-9) && m.fails_at_n.unwrap() >= 6.0 * (1.0 - 1e-9));
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
        let d = &r.directions[0];
        assert!(
            matches!(d.failure, Some(Failure::NoConvergence { .. })),
            "{d:?}"
        );
        // A stall is no margin: undetermined above what held (here nothing above 0).
        assert_eq!((d.margin_n, d.fails_at_n), (None, None), "{d:?}");
        assert!(d.undetermined.is_some() && !d.is_unbounded(), "{d:?}");
    }
}
