//! Exact surface geometry of the primitive shapes in their local frame: closest point,
//! outward normal, principal directions and curvatures (do Carmo, *Differential Geometry of
//! Curves and Surfaces*, 3-2: a sphere of radius R has both principal curvatures 1/R; a
//! circular cylinder 1/R around and 0 along its axis; a plane 0), and the first hit of a ray.

use nalgebra::Vector3;

use crate::geometry::surface_point::perpendicular;
use crate::geometry::surface_point::{SurfaceFeature, SurfacePoint};

/// A point within this fraction of the primitive's size of a face (or edge) lies on it.
const ON_FACE_FRACTION: f64 = 1e-9;

/// A primitive in its local frame (centred on the origin, axis along z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Primitive {
    /// Half edge lengths, m.
    Box {
        /// Half edge lengths along x, y, z, m.
        half_m: [f64; 3],
    },
    /// Radius, m.
    Sphere {
        /// Radius, m.
        radius_m: f64,
    },
    /// Radius and half length, m.
    Cylinder {
        /// Radius, m.
        radius_m: f64,
        /// Half length, m.
        half_length_m: f64,
    },
    /// Radius and half length of the cylindrical part, m.
    Capsule {
        /// Radius, m.
        radius_m: f64,
        /// Half length of the cylindrical part, m.
        half_length_m: f64,
    },
}

/// A surface point with `d2 = n x d1`.
fn point(
    q: Vector3<f64>,
    n: Vector3<f64>,
    d1: Vector3<f64>,
    curvatures_per_m: [f64; 2],
    feature: SurfaceFeature,
    distance_m: f64,
) -> SurfacePoint {
    SurfacePoint {
        point_m: q,
        outward_normal: n,
        directions: [d1, n.cross(&d1)],
        curvatures_per_m,
        feature,
        distance_m,
    }
}

impl Primitive {
    /// Volume, m^3.
    pub fn volume_m3(&self) -> f64 {
        use std::f64::consts::PI;
        match *self {
            Primitive::Box { half_m: a } => 8.0 * a[0] * a[1] * a[2],
            Primitive::Sphere { radius_m: r } => 4.0 / 3.0 * PI * r.powi(3),
            Primitive::Cylinder {
                radius_m: r,
                half_length_m: h,
            } => PI * r * r * 2.0 * h,
            Primitive::Capsule {
                radius_m: r,
                half_length_m: h,
            } => PI * r * r * 2.0 * h + 4.0 / 3.0 * PI * r.powi(3),
        }
    }

    /// The surface point closest to `p` (local frame).
    pub fn closest(&self, p: &Vector3<f64>) -> Result<SurfacePoint, String> {
        match *self {
            Primitive::Box { half_m } => Ok(box_closest(&half_m, p)),
            Primitive::Sphere { radius_m } => sphere_closest(radius_m, p),
            Primitive::Cylinder {
                radius_m,
                half_length_m,
            } => cylinder_closest(radius_m, half_length_m, p),
            Primitive::Capsule {
                radius_m,
                half_length_m,
            } => capsule_closest(radius_m, half_length_m, p),
        }
    }

    /// Ray parameter of the first hit of the ray `o + t d` (`d` unit, `o` outside), if any.
    pub fn ray_hit(&self, o: &Vector3<f64>, d: &Vector3<f64>) -> Option<f64> {
        match *self {
            Primitive::Box { half_m } => box_ray(&half_m, o, d),
            Primitive::Sphere { radius_m } => sphere_ray(radius_m, &Vector3::zeros(), o, d),
            Primitive::Cylinder {
                radius_m,
                half_length_m,
            } => min_hit([
                side_ray(radius_m, half_length_m, o, d),
                caps_ray(radius_m, half_length_m, o, d),
            ]),
            Primitive::Capsule {
                radius_m,
                half_length_m,
            } => {
                let top = Vector3::new(0.0, 0.0, half_length_m);
                let cap = |c: Vector3<f64>, up: f64| {
                    sphere_ray(radius_m, &c, o, d).filter(|t| (o.z + t * d.z - c.z) * up >= 0.0)
                };
                min_hit([
                    side_ray(radius_m, half_length_m, o, d),
                    cap(top, 1.0),
                    cap(-top, -1.0),
                ])
            }
        }
    }
}

fn min_hit<const N: usize>(hits: [Option<f64>; N]) -> Option<f64> {
    hits.into_iter().flatten().reduce(f64::min)
}

fn box_closest(a: &[f64; 3], p: &Vector3<f64>) -> SurfacePoint {
    let inside = (0..3).all(|i| p[i].abs() <= a[i]);
    let mut q = *p;
    let distance_m = if inside {
        let k = (0..3)
            .min_by(|&i, &j| (a[i] - p[i].abs()).total_cmp(&(a[j] - p[j].abs())))
            .unwrap_or(0);
        q[k] = if p[k] < 0.0 { -a[k] } else { a[k] };
        -(a[k] - p[k].abs())
    } else {
        for i in 0..3 {
            q[i] = p[i].clamp(-a[i], a[i]);
        }
        (p - q).norm()
    };
    let tol = ON_FACE_FRACTION * a.iter().fold(0.0_f64, |m, x| m.max(*x));
    let on: Vec<usize> = (0..3).filter(|&i| q[i].abs() >= a[i] - tol).collect();
    let feature = match on.len() {
        1 => SurfaceFeature::Face,
        2 => SurfaceFeature::Edge,
        _ => SurfaceFeature::Vertex,
    };
    // The face normal (for an edge or corner: the face the point came from, or the first).
    let k = on
        .iter()
        .copied()
        .max_by(|&i, &j| (p[i].abs() - a[i]).total_cmp(&(p[j].abs() - a[j])))
        .unwrap_or(2);
    let mut n = Vector3::zeros();
    n[k] = q[k].signum();
    let mut d1 = Vector3::zeros();
    d1[(k + 1) % 3] = 1.0;
    point(q, n, d1, [0.0, 0.0], feature, distance_m)
}

fn sphere_closest(r: f64, p: &Vector3<f64>) -> Result<SurfacePoint, String> {
    let len = p.norm();
    if len.is_nan() || len <= 1e-12 * r {
        return Err("is at the centre of the sphere (every surface point is as near); move it toward the surface".into());
    }
    let n = p / len;
    let c = 1.0 / r;
    Ok(point(
        n * r,
        n,
        perpendicular(&n),
        [c, c],
        SurfaceFeature::Face,
        len - r,
    ))
}

fn cylinder_closest(r: f64, h: f64, p: &Vector3<f64>) -> Result<SurfacePoint, String> {
    let rho = p.xy().norm();
    let inside = rho <= r && p.z.abs() <= h;
    let mut q = *p;
    let distance_m;
    if inside {
        let (to_side, to_cap) = (r - rho, h - p.z.abs());
        if to_side <= to_cap {
            if rho <= 1e-12 * r {
                return Err("is on the cylinder's axis (every side point is as near); move it toward the surface".into());
            }
            q.x *= r / rho;
            q.y *= r / rho;
        } else {
            q.z = if p.z < 0.0 { -h } else { h };
        }
        distance_m = -to_side.min(to_cap);
    } else {
        if rho > r {
            q.x *= r / rho;
            q.y *= r / rho;
        }
        q.z = p.z.clamp(-h, h);
        distance_m = (p - q).norm();
    }
    let tol = ON_FACE_FRACTION * r.max(h);
    let on_side = (q.xy().norm() - r).abs() <= tol;
    let on_cap = q.z.abs() >= h - tol;
    let feature = if on_side && on_cap {
        SurfaceFeature::Edge
    } else {
        SurfaceFeature::Face
    };
    let side = on_side && (!on_cap || (p.z.abs() - h) < (p.xy().norm() - r));
    Ok(if side {
        let n = Vector3::new(q.x, q.y, 0.0).normalize();
        let around = Vector3::z().cross(&n);
        point(q, n, around, [1.0 / r, 0.0], feature, distance_m)
    } else {
        let n = Vector3::new(0.0, 0.0, q.z.signum());
        point(q, n, Vector3::x(), [0.0, 0.0], feature, distance_m)
    })
}

fn capsule_closest(r: f64, h: f64, p: &Vector3<f64>) -> Result<SurfacePoint, String> {
    let c = Vector3::new(0.0, 0.0, p.z.clamp(-h, h));
    let v = p - c;
    let len = v.norm();
    if len.is_nan() || len <= 1e-12 * r {
        return Err("is on the capsule's axis (every surface point around it is as near); move it toward the surface".into());
    }
    let n = v / len;
    let q = c + n * r;
    let k = 1.0 / r;
    Ok(if p.z.abs() < h {
        point(
            q,
            n,
            Vector3::z().cross(&n),
            [k, 0.0],
            SurfaceFeature::Face,
            len - r,
        )
    } else {
        point(
            q,
            n,
            perpendicular(&n),
            [k, k],
            SurfaceFeature::Face,
            len - r,
        )
    })
}

/// The first hit of `o + t d` on the box of half sides `a`. A ray parallel to a face's plane
/// and in it within the on-face tolerance (along an edge or across a face, whose origin
/// moving into the box's frame rounded a little outside) grazes the box and hits it where it
/// enters, as it does the box's mesh.
fn box_ray(a: &[f64; 3], o: &Vector3<f64>, d: &Vector3<f64>) -> Option<f64> {
    let tol = ON_FACE_FRACTION * a.iter().fold(0.0_f64, |m, x| m.max(*x));
    let (mut enter, mut exit) = (0.0_f64, f64::INFINITY);
    for i in 0..3 {
        if d[i].abs() < 1e-300 {
            if o[i].abs() > a[i] + tol {
                return None;
            }
            continue;
        }
        let (t1, t2) = ((-a[i] - o[i]) / d[i], (a[i] - o[i]) / d[i]);
        enter = enter.max(t1.min(t2));
        exit = exit.min(t1.max(t2));
    }
    (enter <= exit).then_some(enter)
}

fn sphere_ray(r: f64, c: &Vector3<f64>, o: &Vector3<f64>, d: &Vector3<f64>) -> Option<f64> {
    let oc = o - c;
    let b = oc.dot(d);
    let disc = b * b - (oc.norm_squared() - r * r);
    if disc < 0.0 {
        return None;
    }
    let t = -b - disc.sqrt();
    (t >= 0.0).then_some(t)
}

/// First hit of the side `x^2 + y^2 = r^2, |z| <= h`.
fn side_ray(r: f64, h: f64, o: &Vector3<f64>, d: &Vector3<f64>) -> Option<f64> {
    let a = d.x * d.x + d.y * d.y;
    if a < 1e-300 {
        return None;
    }
    let b = o.x * d.x + o.y * d.y;
    let disc = b * b - a * (o.x * o.x + o.y * o.y - r * r);
    if disc < 0.0 {
        return None;
    }
    let t = (-b - disc.sqrt()) / a;
    (t >= 0.0 && (o.z + t * d.z).abs() <= h).then_some(t)
}

/// First hit of the caps `z = +-h, x^2 + y^2 <= r^2`.
fn caps_ray(r: f64, h: f64, o: &Vector3<f64>, d: &Vector3<f64>) -> Option<f64> {
    if d.z.abs() < 1e-300 {
        return None;
    }
    let hit = |z: f64| {
        let t = (z - o.z) / d.z;
        let q = o + d * t;
        (t >= 0.0 && q.xy().norm() <= r).then_some(t)
    };
    min_hit([hit(h), hit(-h)])
}
