//! The libraries name the options a user can change as their Rust API spells them
//! (`grasp_model::option_names`, `grasp_batch::option_names`); the CLI says the flag instead.

use grasp_model::Solution;
use grasp_model::{
    option_names::respell, option_names::AUTO_PATCH, option_names::COMPLIANCE,
    option_names::MARGIN_LENGTH, option_names::MARGIN_TOLERANCE, option_names::SOLVER,
    option_names::TOLERANCE,
};

/// Library option name -> command-line flag.
const FLAGS: &[(&str, &str)] = &[
    (SOLVER, "--solver"),
    (COMPLIANCE, "--compliance"),
    (TOLERANCE, "--tolerance"),
    (MARGIN_LENGTH, "--length"),
    (MARGIN_TOLERANCE, "--tolerance"),
    (AUTO_PATCH, "--auto-patch"),
    (grasp_batch::option_names::THREADS, "--jobs"),
    (grasp_io::MAX_MEMORY, "--max-memory"),
    (grasp_batch::option_names::SHARD, "--shard"),
    (grasp_batch::option_names::SWEEP_AXIS, "--vary"),
    (grasp_io::FORCE, "--force"),
];

/// `text` with every library option name replaced by its flag.
pub fn in_flags(text: &str) -> String {
    respell(text, FLAGS)
}

/// The solution's texts (reason, warnings, solver fallback) with flags for option names.
pub fn respell_solution(solution: &mut Solution) {
    solution.respell_options(FLAGS);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_library_option_has_a_flag() {
        let text = format!("set `{SOLVER}` to clarabel, or `{AUTO_PATCH}`");
        assert_eq!(
            in_flags(&text),
            "set `--solver` to clarabel, or `--auto-patch`"
        );
        let text = format!("`{TOLERANCE}`, `{MARGIN_LENGTH}`, `{MARGIN_TOLERANCE}`");
        assert_eq!(in_flags(&text), "`--tolerance`, `--length`, `--tolerance`");
    }
}
