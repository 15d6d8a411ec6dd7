//! The texture heights under a finger's patch: `h` (m, a peak positive, toward the other
//! body) at each element centre `(x along t1, y along t2)`, the contact point at the origin,
//! from `fingers[i].texture` (a height map, ridges, or a seeded random surface).

use crate::geometry::random_surface::random_surface;
use crate::geometry::texture_spec::{HeightGrid, RidgesSpec, TextureSpec};

/// How far (in pixels) an element centre may lie beyond a height map's outermost pixel
/// centres and still be sampled there: round-off of the element centres, never more.
pub const MAP_EDGE_TOLERANCE_PIXELS: f64 = 1e-6;

/// The heights `h_k`, m, of `spec` at the element centres `centres_m` (m, patch coordinates)
/// of a patch of elements `element_m` (m, along `t1` and `t2`):
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
    centres_m: &[[f64; 2]],
    element_m: [f64; 2],
) -> Result<Vec<f64>, String> {
    match (&spec.heights, &spec.ridges, &spec.random) {
        (Some(map), None, None) => {
            let grid = map.data.as_deref().ok_or(
                "the height map was not read: read the scene with its files (the grasp CLI, \
                 grasp.Scene or grasp_io)",
            )?;
            centres_m
                .iter()
                .map(|c| map_height_at_m(grid, map.pixel_m, *c))
                .collect()
        }
        (None, Some(ridges), None) => Ok(centres_m
            .iter()
            .map(|c| ridge_height_m(ridges, *c))
            .collect()),
        (None, None, Some(random)) => {
            if centres_m.is_empty() {
                return Ok(Vec::new());
            }
            let patch_m = patch_sides_m(centres_m, element_m)
                .ok_or("needs finite element centres and element sizes > 0")?;
            let surface = random_surface(random, patch_m)?;
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

/// The ridges' height `A cos(2 pi s / L)` at `c = (x, y)`, `s = x cos(theta) + y sin(theta)`.
pub fn ridge_height_m(ridges: &RidgesSpec, c: [f64; 2]) -> f64 {
    let (sin, cos) = libm::sincos(ridges.angle_deg.to_radians());
    let s = c[0] * cos + c[1] * sin;
    ridges.amplitude_m * libm::cos(2.0 * std::f64::consts::PI * s / ridges.period_m)
}

/// Half the span of a map's pixel centres along `t1` and `t2`, m:
/// `((rows - 1) dx / 2, (cols - 1) dy / 2)`. Bilinear interpolation reaches that far from the
/// map's centre (the contact point).
pub fn map_half_extent_m(grid: &HeightGrid, pixel_m: [f64; 2]) -> [f64; 2] {
    [
        0.5 * (grid.rows.max(1) - 1) as f64 * pixel_m[0],
        0.5 * (grid.cols.max(1) - 1) as f64 * pixel_m[1],
    ]
}

/// The map's height at `c = (x, y)`, m: bilinear between the four pixel centres around it,
/// pixel `(i, j)` at `((i - (rows - 1)/2) dx, (j - (cols - 1)/2) dy)`, rows along `t1`. A point
/// beyond the outermost pixel centres (more than [`MAP_EDGE_TOLERANCE_PIXELS`]) is an error.
pub fn map_height_at_m(grid: &HeightGrid, pixel_m: [f64; 2], c: [f64; 2]) -> Result<f64, String> {
    let cell = |x: f64, n: usize, d: f64| -> Option<(usize, f64)> {
        let u = x / d + 0.5 * (n - 1) as f64;
        let last = (n - 1) as f64;
        if !(u >= -MAP_EDGE_TOLERANCE_PIXELS && u <= last + MAP_EDGE_TOLERANCE_PIXELS) {
            return None;
        }
        let u = u.clamp(0.0, last);
        // The lower node of the cell; the last cell for the last node (and a one-pixel axis).
        let lo = (u.floor() as usize).min(n.saturating_sub(2));
        Some((lo, u - lo as f64))
    };
    let (rows, cols) = (grid.rows, grid.cols);
    let outside = || {
        let e = map_half_extent_m(grid, pixel_m);
        format!(
            "the element centre ({:e}, {:e}) m lies outside the height map, whose pixel \
             centres span +-{:e} m along t1 and +-{:e} m along t2",
            c[0], c[1], e[0], e[1]
        )
    };
    if rows == 0 || cols == 0 || grid.heights_m.len() != rows * cols {
        return Err(format!(
            "the height map holds {} heights, not {rows} x {cols} (> 0)",
            grid.heights_m.len()
        ));
    }
    let (i, fx) = cell(c[0], rows, pixel_m[0]).ok_or_else(outside)?;
    let (j, fy) = cell(c[1], cols, pixel_m[1]).ok_or_else(outside)?;
    let h = |a: usize, b: usize| grid.heights_m[a.min(rows - 1) * cols + b.min(cols - 1)];
    Ok((1.0 - fx) * ((1.0 - fy) * h(i, j) + fy * h(i, j + 1))
        + fx * ((1.0 - fy) * h(i + 1, j) + fy * h(i + 1, j + 1)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::texture_spec::{HeightMapSpec, RandomSurfaceSpec};
    use std::sync::Arc;

    fn map(rows: usize, cols: usize, f: impl Fn(usize, usize) -> f64) -> HeightGrid {
        HeightGrid {
            rows,
            cols,
            heights_m: (0..rows * cols).map(|k| f(k / cols, k % cols)).collect(),
        }
    }

    #[test]
    fn one_pixel_axes_and_edges_are_sampled() {
        // A single column: only y = 0 lies on it; x runs along the rows.
        let g = map(3, 1, |i, _| i as f64);
        assert_eq!(map_height_at_m(&g, [1.0, 1.0], [0.5, 0.0]), Ok(1.5));
        assert_eq!(map_height_at_m(&g, [1.0, 1.0], [1.0, 0.0]), Ok(2.0));
        assert!(map_height_at_m(&g, [1.0, 1.0], [0.0, 1e-3]).is_err());
        assert!(map_height_at_m(&g, [1.0, 1.0], [1.001, 0.0])
            .unwrap_err()
            .contains("outside the height map"));
    }

    #[test]
    fn a_texture_needs_exactly_one_member_and_a_read_map() {
        let none = TextureSpec::default();
        assert!(texture_heights_m(&none, &[[0.0, 0.0]], [1.0, 1.0]).is_err());
        let unread = TextureSpec {
            heights: Some(HeightMapSpec {
                file: "h.npy".into(),
                pixel_m: [1.0, 1.0],
                data: None,
            }),
            ..TextureSpec::default()
        };
        let e = texture_heights_m(&unread, &[[0.0, 0.0]], [1.0, 1.0]).unwrap_err();
        assert!(e.contains("not read"), "{e}");
        let read = TextureSpec {
            heights: Some(HeightMapSpec {
                data: Some(Arc::new(map(2, 2, |i, j| (i + 2 * j) as f64))),
                ..unread.heights.clone().unwrap()
            }),
            ..TextureSpec::default()
        };
        // The centre of a 2 x 2 map is the mean of its four pixels.
        assert_eq!(
            texture_heights_m(&read, &[[0.0, 0.0]], [1.0, 1.0]),
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
        assert!(texture_heights_m(&random, &[[0.0, 0.0]], [1.0, 1.0]).is_err());
    }
}
