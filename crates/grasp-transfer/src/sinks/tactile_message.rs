//! The MCAP's tactile message, `/grasp/tactile` (`grasp.TactileReadings`, only when the scene
//! has a finger with a `sensor`): per step, every active sensor finger's readings as
//! `grasp solve --json` writes them under `sensors`, grouped by kind:
//!
//! ```text
//! {"time_s": 0.5, "step": 5, "sensors": [{"finger": "f1",
//!    "taxels": {"count": [4, 4], "depth_m": 0.0, "size_m": 0.005,
//!               "centre_m": [[t1, t2], ...], "force_n": [[normal, t1, t2], ...]},
//!    "markers": {"count": [5, 5], "position_m": [[t1, t2], ...],
//!                "displacement_m": [[normal, t1, t2], ...]}}]}
//! ```
//!
//! Arrays are row-major, `k = i ny + j` with `i` along the grid's first side; a kind the
//! finger's sensor lacks is `null`; a released finger (or a failed step) has no entry. The
//! schema is generated from the message's own types, so the two cannot drift apart. A gel
//! image is not in it: it has its own topics on Foxglove's image schema
//! ([`super::gel_image_message`]).

use grasp_model::{MarkerReadings, SensorReadings, TaxelReadings};
use schemars::JsonSchema;
use serde::Serialize;

use super::sink::RunInfo;
use crate::stepper::StepRecord;

/// Topic of the per-step tactile readings.
pub const TACTILE_TOPIC: &str = "/grasp/tactile";

/// Name of the message's JSON Schema.
pub const TACTILE_SCHEMA: &str = "grasp.TactileReadings";

/// Whether the run has a finger with a sensor (the topic is written only then).
pub fn has_sensor(run: &RunInfo) -> bool {
    run.scene.fingers.iter().any(|f| f.sensor.is_some())
}

/// One step's readings.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct TactileMessage {
    /// Schedule time, s.
    pub time_s: f64,
    /// Step index.
    pub step: usize,
    /// Every active finger with a sensor, scene order.
    pub sensors: Vec<SensorMessage>,
}

/// One finger's readings.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct SensorMessage {
    /// The finger.
    pub finger: String,
    /// Its taxels' readings (`null` without taxels).
    pub taxels: Option<TaxelMessage>,
    /// Its markers' readings (`null` without markers).
    pub markers: Option<MarkerMessage>,
}

/// A taxel grid's readings.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct TaxelMessage {
    /// Taxels along the grid's sides `[nx, ny]`.
    pub count: [usize; 2],
    /// Depth below the pad's surface, m.
    pub depth_m: f64,
    /// Side of each taxel, m.
    pub size_m: f64,
    /// Each taxel's centre from the contact point along `t1`, `t2`, m.
    pub centre_m: Vec<[f64; 2]>,
    /// Each taxel's force `[normal, t1, t2]`, N (normal along `n`, into the object).
    pub force_n: Vec<[f64; 3]>,
}

/// A marker grid's readings.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct MarkerMessage {
    /// Markers along the grid's sides `[nx, ny]`.
    pub count: [usize; 2],
    /// Each marker's point from the contact point along `t1`, `t2`, m.
    pub position_m: Vec<[f64; 2]>,
    /// Each marker's displacement `[normal, t1, t2]` relative to the finger's core, m
    /// (normal positive into the finger).
    pub displacement_m: Vec<[f64; 3]>,
}

impl From<&TaxelReadings> for TaxelMessage {
    fn from(t: &TaxelReadings) -> Self {
        TaxelMessage {
            count: t.count,
            depth_m: t.depth_m,
            size_m: t.size_m,
            centre_m: t.centre_m.clone(),
            force_n: t.force_n.clone(),
        }
    }
}

impl From<&MarkerReadings> for MarkerMessage {
    fn from(m: &MarkerReadings) -> Self {
        MarkerMessage {
            count: m.count,
            position_m: m.position_m.clone(),
            displacement_m: m.displacement_m.clone(),
        }
    }
}

impl From<&SensorReadings> for SensorMessage {
    fn from(r: &SensorReadings) -> Self {
        SensorMessage {
            finger: r.finger.clone(),
            taxels: r.taxels.as_ref().map(TaxelMessage::from),
            markers: r.markers.as_ref().map(MarkerMessage::from),
        }
    }
}

/// The message of step `r`.
pub fn tactile_message(r: &StepRecord) -> TactileMessage {
    TactileMessage {
        time_s: r.time_s,
        step: r.index,
        sensors: r.sensors.iter().map(SensorMessage::from).collect(),
    }
}

/// The JSON Schema of a `/grasp/tactile` message, with its title.
pub fn tactile_schema() -> serde_json::Value {
    let mut schema = serde_json::to_value(schemars::schema_for!(TactileMessage))
        .unwrap_or(serde_json::Value::Null);
    schema["title"] = TACTILE_SCHEMA.into();
    schema
}
