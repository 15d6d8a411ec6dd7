//! The tactile sensors' columns of the hand-off's CSV (`super::csv_history`): per finger with
//! a sensor, per kind it has, a step's summary of its readings (the arrays are in the MCAP and
//! the `.npz`):
//!
//! - taxels: `<name>_taxels_normal_n` (the taxels' normal forces summed, N),
//!   `<name>_taxels_shear_n` (the length of their shear forces' sum, N) and
//!   `<name>_taxels_largest_n` (the largest taxel force's length, N);
//! - markers: `<name>_markers_shift_m` (the largest tangential displacement, m) and
//!   `<name>_markers_normal_m` (the normal displacement of largest size, m, + into the pad);
//! - a gel image: `<name>_gel_deepest_m` (the deepest pixel's height, m; the ideal height:
//!   a sensor's `response` acts on the image's colours).
//!
//! A finger without readings at a step (released, or a step without forces) has empty cells.

use grasp_model::SensorReadings;

use super::sink::RunInfo;
use crate::stepper::StepRecord;

/// The columns of one finger's sensor, after its name and `_`: per kind it has.
fn columns(sensor: &grasp_model::SensorSpec) -> Vec<&'static str> {
    let mut out = Vec::new();
    if sensor.taxels.is_some() {
        out.extend(["taxels_normal_n", "taxels_shear_n", "taxels_largest_n"]);
    }
    if sensor.markers.is_some() {
        out.extend(["markers_shift_m", "markers_normal_m"]);
    }
    if sensor.gel.is_some() {
        out.push("gel_deepest_m");
    }
    out
}

/// The header's sensor columns, each with its leading comma (empty for a scene without).
pub fn sensor_header(run: &RunInfo, field: impl Fn(&str) -> String) -> String {
    let mut h = String::new();
    for f in &run.scene.fingers {
        let Some(sensor) = &f.sensor else { continue };
        for col in columns(sensor) {
            h.push(',');
            h.push_str(&field(&format!("{}_{col}", f.name)));
        }
    }
    h
}

/// The cells of one finger's readings, in its columns' order (each with its leading comma):
/// per kind of its `sensor`, the reading's numbers, or empty cells where the reading lacks it.
fn cells(sensor: &grasp_model::SensorSpec, r: Option<&SensorReadings>) -> String {
    let mut kinds: Vec<(usize, Option<Vec<f64>>)> = Vec::new();
    if sensor.taxels.is_some() {
        let t = r.and_then(|r| r.taxels.as_ref()).map(|t| {
            let [s1, s2] = t.total_shear_n();
            vec![t.total_normal_n(), s1.hypot(s2), t.largest().1]
        });
        kinds.push((3, t));
    }
    if sensor.markers.is_some() {
        let m = r.and_then(|r| r.markers.as_ref());
        kinds.push((
            2,
            m.map(|m| vec![m.largest_tangential().1, m.largest_normal().1]),
        ));
    }
    if sensor.gel.is_some() {
        let g = r.and_then(|r| r.gel.as_ref());
        kinds.push((1, g.map(|g| vec![g.deepest().1])));
    }
    let mut out = String::new();
    for (n, values) in kinds {
        match values {
            Some(v) => v.iter().for_each(|x| out.push_str(&format!(",{x}"))),
            None => out.push_str(&",".repeat(n)),
        }
    }
    out
}

/// Step `r`'s sensor cells, each with its leading comma.
pub fn sensor_cells(run: &RunInfo, r: &StepRecord) -> String {
    let mut line = String::new();
    for f in &run.scene.fingers {
        let Some(sensor) = &f.sensor else { continue };
        let read = r.sensors.iter().find(|s| s.finger == f.name);
        line.push_str(&cells(sensor, read));
    }
    line
}
