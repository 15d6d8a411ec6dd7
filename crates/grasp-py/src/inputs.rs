//! Input files read by the pure-Python part of the package (`grasp.mujoco`: state files,
//! rollouts, material maps, and the MuJoCo model checked before MuJoCo reads it): the project's
//! one input policy (`grasp_io::InputFile`, the same code as the CLI's), so a FIFO, a device
//! (`/dev/zero`) or a folder is refused before it is opened, and a file larger than its kind's
//! limit before it is read.

use std::path::PathBuf;

use grasp_io::{
    read_bytes, InputFile, InputFileError, InputKind, MATERIAL_MAP, MUJOCO_MODEL, MUJOCO_ROLLOUT,
    MUJOCO_STATE,
};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// The kinds Python may name: name -> kind.
const KINDS: &[(&str, InputKind)] = &[
    ("mujoco_model", MUJOCO_MODEL),
    ("mujoco_state", MUJOCO_STATE),
    ("mujoco_rollout", MUJOCO_ROLLOUT),
    ("material_map", MATERIAL_MAP),
];

fn kind_of(name: &str) -> PyResult<InputKind> {
    KINDS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, k)| *k)
        .ok_or_else(|| {
            let names: Vec<&str> = KINDS.iter().map(|(n, _)| *n).collect();
            PyValueError::new_err(format!(
                "kind={name:?}: not a kind of input file; give one of {}",
                names.join(", ")
            ))
        })
}

/// An `OSError` with the whole text, and `message` and `fix` apart.
fn input_error(py: Python<'_>, e: &InputFileError) -> PyErr {
    let err = PyOSError::new_err(e.to_string());
    let _ = err.value(py).setattr("message", &e.message);
    let _ = err.value(py).setattr("fix", &e.fix);
    err
}

/// The whole file at `path`, a regular file within the limit of its `kind` (`OSError` with
/// `message` and `fix` otherwise). The GIL is released while reading.
#[pyfunction]
#[pyo3(name = "_read_input", signature = (path, kind))]
pub fn read_input<'py>(
    py: Python<'py>,
    path: PathBuf,
    kind: &str,
) -> PyResult<Bound<'py, PyBytes>> {
    let kind = kind_of(kind)?;
    let bytes = py
        .allow_threads(|| read_bytes(&path, kind))
        .map_err(|e| input_error(py, &e))?;
    Ok(PyBytes::new(py, &bytes.0))
}

/// Checks that `path` is a regular file within the limit of its `kind`, without reading it
/// (for files another library reads by path).
#[pyfunction]
#[pyo3(name = "_check_input", signature = (path, kind))]
pub fn check_input(py: Python<'_>, path: PathBuf, kind: &str) -> PyResult<()> {
    let kind = kind_of(kind)?;
    py.allow_threads(|| InputFile::open(&path, kind).map(drop))
        .map_err(|e| input_error(py, &e))
}
