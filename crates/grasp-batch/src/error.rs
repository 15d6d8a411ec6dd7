//! Errors of a batch that stop it (unreadable inputs, an output that cannot be written, shards
//! that do not fit together). A bad scene is not one of them: it becomes an `invalid` line.

use std::path::PathBuf;

use crate::option_names;

/// An error that stops a batch.
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    /// An input or output file could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong, with the fix where there is one.
        message: String,
    },
    /// A flag or environment value is unusable.
    #[error("{what}: {message}")]
    Usage {
        /// The flag or variable (e.g. `--shard`, `SLURM_ARRAY_TASK_ID`).
        what: String,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// An input file that cannot be read (not a regular file, too large, ...).
    #[error(transparent)]
    Input(#[from] grasp_io::InputFileError),
    /// Scenes of the input share an id (every id is listed with its lines).
    #[error("{0}")]
    DuplicateIds(String),
    /// An output given to resume that is not this batch's own output (nothing was changed).
    #[error("{}: {message}", path.display())]
    NotBatchOutput {
        /// The output.
        path: PathBuf,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// Shard outputs that do not make one complete run.
    #[error("cannot merge: {0}")]
    Merge(String),
    /// A sweep specification that cannot be expanded.
    #[error("`{}` `{spec}`: {message}", option_names::SWEEP_AXIS)]
    Sweep {
        /// The `--vary` argument.
        spec: String,
        /// What is wrong and how to fix it.
        message: String,
    },
}

/// An I/O error naming the file.
pub(crate) fn io(path: &std::path::Path, e: impl std::fmt::Display) -> BatchError {
    BatchError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}
