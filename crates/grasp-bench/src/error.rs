//! Why a benchmark case could not run.

/// Why a benchmark case could not run.
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
}
