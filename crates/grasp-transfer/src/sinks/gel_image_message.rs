//! The MCAP's gel images (only for fingers whose sensor has a gel image): per step, on
//! Foxglove's image schema (`foxglove.RawImage`, JSON encoding, `data` as base64 as
//! Foxglove's JSON encoding carries bytes), two topics a finger:
//!
//! - `/grasp/tactile/<finger>/gel`: the shaded image, `encoding` `rgb8`;
//! - `/grasp/tactile/<finger>/gel_height`: the height map, `encoding` `32FC1`, metres
//!   (positive into the pad), little-endian.
//!
//! The images are as the camera inside the finger sees them (`GelImage::camera_rgb8`):
//! columns along the image's first side (`width` = its `nx` pixels), rows along the second
//! (`height` = `ny`), looking along `n`; `frame_id` is `<finger>/gel`; `timestamp` the
//! schedule's time. A released finger (or a failed step) has no image that step.

use base64::Engine as _;
use grasp_model::GelImage;
use serde_json::{json, Value};

use super::foxglove_scene::foxglove_time;

/// Name of the image schema (Foxglove's).
pub const RAW_IMAGE_SCHEMA: &str = "foxglove.RawImage";

/// The topics of finger `name`'s gel image: `[colour, height]`.
pub fn gel_topics(name: &str) -> [String; 2] {
    [
        format!("/grasp/tactile/{name}/gel"),
        format!("/grasp/tactile/{name}/gel_height"),
    ]
}

/// Foxglove's `RawImage` as a JSON Schema (the fields of foxglove/schemas' `RawImage`).
pub fn raw_image_schema() -> Value {
    let int = json!({"type": "integer", "minimum": 0});
    json!({
        "title": RAW_IMAGE_SCHEMA,
        "description": "A raw image (Foxglove's RawImage)",
        "type": "object",
        "properties": {
            "timestamp": {"type": "object", "properties": {"sec": int, "nsec": int},
                          "required": ["sec", "nsec"]},
            "frame_id": {"type": "string"},
            "width": int,
            "height": int,
            "encoding": {"type": "string"},
            "step": int,
            "data": {"type": "string", "contentEncoding": "base64"}
        },
        "required": ["timestamp", "frame_id", "width", "height", "encoding", "step", "data"]
    })
}

/// The image's two messages at `time_s` for finger `name`: `[colour, height]`.
pub fn gel_messages(name: &str, g: &GelImage, time_s: f64) -> [Value; 2] {
    let [width, height] = g.camera_size();
    let message = |encoding: &str, bytes_per_pixel: u32, data: &[u8]| {
        json!({
            "timestamp": foxglove_time(time_s),
            "frame_id": format!("{name}/gel"),
            "width": width,
            "height": height,
            "encoding": encoding,
            "step": width * bytes_per_pixel,
            "data": base64::engine::general_purpose::STANDARD.encode(data),
        })
    };
    [
        message("rgb8", 3, &g.camera_rgb8()),
        message("32FC1", 4, &g.camera_height_f32_le()),
    ]
}
