//! Disturbance margins: for each direction of an extra wrench on the object, the
//! largest magnitude the grasp can take while it still holds in the scene's model.
//!
//! A direction is a unit vector `(f, t)` of the scaled wrench space; magnitude `s` (N) means a
//! force `s f` (N) at the centre of mass plus a couple `s L t` (N m), `L` the characteristic
//! length ([`MarginOptions::length_m`], by default the grasp's reach [`crate::Scales`]
//! `length_m`), so force and torque directions compare at the grasp's size.
//!
//! The grasp **holds** at `s` when
//! - energy model: the program has a solution, i.e. forces within the element cones (and the
//!   commanded loads) balance the load: the rigid-body bound of the patches' cones. (The energy
//!   model's minimum-energy grasp may slide as a whole at no disturbance at all: its held
//!   fingers squeeze no more than friction needs, so sliding is not its failure criterion.)
//! - coulomb model: an equilibrium exists and every loaded frictional finger keeps at least
//!   one sticking element (a finger whose every element slips slides as a whole). A finger
//!   that already slides as a whole without disturbance (a receiving finger settling in a
//!   hand-off) is listed apart and not judged by sliding.
//!

use std::ops::RangeInclusive;

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::analysis::wrench_directions::WrenchDirection;
use crate::error::OptionError;
use crate::model::grasp_model::GraspModel;
use crate::option_names;
use crate::scene::limits::LENGTH_RANGE_M;
use crate::scene::scene_format::ModelKind;
use crate::solve::solution::{Solution, SolveStatus, LOADED_FRACTION};
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
    /// reach (`Scales::length_m`). In the scene's length range [`LENGTH_RANGE_M`].
    pub length_m: Option<f64>,
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
}

impl MarginOptions {
    /// Checks every option against its range and returns the first one outside it, named as
    /// the API spells it ([`option_names`]). [`crate::disturbance_margins`] checks its options; front
    /// ends call this first so that a bad option is refused before any work.
    pub fn validate(&self) -> Result<(), OptionError> {
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

impl Default for MarginOptions {
    fn default() -> Self {
        MarginOptions {
            length_m: None,
            relative_tolerance: 1e-3,
            max_factor: 1e3,
            load_capacity: true,
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
    /// Largest magnitude found to hold, N (the lower end of the final bracket; the cap when
    /// unbounded).
    pub margin_n: f64,
    /// Smallest magnitude found to fail, N (absent when unbounded).
    pub fails_at_n: Option<f64>,
    /// Force part of the wrench at the margin, N (at the centre of mass).
    pub force_n: [f64; 3],
    /// Torque part of the wrench at the margin, N m.
    pub torque_nm: [f64; 3],
    /// False when the grasp still held at the cap.
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
    /// The warnings of the solve at the margin (the largest magnitude that held), the scene's
    /// left out (they are the report's): forces near the margin beyond the model's limits
    /// make the margin approximate too. Absent when none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
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
        length_m: f64,
        sliding_undisturbed: Vec<String>,
        margins: Vec<DirectionMargin>,
        clock: Instant,
    ) -> MarginReport {
        let (unresisted, smallest) = unresisted_and_smallest(&margins);
        MarginReport {
            model: model.kind(),
            length_m,
            load_scale_n: model.scales.load_n,
            solves: 1 + margins.iter().map(|m| m.solves).sum::<u32>(),
            sliding_undisturbed,
            directions: margins,
            smallest,
            unresisted,
            time_s: clock.elapsed().as_secs_f64(),
            warnings: Vec::new(),
        }
    }
}

/// The loaded frictional fingers of `sol` that slide as a whole (no sticking element).
pub(crate) fn sliding_fingers(sol: &Solution) -> Vec<String> {
    sol.fingers_sliding_as_a_whole()
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

/// The largest friction utilisation `|Q|/(mu P)` of the loaded frictional fingers of `sol`
/// not in `exempt` (coulomb model; `None` for others, or with no such finger).
pub(crate) fn utilisation_of(model: &GraspModel, sol: &Solution, exempt: &[String]) -> Option<f64> {
    if model.kind() != ModelKind::Coulomb {
        return None;
    }
    let loaded = LOADED_FRACTION * sol.load_scale_n;
    let judged = sol.fingers.iter().zip(&model.fingers).filter(|(f, fm)| {
        fm.n_tangential > 0 && f.normal_force_n > loaded && !exempt.contains(&f.name)
    });
    judged
        .map(|(f, _)| f.friction_utilization)
        .filter(|u| u.is_finite())
        .reduce(f64::max)
}

/// The loaded frictional finger with the highest friction utilisation.
pub(crate) fn most_utilised(model: &GraspModel, sol: &Solution) -> Option<String> {
    let loaded = LOADED_FRACTION * sol.load_scale_n;
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
    DirectionMargin {
        direction: d,
        margin_n: 0.0,
        fails_at_n: Some(0.0),
        force_n: [0.0; 3],
        torque_nm: [0.0; 3],
        bounded: true,
        failing_finger: match f {
            Failure::Slides { finger } => Some(finger.clone()),
            _ => None,
        },
        failure: Some(f.clone()),
        solves: 0,
        time_s: 0.0,
        stopped_early: None,
        warnings: Vec::new(),
    }
}

/// The directions not resisted at all (searched, and failing at the smallest magnitude), and
/// the index of the smallest margin among the others (among all when none is resisted).
pub(crate) fn unresisted_and_smallest(margins: &[DirectionMargin]) -> (Vec<usize>, usize) {
    let searched = margins.iter().any(|m| m.solves > 0);
    let unresisted: Vec<usize> = (0..margins.len())
        .filter(|&i| searched && margins[i].margin_n == 0.0 && margins[i].failure.is_some())
        .collect();
    let smallest = (0..margins.len())
        .filter(|i| !unresisted.contains(i) || unresisted.len() == margins.len())
        .min_by(|&a, &b| margins[a].margin_n.total_cmp(&margins[b].margin_n))
        .unwrap_or(0);
    (unresisted, smallest)
}
