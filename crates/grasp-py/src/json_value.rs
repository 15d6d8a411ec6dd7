//! Python objects (dict, list, float, int, str, bool, None) of serialisable records, so every
//! record the library serialises reaches Python with the same field names as the CLI's JSON;
//! and the non-finite numbers of a Python object given as an input.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// Any serialisable record as a Python object, built directly
/// ([`crate::python_serializer`]): the object `json.loads` makes of its JSON text.
pub fn serialize_to_py<'py, T: serde::Serialize>(
    py: Python<'py>,
    record: &T,
) -> PyResult<Bound<'py, PyAny>> {
    crate::python_serializer::to_python(py, record)
}

/// Most problems [`non_finite_numbers`] lists.
const MAX_NON_FINITE_LISTED: usize = 20;

/// Every float in the Python object `v` (dicts, lists, tuples) that is NaN or infinite
/// (Python's `float("nan")`, `math.inf`, and `1e400`, which Python reads as infinity), each
/// named by its JSON path (`fingers[1].material.youngs_modulus`), at most
/// [`MAX_NON_FINITE_LISTED`]: a scene or schedule given as a dict is checked before it is
/// serialised, so the error names the user's field, not a position in a text they never
/// wrote.
pub fn non_finite_numbers(v: &Bound<'_, PyAny>) -> Vec<grasp_model::InputProblem> {
    let mut out = Vec::new();
    walk(v, String::new(), &mut out);
    out
}

fn walk(v: &Bound<'_, PyAny>, path: String, out: &mut Vec<grasp_model::InputProblem>) {
    if out.len() >= MAX_NON_FINITE_LISTED {
        return;
    }
    if let Ok(d) = v.downcast::<PyDict>() {
        for (k, item) in d.iter() {
            let key = k.str().map_or_else(|_| "?".to_string(), |s| s.to_string());
            let p = if path.is_empty() {
                key
            } else {
                format!("{path}.{key}")
            };
            walk(&item, p, out);
        }
    } else if let Ok(l) = v.downcast::<PyList>() {
        for (i, item) in l.iter().enumerate() {
            walk(&item, format!("{path}[{i}]"), out);
        }
    } else if let Ok(t) = v.downcast::<pyo3::types::PyTuple>() {
        for (i, item) in t.iter().enumerate() {
            walk(&item, format!("{path}[{i}]"), out);
        }
    } else if let Ok(f) = v.downcast::<pyo3::types::PyFloat>() {
        let x = f.value();
        if !x.is_finite() {
            out.push(grasp_model::InputProblem::new(
                if path.is_empty() {
                    ".".to_string()
                } else {
                    path
                },
                format!("is {x}"),
                "give a finite number (NaN and infinities are no values here; Python reads \
                 1e400 as infinity)",
            ));
        }
    }
}
