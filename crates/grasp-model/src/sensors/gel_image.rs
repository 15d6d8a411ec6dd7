//! The image of one finger's optical gel sensor: the deformed pad's height map
//! (`super::gel_height`), its surface normals and its colours (`super::gel_shading`), pixel by
//! pixel, row-major (`k = i ny + j`, `i` along the image's first side).

use serde::{Deserialize, Serialize};

use crate::error::OutOfMemory;
use crate::model::influence::GridSpec;
use crate::model::material::Material;
use crate::scene::gel_spec::GelSpec;
use crate::scene::sensor_kind::SensorKind;
use crate::sensors::gel_height::{height_map, HeightPath};
use crate::sensors::gel_shading::{shade, surface_normals};
use crate::solve::solution::ElementSolution;

/// One finger's gel image.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GelImage {
    /// Pixels along the image's sides `[nx, ny]`.
    pub count: [usize; 2],
    /// The pixel pitch along the image's sides, m.
    pub pixel_m: [f64; 2],
    /// The image's centre from the contact point along `t1`, `t2`, m.
    pub centre_m: [f64; 2],
    /// Angle of the image's first side to `t1`, rad.
    pub rotation_rad: f64,
    /// How the height map was read (`lattice`: one FFT convolution; `dense`; `flat`).
    pub path: HeightPath,
    /// Each pixel's height: the pad's surface displacement along the normal relative to the
    /// finger's core, m, positive into the pad (toward the camera).
    pub height_m: Vec<f64>,
    /// Each pixel's unit surface normal `[u, v, w]` in the image's frame (`w` toward the
    /// camera).
    pub normal: Vec<[f64; 3]>,
    /// Each pixel's colour `[r, g, b]`, each in `[0, 1]`.
    pub rgb: Vec<[f64; 3]>,
}

impl GelImage {
    /// The largest height, m, and its pixel's index (0 and 0 for a flat image).
    pub fn deepest(&self) -> (usize, f64) {
        self.height_m.iter().enumerate().fold(
            (0, 0.0),
            |best, (k, h)| if *h > best.1 { (k, *h) } else { best },
        )
    }

    /// Each pixel's centre from the contact point along `t1`, `t2`, m.
    pub fn positions_m(&self) -> Vec<[f64; 2]> {
        crate::scene::sensor_kind::GridLayout {
            count: self.count,
            pitch_m: self.pixel_m,
            rotation_rad: self.rotation_rad,
            offset_m: self.centre_m,
        }
        .points_m()
    }

    /// The colours as 8-bit RGB, row-major, 3 bytes a pixel (`round(255 c)`).
    pub fn rgb8(&self) -> Vec<u8> {
        self.rgb
            .iter()
            .flatten()
            .map(|c| (c * 255.0).round() as u8)
            .collect()
    }
}

/// The image of `spec` over a finger of material `finger` with solved `elements` (their
/// element grid `patch`): the height map, its normals, its shading; [`OutOfMemory`] when the
/// FFT read-out's lattice cannot be allocated.
pub fn read_gel(
    spec: &GelSpec,
    finger: &Material,
    patch: &GridSpec,
    elements: &[ElementSolution],
) -> Result<GelImage, OutOfMemory> {
    let (height_m, path) = height_map(spec, finger, patch, elements)?;
    let layout = spec.layout();
    let normal = surface_normals(&height_m, layout.count, layout.pitch_m);
    let rgb = shade(spec, &normal);
    Ok(GelImage {
        count: layout.count,
        pixel_m: layout.pitch_m,
        centre_m: spec.offset_m,
        rotation_rad: spec.rotation_rad,
        path,
        height_m,
        normal,
        rgb,
    })
}
