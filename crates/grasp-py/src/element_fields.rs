//! One finger's element fields as NumPy arrays by field name (`Solution.element_fields`), the
//! arrays `grasp solve --npz` writes for the finger, built from the solution's own numbers.

use grasp_model::ElementSolution;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{float_array, int_array, state_array};

/// The fields of `elements` (see `Solution.element_fields`).
pub fn element_fields<'py>(
    py: Python<'py>,
    elements: &[ElementSolution],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let n = elements.len();
    let index: Vec<i64> = elements
        .iter()
        .flat_map(|e| e.index.map(|i| i as i64))
        .collect();
    d.set_item("index", int_array(py, &index, &[n, 2])?)?;
    let floats = |f: &dyn Fn(&ElementSolution, &mut Vec<f64>), width: usize| {
        let mut v = Vec::with_capacity(n * width);
        elements.iter().for_each(|e| f(e, &mut v));
        match width {
            1 => float_array(py, &v, &[n]),
            w => float_array(py, &v, &[n, w]),
        }
    };
    d.set_item("local_m", floats(&|e, v| v.extend(e.local_m), 2)?)?;
    d.set_item("position_m", floats(&|e, v| v.extend(e.position_m), 3)?)?;
    d.set_item(
        "normal_force_n",
        floats(&|e, v| v.push(e.normal_force_n), 1)?,
    )?;
    d.set_item(
        "tangential_force_n",
        floats(&|e, v| v.extend(e.tangential_force_n), 2)?,
    )?;
    d.set_item("pressure_pa", floats(&|e, v| v.push(e.pressure_pa), 1)?)?;
    d.set_item("traction_pa", floats(&|e, v| v.extend(e.traction_pa), 2)?)?;
    d.set_item("gap_m", floats(&|e, v| v.push(e.gap_m), 1)?)?;
    d.set_item("slip_m", floats(&|e, v| v.extend(e.slip_m), 2)?)?;
    d.set_item("step_slip_m", floats(&|e, v| v.extend(e.step_slip_m), 2)?)?;
    d.set_item("state", state_array(py, elements.iter().map(|e| e.state))?)?;
    // The patch's [nx, ny], as `--npz` writes it: one more than the largest index each way.
    let most = |k: usize| elements.iter().map(|e| e.index[k] as i64 + 1).max();
    let grid = [most(0).unwrap_or(0), most(1).unwrap_or(0)];
    d.set_item("grid", int_array(py, &grid, &[2])?)?;
    if elements.iter().any(|e| e.viscous_displacement_m.is_some()) {
        let nan = [f64::NAN; 3];
        let viscous = floats(&|e, v| v.extend(e.viscous_displacement_m.unwrap_or(nan)), 3)?;
        d.set_item("viscous_displacement_m", viscous)?;
    }
    Ok(d)
}
