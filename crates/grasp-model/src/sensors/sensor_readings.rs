//! Every sensor of a scene read from its solved grasp: per finger with a `sensor`, its
//! taxels' readings (`super::taxel_readings`), from the elements of the solution and the
//! element grid of the model that was solved (an automatic patch's, not the scene's).

use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::scene::scene_format::Scene;
use crate::scene::sensor_spec::MAX_TAXEL_KERNEL_EVALUATIONS;
use crate::sensors::taxel_grid::TaxelGrid;
use crate::sensors::taxel_readings::{read_taxels, TaxelReadings};
use crate::solve::solution::Solution;

/// The readings of every finger of `scene` that has a sensor, in the scene's order, from
/// `solution` (solved from `model`, built from `scene`). Empty for a scene without sensors:
/// nothing is computed. A finger of the scene the solution lacks is skipped; a read-out over
/// more than [`MAX_TAXEL_KERNEL_EVALUATIONS`] kernel evaluations (an automatic patch finer
/// than the scene's) is refused, naming `fingers[i].sensor` and the fix.
pub fn sensor_readings(
    scene: &Scene,
    model: &GraspModel,
    solution: &Solution,
) -> Result<Vec<TaxelReadings>, ModelError> {
    let mut out = Vec::new();
    for (i, spec) in scene.fingers.iter().enumerate() {
        let Some(sensor) = &spec.sensor else { continue };
        let Some((_, finger)) = model.finger(&spec.name) else {
            continue;
        };
        let Some(solved) = solution.fingers.iter().find(|f| f.name == spec.name) else {
            continue;
        };
        let grid = finger.patch().grid;
        let taxels = &sensor.taxels;
        let work = taxels.kernel_evaluations(grid.len());
        if taxels.depth_m > 0.0 && work > MAX_TAXEL_KERNEL_EVALUATIONS {
            return Err(ModelError::BadInput(format!(
                "fingers[{i}].sensor: the read-out needs {work:.2e} kernel evaluations \
                 (taxels x quadrature points x elements), above \
                 {MAX_TAXEL_KERNEL_EVALUATIONS:.0e}; use fewer taxels, a larger depth_m or a \
                 coarser patch"
            )));
        }
        out.push(read_taxels(
            &spec.name,
            &TaxelGrid::new(taxels),
            &grid,
            &solved.elements,
        ));
    }
    Ok(out)
}
