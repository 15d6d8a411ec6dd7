//! A gel image's surface normals and colours from its height map: the photometric model of an
//! optical tactile sensor (GelSight: Johnson and Adelson, CVPR 2009; Yuan et al., Sensors
//! 2017), in the image's frame `(u, v, w)`: `u`, `v` along the image's sides, `w` from the
//! gel toward the camera (inside the finger).
//!
//! - **Normals.** The surface is `w = h(u, v)` (`h` the height map, into the pad, toward the
//!   camera), so its unit normal toward the camera is `N = (-h_u, -h_v, 1) / sqrt(1 + h_u^2 +
//!   h_v^2)`; the slopes `h_u`, `h_v` are central differences between the neighbouring pixels
//!   (one-sided on the image's border, 0 along a side of one pixel). A flat gel has `N = (0,
//!   0, 1)`.
//! - **Lights** (Lambertian reflection of the gel's matte coating): each channel `c` of a
//!   pixel reads `I_c = ambient_c + sum_l rgb_lc max(0, N . L_l)`, `L_l` the unit direction
//!   toward light `l`, clipped to `[0, 1]` (the camera saturates).
//! - **Lookup** (a calibrated sensor's table): the colour read bilinearly from a table over
//!   the slopes `(s_u, s_v) = (-h_u, -h_v)`, slopes beyond its range clamped to its edge.

use crate::scene::gel_spec::{default_lights, GelSpec, LightSpec, LookupSpec};

/// The unit surface normals `(u, v, w)` of a height map `h` (m, row-major over `count`
/// pixels at `pitch_m`), by central differences (the module's formula).
pub fn surface_normals(h: &[f64], count: [usize; 2], pitch_m: [f64; 2]) -> Vec<[f64; 3]> {
    let [nx, ny] = count;
    let at = |i: usize, j: usize| h[i * ny + j];
    let slope = |lo: f64, hi: f64, steps: usize, pitch: f64| match steps {
        0 => 0.0,
        s => (hi - lo) / (s as f64 * pitch),
    };
    let mut out = Vec::with_capacity(nx * ny);
    for i in 0..nx {
        let (i0, i1) = (i.saturating_sub(1), (i + 1).min(nx - 1));
        for j in 0..ny {
            let (j0, j1) = (j.saturating_sub(1), (j + 1).min(ny - 1));
            let hu = slope(at(i0, j), at(i1, j), i1 - i0, pitch_m[0]);
            let hv = slope(at(i, j0), at(i, j1), j1 - j0, pitch_m[1]);
            let norm = (1.0 + hu * hu + hv * hv).sqrt();
            out.push([-hu / norm, -hv / norm, 1.0 / norm]);
        }
    }
    out
}

/// The colour `[r, g, b]` (each in `[0, 1]`) of every normal under `spec`'s shading: its
/// lookup table when it has one, else its lights (or [`default_lights`]) and ambient light.
pub fn shade(spec: &GelSpec, normals: &[[f64; 3]]) -> Vec<[f64; 3]> {
    if let Some(table) = &spec.lookup {
        return normals.iter().map(|n| looked_up(table, n)).collect();
    }
    let lights = spec.lights.clone().unwrap_or_else(default_lights);
    let units: Vec<([f64; 3], [f64; 3])> = lights.iter().map(unit_light).collect();
    let ambient = spec.ambient_rgb.unwrap_or([0.0; 3]);
    normals.iter().map(|n| lit(&units, ambient, n)).collect()
}

/// A light's unit direction and colour.
fn unit_light(l: &LightSpec) -> ([f64; 3], [f64; 3]) {
    let d = l.direction;
    let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    ([d[0] / length, d[1] / length, d[2] / length], l.rgb)
}

/// Lambert's law at one normal: `ambient + sum_l rgb_l max(0, N . L_l)`, clipped to `[0, 1]`.
fn lit(lights: &[([f64; 3], [f64; 3])], ambient: [f64; 3], n: &[f64; 3]) -> [f64; 3] {
    let mut out = ambient;
    for (d, rgb) in lights {
        let cosine = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]).max(0.0);
        for c in 0..3 {
            out[c] += rgb[c] * cosine;
        }
    }
    out.map(|x| x.clamp(0.0, 1.0))
}

/// The table's colour at the slopes of normal `n`, bilinear between its entries.
fn looked_up(t: &LookupSpec, n: &[f64; 3]) -> [f64; 3] {
    let (na, nb) = (t.rgb.len(), t.rgb[0].len());
    let r = t.slope_range;
    // Position on the table's axis of `na` entries over `[-r, r]`: the lower entry and the
    // fraction toward the next.
    let place = |slope: f64, entries: usize| {
        let x = ((slope.clamp(-r, r) + r) / (2.0 * r)) * (entries - 1) as f64;
        let k = (x.floor() as usize).min(entries - 2);
        (k, x - k as f64)
    };
    // `N = (s_u, s_v, 1) / |.|`.
    let (a, fa) = place(n[0] / n[2], na);
    let (b, fb) = place(n[1] / n[2], nb);
    std::array::from_fn(|c| {
        let low = t.rgb[a][b][c] * (1.0 - fb) + t.rgb[a][b + 1][c] * fb;
        let high = t.rgb[a + 1][b][c] * (1.0 - fb) + t.rgb[a + 1][b + 1][c] * fb;
        low * (1.0 - fa) + high * fa
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gel(lights: Option<Vec<LightSpec>>, lookup: Option<LookupSpec>) -> GelSpec {
        GelSpec {
            image_px: [5, 4],
            field_of_view_m: [5e-3, 4e-3],
            rotation_rad: 0.0,
            offset_m: [0.0; 2],
            lights,
            ambient_rgb: None,
            lookup,
            response: None,
        }
    }

    #[test]
    fn a_plane_has_its_own_normal_everywhere() {
        // h = a u + b v: every difference, central or one-sided, is exact.
        let (a, b, p) = (0.3, -0.2, [1e-3, 2e-3]);
        let h: Vec<f64> = (0..5)
            .flat_map(|i| (0..4).map(move |j| a * i as f64 * p[0] + b * j as f64 * p[1]))
            .collect();
        let norm = (1.0 + a * a + b * b).sqrt();
        for n in surface_normals(&h, [5, 4], p) {
            let want = [-a / norm, -b / norm, 1.0 / norm];
            for c in 0..3 {
                assert!((n[c] - want[c]).abs() < 1e-12, "{n:?} {want:?}");
            }
        }
    }

    #[test]
    fn a_flat_gel_under_the_default_lights_reads_half_of_each_colour() {
        // Each default light is 30 degrees above the plane: N . L = sin 30 = 0.5.
        let colours = shade(&gel(None, None), &[[0.0, 0.0, 1.0]]);
        for c in colours[0] {
            assert!((c - 0.5).abs() < 1e-12, "{colours:?}");
        }
    }

    #[test]
    fn a_surface_turned_from_a_light_is_dark_in_its_colour() {
        let light = LightSpec {
            direction: [1.0, 0.0, 1.0],
            rgb: [0.0, 2.0, 0.0],
        };
        let g = gel(Some(vec![light]), None);
        // Normal at 45 degrees toward the light: N . L = 1; away from it: 0.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let out = shade(&g, &[[s, 0.0, s], [-s, 0.0, s]]);
        assert_eq!(out[0], [0.0, 1.0, 0.0], "clipped to 1");
        assert_eq!(out[1], [0.0, 0.0, 0.0]);
    }

    #[test]
    fn a_lookup_table_of_a_linear_colour_is_read_exactly() {
        // Red = (s_u + 1)/2, green = (s_v + 1)/2 over [-1, 1]: bilinear reads it exactly.
        let rgb: Vec<Vec<[f64; 3]>> = (0..3)
            .map(|a| {
                (0..5)
                    .map(|b| [a as f64 / 2.0, b as f64 / 4.0, 0.25])
                    .collect()
            })
            .collect();
        let g = gel(
            None,
            Some(LookupSpec {
                slope_range: 1.0,
                rgb,
            }),
        );
        let (su, sv): (f64, f64) = (0.37, -0.61);
        let norm = (1.0 + su * su + sv * sv).sqrt();
        let out = shade(&g, &[[su / norm, sv / norm, 1.0 / norm], [0.0, -3.0, 1.0]]);
        assert!((out[0][0] - (su + 1.0) / 2.0).abs() < 1e-12, "{out:?}");
        assert!((out[0][1] - (sv + 1.0) / 2.0).abs() < 1e-12, "{out:?}");
        assert_eq!(
            out[1],
            [0.5, 0.0, 0.25],
            "a slope beyond the range is clamped"
        );
    }
}
