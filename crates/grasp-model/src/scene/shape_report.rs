//! What the object's shape gave the scene: per finger the derived frame, the shape's volume,
//! mass and surface, and the shape checks' warnings.

use serde::Serialize;

use std::sync::Arc;

use crate::geometry::mesh_surface::TriangleMesh;
use crate::geometry::shape::Shape;

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
    /// The shape's surface as triangles, world frame, for drawing (not serialised).
    #[serde(skip)]
    pub surface: TriangleMesh,
    /// The posed shape itself, for the exact gaps (not serialised).
    #[serde(skip)]
    pub shape: SharedShape,
    /// Per finger, scene order, its posed tip shape (`fingers[i].tip.shape`; `None` for the
    /// other tips), for the exact gaps (not serialised).
    #[serde(skip)]
    pub tips: Vec<Option<SharedShape>>,
}

/// A posed shape shared by the scene and its models; two are equal when they are the same one.
#[derive(Debug, Clone)]
pub struct SharedShape(pub Arc<Shape>);

impl PartialEq for SharedShape {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}
