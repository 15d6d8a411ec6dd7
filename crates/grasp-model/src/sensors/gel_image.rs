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
    /// The deepest pixel: its index and its height, m (`(0, 0.0)` when no pixel is pushed
    /// in).
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

    /// The colours as 8-bit RGB (`round(255 c)`), 3 bytes a pixel, in the arrays' order (`k
    /// = i ny + j`).
    pub fn rgb8(&self) -> Vec<u8> {
        self.rgb.iter().flatten().map(|c| byte(*c)).collect()
    }

    /// `[width, height]` of the image as its camera sees it: `[nx, ny]`.
    pub fn camera_size(&self) -> [u32; 2] {
        [self.count[0] as u32, self.count[1] as u32]
    }

    /// The pixels' indices in the camera's order: the camera inside the finger looks along
    /// `n` with its `x` along the image's first side (`u`, columns, left to right) and its `y`
    /// along the second (`v`, rows, top to bottom), a right-handed frame, so an image viewer
    /// shows what it sees (not its mirror). Row `j`, column `i` is pixel `i ny + j`.
    fn camera_order(&self) -> impl Iterator<Item = usize> + '_ {
        let [nx, ny] = self.count;
        (0..ny).flat_map(move |j| (0..nx).map(move |i| i * ny + j))
    }

    /// The colours as 8-bit RGB in the camera's order (image files, MCAP, Rerun).
    pub fn camera_rgb8(&self) -> Vec<u8> {
        self.camera_order()
            .flat_map(|k| self.rgb[k].map(byte))
            .collect()
    }

    /// The heights as little-endian float32, m, in the camera's order.
    pub fn camera_height_f32_le(&self) -> Vec<u8> {
        self.camera_order()
            .flat_map(|k| (self.height_m[k] as f32).to_le_bytes())
            .collect()
    }
}

/// A colour channel in `[0, 1]` as a byte, `round(255 c)`.
fn byte(c: f64) -> u8 {
    (c * 255.0).round() as u8
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
