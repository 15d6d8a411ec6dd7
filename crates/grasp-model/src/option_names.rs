//! How library messages name the options a caller can change. The library spells an option as
//! its Rust API does (`SolveOptions::solver`), always between backticks; each front end
//! rewrites these names into its own spelling with [`respell`] (the CLI: `--solver`; Python:
//! `solver=`), so no library message names a command-line flag.

/// The solver choice, [`crate::SolveOptions::solver`].
pub const SOLVER: &str = "SolveOptions::solver";
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
