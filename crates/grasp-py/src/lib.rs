//! # grasp-py: the Python module `grasp._native`
//!
//! The Python package `grasp` (in `python/grasp`, built by maturin from the repository root)
//! re-exports this module: [`scene::Scene`] (a validated scene from a file, a dict or JSON
//! text), [`solve::solve`] (one grasp, returning [`solution::Solution`] with NumPy element
//! arrays) and [`transfer::transfer`] (a hand-off writing the CLI's MCAP, Rerun and CSV
//! files, returning [`transfer::Transfer`] with force histories, time x finger). The GIL is
//! released while the library computes. SI units throughout; names carry their unit.

#![warn(missing_docs)]

use pyo3::prelude::*;

mod arrays;
mod drawing_scale;
mod element_fields;
mod errors;
mod height_arrays;
mod histories;
mod inputs;
mod json_value;
mod keywords;
mod outputs;
mod plan;
mod python_serializer;
mod scene;
mod sensor_arrays;
mod sensor_histories;
mod solution;
mod solve;
mod transfer;

/// The native part of the `grasp` package.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The default of `solve`'s `tolerance=` (its signature writes the number: a test checks
    // that the two agree).
    m.add("DEFAULT_TOLERANCE", grasp_model::DEFAULT_TOLERANCE)?;
    m.add("SceneError", py.get_type::<errors::SceneError>())?;
    m.add("ScheduleError", py.get_type::<errors::ScheduleError>())?;
    m.add("GraspError", py.get_type::<errors::GraspError>())?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<solution::Solution>()?;
    m.add_class::<transfer::Transfer>()?;
    m.add_function(wrap_pyfunction!(solve::solve, m)?)?;
    m.add_function(wrap_pyfunction!(transfer::transfer, m)?)?;
    m.add_function(wrap_pyfunction!(plan::plan, m)?)?;
    // For the pure-Python writers and readers of the package (`grasp.mujoco`).
    m.add_function(wrap_pyfunction!(inputs::read_input, m)?)?;
    m.add_function(wrap_pyfunction!(inputs::check_input, m)?)?;
    m.add_function(wrap_pyfunction!(outputs::check_outputs, m)?)?;
    m.add_function(wrap_pyfunction!(outputs::write_outputs, m)?)?;
    m.add_function(wrap_pyfunction!(drawing_scale::arrow_scale_m_per_n, m)?)?;
    Ok(())
}
