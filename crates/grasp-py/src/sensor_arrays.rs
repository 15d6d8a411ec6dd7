//! A finger's tactile readings as NumPy arrays over its grids (`Solution.sensor`): the
//! row-major lists of `grasp_model::SensorReadings` reshaped to `(nx, ny, k)`, as `grasp solve
//! --npz` writes them (and the taxels' `size_m`, which the archive leaves out).

use grasp_model::SensorReadings;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::float_array;

/// `{"taxels": {...}, "markers": {...}, "gel": {...}}` of `r`, each kind present only when
/// the sensor has it.
pub fn sensor_arrays<'py>(py: Python<'py>, r: &SensorReadings) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    if let Some(t) = &r.taxels {
        let [nx, ny] = t.count;
        let d = PyDict::new(py);
        d.set_item("force_n", float_array(py, &flat(&t.force_n), &[nx, ny, 3])?)?;
        d.set_item(
            "centre_m",
            float_array(py, &flat(&t.centre_m), &[nx, ny, 2])?,
        )?;
        d.set_item("depth_m", t.depth_m)?;
        d.set_item("size_m", t.size_m)?;
        out.set_item("taxels", d)?;
    }
    if let Some(m) = &r.markers {
        let [nx, ny] = m.count;
        let d = PyDict::new(py);
        let u = flat(&m.displacement_m);
        d.set_item("displacement_m", float_array(py, &u, &[nx, ny, 3])?)?;
        d.set_item(
            "position_m",
            float_array(py, &flat(&m.position_m), &[nx, ny, 2])?,
        )?;
        out.set_item("markers", d)?;
    }
    if let Some(g) = &r.gel {
        let [nx, ny] = g.count;
        let d = PyDict::new(py);
        d.set_item("height_m", float_array(py, &g.height_m, &[nx, ny])?)?;
        d.set_item("normal", float_array(py, &flat(&g.normal), &[nx, ny, 3])?)?;
        d.set_item("rgb", float_array(py, &flat(&g.rgb), &[nx, ny, 3])?)?;
        let points = flat(&g.positions_m());
        d.set_item("position_m", float_array(py, &points, &[nx, ny, 2])?)?;
        d.set_item("pixel_m", g.pixel_m.to_vec())?;
        let path = match g.path {
            grasp_model::HeightPath::Lattice => "lattice",
            grasp_model::HeightPath::Dense => "dense",
            grasp_model::HeightPath::Flat => "flat",
        };
        d.set_item("path", path)?;
        out.set_item("gel", d)?;
    }
    Ok(out)
}

/// The rows of `rows` one after the other.
fn flat<const K: usize>(rows: &[[f64; K]]) -> Vec<f64> {
    rows.iter().flatten().copied().collect()
}
