//! Triangle meshes: the data a mesh file gives ([`TriangleMesh`], read by the I/O layer),
//! its volume integrals, and the surface queries of a mesh object ([`MeshSurface`]): closest
//! point and ray hits through parry's bounding-volume tree, and the normal, principal
//! directions and curvatures estimated by a least-squares quadric fit to the vertices around
//! the point (the osculating paraboloid; do Carmo 3-3, the shape operator of a graph
//! `z = f(x, y)` from its first and second fundamental forms).

use nalgebra::{DMatrix, DVector, Matrix2, Vector3};
use parry3d_f64::math::Vector as PVec;
use parry3d_f64::query::{PointQuery, Ray, RayCast};
use parry3d_f64::shape::{TriMesh, TriMeshFlags};

use crate::surface_point::{perpendicular, SurfaceFeature, SurfacePoint};

/// A triangle mesh in metres (local frame of the shape), triangles counter-clockwise seen
/// from outside (a mesh wound the other way is turned over on load).
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions, m.
    pub vertices_m: Vec<[f64; 3]>,
    /// Vertex indices of each triangle.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Volume, m^3, and centroid, m, of the closed surface (divergence theorem: a signed
    /// tetrahedron from the origin per triangle; Zhang and Chen 2001). The volume is negative
    /// when the triangles are wound clockwise seen from outside.
    pub fn volume_and_centroid(&self) -> (f64, Vector3<f64>) {
        let mut volume = 0.0;
        let mut moment = Vector3::zeros();
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| Vector3::from(self.vertices_m[i as usize]));
            let v = a.dot(&b.cross(&c)) / 6.0;
            volume += v;
            moment += (a + b + c) * (v / 4.0);
        }
        let centroid = if volume != 0.0 {
            moment / volume
        } else {
            Vector3::zeros()
        };
        (volume, centroid)
    }
}

/// Fewest vertices of the curvature fit around a point.
pub const FIT_VERTICES: usize = 12;

/// A mesh object ready for queries.
#[derive(Debug, Clone)]
pub struct MeshSurface {
    mesh: TriangleMesh,
    trimesh: TriMesh,
    /// Mean length of the edges at each vertex, m: the local mesh size.
    vertex_edge_m: Vec<f64>,
}

fn pv(v: &Vector3<f64>) -> PVec {
    PVec::new(v.x, v.y, v.z)
}

fn nv(v: PVec) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

impl MeshSurface {
    /// Prepares `mesh` (turned over if wound clockwise; duplicate vertices merged).
    pub fn new(mut mesh: TriangleMesh) -> Result<MeshSurface, String> {
        if mesh.triangles.is_empty() {
            return Err("has no triangles".into());
        }
        if mesh.volume_and_centroid().0 < 0.0 {
            for t in &mut mesh.triangles {
                t.swap(1, 2);
            }
        }
        let vertices: Vec<PVec> = mesh
            .vertices_m
            .iter()
            .map(|v| pv(&Vector3::from(*v)))
            .collect();
        let flags = TriMeshFlags::MERGE_DUPLICATE_VERTICES
            | TriMeshFlags::DELETE_DEGENERATE_TRIANGLES
            | TriMeshFlags::ORIENTED;
        let trimesh = TriMesh::with_flags(vertices, mesh.triangles.clone(), flags)
            .map_err(|e| format!("is not a usable triangle mesh: {e}"))?;
        let vertex_edge_m = vertex_edge_lengths(&trimesh);
        Ok(MeshSurface {
            mesh,
            trimesh,
            vertex_edge_m,
        })
    }

    /// The mesh as read (outward winding).
    pub fn mesh(&self) -> &TriangleMesh {
        &self.mesh
    }

    /// The surface point closest to `p` (local frame) with its fitted geometry.
    pub fn closest(&self, p: &Vector3<f64>) -> Result<SurfacePoint, String> {
        let proj = self.trimesh.project_local_point(pv(p), false);
        let q = nv(proj.point);
        let sign = if proj.is_inside { -1.0 } else { 1.0 };
        let mut s = self.fit_at(&q)?;
        s.distance_m = sign * (p - q).norm();
        Ok(s)
    }

    /// Ray parameter of the first hit of `o + t d` (`d` unit), if any.
    pub fn ray_hit(&self, o: &Vector3<f64>, d: &Vector3<f64>) -> Option<f64> {
        self.trimesh
            .cast_local_ray(&Ray::new(pv(o), pv(d)), f64::MAX, true)
    }

    /// The vertices used for the fit at `q`: those within 1.5 local edge lengths (the mean
    /// edge at the nearest vertex), and at least the [`FIT_VERTICES`] nearest. A wider
    /// neighbourhood feels the surface's higher-order terms: on a sphere the quadric's error
    /// grows like (radius / R)^2.
    fn neighbourhood(&self, q: &Vector3<f64>) -> Vec<Vector3<f64>> {
        let mut by_distance: Vec<(f64, usize)> = self
            .trimesh
            .vertices()
            .iter()
            .enumerate()
            .map(|(i, v)| ((nv(*v) - q).norm(), i))
            .collect();
        by_distance.sort_by(|a, b| a.0.total_cmp(&b.0));
        let radius = 1.5
            * by_distance
                .first()
                .map_or(0.0, |&(_, i)| self.vertex_edge_m[i]);
        let n = by_distance
            .iter()
            .take_while(|(d, _)| *d <= radius)
            .count()
            .max(FIT_VERTICES);
        by_distance
            .into_iter()
            .take(n)
            .map(|(_, i)| nv(self.trimesh.vertices()[i]))
            .collect()
    }

    /// Area-weighted normal of the triangles with a vertex among `near` (outward).
    fn reference_normal(&self, q: &Vector3<f64>, radius: f64) -> Vector3<f64> {
        let mut n = Vector3::zeros();
        for t in self.trimesh.indices() {
            let [a, b, c] = t.map(|i| nv(self.trimesh.vertices()[i as usize]));
            let centre = (a + b + c) / 3.0;
            let w = 1.0 / (1.0 + ((centre - q).norm() / radius).powi(2));
            n += (b - a).cross(&(c - a)) * w * f64::from((centre - q).norm() <= 2.0 * radius);
        }
        n.normalize()
    }

    /// Normal, principal directions and curvatures at the surface point `q` from a quadric
    /// `w = c0 + c1 u + c2 v + c3 u^2 + c4 uv + c5 v^2` fitted to the nearby vertices in a
    /// frame `(u, v, w)` with `w` along the reference normal.
    fn fit_at(&self, q: &Vector3<f64>) -> Result<SurfacePoint, String> {
        let near = self.neighbourhood(q);
        let radius = near.iter().map(|p| (p - q).norm()).fold(0.0, f64::max);
        let w = self.reference_normal(q, radius);
        if !w.iter().all(|x| x.is_finite()) {
            return Err("lies where the mesh has no usable normal".into());
        }
        let u = perpendicular(&w);
        let v = w.cross(&u);
        let mut a = DMatrix::zeros(near.len(), 6);
        let mut b = DVector::zeros(near.len());
        for (r, p) in near.iter().enumerate() {
            let d = p - q;
            let (x, y) = (d.dot(&u), d.dot(&v));
            let row = [1.0, x, y, x * x, x * y, y * y];
            for (c, val) in row.iter().enumerate() {
                a[(r, c)] = *val;
            }
            b[r] = d.dot(&w);
        }
        let c = a
            .svd(true, true)
            .solve(&b, 1e-12)
            .map_err(|e| format!("curvature fit failed: {e}"))?;
        Ok(graph_geometry(
            q,
            [u, v, w],
            [c[1], c[2]],
            [2.0 * c[3], c[4], 2.0 * c[5]],
        ))
    }
}

/// Geometry of the graph `w = f(u, v)` at the origin from its gradient `[fu, fv]` and
/// Hessian `[fuu, fuv, fvv]` (shape operator `S = I^-1 II`; do Carmo 3-3). `w` points out.
fn graph_geometry(
    q: &Vector3<f64>,
    [u, v, w]: [Vector3<f64>; 3],
    [fu, fv]: [f64; 2],
    [fuu, fuv, fvv]: [f64; 3],
) -> SurfacePoint {
    let len = (1.0 + fu * fu + fv * fv).sqrt();
    let normal = ((w - u * fu - v * fv) / len).normalize();
    let first = Matrix2::new(1.0 + fu * fu, fu * fv, fu * fv, 1.0 + fv * fv);
    let second = Matrix2::new(fuu, fuv, fuv, fvv) / len;
    let shape = first.try_inverse().unwrap_or_else(Matrix2::identity) * second;
    // S is self-adjoint in the first form: eigen-decompose the symmetric I^-1/2 II I^-1/2.
    let eig = shape.complex_eigenvalues();
    let mut ks = [eig[0].re, eig[1].re];
    // Outward normal: a convex surface curves down (f'' < 0), so convex curvature is -k.
    ks = [-ks[0], -ks[1]];
    let order = if ks[0] >= ks[1] { [0, 1] } else { [1, 0] };
    let k1 = ks[order[0]];
    let dir_param = principal_direction(&shape, -k1);
    let tangent = (u + w * fu) * dir_param.0 + (v + w * fv) * dir_param.1;
    let d1 = (tangent - normal * normal.dot(&tangent)).normalize();
    let d1 = if d1.iter().all(|x| x.is_finite()) {
        d1
    } else {
        perpendicular(&normal)
    };
    SurfacePoint {
        point_m: *q,
        outward_normal: normal,
        directions: [d1, normal.cross(&d1)],
        curvatures_per_m: [k1, ks[order[1]]],
        feature: SurfaceFeature::Face,
        distance_m: 0.0,
    }
}

/// A parameter-space eigenvector `(du, dv)` of `shape` for eigenvalue `lambda`.
fn principal_direction(shape: &Matrix2<f64>, lambda: f64) -> (f64, f64) {
    let m = shape - Matrix2::identity() * lambda;
    // Null vector of the 2x2 `m`: perpendicular to its larger row.
    let (r0, r1) = (m.row(0), m.row(1));
    let row = if r0.norm() >= r1.norm() { r0 } else { r1 };
    if row.norm() < 1e-12 * (1.0 + shape.norm()) {
        return (1.0, 0.0); // umbilic: every direction is principal
    }
    (-row[1], row[0])
}

/// Mean length of the edges meeting at each vertex of `m`, m.
fn vertex_edge_lengths(m: &TriMesh) -> Vec<f64> {
    let mut total = vec![0.0; m.vertices().len()];
    let mut count = vec![0usize; m.vertices().len()];
    for t in m.indices() {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            let len = (m.vertices()[a] - m.vertices()[b]).length();
            for v in [a, b] {
                total[v] += len;
                count[v] += 1;
            }
        }
    }
    total
        .iter()
        .zip(&count)
        .map(|(t, c)| t / (*c).max(1) as f64)
        .collect()
}
