//! Height maps given as NumPy arrays in a scene dict: `fingers[i].texture.heights` may be
//! `{"array": a, "pixel_m": [dx, dy]}` instead of `{"file": ..., "pixel_m": ...}` (heights in
//! metres, rows of `a` along `t1`, its centre on the contact point). The arrays are taken out
//! of a copy of the dict before it becomes JSON, [`ARRAY_FILE`] written as their file, and
//! given to the scene reader by finger (`grasp_io::HeightArrays`).

use std::sync::Arc;

use grasp_io::HeightArrays;
use grasp_model::{HeightGrid, InputProblem, SceneError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// The `file` a height map given as an array has in the scene (`Scene.to_dict()` shows it; a
/// scene read again from that dict needs the array again).
pub const ARRAY_FILE: &str = "<array>";

/// How a complex array's message starts.
const COMPLEX: &str = "holds complex numbers";

/// How the message of a masked array with masked heights starts.
const MASKED: &str = "is a masked array with masked heights";

/// `d` with every `fingers[i].texture.heights.array` replaced by `"file": "<array>"` (a copy;
/// `d` itself is not changed), and the arrays by finger. A value that is not a 2-D array of
/// numbers, or an array given with a file, raises `grasp.SceneError` naming the path.
pub fn take_height_arrays<'py>(
    py: Python<'py>,
    origin: &str,
    d: &Bound<'py, PyDict>,
) -> PyResult<(Bound<'py, PyDict>, HeightArrays)> {
    let mut arrays = HeightArrays::new();
    let Some(fingers) = d.get_item("fingers")? else {
        return Ok((d.clone(), arrays));
    };
    let Ok(fingers) = fingers.downcast::<PyList>() else {
        return Ok((d.clone(), arrays));
    };
    let copy = d.copy()?;
    let new_fingers = PyList::empty(py);
    let mut problems = Vec::new();
    for (i, finger) in fingers.iter().enumerate() {
        match heights_of(&finger)? {
            Some(heights) if heights.contains("array")? => {
                let path = format!("fingers[{i}].texture.heights");
                if heights.contains("file")? {
                    problems.push(InputProblem::new(
                        &path,
                        "gives both file and array",
                        "give one: file (a .npy or .csv path) or array (a 2-D NumPy array)",
                    ));
                }
                match grid_of(py, &heights.as_any().get_item("array")?) {
                    Ok(grid) => {
                        arrays.insert(i, Arc::new(grid));
                    }
                    Err(message) => {
                        let fix = match &message {
                            m if m.starts_with(COMPLEX) => {
                                "give the real heights in metres: `a.real` if the imaginary \
                                 parts are zero"
                            }
                            m if m.starts_with(MASKED) => {
                                "fill the masked heights (`a.filled(value)`) or give a plain \
                                 array"
                            }
                            _ => {
                                "give a 2-D array of heights in metres (rows along t1), e.g. a \
                                 NumPy float array"
                            }
                        };
                        problems.push(InputProblem::new(format!("{path}.array"), message, fix))
                    }
                }
                new_fingers.append(with_array_file(&finger, &heights)?)?;
            }
            _ => new_fingers.append(finger)?,
        }
    }
    if !problems.is_empty() {
        return Err(crate::errors::scene_error(
            py,
            origin,
            &SceneError::Invalid(problems),
        ));
    }
    copy.set_item("fingers", new_fingers)?;
    Ok((copy, arrays))
}

/// `finger["texture"]["heights"]` when each is a dict.
fn heights_of<'py>(finger: &Bound<'py, PyAny>) -> PyResult<Option<Bound<'py, PyDict>>> {
    let step = |v: &Bound<'py, PyAny>, key: &str| -> PyResult<Option<Bound<'py, PyDict>>> {
        let Ok(d) = v.downcast::<PyDict>() else {
            return Ok(None);
        };
        Ok(d.get_item(key)?
            .and_then(|x| x.downcast_into::<PyDict>().ok()))
    };
    match step(finger, "texture")? {
        Some(texture) => step(texture.as_any(), "heights"),
        None => Ok(None),
    }
}

/// A copy of `finger` whose `texture.heights` names [`ARRAY_FILE`] instead of holding an array.
fn with_array_file<'py>(
    finger: &Bound<'py, PyAny>,
    heights: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyDict>> {
    let finger = finger.downcast::<PyDict>()?.copy()?;
    let texture = finger
        .get_item("texture")?
        .expect("a texture")
        .downcast_into::<PyDict>()?
        .copy()?;
    let heights = heights.copy()?;
    heights.del_item("array")?;
    if !heights.contains("file")? {
        heights.set_item("file", ARRAY_FILE)?;
    }
    texture.set_item("heights", heights)?;
    finger.set_item("texture", texture)?;
    Ok(finger)
}

/// The heights of a 2-D array of real numbers (through NumPy: `numpy.asarray(a, float64)`, C
/// order). A complex array is refused, as the CLI refuses a complex `.npy` (converting would
/// drop its imaginary parts); so is a masked array with a masked height (its mask would be
/// lost, and the value under it used as a height).
fn grid_of(py: Python<'_>, a: &Bound<'_, PyAny>) -> Result<HeightGrid, String> {
    let np = py.import("numpy").map_err(|e| e.to_string())?;
    let err = |e: PyErr| e.to_string();
    if np
        .call_method1("iscomplexobj", (a,))
        .and_then(|v| v.is_truthy())
        .map_err(err)?
    {
        return Err(format!(
            "{COMPLEX}, not floats or integers (converting would drop their imaginary parts)"
        ));
    }
    let ma = np.getattr("ma").map_err(err)?;
    let masked_array = ma.getattr("MaskedArray").map_err(err)?;
    if a.is_instance(&masked_array).map_err(err)?
        && ma
            .call_method1("getmaskarray", (a,))
            .and_then(|m| m.call_method0("any"))
            .and_then(|v| v.is_truthy())
            .map_err(err)?
    {
        return Err(format!("{MASKED}: a height map has no gaps"));
    }
    let arr = np
        .call_method1("ascontiguousarray", (a, "float64"))
        .map_err(|e| format!("is not an array of numbers: {e}"))?;
    let shape: Vec<usize> = arr
        .getattr("shape")
        .and_then(|s| s.extract())
        .map_err(|e| e.to_string())?;
    let &[rows, cols] = &shape[..] else {
        return Err(format!("has shape {shape:?}, not a 2-D one"));
    };
    if rows == 0 || cols == 0 || rows.saturating_mul(cols) > grasp_io::MAX_PIXELS {
        return Err(format!(
            "holds {rows} x {cols} heights: give at least one and at most {}",
            grasp_io::MAX_PIXELS
        ));
    }
    let bytes: Vec<u8> = arr
        .call_method0("tobytes")
        .and_then(|b| b.extract())
        .map_err(|e| e.to_string())?;
    let heights_m = bytes
        .chunks_exact(8)
        .map(|c| f64::from_ne_bytes(c.try_into().expect("8 bytes")))
        .collect();
    Ok(HeightGrid {
        rows,
        cols,
        heights_m,
    })
}
