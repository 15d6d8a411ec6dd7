//! The libraries name the options a caller can change as their Rust API spells them
//! (`grasp_model::option_names`); Python says the keyword argument instead (`solver=`,
//! `tolerance=`). Every library text that reaches Python (exception messages, a solution's
//! reason, warnings and fallback, serialised records) goes through [`in_keywords`].
//!
//! Tested from Python (the crate has no Rust test binary): `tests/python/test_option_ranges.py`
//! checks messages of the library that reach Python naming `tolerance=` and `compliance=`,
//! `tests/python/test_plan.py` the planner's naming `objective=` and `max_rate=`.

use grasp_model::Solution;
use grasp_model::{
    option_names::respell, option_names::COMPLIANCE, option_names::SOLVER, option_names::TOLERANCE,
};
use grasp_transfer::plan_option_names as plan;

/// Library option name -> keyword argument of `grasp.solve` / `grasp.transfer` / `grasp.plan`
/// (or, for a relation between two options, the inequality of their keywords). Options
/// without a keyword keep the library's name.
const KEYWORDS: &[(&str, &str)] = &[
    (SOLVER, "solver="),
    (TOLERANCE, "tolerance="),
    (COMPLIANCE, "compliance="),
    (plan::RELEASING, "releasing="),
    (plan::RECEIVING, "receiving="),
    (plan::MIN_SLIP_MARGIN, "min_slip_margin="),
    (plan::MIN_MARGIN, "min_margin="),
    (plan::MIN_LOAD, "min_load="),
    (plan::MAX_LOAD, "max_load="),
    (plan::MAX_RATE, "max_rate="),
    (plan::MAX_SPEED, "max_speed="),
    (plan::OPEN_TO, "open_to="),
    (plan::CLOSE_TO, "close_to="),
    (plan::MIN_APPROACH, "min_approach="),
    (plan::MAX_APPROACH, "max_approach="),
    (plan::MIN_DURATION, "min_duration="),
    (plan::MAX_DURATION, "max_duration="),
    (plan::OBJECTIVE, "objective="),
    (plan::OBJECTIVE_MARGIN, "objective=\"margin\""),
    (plan::DURATION, "duration="),
    (plan::STEPS, "steps="),
    (plan::KEYFRAMES, "keyframes="),
    (plan::MAX_RUNS, "max_runs="),
    (plan::TEMPLATE, "template="),
    (plan::LOAD_ORDER, "min_load < max_load"),
    (plan::DURATION_ORDER, "min_duration <= max_duration"),
    (plan::APPROACH_ORDER, "min_approach < max_approach"),
];

/// `text` with every library option name replaced by its keyword argument.
pub fn in_keywords(text: &str) -> String {
    respell(text, KEYWORDS)
}

/// The solution's texts (reason, warnings, solver fallback) with keywords for option names.
pub fn respell_solution(solution: &mut Solution) {
    solution.respell_options(KEYWORDS);
}
