//! Errors of the contact-model crate.
//!
//! Bad input is an error that names the field (as a JSON path) and the fix. Solver outcomes
//! (infeasible grasp, no convergence) are NOT errors: they are [`crate::SolveStatus`] values in
//! a [`crate::Solution`].

use std::fmt;

use serde::{Deserialize, Serialize};

/// One problem found in an input (a scene, a schedule, a batch line): where, what, and how to
/// fix it. The one problem type of every input the project reads; the CLI prints it, batch
/// lines and the Python exceptions carry it as is.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputProblem {
    /// JSON path of the offending field, e.g. `fingers[2].normal`.
    pub path: String,
    /// What is wrong.
    pub message: String,
    /// What to do about it.
    pub fix: String,
}

impl InputProblem {
    /// A problem at `path`.
    pub fn new(
        path: impl Into<String>,
        message: impl Into<String>,
        fix: impl Into<String>,
    ) -> Self {
        InputProblem {
            path: path.into(),
            message: message.into(),
            fix: fix.into(),
        }
    }
}

impl fmt::Display for InputProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}; fix: {}", self.path, self.message, self.fix)
    }
}

/// `the {what} has N problem(s):` followed by one problem per line.
pub fn format_problems(what: &str, p: &[InputProblem]) -> String {
    let mut s = format!("the {what} has {} problem(s):", p.len());
    for q in p {
        s.push_str("\n  - ");
        s.push_str(&q.to_string());
    }
    s
}

/// An allocation the system refused (a memory or address-space limit), reported instead of
/// aborting the process: what it was for and how many bytes it needed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("not enough memory for {what} ({}); fix: {}", mebibytes(*bytes), OutOfMemory::FIX)]
pub struct OutOfMemory {
    /// What the memory was for, e.g. `the 512 x 512 influence spectra of finger `tip``.
    pub what: String,
    /// Bytes needed.
    pub bytes: u64,
}

impl OutOfMemory {
    /// What to do about it.
    pub const FIX: &'static str = "use a coarser grid, or free memory or raise the memory \
                                   limit (or solve fewer scenes at once)";

    /// `bytes` refused for `what`.
    pub fn new(what: impl Into<String>, bytes: u64) -> Self {
        OutOfMemory {
            what: what.into(),
            bytes,
        }
    }

    /// The same failure said of `what`, which needs `bytes` in all.
    pub fn named(self, what: impl Into<String>, bytes: u64) -> Self {
        OutOfMemory::new(what, bytes.max(self.bytes))
    }

    /// What failed, without the fix: `not enough memory for ... (N MiB)`.
    pub fn message(&self) -> String {
        format!(
            "not enough memory for {} ({})",
            self.what,
            mebibytes(self.bytes)
        )
    }
}

/// Bytes as MiB with one decimal.
fn mebibytes(bytes: u64) -> String {
    format!("{:.1} MiB", bytes as f64 / (1u64 << 20) as f64)
}

/// A scene that cannot be used.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SceneError {
    /// The text is not valid JSON of the scene format (syntax, types, unknown fields).
    #[error("{path}: {message}")]
    Parse {
        /// JSON path where parsing stopped (`.` for the top level).
        path: String,
        /// The parser's message.
        message: String,
    },
    /// The scene parsed but some values are unusable; every problem found is listed.
    #[error("{}", format_problems("scene", .0))]
    Invalid(Vec<InputProblem>),
    /// The model of a valid scene could not be built in the memory there is.
    #[error("{path}: {source}")]
    OutOfMemory {
        /// JSON path of the finger's grid whose buffers were refused.
        path: String,
        /// What was refused.
        #[source]
        source: OutOfMemory,
    },
}

impl SceneError {
    /// Every problem as (path, message, fix); a parse error is a single problem.
    pub fn problems(&self) -> Vec<InputProblem> {
        match self {
            SceneError::Parse { path, message } => vec![InputProblem {
                path: path.clone(),
                message: message.clone(),
                fix: "correct the JSON (see `grasp schema`)".into(),
            }],
            SceneError::Invalid(p) => p.clone(),
            SceneError::OutOfMemory { path, source } => vec![InputProblem {
                path: path.clone(),
                message: source.message(),
                fix: OutOfMemory::FIX.into(),
            }],
        }
    }
}

/// An option of a solve or an analysis outside the range it can have (see
/// [`crate::SolveOptions::validate`]). The option is named as the Rust API spells it, between
/// backticks ([`crate::option_names`]), so that front ends can respell it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("`{option}` is {value}; {expected}")]
pub struct OptionError {
    /// The option, e.g. `SolveOptions::tolerance`.
    pub option: &'static str,
    /// The value given, as text (numbers in [`crate::number_text::readable`] form).
    pub value: String,
    /// The range the option must lie in and why, with an example.
    pub expected: String,
}

/// Errors raised while assembling or running the cone program that are not solver outcomes:
/// they indicate a bug or an input that validation should have caught.
#[derive(Debug, Clone, thiserror::Error)]
pub enum ModelError {
    /// A prescribed load vector has the wrong length.
    #[error("expected {expected} prescribed loads (one per force-controlled finger), got {got}")]
    LoadCount {
        /// Number of force-controlled fingers.
        expected: usize,
        /// Number of loads given.
        got: usize,
    },
    /// A prescribed load is negative or not finite.
    #[error(
        "prescribed load of finger `{finger}` is {} N; it must be finite and >= 0",
        crate::number_text::Readable(*value)
    )]
    BadLoad {
        /// Finger name.
        finger: String,
        /// The value given.
        value: f64,
    },
    /// A solve's inputs do not fit the model (an approach of a finger the model lacks or of a
    /// force-controlled one).
    #[error("{0}")]
    BadInput(String),
    /// A contact state built for another model was passed to a solve.
    #[error("the contact state does not belong to this model (finger names or element counts differ); build it with ContactState::new(model)")]
    StateMismatch,
    /// Sensitivities were asked of a solve without forces, or of another solver's solution.
    #[error("sensitivities need a solved grasp from this solver; solve first and check that the status is solved")]
    NoSolution,
    /// The KKT system at the solution's active set could not be solved.
    #[error("the derivative at the solution could not be computed: {0}")]
    Derivative(String),
    /// Clarabel refused the problem data.
    #[error("the cone solver rejected the problem: {0}")]
    Solver(String),
    /// An option outside its range.
    #[error(transparent)]
    Option(#[from] OptionError),
    /// The solve's working memory could not be had.
    #[error(transparent)]
    OutOfMemory(#[from] OutOfMemory),
    /// A scene derived from the caller's (a coarser grid, a grown patch) is not usable.
    #[error("{context}: {source}")]
    DerivedScene {
        /// Which derived scene (e.g. `the grid half as fine`).
        context: String,
        /// Its problems.
        #[source]
        source: SceneError,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A model refused its memory is one problem at the finger's grid: the message says what
    /// and how much (in MiB), the fix says what to do.
    #[test]
    fn out_of_memory_is_one_problem_at_its_grid_with_the_fix() {
        let e = SceneError::OutOfMemory {
            path: "fingers[1].patch.grid".into(),
            source: OutOfMemory::new("a buffer", 8 << 20).named("the spectra of `b`", 3 << 20),
        };
        let p = e.problems();
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].path, "fingers[1].patch.grid");
        // The larger of the failed allocation and the named need.
        assert_eq!(
            p[0].message,
            "not enough memory for the spectra of `b` (8.0 MiB)"
        );
        assert_eq!(p[0].fix, OutOfMemory::FIX);
        assert_eq!(
            e.to_string(),
            format!(
                "fingers[1].patch.grid: {}; fix: {}",
                p[0].message,
                OutOfMemory::FIX
            )
        );
    }
}
