//! Why a benchmark case, or a row of the table around the cases, could not be measured.

use std::path::PathBuf;

/// Why a benchmark case, or a row of the table around the cases, could not be measured.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// A bundled scene or schedule did not load (a bug in the bundled inputs).
    #[error("bench case {case}: {message}")]
    Input {
        /// The case's name.
        case: String,
        /// What went wrong.
        message: String,
    },
    /// The solve or the hand-off failed.
    #[error("bench case {case}: {message}")]
    Run {
        /// The case's name.
        case: String,
        /// What went wrong.
        message: String,
    },
    /// A scratch folder, a file in it, or the timed `grasp transfer` process could not be
    /// made or run (the message says what the bench was doing; the cause is the source).
    #[error("{doing}")]
    Io {
        /// What the bench was doing, e.g. `creating /tmp/grasp-bench-...`.
        doing: String,
        /// Why it failed.
        #[source]
        source: std::io::Error,
    },
    /// Every fresh name tried for a scratch folder was taken.
    #[error("cannot create a fresh scratch folder in {}", base.display())]
    NoScratchFolder {
        /// The temporary folder the scratch folder was to be made in.
        base: PathBuf,
    },
    /// The timed `grasp transfer` exited with a failure.
    #[error("grasp transfer failed in the bench: {stderr}")]
    TransferCommand {
        /// What it printed on standard error.
        stderr: String,
    },
    /// The batch runner (or the sweep making its variants) failed.
    #[error(transparent)]
    Batch(#[from] grasp_batch::BatchError),
    /// The batch runner solved fewer variants than it was given.
    #[error("batch bench: {solved} of {variants} variants solved")]
    BatchUnsolved {
        /// Variants solved.
        solved: usize,
        /// Variants given.
        variants: usize,
    },
}
