//! `fingers[i].sensor.gel` as written: an optical gel sensor's image of the pad, GelSight or
//! DIGIT style. Its camera looks at the pad's surface from inside the finger; the image is
//! the deformed surface as a height map, its surface normals, and an RGB image shaded from
//! them, by lights (a Lambertian model) or by a calibrated lookup table from slopes to colour
//! (`crate::sensors::gel_shading`).
//!
//! The image is `image_px` pixels over the gel's `field_of_view_m`, centred on the contact
//! point plus `offset_m` and turned by `rotation_rad` from `t1` toward `t2`; pixel `(i, j)`
//! is the surface point at its centre (a grid laid out as the taxels' and markers', with the
//! pitch `field_of_view_m / image_px` along each side).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::scene::response_spec::ResponseSpec;
use crate::scene::sensor_kind::{ElementGrid, GridLayout, HalfSpaceNeed, SensorKind};

/// `fingers[i].sensor.gel`: an optical gel sensor's image of the pad.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GelSpec {
    /// Pixels along the image's two sides `[nx, ny]` (along `t1`, `t2` before
    /// `rotation_rad`), each in `[1, 1024]`.
    pub image_px: [usize; 2],
    /// The gel's field of view `[wx, wy]`, m: the image's extent along its sides, each in
    /// `[1e-9, 10]` (pixel pitch `wx / nx`, `wy / ny`).
    pub field_of_view_m: [f64; 2],
    /// Angle of the image's first side to `t1`, rad (counter-clockwise toward `t2`), in
    /// `[-2 pi, 2 pi]`; default 0.
    #[serde(default)]
    pub rotation_rad: f64,
    /// The image's centre from the contact point along `t1`, `t2`, m, each in `[-1e3, 1e3]`;
    /// default `[0, 0]`.
    #[serde(default)]
    pub offset_m: [f64; 2],
    /// The lights of the Lambertian shading (1 to 8), each `{"direction": [u, v, w], "rgb":
    /// [r, g, b]}`: the direction toward the light in the image's frame (`u`, `v` its sides,
    /// `w` from the gel toward the camera), any length but zero, `w > 0`; the colour each
    /// channel in `[0, 10]`. Default: [`default_lights`]. Not with `lookup`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lights: Option<Vec<LightSpec>>,
    /// Light reaching the camera from everywhere, added to every pixel, each channel in
    /// `[0, 1]`; default `[0, 0, 0]`. Not with `lookup`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambient_rgb: Option<[f64; 3]>,
    /// A calibrated table from the surface's slopes to colour, in place of the lights.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lookup: Option<LookupSpec>,
    /// How the camera departs from the ideal image (gain, noise, saturation, quantisation of
    /// each colour channel, in its `[0, 1]`; `crate::scene::response_spec`); default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub response: Option<ResponseSpec>,
}

/// One light of the Lambertian shading.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LightSpec {
    /// Direction toward the light in the image's frame `[u, v, w]` (`w` from the gel toward
    /// the camera), any non-zero length, `w > 0`.
    pub direction: [f64; 3],
    /// The light's colour `[r, g, b]`, each in `[0, 10]`: a flat gel lit by it alone reads
    /// `rgb` times the cosine of its angle to `w`.
    pub rgb: [f64; 3],
}

/// A calibrated lookup table from the surface's slopes `(s_u, s_v) = (-dh/du, -dh/dv)` (`h`
/// the height map, into the pad) to colour, as calibrated optical sensors (GelSight's
/// gradient tables) use: `rgb[a][b]` is the colour at `s_u = -r + 2 r a / (na - 1)`, `s_v =
/// -r + 2 r b / (nb - 1)` (`r` = `slope_range`), read bilinearly, slopes beyond `r` clamped.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LookupSpec {
    /// The largest slope the table covers, in `(0, 100]` (dimensionless, m/m).
    pub slope_range: f64,
    /// The colours, `na x nb` (each in `[2, 256]`), each channel in `[0, 1]`.
    pub rgb: Vec<Vec<[f64; 3]>>,
}

/// Most pixels along an image's side.
pub const MAX_PIXELS_PER_SIDE: usize = 1024;

/// Most lights of a Lambertian shading.
pub const MAX_LIGHTS: usize = 8;

/// The most kernel evaluations a gel image may take: on the dense path pixels x elements
/// (each the surface rectangle integrals of one element at one pixel), on the FFT path the
/// entries of the lattice's kernel table; about 20 s on one core, as the markers'.
pub const MAX_GEL_KERNEL_EVALUATIONS: f64 = 2e8;

/// Most points of the element lattice the FFT read-out convolves on (its kernel spectra,
/// forces and displacements take about 600 bytes a point with friction, 620 MB at this size,
/// counted in the solve's memory estimate, `crate::scene::memory_budget::sensor_bytes`); a
/// larger lattice is read densely.
pub const MAX_LATTICE_POINTS: usize = 1024 * 1024;

/// The lights when a gel gives none: red, green and blue at 120 degrees from each other
/// (azimuths 0, 120 and 240 degrees from the image's first side), 30 degrees above the gel's
/// plane, each of unit colour; a flat gel reads `sin 30 deg` = 0.5 in each channel.
pub fn default_lights() -> Vec<LightSpec> {
    let elevation = 30f64.to_radians();
    (0..3)
        .map(|k| {
            let azimuth = (120.0 * k as f64).to_radians();
            let mut rgb = [0.0; 3];
            rgb[k] = 1.0;
            LightSpec {
                direction: [
                    elevation.cos() * azimuth.cos(),
                    elevation.cos() * azimuth.sin(),
                    elevation.sin(),
                ],
                rgb,
            }
        })
        .collect()
}

impl GelSpec {
    /// Pixels in the image.
    pub fn pixel_count(&self) -> usize {
        self.image_px[0] * self.image_px[1]
    }

    /// The pixel pitch along the image's sides, m.
    pub fn pixel_m(&self) -> [f64; 2] {
        [
            self.field_of_view_m[0] / self.image_px[0] as f64,
            self.field_of_view_m[1] / self.image_px[1] as f64,
        ]
    }

    /// Where the image's pixels fall on the patch's element lattice, when they do: the
    /// image unturned, its pixel pitch the elements' (to 1e-9 of it) and its first pixel's
    /// centre an element lattice point (to 1e-6 of the pitch). `Some([i0, j0])`: the lattice
    /// index of pixel `(0, 0)`, element `(0, 0)` at `[0, 0]`.
    pub fn lattice_origin(&self, patch: &ElementGrid) -> Option<[i64; 2]> {
        if self.rotation_rad != 0.0 {
            return None;
        }
        let pitch = self.pixel_m();
        let mut origin = [0i64; 2];
        for k in 0..2 {
            let (n, h) = (patch.count[k], patch.element_m[k]);
            if (pitch[k] - h).abs() > 1e-9 * h {
                return None;
            }
            // Pixel 0's and element 0's centres (`GridLayout::points_m`, unturned).
            let pixel0 = self.offset_m[k] - (self.image_px[k] as f64 - 1.0) / 2.0 * pitch[k];
            let element0 = -(n as f64 - 1.0) / 2.0 * h;
            let steps = (pixel0 - element0) / h;
            if (steps - steps.round()).abs() > 1e-6 || steps.abs() > 1e9 {
                return None;
            }
            origin[k] = steps.round() as i64;
        }
        Some(origin)
    }

    /// The element lattice the FFT read-out convolves on, when it is the cheaper read-out:
    /// the patch's elements and the image's pixels together, `[Lx, Ly]` points, and where the
    /// patch's element `(0, 0)` and the image's pixel `(0, 0)` are on it. `None` when the
    /// pixels are not on the lattice, when it has more than [`MAX_LATTICE_POINTS`], or when
    /// its kernel table (`(2 Lx - 1)(2 Ly - 1)` evaluations) is more work than reading every
    /// pixel from every element (a small image far from the patch).
    pub fn lattice(&self, patch: &ElementGrid) -> Option<Lattice> {
        let origin = self.lattice_origin(patch)?;
        let mut size = [0usize; 2];
        let mut element0 = [0usize; 2];
        let mut pixel0 = [0usize; 2];
        for k in 0..2 {
            let (n, px) = (patch.count[k] as i64, self.image_px[k] as i64);
            let low = origin[k].min(0);
            let high = (origin[k] + px).max(n);
            size[k] = (high - low) as usize;
            element0[k] = (-low) as usize;
            pixel0[k] = (origin[k] - low) as usize;
        }
        let table = ((2 * size[0] - 1) * (2 * size[1] - 1)) as f64;
        let dense = self.pixel_count() as f64 * patch.len() as f64;
        if size[0] * size[1] > MAX_LATTICE_POINTS || table >= dense {
            return None;
        }
        Some(Lattice {
            size,
            element0,
            pixel0,
        })
    }
}

/// The lattice of a gel image on its patch's element grid (the FFT read-out's).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lattice {
    /// Points along the lattice's sides.
    pub size: [usize; 2],
    /// The lattice index of the patch's element `(0, 0)`.
    pub element0: [usize; 2],
    /// The lattice index of the image's pixel `(0, 0)`.
    pub pixel0: [usize; 2],
}

impl Lattice {
    /// Points of the lattice.
    pub fn len(&self) -> usize {
        self.size[0] * self.size[1]
    }

    /// True for a lattice without points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl SensorKind for GelSpec {
    fn key(&self) -> &'static str {
        "gel"
    }

    fn layout(&self) -> GridLayout {
        GridLayout {
            count: self.image_px,
            pitch_m: self.pixel_m(),
            rotation_rad: self.rotation_rad,
            offset_m: self.offset_m,
        }
    }

    /// On the lattice (the FFT read-out): its kernel table's `(2 Lx - 1)(2 Ly - 1)` entries;
    /// otherwise pixels x elements.
    fn kernel_evaluations(&self, patch: &ElementGrid) -> f64 {
        match self.lattice(patch) {
            Some(l) => ((2 * l.size[0] - 1) * (2 * l.size[1] - 1)) as f64,
            None => self.pixel_count() as f64 * patch.len() as f64,
        }
    }

    fn most_kernel_evaluations(&self) -> f64 {
        MAX_GEL_KERNEL_EVALUATIONS
    }

    fn work_terms(&self) -> &'static str {
        "pixels x elements, or the kernel table of the element lattice when the pixels lie on it"
    }

    fn work_fix(&self) -> &'static str {
        "use fewer pixels or a coarser patch, or lay the pixels on the element lattice (no \
         rotation, field_of_view_m / image_px equal to the element size, the image's first \
         pixel on an element centre) for the FFT read-out"
    }

    fn half_space_need(&self) -> Option<HalfSpaceNeed> {
        Some(HalfSpaceNeed {
            what: "gel images",
            instead: "drop the gel image",
            reads_stress: false,
        })
    }
}
