//! The disturbance margin of one hand-off step: the smallest, over the axis
//! directions of force and couple, of the margins of [`grasp_model::disturbance_margins`], continued from
//! the contact state at the start of the step.

use std::sync::Arc;

use grasp_model::{axis_directions, disturbance_margins, MarginOptions, WrenchDirection};
use grasp_model::{
    ContactState, GraspModel, MarginReport, MarginTracker, ModelError, SolveOptions, SolvedStep,
    StepInputs,
};
use serde::Serialize;

/// The smallest margin of a step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepMargin {
    /// Smallest margin over the axis directions that the grasp resists at all, N (force N at
    /// the centre of mass, or couple N times `length_m` in N m); 0 when it resists none.
    /// `None` when that direction has no magnitude found to fail: unbounded (it held at the
    /// search's cap) or undetermined (`undetermined` says why); `held_to_n` then says how far
    /// it held.
    pub smallest_n: Option<f64>,
    /// Largest magnitude found to hold along `direction`, N: the margin when there is one,
    /// else the cap (unbounded) or the lower bound of an undetermined margin.
    pub held_to_n: f64,
    /// Why the margin along `direction` is not known above `held_to_n`, when it is not (no
    /// solver converged there).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub undetermined: Option<String>,
    /// Axis directions the grasp does not resist at all (margin 0 whatever the step: with
    /// commanded loads, a push along the squeeze axis, say, has no equilibrium). Listed
    /// apart so that the smallest margin tracks how safe the step is.
    pub unresisted: Vec<WrenchDirection>,
    /// Its direction.
    pub direction: WrenchDirection,
    /// False when even the smallest margin reached the search's cap.
    pub bounded: bool,
    /// The finger that fails first along it.
    pub failing_finger: Option<String>,
    /// Characteristic length of the couples, m.
    pub length_m: f64,
    /// Solves spent on the margins of this step.
    pub solves: u32,
    /// Wall time of the margins of this step, s.
    pub time_s: f64,
    /// The first direction (in the search's order) whose failing end the coulomb law gives a
    /// second equilibrium ([`grasp_model::DirectionMargin::other_equilibrium`]): the margins
    /// follow the search's path, which is not the only one there.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub other_equilibrium: Option<OtherEquilibrium>,
}

/// A second equilibrium at a margin's failing end.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OtherEquilibrium {
    /// The direction whose margin it is.
    pub direction: WrenchDirection,
    /// The two equilibria in words (the magnitude, N; who found each; how far apart, N).
    pub found: String,
}

impl StepMargin {
    /// The largest push known to hold along `direction`, N: the margin, else `held_to_n` (the
    /// cap when unbounded, a lower bound when undetermined). What a threshold is compared with.
    pub fn known_to_hold_n(&self) -> f64 {
        self.smallest_n.unwrap_or(self.held_to_n)
    }

    /// The margin for ordering, N: the margin, infinite when unbounded, the lower bound
    /// `held_to_n` when undetermined.
    pub fn margin_or_bound_n(&self) -> f64 {
        grasp_model::margin_for_ordering_n(
            self.smallest_n,
            self.held_to_n,
            self.undetermined.is_some(),
        )
    }
}

/// The margin of the step grasp `model` under the step's `inputs` (its loads, approaches and
/// external wrench) from `state`, the contact state at the start of the step, searched with
/// `options`.
pub fn step_margin(
    model: &Arc<GraspModel>,
    inputs: &StepInputs,
    state: &ContactState,
    solve: SolveOptions,
    options: &MarginOptions,
) -> Result<StepMargin, ModelError> {
    let dirs = axis_directions(model);
    let r = disturbance_margins(model, inputs, state, solve, &dirs, options)?;
    Ok(smallest_of(&r))
}

/// The margins of the successive steps of a hand-off, each step's search continued from the
/// last step's ([`grasp_model::MarginTracker`]): the same margins as [`step_margin`]'s, to
/// the search's tolerance.
pub struct MarginPath {
    /// The tracker, made at the first step (its directions are the first step's model's).
    tracker: Option<MarginTracker>,
    /// The options of its searches.
    options: MarginOptions,
}

impl Default for MarginPath {
    fn default() -> Self {
        Self::new()
    }
}

impl MarginPath {
    /// A path before its first step, searched with the default options.
    pub fn new() -> Self {
        Self::with_options(MarginOptions::default())
    }

    /// A path before its first step, searched with `options`.
    pub fn with_options(options: MarginOptions) -> Self {
        MarginPath {
            tracker: None,
            options,
        }
    }

    /// The margin of the next step: as [`step_margin`], from the last step's margins and the
    /// step's own undisturbed solve `solved` ([`grasp_model::GraspSolver::solve_step`] from
    /// the step's start state, before [`ContactState::advance_time_step`]).
    pub fn step_margin(
        &mut self,
        model: &Arc<GraspModel>,
        inputs: &StepInputs,
        solved: SolvedStep,
        solve: SolveOptions,
    ) -> Result<StepMargin, ModelError> {
        let tracker = match &mut self.tracker {
            Some(t) => t,
            None => self
                .tracker
                .insert(MarginTracker::new(axis_directions(model), self.options)?),
        };
        Ok(smallest_of(
            &tracker.margins_of_solved(model, inputs, solved, solve)?,
        ))
    }
}

/// The smallest margin of a report, with its cost.
fn smallest_of(r: &MarginReport) -> StepMargin {
    let d = &r.directions[r.smallest];
    StepMargin {
        unresisted: r
            .unresisted
            .iter()
            .map(|&i| r.directions[i].direction)
            .collect(),
        smallest_n: d.margin_n,
        held_to_n: d.held_to_n,
        undetermined: d.undetermined.clone(),
        direction: d.direction,
        bounded: d.bounded,
        failing_finger: d.failing_finger.clone(),
        length_m: r.length_m,
        solves: r.solves,
        time_s: r.time_s,
        other_equilibrium: r.directions.iter().find_map(|d| {
            d.other_equilibrium.as_ref().map(|found| OtherEquilibrium {
                direction: d.direction,
                found: found.clone(),
            })
        }),
    }
}
