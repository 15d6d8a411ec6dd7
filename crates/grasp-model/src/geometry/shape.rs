//! The object's shape (scene format `object.shape`) and its surface queries in the world
//! frame: the closest surface point to a point, the first hit of a ray, each with the outward
//! normal, the principal directions and the principal curvatures there
//! ([`SurfacePoint`]). Primitives are exact ([`crate::geometry::primitive_surface`]); triangle meshes
//! are queried with parry and their curvature estimated from the neighbourhood
//! ([`crate::geometry::mesh_surface`]).
//!
//! The shape's local frame is placed by `position` (m) and `quaternion` `[w, x, y, z]`
//! (MuJoCo's order, normalised on load): `world = position + R(q) local`.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::geometry::mesh_surface::MeshSurface;
use crate::geometry::mesh_topology::MeshDefects;
use crate::geometry::primitive_surface::Primitive;
use crate::geometry::surface_point::{SurfaceFeature, SurfacePoint};

/// How far back along a ray, as a fraction of its length to the hit, the face it comes through
/// is looked for when it hits an edge or a corner ([`Shape::ray_hit`]).
const RAY_STEP_BACK: f64 = 1e-9;

/// The shape in its local frame.
#[derive(Debug, Clone)]
pub enum LocalShape {
    /// A primitive, exact.
    Primitive(Primitive),
    /// A triangle mesh.
    Mesh(Box<MeshSurface>),
}

/// A posed shape.
#[derive(Debug, Clone)]
pub struct Shape {
    /// The shape in its local frame.
    pub local: LocalShape,
    /// Rotation local -> world.
    pub rotation: UnitQuaternion<f64>,
    /// Origin of the local frame, m (world).
    pub position_m: Vector3<f64>,
}

impl Shape {
    /// The shape `local` posed: rotated by the quaternion `[w, x, y, z]` (normalised) and its
    /// local origin moved to `position_m` (m, world).
    pub fn posed(local: LocalShape, quaternion: [f64; 4], position_m: [f64; 3]) -> Shape {
        let [w, x, y, z] = quaternion;
        Shape {
            local,
            rotation: UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)),
            position_m: Vector3::from(position_m),
        }
    }

    fn to_local(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.rotation
            .inverse_transform_vector(&(p - self.position_m))
    }

    fn to_world(&self, s: SurfacePoint) -> SurfacePoint {
        let r = |v: Vector3<f64>| self.rotation.transform_vector(&v);
        SurfacePoint {
            point_m: self.position_m + r(s.point_m),
            outward_normal: r(s.outward_normal),
            directions: [r(s.directions[0]), r(s.directions[1])],
            ..s
        }
    }

    /// The surface point closest to `p` (world), or why there is none (the centre of a
    /// sphere, say).
    pub fn closest(&self, p: &Vector3<f64>) -> Result<SurfacePoint, String> {
        let q = self.to_local(p);
        let s = match &self.local {
            LocalShape::Primitive(prim) => prim.closest(&q)?,
            LocalShape::Mesh(m) => m.closest(&q)?,
        };
        Ok(self.to_world(s))
    }

    /// The first surface point hit by the ray from `origin` along `direction` (world; the
    /// direction need not be unit), or `None` when it misses. A ray starting inside the
    /// object is refused (not on a mesh that is not closed: it has no inside; a ray may then
    /// hit the back of a triangle, which the caller checks). On a closed mesh a ray that
    /// slips between triangles is cast again beside itself ([`Self::local_hit`]).
    pub fn ray_hit(
        &self,
        origin: &Vector3<f64>,
        direction: &Vector3<f64>,
    ) -> Result<Option<SurfacePoint>, String> {
        let o = self.to_local(origin);
        let d = self
            .rotation
            .inverse_transform_vector(direction)
            .normalize();
        if self.open_mesh().is_none() && self.closest(origin)?.distance_m < 0.0 {
            return Err("starts inside the object".into());
        }
        let LocalShape::Mesh(m) = &self.local else {
            return self.local_hit(&o, &d).map(|s| s.map(|s| self.to_world(s)));
        };
        if let Some(s) = self.local_hit(&o, &d)? {
            return Ok(Some(self.to_world(s)));
        }
        // A ray exactly through an edge or a vertex can slip between the triangles in floating
        // point: cast again a tenth of the edge tolerance aside, so that it lands on the edge;
        // then diagonally aside, for a ray along an edge (in the planes of both its faces, so
        // that only a step off both reaches the face it comes through, as on a primitive).
        let e1 = d
            .cross(&Vector3::x())
            .try_normalize(1e-6)
            .unwrap_or_else(|| d.cross(&Vector3::y()).normalize());
        let e2 = d.cross(&e1);
        let nudge = 0.1 * m.edge_tolerance_m();
        let diagonal = |a: f64, b: f64| (e1 * a + e2 * b) * std::f64::consts::FRAC_1_SQRT_2;
        let aside = [
            e1,
            -e1,
            e2,
            -e2,
            diagonal(1.0, 1.0),
            diagonal(1.0, -1.0),
            diagonal(-1.0, 1.0),
            diagonal(-1.0, -1.0),
        ];
        for e in aside {
            if let Some(s) = self.local_hit(&(o + e * nudge), &d)? {
                return Ok(Some(self.to_world(s)));
            }
        }
        Ok(None)
    }

    /// The first hit of the local ray `o + t d` (`d` unit) on a face turned towards it (local
    /// frame): on a closed mesh, a hit on a face turned away is the far side met from within
    /// by a ray that slipped between two triangles, and counts as none. At an edge or a corner
    /// the face is the one the ray comes through (a ray grazing a box along its top edge hits
    /// the end face's corner, on the primitive as on its mesh).
    fn local_hit(
        &self,
        o: &Vector3<f64>,
        d: &Vector3<f64>,
    ) -> Result<Option<SurfacePoint>, String> {
        let hit = match &self.local {
            LocalShape::Primitive(prim) => prim.ray_hit(o, d),
            LocalShape::Mesh(m) => m.ray_hit(o, d),
        };
        let Some(t) = hit else { return Ok(None) };
        let closest = |p: &Vector3<f64>| match &self.local {
            LocalShape::Primitive(prim) => prim.closest(p),
            LocalShape::Mesh(m) => m.closest(p),
        };
        let mut s = closest(&(o + d * t))?;
        if s.feature != SurfaceFeature::Face && s.outward_normal.dot(d) >= 0.0 {
            // At an edge or a corner the face `closest` names may not be the one the ray comes
            // through (a ray along a box's top edge enters by its end face, not the top): that
            // one is the face nearest a point just before the hit.
            let before = closest(&(o + d * (t * (1.0 - RAY_STEP_BACK))))?;
            if before.outward_normal.dot(d) < 0.0 {
                s = before;
            }
        }
        s.distance_m = 0.0;
        let back = s.outward_normal.dot(d) >= 0.0 && self.open_mesh().is_none();
        Ok((!back).then_some(s))
    }

    /// Why the shape does not bound a solid: the defects of a mesh that is not closed
    /// (`None` for a closed mesh and for the primitives, which always are).
    pub fn open_mesh(&self) -> Option<MeshDefects> {
        match &self.local {
            LocalShape::Mesh(m) if !m.defects().is_closed() => Some(m.defects()),
            _ => None,
        }
    }

    /// Volume, m^3, and centroid, m (world): for a mesh, of the closed surface its triangles
    /// form (meaningless when it is not closed, [`Shape::open_mesh`]).
    pub fn volume_and_centroid(&self) -> (f64, Vector3<f64>) {
        let (v, c) = match &self.local {
            LocalShape::Primitive(p) => (p.volume_m3(), Vector3::zeros()),
            LocalShape::Mesh(m) => m.mesh().volume_and_centroid(),
        };
        (v, self.position_m + self.rotation.transform_vector(&c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::mesh_surface::TriangleMesh;

    /// The box `[-a, a]` as 12 triangles wound outward (corner `i` has `+a[k]` where bit `k`
    /// of `i` is set).
    fn box_mesh(a: [f64; 3]) -> TriangleMesh {
        TriangleMesh {
            vertices_m: (0..8)
                .map(|i| [0, 1, 2].map(|k| if (i >> k) & 1 == 1 { a[k] } else { -a[k] }))
                .collect(),
            triangles: vec![
                [0, 2, 1],
                [1, 2, 3],
                [4, 5, 6],
                [5, 7, 6],
                [0, 1, 4],
                [1, 5, 4],
                [2, 6, 3],
                [3, 6, 7],
                [0, 4, 2],
                [2, 4, 6],
                [1, 3, 5],
                [3, 7, 5],
            ],
        }
    }

    /// A ray along an edge or across a face of a box (grazing it) gets the same answer from the
    /// primitive box and from the same box as a 12-triangle mesh, posed alike: a hit at the
    /// same point where it enters (the face it comes through is turned towards it), or a miss
    /// for both.
    #[test]
    fn a_ray_along_a_box_edge_gets_one_answer_from_the_primitive_and_the_mesh() {
        let a = [0.03, 0.02, 0.01];
        let poses: [([f64; 4], [f64; 3]); 2] = [
            ([1.0, 0.0, 0.0, 0.0], [0.0; 3]),
            ([1.0, 0.0, 0.0, 0.0], [0.1, -0.2, 0.3]),
        ];
        for (q, at) in poses {
            let prim = Shape::posed(LocalShape::Primitive(Primitive::Box { half_m: a }), q, at);
            let mesh = Shape::posed(
                LocalShape::Mesh(Box::new(MeshSurface::new(box_mesh(a)).unwrap())),
                q,
                at,
            );
            let p = Vector3::from(at);
            let (x, y): (Vector3<f64>, Vector3<f64>) = (Vector3::x(), Vector3::y());
            // (origin, direction), local: along the top edges, across the top face, and
            // just outside an edge (a miss for both).
            let rays = [
                (Vector3::new(-0.1, a[1], a[2]), x),
                (Vector3::new(0.1, -a[1], a[2]), -x),
                (Vector3::new(a[0], -0.1, a[2]), y),
                (Vector3::new(-a[0], 0.1, a[2]), -y),
                (Vector3::new(-0.1, 0.0, a[2]), x),
                (Vector3::new(-0.1, a[1], 0.0), x),
                (Vector3::new(-0.1, a[1] * 1.01, a[2]), x),
                (Vector3::new(-0.1, 0.0, a[2] * 1.01), x),
            ];
            for (o, d) in rays {
                let (o, d) = (o + p, d);
                let hp = prim.ray_hit(&o, &d).unwrap();
                let hm = mesh.ray_hit(&o, &d).unwrap();
                match (&hp, &hm) {
                    (Some(sp), Some(sm)) => {
                        assert!(
                            (sp.point_m - sm.point_m).norm() < 1e-9,
                            "{o:?} {d:?}: {sp:?} {sm:?}"
                        );
                        assert!(sp.outward_normal.dot(&d) < 0.0, "{o:?} {d:?}: {sp:?}");
                    }
                    (None, None) => {}
                    _ => panic!("{o:?} {d:?}: primitive {hp:?}, mesh {hm:?}"),
                }
            }
        }
    }
}
