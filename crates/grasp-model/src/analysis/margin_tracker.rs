//! Disturbance margins along a loading path (the steps of a hand-off), each step's search
//! started from the previous step's margins, each direction keeping its solver (its warm start
//! and factorisations) from step to step.
//!
//! The answers are those of [`crate::disturbance_margins`] to its bisection tolerance: a
//! margin is again a bracket `[held, fails]` no wider than
//! [`MarginOptions::relative_tolerance`] of its upper end, whose lower end holds and whose
//! upper end fails in the criterion of [`holds`] (or the cap, held). Only where the trials go
//! changes. Per direction and step:
//!
//! - **prediction**: the margins of the last three steps extrapolated by the parabola through
//!   them (two: the line; one: itself), the last margin alone when the extrapolation moves it
//!   by more than [`PREDICTION_REACH`] of it;
//! - **check**: a trial at the prediction, then one a tolerance above it when it held (below
//!   it when it failed): two solves when the prediction is within a tolerance of the margin.
//!   A prediction at or beyond the load capacity ([`crate::analysis::load_capacity`]) is
//!   checked just below the capacity instead, where one solve settles it;
//! - **fallback**: from the end that was wrong the bracket walks on, in steps of a tolerance
//!   three times, then growing fourfold, until it holds the margin, and the bisection of the search from
//!   scratch narrows it. In a planar coulomb scene the walk upwards and the bisection are guided:
//!   the line through the largest friction utilisation `|Q|/(mu P)` of the judged fingers at
//!   the two largest magnitudes that held (the step's undisturbed state among them) reaches 1,
//!   a finger sliding as a whole, near the margin; the next trial goes half a tolerance above
//!   it (at most twice the magnitude that held; a tolerance below the failing end when the
//!   line reaches 1 beyond it), and a guided trial that did not halve the bracket is followed
//!   by a bisection (`Search::guided_point`). The first step, a step after one whose grasp failed undisturbed, a
//!   direction unresisted or unbounded at the last step, and a prediction above 100 times the
//!   load scale run the search from scratch (with a fresh solver, as it does: the same trials,
//!   the same answers). Whether a direction is resisted at all is decided at the edge of
//!   equilibrium, where the solver's start can tip the answer; far above the load scale the
//!   solves themselves stop converging at some magnitudes ([`LARGE_MARGIN_FACTOR`]).
//! - **kept**: each direction's load-capacity certificate, found by Clarabel at the first step
//!   of a model and kept while the model is (its bound at a step costs two right-hand sides),
//!   found anew after a step where a solve failed below its bound;
//! - **started**: each trial's Tresca iteration from the forces of the direction's last two
//!   trials, extrapolated to its magnitude ([`crate::analysis::trial_forces`]), instead of its
//!   start state's (the start state's slip memory, which sets the answer, stays);
//! - **shared**: the step's undisturbed solve (its solver kept from step to step, warm; or
//!   the hand-off's own solve of the step, [`MarginTracker::margins_of_solved`]), and
//!   the directions that only the commanded
//!   loads could balance ([`crate::analysis::load_fixed_directions`], once per model): a
//!   disturbance along one of them is unresisted without a solve (the search from scratch
//!   finds the same, margin 0, with one solve that certifies no equilibrium).
//!
//! As in the search from scratch, each trial is one quasi-static step from the state at the
//! largest magnitude known to hold (the step's undisturbed state when none is), so the coulomb
//! model's slip memory follows a monotone loading path. That path takes fewer, larger steps
//! here; slip memory makes the two searches' criteria differ only where a margin depends on
//! the loading path within a step, which `tests/margin_tracking.rs` checks along every
//! example hand-off.

use std::sync::Arc;
use std::time::Instant;

use nalgebra::Vector3;

use crate::analysis::load_capacity::LoadCapacity;
use crate::analysis::load_fixed_directions::LoadFixedDirections;
use crate::analysis::margin_report::{
    failing_undisturbed, holds, sliding_fingers, DirectionMargin, Failure, MarginOptions,
    MarginReport,
};
use crate::analysis::margin_search::{End, Found, SolvedStep, StepSearch, CAPACITY_PROBE};
use crate::analysis::margin_trial::{Fails, Held, Search, Trial, ZERO_MARGIN};
use crate::analysis::trial_forces::TrialForces;
use crate::analysis::wrench_directions::WrenchDirection;
use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::scene::scene_format::ModelKind;
use crate::solve::contact_state::ContactState;
use crate::solve::grasp_solver::GraspSolver;
use crate::solve::step_inputs::StepInputs;
use crate::solver::options::SolveOptions;

/// Width of the checking bracket as a fraction of the tolerance: a prediction `m` that holds
/// is checked at `m (1 + w tol)`, one that fails at `m (1 - w tol)`, brackets narrower than
/// `tol` times their upper end, so that two trials confirm a prediction within a tolerance of
/// the margin on either side without a bisection.
const CHECK_WIDTH: f64 = 0.99;

/// Predictions above this multiple of the load scale are not checked: there the scaled
/// program is ill-conditioned and solves fail to converge at some magnitudes and not at
/// others (a failure), so holding stops being monotone in the magnitude and any search's
/// answer depends on where it tries. The search from scratch's own trials are taken.
const LARGE_MARGIN_FACTOR: f64 = 100.0;

/// Largest move of a prediction from the last margin, as a fraction of it: a margin that
/// grows fast (a receiving finger taking the load) is followed by the parabola up to doubling
/// (on the coulomb plate hand-off 1,878 solves where half took 1,911).
const PREDICTION_REACH: f64 = 1.0;

/// Growth of the walking step after each trial that did not bracket the margin, once the
/// first [`EVEN_WALK_STEPS`] have not.
const WALK_GROWTH: f64 = 4.0;

/// The walk's first steps keep the check's width (a tolerance, so a margin they pass needs no
/// bisection): the predictions miss by one to three tolerances more often than by more (the
/// margins along a coulomb path move in steps of their own bracket). On the coulomb plate
/// hand-off this takes 1,911 solves where growing from the first step took 2,067.
const EVEN_WALK_STEPS: u32 = 3;

/// Largest number of walking trials before the search from scratch takes over (a step
/// growing fourfold from 1e-9 of the margin passes any cap within 40).
const MAX_WALK_STEPS: u32 = 64;

/// What the last step's search found along a direction.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Seen {
    /// A margin, N.
    Margin(f64),
    /// Not resisted at all.
    Unresisted,
    /// Held at the cap.
    Unbounded,
}

/// One direction's solver, its load-capacity certificate and the margins of the last steps
/// (newest last).
#[derive(Default)]
struct Track {
    solver: Option<GraspSolver>,
    capacity: Capacity,
    /// The forces of the direction's last solved trials ([`TrialForces`]).
    trial_forces: TrialForces,
    last: Vec<Seen>,
}

/// A direction's load-capacity certificate along the path.
#[derive(Default)]
enum Capacity {
    /// To be found at the next step (the first, after a change of model, or after a step
    /// whose margin a solve found to fail below the certificate's bound: it has gone loose).
    #[default]
    Unknown,
    /// None exists or is sought ([`LoadCapacity::find`]) for this model.
    None,
    /// Kept from an earlier step of the same model (a certificate depends on the model only).
    Known(Box<LoadCapacity>),
}

/// The step's data every direction's search shares: the step's search, and the model's
/// directions fixed by the commanded loads.
struct Shared<'a> {
    step: StepSearch<'a>,
    fixed: &'a LoadFixedDirections,
}

/// Disturbance margins of the successive steps of a loading path (see the module).
pub struct MarginTracker {
    directions: Vec<WrenchDirection>,
    options: MarginOptions,
    /// The model and solve options the solvers were built for.
    built_for: Option<(Arc<GraspModel>, SolveOptions)>,
    /// That model's directions fixed by the commanded loads.
    fixed: LoadFixedDirections,
    tracks: Vec<Track>,
    /// The solver of the steps' undisturbed solves, kept (warm-started) from step to step.
    base_solver: Option<GraspSolver>,
}

impl MarginTracker {
    /// A tracker of the margins along `directions`; options outside their ranges are an error
    /// ([`MarginOptions::validate`]).
    pub fn new(
        directions: Vec<WrenchDirection>,
        options: MarginOptions,
    ) -> Result<Self, ModelError> {
        options.validate()?;
        let tracks = directions.iter().map(|_| Track::default()).collect();
        Ok(MarginTracker {
            directions,
            options,
            built_for: None,
            fixed: LoadFixedDirections::none(),
            tracks,
            base_solver: None,
        })
    }

    /// The margins of the next step of the path: `model` under `inputs` from `state`, as
    /// [`crate::disturbance_margins`] defines them. The solvers are kept while `model` (the
    /// same `Arc`) and `solve_options` stay; the predictions carry over a change of either.
    pub fn margins(
        &mut self,
        model: &Arc<GraspModel>,
        inputs: &StepInputs,
        state: &ContactState,
        solve_options: SolveOptions,
    ) -> Result<MarginReport, ModelError> {
        solve_options.validate()?;
        let clock = Instant::now();
        self.keep_solvers_of(model, solve_options);
        let mut base_state = state.clone();
        let base_solver = self
            .base_solver
            .get_or_insert_with(|| GraspSolver::new(Arc::clone(model), solve_options));
        let base = base_solver.solve_step(inputs, &mut base_state)?;
        let solved = SolvedStep {
            state: &base_state,
            solution: &base,
        };
        self.margins_beyond(model, inputs, solved, solve_options, clock)
    }

    /// [`MarginTracker::margins`] of a step whose undisturbed solve the caller has made:
    /// `solved` is [`GraspSolver::solve_step`] of `inputs` from the step's start state,
    /// solved with `solve_options` (a hand-off's own step: its margins then cost no second
    /// solve of the step).
    pub fn margins_of_solved(
        &mut self,
        model: &Arc<GraspModel>,
        inputs: &StepInputs,
        solved: SolvedStep,
        solve_options: SolveOptions,
    ) -> Result<MarginReport, ModelError> {
        solve_options.validate()?;
        let clock = Instant::now();
        self.keep_solvers_of(model, solve_options);
        self.margins_beyond(model, inputs, solved, solve_options, clock)
    }

    /// The margins from the step's undisturbed solve `solved`.
    fn margins_beyond(
        &mut self,
        model: &Arc<GraspModel>,
        inputs: &StepInputs,
        solved: SolvedStep,
        solve_options: SolveOptions,
        clock: Instant,
    ) -> Result<MarginReport, ModelError> {
        use rayon::prelude::*;
        let base = solved.solution;
        let sliding_undisturbed = match model.kind() {
            ModelKind::Coulomb if base.status.has_forces() => sliding_fingers(base),
            _ => Vec::new(),
        };
        let margins: Vec<DirectionMargin> = match holds(model, base, &sliding_undisturbed) {
            Err(f) => {
                self.tracks.iter_mut().for_each(|t| t.last.clear());
                let dirs = self.directions.iter();
                dirs.map(|&d| failing_undisturbed(d, &f)).collect()
            }
            Ok(()) => {
                let shared = Shared {
                    step: StepSearch {
                        model,
                        inputs,
                        solved,
                        solve_options,
                        options: &self.options,
                        exempt: &sliding_undisturbed,
                    },
                    fixed: &self.fixed,
                };
                let pairs = self.tracks.par_iter_mut().zip(self.directions.par_iter());
                pairs
                    .map(|(track, &d)| continue_along(track, &shared, d))
                    .collect::<Result<_, _>>()?
            }
        };
        Ok(MarginReport::of(
            model,
            &self.options,
            sliding_undisturbed,
            margins,
            clock,
        ))
    }

    /// Drops the solvers unless they were built for `model` and `solve_options`.
    fn keep_solvers_of(&mut self, model: &Arc<GraspModel>, solve_options: SolveOptions) {
        let same = self
            .built_for
            .as_ref()
            .is_some_and(|(m, o)| Arc::ptr_eq(m, model) && *o == solve_options);
        if !same {
            self.fixed = LoadFixedDirections::of(model);
            self.built_for = Some((Arc::clone(model), solve_options));
            self.base_solver = None;
            for t in &mut self.tracks {
                t.solver = None;
                t.capacity = Capacity::Unknown;
            }
        }
    }
}

/// The margin along `direction` at this step, started from what `track` saw at the last ones.
fn continue_along(
    track: &mut Track,
    shared: &Shared<'_>,
    direction: WrenchDirection,
) -> Result<DirectionMargin, ModelError> {
    let clock = Instant::now();
    let step = &shared.step;
    let model = step.model;
    let predicted = prediction(&track.last);
    let solver = track
        .solver
        .get_or_insert_with(|| GraspSolver::new(Arc::clone(model), step.solve_options));
    let mut search = step.search(solver, direction, true);
    search.trial_forces = std::mem::take(&mut track.trial_forces);
    search.note_held(0.0, step.solved.solution);
    let cap = step.cap_n();
    if step.options.load_capacity {
        bound(&mut track.capacity, &mut search, cap);
    }
    let base = step.base();
    let (force, torque) = (
        Vector3::from(direction.force),
        Vector3::from(direction.torque) * search.length_m,
    );
    let found = match predicted {
        _ if shared.fixed.fixes(model, &force, &torque) => fixed_by_loads(&search, base),
        Some(Seen::Margin(m)) => around(&mut search, base, m, step.options)?,
        Some(Seen::Unresisted | Seen::Unbounded) | None => {
            from_scratch(&mut search, base, step.options)?
        }
    };
    let loose = match &found.end {
        End::Fails(Fails {
            s: at,
            failure: Failure::NoEquilibrium { .. },
        }) => *at < search.capacity_n,
        End::Undetermined(_) => true,
        _ => false,
    };
    let m = search.finish(found, clock)?;
    track.trial_forces = std::mem::take(&mut search.trial_forces);
    if loose && matches!(track.capacity, Capacity::Known(_)) {
        track.capacity = Capacity::Unknown;
    }
    track.last.push(seen(&m));
    if track.last.len() > 3 {
        track.last.remove(0);
    }
    Ok(m)
}

/// Bounds `search` by the capacity `capacity` proves at this step, found first when unknown.
fn bound(capacity: &mut Capacity, search: &mut Search<'_>, cap_n: f64) {
    if matches!(capacity, Capacity::Unknown) {
        *capacity = match search.find_capacity(cap_n) {
            Some(c) => Capacity::Known(Box::new(c)),
            None => Capacity::None,
        };
    }
    if let Capacity::Known(c) = capacity {
        search.bound_by(c);
    }
}

/// What a margin says for the next step's prediction.
fn seen(m: &DirectionMargin) -> Seen {
    match m.margin_n {
        Some(0.0) => Seen::Unresisted,
        Some(x) => Seen::Margin(x),
        // Unbounded, or undetermined: the next step searches from scratch.
        None => Seen::Unbounded,
    }
}

/// The prediction of this step from the last ones (newest last): three margins extrapolated
/// by their parabola, two by their line (steps taken as equally spaced), unless that moves the
/// last by more than [`PREDICTION_REACH`] of it; else the last.
fn prediction(last: &[Seen]) -> Option<Seen> {
    let p = match last {
        [.., Seen::Margin(a), Seen::Margin(b), Seen::Margin(c)] => 3.0 * (c - b) + a,
        [.., Seen::Margin(b), Seen::Margin(c)] => 2.0 * c - b,
        [.., x] => return Some(*x),
        [] => return None,
    };
    let Some(Seen::Margin(c)) = last.last() else {
        return None;
    };
    Some(Seen::Margin(if (p - c).abs() <= PREDICTION_REACH * c {
        p
    } else {
        *c
    }))
}

/// A fresh solver for `search` (no warm start from other steps), as the search from scratch
/// starts with.
fn start_afresh(search: &mut Search<'_>) {
    let model = Arc::clone(search.solver.shared_model());
    *search.solver = GraspSolver::new(model, *search.solver.options());
    search.guessing = false;
    search.trial_forces = TrialForces::default();
    search.utilisation.clear();
}

/// The search from scratch ([`crate::disturbance_margins`]'s): growth from `held`, then
/// bisection, with a fresh solver.
fn from_scratch(
    search: &mut Search<'_>,
    held: Held,
    options: &MarginOptions,
) -> Result<Found, ModelError> {
    start_afresh(search);
    let cap = options.max_factor * search.load_n;
    search.search_from_zero(held, cap, options.relative_tolerance)
}

/// A direction only the commanded loads could balance: unresisted, failing at the smallest
/// magnitude as the search from scratch finds with a solve.
fn fixed_by_loads(search: &Search<'_>, base: Held) -> Found {
    let zero = ZERO_MARGIN * search.load_n;
    let failure = Failure::NoEquilibrium {
        reason: "no equilibrium: the disturbance has a component that only the commanded \
                 normal loads could balance, and they are fixed"
            .into(),
    };
    Found {
        held: base,
        end: End::Fails(Fails { s: zero, failure }),
        note: None,
    }
}

/// A margin predicted at `m` N: a trial there (ramped from the undisturbed state, coulomb),
/// then one a tolerance above it (when it held) or below it (when it failed), walking on from
/// there, then the bisection. A prediction at the load capacity or beyond it is checked just
/// below the capacity instead.
fn around(
    search: &mut Search<'_>,
    base: Held,
    m: f64,
    options: &MarginOptions,
) -> Result<Found, ModelError> {
    let tol = options.relative_tolerance;
    let cap = options.max_factor * search.load_n;
    let c = search.capacity_n;
    let (lo, hi) = if m * (1.0 + CHECK_WIDTH * tol) < c {
        (m, m * (1.0 + CHECK_WIDTH * tol))
    } else {
        (c * (1.0 - CAPACITY_PROBE * tol), c)
    };
    let load_n = search.load_n;
    if !(lo > ZERO_MARGIN * load_n && hi < LARGE_MARGIN_FACTOR * load_n) {
        return from_scratch(search, base, options);
    }
    let (mut held, mut fails) = match search.trial(lo, &base)? {
        Trial::Holds(h) => match walk_up(search, h, hi, cap, tol)? {
            Found {
                held,
                end: End::Fails(fails),
                ..
            } => (held, fails),
            other => return Ok(other),
        },
        Trial::Fails { fails, below } => {
            match walk_down(search, below.unwrap_or(base), fails, tol)? {
                // Down to the smallest magnitude: whether the direction is resisted at all is
                // the search from scratch's to say (see the module).
                (b, _) if b.s == 0.0 => return from_scratch(search, b, options),
                found => found,
            }
        }
        // Nothing known at the prediction: the search from scratch finds where the answers
        // end.
        Trial::Stalls { .. } => return from_scratch(search, base, options),
    };
    let note = search.narrow(&mut held, &mut fails, tol)?;
    Ok(Found {
        held,
        end: End::Fails(fails),
        note,
    })
}

/// From `held`, trials at `first` N and on upwards (the step `first - held` for
/// [`EVEN_WALK_STEPS`] steps, then each four times the last, never past the capacity; where
/// the utilisation predicts sliding, just above it instead, [`Search::guided_point`]) until
/// one fails, the grasp holds at `cap`, or no solver answers; past [`MAX_WALK_STEPS`], the
/// growth of the search from scratch. `tol`: the relative tolerance.
fn walk_up(
    search: &mut Search<'_>,
    mut held: Held,
    first: f64,
    cap: f64,
    tol: f64,
) -> Result<Found, ModelError> {
    let (mut s, mut step) = (first, first - held.s);
    for k in 0..MAX_WALK_STEPS {
        if let Some(end) = End::of_trial(search.trial(s, &held)?, &mut held) {
            return Ok(Found {
                held,
                end,
                note: None,
            });
        }
        if held.s >= cap {
            return Ok(Found {
                held,
                end: End::Cap,
                note: None,
            });
        }
        if k + 1 >= EVEN_WALK_STEPS {
            step *= WALK_GROWTH;
        }
        let guided = search.guided_point(held.s, f64::INFINITY, tol);
        s = guided.unwrap_or(s + step).min(cap).min(search.capacity_n);
    }
    let end = search.grow(&mut held, cap)?;
    Ok(Found {
        held,
        end,
        note: None,
    })
}

/// From a failure at `fails`, trials downwards from `below`, the largest magnitude known to
/// hold under it (the gap growing by `0.99 tol` of the magnitude for [`EVEN_WALK_STEPS`]
/// steps, then fourfold), until one holds; at `below` (or the smallest magnitude), the bracket
/// is `[below, fails]`. A trial no solver answers is passed over (the bracket ends stay true).
fn walk_down(
    search: &mut Search<'_>,
    below: Held,
    mut fails: Fails,
    tol: f64,
) -> Result<(Held, Fails), ModelError> {
    let zero = ZERO_MARGIN * search.load_n;
    let first = CHECK_WIDTH * tol * fails.s;
    let mut gap = first;
    for k in 0..MAX_WALK_STEPS {
        let s = fails.s - gap;
        if s.is_nan() || s <= zero || s <= below.s {
            break;
        }
        match search.trial(s, &below)? {
            Trial::Holds(h) => return Ok((h, fails)),
            Trial::Fails { fails: f, below: b } => {
                fails = f;
                if let Some(b) = b {
                    return Ok((b, fails));
                }
            }
            Trial::Stalls { .. } => {}
        }
        gap = if k + 1 >= EVEN_WALK_STEPS {
            gap * WALK_GROWTH
        } else {
            gap + first
        };
    }
    Ok((below, fails))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::margin_search::tests::{pinch, DOWN};

    /// A step solved by the caller (a hand-off's own solve) gives the margins of the step
    /// solved by the tracker itself, bit for bit (the same inputs and start state, fresh
    /// solvers: the same undisturbed solution), at two successive steps (the second continued
    /// from the first); and the downward margin brackets the pads' friction capacity, the
    /// closed form `2 mu P - W = 6 N`, to the bisection's relative tolerance.
    #[test]
    fn a_step_solved_by_the_caller_gives_the_margins_of_a_step_solved_here() {
        let model = pinch();
        let solve = SolveOptions::default();
        let options = MarginOptions::default();
        let directions = vec![
            DOWN,
            WrenchDirection::of_wrench([1.0, 0.0, 0.0], [0.0; 3], 1.0).unwrap(),
        ];
        let mut itself = MarginTracker::new(directions.clone(), options).unwrap();
        let mut given = MarginTracker::new(directions, options).unwrap();
        let mut stepper = GraspSolver::new(Arc::clone(&model), solve);
        let start = ContactState::new(&model);
        let inputs = StepInputs::of_scene(&model);
        for step in 0..2 {
            let mut after = start.clone();
            let sol = stepper.solve_step(&inputs, &mut after).unwrap();
            let a = itself.margins(&model, &inputs, &start, solve).unwrap();
            let b = given
                .margins_of_solved(
                    &model,
                    &inputs,
                    SolvedStep {
                        state: &after,
                        solution: &sol,
                    },
                    solve,
                )
                .unwrap();
            for (x, y) in a.directions.iter().zip(&b.directions) {
                assert_eq!(
                    (x.margin_n, x.fails_at_n, x.solves),
                    (y.margin_n, y.fails_at_n, y.solves),
                    "step {step}"
                );
            }
            let down = &b.directions[0];
            let fails = down.fails_at_n.unwrap();
            let margin = down.margin_n.unwrap();
            assert!(
                margin <= 6.0 * (1.0 + 1e-9) && fails >= 6.0 * (1.0 - 1e-9),
                "step {step}: {down:?}"
            );
            assert!(
                fails - margin <= options.relative_tolerance * fails,
                "step {step}: {down:?}"
            );
        }
    }
}
