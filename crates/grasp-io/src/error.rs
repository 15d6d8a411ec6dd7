//! Why a file could not be read or an output could not be written: each error names the file,
//! says what is wrong, and how to fix it. Library messages name options as the Rust API spells
//! them (`OutputRules::force`); front ends respell them (`--force`, `overwrite=True`).

use std::path::{Path, PathBuf};

/// An input file that cannot be read.
#[derive(Debug, thiserror::Error)]
#[error("{message}; {fix}")]
pub struct InputFileError {
    /// The file.
    pub path: PathBuf,
    /// What is wrong (names the file).
    pub message: String,
    /// How to fix it.
    pub fix: String,
}

impl InputFileError {
    /// An error of `path`.
    pub(crate) fn new(path: &Path, message: String, fix: &str) -> Self {
        InputFileError {
            path: path.to_path_buf(),
            message,
            fix: fix.to_string(),
        }
    }
}

/// What kind of refusal an [`OutputError`] is (front ends map it to their own error types).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputErrorKind {
    /// The target is not something an output may replace (a folder, a link, a device, an
    /// input of the run, another output of the run, not a file name).
    Refused,
    /// The target exists and replacing was not allowed.
    Exists,
    /// The target's folder does not exist (and folders are not created).
    MissingFolder,
    /// Another run holds the target's lock.
    Locked,
    /// The file system refused (no space, no permission, ...).
    Io,
}

/// An output that cannot be written safely.
#[derive(Debug, thiserror::Error)]
#[error("{}", join(.message, .fix))]
pub struct OutputError {
    /// The kind of refusal.
    pub kind: OutputErrorKind,
    /// The target the user named.
    pub path: PathBuf,
    /// What is wrong (names the target).
    pub message: String,
    /// How to fix it (empty when the message says it all).
    pub fix: String,
}

impl OutputError {
    /// A refusal of `path`.
    pub(crate) fn new(kind: OutputErrorKind, path: &Path, message: String, fix: &str) -> Self {
        OutputError {
            kind,
            path: path.to_path_buf(),
            message,
            fix: fix.to_string(),
        }
    }

    /// The file system refused `action` ("write", "create", ...) on `path`.
    pub(crate) fn io(path: &Path, action: &str, e: &std::io::Error) -> Self {
        OutputError::new(
            OutputErrorKind::Io,
            path,
            format!("cannot {action} {}: {e}", path.display()),
            "",
        )
    }
}

fn join(message: &str, fix: &str) -> String {
    if fix.is_empty() {
        message.to_string()
    } else {
        format!("{message}; {fix}")
    }
}
