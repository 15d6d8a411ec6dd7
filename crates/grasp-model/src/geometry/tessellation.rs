//! Triangle surfaces of the shapes, for drawing (the Rerun recording): the primitives
//! tessellated (a box's 12 triangles; a sphere as an icosphere; cylinders and capsules with 48
//! segments around), a mesh as read; all posed in the world frame, wound outward.

use std::collections::HashMap;
use std::f64::consts::PI;

use nalgebra::Vector3;

use crate::geometry::mesh_surface::TriangleMesh;
use crate::geometry::primitive_surface::Primitive;
use crate::geometry::shape::{LocalShape, Shape};

/// Segments around a cylinder or capsule.
const SEGMENTS: usize = 48;

/// The shape's surface as triangles, world frame, m.
pub fn tessellate(shape: &Shape) -> TriangleMesh {
    let local = match &shape.local {
        LocalShape::Primitive(p) => primitive(p),
        LocalShape::Mesh(m) => m.mesh().clone(),
    };
    let pose = |v: &[f64; 3]| {
        let w = shape.position_m + shape.rotation.transform_vector(&Vector3::from(*v));
        [w.x, w.y, w.z]
    };
    TriangleMesh {
        vertices_m: local.vertices_m.iter().map(pose).collect(),
        triangles: local.triangles,
    }
}

fn primitive(p: &Primitive) -> TriangleMesh {
    match *p {
        Primitive::Box { half_m } => box_mesh(half_m),
        Primitive::Sphere { radius_m } => icosphere(radius_m, 3),
        Primitive::Cylinder {
            radius_m,
            half_length_m,
        } => revolved(&[
            (0.0, -half_length_m),
            (radius_m, -half_length_m),
            (radius_m, half_length_m),
            (0.0, half_length_m),
        ]),
        Primitive::Capsule {
            radius_m,
            half_length_m,
        } => {
            let arc = |from: f64, to: f64, z0: f64| -> Vec<(f64, f64)> {
                (0..=12)
                    .map(|i| from + (to - from) * i as f64 / 12.0)
                    .map(|a| (radius_m * a.cos(), z0 + radius_m * a.sin()))
                    .collect()
            };
            let mut profile = arc(-PI / 2.0, 0.0, -half_length_m);
            profile.extend(arc(0.0, PI / 2.0, half_length_m));
            revolved(&profile)
        }
    }
}

/// The box `[-a, a]` (half sides `a`, m), 8 corners and 12 triangles wound outward: corner `i`
/// has `+a[k]` where bit `k` of `i` is set, `-a[k]` where it is not.
pub fn box_mesh(a: [f64; 3]) -> TriangleMesh {
    let vertices_m = (0..8)
        .map(|i| [0, 1, 2].map(|k| if (i >> k) & 1 == 1 { a[k] } else { -a[k] }))
        .collect();
    let triangles = vec![
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
    ];
    TriangleMesh {
        vertices_m,
        triangles,
    }
}

/// A surface of revolution about z of the profile `(radius, z)` from the bottom pole to the
/// top (radius 0 at both ends).
fn revolved(profile: &[(f64, f64)]) -> TriangleMesh {
    let mut vertices_m = Vec::new();
    for &(r, z) in profile {
        for s in 0..SEGMENTS {
            let a = 2.0 * PI * s as f64 / SEGMENTS as f64;
            vertices_m.push([r * a.cos(), r * a.sin(), z]);
        }
    }
    let ring = |i: usize, s: usize| (i * SEGMENTS + s % SEGMENTS) as u32;
    let mut triangles = Vec::new();
    for i in 0..profile.len() - 1 {
        for s in 0..SEGMENTS {
            triangles.push([ring(i, s), ring(i, s + 1), ring(i + 1, s + 1)]);
            triangles.push([ring(i, s), ring(i + 1, s + 1), ring(i + 1, s)]);
        }
    }
    TriangleMesh {
        vertices_m,
        triangles,
    }
}

/// An icosphere of radius `r` subdivided `k` times.
pub fn icosphere(r: f64, k: usize) -> TriangleMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..k {
        let mut middle: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, v: &mut Vec<[f64; 3]>| -> u32 {
            *middle.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (v[a as usize], v[b as usize]);
                v.push([0, 1, 2].map(|i| (p[i] + q[i]) / 2.0));
                (v.len() - 1) as u32
            })
        };
        f = f
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (mid(a, b, &mut v), mid(b, c, &mut v), mid(c, a, &mut v));
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    let vertices_m = v
        .iter()
        .map(|p| {
            let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            p.map(|x| x * r / n)
        })
        .collect();
    TriangleMesh {
        vertices_m,
        triangles: f,
    }
}
