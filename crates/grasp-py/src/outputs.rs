//! Output files of a Python-driven run: the project's one output policy
//! (`grasp_io::OutputSet`, the same code as the CLI's), so the same refusals (a folder, a
//! symbolic link, a dangling one too, a device, an input of the run, the same file twice), the
//! same lock (a second run, in another process or another thread, is refused and told who
//! writes the file), and exclusive, unguessable temporary files moved into place only when the
//! run completes. Two differences, both of the front end: `overwrite=True` is the CLI's
//! `--force`, and a missing folder is refused (the CLI creates it and says so).
//!
//! The pure-Python writers of the package (`grasp.mujoco`) use the same policy through
//! [`check_outputs`] (targets checked and their locks tried before the work) and
//! [`write_outputs`] (several files claimed, written to temporary files and moved into place
//! together).

use std::path::{Path, PathBuf};

use grasp_io::{OutputError, OutputErrorKind, OutputRules, OutputSet, RunInputs};
use pyo3::exceptions::{PyFileExistsError, PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::errors::GraspError;

/// Checks and locks the `targets` (each with the keyword it came from) of a run that reads
/// `inputs`; the lock is held until the returned set is dropped.
pub fn claim(
    targets: &[(&str, &Path)],
    inputs: &RunInputs,
    overwrite: bool,
) -> PyResult<OutputSet> {
    let paths: Vec<&Path> = targets.iter().map(|(_, p)| *p).collect();
    OutputSet::claim(&paths, inputs, rules(overwrite)).map_err(|e| output_error(targets, &e))
}

/// A Python exception for an output refused: `FileExistsError` (exists without
/// `overwrite=True`, or appeared during the run), `FileNotFoundError` (no such folder),
/// `ValueError` (not a file one may write: a folder, a link, a device, an input, twice),
/// `grasp.GraspError` (another run holds it), `OSError` (the file system refused). The
/// message starts with the keyword the target came from.
pub fn output_error(targets: &[(&str, &Path)], e: &OutputError) -> PyErr {
    output_error_saying(targets, e, "overwrite=True")
}

/// [`output_error`], the library's force option named `force_name`.
fn output_error_saying(targets: &[(&str, &Path)], e: &OutputError, force_name: &str) -> PyErr {
    let text = grasp_model::option_names::respell(&e.to_string(), &[(grasp_io::FORCE, force_name)]);
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

/// The rules of a Python run: `overwrite` is the CLI's `--force`; missing folders are refused.
fn rules(overwrite: bool) -> OutputRules {
    OutputRules {
        force: overwrite,
        create_folders: false,
    }
}

/// Checks the `targets` of a run that reads `inputs` against the output policy and tries
/// their locks (a target another run is writing is refused, naming it), then lets them go:
/// the check before a long computation. `force_name` is how messages name `overwrite`.
#[pyfunction]
#[pyo3(name = "_check_outputs",
       signature = (targets, *, overwrite=false, inputs=Vec::new(), force_name="overwrite=True"))]
pub fn check_outputs(
    py: Python<'_>,
    targets: Vec<PathBuf>,
    overwrite: bool,
    inputs: Vec<PathBuf>,
    force_name: &str,
) -> PyResult<()> {
    let paths: Vec<&Path> = targets.iter().map(PathBuf::as_path).collect();
    let run_inputs = RunInputs::of_paths(&inputs.iter().map(PathBuf::as_path).collect::<Vec<_>>());
    py.allow_threads(|| OutputSet::claim(&paths, &run_inputs, rules(overwrite)).map(drop))
        .map_err(|e| output_error_saying(&[], &e, force_name))
}

/// Writes `contents` (a list of (path, bytes)) all together under the output policy: every
/// target checked and locked, each written to its exclusive temporary file, the inputs checked
/// again, then all moved into place; on any refusal nothing is written and the temporary files
/// are removed. The GIL is released while writing.
#[pyfunction]
#[pyo3(name = "_write_outputs",
       signature = (contents, *, overwrite=false, inputs=Vec::new(), force_name="overwrite=True"))]
pub fn write_outputs(
    py: Python<'_>,
    contents: Vec<(PathBuf, Bound<'_, PyBytes>)>,
    overwrite: bool,
    inputs: Vec<PathBuf>,
    force_name: &str,
) -> PyResult<()> {
    let files: Vec<(&Path, &[u8])> = contents
        .iter()
        .map(|(p, b)| (p.as_path(), b.as_bytes()))
        .collect();
    let input_paths: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    py.allow_threads(|| -> Result<(), OutputError> {
        let paths: Vec<&Path> = files.iter().map(|(p, _)| *p).collect();
        let set = OutputSet::claim(&paths, &RunInputs::of_paths(&input_paths), rules(overwrite))?;
        let mut pending = Vec::with_capacity(files.len());
        for (path, bytes) in &files {
            let mut p = set.create(path)?;
            p.write_all(bytes)?;
            pending.push(p);
        }
        set.refuse_inputs(&RunInputs::of_paths(&input_paths))?;
        set.commit(pending)
    })
    .map_err(|e| output_error_saying(&[], &e, force_name))
}
