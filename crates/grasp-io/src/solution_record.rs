//! A solution as its JSON file holds it (`grasp solve --json`, Python's `Solution.to_json`):
//! the solution's fields in their declared order, then the solve's time for a viscoelastic
//! scene, the sensitivities when asked and the sensors' readings when the scene has sensors.
//! Serialised straight into a writer, so a fine patch's answer (about 2 GB of text at 1024 x 1024) needs no copy in memory.

use grasp_model::{Sensitivities, SensorReadings, Solution, TimePoint};
use serde::Serialize;

/// What a solution's JSON file holds.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SolutionRecord<'a> {
    /// The solution.
    #[serde(flatten)]
    pub solution: &'a Solution,
    /// When a viscoelastic scene was solved (`None` for an elastic one): `"instantaneous"`,
    /// `{"at_s": t}` or `"long_term"`.
    #[serde(skip_serializing_if = "Option::is_none", serialize_with = "time_json")]
    pub time: Option<TimePoint>,
    /// The sensitivities, when they were computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensitivities: Option<&'a Sensitivities>,
    /// The readings of the fingers' tactile sensors (`grasp_model::sensor_readings`), only
    /// when the scene has one: `"sensors"`, one record per finger with a sensor (its taxels'
    /// fields, then its `markers`: `grasp_model::SensorReadings`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensors: Option<&'a [SensorReadings]>,
}

fn time_json<S: serde::Serializer>(t: &Option<TimePoint>, s: S) -> Result<S::Ok, S::Error> {
    t.map(time_value).serialize(s)
}

/// The time as the file writes it: `"instantaneous"`, `{"at_s": t}` or `"long_term"`.
fn time_value(t: TimePoint) -> serde_json::Value {
    match t {
        TimePoint::Instantaneous => serde_json::json!("instantaneous"),
        TimePoint::At { seconds } => serde_json::json!({ "at_s": seconds }),
        TimePoint::LongTerm => serde_json::json!("long_term"),
    }
}
