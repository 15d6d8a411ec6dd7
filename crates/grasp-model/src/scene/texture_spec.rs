//! `fingers[i].texture` and `fingers[i].gap` as written: a contact's surface texture (a height
//! map from a file, ridges, or a seeded random self-affine surface) and how its smooth gap is
//! computed (exact from the shapes, or the thesis's quadratic form).
//!
//! Heights `h` (m) are the combined roughness of both surfaces under the patch, measured
//! toward the other body (a peak is positive): the initial gap of an element is its smooth
//! gap less `h` at its centre, the whole shifted so that the first touch is at gap zero.

use crate::geometry::random_surface::{random_surface, SelfAffineSurface};
pub use crate::geometry::surface_texture::HeightGrid;
use crate::geometry::surface_texture::{map_height_at_m, ridge_height_m, Ridges};

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// How a finger's smooth initial gap is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum GapSpec {
    /// The distance along the contact normal between the fingertip's and the object's real
    /// surfaces at each element centre (the object's from `object.shape`, the tip's from
    /// `tip`): the default when the object has a shape.
    Exact,
    /// The thesis's parabolic form `x^2/2R1 + y^2/2R2` from the curvatures at the contact
    /// (Johnson 4.1): the default without a shape, and the only form without one.
    Quadratic,
}

/// `fingers[i].texture`: exactly one of `heights`, `ridges`, `random`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TextureSpec {
    /// A measured height map: `{"file": "h.npy", "pixel_m": [dx, dy]}`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heights: Option<HeightMapSpec>,
    /// Parallel ridges: `{"amplitude_m": A, "period_m": L, "angle_deg": theta}`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ridges: Option<RidgesSpec>,
    /// A seeded random isotropic self-affine surface:
    /// `{"rms_m": s, "hurst": H, "wavelengths_m": [long, short], "seed": n}`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub random: Option<RandomSurfaceSpec>,
}

/// A height map read from a file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HeightMapSpec {
    // Its heights, once read (or given as an array), travel beside the scene: the loaded
    // scene's `SceneGeometry::height_maps`.
    /// Path of a `.npy` (2-D, float or integer) or `.csv` (rows of numbers) file of heights in
    /// metres, relative to the scene file's folder. Rows run along `t1`, columns along `t2`;
    /// the map's centre is on the contact point.
    pub file: String,
    /// Pixel sizes `[dx, dy]`, m, along `t1` (rows) and `t2` (columns).
    pub pixel_m: [f64; 2],
}

/// Parallel ridges of a cosine profile.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RidgesSpec {
    /// Amplitude `A`, m (half the peak-to-valley height): `h = A cos(2 pi s / L)`.
    pub amplitude_m: f64,
    /// Period `L`, m.
    pub period_m: f64,
    /// Direction across the ridges, degrees from `t1` toward `t2`: the profile varies along
    /// `s = x cos(theta) + y sin(theta)` (default 0: crests along `t2`).
    #[serde(default)]
    pub angle_deg: f64,
}

/// A random isotropic self-affine surface (Persson et al. 2005): power spectral density
/// `C(q) ~ q^(-2(1 + H))` between the wavenumbers of the long and short wavelengths, flat
/// below the long one (roll-off), zero above the short one.
///
/// It is generated on a periodic square grid of pixels `short / 8`, `N x N` with `N` the
/// smallest power of two whose side covers both the patch's larger side and the long
/// wavelength, by the random-phase method (phases from ChaCha8 seeded with `seed`), scaled to
/// exactly `rms_m`, and sampled bilinearly at the element centres: the same seed gives the
/// same heights on every machine and for any element count (a finer grid samples the same
/// surface), but a patch of another *size* may need another `N` and then sees another
/// realisation of the same statistics. Validation asks for `short` at least two elements
/// (finer texture cannot be resolved) and `N <= 8192`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RandomSurfaceSpec {
    /// Root-mean-square height, m.
    pub rms_m: f64,
    /// Hurst exponent `H`, in (0, 1].
    pub hurst: f64,
    /// `[long, short]` wavelengths, m: the roll-off and the short-wavelength cutoff.
    pub wavelengths_m: [f64; 2],
    /// Seed of the generator: the same seed gives the same heights on every machine.
    #[serde(default)]
    pub seed: u64,
}

impl RidgesSpec {
    /// The ridges this spec describes.
    pub fn ridges(&self) -> Ridges {
        Ridges {
            amplitude_m: self.amplitude_m,
            period_m: self.period_m,
            angle_deg: self.angle_deg,
        }
    }
}

impl RandomSurfaceSpec {
    /// The statistics of the surface this spec describes.
    pub fn surface(&self) -> SelfAffineSurface {
        SelfAffineSurface {
            rms_m: self.rms_m,
            hurst: self.hurst,
            wavelengths_m: self.wavelengths_m,
            seed: self.seed,
        }
    }
}

/// The heights `h_k`, m, of the texture `spec` at the element centres `centres_m` (m, patch
/// coordinates) of a patch of elements `element_m` (m, along `t1` and `t2`), `map` the height
/// map's heights when the texture is one (its file read by the caller):
///
/// - `heights`: bilinear interpolation of the map, pixel `(i, j)` centred at
///   `((i - (rows - 1)/2) dx, (j - (cols - 1)/2) dy)` (`map_height_at_m`); a centre outside
///   the map is an error.
/// - `ridges`: `h = A cos(2 pi s / L)`, `s = x cos(theta) + y sin(theta)` (`ridge_height_m`).
/// - `random`: the self-affine surface of [`crate::random_surface`] for a patch whose sides
///   are the centres' extent plus one element (the patch itself: its element centres lie half
///   an element inside its edges), sampled bilinearly.
///
/// Errors (a spec validation refuses, or a map not read) name no path: the caller does.
pub fn texture_heights_m(
    spec: &TextureSpec,
    map: Option<&HeightGrid>,
    centres_m: &[[f64; 2]],
    element_m: [f64; 2],
) -> Result<Vec<f64>, String> {
    match (&spec.heights, &spec.ridges, &spec.random) {
        (Some(heights), None, None) => {
            let grid = map.ok_or(
                "the height map was not read: read the scene with its files (the grasp CLI, \
                 grasp.Scene or grasp_io)",
            )?;
            centres_m
                .iter()
                .map(|c| map_height_at_m(grid, heights.pixel_m, *c))
                .collect()
        }
        (None, Some(ridges), None) => {
            let ridges = ridges.ridges();
            Ok(centres_m
                .iter()
                .map(|c| ridge_height_m(&ridges, *c))
                .collect())
        }
        (None, None, Some(random)) => {
            if centres_m.is_empty() {
                return Ok(Vec::new());
            }
            let patch_m = patch_sides_m(centres_m, element_m)
                .ok_or("needs finite element centres and element sizes > 0")?;
            let surface = random_surface(&random.surface(), patch_m)?;
            Ok(centres_m
                .iter()
                .map(|c| surface.height_at_m(c[0], c[1]))
                .collect())
        }
        _ => Err("needs exactly one of heights, ridges, random".into()),
    }
}

/// The sides of the patch whose element centres are `centres_m`: `2 max |c| + element` along
/// each axis (the patch is centred on the contact point).
fn patch_sides_m(centres_m: &[[f64; 2]], element_m: [f64; 2]) -> Option<[f64; 2]> {
    let mut sides = [0.0; 2];
    for k in 0..2 {
        let reach = centres_m.iter().fold(0.0_f64, |m, c| m.max(c[k].abs()));
        sides[k] = 2.0 * reach + element_m[k];
        if !(sides[k].is_finite() && element_m[k] > 0.0) {
            return None;
        }
    }
    Some(sides)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_texture_needs_exactly_one_member_and_a_read_map() {
        let none = TextureSpec::default();
        assert!(texture_heights_m(&none, None, &[[0.0, 0.0]], [1.0, 1.0]).is_err());
        let unread = TextureSpec {
            heights: Some(HeightMapSpec {
                file: "h.npy".into(),
                pixel_m: [1.0, 1.0],
            }),
            ..TextureSpec::default()
        };
        let e = texture_heights_m(&unread, None, &[[0.0, 0.0]], [1.0, 1.0]).unwrap_err();
        assert!(e.contains("not read"), "{e}");
        let read = unread.clone();
        let map = HeightGrid {
            rows: 2,
            cols: 2,
            heights_m: (0..4).map(|k| (k / 2 + 2 * (k % 2)) as f64).collect(),
        };
        // The centre of a 2 x 2 map is the mean of its four pixels.
        assert_eq!(
            texture_heights_m(&read, Some(&map), &[[0.0, 0.0]], [1.0, 1.0]),
            Ok(vec![1.5])
        );
        let random = TextureSpec {
            random: Some(RandomSurfaceSpec {
                rms_m: 1e-6,
                hurst: 0.5,
                wavelengths_m: [1e-4, 1e-5],
                seed: 1,
            }),
            ..read
        };
        assert!(texture_heights_m(&random, Some(&map), &[[0.0, 0.0]], [1.0, 1.0]).is_err());
    }
}
