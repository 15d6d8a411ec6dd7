//! The MCAP's compact patch message, `/grasp/patch_maps` (`grasp.PatchMaps`): per step, every
//! active patch of more than [`COMPACT_ABOVE_ELEMENTS`] elements as flat arrays
//! ([`super::element_maps`]), each a base64 string of the array's little-endian bytes (f32 for
//! numbers, u8 for the state), in a JSON message with a JSON Schema like the other topics
//! (bytes as base64 strings is how Foxglove's JSON encoding carries binary fields).
//!
//! ```text
//! {"time_s": 0.1, "step": 1, "patches": [{
//!    "name": "f3", "grid": [128, 128], "element_size_m": [7.8e-5, 3.9e-5],
//!    "origin_m": [...], "t1": [...], "t2": [...], "normal": [...],
//!    "normal_force_n": "<base64 f32 x N>", "pressure_pa": "...", "tangential_force_n": "<2N>",
//!    "gap_m": "...", "slip_m": "<2N>", "step_slip_m": "<2N>", "state": "<base64 u8 x N>"}]}
//! ```
//!
//! Element `k = i ny + j` (`i` along `t1`) is centred at `origin_m + x_i t1 + y_j t2` with
//! `x_i = (i + 1/2) hx - nx hx / 2`, `y_j = (j + 1/2) hy - ny hy / 2` (the finger's patch
//! frame; the element records of smaller patches carry that position as `position_m`).

use base64::Engine as _;
use serde_json::json;

use super::element_maps::{is_compact, little_endian, ElementMaps, COMPACT_ABOVE_ELEMENTS};
use super::sink::RunInfo;
use crate::stepper::StepRecord;

/// Topic of the compact per-element maps of large patches.
pub const PATCH_MAPS_TOPIC: &str = "/grasp/patch_maps";

/// Name of the message's JSON Schema.
pub const PATCH_MAPS_SCHEMA: &str = "grasp.PatchMaps";

/// Whether the run has a patch recorded as compact maps (the topic is written only then).
pub fn has_compact_patch(run: &RunInfo) -> bool {
    run.model
        .fingers()
        .iter()
        .any(|f| is_compact(f.patch().len()))
}

/// The JSON Schema of a `/grasp/patch_maps` message.
pub fn patch_maps_schema() -> serde_json::Value {
    let num = json!({"type": "number"});
    let v2 = json!({"type": "array", "items": num, "minItems": 2, "maxItems": 2});
    let v3 = json!({"type": "array", "items": num, "minItems": 3, "maxItems": 3});
    let f32s = |what: &str| {
        json!({"type": "string", "contentEncoding": "base64", "description": format!(
            "{what}: little-endian float32, element k = i ny + j (i along t1)")})
    };
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": PATCH_MAPS_SCHEMA,
        "description": format!("Per-element fields of every active patch of more than {COMPACT_ABOVE_ELEMENTS} elements, as base64 arrays"),
        "type": "object",
        "properties": {
            "time_s": num, "step": {"type": "integer"},
            "patches": {"type": "array", "items": {"type": "object", "properties": {
                "name": {"type": "string"},
                "grid": {"type": "array", "items": {"type": "integer"}, "minItems": 2, "maxItems": 2,
                         "description": "[nx along t1, ny along t2]"},
                "element_size_m": v2, "origin_m": v3, "t1": v3, "t2": v3, "normal": v3,
                "normal_force_n": f32s("normal force F_k, N (N values)"),
                "pressure_pa": f32s("mean pressure F_k / A, Pa (N values)"),
                "tangential_force_n": f32s("tangential force along [t1, t2], N (2N values, interleaved)"),
                "gap_m": f32s("gap after loading, m (N values)"),
                "slip_m": f32s("accumulated slip along [t1, t2], m (2N values, interleaved)"),
                "step_slip_m": f32s("this step's slip along [t1, t2], m (2N values, interleaved)"),
                "state": {"type": "string", "contentEncoding": "base64",
                          "description": "uint8 per element: 0 stick, 1 slip, 2 separated, 3 off the surface, 4 in contact without friction (a frictionless finger)"}
            }}}
        }
    })
}

/// The `/grasp/patch_maps` message of a step: every solved finger with a compact patch.
pub fn patch_maps_message(run: &RunInfo, r: &StepRecord) -> serde_json::Value {
    let b64 = |bytes: &[u8]| base64::engine::general_purpose::STANDARD.encode(bytes);
    let f32s = |v: &[f32]| b64(&little_endian(v));
    let v3 = |v: &nalgebra::Vector3<f64>| [v.x, v.y, v.z];
    let patches: Vec<serde_json::Value> = run
        .model
        .fingers()
        .iter()
        .filter(|fm| is_compact(fm.patch().len()))
        .filter_map(|fm| r.solution.finger(fm.name()).map(|f| (fm, f)))
        .map(|(fm, f)| {
            let m = ElementMaps::of(f);
            let g = &fm.patch().grid;
            json!({
                "name": fm.name(), "grid": [g.nx, g.ny], "element_size_m": [g.hx, g.hy],
                "origin_m": v3(&fm.frame().origin_m), "t1": v3(&fm.frame().t1),
                "t2": v3(&fm.frame().t2), "normal": v3(&fm.frame().normal),
                "normal_force_n": f32s(&m.normal_force_n), "pressure_pa": f32s(&m.pressure_pa),
                "tangential_force_n": f32s(&m.tangential_force_n), "gap_m": f32s(&m.gap_m),
                "slip_m": f32s(&m.slip_m), "step_slip_m": f32s(&m.step_slip_m),
                "state": b64(&m.state)
            })
        })
        .collect();
    json!({"time_s": r.time_s, "step": r.index, "patches": patches})
}
