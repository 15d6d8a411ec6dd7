//! The orthonormal frame of a contact: inward normal and two tangents.

use nalgebra::Vector3;

/// Orthonormal frame of a contact: `normal` points INTO the object (direction of the normal
/// force the finger applies); `t1 x t2 = normal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactFrame {
    /// Contact point `v_i`, m (world frame).
    pub origin_m: Vector3<f64>,
    /// Unit inward normal `n_i`.
    pub normal: Vector3<f64>,
    /// First unit tangent `t1_i`.
    pub t1: Vector3<f64>,
    /// Second unit tangent `t2_i = n x t1`.
    pub t2: Vector3<f64>,
}

impl ContactFrame {
    /// Builds the frame from a (not necessarily unit) normal and an optional tangent hint.
    ///
    /// - `planar_normal = Some(p)`: `t2 = p` and `t1 = p x n`, so the first tangent lies in the
    ///   plane of motion (a planar scene's one tangential unknown).
    /// - a hint: `t1` is the hint projected onto the plane normal to `n`.
    /// - neither: `t1` is the world axis least aligned with `n`, projected (deterministic).
    pub fn new(
        origin_m: Vector3<f64>,
        normal: Vector3<f64>,
        tangent_hint: Option<Vector3<f64>>,
        planar_normal: Option<Vector3<f64>>,
    ) -> Self {
        let n = normal.normalize();
        let t1 = if let Some(p) = planar_normal {
            p.normalize().cross(&n).normalize()
        } else {
            let hint = tangent_hint.unwrap_or_else(|| {
                let a = n.abs();
                if a.x <= a.y && a.x <= a.z {
                    Vector3::x()
                } else if a.y <= a.z {
                    Vector3::y()
                } else {
                    Vector3::z()
                }
            });
            (hint - n * n.dot(&hint)).normalize()
        };
        let t2 = n.cross(&t1);
        ContactFrame {
            origin_m,
            normal: n,
            t1,
            t2,
        }
    }

    /// World position of the point with patch coordinates `(x, y)` metres.
    pub fn point(&self, x_m: f64, y_m: f64) -> Vector3<f64> {
        self.origin_m + self.t1 * x_m + self.t2 * y_m
    }
}
