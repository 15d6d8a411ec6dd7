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

use crate::geometry::surface_point::{perpendicular, SurfaceFeature, SurfacePoint};

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

    /// Normal, principal directions and curvatures at the surface point `q` from a height
    /// function `w = f(u, v)` fitted to the nearby vertices in a frame `(u, v, w)` with `w`
    /// along the reference normal ([`height_fit`]). When the neighbourhood is wide against the
    /// curvature it finds (long thin CAD facets force that: the nearest vertices may be far
    /// along a facet), the fit is repeated on the vertices within about 30 degrees of arc of
    /// `q` by that first estimate (`|h| k_max <= 1/8`, `h` its quadratic height), if at least
    /// [`FIT_VERTICES`] remain: further round, the surface turns away and a polynomial over
    /// the tangent plane no longer follows it.
    fn fit_at(&self, q: &Vector3<f64>) -> Result<SurfacePoint, String> {
        let near = self.neighbourhood(q);
        let radius = near.iter().map(|p| (p - q).norm()).fold(0.0, f64::max);
        let w = self.reference_normal(q, radius);
        if !w.iter().all(|x| x.is_finite()) {
            return Err("lies where the mesh has no usable normal".into());
        }
        let offsets: Vec<Vector3<f64>> = near.iter().map(|p| p - q).collect();
        let first = height_fit(&offsets, &w)?;
        let k_max = first.hessian_norm();
        // Within the window (widened while it holds too few vertices: the first estimate
        // errs high on a wide neighbourhood), and on the surface the first fit describes (not,
        // say, the centre of a cylinder's end cap, level with the side's vertices but far
        // below them).
        let window = |scale: f64| -> Vec<Vector3<f64>> {
            offsets
                .iter()
                .filter(|d| {
                    let inside = (first.quadratic_part(d) * k_max).abs() <= scale * ARC_WINDOW;
                    inside && (d.dot(&w) - first.value(d)).abs() * k_max <= scale * ARC_WINDOW
                })
                .copied()
                .collect()
        };
        let local = [1.0, 2.0, 4.0]
            .into_iter()
            .map(window)
            .find(|l| l.len() >= FIT_VERTICES);
        let fit = match local {
            Some(l) if k_max > 0.0 && l.len() < offsets.len() => height_fit(&l, &w)?,
            _ => first,
        };
        Ok(graph_geometry(
            q,
            [fit.u, fit.v, w],
            [fit.c[1], fit.c[2]],
            [2.0 * fit.c[3], fit.c[4], 2.0 * fit.c[5]],
        ))
    }
}

/// Largest `|h| k_max` of a vertex in the second pass of the curvature fit (`h` the first
/// fit's quadratic height there; on a circle of curvature `k`, `h k = 1/8` at 30 degrees of
/// arc), and largest `|h - f| k_max` (`f` the first fit's height: a vertex off the surface it
/// describes is left out).
const ARC_WINDOW: f64 = 0.125;

/// Singular values below this fraction of the largest count as zero in [`fit_terms`].
const RANK_TOLERANCE: f64 = 1e-8;

/// A quadric height function over the tangent plane: axes and the coefficients of
/// `1, u, v, u^2, uv, v^2` (zero where the term was not fitted).
struct HeightFit {
    u: Vector3<f64>,
    v: Vector3<f64>,
    c: [f64; 6],
}

impl HeightFit {
    /// The fitted height at offset `d`.
    fn value(&self, d: &Vector3<f64>) -> f64 {
        let (x, y) = (d.dot(&self.u), d.dot(&self.v));
        self.c[0] + self.c[1] * x + self.c[2] * y + self.quadratic_part(d)
    }

    /// The quadratic part `c3 u^2 + c4 uv + c5 v^2` at offset `d`.
    fn quadratic_part(&self, d: &Vector3<f64>) -> f64 {
        let (x, y) = (d.dot(&self.u), d.dot(&self.v));
        self.c[3] * x * x + self.c[4] * x * y + self.c[5] * y * y
    }

    /// The largest absolute eigenvalue of the Hessian at the origin, 1/m (about the largest
    /// principal curvature).
    fn hessian_norm(&self) -> f64 {
        let h = Matrix2::new(2.0 * self.c[3], self.c[4], self.c[4], 2.0 * self.c[5]);
        let e = h.symmetric_eigen().eigenvalues;
        e[0].abs().max(e[1].abs())
    }
}

/// Least-squares quadric height function through `offsets` (vertex minus surface point; `w`
/// the normal) in the axes of their spread ([`spread_axes`]), each term kept only if the
/// vertices can tell it from the terms before it ([`fit_terms`]).
fn height_fit(offsets: &[Vector3<f64>], w: &Vector3<f64>) -> Result<HeightFit, String> {
    let (u, v) = spread_axes(offsets, w);
    let mut a = DMatrix::zeros(offsets.len(), 6);
    let mut b = DVector::zeros(offsets.len());
    for (r, d) in offsets.iter().enumerate() {
        let (x, y) = (d.dot(&u), d.dot(&v));
        for (c, val) in [1.0, x, y, x * x, x * y, y * y].iter().enumerate() {
            a[(r, c)] = *val;
        }
        b[r] = d.dot(w);
    }
    // Columns scaled to unit size so the rank test and the SVD's cut-off treat every order
    // alike.
    let scales: Vec<f64> = (0..6)
        .map(|c| a.column(c).norm().max(f64::MIN_POSITIVE))
        .collect();
    for (c, s) in scales.iter().enumerate() {
        a.column_mut(c).scale_mut(1.0 / s);
    }
    let terms = fit_terms(&a);
    let design = DMatrix::from_fn(offsets.len(), terms.len(), |r, j| a[(r, terms[j])]);
    let solved = design
        .svd(true, true)
        .solve(&b, 1e-12)
        .map_err(|e| format!("curvature fit failed: {e}"))?;
    let mut c = [0.0; 6];
    for (j, &t) in terms.iter().enumerate() {
        c[t] = solved[j] / scales[t];
    }
    Ok(HeightFit { u, v, c })
}

/// The columns of the (scaled) design `a` the fit uses, in order: each term is kept only if
/// it adds rank to the terms before it. A term that adds no rank is an alias the vertices
/// cannot tell apart: on two rows of vertices (the rims of long facets) at `u = +-a`, `u^2`
/// is a multiple of the constant, and fitting both would put an arbitrary curvature across
/// the rows (it stays zero: nothing there says otherwise).
fn fit_terms(a: &DMatrix<f64>) -> Vec<usize> {
    let rank = |cols: &[usize]| -> usize {
        let m = DMatrix::from_fn(a.nrows(), cols.len(), |r, j| a[(r, cols[j])]);
        let sv = m.singular_values();
        let top = sv.max();
        sv.iter().filter(|s| **s > RANK_TOLERANCE * top).count()
    };
    let mut terms = Vec::with_capacity(a.ncols());
    let mut have = 0;
    for t in 0..a.ncols() {
        terms.push(t);
        let r = rank(&terms);
        if r > have {
            have = r;
        } else {
            terms.pop();
        }
    }
    terms
}

/// Tangent axes `(u, v)` (with `w` right-handed) along the principal directions of the
/// offsets' spread in the tangent plane, `u` the wider: the fit's frame follows the sampling,
/// so that on two rows of vertices the aliased terms are whole terms ([`fit_terms`]).
fn spread_axes(offsets: &[Vector3<f64>], w: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let u0 = perpendicular(w);
    let v0 = w.cross(&u0);
    let mut cov = Matrix2::zeros();
    for d in offsets {
        let (x, y) = (d.dot(&u0), d.dot(&v0));
        cov += Matrix2::new(x * x, x * y, x * y, y * y);
    }
    let eig = cov.symmetric_eigen();
    let i = if eig.eigenvalues[0] >= eig.eigenvalues[1] {
        0
    } else {
        1
    };
    let e = eig.eigenvectors.column(i);
    let u = (u0 * e[0] + v0 * e[1]).normalize();
    if !u.iter().all(|c| c.is_finite()) {
        return (u0, v0);
    }
    (u, w.cross(&u))
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
