//! How each fingertip is drawn (Rerun and Foxglove alike): its shape near the contact, from
//! the curvatures the gap function uses ([`grasp_model::tip_curvatures_per_m`]), on the
//! finger's side of the contact (against the inward normal `n`).
//!
//! - a sphere (equal curvatures `1/R`): the ball of radius `R` touching the contact point;
//! - a cylinder (curved across one tangent, straight along the other): radius `R`, its axis
//!   along the straight tangent, lying on the contact, as long as three patch sides (at
//!   least `2R`);
//! - flat (no curvature): a pad behind the patch, its size the tip's `flat.size` or 1.5 times
//!   the patch, a quarter of its smaller side thick.
//!
//! A curved tip much larger than the scene (radius over [`LARGEST_DRAWN`] scene sizes) is
//! drawn as a pad, so a nearly flat tip does not fill the view.

use grasp_model::tip_curvatures_per_m;
use grasp_model::{ContactFrame, FingerModel};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

use super::sink::RunInfo;

/// Largest radius drawn as a curved tip, in scene sizes.
pub const LARGEST_DRAWN: f64 = 10.0;

/// A fingertip's drawing, world frame, metres.
#[derive(Clone, Debug, PartialEq)]
pub enum TipDrawing {
    /// A ball touching the contact from the finger's side.
    Sphere {
        /// Centre, m.
        centre: Vector3<f64>,
        /// Radius, m.
        radius_m: f64,
    },
    /// A cylinder lying on the contact.
    Cylinder {
        /// Centre, m.
        centre: Vector3<f64>,
        /// Unit vector along the axis.
        axis: Vector3<f64>,
        /// Radius, m.
        radius_m: f64,
        /// Length along the axis, m.
        length_m: f64,
    },
    /// A box behind the contact.
    Pad {
        /// Centre, m.
        centre: Vector3<f64>,
        /// Takes the box's x, y, z to `t1`, `t2`, `n`.
        rotation: UnitQuaternion<f64>,
        /// Half sizes along the box's x, y, z, m.
        half_sizes_m: Vector3<f64>,
    },
}

/// Every finger's tip drawing, by finger name, in scene order (`size_m`: the scene's size).
pub fn tip_drawings(run: &RunInfo, size_m: f64) -> Vec<(String, TipDrawing)> {
    let mut out = Vec::new();
    for spec in &run.scene.fingers {
        if let Some(m) = run.model.fingers().iter().find(|m| m.name() == spec.name) {
            let k = tip_curvatures_per_m(spec, m.frame());
            let flat_size = spec.tip.as_ref().and_then(|t| t.flat).map(|f| f.size);
            out.push((spec.name.clone(), drawing(m, k, flat_size, size_m)));
        }
    }
    out
}

/// The drawing of finger `m`'s tip with curvatures `k` along `t1`, `t2` (1/m).
fn drawing(m: &FingerModel, k: [f64; 2], flat_size_m: Option<[f64; 2]>, size_m: f64) -> TipDrawing {
    let f = &m.frame();
    let g = &m.patch().grid;
    let side = [g.nx as f64 * g.hx, g.ny as f64 * g.hy];
    let drawn = |k: f64| k > 0.0 && 1.0 / k <= LARGEST_DRAWN * size_m;
    match (drawn(k[0]), drawn(k[1])) {
        (true, true) => {
            let r = 2.0 / (k[0] + k[1]);
            TipDrawing::Sphere {
                centre: f.origin_m - f.normal * r,
                radius_m: r,
            }
        }
        (false, true) | (true, false) => {
            // Straight along the tangent without curvature.
            let (axis, r, along) = match drawn(k[1]) {
                true => (f.t1, 1.0 / k[1], side[0]),
                false => (f.t2, 1.0 / k[0], side[1]),
            };
            TipDrawing::Cylinder {
                centre: f.origin_m - f.normal * r,
                axis,
                radius_m: r,
                length_m: (3.0 * along).max(2.0 * r),
            }
        }
        (false, false) => {
            let [a, b] = flat_size_m.unwrap_or([1.5 * side[0], 1.5 * side[1]]);
            let thick = 0.25 * a.min(b);
            let rotation = frame_rotation(f);
            TipDrawing::Pad {
                centre: f.origin_m - f.normal * (0.5 * thick),
                rotation,
                half_sizes_m: Vector3::new(0.5 * a, 0.5 * b, 0.5 * thick),
            }
        }
    }
}

/// The rotation taking the x, y and z axes to a contact frame's `t1`, `t2` and inward normal
/// (orthonormal and right-handed: `t1 x t2 = n`), as a pad's pose and as the ROS 2 profile's
/// contact frame.
pub fn frame_rotation(f: &ContactFrame) -> UnitQuaternion<f64> {
    let axes = Matrix3::from_columns(&[f.t1, f.t2, f.normal]);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(axes))
}

/// The rotation taking the z axis to the unit vector `axis` (a cylinder's pose).
pub fn z_to(axis: &Vector3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::rotation_between(&Vector3::z(), axis).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cylinder_pose_turns_z_onto_the_axis_even_when_opposite() {
        for a in [
            Vector3::x(),
            Vector3::new(0.0, 0.6, 0.8),
            -Vector3::z(),
            Vector3::z(),
        ] {
            let q = z_to(&a);
            assert!((q * Vector3::z() - a).norm() < 1e-12, "{a:?}");
        }
    }
}
