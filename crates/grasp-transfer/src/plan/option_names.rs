//! How the planner's messages name what a caller can change (see
//! `grasp_model::option_names`): each [`PlanOptions`](crate::plan::PlanOptions) field as the
//! Rust API spells it, always between backticks; front ends respell them (the CLI:
//! `--max-rate`; Python: `max_rate=`), so no planner message names a command-line flag.

/// Fingers that let go, [`crate::plan::PlanOptions::releasing`].
pub const RELEASING: &str = "PlanOptions::releasing";
/// Fingers that take over, [`crate::plan::PlanOptions::receiving`].
pub const RECEIVING: &str = "PlanOptions::receiving";
/// Smallest slip margin, [`crate::plan::PlanOptions::min_slip_margin`].
pub const MIN_SLIP_MARGIN: &str = "PlanOptions::min_slip_margin";
/// Smallest disturbance margin, [`crate::plan::PlanOptions::min_margin_n`].
pub const MIN_MARGIN: &str = "PlanOptions::min_margin_n";
/// Smallest planned load, [`crate::plan::PlanOptions::min_load_n`].
pub const MIN_LOAD: &str = "PlanOptions::min_load_n";
/// Largest planned load, [`crate::plan::PlanOptions::max_load_n`].
pub const MAX_LOAD: &str = "PlanOptions::max_load_n";
/// Largest load rate, [`crate::plan::PlanOptions::max_rate_n_per_s`].
pub const MAX_RATE: &str = "PlanOptions::max_rate_n_per_s";
/// Largest approach speed, [`crate::plan::PlanOptions::max_speed_m_per_s`].
pub const MAX_SPEED: &str = "PlanOptions::max_speed_m_per_s";
/// Where releasing jaws end, [`crate::plan::PlanOptions::open_to_m`].
pub const OPEN_TO: &str = "PlanOptions::open_to_m";
/// Where receiving jaws close to, [`crate::plan::PlanOptions::close_to_m`].
pub const CLOSE_TO: &str = "PlanOptions::close_to_m";
/// Smallest planned approach, [`crate::plan::PlanOptions::min_approach_m`].
pub const MIN_APPROACH: &str = "PlanOptions::min_approach_m";
/// Largest planned approach, [`crate::plan::PlanOptions::max_approach_m`].
pub const MAX_APPROACH: &str = "PlanOptions::max_approach_m";
/// Shortest duration, [`crate::plan::PlanOptions::min_duration_s`].
pub const MIN_DURATION: &str = "PlanOptions::min_duration_s";
/// Longest duration, [`crate::plan::PlanOptions::max_duration_s`].
pub const MAX_DURATION: &str = "PlanOptions::max_duration_s";
/// The objective, [`crate::plan::PlanOptions::objective`].
pub const OBJECTIVE: &str = "PlanOptions::objective";
/// The objective set to the largest smallest margin, [`crate::plan::Objective::Margin`].
pub const OBJECTIVE_MARGIN: &str = "Objective::Margin";
/// The duration, [`crate::plan::PlanOptions::duration_s`].
pub const DURATION: &str = "PlanOptions::duration_s";
/// Steps after the first, [`crate::plan::PlanOptions::steps`].
pub const STEPS: &str = "PlanOptions::steps";
/// Keyframes per finger, [`crate::plan::PlanOptions::keyframes`].
pub const KEYFRAMES: &str = "PlanOptions::keyframes";
/// Most hand-off runs, [`crate::plan::PlanOptions::max_runs`].
pub const MAX_RUNS: &str = "PlanOptions::max_runs";
/// The planner's stopping tolerance, [`crate::plan::PlanOptions::tolerance`].
pub const TOLERANCE: &str = "PlanOptions::tolerance";
/// The schedule to start from and compare with, [`crate::plan::Template`] (the second
/// argument of [`crate::plan::plan`]).
pub const TEMPLATE: &str = "plan::Template";
/// The order of the load bounds, [`MIN_LOAD`] below [`MAX_LOAD`]: one name for the relation,
/// which front ends spell as they write an inequality between two of their options.
pub const LOAD_ORDER: &str = "PlanOptions::min_load_n < PlanOptions::max_load_n";
/// The order of the duration bounds, [`MIN_DURATION`] at most [`MAX_DURATION`] (as
/// [`LOAD_ORDER`]).
pub const DURATION_ORDER: &str = "PlanOptions::min_duration_s <= PlanOptions::max_duration_s";
/// The order of the approach bounds, [`MIN_APPROACH`] below [`MAX_APPROACH`] (as
/// [`LOAD_ORDER`]).
pub const APPROACH_ORDER: &str = "PlanOptions::min_approach_m < PlanOptions::max_approach_m";
