//! The libraries name the options a caller can change as their Rust API spells them
//! (`grasp_model::option_names`); Python says the keyword argument instead (`solver=`,
//! `tolerance=`). Every library text that reaches Python (exception messages, a solution's
//! reason, warnings and fallback, serialised records) goes through [`in_keywords`].
//!
//! Tested from Python (the crate has no Rust test binary): `tests/python/test_option_ranges.py`
//! checks messages of the library that reach Python naming `tolerance=` and `compliance=`.

use grasp_model::Solution;
use grasp_model::{
    option_names::respell, option_names::COMPLIANCE, option_names::SOLVER, option_names::TOLERANCE,
};

/// Library option name -> keyword argument of `grasp.solve` / `grasp.transfer`. Options
/// without a keyword keep the library's name.
const KEYWORDS: &[(&str, &str)] = &[
    (SOLVER, "solver="),
    (TOLERANCE, "tolerance="),
    (COMPLIANCE, "compliance="),
];

/// `text` with every library option name replaced by its keyword argument.
pub fn in_keywords(text: &str) -> String {
    respell(text, KEYWORDS)
}

/// The solution's texts (reason, warnings, solver fallback) with keywords for option names.
pub fn respell_solution(solution: &mut Solution) {
    solution.respell_options(KEYWORDS);
}
