//! What the object's shape gave the scene: per finger the derived frame, the shape's volume
//! and mass, and the shape checks' warnings (plain data, serialisable; the posed shapes and
//! the surface travel in [`crate::scene::scene_geometry::SceneGeometry`]).

use serde::Serialize;

type Vec3 = [f64; 3];

/// What was derived for one finger.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DerivedFrame {
    /// Finger name.
    pub finger: String,
    /// `"point"`, `"ray"` or `"explicit"` (a frame written by hand, checked on the shape).
    pub source: String,
    /// Contact point on the surface, m.
    pub contact_point_m: Vec3,
    /// Inward unit normal of the surface there.
    pub normal: Vec3,
    /// First tangent `t1` (placed fingers).
    pub tangent: Option<Vec3>,
    /// Principal curvatures along `t1`, `t2`, 1/m (positive convex).
    pub curvature_per_m: [f64; 2],
    /// Object radii along `t1`, `t2` written into the scene, m (`None`: flat).
    pub object_radius_m: [Option<f64>; 2],
    /// Distance of the given point from the surface, m (0 for a ray).
    pub distance_m: f64,
    /// Remarks (concave directions treated as flat, normals off the surface normal).
    pub notes: Vec<String>,
}

/// The shape's derived quantities and the placement of every finger.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeReport {
    /// Volume of the shape, m^3.
    pub volume_m3: f64,
    /// Centroid of the shape, m (world).
    pub centroid_m: Vec3,
    /// Mass from `object.density`, kg (when given).
    pub mass_kg: Option<f64>,
    /// One entry per finger, scene order.
    pub fingers: Vec<DerivedFrame>,
    /// Problems that do not stop the solve (a patch over an edge, overlapping patches).
    pub warnings: Vec<String>,
}
