//! Output files of a Python-driven run: the project's one output policy
//! (`grasp_io::output_file`, the same code as the CLI's), so the same refusals (a folder, a
//! symbolic link, a dangling one too, a device, an input of the run, the same file twice), the
//! same lock (a second run, in another process or another thread, is refused and told who
//! writes the file), and exclusive, unguessable temporary files moved into place only when the
//! run completes. Two differences, both of the front end: `overwrite=True` is the CLI's
//! `--force`, and a missing folder is refused (the CLI creates it and says so).

use std::path::Path;

use grasp_io::{OutputError, OutputErrorKind, OutputRules, OutputSet, RunInputs};
use pyo3::exceptions::{PyFileExistsError, PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;

use crate::errors::GraspError;

/// Checks and locks the `targets` (each with the keyword it came from) of a run that reads
/// `inputs`; the lock is held until the returned set is dropped.
pub fn claim(
    targets: &[(&str, &Path)],
    inputs: &RunInputs,
    overwrite: bool,
) -> PyResult<OutputSet> {
    let paths: Vec<&Path> = targets.iter().map(|(_, p)| *p).collect();
    let rules = OutputRules {
        force: overwrite,
        create_folders: false,
    };
    OutputSet::claim(&paths, inputs, rules).map_err(|e| output_error(targets, &e))
}

/// A Python exception for an output refused: `FileExistsError` (exists without
/// `overwrite=True`, or appeared during the run), `FileNotFoundError` (no such folder),
/// `ValueError` (not a file one may write: a folder, a link, a device, an input, twice),
/// `grasp.GraspError` (another run holds it), `OSError` (the file system refused). The
/// message starts with the keyword the target came from.
pub fn output_error(targets: &[(&str, &Path)], e: &OutputError) -> PyErr {
    let text = grasp_model::option_names::respell(
        &e.to_string(),
        &[(grasp_io::output_file::FORCE, "overwrite=True")],
    );
    let text = match targets.iter().find(|(_, p)| *p == e.path) {
        Some((name, _)) => format!("{name}: {text}"),
        None => text,
    };
    match e.kind {
        OutputErrorKind::Exists => PyFileExistsError::new_err(text),
        OutputErrorKind::MissingFolder => PyFileNotFoundError::new_err(text),
        OutputErrorKind::Refused => PyValueError::new_err(text),
        OutputErrorKind::Locked => GraspError::new_err(text),
        OutputErrorKind::Io => PyOSError::new_err(text),
    }
}
