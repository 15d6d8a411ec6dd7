//! Disturbance margins: for each direction of an extra wrench on the object, the
//! largest magnitude the grasp can take while it still holds in the scene's model.
//!
//! A direction is a unit vector `(f, t)` of the scaled wrench space; magnitude `s` (N) means a
//! force `s f` (N) at the centre of mass plus a couple `s L t` (N m), `L` the characteristic
//! length ([`MarginOptions::length_m`], by default the grasp's reach [`crate::Scales`]
//! `length_m`), so force and torque directions compare at the grasp's size.
//!
//! **The margin** along a direction is the largest magnitude `s` such that the disturbance,
//! ramped quasi-statically from 0 to `s` on top of the step's loads, from the step's contact
//! state (with its slip history), leaves the grasp holding at every magnitude on the way. For
//! the energy model, which has no slip memory, that is the largest magnitude at which it holds.
//! For the coulomb model the ramp matters: a push taken in one step far beyond the margin can
//! land on an equilibrium that holds again ([`crate::analysis::margin_trial`]). A search reports
//! it as a bracket `[margin_n, fails_at_n]` no wider than its tolerance; a push ramped to just
//! below `margin_n` holds, one ramped past `fails_at_n` fails (`tests/margin_agreement.rs`
//! pushes both through `grasp transfer`).
//!
//! The grasp **holds** at `s` when
//! - energy model: the program has a solution, i.e. forces within the element cones (and the
//!   commanded loads) balance the load: the rigid-body bound of the patches' cones. (The energy
//!   model's minimum-energy grasp may slide as a whole at no disturbance at all: its held
//!   fingers squeeze no more than friction needs, so sliding is not its failure criterion.)
//! - coulomb model: an equilibrium exists and every frictional finger carrying more than
//!   [`JUDGED_FRACTION`] of the load scale keeps at least one sticking element (a finger whose every element slips slides as a whole). A finger
//!   that already slides as a whole without disturbance (a receiving finger settling in a
//!   hand-off) is listed apart and not judged by sliding.
//!
//! It **fails** where a solve certifies that no equilibrium exists (or the load capacity
//! proves it) or a judged finger slides as a whole. A solve that does not converge says
//! neither: the other solver takes the step, and where neither converges the margin is
//! **undetermined** above the largest magnitude that held ([`DirectionMargin::undetermined`]),
//! a lower bound, never a margin. Where the grasp still holds at the cap
//! ([`MarginOptions::max_factor`] times the load scale) the margin is **unbounded**. Both are
//! written as what they are: `margin_n` is null in JSON (with `held_to_n`), `inf` or empty in
//! CSV, infinite or NaN in Python.
//!

use std::ops::RangeInclusive;

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::analysis::wrench_directions::WrenchDirection;
use crate::error::OptionError;
use crate::model::grasp_model::GraspModel;
use crate::option_names;
use crate::scene::limits::{LENGTH_RANGE_M, MAX_FORCE_N, MIN_NONZERO_FORCE_N};
use crate::scene::scene_format::ModelKind;
use crate::solve::solution::{Solution, SolveStatus};
use crate::solver::options::check_range;

/// Range of [`MarginOptions::relative_tolerance`]: the solves balance the load only to about
/// 1e-10 of it, so a narrower bracket than 1e-9 would sort round-off; above 0.5 the bracket
/// says little.
pub const RELATIVE_TOLERANCE_RANGE: RangeInclusive<f64> = 1e-9..=0.5;

/// Range of [`MarginOptions::max_factor`]: at least the load scale itself; beyond 1e6 times it
/// a disturbance is no longer one a grasp meets.
pub const MAX_FACTOR_RANGE: RangeInclusive<f64> = 1.0..=1e6;

/// Options of the margin search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarginOptions {
    /// Characteristic length `L`, m: torque `s L t` per magnitude `s`. `None`: the grasp's
    /// reach (`Scales::length_m`). In the scene's length range [`LENGTH_RANGE_M`]. A hand-off
    /// sets it to the scene's reach, so that every step's couples compare with each other and
    /// with `grasp margin`'s on the scene, whichever fingers a step holds with.
    pub length_m: Option<f64>,
    /// The load scale of the search, N: its first step (the margin trial's
    /// `INITIAL_STEP` of it, also a coulomb ramp's first), its cap (`max_factor` times it) and
    /// the magnitude below which a margin is 0. `None`: the model's (`Scales::load_n`). A
    /// hand-off sets it to the scene's, as `length_m`. Positive, at most [`MAX_FORCE_N`].
    pub load_scale_n: Option<f64>,
    /// Bisection stops when the bracket is below this fraction of its upper end (in
    /// `RELATIVE_TOLERANCE_RANGE`).
    pub relative_tolerance: f64,
    /// Magnitudes above this multiple of the load scale count as unbounded (in
    /// `MAX_FACTOR_RANGE`).
    pub max_factor: f64,
    /// Bound each direction's search by its load capacity, the magnitude from which no contact
    /// forces within the friction cones balance the load, proved by a Farkas certificate
    /// (default). `false` solves every trial, as the search did before the capacity: the same
    /// margins to the tolerance, at the cost of the stalling solves past the edge of
    /// equilibrium (for comparison).
    pub load_capacity: bool,
    /// Probe the failing end of each coulomb bracket for another equilibrium (default;
    /// the search's solver started cold and the other solver, compared to [`crate::DISTINCT_FRACTION`]): three more solves per bounded direction.
    /// `false` leaves the probe out, for comparison.
    pub probe_equilibria: bool,
}

impl MarginOptions {
    /// Checks every option against its range and returns the first one outside it, named as
    /// the API spells it ([`option_names`]). [`crate::disturbance_margins`] checks its options; front
    /// ends call this first so that a bad option is refused before any work.
    pub fn validate(&self) -> Result<(), OptionError> {
        if let Some(p) = self.load_scale_n {
            check_range(
                option_names::MARGIN_LOAD_SCALE,
                p,
                MIN_NONZERO_FORCE_N..=MAX_FORCE_N,
                "a force in newtons",
                "10",
            )?;
        }
        if let Some(l) = self.length_m {
            check_range(
                option_names::MARGIN_LENGTH,
                l,
                LENGTH_RANGE_M,
                "a length in metres (the scene's range)",
                "0.05",
            )?;
        }
        check_range(
            option_names::MARGIN_TOLERANCE,
            self.relative_tolerance,
            RELATIVE_TOLERANCE_RANGE,
            "a relative width of the final bracket",
            "1e-3",
        )?;
        check_range(
            option_names::MARGIN_MAX_FACTOR,
            self.max_factor,
            MAX_FACTOR_RANGE,
            "a multiple of the load scale",
            "1000",
        )
    }
}

impl MarginOptions {
    /// The characteristic length of the search on `model`, m.
    pub fn length_for(&self, model: &GraspModel) -> f64 {
        self.length_m.unwrap_or(model.scales.length_m)
    }

    /// The load scale of the search on `model`, N.
    pub fn load_scale_for(&self, model: &GraspModel) -> f64 {
        self.load_scale_n.unwrap_or(model.scales.load_n)
    }

    /// These options with the length and load scale unset taken from `scene_model` (a
    /// hand-off's model of the whole scene): every step's search then measures in the scene's
    /// units, whichever fingers the step holds with.
    pub fn in_units_of(self, scene_model: &GraspModel) -> Self {
        MarginOptions {
            length_m: Some(self.length_for(scene_model)),
            load_scale_n: Some(self.load_scale_for(scene_model)),
            ..self
        }
    }
}

impl Default for MarginOptions {
    fn default() -> Self {
        MarginOptions {
            length_m: None,
            load_scale_n: None,
            relative_tolerance: 1e-3,
            max_factor: 1e3,
            load_capacity: true,
            probe_equilibria: true,
        }
    }
}

/// Why the grasp stopped holding.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Failure {
    /// No equilibrium: the solve's reason.
    NoEquilibrium {
        /// The solver's explanation.
        reason: String,
    },
    /// A loaded finger slides as a whole (coulomb model: no sticking element left).
    Slides {
        /// The finger.
        finger: String,
    },
    /// The solver gave no answer at this magnitude (counted as a failure; the reason says
    /// why).
    NoConvergence {
        /// The solver's explanation.
        reason: String,
    },
}

/// The margin along one direction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DirectionMargin {
    /// The direction.
    pub direction: WrenchDirection,
    /// The margin, N: the lower end of the final bracket `[margin_n, fails_at_n]`. `None`
    /// when no magnitude was found to fail: unbounded (held at the cap) or undetermined
    /// ([`DirectionMargin::undetermined`]); `held_to_n` then says how far it held.
    pub margin_n: Option<f64>,
    /// Largest magnitude found to hold, N: the margin when there is one, else the cap
    /// (unbounded) or the lower bound of an undetermined margin.
    pub held_to_n: f64,
    /// Smallest magnitude found to fail, N (absent when unbounded or undetermined).
    pub fails_at_n: Option<f64>,
    /// Force part of the wrench at `held_to_n`, N (at the centre of mass).
    pub force_n: [f64; 3],
    /// Torque part of the wrench at `held_to_n`, N m.
    pub torque_nm: [f64; 3],
    /// True when a magnitude that fails was found (`fails_at_n`): false when the grasp still
    /// held at the cap, or when the margin is undetermined.
    pub bounded: bool,
    /// The finger that fails first: the one that slides, else the loaded frictional finger
    /// with the highest friction utilisation at the margin.
    pub failing_finger: Option<String>,
    /// How the grasp failed just above the margin.
    pub failure: Option<Failure>,
    /// Solves spent on this direction.
    pub solves: u32,
    /// Wall time of this direction, s.
    pub time_s: f64,
    /// Why the search stopped before its tolerance, when it did: the bracket could not be
    /// narrowed further in double precision, or a step limit was reached (the bracket
    /// `[margin_n, fails_at_n]` is still a true one, only wider than asked).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped_early: Option<String>,
    /// Why nothing is known above `held_to_n`, when the search ended there without a magnitude
    /// that fails and below the cap: neither solver converged at a magnitude (their reasons),
    /// or the growth reached its step limit. The margin is then at least `held_to_n`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub undetermined: Option<String>,
    /// Steps the chosen solver did not converge on and the other solver answered (a stall is
    /// the solver's, not the grasp's).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub solver_fallbacks: u32,
    /// The warnings of the solve at the margin (the largest magnitude that held), the scene's
    /// left out (they are the report's): forces near the margin beyond the model's limits
    /// make the margin approximate too. Absent when none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// The coulomb law's second equilibrium at the failing end, when a probe found one
    /// (compared to [`crate::DISTINCT_FRACTION`]): the step from the margin's state to
    /// `fails_at_n` solved cold or by the other solver lands on an equilibrium whose forces
    /// differ from the search's. The margin follows the search's path; this says it is not the
    /// only one. Absent when every probe agreed (or none applies).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub other_equilibrium: Option<String>,
}

fn is_zero(n: &u32) -> bool {
    *n == 0
}

impl DirectionMargin {
    /// True when the grasp still held at the cap.
    pub fn is_unbounded(&self) -> bool {
        self.fails_at_n.is_none() && self.undetermined.is_none()
    }

    /// The margin for ordering and plotting, N ([`margin_for_ordering_n`]).
    pub fn margin_or_bound_n(&self) -> f64 {
        margin_for_ordering_n(self.margin_n, self.held_to_n, self.undetermined.is_some())
    }
}

/// A margin as one number for ordering and plotting, N: `margin_n` when there is one, infinite
/// when there is none and the search was not `undetermined` (the grasp held at the cap), the
/// lower bound `held_to_n` when it was. The one rule for a direction's margin, a step's
/// smallest and a run's least safe step.
pub fn margin_for_ordering_n(margin_n: Option<f64>, held_to_n: f64, undetermined: bool) -> f64 {
    match margin_n {
        Some(m) => m,
        None if !undetermined => f64::INFINITY,
        None => held_to_n,
    }
}

/// Margins of a grasp.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MarginReport {
    /// The model whose criterion was used.
    pub model: ModelKind,
    /// Characteristic length `L`, m.
    pub length_m: f64,
    /// Load scale, N (the unit of the growth step; the cap is `max_factor` times it).
    pub load_scale_n: f64,
    /// Loaded fingers that already slide as a whole without disturbance (coulomb model; a
    /// receiving finger settling, a releasing one letting go): not judged by sliding, since the
    /// disturbance is not what makes them slide.
    pub sliding_undisturbed: Vec<String>,
    /// The fingers on mounts (`fingers[i].mount`): these margins are then the compliant
    /// grasp's (a push moves their cores on their springs, which shares the load differently
    /// from rigid cores); empty when every core is rigid.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mounted: Vec<String>,
    /// The hands and servos whose fingers hold the grasp (`hands`, `servos`): the margins are
    /// then the compliant grasp's too (a push moves their bases and jaws on their springs);
    /// empty without them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shared_springs: Vec<String>,
    /// Per direction, in the order given.
    pub directions: Vec<DirectionMargin>,
    /// Index of the direction with the smallest margin among those the grasp resists at all
    /// (among all when it resists none).
    pub smallest: usize,
    /// Directions the grasp does not resist at all (margin 0 although it holds undisturbed:
    /// with commanded loads, a push along the squeeze axis has no equilibrium).
    pub unresisted: Vec<usize>,
    /// Solves over all directions (the undisturbed solve included).
    pub solves: u32,
    /// Wall time of the whole search, s.
    pub time_s: f64,
    /// The warnings of the undisturbed solve (the scene's first): what holds for the grasp
    /// whose margins these are; empty when it gave none.
    #[serde(default)]
    pub warnings: Vec<String>,
}

impl MarginReport {
    /// The report of `margins` (one per direction) found for `model` since `clock` started,
    /// the undisturbed solve counted among the solves.
    pub(crate) fn of(
        model: &GraspModel,
        options: &MarginOptions,
        sliding_undisturbed: Vec<String>,
        margins: Vec<DirectionMargin>,
        clock: Instant,
    ) -> MarginReport {
        let (unresisted, smallest) = unresisted_and_smallest(&margins);
        MarginReport {
            model: model.kind(),
            length_m: options.length_for(model),
            load_scale_n: options.load_scale_for(model),
            solves: 1 + margins.iter().map(|m| m.solves).sum::<u32>(),
            sliding_undisturbed,
            mounted: model
                .fingers
                .iter()
                .filter(|f| f.mount.is_some())
                .map(|f| f.name.clone())
                .collect(),
            shared_springs: model.springs.iter().map(|s| s.name.clone()).collect(),
            directions: margins,
            smallest,
            unresisted,
            time_s: clock.elapsed().as_secs_f64(),
            warnings: Vec::new(),
        }
    }
}

/// A finger is judged by sliding only above this fraction of the load scale: one carrying
/// less touches the object but does not hold it (a ten-thousandth of the load), and its sliding
/// loses nothing. Below it the solvers' own accuracy can set the force: on the padded
/// cylinder's receiving jaws, held at first touch, Clarabel's interior-point answers put
/// 1e-6 to 2e-5 N (of a 15 N load scale) where the native solver puts 1e-15 N, and a margin
/// judged on those forces read 0.0025 N (and 6.04 N) where the grasp carries 2.75 N (and
/// 20.1 N). (`LOADED_FRACTION`, 1e-9, is round-off, for stick counts and utilisation.)
pub const JUDGED_FRACTION: f64 = 1e-4;

/// The frictional fingers of `sol` carrying more than [`JUDGED_FRACTION`] of the load scale
/// that slide as a whole (no sticking element).
pub(crate) fn sliding_fingers(sol: &Solution) -> Vec<String> {
    let judged = JUDGED_FRACTION * sol.load_scale_n;
    sol.fingers_sliding_as_a_whole()
        .filter(|f| f.normal_force_n > judged)
        .map(|f| f.name.clone())
        .collect()
}

/// Whether `sol` holds in `model`'s criterion (see the module); fingers in `exempt` (those
/// already sliding without disturbance) are not judged by sliding.
pub fn holds(model: &GraspModel, sol: &Solution, exempt: &[String]) -> Result<(), Failure> {
    match sol.status {
        SolveStatus::NoEquilibrium => {
            return Err(Failure::NoEquilibrium {
                reason: sol.reason.clone().unwrap_or_default(),
            })
        }
        SolveStatus::NoConvergence => {
            return Err(Failure::NoConvergence {
                reason: sol.reason.clone().unwrap_or_default(),
            })
        }
        _ => {}
    }
    if model.kind() == ModelKind::Coulomb {
        if let Some(finger) = sliding_fingers(sol)
            .into_iter()
            .find(|f| !exempt.contains(f))
        {
            return Err(Failure::Slides { finger });
        }
    }
    Ok(())
}

/// The largest friction utilisation `|Q|/(mu P)` of the judged frictional fingers of `sol`
/// not in `exempt` (coulomb model; `None` for others, or with no such finger).
pub(crate) fn utilisation_of(model: &GraspModel, sol: &Solution, exempt: &[String]) -> Option<f64> {
    if model.kind() != ModelKind::Coulomb {
        return None;
    }
    let loaded = JUDGED_FRACTION * sol.load_scale_n;
    let judged = sol.fingers.iter().zip(&model.fingers).filter(|(f, fm)| {
        fm.n_tangential > 0 && f.normal_force_n > loaded && !exempt.contains(&f.name)
    });
    judged
        .map(|(f, _)| f.friction_utilization)
        .filter(|u| u.is_finite())
        .reduce(f64::max)
}

/// The judged frictional finger ([`JUDGED_FRACTION`]) with the highest friction utilisation.
pub(crate) fn most_utilised(model: &GraspModel, sol: &Solution) -> Option<String> {
    let loaded = JUDGED_FRACTION * sol.load_scale_n;
    sol.fingers
        .iter()
        .zip(&model.fingers)
        .filter(|(f, fm)| fm.n_tangential > 0 && f.normal_force_n > loaded)
        .max_by(|a, b| {
            a.0.friction_utilization
                .total_cmp(&b.0.friction_utilization)
        })
        .map(|(f, _)| f.name.clone())
}

/// The margin along `d` of a grasp that fails undisturbed (`f`): 0, with that failure.
pub(crate) fn failing_undisturbed(d: WrenchDirection, f: &Failure) -> DirectionMargin {
    let stalled = match f {
        Failure::NoConvergence { reason } => {
            Some(format!("the undisturbed step did not converge: {reason}"))
        }
        _ => None,
    };
    DirectionMargin {
        direction: d,
        margin_n: stalled.is_none().then_some(0.0),
        held_to_n: 0.0,
        fails_at_n: stalled.is_none().then_some(0.0),
        force_n: [0.0; 3],
        torque_nm: [0.0; 3],
        bounded: stalled.is_none(),
        failing_finger: match f {
            Failure::Slides { finger } => Some(finger.clone()),
            _ => None,
        },
        failure: Some(f.clone()),
        solves: 0,
        time_s: 0.0,
        stopped_early: None,
        undetermined: stalled,
        solver_fallbacks: 0,
        warnings: Vec::new(),
        other_equilibrium: None,
    }
}

/// The directions not resisted at all (searched, and failing at the smallest magnitude), and
/// the index of the smallest margin among the others (among all when none is resisted).
pub(crate) fn unresisted_and_smallest(margins: &[DirectionMargin]) -> (Vec<usize>, usize) {
    let searched = margins.iter().any(|m| m.solves > 0);
    let unresisted: Vec<usize> = (0..margins.len())
        .filter(|&i| searched && margins[i].margin_n == Some(0.0) && margins[i].failure.is_some())
        .collect();
    let smallest = (0..margins.len())
        .filter(|i| !unresisted.contains(i) || unresisted.len() == margins.len())
        .min_by(|&a, &b| {
            let m = |i: usize| margins[i].margin_or_bound_n();
            m(a).total_cmp(&m(b))
        })
        .unwrap_or(0);
    (unresisted, smallest)
}
