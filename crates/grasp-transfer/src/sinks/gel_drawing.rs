//! The gel images in the Rerun recording: per step, for each finger whose sensor has a gel
//! image, two 2-D entities the layout gives views of (`super::rerun_layout`):
//!
//! - `tactile/<name>/gel`: the shaded image, 8-bit RGB, as the camera inside the finger sees
//!   it (`GelImage::camera_rgb8`: columns along the image's first side, rows along the second);
//! - `tactile/<name>/gel_height`: the height map as a depth image, float32 metres (positive
//!   into the pad), `meter` 1.
//!
//! A released finger (or a failed step) clears both.

use grasp_model::GelImage;
use rerun::datatypes::ChannelDatatype;
use rerun::{AsComponents, DepthImage, Image};

use super::sink::RunInfo;
use super::tactile_drawing::Drawing;
use crate::stepper::StepRecord;

/// The gel drawings of step `r`: every finger of `RunInfo::gel_fingers`, its image when the
/// step has it, else cleared.
pub fn gel_drawings(run: &RunInfo, r: &StepRecord) -> Vec<Drawing> {
    let mut out: Vec<Drawing> = Vec::new();
    for name in &run.gel_fingers() {
        let image = r
            .sensors
            .iter()
            .find(|s| &s.finger == name)
            .and_then(|s| s.gel.as_ref());
        let (colour, height): (Box<dyn AsComponents>, Box<dyn AsComponents>) = match image {
            Some(g) => (Box::new(colour_image(g)), Box::new(height_image(g))),
            None => (
                Box::new(rerun::Clear::flat()),
                Box::new(rerun::Clear::flat()),
            ),
        };
        out.push((format!("tactile/{name}/gel"), colour));
        out.push((format!("tactile/{name}/gel_height"), height));
    }
    out
}

/// `[width, height]` of an image of `count` pixels: `ny` columns, `nx` rows.
fn resolution(g: &GelImage) -> [u32; 2] {
    [g.count[1] as u32, g.count[0] as u32]
}

/// The shaded image, 8-bit RGB.
pub fn colour_image(g: &GelImage) -> Image {
    Image::from_rgb24(g.rgb8(), resolution(g))
}

/// The height map, float32 metres.
pub fn height_image(g: &GelImage) -> DepthImage {
    let bytes: Vec<u8> = g
        .height_m
        .iter()
        .flat_map(|h| (*h as f32).to_le_bytes())
        .collect();
    DepthImage::from_data_type_and_bytes(bytes, resolution(g), ChannelDatatype::F32).with_meter(1.0)
}
