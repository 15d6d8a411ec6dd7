//! A large patch (more than [`super::element_maps::COMPACT_ABOVE_ELEMENTS`] elements) in the
//! Rerun recording: two images on the patch's plane in the 3-D view instead of one point per
//! element.
//!
//! - `world/patches/<name>` (static): `Transform3D` from grid cells to the world: the patch's
//!   lower-left corner, columns `hx t1`, `hy t2` and the unit normal, so one image pixel covers
//!   one element (non-square elements included; a `GridMap`'s cell is square);
//! - `world/patches/<name>/pressure`: `GridMap`, one f32 pixel an element, the element's
//!   pressure as a fraction of the step's largest pressure (of any finger, as the points of
//!   smaller patches are coloured), Viridis colours (the viewer maps `[0, 1]` to the colormap
//!   for float data within it); hovering shows the fraction;
//! - `world/patches/<name>/state`: `GridMap`, RGB8, stick green, slip orange, separated grey
//!   (the points' colours), set off behind the patch by one element as the state points are.
//!
//! 7 bytes an element per step (the points took 20: position, colour and radius), before
//! Rerun's compression. Images are built with [`super::element_maps::raster`]: `t1` to the
//! right, `t2` up, so the picture is the patch seen from the object's side.

use grasp_model::{FingerModel, FingerSolution};
use nalgebra::Vector3;
use rerun::components::Colormap;
use rerun::{ChannelDatatype, ColorModel, GridMap, Transform3D};

use super::colour_key::state_rgb;
use super::element_maps::raster;

/// Grid cells to the world: the patch's lower-left corner (m) and the columns `hx t1`, `hy t2`
/// (m a cell) and `normal` (unit); cell `(x, y)` lies at `corner + x c0 + y c1`.
pub fn grid_to_world(fm: &FingerModel) -> (Vector3<f64>, [Vector3<f64>; 3]) {
    let g = &fm.patch().grid;
    let f = &fm.frame();
    let corner = f.origin_m - f.t1 * (0.5 * g.nx as f64 * g.hx) - f.t2 * (0.5 * g.ny as f64 * g.hy);
    (corner, [f.t1 * g.hx, f.t2 * g.hy, f.normal])
}

/// [`grid_to_world`] as a Rerun transform (pixel `(i, row)` at cell `[i, ny - 1 - row]`).
pub fn patch_pose(fm: &FingerModel) -> Transform3D {
    let (corner, c) = grid_to_world(fm);
    let v = |v: &Vector3<f64>| [v.x as f32, v.y as f32, v.z as f32];
    Transform3D::from_translation_mat3x3(v(&corner), [v(&c[0]), v(&c[1]), v(&c[2])])
}

/// The pressure image of finger `fm`: each element's pressure over `p_max_pa`, in `[0, 1]`.
pub fn pressure_map(fm: &FingerModel, f: &FingerSolution, p_max_pa: f64) -> GridMap {
    let (nx, ny) = (fm.patch().grid.nx, fm.patch().grid.ny);
    let fraction: Vec<f32> = f
        .elements
        .iter()
        .map(|e| (e.pressure_pa / p_max_pa).clamp(0.0, 1.0) as f32)
        .collect();
    let bytes: Vec<u8> = raster(&fraction, nx, ny)
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let format = rerun::components::ImageFormat::from_color_model(
        [nx as u32, ny as u32],
        ColorModel::L,
        ChannelDatatype::F32,
    );
    GridMap::new(bytes, format, 1.0).with_colormap(Colormap::Viridis)
}

/// The state image of finger `fm`, one element behind the patch.
pub fn state_map(fm: &FingerModel, f: &FingerSolution) -> GridMap {
    let (nx, ny) = (fm.patch().grid.nx, fm.patch().grid.ny);
    let rgb: Vec<[u8; 3]> = f.elements.iter().map(|e| state_rgb(e.state)).collect();
    let bytes: Vec<u8> = raster(&rgb, nx, ny).into_iter().flatten().collect();
    let format = rerun::components::ImageFormat::rgb8([nx as u32, ny as u32]);
    let behind_m = -fm.patch().grid.hx.min(fm.patch().grid.hy);
    GridMap::new(bytes, format, 1.0).with_translation([0.0, 0.0, behind_m as f32])
}

/// An empty image (a released finger, or a failed step): clears the map.
pub fn cleared_map() -> GridMap {
    GridMap::clear_fields()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_centres_are_the_element_centres() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../examples/disc_three_fingers.json"
        );
        let scene = grasp_model::Scene::from_json_str(&std::fs::read_to_string(path).unwrap());
        let model = grasp_model::GraspModel::from_scene(&scene.unwrap()).unwrap();
        for fm in model.fingers() {
            let (corner, c) = grid_to_world(fm);
            let ny = fm.patch().grid.ny;
            for k in 0..fm.patch().len() {
                let (x, y) = ((k / ny) as f64 + 0.5, (k % ny) as f64 + 0.5);
                let cell = corner + c[0] * x + c[1] * y;
                let d = (cell - fm.element_point(k)).norm();
                assert!(d < 1e-15, "{} element {k}: {d:e} m", fm.name());
            }
            assert!(
                (c[0].cross(&c[1]).normalize() - c[2]).norm() < 1e-12,
                "right-handed"
            );
        }
    }
}
