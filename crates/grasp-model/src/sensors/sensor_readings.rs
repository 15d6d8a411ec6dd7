//! Every sensor of a scene read from its solved grasp: per finger with a `sensor`, the
//! readings of each of its kinds, its taxels (`super::taxel_readings`), its markers
//! (`super::marker_readings`) and its gel image (`super::gel_image`), from the elements of the solution and the element grid of the
//! model that was solved (an automatic patch's, not the scene's).

use serde::{Serialize, Serializer};

use crate::error::ModelError;
use crate::model::grasp_model::GraspModel;
use crate::scene::response_spec::ResponseSpec;
use crate::scene::scene_format::Scene;
use crate::scene::sensor_kind::{ElementGrid, SensorKind};
use crate::scene::sensor_spec::SensorSpec;
use crate::sensors::gel_image::{read_gel, GelImage};
use crate::sensors::marker_readings::{read_markers, MarkerReadings};
use crate::sensors::sensor_response::apply_response;
use crate::sensors::taxel_grid::TaxelGrid;
use crate::sensors::taxel_readings::{read_taxels_fastest, TaxelReadings};
use crate::solve::solution::Solution;

/// One finger's sensor readings, of each kind its sensor has (at least one).
///
/// As JSON (`grasp solve --json`'s `"sensors"`): the taxels' record's fields at the top
/// (`finger`, `count`, `depth_m`, `size_m`, `centre_m`, `force_n`, as the taxels' first slice
/// wrote them), then `"markers"`: `{count, position_m, displacement_m}`, then `"gel"`:
/// `{count, pixel_m, centre_m, rotation_rad, path, height_m, normal, rgb}`; a sensor without
/// taxels writes `finger` and its kinds.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorReadings {
    /// The finger's name.
    pub finger: String,
    /// Its taxels' readings, when the sensor has taxels.
    pub taxels: Option<TaxelReadings>,
    /// Its markers' readings, when the sensor has markers.
    pub markers: Option<MarkerReadings>,
    /// Its gel image, when the sensor has one.
    pub gel: Option<GelImage>,
}

/// [`SensorReadings`] as its JSON record writes it.
#[derive(Serialize)]
struct Record<'a> {
    #[serde(skip_serializing_if = "Option::is_none")]
    finger: Option<&'a str>,
    #[serde(flatten)]
    taxels: Option<&'a TaxelReadings>,
    #[serde(skip_serializing_if = "Option::is_none")]
    markers: Option<&'a MarkerReadings>,
    #[serde(skip_serializing_if = "Option::is_none")]
    gel: Option<&'a GelImage>,
}

impl Serialize for SensorReadings {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        Record {
            finger: self.taxels.is_none().then_some(self.finger.as_str()),
            taxels: self.taxels.as_ref(),
            markers: self.markers.as_ref(),
            gel: self.gel.as_ref(),
        }
        .serialize(s)
    }
}

/// The readings of every finger of `scene` that has a sensor, in the scene's order, from
/// `solution` (solved from `model`, built from `scene`), as one solve reads them (read-out 0
/// of each sensor's noise: [`sensor_readings_drawn`]). Empty for a scene without sensors:
/// nothing is computed. A finger of the scene the solution lacks is skipped; a kind's
/// read-out over more kernel evaluations than it may take (an automatic patch finer than the
/// scene's) is refused, naming `fingers[i].sensor` and the fix.
pub fn sensor_readings(
    scene: &Scene,
    model: &GraspModel,
    solution: &Solution,
) -> Result<Vec<SensorReadings>, ModelError> {
    sensor_readings_drawn(scene, model, solution, 0)
}

/// [`sensor_readings`] as read-out `draw` of each sensor's noise (a hand-off's step index):
/// each kind's `response` (`super::sensor_response`) applied to its ideal readings with the
/// noise of that draw.
pub fn sensor_readings_drawn(
    scene: &Scene,
    model: &GraspModel,
    solution: &Solution,
    draw: u64,
) -> Result<Vec<SensorReadings>, ModelError> {
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
        check_work(i, sensor, &grid.element_grid())?;
        let elements = &solved.elements;
        let taxels = match &sensor.taxels {
            Some(t) => {
                let mut r = read_taxels_fastest(&spec.name, &TaxelGrid::new(t), &grid, elements)?;
                respond(&t.response, &mut r.force_n, stream(i, 0), draw);
                Some(r)
            }
            None => None,
        };
        let markers = sensor.markers.as_ref().map(|m| {
            let mut r = read_markers(&m.layout(), finger.material(), &grid, elements);
            respond(&m.response, &mut r.displacement_m, stream(i, 1), draw);
            r
        });
        let gel = match &sensor.gel {
            Some(g) => {
                let mut image = read_gel(g, finger.material(), &grid, elements)?;
                respond(&g.response, &mut image.rgb, stream(i, 2), draw);
                Some(image)
            }
            None => None,
        };
        out.push(SensorReadings {
            finger: spec.name.clone(),
            taxels,
            markers,
            gel,
        });
    }
    Ok(out)
}

/// `response` applied to `values` of sensor stream `sensor`, when given.
fn respond<const N: usize>(
    response: &Option<ResponseSpec>,
    values: &mut [[f64; N]],
    sensor: u64,
    draw: u64,
) {
    if let Some(r) = response {
        apply_response(r, values, sensor, draw);
    }
}

/// The noise streams of kind `kind` (0 taxels, 1 markers, 2 gel) of `fingers[finger]`.
fn stream(finger: usize, kind: u64) -> u64 {
    (finger as u64) * 4 + kind
}

/// Refuses a read-out of `sensor` (of `fingers[i]`) over the element grid `grid` that would
/// take more kernel evaluations than its kind may.
fn check_work(i: usize, sensor: &SensorSpec, grid: &ElementGrid) -> Result<(), ModelError> {
    for kind in sensor.kinds() {
        let work = kind.kernel_evaluations(grid);
        let most = kind.most_kernel_evaluations();
        if work > most {
            return Err(ModelError::BadInput(format!(
                "fingers[{i}].sensor: the read-out needs {work:.2e} kernel evaluations \
                 ({}), above {most:.0e}; {}",
                kind.work_terms(),
                kind.work_fix()
            )));
        }
    }
    Ok(())
}
