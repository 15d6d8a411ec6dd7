//! `grasp solve --gel-png`: the gel images of a solve as one PNG, each finger's shaded image
//! as its camera sees it (`GelImage::camera_rgb8`: one PNG pixel a gel pixel, columns along
//! the image's first side, rows along the second) side by side in scene order, 8 white pixels
//! apart.

use anyhow::{bail, Result};
use grasp_model::SensorReadings;

use super::picture::encode_png;

/// The refusal of `--gel-png` for a scene without a gel image.
pub const NO_GEL_IMAGE: &str =
    "--gel-png: no finger has a gel image; give a finger `sensor.gel` or drop --gel-png";

/// White columns between two images.
const GAP_PX: usize = 8;

/// The PNG of every gel image of `sensors`; an error when there is none.
pub fn gel_png(sensors: &[SensorReadings]) -> Result<Vec<u8>> {
    let images: Vec<_> = sensors.iter().filter_map(|s| s.gel.as_ref()).collect();
    if images.is_empty() {
        bail!(NO_GEL_IMAGE);
    }
    let size = |g: &grasp_model::GelImage| g.camera_size().map(|s| s as usize);
    let height = images.iter().map(|g| size(g)[1]).max().unwrap_or(0);
    let width = images.iter().map(|g| size(g)[0]).sum::<usize>() + GAP_PX * (images.len() - 1);
    let mut rgb = vec![255u8; width * height * 3];
    let mut left = 0;
    for g in images {
        let [w, h] = size(g);
        let bytes = g.camera_rgb8();
        for row in 0..h {
            let at = (row * width + left) * 3;
            rgb[at..at + w * 3].copy_from_slice(&bytes[row * w * 3..(row + 1) * w * 3]);
        }
        left += w + GAP_PX;
    }
    encode_png(&rgb, (width as u32, height as u32))
}
