//! `fingers[i].sensor.<kind>.response` as written: how a real sensor departs from the ideal
//! reading of its kind, all off unless given: a gain per taxel (marker, pixel) fixed for the
//! sensor, noise drawn anew at every read-out, saturation and quantisation, in that order
//! (`crate::sensors::sensor_response`), seeded so that a run gives the same readings every
//! time. Its numbers are in the reading's own unit: N for taxels, m for markers, the colour's
//! `[0, 1]` for a gel image.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A sensor's departures from the ideal reading (each optional; none given: the ideal).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ResponseSpec {
    /// Standard deviation of each point's gain about 1 (a calibration error, fixed for the
    /// sensor: drawn once per taxel, marker or pixel from the seed), in `[0, 1]`; default 0.
    #[serde(default)]
    pub gain_std: f64,
    /// Standard deviation of the additive Gaussian noise of every reading (each component, each
    /// read-out), in the reading's unit, in `[0, 1e6]`; default 0.
    #[serde(default)]
    pub noise_std: f64,
    /// The range `[low, high]` a reading saturates at (each component clipped to it), in the
    /// reading's unit, `low < high`; default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub saturation: Option<[f64; 2]>,
    /// The reading's resolution: each component rounded to the nearest multiple of it, in the
    /// reading's unit, in `(0, 1e6]`; default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quantum: Option<f64>,
    /// Seed of the gains and the noise (any integer in `[0, 2^53]`); default 0.
    #[serde(default)]
    pub seed: u64,
}
