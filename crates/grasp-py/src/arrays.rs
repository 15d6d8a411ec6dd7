//! NumPy arrays from Rust slices, made through NumPy's own Python API (`numpy.frombuffer`,
//! then a copy the array owns), so the extension needs no NumPy headers and no compiled
//! dependency beyond the interpreter.

use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyList, PyTuple};

/// A float64 array of `shape` (row-major) holding `data`.
pub fn float_array<'py>(
    py: Python<'py>,
    data: &[f64],
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_ne_bytes()).collect();
    from_bytes(py, &bytes, "float64", shape)
}

/// An int64 array of `shape` (row-major) holding `data`.
pub fn int_array<'py>(
    py: Python<'py>,
    data: &[i64],
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_ne_bytes()).collect();
    from_bytes(py, &bytes, "int64", shape)
}

/// A NumPy array of strings (dtype `<U`), one per item.
pub fn str_array<'py>(py: Python<'py>, items: &[&str]) -> PyResult<Bound<'py, PyAny>> {
    let np = py.import("numpy")?;
    np.call_method1("array", (PyList::new(py, items)?, "str"))
}

fn from_bytes<'py>(
    py: Python<'py>,
    bytes: &[u8],
    dtype: &str,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let np = py.import("numpy")?;
    let flat = np.call_method1("frombuffer", (PyBytes::new(py, bytes), dtype))?;
    let shaped = flat.call_method1("reshape", (PyTuple::new(py, shape)?,))?;
    // frombuffer views the (immutable) bytes: copy so the array is writable and its own.
    shaped.call_method0("copy")
}
