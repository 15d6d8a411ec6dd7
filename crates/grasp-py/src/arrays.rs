//! NumPy arrays from Rust slices, made through NumPy's own Python API (`numpy.frombuffer` of
//! a `bytearray` the values are written into once), so the extension needs no NumPy headers and no compiled
//! dependency beyond the interpreter.

use grasp_model::ElementState;
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyList, PyTuple};

/// A float64 array of `shape` (row-major) holding `data`.
pub fn float_array<'py>(
    py: Python<'py>,
    data: &[f64],
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    from_values(py, data, |x| x.to_ne_bytes(), "float64", shape)
}

/// An int64 array of `shape` (row-major) holding `data`.
pub fn int_array<'py>(
    py: Python<'py>,
    data: &[i64],
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    from_values(py, data, |x| x.to_ne_bytes(), "int64", shape)
}

/// A NumPy array of strings (dtype `<U`), one per item.
pub fn str_array<'py>(py: Python<'py>, items: &[&str]) -> PyResult<Bound<'py, PyAny>> {
    let np = py.import("numpy")?;
    np.call_method1("array", (PyList::new(py, items)?, "str"))
}

/// The elements' state names as a NumPy string array (dtype `<U12`), made from their codes:
/// the five names indexed by an int64 array of codes, so no Python string is made per element.
pub fn state_array<'py>(
    py: Python<'py>,
    states: impl Iterator<Item = ElementState>,
) -> PyResult<Bound<'py, PyAny>> {
    use ElementState::*;
    let all = [Stick, Slip, Separated, OffSurface, Frictionless];
    let codes: Vec<i64> = states
        .map(|s| all.iter().position(|a| *a == s).unwrap_or(0) as i64)
        .collect();
    let names = str_array(py, &all.map(|s| s.as_str()))?;
    names.get_item(int_array(py, &codes, &[codes.len()])?)
}

/// The array of `data` (each value as its 8 native-endian `bytes`): the values are written
/// once, into a `bytearray` that the array then views (`numpy.frombuffer` of a `bytearray` is
/// writable and keeps it alive), so no other copy is made.
fn from_values<'py, T: Copy>(
    py: Python<'py>,
    data: &[T],
    bytes: impl Fn(T) -> [u8; 8],
    dtype: &str,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let buffer = PyByteArray::new_with(py, data.len() * 8, |b| {
        for (chunk, &x) in b.chunks_exact_mut(8).zip(data) {
            chunk.copy_from_slice(&bytes(x));
        }
        Ok(())
    })?;
    let np = py.import("numpy")?;
    let flat = np.call_method1("frombuffer", (buffer, dtype))?;
    flat.call_method1("reshape", (PyTuple::new(py, shape)?,))
}
