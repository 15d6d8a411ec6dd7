//! How library messages name the options a caller can change. The library spells an option as
//! its Rust API does (`SolveOptions::solver`), always between backticks; each front end
//! rewrites these names into its own spelling with [`respell`] (the CLI: `--solver`; Python:
//! `solver=`), so no library message names a command-line flag.

/// The solver choice, [`crate::SolveOptions::solver`].
pub const SOLVER: &str = "SolveOptions::solver";
/// The form of the patch compliances (dense matrix or FFT operator),
/// [`crate::SolveOptions::compliance`].
pub const COMPLIANCE: &str = "SolveOptions::compliance";
/// The scaled program's tolerance, [`crate::SolveOptions::tolerance`].
pub const TOLERANCE: &str = "SolveOptions::tolerance";
/// Iterations of one convex solve, [`crate::SolveOptions::max_iterations`].
pub const MAX_ITERATIONS: &str = "SolveOptions::max_iterations";
/// Time limit of one Clarabel solve, [`crate::SolveOptions::time_limit_s`].
pub const TIME_LIMIT: &str = "SolveOptions::time_limit_s";
/// Convergence of the sequential solve, [`crate::SolveOptions::sequential_tolerance`].
pub const SEQUENTIAL_TOLERANCE: &str = "SolveOptions::sequential_tolerance";
/// Convex solves of one sequential solve, [`crate::SolveOptions::max_sequential_iterations`].
pub const MAX_SEQUENTIAL_ITERATIONS: &str = "SolveOptions::max_sequential_iterations";
/// Smallest relaxation of the sequential solve, [`crate::SolveOptions::min_relaxation`].
pub const MIN_RELAXATION: &str = "SolveOptions::min_relaxation";
/// The margins' characteristic length,
/// [`crate::analysis::margin_report::MarginOptions::length_m`].
pub const MARGIN_LENGTH: &str = "MarginOptions::length_m";
/// The margins' final bracket width,
/// [`crate::analysis::margin_report::MarginOptions::relative_tolerance`].
pub const MARGIN_TOLERANCE: &str = "MarginOptions::relative_tolerance";
/// The margins' cap over the load scale,
/// [`crate::analysis::margin_report::MarginOptions::max_factor`].
pub const MARGIN_MAX_FACTOR: &str = "MarginOptions::max_factor";
/// The margins' load scale,
/// [`crate::analysis::margin_report::MarginOptions::load_scale_n`].
pub const MARGIN_LOAD_SCALE: &str = "MarginOptions::load_scale_n";
/// Growing curved patches until their boundary is unloaded,
/// [`crate::analysis::patch_sizing::auto_patch`].
pub const AUTO_PATCH: &str = "patch_sizing::auto_patch";

/// `text` with every option name of `spelling` (pairs of library name and the front end's
/// spelling, names without backticks) replaced where it stands between backticks.
pub fn respell(text: &str, spelling: &[(&str, &str)]) -> String {
    let mut out = text.to_string();
    for (name, spelled) in spelling {
        out = out.replace(&format!("`{name}`"), &format!("`{spelled}`"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn respells_only_names_between_backticks() {
        let table = [(SOLVER, "--solver")];
        let text = format!("set `{SOLVER}` to clarabel; SolveOptions::solver stays");
        assert_eq!(
            respell(&text, &table),
            "set `--solver` to clarabel; SolveOptions::solver stays"
        );
    }
}
