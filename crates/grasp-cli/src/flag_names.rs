//! The libraries name the options a user can change as their Rust API spells them
//! (`grasp_model::option_names`, `grasp_batch::option_names`,
//! `grasp_transfer::plan_option_names`); the CLI says the flag instead.

use grasp_model::Solution;
use grasp_model::{
    option_names::respell, option_names::AUTO_PATCH, option_names::COMPLIANCE,
    option_names::MARGIN_LENGTH, option_names::MARGIN_TOLERANCE, option_names::SOLVER,
    option_names::TOLERANCE,
};
use grasp_transfer::plan_option_names as plan;

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

/// The planner's option names (`grasp_transfer::plan_option_names`) -> what `grasp plan` says:
/// its flag, bare (`--max-rate: must be ...`, not between backticks), or its inequality of two
/// flags.
const PLAN_FLAGS: &[(&str, &str)] = &[
    (plan::RELEASING, "--releasing"),
    (plan::RECEIVING, "--receiving"),
    (plan::MIN_SLIP_MARGIN, "--min-slip-margin"),
    (plan::MIN_MARGIN, "--min-margin"),
    (plan::MIN_LOAD, "--min-load"),
    (plan::MAX_LOAD, "--max-load"),
    (plan::MAX_RATE, "--max-rate"),
    (plan::MAX_SPEED, "--max-speed"),
    (plan::OPEN_TO, "--open-to"),
    (plan::CLOSE_TO, "--close-to"),
    (plan::MIN_APPROACH, "--min-approach"),
    (plan::MAX_APPROACH, "--max-approach"),
    (plan::MIN_DURATION, "--min-duration"),
    (plan::MAX_DURATION, "--max-duration"),
    (plan::OBJECTIVE, "--objective"),
    (plan::OBJECTIVE_MARGIN, "--objective margin"),
    (plan::DURATION, "--duration"),
    (plan::STEPS, "--steps"),
    (plan::KEYFRAMES, "--keyframes"),
    (plan::MAX_RUNS, "--max-runs"),
    (plan::TEMPLATE, "--template"),
    (plan::LOAD_ORDER, "min-load < max-load"),
    (plan::DURATION_ORDER, "min-duration <= max-duration"),
    (plan::APPROACH_ORDER, "min-approach < max-approach"),
];

/// `text` with every library option name replaced by its flag.
pub fn in_flags(text: &str) -> String {
    let text = respell(text, FLAGS);
    PLAN_FLAGS.iter().fold(text, |t, (name, flag)| {
        t.replace(&format!("`{name}`"), flag)
    })
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

    #[test]
    fn planner_options_are_bare_flags() {
        let text = format!(
            "`{}`: needs 0 <= `{}`; give `{}`, or `{}`",
            plan::MIN_LOAD,
            plan::LOAD_ORDER,
            plan::MAX_RATE,
            plan::OBJECTIVE_MARGIN
        );
        assert_eq!(
            in_flags(&text),
            "--min-load: needs 0 <= min-load < max-load; give --max-rate, or --objective margin"
        );
    }
}
