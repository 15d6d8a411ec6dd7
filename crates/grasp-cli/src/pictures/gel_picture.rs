//! `grasp solve --gel-png`: the gel images of a solve as one PNG, each finger's shaded image
//! (`GelImage::rgb8`, one PNG pixel a gel pixel, its rows along the image's first side) side
//! by side in scene order, 8 white pixels apart.

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
    let height = images.iter().map(|g| g.count[0]).max().unwrap_or(0);
    let width = images.iter().map(|g| g.count[1]).sum::<usize>() + GAP_PX * (images.len() - 1);
    let mut rgb = vec![255u8; width * height * 3];
    let mut left = 0;
    for g in images {
        let [nx, ny] = g.count;
        let bytes = g.rgb8();
        for i in 0..nx {
            let at = (i * width + left) * 3;
            rgb[at..at + ny * 3].copy_from_slice(&bytes[i * ny * 3..(i + 1) * ny * 3]);
        }
        left += ny + GAP_PX;
    }
    encode_png(&rgb, (width as u32, height as u32))
}
