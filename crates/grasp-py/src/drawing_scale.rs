//! The project's force-arrow scale for the package's own drawings (`grasp.mujoco` draws
//! MuJoCo's forces beside the project's in one recording): the sinks' scale of the scene
//! (`grasp_transfer::drawing_scale`), so that both force sets are drawn alike.

use pyo3::prelude::*;

use crate::errors::scene_error;
use crate::scene::Scene;

/// The force arrows' scale of the scene's recordings, m per N (the load scale drawn as 0.3 of
/// the diagonal of the box around the contact points and the centre of mass).
#[pyfunction]
#[pyo3(name = "_arrow_scale_m_per_n")]
pub fn arrow_scale_m_per_n(py: Python<'_>, scene: &Scene) -> PyResult<f64> {
    let model = py
        .allow_threads(|| grasp_model::GraspModel::from_loaded(&scene.scene))
        .map_err(|e| scene_error(py, &scene.origin, &e))?;
    Ok(grasp_transfer::drawing_scale(&model).1)
}
