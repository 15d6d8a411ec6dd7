//! The checks of `fingers[i].texture`: exactly one member; a height map read, finite, of
//! heights no larger than the patch and covering the patch; ridges and a random surface with
//! their numbers in range and a shortest wavelength the patch's elements resolve (at least
//! [`MIN_ELEMENTS_PER_TEXTURE_WAVELENGTH`] elements: finer texture is refused, not warned
//! about, since it would alias into a longer, false one); a random surface's generation grid
//! bounded. Each problem names its JSON path and the fix.

use crate::geometry::random_surface::{grid_side, pixel_m};
use crate::geometry::surface_texture::{map_half_extent_m, MAP_EDGE_TOLERANCE_PIXELS};
use crate::scene::field_checks::{number, FieldChecks};
use crate::scene::limits::*;
use crate::scene::scene_format::FingerSpec;
use crate::scene::texture_spec::{HeightGrid, HeightMapSpec, RandomSurfaceSpec, RidgesSpec};

/// A usable patch, as the texture checks need it (the patch's own checks report the rest).
#[derive(Clone, Copy)]
struct Patch {
    size_m: [f64; 2],
    grid: [usize; 2],
    element_m: [f64; 2],
}

impl Patch {
    fn of(f: &FingerSpec) -> Option<Patch> {
        let (size_m, grid) = (f.patch.size, f.patch.grid);
        let ok = (0..2).all(|k| {
            size_m[k].is_finite() && PATCH_SIDE_RANGE_M.contains(&size_m[k]) && grid[k] > 0
        });
        ok.then(|| Patch {
            size_m,
            grid,
            element_m: [size_m[0] / grid[0] as f64, size_m[1] / grid[1] as f64],
        })
    }

    fn larger_side_m(&self) -> f64 {
        self.size_m[0].max(self.size_m[1])
    }

    /// Elements needed along each side for [`MIN_ELEMENTS_PER_TEXTURE_WAVELENGTH`] elements
    /// per `length_m` along `direction` (components along `t1`, `t2`), at least the grid's.
    fn grid_for(&self, length_m: f64, direction: [f64; 2]) -> [usize; 2] {
        let need = |k: usize| {
            let n = MIN_ELEMENTS_PER_TEXTURE_WAVELENGTH * self.size_m[k] * direction[k].abs()
                / length_m;
            (n.ceil() as usize).max(self.grid[k])
        };
        [need(0), need(1)]
    }
}

/// Checks `fingers[i].texture` (`p` is `fingers[i]`), `map` its height map's heights (when
/// its texture is one and they were read).
pub fn check_texture(p: &str, f: &FingerSpec, map: Option<&HeightGrid>, v: &mut FieldChecks) {
    let Some(t) = &f.texture else { return };
    let p = format!("{p}.texture");
    let given = [t.heights.is_some(), t.ridges.is_some(), t.random.is_some()];
    let count = given.iter().filter(|g| **g).count();
    if count != 1 {
        return v.push(
            &p,
            format!("has {count} of heights, ridges, random"),
            "give exactly one: {\"heights\": {...}}, {\"ridges\": {...}} or {\"random\": {...}}",
        );
    }
    let patch = Patch::of(f);
    if let Some(h) = &t.heights {
        check_height_map(&format!("{p}.heights"), h, map, patch, v);
    }
    if let Some(r) = &t.ridges {
        check_ridges(&format!("{p}.ridges"), r, patch, v);
    }
    if let Some(r) = &t.random {
        check_random(&format!("{p}.random"), r, patch, v);
    }
}

/// A height (an amplitude, an rms): finite, 0 only where `zero_ok`, else in
/// [`LENGTH_RANGE_M`], and no larger than the patch's larger side (the half-space theory
/// needs small slopes; a larger texture is a unit mistake).
fn check_height(path: &str, h: f64, zero_ok: bool, patch: Option<Patch>, v: &mut FieldChecks) {
    let fix = "give the height in metres (1 um = 1e-6)";
    if (zero_ok && h == 0.0) || !v.range(path, h, LENGTH_RANGE_M, "m", fix) {
        return;
    }
    if let Some(patch) = patch.filter(|q| h > q.larger_side_m()) {
        v.push(
            path,
            format!(
                "is {} m, larger than the patch's larger side {} m",
                number(h),
                number(patch.larger_side_m())
            ),
            fix,
        );
    }
}

fn check_height_map(
    p: &str,
    h: &HeightMapSpec,
    map: Option<&HeightGrid>,
    patch: Option<Patch>,
    v: &mut FieldChecks,
) {
    let mut pixels_ok = true;
    for k in 0..2 {
        pixels_ok &= v.range(
            &format!("{p}.pixel_m[{k}]"),
            h.pixel_m[k],
            LENGTH_RANGE_M,
            "m",
            "give the map's pixel size in metres (1 um = 1e-6), along t1 (rows) and t2 (columns)",
        );
    }
    let file = format!("{p}.file");
    let Some(grid) = map else {
        return v.push(
            &file,
            "was not read (a scene built in code, or read without its files)".into(),
            "read the scene with its files (the grasp CLI, grasp.Scene, grasp_io), or give its \
             heights in the loaded scene's geometry (`SceneGeometry::height_maps`)",
        );
    };
    if grid.rows == 0 || grid.cols == 0 || grid.heights_m.len() != grid.rows * grid.cols {
        return v.push(
            &file,
            format!(
                "holds {} heights, not {} x {} (> 0)",
                grid.heights_m.len(),
                grid.rows,
                grid.cols
            ),
            "give a 2-D array of heights with at least one row and one column",
        );
    }
    let at = |k: usize| format!("row {}, column {}", k / grid.cols, k % grid.cols);
    if let Some(k) = grid.heights_m.iter().position(|x| !x.is_finite()) {
        return v.push(
            &file,
            format!("has the height {} at {}", grid.heights_m[k], at(k)),
            "give finite heights in metres",
        );
    }
    let Some(patch) = patch else { return };
    let (k, top) = grid
        .heights_m
        .iter()
        .enumerate()
        .fold(
            (0, 0.0_f64),
            |m, (k, x)| if x.abs() > m.1 { (k, x.abs()) } else { m },
        );
    if top > patch.larger_side_m() {
        v.push(
            &file,
            format!(
                "has a height of {} m at {}, larger than the patch's larger side {} m",
                number(grid.heights_m[k]),
                at(k),
                number(patch.larger_side_m())
            ),
            "give the heights in metres (1 um = 1e-6), a peak positive",
        );
    }
    if pixels_ok {
        check_coverage(&file, h, grid, patch, v);
    }
}

/// The map's pixel centres must span the patch's element centres.
fn check_coverage(
    file: &str,
    h: &HeightMapSpec,
    grid: &HeightGrid,
    patch: Patch,
    v: &mut FieldChecks,
) {
    let half = map_half_extent_m(grid, h.pixel_m);
    let reach = [0, 1].map(|k| 0.5 * (patch.size_m[k] - patch.element_m[k]));
    let covers = (0..2).all(|k| reach[k] <= half[k] + MAP_EDGE_TOLERANCE_PIXELS * h.pixel_m[k]);
    if !covers {
        v.push(
            file,
            format!(
                "covers +-{} m by +-{} m around the contact point ({} x {} pixel centres), \
                 but the patch's element centres reach +-{} m by +-{} m",
                number(half[0]),
                number(half[1]),
                grid.rows,
                grid.cols,
                number(reach[0]),
                number(reach[1])
            ),
            "give a larger map (or larger pixel_m if the pixels were mis-sized), or a smaller \
             patch.size: the map's centre is on the contact point, rows along t1",
        );
    }
}

fn check_ridges(p: &str, r: &RidgesSpec, patch: Option<Patch>, v: &mut FieldChecks) {
    check_height(&format!("{p}.amplitude_m"), r.amplitude_m, true, patch, v);
    let period = format!("{p}.period_m");
    let period_ok = v.range(
        &period,
        r.period_m,
        LENGTH_RANGE_M,
        "m",
        "give the ridges' period in metres",
    );
    let angle_ok = v.range(
        &format!("{p}.angle_deg"),
        r.angle_deg,
        -360.0..=360.0,
        "deg",
        "give the direction across the ridges in degrees from t1 toward t2",
    );
    let (Some(patch), true, true) = (patch, period_ok, angle_ok) else {
        return;
    };
    // The wave vector's components must stay below the grid's Nyquist wavenumbers:
    // L >= 2 max(hx |cos|, hy |sin|).
    let (sin, cos) = r.angle_deg.to_radians().sin_cos();
    let along = (patch.element_m[0] * cos.abs()).max(patch.element_m[1] * sin.abs());
    let need = MIN_ELEMENTS_PER_TEXTURE_WAVELENGTH * along;
    if r.period_m < need * (1.0 - 1e-12) {
        let g = patch.grid_for(r.period_m, [cos, sin]);
        v.push(
            &period,
            format!(
                "is {} m, shorter than two elements along the ridges' direction ({} m): the \
                 elements cannot resolve it",
                number(r.period_m),
                number(need)
            ),
            &format!(
                "refine patch.grid to at least [{}, {}], or give a longer period",
                g[0], g[1]
            ),
        );
    }
}

fn check_random(p: &str, r: &RandomSurfaceSpec, patch: Option<Patch>, v: &mut FieldChecks) {
    check_height(&format!("{p}.rms_m"), r.rms_m, false, patch, v);
    if !(r.hurst.is_finite() && r.hurst > 0.0 && r.hurst <= 1.0) {
        v.push(
            &format!("{p}.hurst"),
            format!("is {}, outside (0, 1]", number(r.hurst)),
            "give the Hurst exponent in (0, 1] (0.8 is typical of many surfaces)",
        );
    }
    let w = format!("{p}.wavelengths_m");
    let mut ok = true;
    for k in 0..2 {
        ok &= v.range(
            &format!("{w}[{k}]"),
            r.wavelengths_m[k],
            LENGTH_RANGE_M,
            "m",
            "give [long, short] wavelengths in metres",
        );
    }
    let [long, short] = r.wavelengths_m;
    if ok && long <= short {
        v.push(
            &w,
            format!(
                "has long {} m not above short {} m",
                number(long),
                number(short)
            ),
            "give [long, short] with long > short: the roll-off wavelength first",
        );
        return;
    }
    let Some(patch) = patch.filter(|_| ok) else {
        return;
    };
    let need = MIN_ELEMENTS_PER_TEXTURE_WAVELENGTH * patch.element_m[0].max(patch.element_m[1]);
    if short < need * (1.0 - 1e-12) {
        let g = patch.grid_for(short, [1.0, 1.0]);
        v.push(
            &format!("{w}[1]"),
            format!(
                "is {} m, shorter than two elements ({} m): the elements cannot resolve it",
                number(short),
                number(need)
            ),
            &format!(
                "refine patch.grid to at least [{}, {}], or give a longer short wavelength",
                g[0], g[1]
            ),
        );
    }
    let side = grid_side(&r.surface(), patch.size_m);
    if side.is_none_or(|n| n > MAX_RANDOM_TEXTURE_GRID_SIDE) {
        let n = side.map_or("over 2^62".to_string(), |n| n.to_string());
        v.push(
            &w,
            format!(
                "needs a generation grid of {n} x {n} pixels of short/8 = {} m (covering the \
                 patch and the long wavelength), more than {MAX_RANDOM_TEXTURE_GRID_SIDE}",
                number(pixel_m(&r.surface()))
            ),
            "give a longer short wavelength, or a shorter long wavelength and a smaller patch",
        );
    }
}
