//! A point of a surface with its differential geometry: outward normal, principal directions
//! and curvatures (do Carmo, *Differential Geometry of Curves and Surfaces*, 3-2).

use nalgebra::Vector3;
use serde::Serialize;

/// Where a surface point lies on the shape: a smooth face, or an edge / vertex where the
/// normal and curvature are not defined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceFeature {
    /// A smooth part of the surface.
    Face,
    /// An edge (box edge, cylinder rim).
    Edge,
    /// A corner.
    Vertex,
}

/// A point of the surface with its differential geometry (world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// The point, m.
    pub point_m: Vector3<f64>,
    /// Unit outward normal.
    pub outward_normal: Vector3<f64>,
    /// Unit principal directions `[d1, d2]`, tangent, `d1 x d2 = outward normal`.
    pub directions: [Vector3<f64>; 2],
    /// Principal curvatures along `directions`, 1/m: positive where the surface is convex
    /// (curves away from a finger pressing on it), 0 where flat, negative where concave.
    pub curvatures_per_m: [f64; 2],
    /// Face, edge or vertex.
    pub feature: SurfaceFeature,
    /// Signed distance of the queried point from the surface, m (negative inside); 0 for a
    /// ray hit.
    pub distance_m: f64,
}

/// A unit vector perpendicular to the unit vector `n` (deterministic).
pub fn perpendicular(n: &Vector3<f64>) -> Vector3<f64> {
    let a = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    (a - n * n.dot(&a)).normalize()
}
