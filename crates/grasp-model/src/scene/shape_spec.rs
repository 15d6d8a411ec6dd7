//! The scene format's shape fields: `object.shape` (a box, sphere, cylinder, capsule or mesh
//! file, and its pose) and `fingers[i].place` (a point or an approach ray). Plain data; what
//! they mean is in [`crate::geometry::shape`] and [`crate::scene::finger_placement`].

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::geometry::mesh_surface::{MeshSurface, TriangleMesh};
use crate::geometry::primitive_surface::Primitive;
use crate::geometry::shape::{LocalShape, Shape};

type Vec3 = [f64; 3];

/// `object.shape`: exactly one of `box`, `sphere`, `cylinder`, `capsule`, `mesh`, and a pose.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ShapeSpec {
    /// A box centred on the shape origin: `{"size": [lx, ly, lz]}`, full edge lengths, m.
    #[serde(default, rename = "box", skip_serializing_if = "Option::is_none")]
    pub box_shape: Option<BoxSpec>,
    /// A sphere centred on the shape origin: `{"radius": R}`, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sphere: Option<SphereSpec>,
    /// A solid cylinder centred on the origin, axis along local z: `{"radius": R, "length":
    /// L}` (L the full length), m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cylinder: Option<CylinderSpec>,
    /// A capsule: a cylinder of radius R and length L along local z (centred) capped by two
    /// hemispheres, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capsule: Option<CylinderSpec>,
    /// A closed triangle mesh read from an OBJ or STL file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<MeshSpec>,
    /// Position of the shape's origin, m (world frame). Default `[0, 0, 0]`.
    #[serde(default)]
    pub position: Vec3,
    /// Orientation `[w, x, y, z]` (unit quaternion; normalised on load). Default identity.
    #[serde(default = "identity_quaternion")]
    pub quaternion: [f64; 4],
}

fn identity_quaternion() -> [f64; 4] {
    [1.0, 0.0, 0.0, 0.0]
}

/// A box.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// Full edge lengths along local x, y, z, m, each in `[1e-6, 1e3]`.
    pub size: Vec3,
}

/// A sphere.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SphereSpec {
    /// Radius, m, in `[1e-6, 1e3]`.
    pub radius: f64,
}

/// A cylinder or capsule along local z.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CylinderSpec {
    /// Radius, m, in `[1e-6, 1e3]`.
    pub radius: f64,
    /// Length of the cylindrical part, m, in `[1e-6, 1e3]` (a capsule may have 0).
    pub length: f64,
}

/// A mesh file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// Path of an `.obj` or `.stl` file, relative to the scene file's folder.
    pub file: String,
    /// Factor applied to the file's coordinates (after `unit`). Default 1.
    #[serde(default = "one")]
    pub scale: f64,
    /// Unit of the file's coordinates: `"m"` (default), `"cm"`, `"mm"` or `"in"`.
    #[serde(default)]
    pub unit: LengthUnit,
}

fn one() -> f64 {
    1.0
}

/// A length unit of a mesh file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum LengthUnit {
    /// Metres.
    #[default]
    M,
    /// Centimetres.
    Cm,
    /// Millimetres.
    Mm,
    /// Inches.
    In,
}

impl LengthUnit {
    /// Metres per unit.
    pub fn metres(self) -> f64 {
        match self {
            LengthUnit::M => 1.0,
            LengthUnit::Cm => 0.01,
            LengthUnit::Mm => 0.001,
            LengthUnit::In => 0.0254,
        }
    }
}

/// `fingers[i].place`: where the finger touches the object's shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlaceSpec {
    /// A point on or near the surface, m (world): the finger touches the closest surface
    /// point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<Vec3>,
    /// An approach ray: the finger touches the first surface point it hits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ray: Option<RaySpec>,
    /// Largest distance of `point` from the surface, m (default 1e-3).
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// Preferred first tangent `t1`: used where every tangent direction is principal (a
    /// sphere, a flat face); elsewhere `t1` is the principal direction closest to it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangent: Option<Vec3>,
}

/// Default largest distance of a finger's point from the surface, m.
pub const DEFAULT_SURFACE_TOLERANCE_M: f64 = 1e-3;

fn default_tolerance() -> f64 {
    DEFAULT_SURFACE_TOLERANCE_M
}

/// An approach ray.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RaySpec {
    /// Start, m (world), outside the object.
    pub origin: Vec3,
    /// Direction (any nonzero length).
    pub direction: Vec3,
}

/// `fingers[i].tip`: the fingertip's shape near the contact (exactly one member; the older
/// `tip_radius` is a sphere; `shape` a solid posed in the world, a mesh say).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TipSpec {
    /// A spherical tip: `{"radius": R}`, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sphere: Option<TipSphereSpec>,
    /// A cylindrical tip: `{"radius": R, "axis": [x, y, z]}` (m; the axis in the world frame,
    /// tangent to the contact and along `t1` or `t2`): curved across the axis, straight along it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cylinder: Option<TipCylinderSpec>,
    /// A flat pad: `{"size": [a, b], "edge_radius": r}`, m along `t1`, `t2`; the patch must
    /// lie on the pad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flat: Option<TipFlatSpec>,
    /// A round flat pad (a disc, its rim rounded): `{"diameter": D, "edge_radius": r}`, m; the
    /// patch must lie on the pad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub disc: Option<TipDiscSpec>,
    /// A fingertip of any shape the object can take (a mesh from an OBJ or STL file, a box, a
    /// sphere, a cylinder, a capsule), posed in the world like `object.shape`: its surface
    /// passes through the contact point, facing the object. Exact gaps only (the object's
    /// shape is needed); the tip's height at each element is found by a ray cast from the
    /// object's side (Johnson 5.1: the compliance stays the half-space's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<Box<ShapeSpec>>,
}

/// A spherical fingertip.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TipSphereSpec {
    /// Radius, m, in `[1e-9, 1e3]` and at least half the larger patch side.
    pub radius: f64,
}

/// A cylindrical fingertip.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TipCylinderSpec {
    /// Radius, m, in `[1e-9, 1e3]` and at least half the patch side across the axis.
    pub radius: f64,
    /// Axis direction (any nonzero length), world frame.
    pub axis: Vec3,
}

/// A flat fingertip pad, rectangular, its edges rounded.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TipFlatSpec {
    /// Pad sides along `t1`, `t2`, m (the rounded edges included).
    pub size: [f64; 2],
    /// Radius of the rounded edges, m (0, the default: sharp edges), at most half the smaller
    /// side: the flat part is `size - 2 edge_radius`, beyond it the pad falls away along a
    /// quarter circle of this radius (exact gaps; Ciavarella, Hills and Monno 1998).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub edge_radius: f64,
}

/// A round flat fingertip pad (a disc), its rim rounded.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TipDiscSpec {
    /// Diameter, m (the rounded rim included).
    pub diameter: f64,
    /// Radius of the rounded rim, m (0, the default: a sharp rim), at most half the
    /// diameter: the flat part has radius `diameter / 2 - edge_radius`, beyond it the pad
    /// falls away along a quarter circle of this radius (Ciavarella 1999, axisymmetric).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub edge_radius: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl ShapeSpec {
    /// The primitive of a shape spec, `None` for a mesh.
    pub fn primitive(&self) -> Option<Primitive> {
        let s = self;
        if let Some(b) = &s.box_shape {
            return Some(Primitive::Box {
                half_m: b.size.map(|x| x / 2.0),
            });
        }
        if let Some(b) = &s.sphere {
            return Some(Primitive::Sphere { radius_m: b.radius });
        }
        if let Some(c) = &s.cylinder {
            return Some(Primitive::Cylinder {
                radius_m: c.radius,
                half_length_m: c.length / 2.0,
            });
        }
        s.capsule.as_ref().map(|c| Primitive::Capsule {
            radius_m: c.radius,
            half_length_m: c.length / 2.0,
        })
    }

    /// The posed shape of this spec (validated), with the mesh `mesh` when the spec is one.
    pub fn posed(&self, mesh: Option<TriangleMesh>) -> Result<Shape, String> {
        let local = match (self.primitive(), mesh) {
            (Some(p), _) => LocalShape::Primitive(p),
            (None, Some(m)) => LocalShape::Mesh(Box::new(MeshSurface::new(m)?)),
            (None, None) => return Err("no geometry".into()),
        };
        Ok(Shape::posed(local, self.quaternion, self.position))
    }
}
