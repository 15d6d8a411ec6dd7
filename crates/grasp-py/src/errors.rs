//! The exceptions of the package: bad scenes and schedules carry the list of problems found
//! (JSON path, message, fix); everything else the library refuses is a `GraspError`. Solver
//! outcomes (no equilibrium, no convergence) are not exceptions: they are a solution's status.

use grasp_model::InputProblem;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

create_exception!(
    grasp,
    SceneError,
    PyValueError,
    "A scene that cannot be used. `problems` lists every problem found, each a dict with \
     `path` (JSON path of the field, e.g. `fingers[2].normal`), `message` and `fix`."
);
create_exception!(
    grasp,
    ScheduleError,
    PyValueError,
    "A load schedule that cannot be used. `problems` lists every problem found, each a dict \
     with `path`, `message` and `fix`."
);
create_exception!(
    grasp,
    GraspError,
    PyRuntimeError,
    "The library refused a request that is not a scene or schedule problem (an output file \
     that exists, a sink that failed to write, a step whose active fingers are not a usable \
     scene)."
);

/// The exception `E` with message `message` and attribute `problems` (list of dicts).
fn with_problems<E: pyo3::PyTypeInfo>(
    py: Python<'_>,
    message: String,
    problems: &[InputProblem],
) -> PyErr {
    // The library names options as its Rust API spells them: here, as keyword arguments.
    let words = crate::keywords::in_keywords;
    let err = PyErr::from_type(py.get_type::<E>(), words(&message));
    let list = PyList::empty(py);
    for p in problems {
        let d = PyDict::new(py);
        let _ = d.set_item("path", &p.path);
        let _ = d.set_item("message", words(&p.message));
        let _ = d.set_item("fix", words(&p.fix));
        let _ = list.append(d);
    }
    let _ = err.value(py).setattr("problems", list);
    err
}

/// A `grasp.SceneError` from the model's error; Python's `MemoryError` when the scene is
/// valid but its model did not fit in memory (what did not fit, and the fix).
pub fn scene_error(py: Python<'_>, origin: &str, e: &grasp_model::SceneError) -> PyErr {
    if let grasp_model::SceneError::OutOfMemory { .. } = e {
        return pyo3::exceptions::PyMemoryError::new_err(format!("{origin}: {e}"));
    }
    with_problems::<SceneError>(
        py,
        format!("{origin} is not a usable scene: {e}"),
        &e.problems(),
    )
}

/// A `grasp.ScheduleError` from the driver's error.
pub fn schedule_error(py: Python<'_>, origin: &str, e: &grasp_transfer::ScheduleError) -> PyErr {
    with_problems::<ScheduleError>(
        py,
        format!("{origin} is not a usable schedule: {e}"),
        &e.problems(),
    )
}

/// A `grasp.GraspError` with the error's message (library option names as keywords).
pub fn grasp_error(e: impl std::fmt::Display) -> PyErr {
    GraspError::new_err(crate::keywords::in_keywords(&e.to_string()))
}
