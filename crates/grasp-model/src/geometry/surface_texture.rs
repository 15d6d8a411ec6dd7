//! Texture heights on a patch, `h` (m, a peak positive, toward the other body) at points
//! `(x along t1, y along t2)`, the contact point at the origin: a measured height map's
//! ([`HeightGrid`], sampled bilinearly) and parallel ridges' (a cosine profile). A random
//! surface's are `super::random_surface`'s; which a finger has, its texture spec says
//! (`crate::scene::texture_spec`).

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

/// How far (in pixels) an element centre may lie beyond a height map's outermost pixel
/// centres and still be sampled there: round-off of the element centres, never more.
pub const MAP_EDGE_TOLERANCE_PIXELS: f64 = 1e-6;

/// Parallel ridges of a cosine profile, `h = A cos(2 pi s / L)` across them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ridges {
    /// Amplitude `A`, m.
    pub amplitude_m: f64,
    /// Period `L`, m.
    pub period_m: f64,
    /// Direction across the ridges, degrees from `t1` toward `t2`.
    pub angle_deg: f64,
}

/// The ridges' height `A cos(2 pi s / L)` at `c = (x, y)`, `s = x cos(theta) + y sin(theta)`.
pub fn ridge_height_m(ridges: &Ridges, c: [f64; 2]) -> f64 {
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
}
