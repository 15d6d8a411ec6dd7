//! `fingers[i].texture` and `fingers[i].gap` as written: a contact's surface texture (a height
//! map from a file, ridges, or a seeded random self-affine surface) and how its smooth gap is
//! computed (exact from the shapes, or the thesis's quadratic form).
//!
//! Heights `h` (m) are the combined roughness of both surfaces under the patch, measured
//! toward the other body (a peak is positive): the initial gap of an element is its smooth
//! gap less `h` at its centre, the whole shifted so that the first touch is at gap zero.

use std::sync::Arc;

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
    /// Path of a `.npy` (2-D, float or integer) or `.csv` (rows of numbers) file of heights in
    /// metres, relative to the scene file's folder. Rows run along `t1`, columns along `t2`;
    /// the map's centre is on the contact point.
    pub file: String,
    /// Pixel sizes `[dx, dy]`, m, along `t1` (rows) and `t2` (columns).
    pub pixel_m: [f64; 2],
    /// The heights, filled in when the scene is read (from `file`) or given by Python as an
    /// array. Not part of the file.
    #[serde(skip)]
    #[schemars(skip)]
    pub data: Option<Arc<HeightGrid>>,
}

/// Heights on a regular grid, m: `rows x cols`, row-major. In a height map, pixel `(i, j)` is
/// centred at `((i - (rows - 1)/2) dx, (j - (cols - 1)/2) dy)` from the contact point, and the
/// heights between pixel centres are bilinear.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightGrid {
    /// Number of rows (along `t1`).
    pub rows: usize,
    /// Number of columns (along `t2`).
    pub cols: usize,
    /// Heights, m, `k = row * cols + col`.
    pub heights_m: Vec<f64>,
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
